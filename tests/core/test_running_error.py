"""Floats with a running error bound (vorobench/core/predicates/running_error.py): along chains
of operations with cancellation, underflow and overflow, the exact value stays within the
bound, so a box holds it and a decided sign is the true sign."""

import math
from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobench.core.predicates import running_error as rerr
from vorobench.core.predicates.interval import UNDECIDED


def _holds(v, e, exact: Fraction) -> bool:
    ok, lo, hi = rerr.box(v, e)
    return ok and Fraction(lo) <= exact <= Fraction(hi)


def _root_holds(v, e, square: Fraction) -> bool:
    # sqrt(square) is irrational in general: compare squares
    ok, lo, hi = rerr.box(v, e)
    return ok and (lo <= 0 or Fraction(lo) ** 2 <= square) and hi >= 0 and Fraction(hi) ** 2 >= square


def _inputs(rng, n):
    """Floats of mixed scales (1e-300 to 1e300 among them), some nearly equal to others, so
    that differences cancel to their last bits."""
    scale = 10.0 ** rng.choice([-300, -150, -20, 0, 0, 0, 20, 150], size=n)
    values = rng.standard_normal(n) * scale
    for j in range(1, n):
        if rng.random() < 0.5:
            values[j] = values[j - 1] * (1 + rng.choice([1e-16, 1e-12, 1e-6]) * rng.standard_normal())
    return values


def _chain(rng, steps):
    """(v, e, exact) after a random chain of operations on random inputs; the exact value in
    rationals. A step whose divisor may be 0 gives a NaN bound, which is checked to decide
    nothing and then ends the chain."""
    pool = [(float(x), 0.0, Fraction(float(x))) for x in _inputs(rng, 4)]
    lo, hi = sorted(_inputs(rng, 2))
    pool.append((*rerr.within(lo, hi), Fraction(lo) + (Fraction(hi) - Fraction(lo)) * Fraction(rng.random())))
    for _ in range(steps):
        (a, ea, xa), (b, eb, xb) = (pool[j] for j in rng.integers(len(pool), size=2))
        op = rng.integers(6)
        if op == 0:
            got = (*rerr.add(a, ea, b, eb), xa + xb)
        elif op == 1:
            got = (*rerr.sub(a, ea, b, eb), xa - xb)
        elif op == 2:
            got = (*rerr.mul(a, ea, b, eb), xa * xb)
        elif op == 3:
            got = (*rerr.sqr(a, ea), xa * xa)
        elif op == 4:
            got = (*rerr.half(a, ea), xa / 2)
        else:
            q, eq = rerr.div(a, ea, b, eb)
            if not eq >= 0:
                assert rerr.sign(q, eq) == UNDECIDED and not rerr.box(q, eq)[0]
                break
            got = (q, eq, xa / xb)
        if not (math.isfinite(got[0]) and math.isfinite(got[1])):
            assert rerr.sign(got[0], got[1]) == UNDECIDED and not rerr.box(got[0], got[1])[0]
            break
        pool.append(got)
    return pool


def test_the_bound_holds_along_chains_of_operations():
    rng = np.random.default_rng(5)
    decided = checked = 0
    for _ in range(3000):
        for v, e, exact in _chain(rng, 8)[5:]:
            checked += 1
            assert _holds(v, e, exact), (v, e, exact)
            s = rerr.sign(v, e)
            if s != UNDECIDED:
                decided += 1
                assert s * exact > 0, (v, e, exact)
            if exact >= 0:
                assert _root_holds(*rerr.sqrt(v, e), exact), (v, e, exact)
    assert checked // 2 < decided < checked                 # cancellation leaves some undecided


@settings(max_examples=300, deadline=None)
@given(st.floats(min_value=0.0, max_value=1e300), st.floats(min_value=0.0, max_value=1e300))
def test_a_square_root_near_0_is_bounded_by_the_root_of_the_error(a, e):
    # a quantity known to be >= 0, given as a' = a with error e: the root of any value in
    # [max(a - e, 0), a + e] lies in the box
    r, er = rerr.sqrt(a, e)
    for exact in (max(Fraction(a) - Fraction(e), Fraction(0)), Fraction(a) + Fraction(e)):
        assert _root_holds(r, er, exact), (a, e, exact)


def test_a_divisor_that_may_be_0_and_an_interval_upside_down_decide_nothing():
    q, eq = rerr.div(1.0, 0.0, 1e-3, 0.6e-3)
    assert rerr.sign(q, eq) == UNDECIDED and not rerr.box(q, eq)[0]
    v, e = rerr.within(1.0, 0.5)
    assert rerr.sign(v, e) == UNDECIDED and not rerr.box(v, e)[0]
    v, e = rerr.mul(1e200, 0.0, 1e200, 0.0)                 # overflow
    assert rerr.sign(v, e) == UNDECIDED and not rerr.box(v, e)[0]


@settings(max_examples=300, deadline=None)
@given(st.floats(min_value=-1e300, max_value=1e300), st.floats(min_value=0.0, max_value=4.0))
def test_a_box_holds_both_ends_of_a_bound_below_an_ulp(v, ulps):
    # v - e and v + e are not floats when e is below an ulp of v: the box's ends must still
    # be beyond them, not rounded back to v
    e = ulps * math.ulp(v)
    for exact in (Fraction(v) - Fraction(e), Fraction(v) + Fraction(e)):
        assert _holds(v, e, exact), (v, e)


def test_the_underflow_slack_bounds_an_underflow_and_is_a_normal_float():
    # it covers a rounding that underflows (at most 2**-1075); a subnormal slack would make the
    # bounds' products subnormal, which the processor finishes in microcode (several times the
    # cost of the whole filter)
    assert rerr.TINY >= 2.0 ** -1075
    assert rerr.TINY >= np.finfo(np.float64).tiny
