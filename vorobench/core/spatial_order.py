"""Insertion order: biased randomized insertion order (BRIO) with Hilbert order within rounds.

Randomness keeps the expected cost of incremental Delaunay at O(n log n) whatever the input
order (the ``sorted`` dataset would otherwise make every walk long); the Hilbert order inside
each round keeps consecutive sites close, so the walk from the last insertion is short.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["brio_order", "order_bits", "hilbert_keys", "adaptive_hilbert_keys", "hilbert_index", "HILBERT_BITS",
           "MAX_BITS", "FIRST_ROUND", "ORDER_SEED"]

#: Grid resolution of the Hilbert curve for a fixed-resolution order: 2**HILBERT_BITS cells
#: per side (16M cells).
HILBERT_BITS = 12
#: Finest grid of the insertion order: 2**MAX_BITS cells per side; with the round number in
#: the high bits the sort key still fits an int64 (2 * 26 + 6 bits).
MAX_BITS = 26
#: Sites in the first (purely random, unsorted) round.
FIRST_ROUND = 64
#: Seed of the random permutation: the order (hence the counts in ``stats``) is reproducible.
ORDER_SEED = 20240601


@njit(cache=True)
def hilbert_index(ix: NDArray[np.int64], iy: NDArray[np.int64], bits: int) -> NDArray[np.int64]:
    """Index along a Hilbert curve of integer grid cells (ix, iy) in [0, 2**bits)."""
    n = ix.shape[0]
    keys = np.empty(n, dtype=np.int64)
    side = (1 << bits) - 1
    for i in range(n):
        x = ix[i]
        y = iy[i]
        d = 0
        s = 1 << (bits - 1)
        while s > 0:
            rx = 1 if (x & s) > 0 else 0
            ry = 1 if (y & s) > 0 else 0
            d += s * s * ((3 * rx) ^ ry)
            # rotate the quadrant so the curve stays continuous
            if ry == 0:
                if rx == 1:
                    x = side - x
                    y = side - y
                x, y = y, x
            s >>= 1
        keys[i] = d
    return keys


@njit(cache=True)
def _bounding_box(points):
    x0, y0, x1, y1 = np.inf, np.inf, -np.inf, -np.inf
    for i in range(points.shape[0]):
        x0 = min(x0, points[i, 0])
        x1 = max(x1, points[i, 0])
        y0 = min(y0, points[i, 1])
        y1 = max(y1, points[i, 1])
    return x0, y0, max(x1 - x0, y1 - y0)


@njit(cache=True)
def _box_cells_hilbert(points, x0, y0, span, bits):
    side = (1 << bits) - 1
    scale = side / span if span > 0.0 else 0.0
    n = points.shape[0]
    ix = np.empty(n, dtype=np.int64)
    iy = np.empty(n, dtype=np.int64)
    for i in range(n):
        ix[i] = min(int((points[i, 0] - x0) * scale), side)
        iy[i] = min(int((points[i, 1] - y0) * scale), side)
    return hilbert_index(ix, iy, bits)


def hilbert_keys(points: NDArray[np.float64], bits: int) -> NDArray[np.int64]:
    """Index along a Hilbert curve of each point, on a 2**bits grid over the bounding box."""
    if points.shape[0] == 0:
        return np.zeros(0, dtype=np.int64)
    x0, y0, span = _bounding_box(points)
    return _box_cells_hilbert(points, x0, y0, span, bits)


def adaptive_hilbert_keys(points: NDArray[np.float64], bits: int, seed: int = ORDER_SEED) -> NDArray[np.int64]:
    """Hilbert index on a grid fine enough where the sites are dense.

    If the bounding-box grid puts sampled sites together (a dense core of a heavy-tailed
    set such as kuzmin would fall in one cell, in random order, and make every walk long),
    each coordinate is replaced by its bin among 2**bits quantiles of a random sample, so
    rows and columns hold equal numbers of sites.
    """
    n = points.shape[0]
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    m = min(n, 1 << HILBERT_BITS)
    sample = np.random.default_rng(seed).integers(0, n, size=m)
    x0, y0, span = _bounding_box(points)
    # the plain bounding-box grid is enough when it separates (almost) every sampled site
    box_cells = _box_cells_hilbert(points[sample], x0, y0, span, bits)
    if np.unique(box_cells).size >= 0.9 * np.unique(sample).size:
        return _box_cells_hilbert(points, x0, y0, span, bits)
    width = 1 << HILBERT_BITS
    cuts = np.full((2, width), np.inf)         # padded to a power of two for the search
    cuts[0, :m] = np.sort(points[sample, 0])
    cuts[1, :m] = np.sort(points[sample, 1])
    return _quantile_cells_hilbert(points, cuts, m, bits)


@njit(cache=True)
def _quantile_cells_hilbert(points, cuts, m, bits):
    """Hilbert index of each point's cell: per axis, its rank among the m sorted cuts
    (branch-free binary search over the padded cuts), scaled to 2**bits bins."""
    n = points.shape[0]
    width = cuts.shape[1]
    side = 1 << bits
    ix = np.empty(n, dtype=np.int64)
    iy = np.empty(n, dtype=np.int64)
    for i in range(n):
        for axis in range(2):
            x = points[i, axis]
            pos = 0
            step = width >> 1
            while step > 0:
                pos += step * (cuts[axis, pos + step - 1] < x)
                step >>= 1
            pos += cuts[axis, pos] < x if pos < width else 0   # the last cut
            cell = min(pos * side // (m + 1), side - 1)
            if axis == 0:
                ix[i] = cell
            else:
                iy[i] = cell
    return hilbert_index(ix, iy, bits)


def brio_order(points: NDArray[np.float64], seed: int = ORDER_SEED) -> NDArray[np.int64]:
    """A permutation of range(n): random rounds of doubling size, Hilbert-sorted within each.

    Each round is a random sample; the last round holds about half the sites, the one
    before a quarter, and so on down to ``FIRST_ROUND`` sites.
    """
    n = points.shape[0]
    perm = np.random.default_rng(seed).permutation(n)
    start = n
    while start > FIRST_ROUND:
        start //= 2
    bits = order_bits(n)
    keys = adaptive_hilbert_keys(points, bits, seed)[perm]
    return perm[np.argsort(_round_major(keys, start, bits))]


def order_bits(n: int) -> int:
    """Grid bits of the insertion order for n sites: a cell per site even along a curve
    (sites on a parabola fill a line of cells, not the square; with fewer cells, hundreds
    share one, in random order, and every walk between them crosses the slivers between)."""
    return int(min(MAX_BITS, max(HILBERT_BITS, int(n).bit_length() + 1)))


@njit(cache=True)
def _round_major(keys, start, bits):
    """Sort keys: round number in the high bits, Hilbert index in the low 2 * bits.

    Position t of the random permutation is in round 0 if t < start, else in round
    floor(log2(t / start)) + 1: rounds of doubling size up to n.
    """
    out = np.empty(keys.shape[0], dtype=np.int64)
    r = 0
    bound = start
    for t in range(keys.shape[0]):
        while t >= bound:
            r += 1
            bound *= 2
        out[t] = (r << (2 * bits)) | keys[t]
    return out
