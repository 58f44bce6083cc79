"""Each cell's half-edges in boundary order, for all cells in one pass: the walk behind the
scipy-style ``regions``, cell polygons and exports (linear time instead of a scan per cell)."""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

from vorobench.core.prefetch import prefetch

__all__ = ["cell_cycles"]

#: How many half-edges ahead the walk asks for the rows of the cell it will meet: cell ids
#: jump about memory from one half-edge to the next, and each row would otherwise be a wait
#: (the walk at 10^6 sites: 0.75 s before, 0.45 s after for fortune; 0.53 s and 0.42 s for
#: incremental; A/B in one process).
CELL_AHEAD = 16

#: How many cells are walked at once. A walk is a chain of reads, each waiting for the one
#: before (``h = next[h]``); walking several cells in turn lets the processor wait for their
#: misses together (the walk at 10^6 sites: 0.24 s alone, 0.20 s eight at a time).
WALKERS = 8


@njit(cache=True)
def _count_cells(site, origin, n, start, offsets):
    """Count each cell's half-edges into ``offsets`` (then summed into offsets) and pick its
    start. An unbounded cell's walk starts at its (lowest-numbered) half-edge from infinity, so
    its vertex list reads from one end of the boundary to the other; a bounded cell's starts at
    its lowest-numbered half-edge."""
    H = site.size
    for h in range(H):
        if h + CELL_AHEAD < H:
            later = site[h + CELL_AHEAD]
            prefetch(start, later)
            prefetch(offsets, later + 1)
        c = site[h]
        offsets[c + 1] += 1
        s = start[c]
        if s < 0 or (origin[h] < 0 and origin[s] >= 0):
            start[c] = h
    for c in range(n):
        offsets[c + 1] += offsets[c]


@njit(cache=True)
def _walk_together(site, nxt, origin, start, offsets, order, origins):
    """Walk every cell's cycle from its start, :data:`WALKERS` cells at a time, taken in the
    order their starts lie in memory (builders number a cell's half-edges near each other, so
    the walks stay in cache: 3x faster at 10^6 sites than cells in id order); False as soon as a
    cycle leaves its cell, misses some of its half-edges or does not return to its start (which
    one is not said). The origins are read along the walk, where the half-edge is in cache: a
    gather ``origin[order]`` afterwards reads memory at random again (0.1-0.2 s at 10^6 sites)."""
    H = site.size
    is_start = np.zeros(H, dtype=np.bool_)
    for c in range(start.size):
        if start[c] >= 0:
            is_start[start[c]] = True
    cell = np.full(WALKERS, -1, dtype=np.int64)     # the cell each walker is on, -1 when idle
    first = np.empty(WALKERS, dtype=np.int64)       # its start
    at = np.empty(WALKERS, dtype=np.int64)          # the half-edge it reads next
    k = np.empty(WALKERS, dtype=np.int64)           # where that half-edge goes in ``order``
    scan = 0
    busy = 0
    while True:
        for j in range(WALKERS):
            if cell[j] < 0:
                while scan < H and not is_start[scan]:
                    scan += 1
                if scan == H:
                    continue
                c = site[scan]
                cell[j], first[j], at[j], k[j] = c, scan, scan, offsets[c]
                scan += 1
                busy += 1
            c = cell[j]
            h = at[j]
            if k[j] >= offsets[c + 1] or site[h] != c:
                return False
            order[k[j]] = h
            origins[k[j]] = origin[h]
            k[j] += 1
            h = nxt[h]
            if h == first[j]:
                if k[j] != offsets[c + 1]:
                    return False
                cell[j] = -1
                busy -= 1
            else:
                at[j] = h
                prefetch(site, h)
                prefetch(nxt, h)
                prefetch(origin, h)
        if busy == 0 and scan == H:
            return True


@njit(cache=True)
def _walk_one_at_a_time(site, nxt, origin, start, offsets, order, origins):
    """Walk every cell's cycle from its start, one cell after the other in the order their
    starts lie in memory: the first bad cell found, or -1. Slower than :func:`_walk_together`,
    which hands over to it to name the first bad cell."""
    H = site.size
    for h0 in range(H):
        if h0 + CELL_AHEAD < H:
            later = site[h0 + CELL_AHEAD]
            prefetch(start, later)
            prefetch(offsets, later)
        c = site[h0]
        if start[c] != h0:
            continue
        k, stop, h = offsets[c], offsets[c + 1], h0
        while True:
            if k >= stop or site[h] != c:
                return c
            order[k] = h
            origins[k] = origin[h]
            k += 1
            h = nxt[h]
            if h == h0:
                break
        if k != stop:
            return c
    return -1


def cell_cycles(site: NDArray[np.integer], nxt: NDArray[np.integer], origin: NDArray[np.integer],
                n: int) -> tuple[NDArray[np.integer], NDArray[np.integer], NDArray[np.int64], int]:
    """``(order, origins, offsets, bad)``: the half-edges of cell i are
    ``order[offsets[i]:offsets[i + 1]]`` (int32 when ``next`` is, else int64),
    counter-clockwise along ``next`` (an empty slice for a cell with no half-edges), ``origins``
    is ``origin[order]`` (the scipy-style regions), and ``bad``
    is -1, or a cell whose ``next`` cycle leaves it, misses some of its half-edges or
    does not return to its start. O(n + H); site ids must lie in [0, n).
    """
    # int32 ids stay int32 (no copies of the three arrays); anything else becomes int64
    site, nxt, origin = _ids(site), _ids(nxt), _ids(origin)
    # The arrays it fills come from numpy, which asks for huge pages (see delaunay_dual.voronoi_dcel):
    # at 10^6 sites the walk over fortune's DCEL took 0.47-0.57 s with numba's allocator, 0.35-0.39 s now.
    H = site.size
    start = np.full(n, -1, dtype=nxt.dtype)
    offsets = np.zeros(n + 1, dtype=np.int64)
    order = np.empty(H, dtype=nxt.dtype)        # half-edge ids as the DCEL has them
    origins = np.empty(H, dtype=origin.dtype)
    _count_cells(site, origin, int(n), start, offsets)
    if _walk_together(site, nxt, origin, start, offsets, order, origins):
        return order, origins, offsets, -1
    # a bad cycle: the one-at-a-time walk names the first bad cell in the order of the starts
    return order, origins, offsets, _walk_one_at_a_time(site, nxt, origin, start, offsets, order, origins)


def _ids(a: NDArray[np.integer]) -> NDArray[np.integer]:
    a = np.ascontiguousarray(a)
    return a if a.dtype == np.int32 else a.astype(np.int64, copy=False)
