"""compare(): equal after renumbering and exact normalisation; every kind of breakage is reported."""

import json

import numpy as np
import pytest

import datasets_gen
import impls
from vorobench import Diagram
from vorobench.core.builder import assemble
from vorobench.judge.comparison import compare
from vorobench.judge.testing import assert_diagrams_equal

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


# ------------------------------------------------------------------------------ hand-made diagrams
def square_one_vertex(sites=SQUARE) -> Diagram:
    """The four corners of a square: one degree-4 vertex at the centre, four rays coming in
    from infinity (edge (a, b) runs along perp(b - a), towards the centre)."""
    return assemble(sites, [[0.5, 0.5]], [[0, 1], [1, 2], [2, 3], [3, 0]], [[-1, 0]] * 4).validate()


def square_split_02(vertices=((0.5, 0.5), (0.5, 0.5)), sites=SQUARE) -> Diagram:
    """The same diagram as two degree-3 vertices {0, 1, 2} and {0, 2, 3} joined by a
    zero-length edge between the diagonal sites 0 and 2 (site 1 is right of 0->2: start)."""
    return assemble(sites, vertices, [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]],
                    [[-1, 0], [-1, 0], [-1, 1], [-1, 1], [0, 1]]).validate()


def square_split_13() -> Diagram:
    """The other diagonal: vertices {0, 1, 3} (id 0) and {1, 2, 3} (id 1), zero edge 1|3."""
    return assemble(SQUARE, [[0.5, 0.5], [0.5, 0.5]], [[0, 1], [1, 2], [2, 3], [3, 0], [1, 3]],
                    [[-1, 0], [-1, 1], [-1, 1], [-1, 0], [1, 0]]).validate()


def square_split_wrongly() -> Diagram:
    """A consistent DCEL that pairs the cocircular sites wrongly: the zero-length edge
    separates the *adjacent* cells 0 and 1, so cells 2 and 0 (and 1 and 3) share a ray."""
    return assemble(SQUARE, [[0.5, 0.5], [0.5, 0.5]], [[0, 1], [1, 2], [2, 0], [1, 3], [3, 0]],
                    [[0, 1], [0, -1], [0, -1], [-1, 1], [-1, 1]]).validate()


def qhull(dataset: str, n: int, seed: int = 0) -> Diagram:
    return impls.build("qhull", datasets_gen.generate(dataset, n, seed=seed)).validate()


def renumbered(d: Diagram, seed: int = 1) -> Diagram:
    """The same diagram with half-edges and vertices in a random order."""
    rng = np.random.default_rng(seed)
    H, V = d.n_half_edges, d.n_vertices
    new_of_old_h = rng.permutation(H)          # old half-edge h becomes new_of_old_h[h]
    old_of_new_h = np.argsort(new_of_old_h)
    new_of_old_v = rng.permutation(V)
    vertices = np.empty_like(d.vertices)
    vertices[new_of_old_v] = d.vertices
    origin = np.where(d.origin >= 0, new_of_old_v[np.maximum(d.origin, 0)] if V else -1, -1)
    return Diagram(d.sites, vertices, origin[old_of_new_h], new_of_old_h[d.twin[old_of_new_h]],
                   new_of_old_h[d.next[old_of_new_h]], d.site[old_of_new_h]).validate()


def with_arrays(d: Diagram, **changes) -> Diagram:
    fields = dict(sites=d.sites, vertices=d.vertices, origin=d.origin, twin=d.twin, next=d.next, site=d.site)
    fields = {k: np.array(v, copy=True) for k, v in fields.items()}
    fields.update(changes)
    return Diagram(**fields)


def edge_list(d: Diagram):
    e = d.edges()
    return (np.stack([d.site[e], d.site[d.twin[e]]], 1), np.stack([d.origin[e], d.origin[d.twin[e]]], 1))


def finite_edge(d: Diagram) -> int:
    """A half-edge with both ends finite, between two vertices of degree 3."""
    e = d.edges()
    fin = e[(d.origin[e] >= 0) & (d.origin[d.twin[e]] >= 0)]
    return int(fin[len(fin) // 2])


# ------------------------------------------------------------------------------ equal
@pytest.mark.parametrize("dataset,n", [("uniform", 200), ("grid", 100), ("cocircular", 40), ("collinear", 12),
                                       ("duplicates", 60), ("huge_offset", 100), ("uniform", 3), ("uniform", 2)])
def test_self_compare_after_renumbering_is_exact(dataset, n):
    d = qhull(dataset, n)
    c = compare(d, renumbered(d))
    assert c.equal and c.verdict == "exact", str(c)
    assert c.n_differences == 0 and c.max_vertex_error == 0.0


@pytest.mark.parametrize("n", [0, 1])
def test_tiny_diagrams_compare_equal(n):
    d = qhull("uniform", n)
    assert compare(d, d).verdict == "exact"


def test_degree_4_vertex_equals_two_vertices_and_a_zero_length_edge():
    one = square_one_vertex()
    for split in (square_split_02(), square_split_13()):
        c = compare(one, split)
        assert c.equal and c.verdict == "exact", str(c)
        assert c.zero_length_edges == {"a": 0, "b": 1}
    # Both splits are the same diagram too.
    assert compare(square_split_02(), square_split_13()).verdict == "exact"


def test_grid_of_3x3_degree_4_vertices_equal_a_split_version():
    """3x3 grid: qhull's four degree-4 vertices vs. the same diagram with each split in two."""
    pts = np.array([[x, y] for y in range(3) for x in range(3)], dtype=float)
    d = impls.build("qhull", pts)
    assert (np.bincount(d.origin[d.origin >= 0]) == 4).all()   # four degree-4 vertices
    # Split every vertex along the diagonal (lower-left, upper-right) of its grid square.
    sites, ends = edge_list(d)
    vertices = list(map(tuple, d.vertices))
    sites, ends = sites.tolist(), ends.tolist()
    for v, (x, y) in enumerate(d.vertices):
        ll = int(np.flatnonzero((pts == [x - 0.5, y - 0.5]).all(1))[0])
        ur = int(np.flatnonzero((pts == [x + 0.5, y + 0.5]).all(1))[0])
        w = len(vertices)
        vertices.append((x, y))
        # Edges touching the upper-left site move to the new vertex w = {ll, ul, ur}.
        ul = int(np.flatnonzero((pts == [x - 0.5, y + 0.5]).all(1))[0])
        for k, (a, b) in enumerate(sites):
            if ul in (a, b):
                ends[k] = [w if e == v else e for e in ends[k]]
        # Zero edge ll|ur: the right-hand site of ll->ur is the lower-right one, at vertex v: start.
        sites.append([ll, ur])
        ends.append([v, w])
    split = assemble(pts, vertices, sites, ends).validate()
    assert split.n_vertices == 8 and split.n_edges == d.n_edges + 4
    c = compare(d, split)
    assert c.verdict == "exact" and c.zero_length_edges["b"] == 4, str(c)


def test_sites_in_another_order_are_matched_by_sorting():
    d = qhull("uniform", 50)
    perm = np.random.default_rng(3).permutation(d.n_sites)   # new site k is old site perm[k]
    new_of_old = np.argsort(perm)
    e = with_arrays(d, sites=d.sites[perm], site=new_of_old[d.site])
    c = compare(d, e)
    assert c.equal and c.verdict == "exact" and c.sites_reordered, str(c)


def test_nearly_cocircular_sites_compare_within_tolerance():
    """A corner nudged by 1e-13: the exact diagram has a 1e-13 edge, a float library merges it."""
    sites = SQUARE.copy()
    sites[3, 1] += 1e-13
    a, b, c = sites[0], sites[2], sites[3]
    # Circumcentre of (0, 2, 3): the second vertex of the exact diagram.
    d = 2 * (a[0] * (b[1] - c[1]) + b[0] * (c[1] - a[1]) + c[0] * (a[1] - b[1]))
    ux = ((a @ a) * (b[1] - c[1]) + (b @ b) * (c[1] - a[1]) + (c @ c) * (a[1] - b[1])) / d
    uy = ((a @ a) * (c[0] - b[0]) + (b @ b) * (a[0] - c[0]) + (c @ c) * (b[0] - a[0])) / d
    exact = square_split_02(vertices=((0.5, 0.5), (ux, uy)), sites=sites)
    merged = square_one_vertex(sites)
    comp = compare(merged, exact, labels=("float", "exact"))
    assert comp.equal and comp.verdict == "within_tolerance", str(comp)
    assert comp.short_edge_counts == {"float": 0, "exact": 1}
    assert comp.short_edges[0]["sites"] == [0, 2]
    assert "within tolerance" in str(comp)
    with pytest.raises(AssertionError, match="not exactly equal"):
        assert_diagrams_equal(merged, exact, exact=True)
    assert_diagrams_equal(merged, exact)          # within tolerance is equal


# ------------------------------------------------------------------------------ differences
def test_wrong_pairing_of_cocircular_sites_differs():
    c = compare(square_one_vertex(), square_split_wrongly())
    assert not c.equal and c.verdict == "differs"
    assert c.counts["edges_only_in_a"] == 2 and c.counts["edges_only_in_b"] == 2
    only_a = {d.sites for d in c.differences if d.kind == "edges_only_in_a"}
    assert only_a == {(0, 1), (2, 3)}


def test_dropped_edge_with_its_vertices_merged_differs():
    d = qhull("uniform", 40)
    h = finite_edge(d)
    u, v = int(d.origin[h]), int(d.origin[d.twin[h]])
    sites, ends = edge_list(d)
    keep = ~(((sites == [d.site[h], d.site[d.twin[h]]]).all(1)) | ((sites == [d.site[d.twin[h]], d.site[h]]).all(1)))
    ends = np.where(ends == v, u, ends)[keep]
    broken = assemble(d.sites, d.vertices, sites[keep], ends, compact_vertices=True).validate()
    c = compare(d, broken)
    assert not c.equal
    assert c.counts["edges_only_in_a"] == 1
    assert c.counts["vertices_only_in_a"] == 2 and c.counts["vertices_only_in_b"] == 1
    pair = tuple(sorted((int(d.site[h]), int(d.site[d.twin[h]]))))
    assert any(x.kind == "edges_only_in_a" and tuple(sorted(x.sites)) == pair for x in c.differences)


def test_dropped_half_edge_pair_is_reported_not_raised():
    d = qhull("uniform", 30)
    h = finite_edge(d)
    keep = np.ones(d.n_half_edges, bool)
    keep[[h, d.twin[h]]] = False
    new_id = np.cumsum(keep) - 1
    broken = Diagram(d.sites, d.vertices, d.origin[keep], new_id[d.twin[keep]],
                     new_id[np.where(keep[d.next], d.next, d.next[d.next])[keep]], d.site[keep])
    c = compare(d, broken)
    assert not c.equal and c.counts["invalid_structure"] == 1 and c.counts["edges_only_in_a"] == 1
    assert "b" in c.structure_errors


def test_swapped_site_labels_differ():
    d = qhull("uniform", 40)
    i, j = 3, 17
    site = np.where(d.site == i, j, np.where(d.site == j, i, d.site))
    c = compare(d, with_arrays(d, site=site))
    assert not c.equal
    assert c.counts["edges_only_in_a"] > 0 and c.counts["edges_only_in_b"] > 0
    assert c.counts["vertices_only_in_a"] > 0


def test_moved_vertex_is_a_coordinate_mismatch():
    d = qhull("uniform", 40)
    vertices = d.vertices.copy()
    vertices[5] += [1e-4, 0.0]
    c = compare(d, with_arrays(d, vertices=vertices))
    assert not c.equal and c.verdict == "differs"
    assert c.counts["coordinate_mismatches"] == 1
    assert sum(c.counts.values()) == 1
    assert c.max_vertex_error > 1e-5 and c.max_vertex_error_ratio > 1
    # A move far below the tolerance is not.
    vertices[5] = d.vertices[5] + [1e-14, 0.0]
    assert compare(d, with_arrays(d, vertices=vertices)).verdict == "exact"


def test_flipped_twin_direction_differs():
    d = qhull("uniform", 40)
    h = finite_edge(d)
    origin = d.origin.copy()
    origin[h], origin[d.twin[h]] = d.origin[d.twin[h]], d.origin[h]
    c = compare(d, with_arrays(d, origin=origin))
    assert not c.equal
    assert c.counts["edges_with_different_ends"] == 1
    assert h in c.highlight_b


def test_different_point_sets_are_a_difference_not_a_crash():
    a = qhull("uniform", 20)
    pts = a.sites.copy()
    pts[4] += 0.01
    b = impls.build("qhull", pts)
    c = compare(a, b)
    assert not c.equal and c.counts["site_mismatch"] == 2
    assert "sites only in one diagram" in str(c)
    c = compare(a, qhull("uniform", 21))
    assert not c.equal and c.counts["site_mismatch"] >= 1


def test_report_and_dict():
    d = qhull("uniform", 40)
    vertices = d.vertices.copy()
    vertices[0] += 0.01
    c = compare(d, with_arrays(d, vertices=vertices), labels=("ref", "mine"))
    text = str(c)
    assert "DIFFERENT" in text and "ref" in text and "mine" in text and "coordinate" in text
    data = json.loads(json.dumps(c.to_dict()))
    assert data["verdict"] == "differs" and data["counts"]["coordinate_mismatches"] == 1
    assert data["differences"][0]["kind"] == "coordinate_mismatches"
    assert "EQUAL (exact)" in str(compare(d, d))


def test_assert_diagrams_equal_message_names_the_difference():
    d = qhull("uniform", 30)
    vertices = d.vertices.copy()
    vertices[2] += 0.05
    with pytest.raises(AssertionError, match="coordinate"):
        assert_diagrams_equal(d, with_arrays(d, vertices=vertices))
    assert assert_diagrams_equal(d, renumbered(d), exact=True).verdict == "exact"


def test_non_finite_vertex_is_reported():
    d = qhull("uniform", 50)
    vertices = d.vertices.copy()
    vertices[3] = np.nan
    c = compare(d, with_arrays(d, vertices=vertices))
    assert not c.equal and c.counts["coordinate_mismatches"] == 1 and c.counts["invalid_structure"] == 1
    assert "not finite" in str(c)


# ------------------------------------------------------------------------------ any magnitude
def scaled(d: Diagram, k: int) -> Diagram:
    """``d`` with every coordinate times 2**k (exact for these diagrams)."""
    return Diagram(np.ldexp(d.sites, k), np.ldexp(d.vertices, k), d.origin, d.twin, d.next, d.site)


GRID6 = np.array([[x, y] for x in range(6) for y in range(6)], dtype=float) / 8


@pytest.mark.parametrize("k", [-1057, -664, 997])
def test_split_and_merged_degree_4_vertices_are_equal_at_any_magnitude(k):
    """A grid: Fortune splits its degree-4 vertices, Qhull merges them. The exact contraction
    decides with incircle on the sites, which underflowed at subnormal and 1e-200 scale."""
    split, merged = impls.build("fortune", GRID6), impls.build("qhull", GRID6)
    assert compare(split, merged).verdict == "exact"
    c = compare(scaled(split, k), scaled(merged, k))
    assert c.verdict == "exact", str(c)
    assert c.zero_length_edges["a"] == 25


@pytest.mark.parametrize("k", [-664, 997])
def test_moved_vertex_is_reported_in_the_input_units_at_any_magnitude(k):
    d = scaled(qhull("uniform", 40), k)
    vertices = d.vertices.copy()
    vertices[5] += [np.ldexp(1e-4, k), 0.0]
    c = compare(d, with_arrays(d, vertices=vertices))
    assert c.verdict == "differs" and c.counts["coordinate_mismatches"] == 1, str(c)
    assert np.allclose(c.differences[0].points, [d.vertices[5], vertices[5]], rtol=1e-12, atol=0)
    vertices[5] = d.vertices[5] + [np.ldexp(1e-14, k), 0.0]
    assert compare(d, with_arrays(d, vertices=vertices)).verdict == "exact"


@pytest.mark.parametrize("scale", [1.0, 2.0 ** -40, 2.0 ** 30])
def test_compare_forgives_a_merge_within_rounding_and_not_beyond(scale):
    """The comparer's rule is the certifier's: nudged by 1e-13 of the lattice, four merged sites
    are one vertex within tolerance; by 1e-9 they are a different diagram (an edge length of
    ~1e-9 of the data, which the old 1e-8 equidistance tolerance contracted). Any scale."""
    from tests.judge.test_topology import _merged_grid

    near, exact_near = _merged_grid(1e-13, scale)
    far, exact_far = _merged_grid(1e-9, scale)
    c = compare(near, exact_near, labels=("float", "exact"))
    assert c.equal and c.verdict == "within_tolerance", str(c)
    assert c.short_edge_counts["exact"] > 0 and "near-degenerate" in str(c)
    c = compare(far, exact_far, labels=("float", "exact"))
    assert not c.equal and c.verdict == "differs", str(c)


def test_the_kernels_are_compiled_once_whatever_kind_of_arrays_the_diagrams_hold():
    # as for the certificate: the constructions' int32 read-only DCELs, writable int64 copies
    from vorobench.judge import comparison as cmp

    for sites in (datasets_gen.generate("uniform", 40, seed=5), datasets_gen.generate("grid", 36)):
        fortune, incremental = impls.build("fortune", sites), impls.build("incremental", sites)
        rebuilt = Diagram(np.array(fortune.sites), np.array(fortune.vertices),
                          *(np.array(x, dtype=np.int64) for x in (fortune.origin, fortune.twin, fortune.next,
                                                                  fortune.site)))
        for a, b in ((fortune, incremental), (incremental, rebuilt), (rebuilt, fortune), (fortune, fortune)):
            assert compare(a, b).verdict == "exact"
    for kernel in (cmp._matched_kernel, cmp._coincident_kernel, cmp._flat_vertex_kernel):
        assert len(kernel.signatures) <= 1, (kernel.py_func.__name__, kernel.signatures)
