"""Distances from degenerate, in roundings of the data (vorobench.core.predicates.degeneracy):
checked against a numerical gradient of numpy's own determinant, and for the invariances the
certifier's rule relies on (translation, scaling by powers of two)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobench.core.predicates.degeneracy import incircle_ulps, lift_extent, orient2d_ulps, power_test_ulps

EPS = 2.0 ** -53


def _lifted_det(p: np.ndarray, w: np.ndarray) -> float:
    return float(np.linalg.det(np.column_stack([p, (p ** 2).sum(axis=1) - w, np.ones(4)])))


def _rounding_by_finite_differences(p: np.ndarray, w: np.ndarray, extent: float, lifted: float) -> float:
    """extent * |grad_xy det|_1 + lifted * |grad_lift det|_1, by central differences."""
    total, h = 0.0, 1e-6
    for i in range(4):
        for k in range(2):
            q, r = p.copy(), p.copy()
            q[i, k] += h
            r[i, k] -= h
            total += extent * abs(_lifted_det(q, w) - _lifted_det(r, w)) / (2 * h)
        q, r = w.copy(), w.copy()
        q[i] -= h                 # the lift is x^2 + y^2 - w: a lift change is a weight change
        r[i] += h
        total += lifted * abs(_lifted_det(p, q) - _lifted_det(p, r)) / (2 * h)
    return total


@pytest.mark.parametrize("seed", range(6))
def test_the_lifted_distance_is_the_determinant_over_its_gradient(seed):
    rng = np.random.default_rng(seed)
    p, w = rng.random((4, 2)), rng.random(4) * 0.1
    extent, lifted = 0.7, 1.3
    expected = abs(_lifted_det(p, w)) / (EPS * _rounding_by_finite_differences(p, w, extent, lifted))
    got = power_test_ulps(*np.column_stack([p, w]).ravel(), extent, lifted)
    assert got == pytest.approx(expected, rel=1e-5)
    zero_w = np.zeros(4)
    expected = abs(_lifted_det(p, zero_w)) / (EPS * _rounding_by_finite_differences(p, zero_w, extent, lifted))
    assert incircle_ulps(*p.ravel(), extent, lifted) == pytest.approx(expected, rel=1e-5)


def test_the_line_distance_is_about_a_point_off_the_line():
    # c is 3e-12 off the line ab (|ab| = 1): orient = 3e-12, and its gradient's l1 norm is
    # |b - c|_1 + |c - a|_1 + |a - b|_1 = 0.5 + 0.5 + 1 (to 1e-11)
    got = orient2d_ulps(0.0, 0.0, 1.0, 0.0, 0.5, 3e-12, 1.0)
    assert got == pytest.approx(3e-12 / (EPS * 2.0), rel=1e-6)


def test_degenerate_configurations_are_at_zero():
    assert incircle_ulps(0.0, 0.0, 1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 1.0, 2.0) == 0.0       # a square
    assert orient2d_ulps(0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 1.0) == 0.0
    # four sites with equal weights on a circle: coplanar lifts
    assert power_test_ulps(0.0, 0.0, 0.5, 1.0, 0.0, 0.5, 1.0, 1.0, 0.5, 0.0, 1.0, 0.5, 1.0, 2.5) == 0.0


coordinate = st.floats(-1.0, 1.0, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(coordinate, min_size=8, max_size=8), st.integers(-40, 40), st.floats(-1e3, 1e3))
def test_the_rule_is_the_same_at_any_scale_and_place(xy, power, shift):
    """Scaling by 2**power (with the extents) and translating the input change nothing but the
    rounding of the translation: the verdict of the rule cannot depend on where the data sits."""
    p = np.array(xy).reshape(4, 2)
    if abs(_lifted_det(p, np.zeros(4))) < 1e-6:
        return                                  # too close to degenerate for translation to be exact
    extent = 1.0
    base = incircle_ulps(*p.ravel(), extent, lift_extent(extent))
    s = 2.0 ** power
    scaled = incircle_ulps(*(p * s).ravel(), extent * s, lift_extent(extent * s))
    assert scaled == pytest.approx(base, rel=1e-9)
    moved = incircle_ulps(*(p + shift).ravel(), extent, lift_extent(extent))
    assert moved == pytest.approx(base, rel=1e-6)
    o_base = orient2d_ulps(*p[:3].ravel(), extent)
    assert orient2d_ulps(*(p[:3] * s).ravel(), extent * s) == pytest.approx(o_base, rel=1e-9)
