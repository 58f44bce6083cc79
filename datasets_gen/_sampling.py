"""Platform-stable sampling helpers built only on ``Generator.random`` and IEEE arithmetic.

Every helper uses correctly rounded operations (+, -, *, /, sqrt) on draws from
``Generator.random`` so the results are bit-identical across machines and numpy
versions that keep the PCG64 stream (no libm transcendental functions, no
``Generator.choice``/``permutation`` whose algorithms are not pinned).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "ceil_sqrt",
    "distinct_integers",
    "empty_points",
    "permutation",
    "unit_disk",
    "uniform_index",
]


def empty_points() -> NDArray[np.float64]:
    """Return a (0, 2) float64 array, the result of every generator at n = 0."""
    return np.zeros((0, 2), dtype=np.float64)


def ceil_sqrt(n: int) -> int:
    """Return the smallest k >= 0 with k*k >= n (exact integer arithmetic)."""
    k = math.isqrt(n)
    return k if k * k >= n else k + 1


def permutation(rng: np.random.Generator, m: int) -> NDArray[np.intp]:
    """Return a random permutation of range(m) by stably sorting uniform keys."""
    return np.argsort(rng.random(m), kind="stable")


def uniform_index(rng: np.random.Generator, size: int, upper: int) -> NDArray[np.int64]:
    """Return ``size`` integers in [0, upper) as floor(u * upper) (upper >= 1, < 2**53)."""
    idx = np.floor(rng.random(size) * upper).astype(np.int64)
    return np.minimum(idx, upper - 1)


def distinct_integers(rng: np.random.Generator, n: int, low: int, high: int) -> NDArray[np.int64]:
    """Return n distinct integers in [low, high), in random order (first-draw order)."""
    span = high - low
    if n > span:
        raise ValueError(f"cannot draw {n} distinct integers from a range of {span}")
    got = np.zeros(0, dtype=np.int64)
    while got.size < n:
        need = n - got.size
        batch = uniform_index(rng, 2 * need + 16, span) + low
        pool = np.concatenate([got, batch])
        _, first = np.unique(pool, return_index=True)
        got = pool[np.sort(first)][:n]
    return got


def unit_disk(rng: np.random.Generator, n: int) -> NDArray[np.float64]:
    """Return n points uniform in the closed unit disk minus the origin (rejection sampling)."""
    chunks: list[NDArray[np.float64]] = []
    have = 0
    while have < n:
        m = (n - have) * 4 // 3 + 16
        cand = 2.0 * rng.random((m, 2)) - 1.0
        r2 = cand[:, 0] * cand[:, 0] + cand[:, 1] * cand[:, 1]
        keep = cand[(r2 > 0.0) & (r2 <= 1.0)]
        chunks.append(keep)
        have += keep.shape[0]
    if not chunks:
        return empty_points()
    return np.ascontiguousarray(np.concatenate(chunks)[:n])
