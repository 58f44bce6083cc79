"""`vorobench validate --weights`: power diagrams cross-validated; implementations without weights
reported unsupported and left out of the gate; a weights-ignoring implementation fails with a
witness that keeps its weights."""

from __future__ import annotations

import json
import shlex

import numpy as np
import pytest

import impls
from impls.base import Implementation
from impls.qhull import build as qhull_build
from vorobench.cli import main

REFERENCE = "qhull"
ORDINARY_ONLY = "test_ordinary_only"
IGNORES_WEIGHTS = "test_ignores_weights"


def _ignores_weights(sites, weights, stats=None):
    """The ordinary diagram, handed back as if it were the power diagram."""
    return qhull_build(sites, stats)


@pytest.fixture
def doubles():
    impls.register(Implementation(ORDINARY_ONLY, "ordinary diagrams only", "O(n log n)", qhull_build, exact=False))
    impls.register(Implementation(IGNORES_WEIGHTS, "ignores its weights", "O(n log n)", qhull_build, exact=False,
                                  build_weighted=_ignores_weights))
    yield
    impls.unregister(ORDINARY_ONLY)
    impls.unregister(IGNORES_WEIGHTS)


def _weighted() -> list[str]:
    if not impls.get(REFERENCE).weighted:
        pytest.skip(f"{REFERENCE} does not take weights yet")
    # Programs behind manifests are judged on weights in tests/impls/test_references.py.
    return [name for name in impls.weighted() if impls.get(name).kind != "executable"]


def _validate(tmp_path, *extra: str) -> tuple[int, dict]:
    code = main(["validate", "--reference", REFERENCE, "--out", str(tmp_path), "--no-shrink", *extra])
    return code, json.loads((tmp_path / "summary.json").read_text())


def _failures(summary: dict) -> str:
    return "\n".join(f"{r['impl']} {r['dataset']} n={r['n']}: {r['verdict']}: {r['message']}"
                     for r in summary["results"] if not r["passed"])


def test_equal_weights_pass_and_unweighted_implementations_are_unsupported(tmp_path, capsys, doubles):
    names = _weighted()
    code, summary = _validate(tmp_path, "--impls", ",".join([*names, ORDINARY_ONLY]), "--weights", "equal",
                              "--datasets", "uniform,grid", "--sizes", "10,60")
    out = capsys.readouterr().out
    assert code == 0 and summary["passed"], _failures(summary) + out
    assert summary["weights"] == "equal" and summary["unweighted"] == [ORDINARY_ONLY]
    assert summary["never_judged"] == []
    ordinary = [r for r in summary["results"] if r["impl"] == ORDINARY_ONLY]
    assert len(ordinary) == 4 and all(r["verdict"] == "unsupported" for r in ordinary)
    assert all("does not take weights" in r["message"] for r in ordinary)
    assert all(r["weights"] == "equal" for r in summary["results"])
    judged = {r["impl"] for r in summary["results"] if r["verdict"] != "unsupported"}
    assert judged == set(names)
    assert "equal weights" in out and f"{ORDINARY_ONLY} does not take weights" in out


def test_radii_weights_pass_for_every_weighted_implementation(tmp_path):
    names = _weighted()
    code, summary = _validate(tmp_path, "--impls", ",".join(names), "--weights", "radii",
                              "--datasets", "uniform,normal,clusters", "--sizes", "40,200", "--seeds", "0,1")
    assert code == 0 and summary["passed"], _failures(summary)
    assert len(summary["results"]) >= 3 * 2 * 2 * len(names)


def test_an_implementation_that_ignores_weights_fails_with_a_weighted_witness(tmp_path, doubles):
    _weighted()
    code = main(["validate", "--reference", REFERENCE, "--impls", IGNORES_WEIGHTS, "--weights", "hidden",
                 "--datasets", "uniform", "--sizes", "30", "--out", str(tmp_path), "--shrink-seconds", "20"])
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert code == 1 and not summary["passed"]
    assert summary["failed_impls"] == [IGNORES_WEIGHTS]
    (witness,) = summary["witnesses"]
    points = np.load(witness["points"])
    weights = np.load(witness["points"].replace(".npy", ".weights.npy"))
    assert weights.shape == (points.shape[0],) and points.shape[0] <= 30
    # The witness's command judges the same points with the same weights, and fails again.
    command = (tmp_path / "witnesses" / (witness["points"].rsplit("/", 1)[1][:-4] + ".txt")).read_text().splitlines()[0]
    assert "--weights file:" in command
    args = shlex.split(command)[1:] + ["--no-shrink", "--out", str(tmp_path / "again")]
    assert main(args) == 1
    again = json.loads((tmp_path / "again" / "summary.json").read_text())
    assert [r["verdict"] for r in again["results"] if r["impl"] == IGNORES_WEIGHTS] == [witness["shrunk_verdict"]]


def test_a_reference_without_weights_is_refused(tmp_path, capsys, doubles):
    code = main(["validate", "--reference", ORDINARY_ONLY, "--weights", "radii", "--datasets", "uniform",
                 "--sizes", "10", "--out", str(tmp_path)])
    assert code == 2
    assert f"reference {ORDINARY_ONLY} does not take weights" in capsys.readouterr().err


def test_a_gate_with_nothing_judged_fails(tmp_path, capsys, doubles):
    """`--weights radii --impls X` with an X that takes no weights: only the reference would be
    judged; that is no gate of X, and it must not say "all passed"."""
    junit = tmp_path / "j.xml"
    code, summary = _validate(tmp_path, "--impls", ORDINARY_ONLY, "--weights", "radii", "--datasets", "uniform",
                              "--sizes", "20", "--junit", str(junit))
    out = capsys.readouterr().out
    assert code == 1 and summary["passed"] is False
    assert summary["nothing_judged"] == [ORDINARY_ONLY] and summary["unweighted"] == [ORDINARY_ONLY]
    assert "NOTHING JUDGED" in out and "all passed" not in out
    assert 'type="nothing_judged"' in junit.read_text()
