"""The compiled sweep of disks (``impls/fortune/disk_sweep.py``) against its specification, the
sweep in rationals (``apollonius_sweep.py``): the same diagram on every point layout with every
radius family; the exact stage reached where the filters cannot tell (lattices, cocircular
disks) and not on random disks; vertices of one point merged; rays linked by their asymptotes
where a cell has several."""

from __future__ import annotations

import numpy as np
import pytest

import datasets_gen
import impls
from impls.fortune import apollonius_sweep, build_disks, disk_sweep
from vorobench.core.prepare import prepare_disks
from vorobench.judge.disk_judging import certify_disks, compare_disks
from vorobench.judge.outcomes import Verdict


def _both(points, radii, stats=None):
    centres, radii, _ = prepare_disks(points, radii)
    return build_disks(centres, radii, stats), apollonius_sweep.build(centres, radii)


def _same(compiled, rational) -> None:
    verdict = compare_disks(rational, compiled)
    assert verdict.verdict is Verdict.EXACT, verdict.detail


@pytest.mark.parametrize("family", sorted(datasets_gen.RADIUS_FAMILIES))
def test_every_layout_gives_the_rational_sweeps_diagram(family):
    for layout in datasets_gen.available():
        for n in (5, 30):
            points = datasets_gen.generate(layout, n, seed=11)
            _same(*_both(points, datasets_gen.radii(family, points, seed=11)))


def test_random_disks_need_no_exact_stage():
    rng = np.random.default_rng(3)
    points = rng.random((300, 2))
    stats: dict = {}
    compiled, rational = _both(points, rng.random(300) * 0.03, stats)
    _same(compiled, rational)
    assert stats["circle_events"] > 300 and stats["breakpoint_tests"] > 300
    assert stats["breakpoint_exact"] == stats["event_comparisons_exact"] == stats["circle_tests_exact"] == 0


def test_a_lattice_of_disks_is_decided_exactly_and_its_vertices_merged():
    """Equal disks on a grid but one larger corner: each other square's four disks touch one
    circle, which the filters cannot tell from two circles; the exact stage decides, and the
    square's two circle events make one vertex."""
    points = np.array([[x, y] for y in range(6) for x in range(6)], dtype=np.float64)
    radii = np.full(36, 0.25)
    radii[35] = 0.3
    stats: dict = {}
    compiled, rational = _both(points, radii, stats)
    _same(compiled, rational)
    assert stats["event_comparisons_exact"] > 0 and stats["circle_tests_exact"] > 0
    assert stats["merged_vertices"] == 24                    # one per square but the corner's
    assert certify_disks(compiled).ok


def test_equal_radii_go_to_the_ordinary_sweep():
    """Equal disks have the centres' diagram: the ordinary sweep's, bit for bit, with the copies
    of a disk hidden and the site ids those of the input."""
    rng = np.random.default_rng(6)
    centres = rng.random((50, 2))
    centres[7] = centres[3]                        # a copy: hidden
    ordinary = impls.get("fortune").build(np.delete(centres, 7, axis=0))
    disks = build_disks(centres, np.full(50, 0.01))
    assert disks.hidden.tolist() == [7]
    kept = np.delete(np.arange(50), 7)
    assert np.array_equal(disks.vertices, ordinary.vertices) and np.array_equal(disks.next, ordinary.next)
    assert np.array_equal(disks.site, kept[ordinary.site])


def test_a_cell_with_several_rays_is_linked_by_their_asymptotes():
    """Collinear centres, radii alternating: the big disk 1 between two small ones reaches
    infinity on both sides of the line, and the small disk 2's cell is a lens between two
    vertices; cell 1's two rays out, which the shared linker refuses, are linked in the order of
    their asymptotes."""
    centres = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]])
    radii = np.array([0.1, 0.3, 0.1, 0.3])
    compiled, rational = _both(centres, radii)
    _same(compiled, rational)
    rays_out = [h for h in compiled.cell_half_edges(1) if compiled.origin[compiled.twin[h]] < 0]
    assert len(rays_out) == 2 and compiled.n_vertices == 2
    assert certify_disks(compiled).ok


def test_the_registry_builds_disks_with_the_compiled_sweep():
    rng = np.random.default_rng(8)
    points, radii = rng.random((60, 2)), rng.random(60) * 0.1
    stats: dict = {}
    d = impls.build("fortune", points, radii=radii, stats=stats)
    assert "circle_tests" in stats and stats["site_events"] + stats["hidden_sites"] == 60
    assert certify_disks(d).ok


def test_site_events_come_in_the_exact_order_of_their_times():
    """y - r of disks 0 and 1 round to one float (1.0) but differ exactly: disk 0's comes first
    though its x is larger; disks 1 and 2 share the first exact time after it, in order of x."""
    xs = np.array([5.0, 2.0, 1.0, 0.0])
    ys = np.array([1.0, 1.0, 1.5, 3.0])
    rs = np.array([2.0 ** -60, 0.0, 0.5, 0.0])
    order, first_row = disk_sweep.event_order(xs, ys, rs)
    assert order.tolist() == [0, 2, 1, 3] and first_row == 1
    order, first_row = disk_sweep.event_order(xs[1:], ys[1:], rs[1:])
    assert order.tolist() == [1, 0, 2] and first_row == 2


def test_disks_beyond_the_filters_range_are_decided_exactly():
    """Coordinates near 1e150 overflow the filters' squares: every decision goes to the exact
    stage, and the diagram is still the specification's."""
    rng = np.random.default_rng(4)
    centres, radii = rng.random((12, 2)) * 1e150, rng.random(12) * 1e148
    stats: dict = {}
    compiled = build_disks(centres, radii, stats)
    _same(compiled, apollonius_sweep.build(centres, radii))
    assert stats["circle_tests_exact"] == stats["circle_tests"] > 0
