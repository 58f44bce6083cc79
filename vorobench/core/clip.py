"""Clipping a convex polygon by half-planes (Sutherland-Hodgman), for drawing and areas."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["clip_convex", "polygon_area"]


def clip_convex(poly: NDArray[np.float64], anchor: NDArray[np.float64],
                direction: NDArray[np.float64]) -> NDArray[np.float64]:
    """Keep the part of ``poly`` to the left of every directed line (anchor[k], direction[k])."""
    pts = [tuple(p) for p in poly]
    for (ax, ay), (dx, dy) in zip(anchor, direction):
        if not pts:
            break
        # side > 0: left of the line, inside the cell.
        side = [dx * (py - ay) - dy * (px - ax) for px, py in pts]
        out: list[tuple[float, float]] = []
        for k, (p, sp) in enumerate(zip(pts, side)):
            q, sq = pts[(k + 1) % len(pts)], side[(k + 1) % len(pts)]
            if sp >= 0:
                out.append(p)
            if (sp >= 0) != (sq >= 0):
                t = sp / (sp - sq)
                out.append((p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])))
        pts = out
    return np.array(pts, dtype=np.float64).reshape(-1, 2)


def polygon_area(poly: NDArray[np.float64]) -> float:
    """Signed area (positive for counter-clockwise) by the shoelace formula, taken relative to
    the first corner so that coordinates far from the origin (1e9 + small) keep their digits."""
    if poly.shape[0] < 3:
        return 0.0
    x, y = poly[:, 0] - poly[0, 0], poly[:, 1] - poly[0, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
