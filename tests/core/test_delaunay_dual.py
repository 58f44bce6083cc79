"""The Voronoi DCEL dual to a Delaunay triangulation: the one-pass numbering by triangle gives
the diagram the general path (twin pairs, merges) gives, and hands over at cocircular pairs."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import datasets_gen
import vorobench
from impls.incremental import _triangulate
from vorobench.core.circumcentre import CANCELLATION_THRESHOLD, circumcentre, circumcentre_fast
from vorobench.core.delaunay_dual import (CENTRE_RADIUS_ERROR, CENTRE_ROUNDING_ERROR, _centres_apart,
                                         _circumcentre_of, _general_dcel, _ghosts_last, _merged_vertices,
                                         voronoi_dcel, voronoi_vertices)
from vorobench.core.predicates import INCIRCLE_CALLS, incircle, orient2d
from vorobench.core.diagram import Diagram
from vorobench.core.prepare import prepare
from vorobench.core.read_only import read_only


def _both(sites):
    """(one-pass diagram, general diagram, their counters, merged) of the prepared sites."""
    points, ids, tri, opp, ntri, ok = _triangulate(sites, None)
    assert ok
    points = read_only(points)                  # as the implementations hand them over
    diagrams, counters, merged = [], [], []
    for dual in (voronoi_dcel, _general_dcel):
        c = np.zeros(4, dtype=np.int64)
        vertices, origin, twin, nxt, site, m = dual(points, ids, tri, opp, ntri, c)
        diagrams.append(Diagram(sites, vertices, origin, twin, nxt, site).validate())
        counters.append(c)
        merged.append(m)
    return diagrams, counters, merged


def _assert_same(fast, general):
    assert np.array_equal(fast.vertices, general.vertices), "the vertices (or their order) differ"
    assert fast.n_half_edges == general.n_half_edges
    comparison = vorobench.compare(fast, general)
    assert comparison.equal and comparison.verdict == "exact", str(comparison)


@settings(max_examples=40, deadline=None)
@given(st.integers(3, 80), st.integers(0, 2 ** 32 - 1))
def test_random_sites_give_the_general_diagram_with_fewer_tests(n, seed):
    sites, _ = prepare(np.random.default_rng(seed).random((n, 2)))
    if sites.shape[0] < 3:
        return
    try:
        (fast, general), (c_fast, c_general), (m_fast, m_general) = _both(sites)
    except AssertionError:
        if np.linalg.matrix_rank(sites[1:] - sites[0]) < 2:
            return                     # all collinear: no triangulation to dualise
        raise
    _assert_same(fast, general)
    assert m_fast == m_general == 0
    # the general path tests every pair of finite neighbours; the one pass only those whose
    # computed centres it cannot tell apart
    assert c_fast[INCIRCLE_CALLS] <= c_general[INCIRCLE_CALLS]


@pytest.mark.parametrize("dataset", ["grid", "cocircular_many", "lattice_rotated", "near_grid", "huge_offset",
                                     "clusters", "duplicates"])
def test_every_family_gives_the_general_diagram(dataset):
    sites, _ = prepare(datasets_gen.generate(dataset, 400, seed=2))
    (fast, general), _, (m_fast, m_general) = _both(sites)
    _assert_same(fast, general)
    assert m_fast == m_general


@pytest.mark.parametrize("dataset", ["grid", "cocircular_many", "uniform"])
def test_the_union_find_gives_the_vertices_of_the_one_pass_check(dataset):
    # the general path goes straight to the union-find; it must number and place the vertices
    # as voronoi_vertices does (one pass, then the union-find at the first cocircular pair)
    sites, _ = prepare(datasets_gen.generate(dataset, 300, seed=1))
    points, ids, tri, opp, ntri, _ = _triangulate(sites, None)
    points = read_only(points)
    direct, checked = (f(points, ids, tri, opp, ntri, np.zeros(4, dtype=np.int64))
                       for f in (_merged_vertices, voronoi_vertices))
    for a, b in zip(direct, checked):
        assert np.array_equal(a, b)


def _triangles_to_try(rng, count):
    """Random triples: spread out, with a common offset, and nearly collinear (the formula
    cancels and the careful paths take over)."""
    spread = rng.random((count, 3, 2))
    offset = rng.random((count, 3, 2)) + 1e9
    line = rng.random((count, 1, 1)) * np.array([1.0, 0.5]) + rng.random((count, 3, 1)) * np.array([1.0, 0.5])
    line[:, 1, 1] += 1e-13
    return np.concatenate([spread, offset, line])


def test_the_float_formula_has_the_same_bits_whichever_order_the_last_two_come_in():
    rng = np.random.default_rng(5)
    fast_ones = 0
    for (ax, ay), (bx, by), (cx, cy) in _triangles_to_try(rng, 300):
        one, other = circumcentre_fast(ax, ay, bx, by, cx, cy), circumcentre_fast(ax, ay, cx, cy, bx, by)
        assert one == other
        fast_ones += one[0]
    assert 0 < fast_ones < 900, "both the formula and the careful paths should be reached"


def test_the_centre_of_a_triangle_is_the_one_of_its_corners_in_increasing_site_id():
    # the dual finds the corner of least id and leaves the other two in their order: the bits
    # must be those of the full sort, in every rotation and reflection of the corners
    rng = np.random.default_rng(6)
    triples = _triangles_to_try(rng, 300)
    pts = triples.reshape(-1, 2)
    ids = rng.permutation(pts.shape[0]).astype(np.int64)
    for t in range(triples.shape[0]):
        corners = [3 * t, 3 * t + 1, 3 * t + 2]
        i, j, k = sorted(corners, key=lambda v: ids[v])
        expected = circumcentre(pts[i, 0], pts[i, 1], pts[j, 0], pts[j, 1], pts[k, 0], pts[k, 1])
        for a, b, c in ((0, 1, 2), (1, 2, 0), (2, 0, 1), (0, 2, 1), (2, 1, 0), (1, 0, 2)):
            got = _circumcentre_of(pts, ids, corners[a], corners[b], corners[c])
            assert got == expected, (t, (a, b, c))


def _triangles(tri, ntri):
    """The triangles as a sorted list of corner triples, each rotated to start at its least."""
    rows = np.asarray(tri[:3 * ntri]).reshape(-1, 3)
    turned = [tuple(np.roll(r, -int(np.argmin(r)))) for r in rows]
    return sorted(turned)


def _assert_neighbours_agree(tri, opp, ntri):
    """Every half-edge's opposite points back at it and runs between the same two corners,
    reversed."""
    for e in range(3 * ntri):
        f = opp[e]
        assert opp[f] == e, f"opp is not an involution at {e}"
        t, g = e // 3, f // 3
        assert tri[e] == tri[3 * g + (f - 3 * g + 1) % 3] and tri[3 * t + (e - 3 * t + 1) % 3] == tri[f], \
            f"half-edge {e} and its opposite {f} do not share their corners"


@pytest.mark.parametrize("dataset", ["uniform", "disk", "cocircular", "corners"])
def test_the_ghosts_move_last_and_every_neighbour_follows(dataset):
    # convex input puts every site on the hull: ghosts everywhere, many of them neighbours of
    # the finite triangles they trade places with
    sites, _ = prepare(datasets_gen.generate(dataset, 300, seed=4))
    points, ids, tri, opp, ntri, ok = _triangulate(sites, None)
    assert ok
    inf = points.shape[0]
    ghost = (np.asarray(tri[:3 * ntri]).reshape(-1, 3) == inf).any(axis=1)
    assert ghost[:ntri - ghost.sum()].any(), "no ghost to move: the test would test nothing"
    before = _triangles(tri, ntri)
    finite = _ghosts_last(tri, opp, ntri, inf)
    assert finite == ntri - ghost.sum()
    moved = (np.asarray(tri[:3 * ntri]).reshape(-1, 3) == inf).any(axis=1)
    assert not moved[:finite].any() and moved[finite:].all()
    assert _triangles(tri, ntri) == before
    _assert_neighbours_agree(tri, opp, ntri)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2 ** 32 - 1), st.integers(1, 6))
def test_empty_rectangles_among_random_sites_fold_as_the_general_path_does(seed, rectangles):
    """Random sites with a few small rectangles far apart among them (each one's corners exactly
    cocircular, its circle empty): the one pass meets its first cocircular pair somewhere in
    the middle, goes on from there, and folds each rectangle into one vertex of degree 4."""
    rng = np.random.default_rng(seed)
    sites = rng.random((200, 2)) * 100.0
    corners = []
    for cell in rng.choice(100, size=rectangles, replace=False):
        # random corners (two rectangles in one row would be an isosceles trapezoid, cocircular
        # too); an axis-parallel rectangle's corners are cocircular whatever their floats
        x, y = 10.0 * (cell % 10) + 3.0 + rng.random(), 10.0 * (cell // 10) + 3.0 + rng.random()
        corners += [(x, y), (x + 0.5, y), (x + 0.5, y + 0.25), (x, y + 0.25)]
        sites = sites[np.abs(sites - (x + 0.25, y + 0.125)).max(axis=1) > 1.0]   # its circle empty
    sites, _ = prepare(rng.permutation(np.vstack([sites, corners])))
    (fast, general), _, (m_fast, m_general) = _both(sites)
    _assert_same(fast, general)
    assert m_fast == m_general == rectangles
    assert (np.bincount(fast.origin[fast.origin >= 0]) == 4).sum() == rectangles


def test_a_grid_hands_over_and_merges_its_squares():
    """4 x 4 unit squares: every square's two triangles share one vertex, of degree 4."""
    sites, _ = prepare(np.array([(i, j) for i in range(5) for j in range(5)], dtype=float))
    (fast, _), _, (merged, _) = _both(sites)
    assert merged == 16
    assert fast.vertices.shape[0] == 16
    assert np.array_equal(np.unique(fast.vertices, axis=0), [(i + 0.5, j + 0.5) for i in range(4) for j in range(4)])
    assert vorobench.certify(fast).ok


# ---------------------------------------------------------------------------------------------
# The centre filter: it may call two centres apart only if the triangles are not cocircular
# ---------------------------------------------------------------------------------------------

# coordinates stay in the exact range of the predicates (0, or 2**-100 <= |x| < 2**100)
_FLOATS = st.one_of(st.just(0.0), st.floats(1e-9, 1e6), st.floats(-1e6, -1e-9))
_SCALES = st.sampled_from([2.0 ** k for k in (-60, -40, -1, 0, 7, 30, 60)])


def _four_on_a_circle(a, b, c, d):
    """Four distinct points on one circle, no three of them collinear."""
    return (all(orient2d(*p, *q, *r) != 0 for p, q, r in ((a, b, c), (a, b, d), (a, c, d), (b, c, d)))
            and incircle(*a, *b, *c, *d) == 0)


def _apart(a, b, c, d):
    """The filter on triangles (a, b, c) and (b, a, d), which share the edge a-b."""
    x1, y1 = circumcentre(*a, *b, *c)
    x2, y2 = circumcentre(*b, *a, *d)
    return _centres_apart(x1, y1, x2, y2, *a)


@settings(max_examples=300, deadline=None)
@given(_FLOATS, _FLOATS, _FLOATS, _FLOATS, st.sampled_from([0.0, 1e9, -3.3e5, 0.1]), _SCALES)
def test_a_rectangle_is_never_called_apart(x0, y0, w, h, offset, scale):
    """A rectangle's corners lie on one circle, whatever its floats; the centres computed from
    two of its triangles differ by roundings only."""
    xs = (np.float64(x0) + offset) * scale, (np.float64(x0) + w + offset) * scale
    ys = y0 * scale, (y0 + h) * scale
    # corners in turn a, b, c, d; triangles (a, b, c) and (c, d, a) share the diagonal a-c
    a, b, c, d = (xs[0], ys[0]), (xs[1], ys[0]), (xs[1], ys[1]), (xs[0], ys[1])
    if not _four_on_a_circle(a, b, c, d):
        return                         # a flat rectangle, or corners rounded off the circle
    assert not _apart(c, a, b, d) and not _apart(b, d, c, a)


@settings(max_examples=300, deadline=None)
@given(_FLOATS, _FLOATS, _FLOATS, _FLOATS, _FLOATS, _SCALES)
def test_a_symmetric_trapezoid_is_never_called_apart(cx, half1, half2, y1, y2, scale):
    """(cx -+ half1, y1) and (cx -+ half2, y2) are cocircular: the centre is on x = cx."""
    a, b = (cx - half1, y1), (cx + half1, y1)
    c, d = (cx + half2, y2), (cx - half2, y2)
    a, b, c, d = (tuple(np.multiply(p, scale)) for p in (a, b, c, d))
    if not _four_on_a_circle(a, b, c, d):
        return
    # triangles (a, b, c) and (a, c, d) share the diagonal a-c
    assert not _apart(c, a, b, d)


def test_the_filter_separates_the_neighbours_of_a_random_triangulation():
    """The filter is worth its place: on uniform sites it leaves the exact incircle test to
    none of the 2,900 or so pairs of neighbours."""
    sites, _ = prepare(datasets_gen.generate("uniform", 1000, seed=4))
    (fast, general), (c_fast, c_general), _ = _both(sites)
    assert c_general[INCIRCLE_CALLS] > 2500
    assert c_fast[INCIRCLE_CALLS] == 0


def test_the_bound_keeps_its_margin_over_the_cancellation_threshold():
    """The bound's derivation: the fast path's offsets are within (11 / T + 3) u of their size
    (T the cancellation threshold of ``circumcentre``), and the constant keeps a margin of 16;
    the coordinate's own rounding (u) a margin of 8. Lowering T must raise the constant."""
    u = 2.0 ** -53
    assert CENTRE_RADIUS_ERROR >= 16 * (11 / CANCELLATION_THRESHOLD + 3) * u
    assert CENTRE_ROUNDING_ERROR >= 8 * u


def _gaussian_circle(primes):
    """The integer points of x**2 + y**2 = N**2, N the product of the primes (each 1 mod 4),
    in angular order: products of Gaussian integers, one of (a + bi)**2, p, (a - bi)**2 per
    prime p = a**2 + b**2, and their four rotations."""
    points = [(1, 0)]
    for p in primes:
        a = next(a for a in range(1, p) if round((p - a * a) ** 0.5) ** 2 == p - a * a)
        b = round((p - a * a) ** 0.5)
        factors = ((a * a - b * b, 2 * a * b), (p, 0), (a * a - b * b, -2 * a * b))
        points = [(x * c - y * d, x * d + y * c) for x, y in points for c, d in factors]
    ring = {q for x, y in points for q in ((x, y), (-y, x), (-x, -y), (y, -x))}
    return sorted(ring, key=lambda q: np.arctan2(q[1], q[0]))


def test_nearly_flat_triangles_of_one_lattice_circle_are_never_called_apart():
    """Consecutive integer points of a circle of radius 1.6e11 make nearly collinear triangles,
    whose centres come from the double-double and exact paths of ``circumcentre``; offset
    and scaled by powers of two they stay exactly cocircular."""
    ring = _gaussian_circle([5, 13, 17, 29, 37, 41, 53, 61])
    rng = np.random.default_rng(7)
    flat = 0
    for start in rng.choice(len(ring), 150, replace=False):
        quad = [ring[(start + j) % len(ring)] for j in range(4)]
        for offset, scale in ((0, 2.0 ** -60), (2 ** 40, 1.0), (-(2 ** 45), 2.0 ** 30)):
            a, b, c, d = ((float(x + offset) * scale, float(y - offset) * scale) for x, y in quad)
            assert _four_on_a_circle(a, b, c, d)
            bx, by, cx, cy = b[0] - a[0], b[1] - a[1], c[0] - a[0], c[1] - a[1]
            if abs(bx * cy - by * cx) <= CANCELLATION_THRESHOLD * (abs(bx * cy) + abs(by * cx)):
                flat += 1
            # triangles (a, b, c) and (a, c, d) share the diagonal a-c, and (b, c, d), (b, d, a) share b-d
            assert not _apart(c, a, b, d) and not _apart(b, d, c, a)
    assert flat > 50, "the test no longer reaches the paths for nearly collinear triangles"
