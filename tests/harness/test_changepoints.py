"""Change points of a series of runs: time steps (binary segmentation + ratio + rank test) and
counter changes (exact), on synthetic series whose steps are known."""

from __future__ import annotations

import math

import numpy as np
import pytest

from vorobench.harness.changepoints import counter_steps, time_steps


def _series(levels, repeats=5, noise=0.05, run_noise=0.0, seed=0):
    """Repeats per run: level x uniform noise of +-noise (and a per-run offset of +-run_noise)."""
    rng = np.random.default_rng(seed)
    out = []
    for level in levels:
        offset = 1 + rng.uniform(-run_noise, run_noise)
        out.append(level * offset * (1 + rng.uniform(-noise, noise, repeats)))
    return out


@pytest.mark.parametrize("seed", range(5))
def test_a_30_percent_step_is_found_at_its_run(seed):
    series = _series([0.010] * 7 + [0.013] * 8, seed=seed)
    steps = time_steps(series)
    assert [s.index for s in steps] == [7]
    step = steps[0]
    assert step.ratio == pytest.approx(1.3, rel=0.05)
    assert step.before == pytest.approx(0.010, rel=0.05) and step.after == pytest.approx(0.013, rel=0.05)
    assert step.p_value < 0.05


def test_a_speed_up_is_a_step_too():
    steps = time_steps(_series([2.0] * 6 + [1.4] * 6, seed=3))
    assert [s.index for s in steps] == [6] and steps[0].ratio == pytest.approx(0.7, rel=0.05)


def test_a_step_at_the_last_run_is_found():
    """The case CI cares about: the newest commit made it slower."""
    steps = time_steps(_series([1.0] * 12 + [1.3], seed=1))
    assert [s.index for s in steps] == [12]


def test_a_regression_and_its_fix_are_two_steps():
    steps = time_steps(_series([1.0] * 5 + [1.4] * 5 + [1.0] * 5, seed=2))
    assert [s.index for s in steps] == [5, 10]
    assert steps[0].ratio > 1.3 and steps[1].ratio < 1 / 1.3


@pytest.mark.parametrize("seed", range(20))
def test_pure_noise_of_five_percent_has_no_change_point(seed):
    # +-5 % within a run and +-5 % from run to run: nothing reaches a 10 % step.
    assert time_steps(_series([1.0] * 15, noise=0.05, run_noise=0.05, seed=seed)) == []


def test_the_threshold_decides_how_small_a_step_counts():
    series = _series([1.0] * 8 + [1.06] * 8, noise=0.01, seed=4)
    assert time_steps(series, threshold=0.10) == []
    assert [s.index for s in time_steps(series, threshold=0.03)] == [8]


def test_too_few_repeats_cannot_make_a_change_point():
    """One repeat per run: the rank test of a single run against a single run cannot reach p < alpha."""
    assert time_steps([np.array([1.0]), np.array([2.0])]) == []
    # ... while five repeats a side can
    assert [s.index for s in time_steps([np.full(5, 1.0) * np.linspace(0.99, 1.01, 5),
                                         np.full(5, 2.0) * np.linspace(0.99, 1.01, 5)])] == [1]


def test_every_reported_step_satisfies_the_rule_with_its_reported_numbers():
    levels = [1.0] * 3 + [1.3] * 3 + [0.8] * 3 + [1.15] * 2 + [1.3] * 2
    threshold, alpha = 0.10, 0.05
    steps = time_steps(_series(list(levels), noise=0.08, seed=7), threshold=threshold, alpha=alpha)
    assert steps
    for s in steps:
        assert abs(math.log(s.ratio)) > math.log(1 + threshold)
        assert s.p_value < alpha
        assert s.ratio == pytest.approx(s.after / s.before)


def test_short_series_have_no_step():
    assert time_steps([]) == []
    assert time_steps([np.array([1.0, 1.1, 0.9])]) == []


def test_a_run_without_repeats_is_refused():
    with pytest.raises(ValueError, match="run 1"):
        time_steps([np.array([1.0]), np.array([])])


def test_counter_changes_are_found_exactly():
    steps = counter_steps([5, 5, 5, 7, 7, None, 7, 9])
    assert [(s.index, s.previous_index, s.before, s.after) for s in steps] == [(3, 2, 5, 7), (7, 6, 7, 9)]


def test_a_counter_change_of_one_is_a_change():
    assert [s.index for s in counter_steps([1_000_000] * 4 + [1_000_001])] == [4]


def test_a_constant_or_empty_counter_has_no_change():
    assert counter_steps([3, 3, None, 3]) == []
    assert counter_steps([None, None]) == []
    assert counter_steps([]) == []
