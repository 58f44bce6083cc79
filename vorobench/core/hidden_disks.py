"""Which disks are hidden in the Apollonius diagram: those inside another disk (touching
included), decided exactly, without building the diagram.

Under the distance |x - p_i| - r_i a disk inside another is never strictly closer to any
point than the bigger one, so its cell has no interior; a disk inside no other has a cell
(docs/apollonius.md). Identical disks hide each other: the one with the smallest index stays
visible, as ``prepare`` keeps the first of duplicated points.

Disk i is hidden when some disk j has r_j - |p_i - p_j| >= r_i. The centres go into a grid of
2^k x 2^k cells (about one centre per cell) under a pyramid of coarser grids, each cell keeping
the largest radius below it; the search for disk i descends from the top and enters a cell
only when that radius minus the cell's distance could reach r_i, and stops at the first disk
that covers i. So a disk among small ones looks at its neighbours, a point disk under a huge
one stops at the first disk that covers it, and a disk far from the huge one leaves it at a
coarse level. Each pair is decided by a float test with an error bound; the pairs it cannot
tell go to :func:`vorobench.core.predicates.apollonius.hidden_by`, in rationals.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

from vorobench.core.predicates.apollonius import hidden_by

__all__ = ["hidden_disks"]

#: A float decision of |p_i - p_j| + r_i <= r_j is trusted when the margin g^2 - d^2
#: (g = r_j - r_i, d the distance of the centres) exceeds this many units of roundoff of
#: g^2 + d^2: each of g, dx, dy is rounded once and squared, and the sums add two more.
_FILTER_ULPS = 16.0 * 2.0**-53

#: Relative slack on the grid's pruning distances, far above their rounding: pruning may
#: only skip cells that certainly hold no covering disk.
_PRUNE_SLACK = 1e-9

# answers of the compiled pass, per disk
_VISIBLE, _HIDDEN, _UNSURE = 0, 1, 2


def hidden_disks(centres: NDArray[np.float64], radii: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Boolean mask of the disks (``centres`` (n, 2), ``radii`` (n,), finite, >= 0) that lie
    inside another disk, touching included; of identical disks all but the first."""
    centres = np.ascontiguousarray(centres, dtype=np.float64)
    radii = np.ascontiguousarray(radii, dtype=np.float64)
    if centres.ndim != 2 or centres.shape[1] != 2:
        raise ValueError(f"centres must have shape (n, 2), got {centres.shape}")
    if radii.shape != (centres.shape[0],):
        raise ValueError(f"radii must have shape ({centres.shape[0]},), got {radii.shape}")
    if not (np.isfinite(centres).all() and np.isfinite(radii).all()):
        raise ValueError("centres and radii must be finite")
    if (radii < 0).any():
        raise ValueError(f"radii must be >= 0; disk {int(np.argmax(radii < 0))} has {radii[radii < 0][0]!r}")
    n = centres.shape[0]
    if n < 2:
        return np.zeros(n, dtype=bool)
    lo = centres.min(axis=0)
    span = float(max(centres.max(axis=0) - lo))
    levels = max(0, int(math.ceil(math.log2(max(n, 1)) / 2)))      # 2^levels cells a side
    side = 1 << levels
    cell = span / side if span > 0 else 1.0
    ix = np.minimum((centres[:, 0] - lo[0]) / cell, side - 1).astype(np.int64)
    iy = np.minimum((centres[:, 1] - lo[1]) / cell, side - 1).astype(np.int64)
    key = iy * side + ix
    order = np.argsort(key, kind="stable")
    start = np.searchsorted(key[order], np.arange(side * side + 1))
    pyramid = _pyramid(key, radii, levels)
    state = np.zeros(n, dtype=np.int8)
    pairs = np.empty((0, 2), dtype=np.int64)
    args = (centres, radii, order, start, pyramid, levels, cell, lo[0], lo[1], state)
    unsure = _search(*args, pairs, 0)
    if unsure > 0:
        # the pass counted the pairs its filter could not tell; run it again to list them
        pairs = np.empty((unsure, 2), dtype=np.int64)
        state[:] = _VISIBLE
        _search(*args, pairs, unsure)
    hidden = state == _HIDDEN
    for i, j in pairs:
        if not hidden[i] and hidden_by((centres[i, 0], centres[i, 1], radii[i]), (centres[j, 0], centres[j, 1], radii[j])):
            hidden[i] = True
    return hidden


def _pyramid(key: NDArray[np.int64], radii: NDArray[np.float64], levels: int) -> NDArray[np.float64]:
    """The largest radius in each cell of each level, level L (cells 2^L fine cells wide) at
    offset sum over l < L of 4^(levels - l), row-major."""
    side = 1 << levels
    finest = np.zeros(side * side)
    np.maximum.at(finest, key, radii)
    out = [finest]
    grid = finest.reshape(side, side)
    while grid.shape[0] > 1:
        grid = np.maximum(np.maximum(grid[0::2, 0::2], grid[0::2, 1::2]), np.maximum(grid[1::2, 0::2], grid[1::2, 1::2]))
        out.append(grid.ravel())
    return np.concatenate(out)


@njit(cache=True)
def _search(centres, radii, order, start, pyramid, levels, cell, x0, y0, state, pairs, capacity):
    """Mark each disk HIDDEN when a filtered test finds a disk that covers it; count the pairs
    the filter cannot tell (and list them in ``pairs`` when ``capacity`` allows)."""
    n = centres.shape[0]
    offset = np.zeros(levels + 2, dtype=np.int64)
    for level in range(levels + 1):
        width = 1 << (levels - level)
        offset[level + 1] = offset[level] + width * width
    top = pyramid[offset[levels]]
    stack = np.empty((4 * (levels + 1) + 4, 3), dtype=np.int64)
    unsure = 0
    for i in range(n):
        px = centres[i, 0]
        py = centres[i, 1]
        ri = radii[i]
        slack = _PRUNE_SLACK * (abs(px) + abs(py) + top + cell)
        depth = 1
        stack[0, 0] = levels
        stack[0, 1] = 0
        stack[0, 2] = 0
        while depth > 0 and state[i] != _HIDDEN:
            depth -= 1
            level = stack[depth, 0]
            cx = stack[depth, 1]
            cy = stack[depth, 2]
            width = 1 << (levels - level)
            size = cell * (1 << level)
            # distance from p_i to the cell's box, against the largest radius under it
            bx = max(x0 + cx * size - px, px - (x0 + (cx + 1) * size), 0.0)
            by = max(y0 + cy * size - py, py - (y0 + (cy + 1) * size), 0.0)
            if pyramid[offset[level] + cy * width + cx] - math.sqrt(bx * bx + by * by) < ri - slack:
                continue
            if level > 0:
                # the four children, the one nearest p_i on top of the stack (searched first)
                half = size / 2.0
                nx = 1 if px >= x0 + cx * size + half else 0
                ny = 1 if py >= y0 + cy * size + half else 0
                for q in range(4):
                    kx = (q & 1) ^ nx ^ 1
                    ky = (q >> 1) ^ ny ^ 1
                    stack[depth, 0] = level - 1
                    stack[depth, 1] = 2 * cx + kx
                    stack[depth, 2] = 2 * cy + ky
                    depth += 1
                continue
            c = cy * width + cx
            for t in range(start[c], start[c + 1]):
                j = order[t]
                if j == i or radii[j] < ri:
                    continue
                g = radii[j] - ri
                dx = px - centres[j, 0]
                dy = py - centres[j, 1]
                d2 = dx * dx + dy * dy
                margin = g * g - d2
                bound = _FILTER_ULPS * (g * g + d2)
                if margin > bound:
                    state[i] = _HIDDEN
                    break
                if margin >= -bound:
                    if g == 0.0 and d2 == 0.0:
                        # identical disks: the later one is hidden
                        if j < i:
                            state[i] = _HIDDEN
                            break
                        continue
                    if unsure < capacity:
                        pairs[unsure, 0] = i
                        pairs[unsure, 1] = j
                    unsure += 1
    return unsure
