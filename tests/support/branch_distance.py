"""How far a chord between two samples of a bisector branch strays from the branch: the tests of
curved edges (drawing and polygons of disks) hold sampled polylines to their tolerance with it."""

from __future__ import annotations

import math
from typing import Optional

import numpy as np


def gap(sites, radii, a: int, b: int, point) -> float:
    """Distance to disk a minus distance to disk b: zero on their bisector."""
    return (math.dist(point, sites[a]) - radii[a]) - (math.dist(point, sites[b]) - radii[b])


def chord_stray(sites, radii, a: int, b: int, p, q, reach: float) -> Optional[float]:
    """Distance from the middle of chord pq to the branch of a and b along the chord's
    perpendicular (bisection in floats, 80 halvings), or None if the branch does not cross that
    perpendicular within ``reach`` of the chord."""
    p, q = np.asarray(p, dtype=np.float64), np.asarray(q, dtype=np.float64)
    m = (p + q) / 2
    normal = np.array([q[1] - p[1], p[0] - q[0]])
    normal /= np.linalg.norm(normal)
    lo, hi = -reach, reach

    def f(t: float) -> float:
        return gap(sites, radii, a, b, m + t * normal)

    if f(lo) * f(hi) > 0:
        return None
    for _ in range(80):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if f(lo) * f(mid) > 0 else (lo, mid)
    return abs(lo)
