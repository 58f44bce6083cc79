"""The diagram of disks from the faces of their Apollonius graph (an executable's answer): faces
that CGAL's Apollonius_graph_2 printed (recorded here, so the test needs no toolchain) give
exactly the oracle's diagram; faces turned the wrong way, or with neighbours that do not match,
are refused."""

from __future__ import annotations

import numpy as np
import pytest

from impls import halfplane_disks
from vorobench.core.from_apollonius_graph import NotAnApolloniusGraph, diagram_from_apollonius_faces
from vorobench.judge.disk_judging import compare_disks
from vorobench.judge.outcomes import Verdict

#: A disk of radius 0.1 between two of radius 9.5 (a lens-shaped cell: two faces of the same
#: three sites, one per orientation) and a fourth disk above; CGAL's faces for it.
LENS = (np.array([[-10.0, 0.0], [0.0, 0.0], [10.0, 0.0], [0.0, 30.0]]), np.array([9.5, 0.1, 9.5, 1.0]))
LENS_FACES = [[1, 0, 2, 3, 1, 1], [0, 1, 2, 0, 4, 0], [2, -1, 3, 5, 4, 3],
              [2, 0, -1, 5, 2, 0], [0, 2, 3, 2, 5, 1], [-1, 0, 3, 4, 2, 3]]
#: Three points on a line: no finite face; each edge of the path has infinity on both sides.
PATH = (np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]), np.zeros(3))
PATH_FACES = [[1, -1, 2, 1, 1, 3], [-1, 1, 2, 0, 0, 2], [-1, 0, 1, 3, 1, 3], [1, 0, -1, 2, 0, 2]]


@pytest.mark.parametrize("disks, faces", [(LENS, LENS_FACES), (PATH, PATH_FACES)])
def test_recorded_faces_give_the_oracles_diagram(disks, faces):
    d = diagram_from_apollonius_faces(*disks, faces)
    assert compare_disks(halfplane_disks.build(*disks), d).verdict is Verdict.EXACT


def test_the_lens_has_two_vertices_and_two_edges_between_the_big_cells():
    d = diagram_from_apollonius_faces(*LENS, LENS_FACES)
    pairs = sorted(tuple(sorted((int(d.site[h]), int(d.site[d.twin[h]])))) for h in range(d.n_half_edges)
                   if h < d.twin[h])
    assert pairs.count((0, 2)) == 2 and len(d.cell_half_edges(1)) == 2


def test_no_faces_for_two_visible_disks_is_one_branch():
    d = diagram_from_apollonius_faces([[0.0, 0.0], [1.0, 0.0], [0.1, 0.0]], [0.2, 0.3, 0.05], np.zeros((0, 6)))
    assert d.n_edges == 1 and d.hidden.tolist() == [2] and (np.asarray(d.origin) == -1).all()
    with pytest.raises(NotAnApolloniusGraph, match="no faces for 3"):
        diagram_from_apollonius_faces(*PATH, np.zeros((0, 6)))


def test_a_face_turned_the_wrong_way_is_refused():
    faces = [row[:] for row in LENS_FACES]
    faces[4] = [0, 3, 2, 5, 2, 1]            # (0, 2, 3) listed clockwise, neighbours moved with it
    with pytest.raises(NotAnApolloniusGraph):
        diagram_from_apollonius_faces(*LENS, faces)


@pytest.mark.parametrize("row, column, value, says", [
    (0, 3, 2, "does not have face 0 across"),
    (0, 0, 7, "outside"),
    (1, 4, 9, "neighbour outside"),
])
def test_faces_that_do_not_fit_together_are_refused(row, column, value, says):
    faces = [r[:] for r in LENS_FACES]
    faces[row][column] = value
    with pytest.raises(NotAnApolloniusGraph, match=says):
        diagram_from_apollonius_faces(*LENS, faces)
