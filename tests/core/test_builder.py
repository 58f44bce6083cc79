"""The shared builder and Diagram.validate(): hand-made diagrams and each broken invariant."""

from dataclasses import replace

import numpy as np
import pytest

from vorobench import Diagram, InvalidDiagramError
from vorobench.core.builder import assemble, collinear_diagram
from vorobench.core.clip import polygon_area


def three_sites() -> Diagram:
    """Sites (0,0), (2,0), (0,2): one vertex at (1,1), three rays."""
    sites = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    # Edge (a, b) with a's half-edge running along perp(b - a).
    # 0|1: bisector x = 1, perp((2,0)) = (0, 2): upward, so it starts at infinity below (1,1).
    # 1|2: perp((-2, 2)) = (-2, -2): from infinity at the upper right down to (1,1).
    # 2|0: perp((0, -2)) = (2, 0): along y = 1, from infinity on the left to (1,1).
    return assemble(sites, [[1.0, 1.0]], [[0, 1], [1, 2], [2, 0]], [[-1, 0], [-1, 0], [-1, 0]])


def test_builder_links_a_valid_diagram():
    d = three_sites().validate()
    assert d.counts() == {"n": 3, "V": 1, "E": 3, "H": 6}
    assert np.array_equal(d.twin[d.twin], np.arange(6))
    # Each cell: one half-edge in from infinity, one out.
    for i in range(3):
        hs = d.cell_half_edges(i)
        assert len(hs) == 2 and d.origin[hs[0]] == -1 and d.origin[hs[1]] == 0
    assert sorted(map(tuple, d.ridge_points.tolist())) == [(0, 1), (1, 2), (2, 0)]
    assert d.regions == [[-1, 0], [-1, 0], [-1, 0]]


def test_clipped_cells_tile_the_box():
    d = three_sites()
    box = (-3.0, -3.0, 4.0, 5.0)
    areas = [polygon_area(p) for p in d.polygons(box)]
    assert all(a > 0 for a in areas)
    assert sum(areas) == pytest.approx(7.0 * 8.0)
    # Cell 0 is {x <= 1, y <= 1} within the box.
    assert areas[0] == pytest.approx(4.0 * 4.0)


def test_collinear_sites_give_parallel_lines():
    sites = np.array([[3.0, 3.0], [0.0, 0.0], [1.0, 1.0], [2.0, 2.0]])
    d = collinear_diagram(sites).validate()
    assert d.n_vertices == 0 and d.n_edges == 3
    assert (d.origin == -1).all()
    # The two middle cells are strips: bounded by two lines, each following the other.
    strip = [i for i in range(4) if len(d.cell_half_edges(i)) == 2]
    assert sorted(strip) == [2, 3]
    areas = [polygon_area(p) for p in d.polygons((-1.0, -1.0, 4.0, 4.0))]
    assert sum(areas) == pytest.approx(25.0)


def test_two_sites_one_line_next_is_self():
    d = collinear_diagram(np.array([[0.0, 0.0], [1.0, 0.0]])).validate()
    assert d.n_half_edges == 2 and list(d.next) == [0, 1]


def test_save_and_load_round_trip(tmp_path):
    d = three_sites()
    d.save(tmp_path / "d.npz")
    e = Diagram.load(tmp_path / "d.npz").validate()
    for f in ("sites", "vertices", "origin", "twin", "next", "site"):
        assert np.array_equal(getattr(d, f), getattr(e, f))


def test_load_rejects_other_npz(tmp_path):
    np.savez(tmp_path / "x.npz", a=np.zeros(3))
    with pytest.raises(ValueError, match="not a vorobench diagram"):
        Diagram.load(tmp_path / "x.npz")


def _broken(field, fn):
    d = three_sites()
    arr = getattr(d, field).copy()
    fn(arr)
    return replace(d, **{field: arr})


@pytest.mark.parametrize(
    "field, fn, words",
    [
        ("twin", lambda a: a.__setitem__(0, 0), "own twin"),
        ("twin", lambda a: a.__setitem__(slice(0, 3), [2, 0, 1]), "involution"),
        ("next", lambda a: a.__setitem__(0, 0), "permutation"),
        ("site", lambda a: a.__setitem__(1, a[0]), "both bound cell"),
        ("origin", lambda a: a.__setitem__(0, 0), "ends at"),
        ("origin", lambda a: a.__setitem__(2, 5), "out of range"),
        ("next", lambda a: a.__setitem__(0, 7), "out of range"),
    ],
)
def test_validate_names_each_broken_invariant(field, fn, words):
    with pytest.raises(InvalidDiagramError, match=words):
        _broken(field, fn).validate()


def test_validate_catches_next_leaving_the_cell():
    d = three_sites()
    nxt = d.next.copy()
    h0, h1 = 0, 2  # half-edges of different cells
    nxt[[h0, h1]] = nxt[[h1, h0]]
    d = replace(d, next=nxt)
    with pytest.raises(InvalidDiagramError, match="leaves the cell|starts at"):
        d.validate()


def test_validate_catches_missing_cell_and_unused_vertex():
    d = three_sites()
    d = replace(d, sites=np.vstack([d.sites, [[9.0, 9.0]]]))
    with pytest.raises(InvalidDiagramError, match="site 3 has no cell"):
        d.validate()
    d = three_sites()
    d = replace(d, vertices=np.vstack([d.vertices, [[5.0, 5.0]]]))
    with pytest.raises(InvalidDiagramError, match="vertex 1 is not the origin"):
        d.validate()


def test_builder_reports_cells_that_do_not_close():
    sites = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    with pytest.raises(InvalidDiagramError, match="does not close"):
        # Edge 1|2 wrongly oriented: it leaves the vertex instead of arriving.
        assemble(sites, [[1.0, 1.0]], [[0, 1], [1, 2], [2, 0]], [[-1, 0], [0, -1], [-1, 0]])


def test_a_cell_that_does_not_close_is_reported_among_many_sites():
    # 65,539 sites and 65,535 vertices: (cell, start vertex) keys pass 2**31, where int32 keys
    # wrapped and paired the open cells 2 and 65,538 with each other
    n, rng = 65_539, np.random.default_rng(0)
    vertices = np.zeros((65_535, 2))
    vertices[0] = (0.5, 0.5)
    with pytest.raises(InvalidDiagramError, match="cell 2 does not close"):
        assemble(rng.random((n, 2)), vertices, np.array([[0, 1], [1, 2], [n - 1, 0]]), [[-1, 0]] * 3)


@pytest.mark.parametrize("dtype", [np.int32, np.int64])
def test_the_diagram_shares_no_memory_with_the_callers_edges(dtype):
    sites = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    ab = np.array([[0, 1], [1, 2], [2, 0]], dtype=dtype)
    se = np.array([[-1, 0], [-1, 0], [-1, 0]], dtype=dtype)
    d = assemble(sites, [[1.0, 1.0]], ab, se)
    site, origin = d.site.copy(), d.origin.copy()
    ab[:] = 0                                   # the caller reuses its buffers
    se[:] = 7
    assert np.array_equal(d.site, site) and np.array_equal(d.origin, origin)
    d.validate()


def test_two_cycles_in_one_cell_are_reported():
    # Collinear 3 sites, then make the middle cell's two lines each point to itself.
    d = collinear_diagram(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]))
    nxt = d.next.copy()
    mid = np.flatnonzero(d.site == 1)
    nxt[mid] = mid
    d = replace(d, next=nxt)
    with pytest.raises(InvalidDiagramError, match="one cycle per cell"):
        d.validate()
