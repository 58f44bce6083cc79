"""Interval arithmetic in floats: a filter whose error bound is computed along with the value.

Each quantity is a pair (lo, hi) of floats with the exact real value inside. Every operation
rounds to nearest and then moves each end outward by at least one ulp, which covers the
half-ulp rounding error of the operation, so the interval stays a certified enclosure whatever
the expression (CGAL's ``Interval_nt`` filter does the same with directed rounding). A sign is
decided when the interval excludes 0; otherwise the caller runs its exact stage. Used where a
predicate's expression is too long to derive an a-priori error bound by hand (the weighted
sweep's event times, which mix square roots and quotients). Overflow gives infinite ends and a
zero divisor the whole line: both leave the sign undecided, never wrong.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["UNDECIDED", "add", "sub", "mul", "sqr", "div", "sqrt", "sign", "exact", "half"]

#: :func:`sign` of an interval that contains 0 (the exact stage must decide).
UNDECIDED = 2

_INF = np.inf
_MAX = np.finfo(np.float64).max


#: Relative widening: at least one ulp of any float (ulp(x) <= 2**-52 |x|), so rounding the
#: widened end to nearest still leaves it a float beyond the exact value.
_REL = 2.0 ** -52
#: Absolute widening for results in the subnormal range, where an ulp is 2**-1074.
_TINY = 2.0 ** -1074


@njit(cache=True, inline='always')
def _out(lo, hi):
    # each end moved outward by at least one ulp, which covers the half-ulp rounding of the
    # operation that made it (a multiply and an add, cheaper than nextafter); NaN (0 * inf)
    # widens to the whole line
    if lo != lo or hi != hi:
        return -_INF, _INF
    # an end that overflowed to the far side (a lower end of +inf, an upper end of -inf)
    # stands for a finite value beyond the largest float, which that float bounds; this also
    # keeps inf - inf, a NaN, out of the next operation
    lo = min(lo, _MAX)
    hi = max(hi, -_MAX)
    lo = lo - (abs(lo) * _REL + _TINY)
    hi = hi + (abs(hi) * _REL + _TINY)
    return lo, hi


@njit(cache=True, inline='always')
def exact(x):
    """The interval of a float that is exactly the value meant."""
    return x, x


@njit(cache=True, inline='always')
def add(alo, ahi, blo, bhi):
    """a + b."""
    return _out(alo + blo, ahi + bhi)


@njit(cache=True, inline='always')
def sub(alo, ahi, blo, bhi):
    """a - b."""
    return _out(alo - bhi, ahi - blo)


@njit(cache=True, inline='always')
def mul(alo, ahi, blo, bhi):
    """a * b."""
    p1 = alo * blo
    p2 = alo * bhi
    p3 = ahi * blo
    p4 = ahi * bhi
    if p1 != p1 or p2 != p2 or p3 != p3 or p4 != p4:
        return -_INF, _INF                      # 0 * inf: min and max would drop the NaN
    return _out(min(min(p1, p2), min(p3, p4)), max(max(p1, p2), max(p3, p4)))


@njit(cache=True, inline='always')
def half(alo, ahi):
    """a / 2 (exact in floats, barring underflow: widened anyway)."""
    return _out(alo * 0.5, ahi * 0.5)


@njit(cache=True, inline='always')
def sqr(alo, ahi):
    """a * a (never below 0, unlike mul(a, a) on an interval around 0)."""
    if alo >= 0.0:
        lo, hi = _out(alo * alo, ahi * ahi)
    elif ahi <= 0.0:
        lo, hi = _out(ahi * ahi, alo * alo)
    else:
        lo, hi = _out(0.0, max(alo * alo, ahi * ahi))
    return max(lo, 0.0), hi


@njit(cache=True, inline='always')
def div(alo, ahi, blo, bhi):
    """a / b (the whole line when b may be 0)."""
    if blo <= 0.0 <= bhi:
        return -_INF, _INF
    q1 = alo / blo
    q2 = alo / bhi
    q3 = ahi / blo
    q4 = ahi / bhi
    if q1 != q1 or q2 != q2 or q3 != q3 or q4 != q4:
        return -_INF, _INF                      # inf / inf
    return _out(min(min(q1, q2), min(q3, q4)), max(max(q1, q2), max(q3, q4)))


@njit(cache=True, inline='always')
def sqrt(alo, ahi):
    """The square root of a quantity known to be >= 0 (negative ends are its rounding)."""
    lo, hi = _out(math.sqrt(max(alo, 0.0)), math.sqrt(max(ahi, 0.0)))
    return max(lo, 0.0), hi


@njit(cache=True, inline='always')
def sign(lo, hi):
    """-1 or 1 when the interval is on one side of 0, else :data:`UNDECIDED`."""
    if lo > 0.0:
        return 1
    if hi < 0.0:
        return -1
    return UNDECIDED
