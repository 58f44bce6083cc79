"""Insertion order: biased randomized insertion order (BRIO) with Hilbert order within rounds.

Randomness keeps the expected cost of incremental Delaunay at O(n log n) whatever the input
order (the ``sorted`` dataset would otherwise make every walk long); the Hilbert order inside
each round keeps consecutive sites close, so the walk from the last insertion is short.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["brio_order", "hilbert_keys", "HILBERT_BITS", "FIRST_ROUND", "ORDER_SEED"]

#: Grid resolution of the Hilbert curve: 2**HILBERT_BITS cells per side (16M cells: finer
#: than any benchmark needs for locality).
HILBERT_BITS = 12
#: Sites in the first (purely random, unsorted) round.
FIRST_ROUND = 64
#: Seed of the random permutation: the order (hence the counts in ``stats``) is reproducible.
ORDER_SEED = 20240601


@njit(cache=True)
def hilbert_keys(points: NDArray[np.float64], bits: int) -> NDArray[np.int64]:
    """Index along a Hilbert curve of each point, on a 2**bits grid over the bounding box."""
    n = points.shape[0]
    keys = np.zeros(n, dtype=np.int64)
    if n == 0:
        return keys
    x0 = points[:, 0].min()
    y0 = points[:, 1].min()
    span = max(points[:, 0].max() - x0, points[:, 1].max() - y0)
    side = (1 << bits) - 1
    scale = side / span if span > 0.0 else 0.0
    for i in range(n):
        x = min(int((points[i, 0] - x0) * scale), side)
        y = min(int((points[i, 1] - y0) * scale), side)
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
    keys = hilbert_keys(points, HILBERT_BITS)[perm]
    return perm[np.argsort(_round_major(keys, start))]


@njit(cache=True)
def _round_major(keys, start):
    """Sort keys: round number in the high bits, Hilbert index in the low 2 * HILBERT_BITS.

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
        out[t] = (r << (2 * HILBERT_BITS)) | keys[t]
    return out
