"""Interval arithmetic (vorobench/core/predicates/interval.py): every operation's interval holds
the exact result of its operands' exact values, including near overflow and underflow, so a
sign it decides is the true sign."""

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobench.core.predicates import interval as iv

finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


def _holds(lo, hi, exact: Fraction) -> bool:
    # an infinite end bounds anything on its side
    return (lo == -math.inf or Fraction(lo) <= exact) and (hi == math.inf or exact <= Fraction(hi))


@settings(max_examples=300, deadline=None)
@given(finite, finite)
def test_each_operation_holds_the_exact_result(a, b):
    fa, fb = Fraction(a), Fraction(b)
    assert _holds(*iv.add(a, a, b, b), fa + fb)
    assert _holds(*iv.sub(a, a, b, b), fa - fb)
    assert _holds(*iv.mul(a, a, b, b), fa * fb)
    assert _holds(*iv.sqr(a, a), fa * fa)
    assert _holds(*iv.half(a, a), fa / 2)
    if b != 0:
        assert _holds(*iv.div(a, a, b, b), fa / fb)
    lo, hi = iv.sqrt(abs(a), abs(a))
    # sqrt(|a|) is irrational in general: compare squares
    assert lo * lo <= abs(a) or lo == 0
    assert hi == math.inf or Fraction(hi) ** 2 >= abs(fa)


def test_an_overflowed_end_still_holds_the_exact_value():
    # -1e308 + -1e308 overflows; the interval must still hold -2e308, and dividing by it must
    # hold the true quotient (about -5e-9), not shrink around 0
    below = iv.add(-1e308, -1e308, -1e308, -1e308)
    assert _holds(*below, Fraction(-2) * Fraction(1e308)) and not np.isnan(below[1])
    lo, hi = iv.div(1e300, 1e300, *below)
    assert _holds(lo, hi, Fraction(1e300) / (Fraction(-2) * Fraction(1e308)))
    assert iv.sign(*iv.mul(0.0, 0.0, -math.inf, math.inf)) == iv.UNDECIDED


@pytest.mark.parametrize("x", [0.0, 5e-324, 1e-310, 1.0, 2.0 ** 52, 1e308])
def test_a_float_taken_exactly_is_held_and_decided_unless_zero(x):
    # x + 0 is exact; a sum in the subnormal range (the least subnormal included) is exact too
    lo, hi = iv.add(x, x, 0.0, 0.0)
    assert lo <= x <= hi
    assert iv.sign(lo, hi) == (1 if x > 0 else iv.UNDECIDED)


# ends that are zeros, subnormals or ordinary floats: the cases where a 0 end is kept exact
end = st.one_of(st.just(0.0), st.just(-0.0), st.floats(-1e-300, 1e-300, allow_nan=False), finite)
intervals = st.tuples(end, end).map(sorted)


@settings(max_examples=500, deadline=None)
@given(intervals, intervals)
def test_intervals_hold_every_exact_result_of_their_ends(a, b):
    # the exact extremes of +, -, *, / over two intervals are at their corners (a square's at a
    # corner or 0): each result interval must hold all of them
    (alo, ahi), (blo, bhi) = a, b
    corners = [(Fraction(x), Fraction(y)) for x in (alo, ahi) for y in (blo, bhi)]
    for op, exact in ((iv.add, lambda x, y: x + y), (iv.sub, lambda x, y: x - y), (iv.mul, lambda x, y: x * y)):
        lo, hi = op(alo, ahi, blo, bhi)
        assert all(_holds(lo, hi, exact(x, y)) for x, y in corners), (op, a, b, lo, hi)
    if not blo <= 0.0 <= bhi:
        lo, hi = iv.div(alo, ahi, blo, bhi)
        assert all(_holds(lo, hi, x / y) for x, y in corners), ("div", a, b, lo, hi)
    lo, hi = iv.sqr(alo, ahi)
    squares = [Fraction(x) ** 2 for x in (alo, ahi)] + ([Fraction(0)] if alo <= 0.0 <= ahi else [])
    assert all(_holds(lo, hi, v) for v in squares), ("sqr", a, lo, hi)
    lo, hi = iv.half(alo, ahi)
    assert _holds(lo, hi, Fraction(alo) / 2) and _holds(lo, hi, Fraction(ahi) / 2), ("half", a, lo, hi)
    if alo >= 0.0:
        lo, hi = iv.sqrt(alo, ahi)
        for x in (alo, ahi):
            assert lo == 0 or Fraction(lo) ** 2 <= Fraction(x)
            assert hi == math.inf or Fraction(hi) ** 2 >= Fraction(x)


def _subnormal(x: float) -> bool:
    return x != 0.0 and abs(x) < 2.0 ** -1022


def test_exact_zeros_stay_exact_and_widening_makes_no_subnormal():
    # a lattice's equal coordinates: their difference is exactly 0, and so is its product with
    # anything; a product that underflowed to 0 is widened by the least normal float, not to a
    # subnormal (each operation on one costs the processor a microcode assist: lattices once
    # spent most of their time there)
    zero = iv.sub(0.25, 0.25, 0.25, 0.25)
    assert zero == (0.0, 0.0)
    assert iv.mul(*zero, 0.1, 0.3) == (0.0, 0.0) and iv.sqr(*zero) == (0.0, 0.0)
    assert iv.div(*zero, 0.1, 0.3) == (0.0, 0.0) and iv.sqrt(*zero) == (0.0, 0.0)
    assert iv.half(*zero) == (0.0, 0.0)
    for lo, hi in (iv.mul(0.0, 1e-200, 1e-200, 1e-100),       # 0 exact below, an underflow above
                   iv.mul(-1e-200, 1e-200, 1e-200, 1e-100),   # both ends underflow
                   iv.add(0.1, 0.2, 0.3, 0.4), iv.sqr(-1e-170, 1e-170)):
        assert not _subnormal(lo) and not _subnormal(hi), (lo, hi)


def test_a_divisor_with_one_end_nan_gives_the_whole_line():
    # the two-quotient division picks its corners by the divisor's signs; a NaN end must not
    # pick a branch (an interval operation never makes one, but a caller might)
    assert iv.div(-1.0, 1.0, math.nan, 2.0) == (-math.inf, math.inf)
    assert iv.div(-1.0, 1.0, -2.0, math.nan) == (-math.inf, math.inf)
