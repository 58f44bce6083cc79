"""certify(): correct diagrams pass every check; each kind of breakage fails the check that sees it."""

import json

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import datasets_gen
import impls
from vorobench import Diagram
from vorobench.core.builder import assemble, collinear_diagram
from vorobench.core.hull import convex_hull_boundary
from vorobench.judge.certificate import CHECKS, certify

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def qhull(dataset: str, n: int, seed: int = 0) -> Diagram:
    return impls.build("qhull", datasets_gen.generate(dataset, n, seed=seed)).validate()


def with_arrays(d: Diagram, **changes) -> Diagram:
    fields = dict(sites=d.sites, vertices=d.vertices, origin=d.origin, twin=d.twin, next=d.next, site=d.site)
    fields = {k: np.array(v, copy=True) for k, v in fields.items()}
    fields.update(changes)
    return Diagram(**fields)


def failed(cert) -> set:
    return {c.name for c in cert.checks if not c.ok}


def finite_edge(d: Diagram) -> int:
    e = d.edges()
    fin = e[(d.origin[e] >= 0) & (d.origin[d.twin[e]] >= 0)]
    return int(fin[len(fin) // 2])


# ------------------------------------------------------------------------------ correct diagrams
@pytest.mark.parametrize("dataset,n", [("uniform", 300), ("grid", 100), ("cocircular", 30), ("collinear", 10),
                                       ("clusters", 200), ("huge_offset", 200), ("tiny_spacing", 200),
                                       ("parabola", 50), ("lattice_rotated", 64)])
def test_qhull_diagrams_certify(dataset, n):
    cert = certify(qhull(dataset, n))
    assert cert.ok, str(cert)
    assert [c.name for c in cert.checks] == list(CHECKS)


@pytest.mark.parametrize("n", [0, 1, 2, 3])
def test_tiny_diagrams_certify(n):
    cert = certify(qhull("uniform", n))
    assert cert.ok, str(cert)


def test_degree_4_vertex_and_its_split_both_certify():
    one = assemble(SQUARE, [[0.5, 0.5]], [[0, 1], [1, 2], [2, 3], [3, 0]], [[-1, 0]] * 4)
    split = assemble(SQUARE, [[0.5, 0.5], [0.5, 0.5]], [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]],
                     [[-1, 0], [-1, 0], [-1, 1], [-1, 1], [0, 1]])
    for d in (one, split):
        cert = certify(d)
        assert cert.ok, str(cert)
    assert "V - E + n = 2 - 5 + 4 = 1" in certify(split).check("euler").detail


def test_collinear_euler_and_hull():
    d = collinear_diagram(np.array([[0.0, 0.0], [1.0, 2.0], [2.0, 4.0], [3.0, 6.0]]))
    cert = certify(d)
    assert cert.ok and "0 - 3 + 4 = 1" in cert.check("euler").detail


def test_hull_keeps_collinear_boundary_points():
    # A 5x5 integer grid: 16 boundary points, 4 of them corners (what ConvexHull reports).
    pts = np.array([[x, y] for x in range(5) for y in range(5)], dtype=float)
    boundary = convex_hull_boundary(pts)
    on_edge = np.flatnonzero((pts == 0).any(1) | (pts == 4).any(1))
    assert np.array_equal(boundary, on_edge) and boundary.size == 16
    assert set(ConvexHull(pts).vertices) <= set(boundary.tolist())
    # Exactness: a point a hair inside an edge is not on the boundary.
    pts = np.array([[0.0, 0.0], [2.0, 0.0], [1.0, np.nextafter(0.0, 1.0)], [1.0, 1.0]])
    assert convex_hull_boundary(pts).tolist() == [0, 1, 3]


# ------------------------------------------------------------------------------ breakages
def test_moved_vertex_fails_the_vertex_check():
    d = qhull("uniform", 60)
    vertices = d.vertices.copy()
    vertices[7] += [1e-3, -1e-3]
    cert = certify(with_arrays(d, vertices=vertices))
    assert not cert.ok and "vertices" in failed(cert)
    assert cert.check("vertices").offending == [7]
    assert "edges" in failed(cert)              # its edges leave the bisectors too


def test_vertex_with_a_closer_site_fails_the_empty_circle():
    """Three sites and a fourth inside their circle: the vertex of the first three is wrong."""
    sites = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [0.9, 0.9]])
    d = assemble(sites[:3], [[1.0, 1.0]], [[0, 1], [1, 2], [2, 0]], [[-1, 0], [-1, 0], [-1, 0]])
    bad = Diagram(sites, d.vertices, d.origin, d.twin, d.next, d.site)  # site 3 has no cell
    cert = certify(bad)
    assert "structure" in failed(cert) and "vertices" in failed(cert)
    assert "empty circle" in cert.check("vertices").detail


def test_swapped_sites_fail_the_probes():
    """A cell that claims another site's territory: sites 3 and 17 trade cells."""
    d = qhull("uniform", 60)
    i, j = 3, 17
    site = np.where(d.site == i, j, np.where(d.site == j, i, d.site))
    cert = certify(with_arrays(d, site=site))
    assert not cert.ok and "probes" in failed(cert)
    assert "sites lie outside their own cell" in cert.check("probes").detail
    assert cert.check("probes").offending


def test_swapping_a_hull_site_and_an_interior_site_fails_the_hull_check():
    d = qhull("uniform", 60)
    hull = convex_hull_boundary(d.sites)
    inner = next(i for i in range(d.n_sites) if i not in set(hull.tolist()))
    i, j = int(hull[0]), inner
    site = np.where(d.site == i, j, np.where(d.site == j, i, d.site))
    cert = certify(with_arrays(d, site=site))
    assert "hull" in failed(cert)
    assert set(cert.check("hull").offending) == {i, j}
    assert not cert.check("hull").within_tolerance


def test_flipped_twin_fails_edges_and_structure():
    d = qhull("uniform", 60)
    h = finite_edge(d)
    origin = d.origin.copy()
    origin[h], origin[d.twin[h]] = d.origin[d.twin[h]], d.origin[h]
    cert = certify(with_arrays(d, origin=origin))
    assert {"structure", "edges"} <= failed(cert)
    assert min(h, int(d.twin[h])) in cert.check("edges").offending


def test_ray_pointing_the_wrong_way_fails_edges():
    """Three sites: flip one ray (start at the vertex instead of ending there) in a DCEL that
    is still structurally valid: the ray points into the other sites."""
    sites = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    good = assemble(sites, [[1.0, 1.0]], [[0, 1], [1, 2], [2, 0]], [[-1, 0], [-1, 0], [-1, 0]])
    assert certify(good).ok
    flipped = assemble(sites, [[1.0, 1.0]], [[1, 0], [2, 1], [0, 2]], [[-1, 0], [-1, 0], [-1, 0]])
    cert = certify(flipped)
    assert "edges" in failed(cert) and "wrong way" in cert.check("edges").detail


def test_wrongly_split_degree_4_vertex_fails():
    wrong = assemble(SQUARE, [[0.5, 0.5], [0.5, 0.5]], [[0, 1], [1, 2], [2, 0], [1, 3], [3, 0]],
                     [[0, 1], [0, -1], [0, -1], [-1, 1], [-1, 1]]).validate()
    cert = certify(wrong)
    assert not cert.ok and "edges" in failed(cert) and "probes" in failed(cert)
    # Cells 2 and 3 claim the territory of their neighbours across the wrong rays.
    assert "claims a random probe" in cert.check("probes").detail


def test_dropped_edge_with_merged_vertices_fails_the_vertex_check():
    d = qhull("uniform", 60)
    h = finite_edge(d)
    u, v = int(d.origin[h]), int(d.origin[d.twin[h]])
    e = d.edges()
    sites = np.stack([d.site[e], d.site[d.twin[e]]], 1)
    ends = np.stack([d.origin[e], d.origin[d.twin[e]]], 1)
    keep = e != min(h, int(d.twin[h]))
    ends = np.where(ends == v, u, ends)[keep]
    broken = assemble(d.sites, d.vertices, sites[keep], ends, compact_vertices=True)
    cert = certify(broken)
    assert "vertices" in failed(cert)
    assert "not equidistant" in cert.check("vertices").detail
    assert cert.check("euler").ok                     # V and E both drop by one: Euler cannot see it


def test_two_diagrams_in_one_fail_euler():
    """Two copies of a three-site diagram glued into one DCEL (joined only at infinity)."""
    sites = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    one = assemble(sites, [[1.0, 1.0]], [[0, 1], [1, 2], [2, 0]], [[-1, 0], [-1, 0], [-1, 0]])
    two = np.concatenate([sites, sites + 10])
    d = assemble(two, [[1.0, 1.0], [11.0, 11.0]], [[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 3]],
                 [[-1, 0], [-1, 0], [-1, 0], [-1, 1], [-1, 1], [-1, 1]])
    cert = certify(d)
    assert not cert.check("euler").ok and "V - E + n = 2 - 6 + 6 = 2 (expected 1)" in cert.check("euler").detail
    assert certify(one).check("euler").ok


def test_unusable_arrays_are_reported_not_raised():
    d = qhull("uniform", 20)
    twin = d.twin.copy()
    twin[0] = d.n_half_edges + 5
    cert = certify(with_arrays(d, twin=twin))
    assert not cert.ok and not cert.check("structure").ok
    assert all(not c.ok for c in cert.checks)
    twin = d.twin.copy()
    twin[[0, 1]] = twin[[1, 0]]                       # in range, but not an involution
    cert = certify(with_arrays(d, twin=twin))
    assert not cert.check("structure").ok and "twin" in cert.check("structure").detail


def test_qhull_near_degenerate_errors_are_within_tolerance():
    """Qhull merges nearly collinear hull sites of a grid nudged by 1e-12: wrong, but only
    near-degenerately (what ``within_tolerance`` is for)."""
    cert = certify(qhull("near_grid", 1000, seed=1))
    assert not cert.ok and cert.ok_within_tolerance and cert.verdict == "within_tolerance"
    assert {"edges", "hull", "topology"} >= failed(cert)


def test_report_and_dict():
    d = qhull("uniform", 40)
    vertices = d.vertices.copy()
    vertices[0] += 0.01
    cert = certify(with_arrays(d, vertices=vertices))
    text = str(cert)
    assert text.startswith("certificate: NOT CERTIFIED") and "FAIL vertices" in text
    data = json.loads(json.dumps(cert.to_dict()))
    assert data["ok"] is False and data["verdict"] == "not_certified"
    assert [c["name"] for c in data["checks"]] == list(CHECKS)
    assert "CERTIFIED" in str(certify(d))


def test_non_finite_vertex_fails_every_geometric_check():
    """NaN compares false: the checks must still count it as a violation."""
    d = qhull("uniform", 50)
    vertices = d.vertices.copy()
    vertices[3] = np.nan
    cert = certify(with_arrays(d, vertices=vertices))
    assert {"structure", "vertices", "edges"} <= failed(cert)
    assert 3 in cert.check("vertices").offending


# ------------------------------------------------------------------------------ any magnitude
def scaled(d: Diagram, k: int) -> Diagram:
    """``d`` with every coordinate times 2**k (exact while nothing leaves the float range;
    subnormal results are rounded once)."""
    return with_arrays(d, sites=np.ldexp(d.sites, k), vertices=np.ldexp(d.vertices, k))


GRID6 = np.array([[x, y] for x in range(6) for y in range(6)], dtype=float) / 8
#: 2**k: the 6x6 grid times 2**-1060 (subnormal), ~1e-200, ~1e300, ~1e-30, ~1e30
EXTREME = [-1057, -664, 997, -100, 100]


@pytest.mark.parametrize("k", EXTREME)
def test_right_diagrams_certify_at_any_magnitude(k):
    for d in (impls.build("fortune", GRID6), impls.build("qhull", datasets_gen.generate("uniform", 60))):
        if k < -1000 and d.n_sites != GRID6.shape[0]:
            continue                     # random sites would lose bits as subnormals: another input
        cert = certify(scaled(d, k))
        assert cert.ok, str(cert)


@pytest.mark.parametrize("k", EXTREME)
def test_parallel_lines_for_a_grid_fail_at_any_magnitude(k):
    """The n - 1 parallel lines of 'collinear' sites, for a grid that is not collinear: what
    implementations returned for subnormal and 1e-200-scale input, and certify accepted
    (its orientation tests and probes underflowed to 0)."""
    cert = certify(collinear_diagram(np.ldexp(GRID6, k)))
    assert not cert.ok and not cert.ok_within_tolerance, str(cert)
    assert {"hull", "probes"} <= failed(cert)


@pytest.mark.parametrize("k", EXTREME)
def test_moved_vertex_and_dropped_edge_fail_at_any_magnitude(k):
    d = impls.build("fortune", GRID6) if k < -1000 else qhull("uniform", 60)
    d = scaled(d, k)
    vertices = d.vertices.copy()
    vertices[3] += np.ldexp(1e-3, k)
    cert = certify(with_arrays(d, vertices=vertices))
    assert not cert.ok and "vertices" in failed(cert), str(cert)
    e = d.edges()
    u_all, v_all = d.origin[e], d.origin[d.twin[e]]
    real = (u_all >= 0) & (v_all >= 0)
    real[real] = (d.vertices[u_all[real]] != d.vertices[v_all[real]]).any(axis=1)   # not zero-length
    h = int(e[np.flatnonzero(real)[0]])
    u, v = int(d.origin[h]), int(d.origin[d.twin[h]])
    pairs = np.stack([d.site[e], d.site[d.twin[e]]], 1)
    ends = np.stack([d.origin[e], d.origin[d.twin[e]]], 1)
    keep = e != min(h, int(d.twin[h]))
    broken = assemble(d.sites, d.vertices, pairs[keep], np.where(ends == v, u, ends)[keep], compact_vertices=True)
    cert = certify(broken)
    assert not cert.ok and not cert.ok_within_tolerance, str(cert)


def test_sites_beyond_the_exact_range_are_not_certified():
    """Magnitudes 1 and 1e-300 in one diagram: no power of two makes its tests exact."""
    d = assemble(np.array([[1.0, 0.0], [0.0, 1e-300]]), np.zeros((0, 2)), [[0, 1]], [[-1, -1]])
    cert = certify(d)
    assert not cert.ok and "exact range" in cert.check("structure").detail


def test_probe_ties_within_roundings_of_the_lifts_are_near_degenerate():
    """near_grid with 0/1 weights ties exactly (a weight-0 site's power 0 at itself, its
    weight-1 neighbours' 1 - 1 = 0) up to the 1e-12 nudges: Qhull hides such sites, so their
    own positions are in a neighbour's cell. Ties within roundings of the lifted coordinates:
    near-degenerate. Cells swapped between far sites are no tie: not within tolerance."""
    points = datasets_gen.generate("near_grid", 1000, seed=0)
    weights = datasets_gen.weights("integer", points, seed=0)
    probes = certify(impls.build("qhull", points, weights=weights), probes=1000).check("probes")
    assert not probes.ok and probes.within_tolerance, probes.detail
    exact = impls.build("incremental", points, weights=weights)
    site = np.array(exact.site)
    swapped = site.copy()
    a, b = int(site[0]), int(site[-1])
    swapped[site == a], swapped[site == b] = b, a
    wrong = Diagram(exact.sites, exact.vertices, exact.origin, exact.twin, exact.next, swapped, weights=exact.weights)
    probes = certify(wrong, probes=1000).check("probes")
    assert not probes.ok and not probes.within_tolerance, probes.detail


def test_the_kernels_are_compiled_once_whatever_kind_of_arrays_the_diagram_holds():
    # numba compiles a kernel again for each kind of argument (read-only or not, int32 or
    # int64): every process of a run would pay that. The constructions' DCELs are int32 and
    # read-only; a diagram rebuilt from writable int64 copies is another kind.
    from vorobench.judge import certificate as cert

    sites = datasets_gen.generate("uniform", 40, seed=3)
    fortune, incremental = impls.build("fortune", sites), impls.build("incremental", sites)
    rebuilt = Diagram(np.array(fortune.sites), np.array(fortune.vertices),
                      *(np.array(x, dtype=np.int64) for x in (fortune.origin, fortune.twin, fortune.next, fortune.site)))
    for d in (fortune, incremental, rebuilt):
        assert certify(d).ok
    for kernel in (cert._vertex_kernel, cert._edge_kernel, cert._probe_kernel, cert._site_probe_kernel):
        assert len(kernel.signatures) == 1, (kernel.py_func.__name__, kernel.signatures)
