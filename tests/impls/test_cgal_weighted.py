"""The ``cgal`` adapter's power diagrams (dual to CGAL's ``Regular_triangulation_2``) against an
exact brute-force oracle, CGAL's own hidden vertices, the ordinary ``cgal`` diagram (equal
weights) and the own weighted constructions.

The oracle works in Python integers (every double is an integer times a power of two): a
vertex of the power diagram is a point where three or more sites tie for the least power over
*all* sites; the sites whose cells touch it are the strict corners of the convex hull of the
tied sites (a tied site inside that hull or on one of its sides has a cell without area, so it
is hidden); corners adjacent on that hull share an edge, bounded when two vertices have it,
a ray when one does.
"""

from __future__ import annotations

from fractions import Fraction
from itertools import combinations

import numpy as np
import pytest

import datasets_gen
import impls
from vorobench import compare
from vorobench.core.builder import collinear_diagram
from vorobench.core.circumcentre import power_centre
from vorobench.core.prepare import prepare, prepare_weighted

pytest.importorskip("CGAL", reason="adapter 'cgal' needs the optional library 'cgal' (pip install vorobench[peers])")

from CGAL.CGAL_Kernel import Point_2, Weighted_point_2  # noqa: E402
from CGAL.CGAL_Triangulation_2 import Regular_triangulation_2  # noqa: E402

from impls.external import cgal  # noqa: E402  (imports CGAL)

SEED = 20250316


def _weighted(points, weights):
    sites, w, _ = prepare_weighted(np.asarray(points, dtype=np.float64).reshape(-1, 2),
                                   np.asarray(weights, dtype=np.float64).reshape(-1))
    return sites, w


def _radii_sets(seed: int, n: int, spread: float = 1.4):
    """Random points of the unit square with the weights of disks of random radii up to
    ``spread`` mean spacings: many hidden sites."""
    rng = np.random.default_rng(seed)
    points = rng.random((n, 2))
    return _weighted(points, (rng.random(n) * spread / np.sqrt(n)) ** 2)


# ---------------------------------------------------------------- the oracle


def _as_integers(sites, weights):
    """Sites and weights times one power of two 2**k (weights times 2**(2k)), as Python ints."""
    def exponent(values) -> int:          # denominators are powers of two
        return max([Fraction(float(v)).denominator.bit_length() - 1 for v in values] + [0])

    k = max(exponent(sites.reshape(-1)), (exponent(weights) + 1) // 2)
    scale = 2 ** k
    xs = [int(Fraction(float(v)) * scale) for v in sites[:, 0]]
    ys = [int(Fraction(float(v)) * scale) for v in sites[:, 1]]
    ws = [int(Fraction(float(v)) * scale * scale) for v in weights]
    assert all(Fraction(float(v)) * scale * scale == w for v, w in zip(weights, ws))
    return xs, ys, ws, scale


def _strict_hull(points: list[tuple[int, int, int]]) -> list[int]:
    """Ids (third entries) of the strict corners of the convex hull of (x, y, id) points,
    counter-clockwise (Andrew's monotone chain, collinear points dropped)."""
    pts = sorted(points)

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list = []
    upper: list = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return [p[2] for p in lower[:-1] + upper[:-1]]


def power_oracle(sites, weights):
    """The exact power diagram by brute force: (vertices {corner site set: (x, y) Fractions},
    edges {(a, b) sorted: number of vertices on it (2 bounded, 1 ray)}, hidden site set,
    whether some tied site was not a corner (a degenerate input))."""
    xs, ys, ws, scale = _as_integers(sites, weights)
    n = len(xs)
    X = np.array(xs, dtype=object)
    Y = np.array(ys, dtype=object)
    W = np.array(ws, dtype=object)
    vertices: dict[frozenset, tuple[Fraction, Fraction]] = {}
    seen: set = set()
    degenerate = False
    for i, j, k in combinations(range(n), 3):
        bx, by, cx, cy = xs[j] - xs[i], ys[j] - ys[i], xs[k] - xs[i], ys[k] - ys[i]
        det = bx * cy - by * cx
        if det == 0:
            continue
        b2 = bx * bx + by * by - (ws[j] - ws[i])
        c2 = cx * cx + cy * cy - (ws[k] - ws[i])
        # power centre = a + (num_x, num_y) / (2 det); powers times D^2, D = 2 det, in integers
        D = 2 * det
        nx = xs[i] * D + (cy * b2 - by * c2)
        ny = ys[i] * D + (bx * c2 - cx * b2)
        if (nx, ny, D) in seen:
            continue
        p = (X * D - nx) ** 2 + (Y * D - ny) ** 2 - W * D * D
        low = min(p)
        if p[i] != low:
            continue
        seen.add((nx, ny, D))
        tied = [m for m in range(n) if p[m] == low]
        corners = _strict_hull([(xs[m], ys[m], m) for m in tied])
        degenerate |= len(corners) < len(tied)
        vertices[frozenset(corners)] = (Fraction(nx, D * scale), Fraction(ny, D * scale))
    edges: dict[tuple[int, int], int] = {}
    for key in vertices:
        ring = _strict_hull([(xs[m], ys[m], m) for m in key])
        for a, b in zip(ring, ring[1:] + ring[:1]):
            pair = (min(a, b), max(a, b))
            edges[pair] = edges.get(pair, 0) + 1
    visible = set().union(*vertices) if vertices else set()
    return vertices, edges, set(range(n)) - visible, degenerate


def diagram_structure(d):
    """The same three things read from a diagram: {site set of each vertex: its coordinates},
    {(a, b): 2 for an edge between two vertices, 1 for a ray}, set of hidden sites."""
    touching: dict[int, set] = {}
    for h in range(d.n_half_edges):
        if d.origin[h] >= 0:
            touching.setdefault(int(d.origin[h]), set()).add(int(d.site[h]))
    vertices = {frozenset(s): tuple(d.vertices[v]) for v, s in touching.items()}
    assert len(vertices) == d.n_vertices, "two vertices with the same sites"
    edges = {}
    for h in range(d.n_half_edges):
        t = int(d.twin[h])
        if h < t:
            pair = (min(int(d.site[h]), int(d.site[t])), max(int(d.site[h]), int(d.site[t])))
            assert pair not in edges, f"two edges between sites {pair}"
            edges[pair] = int(d.origin[h] >= 0) + int(d.origin[t] >= 0)
    return vertices, edges, set(d.hidden.tolist())


def assert_matches_oracle(d, sites, weights, what=""):
    """Same vertices (site sets), edges (bounded or rays), hidden sites as the oracle; each vertex
    is the power centre of its three smallest site ids, within a few ulps of the exact point."""
    want_v, want_e, want_hidden, degenerate = power_oracle(sites, weights)
    got_v, got_e, got_hidden = diagram_structure(d)
    assert got_hidden == want_hidden, (what, sorted(got_hidden ^ want_hidden))
    assert set(got_v) == set(want_v), (what, [sorted(s) for s in set(got_v) ^ set(want_v)][:5])
    assert got_e == want_e, (what, sorted(set(got_e.items()) ^ set(want_e.items()))[:5])
    span = float(np.abs(sites).max())
    for key, (x, y) in want_v.items():
        a, b, c = sorted(key)[:3]
        rule = power_centre(sites[a, 0], sites[a, 1], weights[a], sites[b, 0], sites[b, 1], weights[b],
                            sites[c, 0], sites[c, 1], weights[c])
        assert got_v[key] == rule, (what, sorted(key))
        assert abs(got_v[key][0] - float(x)) <= 1e-12 * max(span, abs(float(x)))
        assert abs(got_v[key][1] - float(y)) <= 1e-12 * max(span, abs(float(y)))
    return degenerate


def cgal_hidden(sites, weights) -> set[int]:
    """The sites CGAL's regular triangulation reports hidden, through its public interface."""
    rt = Regular_triangulation_2()
    rt.insert([Weighted_point_2(Point_2(x, y), w) for (x, y), w in zip(sites.tolist(), weights.tolist())])
    index = {(x, y): i for i, (x, y) in enumerate(sites.tolist())}
    return {index[(v.point().x(), v.point().y())] for v in rt.hidden_vertices()}


# ---------------------------------------------------------------- the convention


def test_registered_as_weighted():
    assert "cgal" in impls.weighted() and impls.get("cgal").weighted


def test_cgal_weights_are_squared_radii_subtracted_from_the_squared_distance():
    # three sites; CGAL's weighted circumcentre must be where |x - p|^2 - w is equal for all three
    pts = [(0.0, 0.0, 1.0), (4.0, 0.0, 0.0), (1.0, 3.0, 2.0)]
    rt = Regular_triangulation_2()
    rt.insert([Weighted_point_2(Point_2(x, y), w) for x, y, w in pts])
    (face,) = list(rt.finite_faces())
    c = rt.weighted_circumcenter(face)
    x, y = c.x(), c.y()
    powers = [(x - px) ** 2 + (y - py) ** 2 - w for px, py, w in pts]
    assert max(powers) - min(powers) < 1e-12
    # the other sign convention would tie |x - p|^2 + w instead: not here
    plus = [(x - px) ** 2 + (y - py) ** 2 + w for px, py, w in pts]
    assert max(plus) - min(plus) > 1.0
    # the adapter's vertex is that point
    sites, w = _weighted([p[:2] for p in pts], [p[2] for p in pts])
    d = impls.get("cgal").run(sites, weights=w).validate()
    assert d.n_vertices == 1
    assert np.allclose(d.vertices[0], (x, y), rtol=0, atol=1e-14)
    # (1, 1) inside the triangle (0, 0), (4, 0), (0, 4) of weight 0 (power 8 at its centre
    # (2, 2)) has power 2 - w there: hidden exactly when w < -6
    for w11, hidden in ((-7.0, 1), (-5.0, 0)):
        rt = Regular_triangulation_2()
        rt.insert([Weighted_point_2(Point_2(x, y), w) for x, y, w in [(0, 0, 0), (4, 0, 0), (0, 4, 0), (1, 1, w11)]])
        assert rt.number_of_hidden_vertices() == hidden


# ---------------------------------------------------------------- the oracle on random sets


@pytest.mark.parametrize("seed", range(8))
def test_random_weighted_sets_match_the_power_oracle(seed):
    sites, w = _radii_sets(SEED + seed, 30)
    stats: dict = {}
    d = impls.get("cgal").run(sites, stats, weights=w).validate()
    assert not assert_matches_oracle(d, sites, w, f"seed {seed}")
    assert stats["cgal_hidden"] == d.hidden.size and stats["degenerate_sites"] == 0


def test_the_oracle_sets_hide_many_sites():
    hidden = []
    for seed in range(8):
        sites, w = _radii_sets(SEED + seed, 30)
        hidden.append(len(power_oracle(sites, w)[2]))
    assert sum(hidden) >= 8 * 30 // 10 and min(hidden) >= 1, hidden


def test_most_sites_hidden_match_the_oracle():
    rng = np.random.default_rng(SEED)
    points = rng.random((30, 2))
    w = np.zeros(30)
    w[:4] = 2.0                      # four huge disks hide every site inside the hull
    sites, w = _weighted(points, w)
    d = impls.get("cgal").run(sites, weights=w).validate()
    assert d.hidden.size >= 15
    assert_matches_oracle(d, sites, w)


def test_unit_coordinates_with_53_bit_weights_match_the_oracle():
    rng = np.random.default_rng(SEED + 99)
    sites, w = _weighted(rng.standard_normal((25, 2)) * 1e3, rng.standard_normal(25) * 1e5)
    assert_matches_oracle(impls.get("cgal").run(sites, weights=w).validate(), sites, w)


# ---------------------------------------------------------------- degenerate inputs


def _lattice(k: int, weight_of) -> tuple[np.ndarray, np.ndarray]:
    pts = [(x, y) for x in range(k) for y in range(k)]
    return _weighted(pts, [weight_of(x, y) for x, y in pts])


def test_site_lifted_inside_a_face_is_hidden_and_the_face_is_one_vertex():
    # square of weight 0 around a centre of weight -2: the centre's power at (1, 1) ties with
    # the corners' (2 = 0 + 2): CGAL keeps it as a vertex, its cell is the single point (1, 1)
    sites, w = _weighted([[0, 0], [2, 0], [2, 2], [0, 2], [1, 1]], [0, 0, 0, 0, -2])
    stats: dict = {}
    d = impls.get("cgal").run(sites, stats, weights=w).validate()
    assert cgal_hidden(sites, w) == set()
    centre = int(np.flatnonzero((sites == [1.0, 1.0]).all(axis=1))[0])
    assert d.hidden.tolist() == [centre]
    assert d.n_vertices == 1 and np.array_equal(d.vertices, [[1.0, 1.0]]) and d.n_edges == 4
    assert stats["degenerate_sites"] == 1 and stats["cgal_hidden"] == 0 and stats["merged_triangles"] == 3
    assert assert_matches_oracle(d, sites, w)


def test_sites_lifted_on_a_crease_or_a_hull_side_are_hidden():
    # lattice 3 x 3, weights 1 on even x + y and 0 on odd: every odd site's lifted point lies
    # on the segment of its two even neighbours' across a crease or along the hull
    sites, w = _lattice(3, lambda x, y: 1.0 if (x + y) % 2 == 0 else 0.0)
    stats: dict = {}
    d = impls.get("cgal").run(sites, stats, weights=w).validate()
    assert assert_matches_oracle(d, sites, w)
    assert stats["degenerate_sites"] >= 1


@pytest.mark.parametrize("k,modulus", [(4, 2), (5, 3), (6, 2), (5, 4)])
def test_integer_lattice_weights_match_the_oracle(k, modulus):
    sites, w = _lattice(k, lambda x, y: float((x * x + 3 * y + x * y) % modulus))
    d = impls.get("cgal").run(sites, weights=w).validate()
    assert_matches_oracle(d, sites, w, f"{k} {modulus}")


def test_degenerate_lattices_make_the_oracle_see_ties():
    seen = 0
    for k, modulus in [(4, 2), (5, 3), (6, 2), (5, 4)]:
        sites, w = _lattice(k, lambda x, y: float((x * x + 3 * y + x * y) % modulus))
        seen += power_oracle(sites, w)[3]
    sites, w = _lattice(3, lambda x, y: 1.0 if (x + y) % 2 == 0 else 0.0)
    assert seen >= 1 and power_oracle(sites, w)[3]


def test_weighted_lattice_family_matches_the_oracle():
    points = datasets_gen.generate("grid", 36, seed=1)
    w = datasets_gen.weights("integer", points, seed=1)
    sites, w = _weighted(points, w)
    assert_matches_oracle(impls.get("cgal").run(sites, weights=w).validate(), sites, w)


def test_insertion_order_does_not_change_the_diagram():
    sites, w = _lattice(5, lambda x, y: float((x + 2 * y) % 3))
    base = impls.get("cgal").run(sites, weights=w)
    for seed in range(3):
        perm = np.random.default_rng(seed).permutation(sites.shape[0])
        other = impls.get("cgal").run(sites[perm], weights=w[perm])
        cmp = compare(base, other.__class__(sites, other.vertices, other.origin, other.twin, other.next,
                                            perm[other.site], weights=w))
        assert cmp.equal and cmp.verdict == "exact", str(cmp)


# ---------------------------------------------------------------- hidden sites against CGAL


@pytest.mark.parametrize("seed", range(4))
def test_hidden_sites_are_the_ones_cgal_hides(seed):
    sites, w = _radii_sets(SEED + 50 + seed, 2000, spread=1.6)
    d = impls.get("cgal").run(sites, weights=w).validate()
    hidden = cgal_hidden(sites, w)
    assert len(hidden) > 100
    assert set(d.hidden.tolist()) == hidden


# ---------------------------------------------------------------- equal weights


@pytest.mark.parametrize("dataset", ["uniform", "grid", "cocircular", "cocircular_many", "collinear", "near_grid",
                                     "lattice_rotated", "clusters", "parabola"])
@pytest.mark.parametrize("weight", [0.0, 0.25, -3.0])
def test_equal_weights_give_the_ordinary_cgal_diagram(dataset, weight):
    sites = prepare(datasets_gen.generate(dataset, 200, seed=4))[0]
    ordinary = impls.get("cgal").run(sites)
    power = impls.get("cgal").run(sites, weights=np.full(sites.shape[0], weight))
    assert power.hidden.size == 0
    cmp = compare(power, ordinary)
    assert cmp.equal and cmp.verdict == "exact", str(cmp)
    key = np.lexsort(ordinary.vertices.T[::-1])
    assert np.array_equal(power.vertices[np.lexsort(power.vertices.T[::-1])], ordinary.vertices[key])


# ---------------------------------------------------------------- fewer than two dimensions


def test_collinear_sites_follow_the_collinear_power_diagram():
    # the middle site's lifted point on its neighbours' segment (w = -1): hidden; a far
    # light site hidden by a heavy neighbour
    sites, w = _weighted([[0, 0], [1, 0], [2, 0], [5, 0], [5.5, 0], [7, 0]], [0, -1, 0, 4, -10, 0])
    stats: dict = {}
    d = impls.get("cgal").run(sites, stats, weights=w).validate()
    want = collinear_diagram(sites, w)
    assert compare(d, want).equal and set(d.hidden.tolist()) == {1, 4}
    assert stats["collinear"] == 1 and stats["cgal_hidden"] == 1 and stats["degenerate_sites"] == 1


def test_a_site_off_the_line_is_a_hull_corner_and_never_hidden():
    # however light, (2, 0.5) has the least power far above the line: CGAL's dimension is 2
    sites, w = _weighted([[0, 0], [2, 0], [4, 0], [2, 0.5]], [0, 0, 0, -50])
    stats: dict = {}
    d = impls.get("cgal").run(sites, stats, weights=w).validate()
    assert d.hidden.size == 0 and stats["collinear"] == 0
    assert_matches_oracle(d, sites, w)


def test_two_sites_both_keep_a_cell_whatever_their_weights():
    sites, w = _weighted([[0, 0], [1, 0]], [10, 0])
    d = impls.get("cgal").run(sites, weights=w).validate()
    assert d.hidden.size == 0 and (d.n_vertices, d.n_edges) == (0, 1)


@pytest.mark.parametrize("n", [0, 1, 2, 3])
def test_tiny_weighted_inputs(n):
    rng = np.random.default_rng(n)
    sites, w = _weighted(rng.random((n, 2)), rng.random(n) * 0.01)
    d = impls.get("cgal").run(sites, weights=w).validate()
    if n >= 3:
        assert_matches_oracle(d, sites, w)
    assert d.n_visible == n


# ---------------------------------------------------------------- agreement with the own constructions


def _own_weighted():
    names = [name for name in ("incremental", "halfplane", "qhull") if name in impls.available()]
    return names


@pytest.mark.parametrize("name", _own_weighted())
@pytest.mark.parametrize("seed", range(3))
def test_agrees_with_own_weighted_constructions_on_random_sets(name, seed):
    impl = impls.get(name)
    if not impl.weighted:
        pytest.skip(f"{name} does not take weights yet")
    sites, w = _radii_sets(SEED + 200 + seed, 300)
    ours = impl.run(sites, weights=w)
    theirs = impls.get("cgal").run(sites, weights=w)
    assert theirs.hidden.size > 10
    cmp = compare(theirs, ours)
    assert cmp.equal, str(cmp)
    assert np.array_equal(theirs.hidden, ours.hidden)


@pytest.mark.parametrize("name", _own_weighted())
@pytest.mark.parametrize("k,modulus", [(6, 2), (7, 3), (8, 5)])
def test_agrees_with_own_weighted_constructions_on_lattices(name, k, modulus):
    impl = impls.get(name)
    if not impl.weighted:
        pytest.skip(f"{name} does not take weights yet")
    sites, w = _lattice(k, lambda x, y: float((x * x + 3 * y + x * y) % modulus))
    cmp = compare(impls.get("cgal").run(sites, weights=w), impl.run(sites, weights=w))
    assert cmp.equal, str(cmp)


@pytest.mark.parametrize("name", _own_weighted())
@pytest.mark.parametrize("family", ["radii", "hidden", "integer"])
def test_agrees_with_own_weighted_constructions_on_weight_families(name, family):
    impl = impls.get(name)
    if not impl.weighted:
        pytest.skip(f"{name} does not take weights yet")
    for dataset in ("uniform", "grid", "clusters"):
        points = datasets_gen.generate(dataset, 400, seed=2)
        w = datasets_gen.weights(family, points, seed=2)
        cmp = compare(impls.build("cgal", points, weights=w), impls.build(name, points, weights=w))
        assert cmp.equal, (dataset, str(cmp))


# ---------------------------------------------------------------- timings, counters, plumbing


def test_weighted_build_time_is_split_into_library_and_conversion_timings():
    stats: dict = {}
    timings: dict = {}
    sites, w = _radii_sets(SEED, 300)
    impls.get("cgal").run(sites, stats, timings=timings, weights=w)
    assert timings["library"] > 0 and timings["convert"] > 0
    assert all(isinstance(v, int) and not isinstance(v, bool) for v in stats.values()), stats
    # Euler on the sphere over the visible sites: 2 V - 4 triangles, V counting the infinite vertex
    visible = sites.shape[0] - stats["cgal_hidden"]
    assert stats["cgal_faces"] + stats["cgal_infinite_faces"] == 2 * (visible + 1) - 4


def test_magnitudes_the_run_scales_give_the_same_diagram():
    unit, w = _radii_sets(SEED + 7, 60)
    base = impls.get("cgal").run(unit, weights=w)
    for k in (-500, -60, 60, 450):
        d = impls.get("cgal").run(np.ldexp(unit, k), weights=np.ldexp(w, 2 * k))
        assert np.array_equal(d.hidden, base.hidden)
        assert np.array_equal(np.ldexp(base.vertices, k), d.vertices), k


def test_the_public_weighted_point_constructor_gives_the_same_diagram(monkeypatch):
    sites, w = _lattice(6, lambda x, y: float((x * y) % 3))
    fast = impls.get("cgal").run(sites, weights=w)
    monkeypatch.setattr(cgal, "_MAKE_WEIGHTED_POINT", lambda x, y, ww: Weighted_point_2(Point_2(x, y), ww))
    slow = impls.get("cgal").run(sites, weights=w)
    cmp = compare(fast, slow)
    assert cmp.equal and cmp.verdict == "exact"


def test_read_regular_triangulation_reads_weights_hidden_points_and_dimension_one():
    rt = Regular_triangulation_2()
    rt.insert([Weighted_point_2(Point_2(x, y), w) for x, y, w in [(0, 0, 0), (4, 0, 0), (0, 4, 0), (1, 1, -100.5)]])
    coords, faces, neighbours, dim = cgal.read_regular_triangulation(cgal._file_text(rt, 4))
    assert dim == 2 and coords.shape == (4, 3) and faces.shape[1] == 3
    hidden_row = int(np.flatnonzero(coords[:, 2] == -100.5)[0])
    assert hidden_row + 1 not in set(faces.reshape(-1).tolist())
    line = Regular_triangulation_2()
    line.insert([Weighted_point_2(Point_2(x, 0.0), 0.0) for x in (0.0, 1.0, 3.0)])
    coords, faces, neighbours, dim = cgal.read_regular_triangulation(cgal._file_text(line, 3))
    assert dim == 1 and coords.shape == (3, 3) and faces.shape == neighbours.shape == (4, 2)
    with pytest.raises(ValueError):
        cgal.read_regular_triangulation(b"2 0 0\n1 1 0\n\n")
    with pytest.raises(ValueError):
        cgal.read_triangulation(cgal._file_text(rt, 4))       # three numbers a point: not ordinary


def test_weighted_input_is_left_unchanged():
    sites, w = _radii_sets(SEED + 3, 100)
    s0, w0 = sites.copy(), w.copy()
    cgal.build_weighted(sites, w)
    assert np.array_equal(sites, s0) and np.array_equal(w, w0)
