"""Degenerate and numerically hostile point-set families.

Exact degeneracies (lattices, cocircular, collinear, duplicates) use integer-valued
coordinates small enough that float64 stores them, and the predicates on them, exactly.
Each generator has the signature ``f(n, rng) -> (m, 2) float64``; the row count m is
given by the matching ``*_size`` function where it is not simply n.  Row order is a
seeded random permutation unless the family is about order (``sorted_x``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ._sampling import ceil_sqrt, distinct_integers, empty_points, permutation, uniform_index
from .circles import CIRCLE_LADDER, LatticeCircle, circle_for, lattice_points

__all__ = [
    "COCIRCULAR_MAX_N",
    "COCIRCULAR_MANY_MAX_N",
    "COLLINEAR_DIRECTION",
    "COLLINEAR_OFFSET",
    "CONCENTRIC_CIRCLES",
    "DUPLICATE_SHARE_TENTHS",
    "HUGE_OFFSET",
    "NEAR_GRID_NOISE",
    "ROTATED_LATTICE_VECTOR",
    "TINY_SCALE",
    "cocircular",
    "cocircular_circle",
    "cocircular_many",
    "cocircular_many_circle",
    "cocircular_many_size",
    "cocircular_size",
    "collinear",
    "duplicate_count",
    "duplicates",
    "grid",
    "grid_size",
    "huge_offset",
    "lattice_rotated",
    "near_grid",
    "sorted_x",
    "tiny_spacing",
]

Points = NDArray[np.float64]

#: ``lattice_rotated`` uses the basis (a, b), (-b, a) with this integer (a, b).
ROTATED_LATTICE_VECTOR = (3, 4)
#: ``near_grid`` adds uniform noise in [-NEAR_GRID_NOISE, NEAR_GRID_NOISE) to each coordinate.
NEAR_GRID_NOISE = 1e-12
#: ``collinear`` points are COLLINEAR_OFFSET + t * COLLINEAR_DIRECTION for distinct integers t.
COLLINEAR_DIRECTION = (3, 7)
COLLINEAR_OFFSET = (-5, 11)
#: ``duplicates``: ceil(n * DUPLICATE_SHARE_TENTHS / 10) rows (at most n - 1) repeat others.
DUPLICATE_SHARE_TENTHS = 3
#: ``huge_offset`` adds this to both coordinates of unit-square points.
HUGE_OFFSET = 1e9
#: ``tiny_spacing`` scales unit-square points by this factor.
TINY_SCALE = 1e-9
#: ``cocircular``: the ladder's largest circle (r2 < 2**53) has this many integer points.
COCIRCULAR_MAX_N = CIRCLE_LADDER[-1].count
#: ``cocircular_many``: number of concentric circles, radii s * R for s = 1..CONCENTRIC_CIRCLES.
CONCENTRIC_CIRCLES = 4
_MANY_MAX_R2 = 2**52 // CONCENTRIC_CIRCLES**2
#: ``cocircular_many`` caps at CONCENTRIC_CIRCLES times the largest base circle that fits.
COCIRCULAR_MANY_MAX_N = CONCENTRIC_CIRCLES * circle_for(2**62, _MANY_MAX_R2).count


def _finish(points: NDArray[np.floating] | NDArray[np.integer]) -> Points:
    """Return the points as a C-contiguous float64 (m, 2) array."""
    return np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)


def _shuffled(points: NDArray[np.floating] | NDArray[np.integer], rng: np.random.Generator) -> Points:
    """Return the rows in a seeded random order (insertion order should not be structured)."""
    return _finish(points[permutation(rng, len(points))])


def grid_size(n: int) -> int:
    """Rows returned by the lattice families: k*k with k = ceil(sqrt(n)), the smallest square >= n."""
    return ceil_sqrt(n) ** 2


def _lattice_indices(n: int) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Return (i, j) index arrays of the k x k lattice used for n (k = ceil(sqrt(n)))."""
    k = ceil_sqrt(n)
    i, j = np.divmod(np.arange(k * k, dtype=np.int64), k)
    return i, j


def grid(n: int, rng: np.random.Generator) -> Points:
    """Integer lattice {0..k-1}^2, k = ceil(sqrt(n)): maximal cocircularity (4 per empty square)."""
    i, j = _lattice_indices(n)
    return _shuffled(np.column_stack([i, j]), rng)


def lattice_rotated(n: int, rng: np.random.Generator) -> Points:
    """Integer lattice i*(3,4) + j*(-4,3): a rotated square lattice that is still exactly degenerate."""
    a, b = ROTATED_LATTICE_VECTOR
    i, j = _lattice_indices(n)
    return _shuffled(np.column_stack([a * i - b * j, b * i + a * j]), rng)


def near_grid(n: int, rng: np.random.Generator) -> Points:
    """Integer lattice with every coordinate nudged by ~1e-12: nearly but not exactly degenerate."""
    i, j = _lattice_indices(n)
    pts = np.column_stack([i, j]).astype(np.float64)
    pts = pts + NEAR_GRID_NOISE * (2.0 * rng.random(pts.shape) - 1.0)
    return _shuffled(pts, rng)


def cocircular_size(n: int) -> int:
    """Rows returned by ``cocircular``: min(n, COCIRCULAR_MAX_N)."""
    return min(n, COCIRCULAR_MAX_N)


def cocircular_circle(n: int) -> LatticeCircle:
    """The circle ``cocircular`` samples for n: smallest ladder circle with >= n points."""
    return circle_for(n)


def _sample_circle(circle: LatticeCircle, q: int, rng: np.random.Generator, scale: int = 1) -> NDArray[np.int64]:
    """Return q distinct lattice points of the circle (times scale) chosen by the seed."""
    pts = np.array(lattice_points(circle), dtype=np.int64) * scale
    return pts[permutation(rng, len(pts))[:q]]


def cocircular(n: int, rng: np.random.Generator) -> Points:
    """n distinct integer points on one circle x^2 + y^2 = R2 centred at the origin (R < 2^26)."""
    m = cocircular_size(n)
    if m == 0:
        return empty_points()
    return _finish(_sample_circle(cocircular_circle(m), m, rng))


def _many_counts(n: int) -> list[int]:
    """Points per circle for ``cocircular_many`` (n split as evenly as possible)."""
    m = cocircular_many_size(n)
    c = min(CONCENTRIC_CIRCLES, m)
    return [m // c + (s < m % c) for s in range(c)] if c else []


def cocircular_many_size(n: int) -> int:
    """Rows returned by ``cocircular_many``: min(n, COCIRCULAR_MANY_MAX_N)."""
    return min(n, COCIRCULAR_MANY_MAX_N)


def cocircular_many_circle(n: int) -> LatticeCircle:
    """Base circle of ``cocircular_many`` for n; circle s (1-based) is it scaled by s."""
    counts = _many_counts(n)
    return circle_for(max(counts, default=0), _MANY_MAX_R2)


def cocircular_many(n: int, rng: np.random.Generator) -> Points:
    """Integer points on up to 4 concentric circles of radii R, 2R, 3R, 4R (4R < 2^26)."""
    counts = _many_counts(n)
    if not counts:
        return empty_points()
    base = cocircular_many_circle(n)
    parts = [_sample_circle(base, q, rng, scale=s + 1) for s, q in enumerate(counts)]
    return _shuffled(np.concatenate(parts), rng)


def collinear(n: int, rng: np.random.Generator) -> Points:
    """n distinct integer points on the line (-5, 11) + t*(3, 7), t distinct random integers."""
    if n == 0:
        return empty_points()
    half = 2 * n + 8
    t = distinct_integers(rng, n, -half, half + 1)
    (dx, dy), (x0, y0) = COLLINEAR_DIRECTION, COLLINEAR_OFFSET
    return _finish(np.column_stack([x0 + dx * t, y0 + dy * t]))


def duplicate_count(n: int) -> int:
    """Rows of ``duplicates`` that repeat an earlier point: ceil(0.3 n), but at most n - 1."""
    if n <= 1:
        return 0
    return min((DUPLICATE_SHARE_TENTHS * n + 9) // 10, n - 1)


def duplicates(n: int, rng: np.random.Generator) -> Points:
    """Uniform unit-square points where ~30% of the n rows are exact copies of other rows."""
    if n == 0:
        return empty_points()
    d = duplicate_count(n)
    unique = rng.random((n - d, 2))
    copies = unique[uniform_index(rng, d, n - d)]
    return _shuffled(np.concatenate([unique, copies]), rng)


def huge_offset(n: int, rng: np.random.Generator) -> Points:
    """Unit-square points shifted by 1e9: coordinates keep only ~7 significant fractional digits."""
    return _finish(rng.random((n, 2)) + HUGE_OFFSET)


def tiny_spacing(n: int, rng: np.random.Generator) -> Points:
    """Unit-square points scaled by 1e-9: tests absolute epsilons in predicates."""
    return _finish(rng.random((n, 2)) * TINY_SCALE)


def sorted_x(n: int, rng: np.random.Generator) -> Points:
    """Uniform unit-square points sorted by x (then y): adversarial insertion order."""
    pts = rng.random((n, 2))
    return _finish(pts[np.lexsort((pts[:, 1], pts[:, 0]))])
