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
def test_a_float_taken_exactly_is_held_and_decided_unless_zero_or_the_least_subnormal(x):
    lo, hi = iv.add(x, x, 0.0, 0.0)
    assert lo <= x <= hi
    assert iv.sign(lo, hi) == (1 if x > 5e-324 else iv.UNDECIDED)
