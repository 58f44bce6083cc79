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

__all__ = ["branch_polyline", "cell_polygon", "DEFAULT_CURVE_TOLERANCE", "FINEST_CURVE_TOLERANCE"]

#: How far a polygon may stray from a curved edge by default, and at the least, as fractions of
#: the box's diagonal: finer than the floor, the float sampling could not keep its promise.
DEFAULT_CURVE_TOLERANCE = 1e-3
FINEST_CURVE_TOLERANCE = 1e-6

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


def _clip_to_box(polygon: NDArray[np.float64], box: Sequence[float]) -> NDArray[np.float64]:
    """``polygon`` (any simple ring, counter-clockwise) clipped to ``box`` (Sutherland-Hodgman: a
    convex window clips any polygon; where the polygon leaves the box and comes back, the result
    runs along the box's side)."""
    xmin, ymin, xmax, ymax = box
    ring = [tuple(p) for p in polygon]
    for axis, bound, keep_above in ((0, xmin, True), (0, xmax, False), (1, ymin, True), (1, ymax, False)):
        if not ring:
            break
        inside = (lambda p: p[axis] >= bound) if keep_above else (lambda p: p[axis] <= bound)
        out = []
        for k, q in enumerate(ring):
            p = ring[k - 1]
            if inside(q):
                if not inside(p):
                    out.append(_crossing(p, q, axis, bound))
                out.append(q)
            elif inside(p):
                out.append(_crossing(p, q, axis, bound))
        ring = out
    return np.array(ring, dtype=np.float64).reshape(-1, 2)


def _crossing(p, q, axis: int, bound: float) -> tuple[float, float]:
    t = (bound - p[axis]) / (q[axis] - p[axis])
    point = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]
    point[axis] = bound
    return point[0], point[1]


def cell_polygon(diagram, i: int, box: Sequence[float], tolerance: float) -> NDArray[np.float64]:
    """Cell i of a diagram of disks clipped to ``box``, counter-clockwise, its edges sampled
    within ``tolerance``; a gap at infinity is closed by an arc around the disk's centre beyond
    the box. Empty for a hidden disk."""
    d = diagram
    hs = d.cell_half_edges(i)
    if not hs:
        return np.zeros((0, 2))
    radii = np.asarray(d.radii, dtype=np.float64)
    centre = np.asarray(d.sites[i], dtype=np.float64)
    lines = []
    for h in hs:
        u, w = int(d.origin[h]), int(d.origin[d.twin[h]])
        lines.append(branch_polyline(d.sites, radii, i, int(d.site[d.twin[h]]), None if u < 0 else d.vertices[u],
                                     None if w < 0 else d.vertices[w], box, tolerance))
    ring = []
    for k, (h, line) in enumerate(zip(hs, lines)):
        ring.extend(line if not ring else line[1:] if np.array_equal(line[0], ring[-1]) else line)
        if d.origin[d.twin[h]] < 0:
            # a gap at infinity: around the centre, beyond the box, to where the next edge comes in
            out, back = line[-1] - centre, lines[(k + 1) % len(lines)][0] - centre
            reach = max(math.hypot(*out), math.hypot(*back))
            a0, a1 = math.atan2(out[1], out[0]), math.atan2(back[1], back[0])
            sweep = (a1 - a0) % (2 * math.pi)
            steps = max(2, int(math.ceil(sweep / (math.pi / 32))))
            ring.extend(centre + reach * np.array([math.cos(a0 + sweep * s / steps), math.sin(a0 + sweep * s / steps)])
                        for s in range(steps + 1))
    return _clip_to_box(np.array(ring, dtype=np.float64), box)
