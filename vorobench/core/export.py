"""Cells as polygons for other tools: shapely ``Polygon`` objects and GeoJSON.

Each cell is clipped to a box (default: :func:`~vorobench.core.framing.site_box`, around the
sites) by ``Diagram.cell_polygon``. The cells tile the plane, so the clipped cells tile the box.
"""

from __future__ import annotations

from typing import Any, Optional, Protocol, Sequence

import numpy as np
from numpy.typing import NDArray

from vorobench.core.clip import polygon_area
from vorobench.core.framing import Box, HasSites, checked_box, site_box

__all__ = ["HasCells", "cell_rings", "to_shapely", "to_geojson"]


class HasCells(HasSites, Protocol):
    """What the export reads of a ``Diagram``: its sites and each cell clipped to a box."""

    def cell_polygon(self, i: int, box: Optional[Box] = None) -> NDArray[np.float64]: ...


def cell_rings(diagram: HasCells, box: Optional[Sequence[float]] = None) -> list[Optional[NDArray[np.float64]]]:
    """Each site's cell clipped to ``box`` as a counter-clockwise (k, 2) ring, k >= 3, without
    repeated points and not closed; None where less than an area of the cell is in the box."""
    box = site_box(diagram) if box is None else checked_box(box)
    return [_ring(diagram.cell_polygon(i, box)) for i in range(np.shape(diagram.sites)[0])]


def _ring(polygon: NDArray[np.float64]) -> Optional[NDArray[np.float64]]:
    """A clipped cell without the repeated points clipping leaves where a corner lies on a
    clipping line; None for what has no area (a cell that misses the box or only touches it)."""
    if polygon.shape[0] == 0:
        return None
    repeated = (polygon == np.roll(polygon, -1, axis=0)).all(axis=1)
    ring = polygon[~repeated]
    if ring.shape[0] < 3:
        return None
    area = polygon_area(ring)
    if area == 0:
        return None
    return ring if area > 0 else ring[::-1]


def to_shapely(diagram: HasCells, box: Optional[Sequence[float]] = None) -> list:
    """One ``shapely.Polygon`` per site (index = row of ``diagram.sites``): its cell clipped to
    ``box`` = (xmin, ymin, xmax, ymax), default around the sites; an empty polygon where the
    cell has no area in the box. Needs shapely (the ``peers`` extra)."""
    try:
        import shapely  # optional: only this function needs it
    except ImportError as exc:
        raise ImportError("to_shapely needs shapely: pip install shapely (or pip install 'vorobench[peers]')") from exc
    return [shapely.Polygon() if ring is None else shapely.Polygon(ring) for ring in cell_rings(diagram, box)]


def to_geojson(diagram: HasCells, box: Optional[Sequence[float]] = None) -> dict[str, Any]:
    """A GeoJSON ``FeatureCollection`` (RFC 7946) of the cells clipped to ``box``, default
    around the sites: one ``Feature`` per site, in site order, with ``id`` and property
    ``site`` its index, properties ``x`` and ``y`` its coordinates, and a ``Polygon`` (closed
    ring, counter-clockwise) or ``null`` where the cell has no area in the box. ``bbox`` is the
    box. Plain Python numbers only, so ``json.dumps`` takes it as is."""
    box = site_box(diagram) if box is None else checked_box(box)
    sites = np.asarray(diagram.sites, dtype=np.float64).reshape(-1, 2).tolist()
    features = []
    for i, ring in enumerate(cell_rings(diagram, box)):
        geometry = None
        if ring is not None:
            closed = ring.tolist()
            closed.append(closed[0])
            geometry = {"type": "Polygon", "coordinates": [closed]}
        x, y = sites[i]
        features.append({"type": "Feature", "id": i, "geometry": geometry,
                         "properties": {"site": i, "x": x, "y": y}})
    return {"type": "FeatureCollection", "bbox": list(box), "features": features}
