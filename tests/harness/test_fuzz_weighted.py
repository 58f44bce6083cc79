"""`vorobench fuzz --weights`: every case is a power diagram, implementations without weights are
unsupported (which passes), the campaign log remembers the family, and a weights-ignoring
implementation is caught with a witness that keeps its weights."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import impls
from vorobench.cli import main
from vorobench.harness import fuzz
from vorobench.harness.fuzz import Budget, FuzzCase, run_campaign

SUPPORT = Path(__file__).resolve().parent.parent / "support"
DOUBLES = str(SUPPORT / "doubles.py")
REFERENCE = "qhull"


def _weighted_reference() -> None:
    if not impls.get(REFERENCE).weighted:
        pytest.skip(f"{REFERENCE} does not take weights yet")


def _records(folder: Path) -> list[dict]:
    return [json.loads(line) for line in (folder / fuzz.LOG_NAME).read_text().splitlines()]


def test_weighted_campaign_judges_power_diagrams_and_skips_unweighted(tmp_path):
    _weighted_reference()
    summary = run_campaign(tmp_path, [REFERENCE, "steady"], ["uniform", "int_box"], Budget(cases=4), max_n=15,
                           probes=100, plugins=[DOUBLES], weights="integer")
    assert (summary.checked, summary.failed, summary.lost, summary.errors) == (4, 0, 0, 0)
    records = _records(tmp_path)
    assert records[0]["kind"] == "setup" and records[0]["weights"] == "integer"
    cases = [r for r in records if r["kind"] == "case"]
    assert all(r["weights"] == "integer" and r["passed"] for r in cases)
    steady = [v for r in cases for v in r["results"] if v["impl"] == "steady"]
    assert len(steady) == 4 and all(v["verdict"] == "unsupported" for v in steady)
    assert all("does not take weights" in v["message"] for v in steady)
    # A log made with weights answers for that family only.
    with pytest.raises(ValueError, match="another setup"):
        run_campaign(tmp_path, [REFERENCE, "steady"], ["uniform", "int_box"], Budget(cases=4), max_n=15,
                     probes=100, plugins=[DOUBLES])


def test_a_weighted_case_draws_its_weights_from_its_seed():
    points, weights = FuzzCase("uniform", 12, 5, (REFERENCE,), REFERENCE, weights="radii").input()
    again = FuzzCase("uniform", 12, 5, (REFERENCE,), REFERENCE, weights="radii").input()
    assert weights.shape == (12,) and np.array_equal(weights, again[1]) and np.array_equal(points, again[0])
    assert FuzzCase("uniform", 12, 5, (REFERENCE,), REFERENCE).input()[1] is None


def test_a_weights_ignoring_implementation_is_caught_with_a_weighted_witness(tmp_path, capsys):
    _weighted_reference()
    plugin = tmp_path / "ignoring.py"
    plugin.write_text(
        "from impls.base import Implementation\n"
        "from impls.qhull import build\n\n"
        "def ignore(sites, weights, stats=None):\n"
        "    return build(sites, stats)\n\n"
        "IMPLEMENTATIONS = [Implementation('ignoring', 'ignores weights', 'n', build, exact=False,\n"
        "                                  build_weighted=ignore)]\n")
    out = tmp_path / "campaign"
    code = main(["fuzz", "--plugin", str(plugin), "--impls", "ignoring", "--weights", "hidden", "--generators",
                 "uniform", "--budget", "1", "--min-n", "25", "--max-n", "25", "--shrink-seconds", "10",
                 "--out", str(out)])
    assert code == 1
    summary = json.loads((out / "summary.json").read_text())
    assert summary["weights"] == "hidden" and summary["failed"] == 1
    (witness,) = summary["witnesses"]
    points = np.load(witness["points"])
    weights = np.load(witness["points"].replace(".npy", ".weights.npy"))
    assert weights.shape == (points.shape[0],) and 0 < points.shape[0] <= 25
    assert "--weights file:" in Path(witness["points"].replace(".npy", ".txt")).read_text().splitlines()[0]


def test_fuzz_refuses_a_reference_without_weights(tmp_path, capsys):
    code = main(["fuzz", "--plugin", DOUBLES, "--reference", "steady", "--weights", "radii", "--budget", "1",
                 "--out", str(tmp_path)])
    assert code == 2 and "reference steady does not take weights" in capsys.readouterr().err


def test_the_readmes_weighted_fuzz_passes(tmp_path, capsys):
    """The README's `vorobench fuzz --weights integer`, shrunk to its first 120 cases (they hold
    near_grid and tiny_spacing cases where Qhull only rounds: near-degenerate, a pass for a
    floating-point library, while the exact implementations agree exactly)."""
    from vorobench.cli import main

    code = main(["fuzz", "--budget", "120", "--weights", "integer", "--workers", "1", "--out", str(tmp_path / "fz")])
    summary = json.loads((tmp_path / "fz" / "summary.json").read_text())
    assert code == 0 and summary["passed"] and summary["checked"] == 120, summary
    cases = [json.loads(line) for line in (tmp_path / "fz" / "cases.jsonl").read_text().splitlines()]
    rounded = {case["generator"] for case in cases if case["kind"] == "case"
               for r in case["results"] if r["impl"] == "qhull" and r["peer"] is None and r["verdict"] == "within_tolerance"}
    assert {"near_grid", "tiny_spacing"} <= rounded, rounded
    pairs = [r for case in cases if case["kind"] == "case" for r in case["results"] if r["peer"] is not None]
    assert pairs and all(r["verdict"] == "exact" for r in pairs)       # exact ones against each other
    assert "with 1 local worker;" in capsys.readouterr().out          # says where it runs, plainly
