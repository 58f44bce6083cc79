"""Exact integer points on circles x^2 + y^2 = R2, for the cocircular families.

R2 is a product of primes p = 1 (mod 4).  Each such p splits as (a + bi)(a - bi) in the
Gaussian integers, so the lattice points on the circle are enumerated exactly by
multiplying those factors (there are 4 * prod(e + 1) of them), with no search.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

__all__ = ["CIRCLE_LADDER", "LatticeCircle", "circle_for", "lattice_points", "two_squares"]

#: Exponent maps {prime: exponent} with increasing point counts 8, 16, ..., 4096, 6144.
#: The last one has the most lattice points of any R2 < 2**53 (so radius < 2**26 and
#: x*x + y*y is exact in float64).
_FACTORISATIONS: tuple[dict[int, int], ...] = (
    {5: 1},
    {5: 1, 13: 1},
    {5: 1, 13: 1, 17: 1},
    {5: 1, 13: 1, 17: 1, 29: 1},
    {5: 1, 13: 1, 17: 1, 29: 1, 37: 1},
    {5: 1, 13: 1, 17: 1, 29: 1, 37: 1, 41: 1},
    {5: 1, 13: 1, 17: 1, 29: 1, 37: 1, 41: 1, 53: 1},
    {5: 1, 13: 1, 17: 1, 29: 1, 37: 1, 41: 1, 53: 1, 61: 1},
    {5: 1, 13: 1, 17: 1, 29: 1, 37: 1, 41: 1, 53: 1, 61: 1, 73: 1},
    {5: 1, 13: 1, 17: 1, 29: 1, 37: 1, 41: 1, 53: 1, 61: 1, 73: 1, 89: 1},
    {5: 3, 13: 2, 17: 1, 29: 1, 37: 1, 41: 1, 53: 1, 61: 1, 73: 1},
)


@dataclass(frozen=True)
class LatticeCircle:
    """A circle x^2 + y^2 = r2 with ``count`` integer points; ``factors`` = (prime, exp) pairs."""

    r2: int
    count: int
    factors: tuple[tuple[int, int], ...]

    @classmethod
    def from_factors(cls, factors: dict[int, int]) -> "LatticeCircle":
        """Build the circle record from a {prime: exponent} map of primes = 1 (mod 4)."""
        r2 = math.prod(p**e for p, e in factors.items())
        count = 4 * math.prod(e + 1 for e in factors.values())
        return cls(r2, count, tuple(sorted(factors.items())))


#: Circles in increasing order of r2 and point count.
CIRCLE_LADDER: tuple[LatticeCircle, ...] = tuple(LatticeCircle.from_factors(f) for f in _FACTORISATIONS)


def circle_for(n: int, max_r2: int = 2**53) -> LatticeCircle:
    """Smallest ladder circle with r2 < max_r2 holding >= n points (else the largest such)."""
    fitting = [c for c in CIRCLE_LADDER if c.r2 < max_r2]
    if not fitting:
        raise ValueError(f"no lattice circle with r2 < {max_r2}")
    for circle in fitting:
        if circle.count >= n:
            return circle
    return fitting[-1]


def two_squares(p: int) -> tuple[int, int]:
    """Return (a, b), a > b > 0, with a^2 + b^2 == p for a prime p = 1 (mod 4)."""
    if p % 4 != 1:
        raise ValueError(f"{p} is not 1 mod 4")
    for b in range(1, math.isqrt(p // 2) + 1):
        a = math.isqrt(p - b * b)
        if a * a + b * b == p:
            return a, b
    raise ValueError(f"{p} is not a sum of two squares")


def _gmul(z: tuple[int, int], w: tuple[int, int]) -> tuple[int, int]:
    """Multiply two Gaussian integers given as (re, im)."""
    return (z[0] * w[0] - z[1] * w[1], z[0] * w[1] + z[1] * w[0])


def _gpow(z: tuple[int, int], k: int) -> tuple[int, int]:
    """Raise a Gaussian integer to a non-negative integer power."""
    out = (1, 0)
    for _ in range(k):
        out = _gmul(out, z)
    return out


@lru_cache(maxsize=None)
def lattice_points(circle: LatticeCircle) -> tuple[tuple[int, int], ...]:
    """All integer (x, y) with x^2 + y^2 == circle.r2, sorted, as exact Python ints."""
    reps = [(1, 0)]
    for p, e in circle.factors:
        a, b = two_squares(p)
        reps = [
            _gmul(z, _gmul(_gpow((a, b), k), _gpow((a, -b), e - k)))
            for z in reps
            for k in range(e + 1)
        ]
    units = ((1, 0), (0, 1), (-1, 0), (0, -1))
    points = sorted({_gmul(z, u) for z in reps for u in units})
    if len(points) != circle.count or any(x * x + y * y != circle.r2 for x, y in points):
        raise AssertionError(f"lattice enumeration failed for r2={circle.r2}")
    return tuple(points)
