"""The incremental implementation with weights: its regular triangulation (certified edge by
edge), its power diagram against an exact brute-force construction (random, many hidden,
lattice degeneracies, hypothesis), equal weights against the ordinary build, duplicates, tiny
inputs, and agreement with the other weighted constructions."""

from fractions import Fraction
from itertools import combinations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import datasets_gen
import impls
from impls.incremental import build, build_weighted, delaunay, regular
from vorobench.core.predicates import orient2d_many, power_test_many
from vorobench.core.prepare import prepare, prepare_weighted
from vorobench.judge.comparison import compare

# ---------------------------------------------------------------------------------------------
# Exact brute force: each cell is a box cut by the half-planes pow_i(x) <= pow_j(x), in fractions
# ---------------------------------------------------------------------------------------------


def _clip(poly, a, b, c):
    """The part of convex polygon ``poly`` (Fraction pairs) where a x + b y <= c."""
    out = []
    for k in range(len(poly)):
        P, Q = poly[k], poly[(k + 1) % len(poly)]
        fp = a * P[0] + b * P[1] - c
        fq = a * Q[0] + b * Q[1] - c
        if fp <= 0:
            out.append(P)
        if fp * fq < 0:
            t = fp / (fp - fq)
            out.append((P[0] + t * (Q[0] - P[0]), P[1] + t * (Q[1] - P[1])))
    kept = [P for k, P in enumerate(out) if P != out[k - 1]] if len(out) > 1 else out
    return kept


def _twice_area(poly):
    return sum(poly[k][0] * poly[(k + 1) % len(poly)][1] - poly[(k + 1) % len(poly)][0] * poly[k][1]
               for k in range(len(poly)))


def _exact_power_diagram(sites, weights):
    """(hidden sites, ridges as sorted site pairs, finite vertices of each cell), exactly.

    The box holds every radical centre and where each radical axis crosses its sites' line, with
    a margin, so every vertex and every ridge of the diagram is inside it."""
    S = [(Fraction(float(x)), Fraction(float(y))) for x, y in sites]
    W = [Fraction(float(w)) for w in weights]
    n = len(S)
    if n == 0:
        return set(), set(), {}
    xs = [p[0] for p in S]
    ys = [p[1] for p in S]
    for i, j in combinations(range(n), 2):
        dx, dy = S[j][0] - S[i][0], S[j][1] - S[i][1]
        t = (dx * dx + dy * dy + W[i] - W[j]) / (2 * (dx * dx + dy * dy))
        xs.append(S[i][0] + t * dx)
        ys.append(S[i][1] + t * dy)
    for i, j, k in combinations(range(n), 3):
        (ax, ay), (bx, by), (cx, cy) = S[i], S[j], S[k]
        det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        if det:
            b2 = (bx - ax) ** 2 + (by - ay) ** 2 - (W[j] - W[i])
            c2 = (cx - ax) ** 2 + (cy - ay) ** 2 - (W[k] - W[i])
            xs.append(ax + ((cy - ay) * b2 - (by - ay) * c2) / (2 * det))
            ys.append(ay + ((bx - ax) * c2 - (cx - ax) * b2) / (2 * det))
    span = max(max(xs) - min(xs), max(ys) - min(ys), Fraction(1))
    x0, x1, y0, y1 = min(xs) - span, max(xs) + span, min(ys) - span, max(ys) + span

    def power(j, P):
        return (P[0] - S[j][0]) ** 2 + (P[1] - S[j][1]) ** 2 - W[j]

    cells = []
    for i in range(n):
        poly = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        for j in range(n):
            if j != i and poly:
                poly = _clip(poly, 2 * (S[j][0] - S[i][0]), 2 * (S[j][1] - S[i][1]),
                             S[j][0] ** 2 + S[j][1] ** 2 - W[j] - S[i][0] ** 2 - S[i][1] ** 2 + W[i])
        cells.append(poly if len(poly) >= 3 and _twice_area(poly) != 0 else [])
    hidden = {i for i in range(n) if not cells[i]}
    ridges, vertices = set(), {}
    for i in range(n):
        poly = cells[i]
        vertices[i] = [P for P in poly if P[0] not in (x0, x1) and P[1] not in (y0, y1)]
        for k in range(len(poly)):
            P, Q = poly[k], poly[(k + 1) % len(poly)]
            for j in range(n):
                if j != i and cells[j] and power(j, P) == power(i, P) and power(j, Q) == power(i, Q):
                    ridges.add((min(i, j), max(i, j)))
    return hidden, ridges, vertices


def _assert_exact_power_diagram(d, sites, weights):
    """The diagram has the hidden sites, ridges and cell vertices of the exact construction."""
    hidden, ridges, vertices = _exact_power_diagram(sites, weights)
    assert set(d.hidden.tolist()) == hidden, f"hidden sites {sorted(d.hidden.tolist())}, exactly {sorted(hidden)}"
    got = {(int(min(a, b)), int(max(a, b))) for a, b in d.ridge_points}
    assert got == ridges, f"ridges: extra {sorted(got - ridges)}, missing {sorted(ridges - got)}"
    for i in range(len(sites)):
        own = d.origin[d.site == i]
        mine = np.unique(d.vertices[own[own >= 0]], axis=0).reshape(-1, 2)
        exact = np.array([(float(x), float(y)) for x, y in vertices[i]]).reshape(-1, 2)
        assert len(mine) == len(exact), f"cell {i}: {len(mine)} vertices, exactly {len(exact)}"
        for x, y in exact:
            gap = np.abs(mine - [x, y]).max(axis=1)
            assert gap.min() <= 1e-12 * max(1.0, abs(x), abs(y)), f"cell {i}: no vertex at ({x}, {y})"


def _assert_regular(sites, weights):
    """Exact certificate of :func:`regular`: counter-clockwise finite triangles with consistent
    twins tiling the convex hull, every interior edge locally regular (lifted surface convex),
    and every site left out lifted on or above the triangle it lies in."""
    n = sites.shape[0]
    result = regular(sites, weights)
    if result is None:
        assert n < 3 or not orient2d_many(sites[0], sites[1], sites[2:]).any()
        return
    tri, opp, ntri = result
    corners = tri.reshape(-1, 3)
    e = np.arange(3 * ntri)
    assert np.array_equal(opp[opp], e)
    ends = corners[:, [1, 2, 0]].reshape(-1)
    assert np.array_equal(tri[opp], ends), "a twin does not run the other way"
    finite = corners[(corners < n).all(axis=1)]
    a, b, c = (sites[finite[:, k]] for k in range(3))
    assert np.all(orient2d_many(a, b, c) == 1)
    lifted = np.c_[sites, weights]
    t, k = e // 3, e % 3
    d = corners[opp // 3, (opp % 3 + 2) % 3]
    x, y, z = corners[t, k], corners[t, (k + 1) % 3], corners[t, (k + 2) % 3]
    inner = (x < n) & (y < n) & (z < n) & (d < n)
    assert not np.any(power_test_many(lifted[x[inner]], lifted[y[inner]], lifted[z[inner]], lifted[d[inner]]) > 0), \
        "a locally non-regular edge"
    for g in corners[(corners == n).any(axis=1)]:
        j = int(np.flatnonzero(g == n)[0])
        u, v = g[(j + 1) % 3], g[(j + 2) % 3]
        assert not np.any(orient2d_many(sites[u], sites[v], sites) > 0), "the hull is not convex"
    used = np.zeros(n, dtype=bool)
    used[finite.reshape(-1)] = True
    assert len(finite) == 2 * int(used.sum()) - int((corners == n).any(axis=1).sum()) - 2
    for h in np.flatnonzero(~used):
        inside = np.all([orient2d_many(sites[finite[:, i]], sites[finite[:, (i + 1) % 3]], sites[h]) >= 0
                         for i in range(3)], axis=0)
        assert inside.any(), f"hidden site {h} outside the hull"
        f = finite[np.flatnonzero(inside)[0]]
        assert power_test_many(lifted[f[0]], lifted[f[1]], lifted[f[2]], lifted[h])[0] <= 0, \
            f"site {h} was left out but lies below the lifted triangulation"


def _weighted_sites(kind, n, seed):
    """Prepared (sites, weights) of a named kind."""
    rng = np.random.default_rng(seed)
    if kind == "radii":
        points = rng.random((n, 2))
        weights = (rng.random(n) * 0.3) ** 2
    elif kind == "many_hidden":            # 90% tiny circles among a few large ones
        points = rng.random((n, 2))
        weights = np.where(rng.random(n) < 0.9, (rng.random(n) * 0.01) ** 2, (rng.random(n) * 0.4) ** 2)
    elif kind == "lattice":               # integer weights on an integer lattice: exact degeneracies
        points = rng.integers(0, 5, (n, 2)).astype(float)
        weights = rng.integers(0, 17, n).astype(float)
    elif kind == "coplanar":              # lifts on few planes: merged facets, flat and through sites
        points = rng.integers(0, 5, (n, 2)).astype(float)
        weights = (points ** 2).sum(axis=1) - rng.integers(0, 2, n) * (points[:, 0] + 2 * points[:, 1])
    else:
        raise ValueError(kind)
    sites, site_weights, _ = prepare_weighted(points, weights)
    return sites, site_weights


# ---------------------------------------------------------------------------------------------
# The power diagram against the exact construction
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("kind", ["radii", "many_hidden", "lattice", "coplanar"])
def test_power_diagram_is_exact(kind, seed):
    sites, weights = _weighted_sites(kind, 24, seed)
    _assert_regular(sites, weights)
    d = impls.build("incremental", sites, weights=weights).validate()
    _assert_exact_power_diagram(d, sites, weights)


def _integer_weighted_sets(max_size=24):
    return st.integers(1, 5).flatmap(lambda box: st.lists(
        st.tuples(st.integers(0, box), st.integers(0, box), st.integers(-3, box * box)),
        min_size=0, max_size=max_size))


@settings(max_examples=150, deadline=None)
@given(_integer_weighted_sets())
def test_small_integer_inputs_are_exact(rows):
    data = np.array(rows, dtype=np.float64).reshape(-1, 3)
    sites, weights, _ = prepare_weighted(data[:, :2], data[:, 2])
    _assert_regular(sites, weights)
    impls.build("incremental", data[:, :2], weights=data[:, 2]).validate()     # the rows, duplicates too
    d = impls.build("incremental", sites, weights=weights).validate()
    _assert_exact_power_diagram(d, sites, weights)


def test_every_kind_of_flip_and_degeneracy_is_exercised():
    """The lattice kinds reach 3 -> 1 and 4 -> 2 flips, sites hidden at insertion, merged facets
    and sites the dual finds degenerate, all checked exactly (so those paths are tested)."""
    totals = {}
    for seed in range(40):
        for kind in ("lattice", "coplanar"):
            sites, weights = _weighted_sites(kind, 30, 100 + seed)
            stats = {}
            d = impls.build("incremental", sites, stats, weights=weights).validate()
            _assert_exact_power_diagram(d, sites, weights)
            for key in ("flips_3_1", "flips_4_2", "hidden_at_insertion", "merged_triangles", "hidden_degenerate"):
                totals[key] = totals.get(key, 0) + stats[key]
    assert all(v > 0 for v in totals.values()), totals


def test_a_site_lifted_inside_a_hull_edge_is_hidden_and_its_neighbours_meet():
    # lifts: u (0,0,0), x (2,0,4) and v (1,0,2) exactly between them; a and b high above
    # the line ux, so ux is an edge of the lower hull and v lies inside it: v has no cell,
    # and u and x share the ridge v would have split
    pts = np.array([[0, 0], [2, 0], [1, 0], [1, 1], [1, -1]], dtype=float)
    w = np.array([0, 0, -1, -1, -1], dtype=float)
    for order in ([0, 1, 2, 3, 4], [2, 0, 1, 3, 4], [2, 3, 4, 0, 1], [3, 4, 2, 1, 0]):
        d = impls.build("incremental", pts[order], weights=w[order]).validate()
        assert d.hidden.tolist() == [order.index(2)]
        assert (min(order.index(0), order.index(1)), max(order.index(0), order.index(1))) in \
            {(min(a, b), max(a, b)) for a, b in d.ridge_points.tolist()}
        _assert_exact_power_diagram(d, pts[order], w[order])


def test_a_flat_star_is_hidden_and_collinear_hull_sites_too():
    # every lift on the plane z = 0: only the four corners are vertices of the lower hull
    pts = np.array([[x, y] for x in range(3) for y in range(3)], dtype=float)
    w = (pts ** 2).sum(axis=1)
    stats = {}
    d = impls.build("incremental", pts, stats, weights=w).validate()
    corners = [0, 2, 6, 8]
    assert sorted(set(range(9)) - set(d.hidden.tolist())) == corners
    assert d.n_vertices == 1 and np.array_equal(d.vertices[0], [0.0, 0.0])
    _assert_exact_power_diagram(d, pts, w)


# ---------------------------------------------------------------------------------------------
# Equal weights: the ordinary diagram, bit for bit
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("weight", [0.0, 0.37, -2.0])
@pytest.mark.parametrize("dataset", ["uniform", "grid", "cocircular_many", "collinear", "clusters", "huge_offset",
                                     "parabola"])
def test_equal_weights_give_the_ordinary_diagram(dataset, weight):
    sites, _ = prepare(datasets_gen.generate(dataset, 400, seed=3))
    weights = np.full(sites.shape[0], weight)
    stats = {}
    power = build_weighted(sites, weights, stats).validate()
    plain = build(sites)
    assert power.hidden.size == 0 and stats["flips_3_1"] == stats["flips_4_2"] == stats["hidden_at_insertion"] == 0
    assert compare(power, plain).verdict == "exact"
    assert np.array_equal(np.unique(power.vertices, axis=0), np.unique(plain.vertices, axis=0))


def test_equal_weights_give_the_delaunay_triangulation():
    sites, _ = prepare(datasets_gen.generate("uniform", 2000, seed=5))
    tri, _, ntri = regular(sites, np.full(sites.shape[0], 1.5))
    dtri, _, dntri = delaunay(sites)

    def triangles(t, m):
        rows = t.reshape(-1, 3)
        return {tuple(np.roll(r, -int(np.argmin(r)))) for r in rows}

    assert ntri == dntri and triangles(tri, ntri) == triangles(dtri[:3 * dntri], dntri)


# ---------------------------------------------------------------------------------------------
# Duplicates, tiny inputs, magnitudes
# ---------------------------------------------------------------------------------------------

def test_duplicates_keep_the_largest_weight():
    rng = np.random.default_rng(8)
    base = rng.random((30, 2))
    points = np.vstack([base, base[:10], base[:5]])
    weights = np.concatenate([np.full(30, 0.001), np.full(10, 0.02), np.full(5, 0.0)])
    d = impls.build("incremental", points, weights=weights).validate()
    expected = np.concatenate([np.full(10, 0.02), np.full(20, 0.001)])
    ref = impls.build("incremental", base, weights=expected).validate()
    assert compare(d, ref).verdict == "exact"
    _assert_exact_power_diagram(ref, base, expected)
    assert d.point_region.shape == (45,)
    assert np.array_equal(d.point_region[30:40], d.point_region[:10])


@pytest.mark.parametrize("rows, hidden", [
    ([], []),
    ([[0, 0, 5]], []),
    ([[0, 0, 0], [1, 0, 100]], []),                         # two sites always share a radical axis
    ([[0, 0, 0], [1, 0, 0], [2, 0, 0]], []),
    ([[0, 0, 0], [1, 0, -1], [2, 0, 0]], [1]),               # collinear, the middle lifted too high
    ([[0, 0, 0], [1, 0, 1], [2, 0, 0]], []),
    ([[0, 0, 0], [4, 0, 0], [0, 4, 0]], []),                 # a triangle's three lifts are all extreme
    ([[0, 0, 0], [4, 0, 0], [0, 4, 0], [1, 1, -7]], [3]),   # inside the triangle, lifted above it (9 > 8)
    ([[0, 0, 0], [4, 0, 0], [0, 4, 0], [1, 1, -6]], [3]),   # lifted onto its plane: a cell without interior
    ([[0, 0, 0], [4, 0, 0], [0, 4, 0], [1, 1, -5]], []),
    ([[0, 0, 0], [4, 0, 0], [0, 4, 0], [1, 1, 30]], []),    # hull sites are never hidden
    ([[0, 0, 0], [2, 0, 0], [1, 0, 1], [1, 1, 0]], []),      # a site on a hull edge
    ([[0, 0, 0], [2, 0, 0], [1, 0, -1], [1, 1, 0]], [2]),   # the same, hidden
])
def test_tiny_inputs(rows, hidden):
    data = np.array(rows, dtype=np.float64).reshape(-1, 3)
    d = impls.build("incremental", data[:, :2], weights=data[:, 2]).validate()
    assert d.hidden.tolist() == hidden
    if data.shape[0]:
        _assert_exact_power_diagram(d, data[:, :2], data[:, 2])


def test_huge_offset_changes_nothing_but_the_vertices():
    sites, weights = _weighted_sites("many_hidden", 2000, 9)
    plain = impls.build("incremental", sites, weights=weights)
    shifted = impls.build("incremental", sites + 1e6, weights=weights)
    assert np.array_equal(plain.hidden, shifted.hidden)
    assert {tuple(r) for r in plain.ridge_points.tolist()} == {tuple(r) for r in shifted.ridge_points.tolist()}


# ---------------------------------------------------------------------------------------------
# Agreement with the other weighted constructions
# ---------------------------------------------------------------------------------------------

@pytest.mark.parametrize("kind, n, seed", [("radii", 3000, 1), ("many_hidden", 3000, 2), ("lattice", 400, 3),
                                           ("coplanar", 400, 4)])
def test_agrees_with_weighted_qhull(kind, n, seed):
    sites, weights = _weighted_sites(kind, n, seed)
    mine = impls.build("incremental", sites, weights=weights).validate()
    theirs = impls.build("qhull", sites, weights=weights).validate()
    assert compare(mine, theirs).equal


@pytest.mark.parametrize("kind, seed", [("radii", 1), ("many_hidden", 2)])
def test_agrees_with_cgal_regular_triangulation(kind, seed):
    if "cgal" not in impls.weighted():
        pytest.skip("the cgal adapter (peers extra) is not installed")
    sites, weights = _weighted_sites(kind, 3000, seed)
    mine = impls.build("incremental", sites, weights=weights).validate()
    theirs = impls.build("cgal", sites, weights=weights).validate()
    assert np.array_equal(mine.hidden, theirs.hidden)
    assert compare(mine, theirs).equal
