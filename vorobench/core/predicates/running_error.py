"""Floats with a running error bound: a filter as general as intervals, and cheaper.

A quantity is a pair (v, e) of floats: the exact real value it stands for lies within e of v.
Each operation rounds v to nearest and bounds the new error from its operands' errors and its
own rounding (running error analysis: Higham, *Accuracy and Stability of Numerical
Algorithms*, 2nd ed., section 3.3). A product is one multiplication and four more for its bound,
with no branch; an interval product (:mod:`vorobench.core.predicates.interval`) takes four
products, their minimum and maximum, and the outward moves of both ends. Used where an
expression is too long to bound by hand and too frequent to leave to intervals (the contact
points of the weighted sweep).

The bounds are computed in floats too. Each is made of sums, products and square roots of
nonnegative floats and one quotient by |b| - e_b where |b| > 2 e_b (else the quotient gives a NaN
bound), so each of its roundings makes it smaller by a relative EPSILON at most; over any path
of fewer than 2**12 operations that is less than the factor :data:`SLACK` that :func:`sign`
and :func:`box` apply. A rounding that underflows errs by at most 2**-1075 however small its
result: every product, quotient and half adds :data:`TINY` to its bound. Overflow or NaN make a
bound infinite or NaN, and then :func:`sign` decides nothing and :func:`box` fails.
"""

from __future__ import annotations

import math

from numba import njit

from vorobench.core.predicates.expansion import EPSILON
from vorobench.core.predicates.interval import UNDECIDED

__all__ = ["UNDECIDED", "SLACK", "TINY", "exact", "within", "add", "sub", "mul", "sqr", "div", "half",
           "sqrt", "sign", "sign_within", "box"]

#: Relative slack on a bound computed in floats (see the module docstring).
SLACK = 1.0 + 2.0 ** -40
#: Absolute slack for a rounding that underflows: above 2**-1075, and a normal float (the least
#: is 2**-1022). A subnormal slack (2**-1060 before) makes the bound's products subnormal, and
#: the processor finishes each such operation in microcode: the weighted sweep's power centre
#: filter took 185-325 ns a call with it and 80-95 ns with 2**-1000 (400,000 calls). Far below any
#: quantity of inputs in the exact range of :mod:`vorobench.core.scaling`, it decides as much.
TINY = 2.0 ** -1000
_U = EPSILON
_NAN = math.nan


@njit(cache=True, inline='always')
def exact(x):
    """A float that is exactly the value meant."""
    return x, 0.0


@njit(cache=True, inline='always')
def within(lo, hi):
    """A value known only to lie in [lo, hi] (a NaN bound if lo > hi): its midpoint."""
    v = (lo + hi) * 0.5
    e = (hi - lo) * 0.5 + _U * abs(v) + TINY
    return v, (e if lo <= hi else _NAN)


@njit(cache=True, inline='always')
def add(a, ea, b, eb):
    """a + b (a sum that rounds below the least normal float is exact)."""
    s = a + b
    return s, ea + eb + _U * abs(s)


@njit(cache=True, inline='always')
def sub(a, ea, b, eb):
    """a - b."""
    s = a - b
    return s, ea + eb + _U * abs(s)


@njit(cache=True, inline='always')
def mul(a, ea, b, eb):
    """a * b: |ab - a'b'| <= |a'| e_b + |b'| e_a + e_a e_b."""
    p = a * b
    return p, abs(a) * eb + abs(b) * ea + ea * eb + _U * abs(p) + TINY


@njit(cache=True, inline='always')
def sqr(a, ea):
    """a * a."""
    p = a * a
    return p, 2.0 * abs(a) * ea + ea * ea + _U * p + TINY


@njit(cache=True, inline='always')
def div(a, ea, b, eb):
    """a / b: |a/b - a'/b'| <= (e_a + |a'/b'| e_b) / (|b'| - e_b); a NaN bound unless
    |b'| > 2 e_b (b may be 0, or the bound of the bound would not hold)."""
    if not abs(b) > 2.0 * eb:
        return _NAN, _NAN
    q = a / b
    # |a'/b'| <= |q| (1 + EPSILON): q is a'/b' rounded once
    return q, (ea + abs(q) * (1.0 + 2.0 * _U) * eb) / (abs(b) - eb) + _U * abs(q) + TINY


@njit(cache=True, inline='always')
def half(a, ea):
    """a / 2 (exact, barring underflow)."""
    return a * 0.5, ea * 0.5 + TINY


@njit(cache=True, inline='always')
def sqrt(a, ea):
    """The square root of a quantity known to be >= 0: with a' clamped to 0 (which only brings
    it nearer), |sqrt(a) - sqrt(a')| is at most e_a / sqrt(a') and at most sqrt(e_a)."""
    r = math.sqrt(max(a, 0.0))
    root_e = math.sqrt(ea)
    er = min(ea / r, root_e) if r > 0.0 else root_e
    return r, er + _U * r


@njit(cache=True, inline='always')
def sign_within(value, bound):
    """The sign of a value that errs by at most ``bound``, or UNDECIDED; a bound below 0 or NaN
    (an input given upside down, an overflow) decides nothing."""
    if not bound >= 0.0:
        return UNDECIDED
    if value > bound:
        return 1
    if value < -bound:
        return -1
    return UNDECIDED


@njit(cache=True, inline='always')
def sign(v, e):
    """-1 or 1 when the exact value is surely on that side of 0, else UNDECIDED."""
    return sign_within(v, e * SLACK)


@njit(cache=True, inline='always')
def box(v, e):
    """(ok, lo, hi) with the exact value in [lo, hi] when ok: the bound gets the slack and the
    roundings of v - E and v + E (each errs by at most EPSILON (|v| + E))."""
    bound = (e + 2.0 * _U * abs(v)) * SLACK + TINY
    ok = 0.0 <= bound < math.inf and abs(v) < math.inf
    return ok, v - bound, v + bound
