"""Boxes (xmin, ymin, xmax, ymax) that frame a diagram for export and drawing.

The default frame is the sites with a margin, not the bounding box of the vertices: nearly
collinear sites have vertices far away, and framing those shrinks the sites to a dot.
"""

from __future__ import annotations

import math
from typing import Protocol, Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["Box", "HasSites", "site_box", "point_box", "checked_box"]

#: (xmin, ymin, xmax, ymax)
Box = tuple[float, float, float, float]


class HasSites(Protocol):
    """Anything with an (n, 2) ``sites`` array, such as a ``Diagram`` (not imported here:
    ``Diagram``'s export and plot methods import this package's modules)."""

    @property
    def sites(self) -> NDArray[np.float64]: ...


def site_box(diagram: HasSites, margin: float = 0.1) -> Box:
    """The box around ``diagram.sites`` with ``margin`` (see :func:`point_box`)."""
    return point_box(diagram.sites, margin)


def point_box(points: NDArray[np.float64], margin: float = 0.1) -> Box:
    """The box around ``points`` widened on every side by ``margin`` times its larger side, so
    points on a line get a box of some height; around a lone point, a box of half-width
    ``max(1, margin * |coordinates|)``; (-1, -1, 1, 1) without points."""
    if not (math.isfinite(margin) and margin >= 0):
        raise ValueError(f"margin must be a finite number >= 0, got {margin!r}")
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if points.shape[0] == 0:
        return (-1.0, -1.0, 1.0, 1.0)
    lo, hi = points.min(axis=0), points.max(axis=0)
    magnitude = float(np.abs(points).max())
    span = float((hi - lo).max())
    if span > 0:
        # At least a few units in the last place, so that a zero side still opens up.
        pad = max(margin * span, 4 * float(np.spacing(magnitude)))
    else:
        pad = max(1.0, margin * magnitude)
    return checked_box((lo[0] - pad, lo[1] - pad, hi[0] + pad, hi[1] + pad))


def checked_box(box: Sequence[float]) -> Box:
    """``box`` as four Python floats, or ValueError naming what is wrong with it: not four
    numbers, one not finite, or xmin >= xmax or ymin >= ymax."""
    try:
        values = [float(v) for v in box]
    except (TypeError, ValueError):
        raise ValueError(f"a box is four numbers xmin, ymin, xmax, ymax; got {box!r}") from None
    if len(values) != 4:
        raise ValueError(f"a box is four numbers xmin, ymin, xmax, ymax; got {len(values)}: {values}")
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f"a box needs finite numbers; got {values}")
    xmin, ymin, xmax, ymax = values
    if not xmin < xmax:
        raise ValueError(f"a box needs xmin < xmax; got xmin = {xmin}, xmax = {xmax}")
    if not ymin < ymax:
        raise ValueError(f"a box needs ymin < ymax; got ymin = {ymin}, ymax = {ymax}")
    return (xmin, ymin, xmax, ymax)
