"""vorobench fuzz against implementations that hang or fail on every case: a hanging
implementation costs one timeout per run (not one per case, nor one per shrinking step), and a
duration budget bounds the whole run, shrinking and witnesses included."""

from __future__ import annotations

import json
import time
from pathlib import Path

import pytest

import datasets_gen
import impls
from vorobench.cli import main
from vorobench.harness import fuzz
from vorobench.harness.fuzz import SHRINK_PER_KIND, Budget, FuzzCase, check_fuzz_case, run_campaign
from vorobench.judge.engine import close_shared_judges

SUPPORT = Path(__file__).resolve().parent.parent / "support"
DOUBLES = str(SUPPORT / "doubles.py")
#: The reference (its JIT cache warmed below, so that a short --timeout only ever meets its builds warm).
REFERENCE = "halfplane"

SLEEPER = """\
import time

from vorobench.plugin import Implementation


def build(sites, stats=None):
    time.sleep(3600)


IMPLEMENTATIONS = [Implementation("sleeper", "never returns", "n/a", build, exact=False)]
"""


@pytest.fixture(autouse=True, scope="module")
def warm_reference():
    """Build with the reference here once: a cold JIT cache (after an edit of its source) is
    compiled and saved now, not inside a sandboxed build that has 3 seconds."""
    impls.build(REFERENCE, datasets_gen.generate("uniform", 12, seed=0))


def _sleeper(tmp_path: Path) -> Path:
    plugin = tmp_path / "sleeper.py"
    plugin.write_text(SLEEPER)
    return plugin


def _records(out: Path, kind: str) -> list[dict]:
    records = [json.loads(line) for line in (out / fuzz.LOG_NAME).read_text().splitlines()]
    return [r for r in records if r.get("kind") == kind]


def _fuzz_sleeper(plugin: Path, out: Path, budget: str, timeout: str) -> int:
    return main(["fuzz", "--plugin", str(plugin), "--impls", "sleeper", "--reference", REFERENCE, "--generators",
                 "uniform", "--budget", budget, "--min-n", "10", "--max-n", "12", "--timeout", timeout,
                 "--probes", "100", "--out", str(out)])


def test_a_hanging_implementation_costs_one_timeout_per_run(tmp_path):
    out = tmp_path / "campaign"
    assert _fuzz_sleeper(_sleeper(tmp_path), out, "3", "3") == 1
    first, *later = _records(out, "case")
    assert [(v["impl"], v["verdict"]) for v in first["results"]] == [(REFERENCE, "certified"), ("sleeper", "timeout")]
    # Not built again in this run: the later cases are judged without it, and say so.
    assert len(later) == 2
    assert all(r["skipped"] == ["sleeper"] and r["passed"] for r in later)
    assert all("sleeper" not in {v["impl"] for v in r["results"]} for r in later)
    # The timeout is written as found: no shrinking step, nor a second judging, pays the timeout again.
    (witness,) = _records(out, "witness")
    assert (witness["impl"], witness["verdict"], witness["shrunk"]) == ("sleeper", "timeout", False)
    assert witness["n_points"] == first["n_sites"]
    assert "timed out" in Path(witness["points"]).with_suffix(".txt").read_text()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["not_built_again"] == {"sleeper": f"uniform n={first['n']} seed={first['seed']}"}


def test_a_build_cut_short_by_the_budgets_end_is_no_finding(tmp_path):
    plugin = str(_sleeper(tmp_path))
    case = FuzzCase("uniform", 10, 1, ("sleeper",), REFERENCE, 100, (plugin,), timeout=120.0, deadline=time.time() + 4)
    started = time.monotonic()
    try:
        record = check_fuzz_case(case)
    finally:
        close_shared_judges()
    assert time.monotonic() - started < 60          # the 4 s left of the budget, not the 120 s timeout
    # Not a timeout of the implementation's: the case is not judged, and a rerun checks it again.
    assert (record["status"], record["passed"], record["results"]) == ("cut", False, [])
    assert "sleeper did not finish" in record["note"]


def test_a_duration_budget_bounds_a_campaign_with_a_hanging_implementation(tmp_path):
    out = tmp_path / "campaign"
    code = _fuzz_sleeper(_sleeper(tmp_path), out, "10s", "8")
    assert code == 1
    summary = json.loads((out / "summary.json").read_text())
    assert summary["failed"] + summary["cut"] >= 1          # the hang is reported either way
    # The campaign's own clock (not the queue, not start-up): the hang costs one timeout at most
    # beyond the budget, never one per case.
    assert summary["seconds"] <= 10 + 8 + 20, summary["seconds"]


def test_a_duration_budget_bounds_shrinking_of_many_failures(tmp_path):
    s = run_campaign(tmp_path, ["wrong"], ["uniform"], Budget(seconds=10), min_n=20, max_n=30, probes=100,
                     plugins=[DOUBLES], shrink_seconds=30)
    assert s.failed >= 1
    # That a step which could overrun the budget is not started is tested with a synthetic clock
    # (tests/judge/test_shrink.py); here, what the budget leaves: a witness for every failure.
    # Every failure has a witness; only the first few of each kind were shrunk.
    failing = {(r["generator"], r["n"], r["seed"]) for r in _records(tmp_path, "case") if not r["passed"]}
    assert {(w["generator"], w["n"], w["seed"]) for w in s.witnesses} == failing
    kinds: dict[tuple, int] = {}
    for w in s.witnesses:
        if w["shrunk"]:
            kinds[(w["impl"], w["peer"], w["verdict"])] = kinds.get((w["impl"], w["peer"], w["verdict"]), 0) + 1
    assert kinds and max(kinds.values()) <= SHRINK_PER_KIND
