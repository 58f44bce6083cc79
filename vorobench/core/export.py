"""Cells as polygons for other tools: shapely ``Polygon`` objects and GeoJSON.

Each cell is clipped to a box (default: :func:`~vorobench.core.framing.site_box`, around the
sites) by ``Diagram.cell_polygons``, all cells in one compiled pass. The cells tile the plane,
so the clipped cells tile the box.
"""

from __future__ import annotations

from typing import Any, Optional, Protocol, Sequence

import numpy as np
from numpy.typing import NDArray

from vorobench.core.clip import clean_rings
from vorobench.core.framing import Box, HasSites, checked_box, site_box

__all__ = ["HasCells", "ring_arrays", "cell_rings", "to_shapely", "to_geojson"]


class HasCells(HasSites, Protocol):
    """What the export reads of a ``Diagram``: its sites and all cells clipped to a box."""

    def cell_polygons(self, box: Optional[Box] = None, *, tolerance: Optional[float] = None
                      ) -> tuple[NDArray[np.float64], NDArray[np.int64]]: ...


def ring_arrays(diagram: HasCells, box: Optional[Sequence[float]] = None, tolerance: Optional[float] = None
                ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Every cell clipped to ``box`` as a ring, in one pass: ``(corners, offsets)``, the ring of
    site i being ``corners[offsets[i]:offsets[i + 1]]``: counter-clockwise, at least three
    corners, no repeated corner, not closed; empty where less than an area of the cell is in
    the box. ``tolerance``: how far a ring may stray from a curved edge (diagrams of disks)."""
    box = site_box(diagram) if box is None else checked_box(box)
    return clean_rings(*diagram.cell_polygons(box, tolerance=tolerance))


def cell_rings(diagram: HasCells, box: Optional[Sequence[float]] = None, tolerance: Optional[float] = None
               ) -> list[Optional[NDArray[np.float64]]]:
    """Each site's cell clipped to ``box`` as a counter-clockwise (k, 2) ring, k >= 3, without
    repeated points and not closed; None where less than an area of the cell is in the box
    (``tolerance`` as in :func:`ring_arrays`)."""
    corners, offsets = ring_arrays(diagram, box, tolerance)
    return [corners[a:b] if b > a else None for a, b in zip(offsets[:-1].tolist(), offsets[1:].tolist())]


def to_shapely(diagram: HasCells, box: Optional[Sequence[float]] = None, tolerance: Optional[float] = None) -> list:
    """One ``shapely.Polygon`` per site (index = row of ``diagram.sites``): its cell clipped to
    ``box`` = (xmin, ymin, xmax, ymax), default around the sites; an empty polygon where the
    cell has no area in the box. Needs shapely (the ``peers`` extra). All polygons are made
    from the corner arrays in one call, not one Python call per cell. ``tolerance``: how far a
    polygon may stray from a curved edge (diagrams of disks; default a thousandth of the box's
    diagonal)."""
    try:
        import shapely  # optional: only this function needs it
    except ImportError as exc:
        raise ImportError("to_shapely needs shapely: pip install shapely (or pip install 'vorobench[peers]')") from exc
    corners, offsets = ring_arrays(diagram, box, tolerance)
    sizes = np.diff(offsets)
    has_ring = np.flatnonzero(sizes > 0)
    polygons = np.array([shapely.Polygon()] * sizes.size, dtype=object)
    if has_ring.size:
        # linearrings closes each ring itself; ring r gets the corners tagged r
        rings = shapely.linearrings(corners, indices=np.repeat(np.arange(has_ring.size), sizes[has_ring]))
        polygons[has_ring] = shapely.polygons(rings)
    return polygons.tolist()


def to_geojson(diagram: HasCells, box: Optional[Sequence[float]] = None, tolerance: Optional[float] = None
               ) -> dict[str, Any]:
    """A GeoJSON ``FeatureCollection`` (RFC 7946) of the cells clipped to ``box``, default
    around the sites: one ``Feature`` per site, in site order, with ``id`` and property
    ``site`` its index, properties ``x`` and ``y`` its coordinates, and a ``Polygon`` (closed
    ring, counter-clockwise) or ``null`` where the cell has no area in the box. ``bbox`` is the
    box. Plain Python numbers only, so ``json.dumps`` takes it as is. ``tolerance`` as in
    :func:`to_shapely`."""
    box = site_box(diagram) if box is None else checked_box(box)
    sites = np.asarray(diagram.sites, dtype=np.float64).reshape(-1, 2).tolist()
    corners, offsets = ring_arrays(diagram, box, tolerance)
    points, bounds = corners.tolist(), offsets.tolist()
    features = []
    for i, (x, y) in enumerate(sites):
        a, b = bounds[i], bounds[i + 1]
        geometry = None
        if b > a:
            closed = points[a:b]
            closed.append(closed[0])
            geometry = {"type": "Polygon", "coordinates": [closed]}
        features.append({"type": "Feature", "id": i, "geometry": geometry,
                         "properties": {"site": i, "x": x, "y": y}})
    return {"type": "FeatureCollection", "bbox": list(box), "features": features}
