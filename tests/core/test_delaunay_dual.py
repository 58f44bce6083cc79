"""The Voronoi DCEL dual to a Delaunay triangulation: the one-pass numbering by triangle gives
the diagram the general path (twin pairs, merges) gives, and hands over at cocircular pairs."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import datasets_gen
import vorobench
from impls.incremental import _triangulate
from vorobench.core.delaunay_dual import _general_dcel, voronoi_dcel
from vorobench.core.diagram import Diagram
from vorobench.core.prepare import prepare


def _both(sites):
    """(one-pass diagram, general diagram, their counters, merged) of the prepared sites."""
    points, ids, tri, opp, ntri, ok = _triangulate(sites, None)
    assert ok
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
def test_random_sites_give_the_general_diagram_with_the_same_tests(n, seed):
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
    # each pair of finite neighbours is tested once on either path
    assert np.array_equal(c_fast, c_general)


@pytest.mark.parametrize("dataset", ["grid", "cocircular_many", "lattice_rotated", "near_grid", "huge_offset",
                                     "clusters", "duplicates"])
def test_every_family_gives_the_general_diagram(dataset):
    sites, _ = prepare(datasets_gen.generate(dataset, 400, seed=2))
    (fast, general), _, (m_fast, m_general) = _both(sites)
    _assert_same(fast, general)
    assert m_fast == m_general


def test_a_grid_hands_over_and_merges_its_squares():
    """4 x 4 unit squares: every square's two triangles share one vertex, of degree 4."""
    sites, _ = prepare(np.array([(i, j) for i in range(5) for j in range(5)], dtype=float))
    (fast, _), _, (merged, _) = _both(sites)
    assert merged == 16
    assert fast.vertices.shape[0] == 16
    assert np.array_equal(np.unique(fast.vertices, axis=0), [(i + 0.5, j + 0.5) for i in range(4) for j in range(4)])
    assert vorobench.certify(fast).ok
