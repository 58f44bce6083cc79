"""certify and compare judge power diagrams by the power versions of their rules, and a wrong
power diagram does not pass: wrong weights, a site hidden that should have a cell, weights
forgotten."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import impls
from vorobench import Diagram, certify, compare

REFERENCE = "qhull"


def _weighted(n: int, seed: int, spread: float = 0.6) -> tuple[np.ndarray, np.ndarray]:
    """Random points with weights r^2, r up to ``spread`` times the mean spacing: some hidden."""
    rng = np.random.default_rng(seed)
    pts = rng.random((n, 2))
    r = rng.random(n) * spread / np.sqrt(n)
    return pts, r * r


def _power_build(pts, w) -> Diagram:
    return impls.build(REFERENCE, pts, weights=w)


def _hidden_by_force(d: Diagram, k: int) -> Diagram:
    """The power diagram of the sites without site k, with k put back as a hidden site: wrong
    whenever k has a cell in ``d``."""
    keep = np.flatnonzero(np.arange(d.n_sites) != k)
    rest = impls.build(REFERENCE, d.sites[keep], weights=np.asarray(d.weights)[keep])
    return Diagram(d.sites, rest.vertices, rest.origin, rest.twin, rest.next, keep[rest.site], weights=d.weights)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_power_diagram_is_certified_by_the_power_rules(seed):
    pts, w = _weighted(300, seed)
    d = _power_build(pts, w)
    assert d.hidden.size > 0, "the case should hide some sites"
    cert = certify(d)
    assert cert.ok, str(cert)
    assert "n_visible" in cert.check("euler").detail
    assert "hidden" in cert.check("probes").detail


def test_certify_refuses_a_site_hidden_that_has_a_cell():
    pts, w = _weighted(200, 4)
    d = _power_build(pts, w)
    visible = np.setdiff1d(np.arange(d.n_sites), d.hidden)
    interior = [k for k in visible if not (d.origin[d.site == k] < 0).any()]
    wrong = _hidden_by_force(d, int(interior[0]))
    wrong.validate()                             # a valid DCEL: only the geometry tells
    cert = certify(wrong)
    assert not cert.ok and "probes" in cert.failed


def test_certify_refuses_the_wrong_weights_and_forgotten_weights():
    pts, w = _weighted(200, 5)
    d = _power_build(pts, w)
    other = w[np.random.default_rng(0).permutation(w.size)]
    assert not certify(d.with_weights(other)).ok
    forgotten = certify(replace(d, weights=None))
    assert not forgotten.ok, "a power diagram judged as ordinary must fail"


def test_compare_sees_weights_hidden_sites_and_constants():
    pts, w = _weighted(250, 6)
    d = _power_build(pts, w)
    assert compare(d, d.with_weights(w + 3.5)).verdict == "exact"        # a constant changes no power order
    c = compare(d, d.with_weights(w[::-1].copy()))
    assert not c.equal and c.counts["weight_mismatch"] > 0
    visible = np.setdiff1d(np.arange(d.n_sites), d.hidden)
    c = compare(d, _hidden_by_force(d, int(visible[0])), labels=("right", "wrong"))
    assert not c.equal and c.counts["hidden_only_in_b"] == 1 and c.counts["hidden_only_in_a"] == 0
    assert "no cell in wrong" in str(c)


def test_equal_weights_are_the_ordinary_diagram():
    pts, _ = _weighted(300, 7)
    d = _power_build(pts, np.full(300, 0.25))
    ordinary = impls.build("incremental", pts)
    assert d.hidden.size == 0
    assert compare(d, ordinary).equal
    assert certify(d).ok


def test_hull_corners_keep_their_cells_whatever_the_weights():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.3, 0.3]])
    d = _power_build(pts, np.array([0.0, 0.0, 0.0, 10.0]))
    assert d.hidden.size == 0 and certify(d).ok          # the heavy inner site takes the middle only
    wrong = Diagram.empty(pts, np.array([0.0, 0.0, 0.0, 10.0]))      # "one visible site": never true
    wrong.validate()
    cert = certify(wrong)
    assert not cert.ok and {"hull", "probes"} <= set(cert.failed)


def _kuzmin_radii():
    """Heavy-tailed points whose largest weight is 10^7 times the median: a certificate that
    judged powers by the largest weight would let errors of the small cells through."""
    import datasets_gen

    pts = datasets_gen.generate("kuzmin", 300, seed=2)
    return pts, datasets_gen.weights("radii", pts, seed=2)


def test_a_wide_weight_range_does_not_blunt_the_certificate():
    pts, w = _kuzmin_radii()
    assert w.max() > 1e6 * np.median(w)
    d = _power_build(pts, w)
    assert certify(d).ok
    rng = np.random.default_rng(1)
    judged = 0
    for _ in range(15):
        i, j = rng.choice(pts.shape[0], size=2, replace=False)
        swapped = w.copy()
        swapped[[i, j]] = swapped[[j, i]]
        wrong = impls.build("incremental", pts, weights=swapped).with_weights(w)
        if compare(d, wrong).equal:
            continue                                 # the swap changed nothing
        judged += 1
        assert certify(wrong).verdict == "not_certified", (i, j)
    assert judged >= 5
    visible = np.setdiff1d(np.arange(pts.shape[0]), d.hidden)
    for k in visible[::5]:
        assert certify(_hidden_by_force(d, int(k)), probes=1000).verdict == "not_certified", int(k)


def test_a_swap_of_two_weights_is_reported_as_those_two_sites():
    pts, w = _weighted(100, 8)
    d = _power_build(pts, w)
    swapped = w.copy()
    swapped[[0, 1]] = swapped[[1, 0]]
    c = compare(d, d.with_weights(swapped))
    assert c.counts["weight_mismatch"] == 2 and {x.sites for x in c.differences} == {(0,), (1,)}
