"""Delta debugging shrinks failures to small witnesses; witnesses reproduce and come with a picture."""

import numpy as np
import pytest

import datasets_gen
import impls
from impls.base import Implementation
from impls.qhull import build as qhull_build
from vorobench.core.diagram import Diagram
from vorobench.judge.engine import check_case
from vorobench.judge.shrink import ddmin, shrink_case, write_witness


def _moved_vertex(sites, stats=None) -> Diagram:
    """qhull's diagram with its first vertex pushed by 1e-3 of the scale: wrong."""
    d = qhull_build(sites, stats)
    if d.n_vertices:
        vertices = d.vertices.copy()
        vertices[0] += 1e-3 * np.ptp(sites, axis=0).max()
        d = Diagram(d.sites, vertices, d.origin, d.twin, d.next, d.site)
    return d


@pytest.fixture
def broken():
    impl = Implementation("test_moved_vertex", "qhull with one vertex moved", "O(n log n)", _moved_vertex, exact=True)
    impls.register(impl)
    yield impl.name
    impls.unregister(impl.name)


def test_ddmin_finds_the_two_culprits():
    culprits = {3, 17}
    calls = []

    def fails(idx):
        calls.append(len(idx))
        return culprits <= set(idx.tolist())

    assert sorted(ddmin(40, fails).tolist()) == [3, 17]
    assert len(calls) < 120


def test_ddmin_result_is_one_minimal():
    # Fails while at least 5 even indices remain: the result has exactly 5, all even.
    result = ddmin(64, lambda idx: int(np.sum(idx % 2 == 0)) >= 5)
    assert result.size == 5 and (result % 2 == 0).all()


def test_ddmin_respects_the_test_budget():
    calls = []
    ddmin(1000, lambda idx: calls.append(1) or idx.size > 1, max_tests=10)
    assert len(calls) == 10


def test_shrink_a_broken_implementation_to_a_few_points(broken, tmp_path):
    points = datasets_gen.generate("uniform", 300, seed=4)
    verdict = check_case(broken, points)
    assert not verdict.passed and verdict.verdict == "not_certified"
    small = shrink_case(broken, points, verdict, reference="qhull")
    assert 3 <= small.shape[0] <= 20
    again = check_case(broken, small)
    assert (again.verdict, again.passed) == ("not_certified", False)
    # Every row of the witness is a row of the input.
    assert all((points == row).all(1).any() for row in small)
    w = write_witness(tmp_path / "w", "moved", broken, small, reference="qhull")
    assert np.array_equal(np.load(w.points), small)
    text = w.command.read_text()
    assert text.startswith(f"vorobench validate --impls {broken} --reference qhull --points ")
    assert "not_certified" in text and "FAIL vertices" in text
    assert w.picture is not None and w.picture.stat().st_size > 1000
    assert w.picture.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
