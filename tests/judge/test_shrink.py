"""Delta debugging shrinks failures to small witnesses within its time budget (even when one
step is slow); witnesses reproduce and come with a picture, unless asked not to draw one."""

import time
from types import SimpleNamespace

import numpy as np
import pytest

import datasets_gen
import impls
from impls.base import Implementation
from impls.qhull import build as qhull_build
from vorobench.core.diagram import Diagram
from vorobench.judge import shrink
from vorobench.judge.engine import CaseVerdict, Judge, check_case
from vorobench.judge.shrink import ddmin, shrink_case, write_witness

#: A plugin that builds the diagram of other sites (wrong_sites) on 20 sites or more, and hangs on fewer:
#: every step of shrinking it would cost a whole timeout.
HANGS_WHEN_SMALL = """\
import time

from impls.qhull import build as qhull_build
from vorobench.plugin import Implementation


def build(sites, stats=None):
    if sites.shape[0] < 20:
        time.sleep(3600)
    moved = sites.copy()
    moved[0] += 0.05
    return qhull_build(moved, stats)


IMPLEMENTATIONS = [Implementation("hangs_when_small", "wrong on many sites, hangs on few", "n/a", build,
                                  exact=False)]
"""


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


def test_ddmin_does_not_start_a_test_that_would_overrun_its_budget(monkeypatch):
    now = [0.0]
    monkeypatch.setattr(shrink, "time", SimpleNamespace(monotonic=lambda: now[0]))     # a synthetic clock

    def slow_fails(idx):
        now[0] += 10.0                  # every test takes 10 s
        return idx.size > 1

    ddmin(64, slow_fails, time_budget=25.0)
    # Tests at 0 s and 10 s; a third, started at 20 s, would end at 30 s: past the budget.
    assert now[0] <= 25.0


def test_shrinking_stops_within_its_budget_when_a_step_hangs(tmp_path):
    plugin = tmp_path / "hangs_when_small.py"
    plugin.write_text(HANGS_WHEN_SMALL)
    points = datasets_gen.generate("uniform", 30, seed=2)
    with Judge(["hangs_when_small"], "halfplane", probes=100, timeout=120.0, plugins=[str(plugin)]) as engine:
        verdict = check_case("hangs_when_small", points, reference="halfplane", probes=100, judge=engine)
        assert (verdict.verdict, verdict.passed) == ("wrong_sites", False)
        started = time.monotonic()
        small, _ = shrink_case("hangs_when_small", points, verdict, reference="halfplane", probes=100,
                               time_budget=3.0, judge=engine)
        elapsed = time.monotonic() - started
    # Each step is bounded by what is left of the 3 s, not by the judge's 120 s timeout.
    assert elapsed < 60.0
    assert small.shape[0] == 30         # no smaller set was seen failing the same way
    assert engine.timeout == 120.0      # the judge's own timeout is restored


def test_a_witness_can_be_written_without_its_picture(tmp_path):
    points = datasets_gen.generate("uniform", 12, seed=1)
    verdict = CaseVerdict("fortune", "qhull", "timeout", False, None, None, "fortune timed out: no result", "impl")
    w = write_witness(tmp_path, "hung", "fortune", points, reference="qhull", verdict=verdict, picture=False)
    assert w.picture is None and not (tmp_path / "hung.png").exists()
    assert np.array_equal(np.load(w.points), points)
    assert "verdict timeout: fortune timed out" in w.command.read_text()


def test_shrink_a_broken_implementation_to_a_few_points(broken, tmp_path):
    points = datasets_gen.generate("uniform", 300, seed=4)
    verdict = check_case(broken, points)
    assert not verdict.passed and verdict.verdict == "not_certified"
    small, no_weights = shrink_case(broken, points, verdict, reference="qhull")
    assert no_weights is None
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
