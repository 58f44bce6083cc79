"""The judging engine on weighted sites: the sandbox builds the power diagram and sends its
weights back, an implementation without weights is unsupported (no sandbox started for it),
and a diagram of other weights is refused."""

from __future__ import annotations

import numpy as np
import pytest

import datasets_gen
import impls
from impls.base import Implementation
from impls.qhull import build as qhull_build
from vorobench.judge.engine import (
    NO_WEIGHTS,
    BuildResult,
    Judge,
    build_only,
    certify_result,
    diagram_arrays,
    diagram_from_arrays,
    prepare_case,
)

ORDINARY_ONLY = "test_ordinary_only"


@pytest.fixture
def ordinary_only():
    """An implementation that builds ordinary diagrams only (qhull's, without weights)."""
    impls.register(Implementation(ORDINARY_ONLY, "ordinary diagrams only", "O(n log n)", qhull_build, exact=False))
    yield ORDINARY_ONLY
    impls.unregister(ORDINARY_ONLY)


def _case(family: str = "radii", n: int = 60, seed: int = 2):
    points = datasets_gen.generate("uniform", n, seed=seed)
    return prepare_case(points, datasets_gen.weights(family, points, seed=seed))


def _weighted_reference() -> str:
    if not impls.get("qhull").weighted:
        pytest.skip("qhull does not take weights yet")
    return "qhull"


def test_diagram_arrays_carry_the_weights_and_only_for_a_power_diagram():
    reference = _weighted_reference()
    sites, weights = _case()
    power = impls.get(reference).run(sites, None, weights=weights)
    arrays = diagram_arrays(power)
    assert np.array_equal(arrays["weights"], weights)
    back = diagram_from_arrays(arrays)
    assert back.is_power and np.array_equal(back.weights, weights)
    assert np.array_equal(back.hidden, power.hidden)
    ordinary = impls.get(reference).run(sites, None)
    assert "weights" not in diagram_arrays(ordinary)
    assert not diagram_from_arrays(diagram_arrays(ordinary)).is_power


def test_the_sandboxed_build_returns_the_weights():
    reference = _weighted_reference()
    sites, weights = _case("hidden")
    with Judge([reference], reference) as judge:
        res = judge.build(reference, sites, weights=weights)
        assert reference in judge._sandboxes           # built in a sandbox, not here
    assert not res.error and not res.unsupported, res.error or res.unsupported
    assert res.diagram.is_power and np.array_equal(res.diagram.weights, weights)
    assert res.diagram.hidden.size > 0                  # the hidden family hides sites: a power diagram
    assert res.certified


def test_an_implementation_without_weights_is_unsupported_without_a_sandbox(ordinary_only):
    reference = _weighted_reference()
    sites, weights = _case()
    with Judge([reference, ordinary_only], reference) as judge:
        judged = judge.judge(sites, weights=weights)
        assert ordinary_only not in judge._sandboxes
    verdicts = {name: v for name, v, peer in judged.rows if peer is None}
    assert verdicts[ordinary_only].verdict == "unsupported" and verdicts[ordinary_only].passed
    assert verdicts[ordinary_only].message.startswith(f"{ordinary_only} {NO_WEIGHTS}")
    assert verdicts[reference].verdict == "certified"
    assert np.array_equal(judged.weights, weights)
    # Without weights the same implementation is judged as usual.
    with Judge([reference, ordinary_only], reference, isolate=False) as judge:
        rows = {name: v for name, v, peer in judge.judge(sites).rows if peer is None}
    assert rows[ordinary_only].verdict != "unsupported"


def test_build_only_refuses_weights_for_an_ordinary_implementation(ordinary_only):
    sites, weights = _case()
    res = build_only(ordinary_only, sites, weights)
    assert res.diagram is None and res.unsupported.startswith(NO_WEIGHTS)


def test_a_diagram_of_other_weights_or_none_is_wrong_sites():
    reference = _weighted_reference()
    sites, weights = _case()
    power = impls.get(reference).run(sites, None, weights=weights)
    other = certify_result(BuildResult(reference, False, power), sites, weights=weights * 0.5)
    assert other.failure == "wrong_sites" and "other weights" in other.error
    ordinary = impls.get(reference).run(sites, None)
    forgot = certify_result(BuildResult(reference, False, ordinary), sites, weights=weights)
    assert forgot.failure == "wrong_sites" and "ordinary diagram for weighted sites" in forgot.error
    extra = certify_result(BuildResult(reference, False, power), sites)
    assert extra.failure == "wrong_sites" and "power diagram for unweighted sites" in extra.error
    good = certify_result(BuildResult(reference, False, power), sites, weights=weights)
    assert not good.failure and good.certificate is not None


def test_duplicate_points_keep_their_largest_weight():
    points = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.0], [0.0, 1.0]])
    sites, weights = prepare_case(points, np.array([0.1, 0.0, 0.3, 0.0]))
    assert sites.shape == (3, 2) and np.array_equal(weights, [0.3, 0.0, 0.0])
