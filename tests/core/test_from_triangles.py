"""A diagram from a bare list of triangles: checked to be a triangulation, then dualised."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial import Delaunay

import impls
import vorobench
from vorobench.core.from_triangles import NotATriangulation, diagram_from_triangles


def _shuffled(triangles, seed=0):
    """The same triangles in another order, half of them clockwise, corners rotated."""
    rng = np.random.default_rng(seed)
    t = np.array(triangles)[rng.permutation(len(triangles))]
    t[::2] = t[::2, [0, 2, 1]]
    return np.roll(t, 1, axis=1)


@settings(max_examples=25, deadline=None)
@given(st.integers(4, 60), st.integers(0, 2 ** 32 - 1))
def test_any_order_and_orientation_gives_the_exact_diagram(n, seed):
    sites = np.random.default_rng(seed).random((n, 2))
    d = diagram_from_triangles(sites, _shuffled(Delaunay(sites).simplices, seed))
    comparison = vorobench.compare(impls.build("fortune", sites), d)
    assert comparison.equal and comparison.verdict == "exact", str(comparison)


def test_a_grid_split_either_way_merges_its_cocircular_squares():
    grid = np.array([(i, j) for i in range(5) for j in range(5)], dtype=float)
    d = diagram_from_triangles(grid, _shuffled(Delaunay(grid).simplices))
    assert vorobench.compare(impls.build("fortune", grid), d).verdict == "exact"
    assert vorobench.certify(d).ok


def test_no_triangles_is_the_collinear_diagram_or_an_error():
    line = np.array([[0.0, 0.0], [1.0, 1.0], [3.0, 3.0]])
    assert diagram_from_triangles(line, np.empty((0, 3), int)).n_half_edges == 4
    with pytest.raises(NotATriangulation, match="not all collinear"):
        diagram_from_triangles(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), np.empty((0, 3), int))


SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.5, 0.4]])
FAN = [[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]


@pytest.mark.parametrize("triangles, says", [
    ([[0, 1, 5]], "outside 0..4"),
    ([[0, 1, 1]], "names a site twice"),
    (FAN + [[0, 1, 4]], "overlap"),
    (FAN[:2] + [[0, 2, 3]], "cycle"),                                   # overlapping without a shared edge
    ([[0, 1, 2], [0, 2, 3]], "in no triangle"),                         # site 4 missing
])
def test_what_is_not_a_triangulation_is_said(triangles, says):
    with pytest.raises(NotATriangulation, match=says):
        diagram_from_triangles(SQUARE, np.array(triangles))


def test_a_triangulation_short_of_the_hull_is_assembled_and_fails_its_certificate():
    d = diagram_from_triangles(SQUARE, np.array(FAN[:3]))             # the corner triangle (3, 0, 4) left out
    assert not vorobench.certify(d).ok


def test_a_flat_triangle_is_refused():
    sites = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.0, 1.0]])
    with pytest.raises(NotATriangulation, match="flat"):
        diagram_from_triangles(sites, np.array([[0, 1, 2], [0, 2, 3]]))


def test_two_pieces_touching_at_a_site_are_refused():
    sites = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]])
    with pytest.raises(NotATriangulation, match="cycle"):
        diagram_from_triangles(sites, np.array([[0, 1, 2], [0, 3, 4]]))


def test_a_regular_triangulation_leaves_its_hidden_site_without_a_cell():
    sites = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 4.0], [4.0, 4.0], [2.0, 2.0]])
    weights = np.array([0.0, 0.0, 0.0, 0.0, -10.0])          # the centre's power is too high: hidden
    d = diagram_from_triangles(sites, np.array([[0, 1, 2], [1, 3, 2]]), weights)
    assert d.hidden.tolist() == [4]
    assert vorobench.compare(impls.build("incremental", sites, weights=weights), d).verdict == "exact"
