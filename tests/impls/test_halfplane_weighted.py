"""The half-plane oracle on weighted sites (power diagrams): against an exact brute force that
shares none of its ideas, against the weighted qhull, on hidden sites, on lattices with
integer weights (exact degeneracies), and equal weights giving the ordinary diagram bit for bit."""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import datasets_gen
import impls
import vorobench
from impls.halfplane import cells
from vorobench.core.circumcentre import power_centre
from vorobench.core.predicates import N_POWER_COUNTERS
from vorobench.core.prepare import prepare_weighted

# ------------------------------------------------------------------------------------------
# Brute force: for every pair (a, b), the part of their power bisector where both have the
# smallest power is a 1-D linear program, solved in exact rational arithmetic; O(n^3).
# ------------------------------------------------------------------------------------------

def _brute_force(sites, weights):
    """{(a, b) with a < b: (start, end)} of the power diagram, start/end the exact ends (pairs of
    Fractions, None at infinity) of a's half-edge, which runs along perp(p_b - p_a).

    On the bisector x(t) = x0 + t perp(D), D = p_b - p_a, site k's constraint pow_a <= pow_k is
    alpha t + beta <= 0. A k with alpha = beta = 0 ties with a and b along the whole line (its
    bisectors with them are the same line: k lies on the line through a and b); of such a
    group only the two extreme sites along D own the two sides, the others are hidden."""
    p = [(Fraction(float(x)), Fraction(float(y))) for x, y in sites]
    w = [Fraction(float(v)) for v in weights]
    n = len(p)
    out = {}
    for a in range(n):
        for b in range(a + 1, n):
            dx, dy = p[b][0] - p[a][0], p[b][1] - p[a][1]
            dd = dx * dx + dy * dy
            s = (dd - (w[b] - w[a])) / (2 * dd)
            x0 = (p[a][0] + s * dx, p[a][1] + s * dy)
            d = (-dy, dx)
            lo, hi, ok, tied = None, None, True, [a, b]
            for k in range(n):
                if k in (a, b):
                    continue
                kx, ky = p[k][0] - p[a][0], p[k][1] - p[a][1]
                alpha = 2 * (d[0] * kx + d[1] * ky)
                beta = (2 * (x0[0] * kx + x0[1] * ky) + p[a][0] ** 2 + p[a][1] ** 2
                        - p[k][0] ** 2 - p[k][1] ** 2 - w[a] + w[k])
                if alpha == 0:
                    if beta > 0:
                        ok = False
                    elif beta == 0:
                        tied.append(k)
                elif alpha > 0:
                    hi = -beta / alpha if hi is None else min(hi, -beta / alpha)
                else:
                    lo = -beta / alpha if lo is None else max(lo, -beta / alpha)
            if not ok or (lo is not None and hi is not None and lo >= hi):
                continue
            along = sorted(tied, key=lambda k: (p[k][0] - p[a][0]) * dx + (p[k][1] - p[a][1]) * dy)
            if {along[0], along[-1]} != {a, b}:
                continue
            ends = tuple(None if t is None else (x0[0] + t * d[0], x0[1] + t * d[1]) for t in (lo, hi))
            out[(a, b)] = ends
    return out


def _assert_matches_brute_force(d, rel=1e-9):
    """Same ridges, same hidden sites, half-edges oriented the same way and ends at the exact
    points (to ``rel`` of the coordinates' or the vertex's magnitude: coordinates are rounded)."""
    sites = np.asarray(d.sites)
    expected = _brute_force(sites, d.weights)
    got = {}
    for h in range(d.n_half_edges):
        a, b = int(d.site[h]), int(d.site[d.twin[h]])
        if a < b:
            got[(a, b)] = (int(d.origin[h]), int(d.origin[d.twin[h]]))
    assert set(got) == set(expected), (sorted(set(got) - set(expected)), sorted(set(expected) - set(got)))
    visible = {s for pair in expected for s in pair}
    hidden = [i for i in range(d.n_sites) if i not in visible] if expected else []
    assert list(d.hidden) == hidden
    scale = max(1.0, float(np.abs(sites).max())) if sites.size else 1.0
    for pair, (start, end) in expected.items():
        for vid, exact in zip(got[pair], (start, end)):
            assert (vid < 0) == (exact is None), (pair, vid, exact)
            if exact is not None:
                err = max(abs(Fraction(float(c)) - e) for c, e in zip(d.vertices[vid], exact))
                assert err <= rel * max(scale, *(abs(e) for e in exact)), (pair, d.vertices[vid], exact)


def test_brute_force_finds_the_hidden_middle_of_a_collinear_lifted_triple():
    # the oracle of the oracle: a = (2, 0) ties with i and b along x = 1 and is hidden there;
    # the fourth site makes the set non-collinear
    sites = np.array([[0.0, 0.0], [2.0, 0.0], [4.0, 0.0], [1.0, 5.0]])
    ridges = _brute_force(sites, [0.0, 0.0, 8.0, 0.0])
    assert (0, 2) in ridges and (0, 1) not in ridges and (1, 2) not in ridges
    assert all(1 not in pair for pair in ridges)


# ------------------------------------------------------------------------------------------
# Against the brute force
# ------------------------------------------------------------------------------------------

def _float_sets():
    # rounded to 12 digits: magnitudes stay in the exact range (a weight of 1e-80 is not)
    def real(lo, hi):
        return st.floats(lo, hi).map(lambda v: round(v, 12))
    return st.lists(st.tuples(st.tuples(real(0, 1), real(0, 1)), real(-0.05, 0.25)), min_size=3, max_size=12)


def _lattice_sets():
    # small integer coordinates and integer weights: coplanar lifted quadruples, sites exactly
    # on bisectors, collinear lifted triples
    return st.lists(st.tuples(st.tuples(st.integers(0, 4), st.integers(0, 4)), st.integers(0, 3)),
                    min_size=3, max_size=14)


def _build(rows):
    points = np.array([xy for xy, _ in rows], dtype=np.float64).reshape(-1, 2)
    weights = np.array([w for _, w in rows], dtype=np.float64)
    return impls.build("halfplane", points, weights=weights).validate()


@settings(max_examples=150, deadline=None)
@given(_float_sets())
def test_random_weighted_sets_match_the_brute_force(rows):
    _assert_matches_brute_force(_build(rows))


@settings(max_examples=150, deadline=None)
@given(_lattice_sets())
def test_integer_weights_on_a_lattice_match_the_brute_force(rows):
    _assert_matches_brute_force(_build(rows))


@settings(max_examples=60, deadline=None)
@given(_lattice_sets(), st.randoms(use_true_random=False))
def test_cells_do_not_depend_on_the_clipping_order(rows, random):
    # the same cells (as cyclic lists) whatever order the sites are clipped in
    points = np.array([xy for xy, _ in rows], dtype=np.float64).reshape(-1, 2)
    sites, w, _ = prepare_weighted(points, np.array([w for _, w in rows], dtype=np.float64))
    if sites.shape[0] < 3 or not _not_collinear(sites):
        return
    results = []
    for _ in range(2):
        order = np.array(random.sample(range(sites.shape[0]), sites.shape[0]), dtype=np.int64)
        ptr, nbs, unbounded, _ = cells(sites, order, np.zeros(N_POWER_COUNTERS, dtype=np.int64), w)
        results.append([_canonical(nbs[ptr[i]:ptr[i + 1]], unbounded[i]) for i in range(sites.shape[0])])
    assert results[0] == results[1]


def _not_collinear(sites):
    d = sites[1:] - sites[0]
    return bool(np.any(d[:, 0] * d[0, 1] - d[:, 1] * d[0, 0] != 0))


def _canonical(cycle, unbounded):
    cycle = [int(c) for c in cycle]
    if unbounded or not cycle:
        return tuple(cycle)
    k = cycle.index(min(cycle))
    return tuple(cycle[k:] + cycle[:k])


# ------------------------------------------------------------------------------------------
# Hidden sites, degenerate lattices
# ------------------------------------------------------------------------------------------

def test_a_lattice_lifted_onto_one_plane_keeps_only_its_corners():
    # w = |p|^2 lifts every site to height 0: one plane; only the four corners are lower-hull
    # corners, the other 21 sites are hidden (edge sites: collinear lifted triples, inner
    # sites: points inside the facet), and the corners' four quadrants meet at the origin
    grid = np.stack(np.meshgrid(np.arange(5.0), np.arange(5.0)), axis=-1).reshape(-1, 2)
    stats = {}
    d = impls.build("halfplane", grid, stats, weights=(grid * grid).sum(axis=1)).validate()
    corners = [0, 4, 20, 24]
    assert list(d.hidden) == [i for i in range(25) if i not in corners]
    assert d.n_vertices == 1 and d.n_edges == 4 and np.array_equal(d.vertices[0], [0.0, 0.0])
    assert stats["hidden"] == 21 and stats["relabelled"] > 0 and stats["merged_vertices"] > 0
    _assert_matches_brute_force(d)


def test_an_edge_goes_to_the_farther_of_two_sites_with_the_same_bisector():
    # (2, 0) and (4, 0) with w = 8 have the same bisector with (0, 0): x = 1; (2, 0) is hidden
    # and the edge belongs to (4, 0), whichever of the two is clipped first
    for extra in ([[1.0, 5.0]], [[1.0, -5.0], [3.0, 6.0]]):
        for first, second in ((1, 2), (2, 1)):
            sites = np.array([[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]] + extra)
            w = np.array([0.0, 0.0, 8.0] + [0.0] * len(extra))
            order = np.array([0, first, second] + list(range(3, len(sites))), dtype=np.int64)
            ptr, nbs, _, _ = cells(sites, order, np.zeros(N_POWER_COUNTERS, dtype=np.int64), w)
            assert 1 not in nbs and ptr[2] == ptr[1]          # site 1: no cell, no neighbour
            assert 2 in nbs[ptr[0]:ptr[1]]
            d = impls.build("halfplane", sites, weights=w).validate()
            assert list(d.hidden) == [1]
            _assert_matches_brute_force(d)


def test_many_hidden_sites_agree_with_qhull_and_the_certificate():
    pts = datasets_gen.generate("uniform", 600, seed=5)
    w = datasets_gen.weights("hidden", pts, seed=5)
    stats = {}
    d = impls.build("halfplane", pts, stats, weights=w).validate()
    assert d.hidden.size > 600 // 3 and stats["hidden"] == d.hidden.size
    assert vorobench.compare(d, impls.build("qhull", pts, weights=w)).equal
    assert vorobench.certify(d).ok


def test_a_site_outside_its_own_cell():
    # a light site next to a heavy one: its cell is pushed away and does not contain it
    sites = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 3.0], [3.0, 3.0], [5.0, -2.0]])
    w = np.array([4.0, 0.0, 0.0, 0.0, 0.0])
    d = impls.build("halfplane", sites, weights=w).validate()
    assert 1 not in d.hidden
    x = sites[1]
    power = ((x - sites) ** 2).sum(axis=1) - w
    assert int(np.argmin(power)) == 0                          # site 1 lies in site 0's cell
    _assert_matches_brute_force(d)


@pytest.mark.parametrize("dataset", ["grid", "lattice_rotated"])
def test_integer_weights_on_lattices_give_vertices_of_degree_four_or_more(dataset):
    pts = datasets_gen.generate(dataset, 144, seed=1)
    w = datasets_gen.weights("integer", pts, seed=4)
    stats = {}
    d = impls.build("halfplane", pts, stats, weights=w).validate()
    degree = np.bincount(np.asarray(d.origin)[np.asarray(d.origin) >= 0], minlength=d.n_vertices)
    assert degree.max() >= 4 and stats["merged_vertices"] > 0
    assert vorobench.compare(d, impls.build("qhull", pts, weights=w)).equal
    assert vorobench.certify(d).ok


def test_lattice_vertex_coordinates_come_from_the_three_smallest_site_ids():
    # 6 x 6 unit lattice, weights 0/1: every vertex is the power centre of its three smallest
    # sites, computed by power_centre, whatever triple the cells found it as
    pts = datasets_gen.generate("grid", 36, seed=1)
    w = datasets_gen.weights("integer", pts, seed=2)
    d = impls.build("halfplane", pts, weights=w).validate()
    sites_at = [set() for _ in range(d.n_vertices)]
    for h in range(d.n_half_edges):
        if d.origin[h] >= 0:
            sites_at[d.origin[h]].add(int(d.site[h]))
    s, ww = np.asarray(d.sites), np.asarray(d.weights)
    for v, around in enumerate(sites_at):
        a, b, c = sorted(around)[:3]
        expected = power_centre(s[a, 0], s[a, 1], ww[a], s[b, 0], s[b, 1], ww[b], s[c, 0], s[c, 1], ww[c])
        assert tuple(d.vertices[v]) == expected


@pytest.mark.parametrize("family", ["radii", "integer", "hidden"])
@pytest.mark.parametrize("dataset", ["uniform", "normal", "grid"])
def test_agrees_with_weighted_qhull(family, dataset):
    pts = datasets_gen.generate(dataset, 400, seed=2)
    w = datasets_gen.weights(family, pts, seed=3)
    d = impls.build("halfplane", pts, weights=w).validate()
    result = vorobench.compare(d, impls.build("qhull", pts, weights=w))
    assert result.equal, str(result)


# ------------------------------------------------------------------------------------------
# Equal weights: exactly the ordinary diagram
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("value", [0.0, 0.3, -7.0])
@pytest.mark.parametrize("dataset", ["uniform", "grid", "cocircular_many", "normal"])
def test_equal_weights_give_the_ordinary_diagram_bit_for_bit(dataset, value):
    pts = datasets_gen.generate(dataset, 300, seed=6)
    stats = {}
    weighted = impls.build("halfplane", pts, stats, weights=np.full(len(pts), value)).validate()
    ordinary = impls.build("halfplane", pts)
    assert stats["power_test_calls"] > 0 and stats["hidden"] == 0         # the power path ran
    assert np.array_equal(weighted.vertices, ordinary.vertices)
    assert vorobench.compare(weighted, ordinary).verdict == "exact"


# ------------------------------------------------------------------------------------------
# Small n, duplicates, collinear input
# ------------------------------------------------------------------------------------------

def test_zero_one_and_two_sites():
    assert impls.build("halfplane", np.zeros((0, 2)), weights=np.zeros(0)).validate().n_edges == 0
    one = impls.build("halfplane", [[1.0, 2.0]], weights=[5.0]).validate()
    assert one.n_edges == 0 and one.hidden.size == 0
    # two sites: never hidden, whatever the weights (each keeps a half-plane)
    two = impls.build("halfplane", [[0.0, 0.0], [1.0, 0.0]], weights=[100.0, 0.0]).validate()
    assert two.n_edges == 1 and two.hidden.size == 0
    _assert_matches_brute_force(two)


def test_three_collinear_sites_with_the_middle_one_hidden():
    d = impls.build("halfplane", [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]], weights=[0.0, -1.0, 0.0]).validate()
    assert list(d.hidden) == [1] and d.n_edges == 1
    _assert_matches_brute_force(d)


def test_three_sites_not_collinear_are_never_hidden():
    # the three bisectors meet at the power centre: three wedges, whatever the weights
    d = impls.build("halfplane", [[0.0, 0.0], [1.0, 0.0], [0.5, 0.1]], weights=[0.0, 0.0, -50.0]).validate()
    assert d.hidden.size == 0 and d.n_vertices == 1
    _assert_matches_brute_force(d)


def test_four_sites_with_one_hidden():
    d = impls.build("halfplane", [[0.0, 0.0], [4.0, 0.0], [2.0, 3.0], [2.0, 1.0]],
                    weights=[4.0, 4.0, 4.0, -10.0]).validate()
    assert list(d.hidden) == [3] and d.n_vertices == 1
    _assert_matches_brute_force(d)


def test_duplicates_keep_the_larger_weight():
    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.0], [0.5, 0.2], [0.5, 1.0], [1.0, 0.0]])
    w = np.array([0.0, 0.1, 0.3, 0.0, 0.0, -2.0])
    d = impls.build("halfplane", pts, weights=w).validate()
    kept = impls.build("halfplane", pts[[0, 1, 3, 4]], weights=[0.3, 0.1, 0.0, 0.0]).validate()
    assert vorobench.compare(d, kept).verdict == "exact"
    assert np.array_equal(d.vertices, kept.vertices)
    # heavy duplicate of (0, 0) hides (0.5, 0.2), the light one would not
    heavy = impls.build("halfplane", pts, weights=np.where(np.arange(6) == 2, 1.0, w)).validate()
    assert heavy.n_sites == 4 and 2 in heavy.hidden
    _assert_matches_brute_force(heavy)


def test_collinear_input_goes_to_the_weighted_collinear_diagram():
    pts = np.stack([np.arange(6.0), 2.0 * np.arange(6.0)], axis=1)
    w = np.array([0.0, -3.0, 0.0, 1.0, -20.0, 0.0])
    stats = {}
    d = impls.build("halfplane", pts, stats, weights=w).validate()
    assert stats["collinear"] == 1 and d.hidden.size > 0
    _assert_matches_brute_force(d)
