"""The repeats of a case of disks: their inputs scale the radii with the centres (a length, by
2**shift) and stay in the exact range, and the judge of every repeat takes only the diagram of
exactly those disks."""

from __future__ import annotations

import numpy as np

import datasets_gen
import impls
from disk_doubles import oracle, points_for_disks
from vorobench.core.scaling import exact_shift
from vorobench.harness.repeat_check import RepeatJudging, repeat_shifts
from vorobench.harness.site_attributes import RADII
from vorobench.harness.worker import scaled_input
from vorobench.judge.declarations import declaration_from_data, declaration_of
from vorobench.judge.engine import diagram_arrays, prepare_disk_case


def _disks(n: int = 20, seed: int = 3) -> tuple[np.ndarray, np.ndarray]:
    points = datasets_gen.generate("uniform", n, seed=seed)
    return prepare_disk_case(points, datasets_gen.radii("random", points, seed=seed))


def test_scaled_disks_have_the_scaled_diagram():
    sites, radii = _disks()
    built = oracle(sites, radii)
    for shift in (3, -2):
        given, given_radii = scaled_input(sites, radii, shift, RADII)
        scaled = oracle(given, given_radii)
        assert np.array_equal(scaled.next, built.next) and np.array_equal(scaled.site, built.site)
        assert np.array_equal(np.ldexp(scaled.vertices, -shift), built.vertices)


def test_repeat_shifts_keep_the_radii_in_the_exact_range():
    # centres near 1, radii at the bottom of the exact range (2**-100): any shift down takes
    # the radii out of it, though the centres alone would allow it
    sites = np.array([[0.5, 0.75], [1.0, 0.25], [0.25, 1.0]])
    radii = np.array([2.0 ** -100, 0.0, 2.0 ** -99])
    assert min(repeat_shifts(sites, 7)) < 0                     # the centres alone: shifts both ways
    shifts = repeat_shifts(RADII.range_rows(sites, radii), 7)
    assert len(set(shifts)) == 7 and min(shifts) == 0
    for shift in shifts:
        given, given_radii = scaled_input(sites, radii, shift, RADII)
        assert exact_shift(RADII.range_rows(given, given_radii)) == 0          # in the range, as given


def _judging(sites: np.ndarray, radii: np.ndarray, shifts: list[int]) -> RepeatJudging:
    declared = declaration_from_data(declaration_of(impls.get("halfplane")), "halfplane")
    return RepeatJudging("halfplane", declared, sites, radii, shifts, RADII)


def test_every_repeat_must_carry_exactly_the_case_radii_scaled_by_its_shift():
    sites, radii = _disks()
    judging = _judging(sites, radii, [0, 2, -1, 1])
    right = [diagram_arrays(oracle(*scaled_input(sites, radii, shift, RADII))) for shift in (0, 2, -1, 1)]
    judging.take(0, right[0])
    judging.take(1, right[1])
    judging.take(2, {**right[2], "radii": right[2]["radii"] * 2.0})       # the radii of another shift
    judging.take(3, {k: v for k, v in right[3].items() if k != "radii"})      # a diagram of points
    verdicts = judging.verdicts(4, None, None, probes=100)
    assert [v["verdict"] for v in verdicts] == ["certified", "certified", "wrong_sites", "wrong_sites"]
    assert "other radii" in verdicts[2]["verdict_detail"]
    assert "a diagram of points for disks" in verdicts[3]["verdict_detail"]


def test_a_repeat_of_the_centres_diagram_is_judged_as_disks():
    sites, radii = _disks()
    judging = _judging(sites, radii, [0, 1])
    judging.take(0, diagram_arrays(oracle(sites, radii)))
    judging.take(1, diagram_arrays(points_for_disks(*scaled_input(sites, radii, 1, RADII))))
    verdicts = judging.verdicts(2, None, None, probes=100)
    assert [v["verdict"] for v in verdicts] == ["certified", "not_certified"]
    assert verdicts[1]["verdict_detail"].startswith("repeat 1 differs from repeat 0")
