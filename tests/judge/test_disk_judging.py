"""The judge of diagrams of disks: the oracle's diagrams certify and compare exact with
themselves; diagrams wrong in one way each fail the check that looks at that way."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import datasets_gen
from datasets_gen.radius_families import radii as radius_family
from impls import halfplane, halfplane_disks
from vorobench.core.diagram import Diagram
from vorobench.judge.disk_judging import cells_around, certify_disks, compare_disks
from vorobench.judge.outcomes import Verdict


def _three_cones(degrees):
    """A disk of radius 10 with three of radius 1 sticking out of it at these angles."""
    angles = np.radians(degrees)
    centres = np.vstack([[0.0, 0.0], 10.5 * np.column_stack([np.cos(angles), np.sin(angles)])])
    return centres, np.array([10.0, 1.0, 1.0, 1.0])


@pytest.mark.parametrize("family", ["random", "nested", "integer", "huge", "equal"])
@pytest.mark.parametrize("layout", ["uniform", "grid", "cocircular", "duplicates"])
def test_the_oracles_diagrams_certify_and_compare_exact(layout, family):
    centres = datasets_gen.generate(layout, 25, seed=4)
    d = halfplane_disks.build(centres, radius_family(family, centres, 4))
    certificate = certify_disks(d)
    assert certificate.ok, str(certificate)
    assert compare_disks(d, d).verdict is Verdict.EXACT


def test_cells_around_a_vertex_turn_counter_clockwise():
    # the lens of a small disk between two big ones: its upper corner has cells 0 (left),
    # 1 (the lens, below) and 2 (right), counter-clockwise from the left: 0, 1, 2
    d = halfplane_disks.build(np.array([[-10.0, 0.0], [0.0, 0.0], [10.0, 0.0]]), np.array([9.5, 0.1, 9.5]))
    upper = int(np.argmax(d.vertices[:, 1]))
    cells = cells_around(d)[upper]
    k = cells.index(0)
    assert cells[k:] + cells[:k] == [0, 1, 2]


def test_a_vertex_moved_off_its_circle_fails():
    centres = datasets_gen.generate("uniform", 20, seed=1)
    d = halfplane_disks.build(centres, radius_family("random", centres, 1))
    moved = np.array(d.vertices)
    moved[3] += 1e-5
    certificate = certify_disks(replace(d, vertices=moved))
    assert certificate.failed == ["vertices"] and certificate.check("vertices").offending == [3]
    assert compare_disks(d, replace(d, vertices=moved)).verdict is Verdict.DIFFERS


def test_the_ordinary_diagram_passed_off_as_one_of_disks_fails():
    centres = datasets_gen.generate("uniform", 30, seed=2)
    radii = radius_family("random", centres, 2)
    wrong = replace(halfplane.build(centres), radii=radii)
    certificate = certify_disks(wrong)
    assert {"vertices", "edges", "hidden"} <= set(certificate.failed)
    assert compare_disks(halfplane_disks.build(centres, radii), wrong).verdict is Verdict.DIFFERS


def test_an_edge_crossed_by_a_disk_fails_though_every_vertex_is_right():
    """Cones at 0, 120 and 240 degrees never meet: three whole branches, no vertex. Passed off
    as the diagram of cones at 0, 40 and 240 degrees (whose first two meet, once), it has no vertex to
    fail, the right hidden set and Euler's relation; only the edge check sees disk 2 cross the
    branch of disks 0 and 1."""
    apart = halfplane_disks.build(*_three_cones([0.0, 120.0, 240.0]))
    centres, radii = _three_cones([0.0, 40.0, 240.0])
    assert halfplane_disks.build(centres, radii).n_vertices == 1            # where cones 1 and 2 meet
    wrong = Diagram(centres, apart.vertices, apart.origin, apart.twin, apart.next, apart.site, radii=radii)
    certificate = certify_disks(wrong)
    assert "edges" in certificate.failed and not {"vertices", "hidden", "euler"} & set(certificate.failed), \
        str(certificate)


def test_a_hidden_disk_with_a_cell_and_a_visible_one_without_fail():
    centres, radii = np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 3.0]]), np.array([1.0, 1.0, 1.0])
    d = halfplane_disks.build(centres, radii)
    assert "hidden" in certify_disks(replace(d, radii=np.array([1.0, 1.0, 5.0]))).failed


def test_the_order_of_half_edges_in_the_arrays_does_not_matter():
    centres = datasets_gen.generate("uniform", 20, seed=3)
    d = halfplane_disks.build(centres, radius_family("random", centres, 3))
    H = d.n_half_edges
    perm = np.random.default_rng(0).permutation(H)             # new id of each half-edge
    inverse = np.argsort(perm)
    shuffled = Diagram(d.sites, d.vertices, np.asarray(d.origin)[inverse], perm[np.asarray(d.twin)[inverse]],
                       perm[np.asarray(d.next)[inverse]], np.asarray(d.site)[inverse], radii=d.radii)
    assert certify_disks(shuffled).ok
    assert compare_disks(d, shuffled).verdict is Verdict.EXACT


def test_a_diagram_without_radii_is_refused():
    d = halfplane.build(datasets_gen.generate("uniform", 10, seed=0))
    certificate = certify_disks(d)
    assert not certificate.ok and "no radii" in certificate.check("structure").detail


def test_rays_linked_in_the_wrong_order_around_a_cell_fail():
    """From a helper's review: a big disk with three small ones sticking out has three gaps at
    infinity; walking them clockwise is still one cycle per cell (validate passes) but is no
    diagram. The certificate's rays check and the comparison both see it."""
    from dataclasses import replace as with_fields

    centres = np.array([[0.0, 0.0], [11.0, 0.0], [-5.0, 9.0], [-5.0, -9.0]])
    d = halfplane_disks.build(centres, np.array([10.0, 1.0, 1.0, 1.0]))
    big = d.cell_half_edges(0)
    assert len(big) == 3
    nxt = np.array(d.next)
    nxt[big[0]], nxt[big[1]], nxt[big[2]] = big[2], big[0], big[1]
    wrong = with_fields(d, next=nxt).validate()
    assert certify_disks(d).ok and certify_disks(wrong).failed == ["rays"]
    assert compare_disks(d, wrong).verdict is Verdict.DIFFERS


def test_a_diagram_of_other_radii_or_without_radii_is_wrong_sites():
    from vorobench.judge.engine import BuildResult, certify_result

    centres = datasets_gen.generate("uniform", 12, seed=5)
    radii = radius_family("random", centres, 5)
    d = halfplane_disks.build(centres, radii)
    for diagram, says in ((replace(d, radii=radii * 1.5), "other radii"),
                          (halfplane.build(centres), "a diagram of points for disks")):
        res = certify_result(BuildResult("x", True, diagram), centres, radii=radii)
        assert res.failure == Verdict.WRONG_SITES and says in res.error
    res = certify_result(BuildResult("x", True, d), centres)
    assert res.failure == Verdict.WRONG_SITES and "a diagram of disks for points" in res.error
    assert certify_result(BuildResult("x", True, d), centres, radii=radii).certificate.ok
