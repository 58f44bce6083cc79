"""Random point-set families: generic-position inputs of various shapes and densities.

Each generator has the signature ``f(n, rng) -> (n, 2) float64`` and returns exactly
n rows.  Only ``Generator.random`` / ``Generator.standard_normal`` and correctly rounded
arithmetic are used, so outputs are bit-identical on every platform.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ._sampling import distinct_integers, empty_points, uniform_index, unit_disk

__all__ = [
    "CLUSTER_SIGMA",
    "CORNER_SIGMA",
    "LINE_NOISE",
    "PARABOLA_MAX_N",
    "cluster_count",
    "clusters",
    "corners",
    "cross",
    "diagonal",
    "disk",
    "kuzmin",
    "normal",
    "parabola",
    "parabola_bits",
    "uniform",
]

Points = NDArray[np.float64]

#: Standard deviation of the noise around the lines of ``diagonal`` and ``cross``.
LINE_NOISE = 1e-3
#: Standard deviation of the half-Gaussian offsets of ``corners`` from its corner.
CORNER_SIGMA = 0.05
#: Cluster standard deviation for a single cluster; k clusters use CLUSTER_SIGMA / sqrt(k).
CLUSTER_SIGMA = 0.1
#: ``parabola`` draws x = j / 2**b with distinct integers |j| <= 2**b, b <= 26, from a range
#: at least 4n wide (so sampling stays fast); that caps n at 2**25.
PARABOLA_MAX_N = 2**25
_PARABOLA_MIN_BITS = 20
_PARABOLA_MAX_BITS = 26


def _finish(points: NDArray[np.float64]) -> Points:
    """Return the points as a C-contiguous float64 (m, 2) array."""
    return np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)


def uniform(n: int, rng: np.random.Generator) -> Points:
    """Uniform in the unit square [0, 1)^2: the baseline generic input."""
    return _finish(rng.random((n, 2)))


def disk(n: int, rng: np.random.Generator) -> Points:
    """Uniform in the unit disk (rejection sampling, no trigonometry)."""
    return _finish(unit_disk(rng, n))


def normal(n: int, rng: np.random.Generator) -> Points:
    """Standard bivariate Gaussian: dense centre, sparse unbounded tails."""
    return _finish(rng.standard_normal((n, 2)))


def cluster_count(n: int) -> int:
    """Number of clusters used by ``clusters`` for n points: max(1, isqrt(n) // 4)."""
    return max(1, math.isqrt(n) // 4)


def clusters(n: int, rng: np.random.Generator) -> Points:
    """Gaussian clusters with centres uniform in the unit square: strongly varying density."""
    if n == 0:
        return empty_points()
    k = cluster_count(n)
    centres = rng.random((k, 2))
    sigma = CLUSTER_SIGMA / math.sqrt(k)
    which = uniform_index(rng, n, k)
    return _finish(centres[which] + sigma * rng.standard_normal((n, 2)))


def kuzmin(n: int, rng: np.random.Generator) -> Points:
    """Kuzmin disk (surface density ~ (1 + r^2)^-3/2): heavy-tailed radii up to ~1e16."""
    if n == 0:
        return empty_points()
    direction = unit_disk(rng, n)
    norm = np.sqrt(direction[:, 0] * direction[:, 0] + direction[:, 1] * direction[:, 1])
    # Inverse of the enclosed-mass fraction M(r) = 1 - 1/sqrt(1 + r^2); 1 - u lies in (0, 1].
    q = 1.0 - rng.random(n)
    radius = np.sqrt((1.0 / (q * q)) - 1.0)
    return _finish(direction * (radius / norm)[:, None])


def corners(n: int, rng: np.random.Generator) -> Points:
    """Half-Gaussian blobs (sigma CORNER_SIGMA) at the four corners, folded into the unit square."""
    if n == 0:
        return empty_points()
    corner = uniform_index(rng, n, 4)
    cx = (corner & 1).astype(np.float64)
    cy = (corner >> 1).astype(np.float64)
    offset = np.minimum(0.5, CORNER_SIGMA * np.abs(rng.standard_normal((n, 2))))
    x = cx + (1.0 - 2.0 * cx) * offset[:, 0]
    y = cy + (1.0 - 2.0 * cy) * offset[:, 1]
    return _finish(np.column_stack([x, y]))


def diagonal(n: int, rng: np.random.Generator) -> Points:
    """Points near the segment y = x, 0 <= x < 1, with normal noise of sigma LINE_NOISE."""
    t = rng.random(n)
    noise = LINE_NOISE * rng.standard_normal((n, 2))
    return _finish(np.column_stack([t, t]) + noise)


def cross(n: int, rng: np.random.Generator) -> Points:
    """Points near the two crossing diagonals y = x and y = 1 - x of the unit square."""
    t = rng.random(n)
    second = rng.random(n) < 0.5
    y = np.where(second, 1.0 - t, t)
    noise = LINE_NOISE * rng.standard_normal((n, 2))
    return _finish(np.column_stack([t, y]) + noise)


def parabola_bits(n: int) -> int:
    """Bits b of the x grid j / 2**b used by ``parabola`` for n points (20 <= b <= 26)."""
    b = _PARABOLA_MIN_BITS
    while b < _PARABOLA_MAX_BITS and 2 * n > 2**b:
        b += 1
    return b


def parabola(n: int, rng: np.random.Generator) -> Points:
    """Points exactly on y = x^2 with distinct x in [-1, 1]: all in strictly convex position."""
    if n > PARABOLA_MAX_N:
        raise ValueError(f"parabola supports at most {PARABOLA_MAX_N} points, got n={n}")
    if n == 0:
        return empty_points()
    b = parabola_bits(n)
    j = distinct_integers(rng, n, -(2**b), 2**b + 1)
    # j has at most 27 bits, so x = j * 2^-b is exact and x*x (at most 53 bits) is exact too.
    x = j.astype(np.float64) * (0.5**b)
    return _finish(np.column_stack([x, x * x]))
