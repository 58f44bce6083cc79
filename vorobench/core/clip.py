"""Clipping a convex polygon by half-planes (Sutherland-Hodgman), for drawing, areas and export.

All cells are clipped in one compiled pass over flat arrays (one line per half-edge, grouped by
cell), so that exporting 10^5 cells costs a fraction of a second; one cell is the same pass over
one group, so a cell alone and among all the others is clipped to the same corners.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["clip_convex", "clip_groups", "clean_rings", "polygon_area"]


@njit(cache=True)
def _clip_groups(start, anchor, direction, offsets, empty_without_lines):
    """Clip ``start`` by each group of lines; (corners, offsets per group)."""
    groups = offsets.size - 1
    cap = max(8, 2 * start.shape[0])
    a = np.empty((cap, 2))
    b = np.empty((cap, 2))
    side = np.empty(cap)
    out = np.empty((max(16, start.shape[0] * groups + anchor.shape[0]), 2))
    out_offsets = np.zeros(groups + 1, dtype=np.int64)
    m = 0
    for g in range(groups):
        first, stop = offsets[g], offsets[g + 1]
        k = 0
        if stop > first or not empty_without_lines:
            k = start.shape[0]
            a[:k] = start
        for e in range(first, stop):
            if k == 0:
                break
            if 2 * k > cap:  # a corner is kept or replaced by at most two
                cap = 2 * cap
                grown = np.empty((cap, 2))
                grown[:k] = a[:k]
                a, b, side = grown, np.empty((cap, 2)), np.empty(cap)
            ax, ay = anchor[e, 0], anchor[e, 1]
            dx, dy = direction[e, 0], direction[e, 1]
            # side > 0: left of the line, inside the cell
            for j in range(k):
                side[j] = dx * (a[j, 1] - ay) - dy * (a[j, 0] - ax)
            kept = 0
            for j in range(k):
                q = j + 1 if j + 1 < k else 0
                sp, sq = side[j], side[q]
                if sp >= 0:
                    b[kept, 0], b[kept, 1] = a[j, 0], a[j, 1]
                    kept += 1
                if (sp >= 0) != (sq >= 0):
                    # where the edge from corner j to corner q crosses the line
                    t = sp / (sp - sq)
                    b[kept, 0] = a[j, 0] + t * (a[q, 0] - a[j, 0])
                    b[kept, 1] = a[j, 1] + t * (a[q, 1] - a[j, 1])
                    kept += 1
            a, b = b, a
            k = kept
        if m + k > out.shape[0]:
            grown = np.empty((2 * (m + k), 2))
            grown[:m] = out[:m]
            out = grown
        out[m:m + k] = a[:k]
        m += k
        out_offsets[g + 1] = m
    return out[:m].copy(), out_offsets


def clip_groups(start: NDArray[np.float64], anchor: NDArray[np.float64], direction: NDArray[np.float64],
                offsets: NDArray[np.int64], empty_without_lines: bool = True
                ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """``start`` clipped, for each group g, to the left of every directed line (anchor[k],
    direction[k]) with k in ``offsets[g]:offsets[g + 1]``: ``(corners, corner_offsets)``, the
    polygon of group g being ``corners[corner_offsets[g]:corner_offsets[g + 1]]``. A group with
    no line is empty when ``empty_without_lines``, else ``start`` itself. ValueError when the
    shapes do not fit: (m, 2) corners, (k, 2) anchors and directions, offsets rising from 0 to k."""
    start, anchor, direction = (_points(a, name) for a, name in
                                ((start, "start"), (anchor, "anchor"), (direction, "direction")))
    if anchor.shape != direction.shape:
        raise ValueError(f"anchor {anchor.shape} and direction {direction.shape} must have the same shape")
    offsets = np.ascontiguousarray(offsets, dtype=np.int64)
    if offsets.ndim != 1 or offsets.size < 1 or offsets[0] != 0 or offsets[-1] != anchor.shape[0] \
            or (np.diff(offsets) < 0).any():
        raise ValueError(f"offsets must rise from 0 to the number of lines ({anchor.shape[0]})")
    return _clip_groups(start, anchor, direction, offsets, bool(empty_without_lines))


def _points(a: NDArray[np.float64], name: str) -> NDArray[np.float64]:
    a = np.ascontiguousarray(a, dtype=np.float64)
    if a.ndim != 2 or a.shape[1] != 2:
        raise ValueError(f"{name} must have shape (k, 2), got {a.shape}")
    return a


def clip_convex(poly: NDArray[np.float64], anchor: NDArray[np.float64],
                direction: NDArray[np.float64]) -> NDArray[np.float64]:
    """Keep the part of ``poly`` to the left of every directed line (anchor[k], direction[k])."""
    lines = np.shape(anchor)[0]
    corners, _ = clip_groups(poly, anchor, direction, np.array([0, lines], dtype=np.int64),
                             empty_without_lines=False)
    return corners


@njit(cache=True)
def _clean_rings(corners, offsets):
    """Each polygon without repeated corners, counter-clockwise; empty where it has no area."""
    groups = offsets.size - 1
    out = np.empty_like(corners)
    out_offsets = np.zeros(groups + 1, dtype=np.int64)
    m = 0
    for g in range(groups):
        first, stop = offsets[g], offsets[g + 1]
        begin = m
        for j in range(first, stop):
            q = j + 1 if j + 1 < stop else first
            # a corner on a clipping line comes out twice; keep the last copy
            if corners[j, 0] == corners[q, 0] and corners[j, 1] == corners[q, 1]:
                continue
            out[m, 0], out[m, 1] = corners[j, 0], corners[j, 1]
            m += 1
        k = m - begin
        area2 = 0.0
        if k >= 3:
            # the shoelace sum relative to the first corner, so that 1e9 + small keeps its digits
            x0, y0 = out[begin, 0], out[begin, 1]
            forward, backward = 0.0, 0.0
            for j in range(k):
                q = begin + (j + 1) % k
                xj, yj = out[begin + j, 0] - x0, out[begin + j, 1] - y0
                xq, yq = out[q, 0] - x0, out[q, 1] - y0
                forward += xj * yq
                backward += yj * xq
            area2 = forward - backward
        if area2 == 0.0:
            m = begin
        elif area2 < 0.0:
            for j in range(k // 2):
                lo, hi = begin + j, begin + k - 1 - j
                tx, ty = out[lo, 0], out[lo, 1]
                out[lo, 0], out[lo, 1] = out[hi, 0], out[hi, 1]
                out[hi, 0], out[hi, 1] = tx, ty
        out_offsets[g + 1] = m
    return out[:m].copy(), out_offsets


def clean_rings(corners: NDArray[np.float64], offsets: NDArray[np.int64]
                ) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """Polygons (as :func:`clip_groups` gives them) as rings for export: without the repeated
    corners that clipping leaves where a corner lies on a clipping line, counter-clockwise, at
    least three corners, not closed; an empty ring where a polygon has no area."""
    return _clean_rings(np.ascontiguousarray(corners, dtype=np.float64).reshape(-1, 2),
                        np.ascontiguousarray(offsets, dtype=np.int64))


def polygon_area(poly: NDArray[np.float64]) -> float:
    """Signed area (positive for counter-clockwise) by the shoelace formula, taken relative to
    the first corner so that coordinates far from the origin (1e9 + small) keep their digits."""
    if poly.shape[0] < 3:
        return 0.0
    x, y = poly[:, 0] - poly[0, 0], poly[:, 1] - poly[0, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))
