"""Hidden disks (inside another, touching included) against every pair decided in rationals."""

from fractions import Fraction as F

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import datasets_gen
from vorobench.core.hidden_disks import hidden_disks


def brute_force(centres, radii) -> np.ndarray:
    """Disk i is hidden when some disk j contains it, (|p_i - p_j| + r_i <= r_j, in rationals),
    unless the two are identical and i comes first."""
    n = len(radii)
    out = np.zeros(n, dtype=bool)
    for i in range(n):
        for j in range(n):
            if i == j:
                continue
            g = F(radii[j]) - F(radii[i])
            d2 = (F(centres[i][0]) - F(centres[j][0])) ** 2 + (F(centres[i][1]) - F(centres[j][1])) ** 2
            if g >= 0 and g * g >= d2 and not (g == 0 and d2 == 0 and i < j):
                out[i] = True
    return out


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(-4, 4), st.integers(-4, 4), st.integers(0, 6)), min_size=1, max_size=25),
       st.sampled_from([1.0, 0.1, 2.0 ** -30, 1e6]))
def test_small_integer_disks_tangent_identical_and_nested(disks, scale):
    # small integers: internal tangency, identical disks and point disks on rims abound
    d = np.array(disks, dtype=float) * scale
    assert np.array_equal(hidden_disks(d[:, :2], d[:, 2]), brute_force(d[:, :2], d[:, 2]))


def test_one_ulp_decides_internal_tangency():
    centres = np.array([[0.0, 0.0], [1.0, 0.0]])
    assert hidden_disks(centres, np.array([2.0, 1.0])).tolist() == [False, True]        # touching inside
    assert hidden_disks(centres, np.array([2.0, np.nextafter(1.0, 2.0)])).tolist() == [False, False]
    # a point disk on the rim of a disk off the axes (dyadic 3-4-5 triangle)
    centres = np.array([[0.5, 0.25], [0.875, 0.75]])
    assert hidden_disks(centres, np.array([0.625, 0.0])).tolist() == [False, True]
    assert hidden_disks(centres, np.array([np.nextafter(0.625, 0.0), 0.0])).tolist() == [False, False]


def test_identical_disks_keep_the_first():
    centres = np.array([[1.0, 1.0], [1.0, 1.0], [1.0, 1.0]])
    assert hidden_disks(centres, np.array([0.5, 0.5, 0.5])).tolist() == [False, True, True]
    assert hidden_disks(centres, np.array([0.5, 0.7, 0.5])).tolist() == [True, False, True]


@pytest.mark.parametrize("family", sorted(datasets_gen.RADIUS_FAMILIES))
@pytest.mark.parametrize("centres, n", [("uniform", 200), ("grid", 144)])
def test_radius_families(family, centres, n):
    # on the grid, tangent and integer radii make exact ties (decided in rationals)
    points = datasets_gen.generate(centres, n, seed=1)
    r = datasets_gen.radii(family, points, seed=2)
    hidden = hidden_disks(points, r)
    assert np.array_equal(hidden, brute_force(points, r))
    if family in ("separate", "equal", "tangent", "last_bit") and centres == "uniform":
        assert not hidden.any()
    if family in ("nested", "huge"):
        assert hidden.any()


def test_bad_input_is_refused():
    with pytest.raises(ValueError, match="shape"):
        hidden_disks(np.zeros((3, 3)), np.zeros(3))
    with pytest.raises(ValueError, match="radii must have shape"):
        hidden_disks(np.zeros((3, 2)), np.zeros(2))
    with pytest.raises(ValueError, match=">= 0"):
        hidden_disks(np.zeros((2, 2)), np.array([1.0, -1.0]))
    with pytest.raises(ValueError, match="finite"):
        hidden_disks(np.zeros((2, 2)), np.array([1.0, np.nan]))


def test_far_scales_give_the_same_disks_hidden():
    # scaled by powers of two (exact) far from 1: squares would overflow or underflow there
    points = datasets_gen.generate("grid", 144, seed=3)
    r = datasets_gen.radii("integer", points, seed=4)
    want = hidden_disks(points, r)
    assert want.any()
    for k in (-1000, -520, 500, 1000):
        assert np.array_equal(hidden_disks(np.ldexp(points, k), np.ldexp(r, k)), want)
    # found by a review: a margin below the subnormal range, and one that overflowed to nan
    g, d = np.sqrt(2.6) * 2.0**-537, np.sqrt(1.4) * 2.0**-537
    centres, radii = np.array([[0.0, 0.0], [d, d]]), np.array([0.0, g])
    assert np.array_equal(hidden_disks(centres, radii), brute_force(centres, radii))
    centres, radii = np.array([[0.0, 0.0], [1e200, 0.0]]), np.array([3e200, 1e200])
    assert hidden_disks(centres, radii).tolist() == [False, True]


def test_disks_all_tangent_at_one_point():
    # x = 1..n on a line, r = x: each disk touches all the bigger ones at the origin, so
    # every pair is an exact tie and only the biggest stays visible
    x = np.arange(1.0, 301.0) * 0.1
    centres = np.column_stack([x, np.zeros_like(x)])
    got = hidden_disks(centres, x.copy())
    assert np.array_equal(got, brute_force(centres, x))


def test_inputs_outside_the_exact_range_are_refused():
    from vorobench.core.scaling import OutsideExactRange
    with pytest.raises(OutsideExactRange, match="hidden_disks"):
        hidden_disks(np.array([[0.0, 0.0], [1e-170, 0.0]]), np.array([1.0, 1.0]))
