"""The edges of a diagram of disks as polylines, for drawing (docs/apollonius.md).

An edge of cells a and b lies on the bisector branch of the two disks. Seen from p_a, the branch
lies along direction theta at t = (|d|^2 - s^2) / (2 (s + |d| cos(theta - theta_d))) (d = p_b -
p_a, s = r_b - r_a), for theta within acos(-s / |d|) of d's direction; the half-edge of cell a
runs counter-clockwise around p_a, so theta grows from its start to its end. The polyline is
sampled in theta until no chord strays more than ``tolerance`` from the curve; an end at
infinity is cut where the branch is far beyond the box. Floats only: a picture, not a decision.
"""

from __future__ import annotations

import math
from typing import Optional, Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["branch_polyline"]

#: At most this many halvings of an interval of directions.
_MAX_DEPTH = 14


def branch_polyline(sites: NDArray[np.float64], radii: NDArray[np.float64], a: int, b: int,
                    start: Optional[Sequence[float]], end: Optional[Sequence[float]],
                    box: Sequence[float], tolerance: float) -> NDArray[np.float64]:
    """(k, 2) points along the branch of disks a and b (cell a on the left) from ``start`` to
    ``end`` (vertex coordinates, or None for infinity), within ``tolerance`` of the curve; ends at
    infinity cut beyond ``box`` = (xmin, ymin, xmax, ymax). Finite ends are the given points."""
    pa = np.asarray(sites[a], dtype=np.float64)
    d = np.asarray(sites[b], dtype=np.float64) - pa
    s = float(radii[b] - radii[a])
    norm = math.hypot(d[0], d[1])
    theta_d = math.atan2(d[1], d[0])
    k = (norm - s) * (norm + s) / 2
    half = math.acos(max(-1.0, min(1.0, -s / norm)))

    def at(alpha: float) -> NDArray[np.float64]:
        t = k / (s + norm * math.cos(alpha))
        return pa + t * np.array([math.cos(theta_d + alpha), math.sin(theta_d + alpha)])

    def offset(point: Sequence[float]) -> float:
        angle = math.atan2(point[1] - pa[1], point[0] - pa[0]) - theta_d
        return (angle + math.pi) % (2 * math.pi) - math.pi

    xmin, ymin, xmax, ymax = box
    # beyond the box, and beyond the branch's nearest point to p_a, (|d| - s) / 2
    far = 1.5 * max(math.hypot(x - pa[0], y - pa[1]) for x in (xmin, xmax) for y in (ymin, ymax)) + 2 * (norm - s)

    def far_offset(side: int) -> float:
        # where the branch is ``far`` from p_a: s + |d| cos(alpha) = k / far
        return side * math.acos(max(-1.0, min(1.0, (k / far - s) / norm)))

    lo = offset(start) if start is not None else far_offset(-1)
    hi = offset(end) if end is not None else far_offset(1)
    lo, hi = max(lo, -half), min(hi, half)
    if hi < lo:                                       # rounding at a nearly degenerate edge
        lo, hi = hi, lo
    points = [(lo, at(lo)), (hi, at(hi))]
    out = [points[0]]
    stack = [(points[0], points[1], 0)]
    while stack:
        (a0, p0), (a1, p1), depth = stack.pop()
        mid = (a0 + a1) / 2
        pm = at(mid)
        chord = p1 - p0
        length = math.hypot(chord[0], chord[1])
        stray = abs(chord[0] * (pm[1] - p0[1]) - chord[1] * (pm[0] - p0[0])) / length if length > 0 else 0.0
        if depth < _MAX_DEPTH and (stray > tolerance or depth < 2):
            stack.append(((mid, pm), (a1, p1), depth + 1))
            stack.append(((a0, p0), (mid, pm), depth + 1))
        else:
            out.append((a1, p1))
    polyline = np.array([p for _, p in out])
    if start is not None:
        polyline[0] = start
    if end is not None:
        polyline[-1] = end
    return polyline
