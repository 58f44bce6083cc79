"""The plugin under vorobench's judge: every diagram certified and compared with vorobench's
exact ``incremental`` construction, on random and degenerate datasets.

Runs against the installed package (the entry point registers it) or, from a source
checkout, against the module registered by hand for this test module.
"""

from __future__ import annotations

from importlib.metadata import entry_points

import numpy as np
import pytest
from vorobench_scipy_delaunay import IMPLEMENTATION

import datasets_gen
import impls
from vorobench.judge.engine import Judge
from vorobench.plugin import BuildFunction, Diagram

NAME = IMPLEMENTATION.name
#: An exact construction: a verdict against it says whether Qhull's diagram is the true one.
REFERENCE = "incremental"
DATASETS = ("uniform", "normal", "clusters", "parabola", "grid", "lattice_rotated", "cocircular",
            "cocircular_many", "collinear", "duplicates", "huge_offset", "tiny_spacing")
SIZES = (0, 1, 2, 3, 10, 100, 400)


@pytest.fixture(scope="module", autouse=True)
def registered():
    """The implementation under its name, for ``impls`` and the judge."""
    installed = NAME in impls.available()
    if not installed:
        impls.register(IMPLEMENTATION)
    yield
    if not installed:
        impls.unregister(NAME)


@pytest.fixture(scope="module")
def judge():
    with Judge([NAME], REFERENCE, isolate=False) as j:
        yield j


def test_it_declares_what_it_is():
    assert isinstance(IMPLEMENTATION.build, BuildFunction)
    assert (IMPLEMENTATION.exact, IMPLEMENTATION.kind, IMPLEMENTATION.complexity) == (False, "plugin", "O(n log n)")


def test_the_entry_point_names_this_implementation():
    found = [ep for ep in entry_points(group=impls.ENTRY_POINT_GROUP) if ep.name == NAME]
    if not found:
        pytest.skip("the package is not installed (no entry point)")
    assert found[0].load() is IMPLEMENTATION
    assert impls.get(NAME) is IMPLEMENTATION


@pytest.mark.parametrize("dataset", DATASETS)
def test_it_agrees_with_an_exact_construction(judge, dataset):
    failures = []
    for n in SIZES:
        for seed in (0, 1):
            case = judge.judge(datasets_gen.generate(dataset, n, seed=seed))
            for name, verdict, _ in case.rows:
                if not verdict.passed or (name == NAME and verdict.verdict not in ("exact", "within_tolerance")):
                    failures.append(f"n={n} seed={seed} {name}: {verdict.verdict}: {verdict.message}")
    assert not failures, "\n".join(failures)


def test_counters_obey_euler_and_times_are_split():
    sites = datasets_gen.generate("uniform", 200, seed=3)
    stats: dict = {}
    timings: dict = {}
    diagram = IMPLEMENTATION.run(sites, stats, timings=timings)
    # A triangulation of n sites with h of them on the hull has 2n - 2 - h triangles.
    assert stats["triangles"] == 2 * 200 - 2 - stats["hull_edges"] > 0
    assert diagram.counts()["V"] == stats["triangles"]
    assert set(timings) == {"library", "convert"} and all(t > 0 for t in timings.values())


@pytest.mark.parametrize("points, vertices", [
    (np.zeros((0, 2)), 0),
    (np.array([[0.5, 0.5]]), 0),
    (np.array([[0.0, 0.0], [1.0, 2.0], [2.0, 4.0], [3.0, 6.0]]), 0),       # collinear: 3 parallel lines
    (np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), 1),
])
def test_inputs_without_a_triangulation(points, vertices):
    diagram = impls.build(NAME, points)
    assert type(diagram) is Diagram
    assert diagram.counts()["n"] == len(points) and diagram.counts()["V"] == vertices
    diagram.validate()
