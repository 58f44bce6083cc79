"""The qhull adapter's power diagrams (lower hull of the lifted sites through ConvexHull) against
brute force: probes by smallest power over all sites, the empty-power-circle certificate with the
exact power test, hidden sites decided by brute force over triangles, equal weights, duplicates,
collinear and tiny inputs, and inputs where most sites are hidden."""

from __future__ import annotations

from itertools import combinations

import numpy as np
import pytest

import datasets_gen
import impls
from vorobench import compare
from vorobench.core.incidence import vertex_site_lists
from vorobench.core.predicates import orient2d_many, power_test_many

RNG_SEED = 20250316


def radii_weights(rng, n, radius):
    """Weights of disks with random radii up to ``radius``: w = r**2."""
    return (rng.random(n) * radius) ** 2


def powers(sites, weights, x):
    """(k, n) powers |x - p|^2 - w of k points against every site."""
    return ((x[:, None, :] - sites[None, :, :]) ** 2).sum(axis=2) - weights[None, :]


def assert_probes_lie_in_the_cell_of_least_power(d, sites, weights, rng, k=1500):
    """Random points of the sites' box lie in the cell of the site of least power among all
    sites, hidden ones included (probes within rounding of a tie are skipped)."""
    lo, hi = sites.min(axis=0), sites.max(axis=0)
    span = float((hi - lo).max())
    box = (lo[0] - 0.1 * span, lo[1] - 0.1 * span, hi[0] + 0.1 * span, hi[1] + 0.1 * span)
    x = np.column_stack([rng.uniform(box[0], box[2], k), rng.uniform(box[1], box[3], k)])
    pw = powers(sites, weights, x)
    two = np.argsort(pw, axis=1)[:, :2]
    best = two[:, 0]
    gap = pw[np.arange(k), two[:, 1]] - pw[np.arange(k), best]
    clear = gap > 1e-9 * span * span
    assert clear.mean() > 0.95
    hidden = set(d.hidden.tolist())
    assert not hidden & set(best[clear].tolist()), "a hidden site has the least power somewhere"
    for s in np.unique(best[clear]):
        poly = d.cell_polygon(int(s), box)
        assert poly.shape[0] >= 3, f"site {s} has the least power at probes but no cell"
        q = x[clear & (best == s)]
        e = np.roll(poly, -1, axis=0) - poly                     # CCW polygon edges
        rel = q[:, None, :] - poly[None, :, :]
        cross = e[None, :, 0] * rel[:, :, 1] - e[None, :, 1] * rel[:, :, 0]
        assert np.all(cross >= -1e-9 * span * span), f"a probe of least power at {s} lies outside its cell"


def dual_triangles(d):
    """Counter-clockwise site triples of the diagram's vertices (each has exactly three sites)."""
    ptr, vs = vertex_site_lists(d.site, d.origin, None, d.n_vertices, d.n_sites)
    assert np.all(np.diff(ptr) == 3)
    tri = vs.reshape(-1, 3).copy()
    o = orient2d_many(d.sites[tri[:, 0]], d.sites[tri[:, 1]], d.sites[tri[:, 2]])
    assert np.all(o != 0)
    tri[o < 0] = tri[o < 0][:, [0, 2, 1]]
    return tri


def assert_regular(d, sites, weights):
    """No site, hidden or not, is in conflict with the power circle of any dual triangle (exact
    power test): the triangulation dual to the diagram is the regular one."""
    W = np.column_stack([sites, weights])
    tri = dual_triangles(d)
    T, n = tri.shape[0], sites.shape[0]
    a, b, c = (np.repeat(W[tri[:, k]], n, axis=0) for k in range(3))
    conflict = power_test_many(a, b, c, np.tile(W, (T, 1))) > 0
    assert not conflict.any(), f"{int(conflict.sum())} (triangle, site) conflicts"


def brute_force_hidden(sites, weights):
    """Sites whose lifted point is not a vertex of the lower hull: it lies in (the closed
    projection of) a triangle of three other sites and on or above their lifted plane. Exact
    predicates; O(n^4)."""
    n = sites.shape[0]
    W = np.column_stack([sites, weights])
    hidden = []
    for i in range(n):
        others = [j for j in range(n) if j != i]
        tri = np.array(list(combinations(others, 3)), dtype=np.int64)
        o = orient2d_many(sites[tri[:, 0]], sites[tri[:, 1]], sites[tri[:, 2]])
        tri, o = tri[o != 0], o[o != 0]
        tri[o < 0] = tri[o < 0][:, [0, 2, 1]]
        inside = np.ones(tri.shape[0], dtype=bool)
        for u, v in ((0, 1), (1, 2), (2, 0)):
            inside &= orient2d_many(sites[tri[:, u]], sites[tri[:, v]], sites[i]) >= 0
        tri = tri[inside]
        below = power_test_many(W[tri[:, 0]], W[tri[:, 1]], W[tri[:, 2]], W[i]) <= 0
        if below.any():
            hidden.append(i)
    return hidden


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_weighted_sites_against_brute_force(seed):
    rng = np.random.default_rng(RNG_SEED + seed)
    sites = rng.random((300, 2))
    weights = radii_weights(rng, 300, 0.12)
    stats = {}
    d = impls.build("qhull", sites, weights=weights, stats=stats).validate()
    assert stats["joggled"] == 0
    assert 30 <= d.hidden.size <= 250                  # weights from radii hide many sites
    assert stats["hidden"] == d.hidden.size
    assert d.n_vertices - d.n_edges + d.n_visible == 1
    assert_regular(d, sites, weights)
    assert_probes_lie_in_the_cell_of_least_power(d, sites, weights, rng)


def test_hidden_sites_are_exactly_those_off_the_lower_hull():
    rng = np.random.default_rng(RNG_SEED + 10)
    for _ in range(3):
        sites = rng.random((26, 2))
        weights = radii_weights(rng, 26, 0.5)
        d = impls.build("qhull", sites, weights=weights).validate()
        expected = brute_force_hidden(sites, weights)
        assert 2 <= len(expected) <= 22
        assert d.hidden.tolist() == expected
        # a hidden site has no half-edge and is in no ridge
        assert not np.isin(d.site, expected).any()
        assert not np.isin(d.ridge_points, expected).any()


def test_most_sites_hidden_under_a_few_huge_weights():
    rng = np.random.default_rng(RNG_SEED + 20)
    sites = rng.random((600, 2))
    weights = np.zeros(600)
    big = rng.choice(600, 4, replace=False)
    weights[big] = rng.uniform(0.2, 0.4, 4)
    d = impls.build("qhull", sites, weights=weights).validate()
    assert set(big.tolist()) <= set(range(600)) - set(d.hidden.tolist())
    assert d.n_visible < 150
    assert_regular(d, sites, weights)
    assert_probes_lie_in_the_cell_of_least_power(d, sites, weights, rng)


def test_every_site_but_one_hidden():
    rng = np.random.default_rng(RNG_SEED + 21)
    sites = rng.random((50, 2))
    weights = np.zeros(50)
    weights[7] = 100.0                                     # its disk covers everything
    d = impls.build("qhull", sites, weights=weights).validate()
    # the hull sites stay visible (extreme in the plane, so on the lower hull); others hidden
    from vorobench.core.hull import convex_hull_polygon
    hull_sites = set(convex_hull_polygon(sites).tolist())
    assert set(range(50)) - set(d.hidden.tolist()) == hull_sites | {7}
    assert_regular(d, sites, weights)
    assert_probes_lie_in_the_cell_of_least_power(d, sites, weights, rng)


def test_far_hidden_sites_do_not_drown_tiny_spacing():
    # Sites 1e-9 apart, twenty interior ones with weight -1: their lifted points sit ~1e18
    # spacings^2 above the rest, whose differences Qhull must still see (second, narrower run).
    rng = np.random.default_rng(RNG_SEED + 22)
    sites = rng.random((400, 2)) * 1e-9
    from vorobench.core.hull import convex_hull_polygon
    interior = np.setdiff1d(np.arange(400), convex_hull_polygon(sites))
    far = np.sort(rng.choice(interior, 20, replace=False))
    weights = np.zeros(400)
    weights[far] = -1.0
    d = impls.build("qhull", sites, weights=weights).validate()
    assert d.hidden.tolist() == far.tolist()
    assert_regular(d, sites, weights)


@pytest.mark.parametrize("seed", [0, 1])
def test_the_joggled_run_closes_up_on_nearly_degenerate_sites(seed):
    # The fallback run ("QJ") decides on joggled points, so a sliver at the hull's boundary can
    # face the other way than the original sites say; the triangles are turned consistently
    # over the surface (not one by one), so the cells still close up. Called directly: the
    # first run succeeds on these sites.
    from impls.qhull import _build_from_lifted_hull
    sites = datasets_gen.generate("near_grid", 300, seed=seed)
    weights = np.zeros(len(sites))
    d = _build_from_lifted_hull(sites, weights, None, "Qbb Qc QJ").validate()
    assert d.n_vertices - d.n_edges + d.n_visible == 1
    assert_probes_lie_in_the_cell_of_least_power(d, sites, weights, np.random.default_rng(seed))


def test_lifted_points_on_one_plane_keep_only_the_hull_corners():
    # w = |p - u|^2 - R puts every site on the power circle (u, R): all powers equal at u,
    # one vertex there; the corners of the convex hull keep a cell, every other site is a tie.
    g = np.array([[i, j] for i in range(9) for j in range(7)], dtype=np.float64)
    rng = np.random.default_rng(RNG_SEED + 23)
    pts = np.vstack([g, rng.integers(0, 6, (20, 2)) + 0.5])          # inside the grid
    pts = np.unique(pts, axis=0)
    u = np.array([3.0, 2.0])
    weights = ((pts - u) ** 2).sum(axis=1) - 5.0
    stats = {}
    d = impls.build("qhull", pts, weights=weights, stats=stats).validate()
    assert stats["flat_lift"] == 1 and stats["joggled"] == 0
    corners = {i for i, p in enumerate(pts.tolist()) if p in ([0, 0], [8, 0], [0, 6], [8, 6])}
    assert set(range(len(pts))) - set(d.hidden.tolist()) == corners
    assert d.n_vertices == 1 and np.array_equal(d.vertices[0], u) and d.n_edges == 4


@pytest.mark.parametrize("dataset", ["uniform", "grid"])
def test_equal_weights_give_the_unweighted_qhull_diagram(dataset):
    pts = datasets_gen.generate(dataset, 400, seed=3)
    plain = impls.build("qhull", pts)
    for value in (0.0, 0.7, -2.0):
        d = impls.build("qhull", pts, weights=np.full(len(pts), value)).validate()
        assert d.hidden.size == 0
        result = compare(plain, d)
        assert result.verdict == "exact", result


def test_a_duplicated_point_keeps_its_largest_weight():
    rng = np.random.default_rng(RNG_SEED + 30)
    sites = rng.random((80, 2))
    weights = np.zeros(80)
    rows = np.vstack([sites, sites[[5, 5]]])
    # the copies of site 5 carry 0.05 (hides its neighbours) and 0 (would hide nothing)
    row_weights = np.concatenate([weights, [0.05, 0.0]])
    d = impls.build("qhull", rows, weights=row_weights).validate()
    largest = weights.copy()
    largest[5] = 0.05
    want = impls.build("qhull", sites, weights=largest)
    assert want.hidden.size >= 3
    assert d.hidden.tolist() == want.hidden.tolist()
    assert compare(want, impls.build("qhull", sites, weights=weights)).verdict == "differs"
    assert d.point_region[80] == d.point_region[81] == d.point_region[5]
    assert_probes_lie_in_the_cell_of_least_power(d, sites, largest, rng)


def test_collinear_weighted_sites_have_parallel_power_bisectors():
    # sites on y = 2x; site 3 sits just below the chord of 2 and 4, so it keeps a cell
    t = np.arange(6, dtype=np.float64)
    sites = np.column_stack([t, 2.0 * t])
    weights = np.array([0.0, -100.0, 0.0, -5.0 + 1e-9, 0.0, 3.0])
    stats = {}
    d = impls.build("qhull", sites, weights=weights, stats=stats).validate()
    assert stats["collinear"] == 1
    assert d.hidden.tolist() == [1]
    assert d.n_vertices == 0 and d.n_edges == 4
    tie = weights.copy()
    tie[3] = -5.0               # on the chord of sites 2 and 4 (s = 1/2, |4 - 2|^2 = 20): hidden too
    assert impls.build("qhull", sites, weights=tie).hidden.tolist() == [1, 3]


def test_no_one_or_two_sites():
    empty = impls.build("qhull", np.zeros((0, 2)), weights=np.zeros(0))
    assert empty.n_sites == 0 and empty.n_half_edges == 0
    one = impls.build("qhull", [[0.3, 0.4]], weights=[2.0])
    assert one.n_sites == 1 and one.n_half_edges == 0 and one.is_power
    # two sites: both keep a cell whatever the weights (a line between them)
    two = impls.build("qhull", [[0.0, 0.0], [1.0, 0.0]], weights=[100.0, 0.0]).validate()
    assert two.n_edges == 1 and two.hidden.size == 0 and two.n_vertices == 0


def test_three_sites_are_one_triangle():
    sites = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    d = impls.build("qhull", sites, weights=[0.5, 0.0, 0.1]).validate()
    assert d.n_vertices == 1 and d.n_edges == 3 and d.hidden.size == 0
    x, y = d.vertices[0]
    pw = [(x - p[0]) ** 2 + (y - p[1]) ** 2 - w for p, w in zip(sites, [0.5, 0.0, 0.1])]
    assert np.allclose(pw, pw[0], rtol=0, atol=1e-14)


def test_weights_are_refused_by_shape_and_the_implementation_is_weighted():
    assert impls.get("qhull").weighted
    assert "qhull" in impls.weighted()
    with pytest.raises(ValueError):
        impls.build("qhull", np.random.default_rng(0).random((5, 2)), weights=np.zeros(4))
