"""The sweep for disks in rationals (``impls/fortune/apollonius_sweep.py``, the specification of
the compiled sweep that ``fortune`` runs) against the exact oracle: the same diagram exactly on
every point layout with every radius family, equal radii giving the ordinary diagram, and the
configurations that broke its first version."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import datasets_gen
import impls
from impls import halfplane_disks
from impls.fortune import apollonius_sweep
from vorobench.core.prepare import prepare_disks
from vorobench.judge.disk_judging import certify_disks, compare_disks
from vorobench.judge.outcomes import Verdict


def _agrees(centres, radii) -> None:
    centres, radii, _ = prepare_disks(centres, radii)
    swept = apollonius_sweep.build(centres, radii)
    verdict = compare_disks(halfplane_disks.build(centres, radii), swept)
    assert verdict.verdict is Verdict.EXACT, verdict.detail


@pytest.mark.parametrize("family", sorted(datasets_gen.RADIUS_FAMILIES))
def test_every_layout_agrees_exactly_with_the_oracle(family):
    for layout in datasets_gen.available():
        for n in (3, 9):
            points = datasets_gen.generate(layout, n, seed=7)
            _agrees(points, datasets_gen.radii(family, points, seed=7))


@pytest.mark.parametrize("layout", ["uniform", "grid", "cocircular_many", "near_grid"])
def test_thirty_disks_agree_and_certify(layout):
    points = datasets_gen.generate(layout, 30, seed=2)
    for family in ("random", "integer", "last_bit"):
        radii = datasets_gen.radii(family, points, seed=2)
        _agrees(points, radii)
        centres, site_radii, _ = prepare_disks(points, radii)
        assert certify_disks(apollonius_sweep.build(centres, site_radii)).ok


def test_a_circle_seen_by_two_arcs_closes_the_one_whose_breakpoints_meet_there():
    """Three disks whose two Apollonius circles both exist: the beach line holds 0, 2, 1, 0, and
    the far circle (0, 2, 1) is seen by arc 2 (between 0 and 1) and by arc 1 (between 2 and 0).
    Only arc 1's breakpoints meet there: cell 1 is the bounded lens, cell 2 stays unbounded."""
    centres = np.array([[2.0409191173531683, -2.5556650295328327], [0.4180988492209493, -0.5677696075476458],
                        [-0.45264928929718594, -0.21559715870218823]])
    radii = np.array([0.8394859435651049, 0.11897113791451546, 0.40479514165014854])
    d = apollonius_sweep.build(centres, radii)
    assert d.n_vertices == 2 and all(d.origin[h] >= 0 for h in d.cell_half_edges(1))
    assert any(d.origin[h] < 0 for h in d.cell_half_edges(2))
    _agrees(centres, radii)


def test_a_first_row_of_disks_at_one_time_can_close_its_middle_arc():
    """From `fuzz --radii integer` (shrunk): three disks reach the sweep line at one time, side by
    side; the middle one's parabola is the narrowest, its arc closes at a vertex. The first
    version scheduled no circle event among the spikes of a first row."""
    centres, radii = np.array([[-1.0, -8.0], [1.0, -8.0], [-4.0, -7.0]]), np.array([1.0, 1.0, 2.0])
    assert apollonius_sweep.build(centres, radii).n_vertices == 1
    _agrees(centres, radii)


@pytest.mark.parametrize("layout", ["uniform", "grid", "cocircular", "collinear"])
def test_equal_radii_give_the_ordinary_diagram(layout):
    points = datasets_gen.generate(layout, 30, seed=4)
    radii = np.full(len(points), 0.125)
    ordinary = impls.build("fortune", points)
    disks = impls.build("fortune", points, radii=radii)
    as_disks = replace(ordinary, radii=disks.radii)       # degree-4 vertices split by zero-length edges on a grid
    assert compare_disks(as_disks, replace(disks, input_points=None, input_site=None)).verdict is Verdict.EXACT
    assert certify_disks(as_disks).ok


def test_through_the_registry_with_copies_and_hidden_disks():
    centres = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0], [0.2, 0.1]])
    d = impls.build("fortune", centres, radii=[0.5, 0.1, 0.2, 0.3, 0.05])
    assert d.radii.tolist() == [0.5, 0.3, 0.2, 0.05] and d.hidden.tolist() == [3]     # (0.2, 0.1) inside disk 0
    assert certify_disks(d).ok
