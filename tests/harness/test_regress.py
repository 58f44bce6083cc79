"""`vorobench compare`: flags a slowed implementation, counter changes and lost correctness;
passes two runs of the same code. Timing verdicts are judged on recorded timings, never on
real runs (whose times a busy machine moves): only the counters come from real benchmark runs."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from vorobench.cli import main
from vorobench.harness import regress, timing_rule
from vorobench.harness.results import ResultsFile

DOUBLES = str(Path(__file__).resolve().parents[1] / "support" / "doubles.py")


def _bench(out: Path, monkeypatch, counter_scale: int = 1) -> Path:
    # The `steady` double scales its counter: same name, other work done.
    monkeypatch.setenv("VOROBENCH_TEST_SLEEP", "0.001")
    monkeypatch.setenv("VOROBENCH_TEST_COUNTER_SCALE", str(counter_scale))
    code = main(["bench", "--min-time", "0", "--plugin", DOUBLES, "--impls", "steady", "--datasets", "uniform", "--sizes", "20",
                 "--repeat", "3", "--no-check", "--quiet", "--out", str(out)])
    assert code == 0
    return out


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """Two real runs of the same code, the second with changed counters."""
    mp = pytest.MonkeyPatch()
    folder = tmp_path_factory.mktemp("regress")
    try:
        return {"base": _bench(folder / "base.csv", mp), "counters": _bench(folder / "counters.csv", mp, 3)}
    finally:
        mp.undo()


def _recorded(path: Path, seconds: float, jitter_seed: int) -> str:
    """A recorded run of `steady` (as bench writes it): 5 repeats of about ``seconds`` each,
    scattered by 1 %."""
    jitter = 1 + 0.01 * np.random.default_rng(jitter_seed).standard_normal(5)
    ResultsFile(path).append([{"run_id": f"r{jitter_seed}", "impl": "steady", "dataset": "uniform", "n": 20, "seed": 0,
                               "repeat": i, "status": "ok", "verdict": "exact", "time_s": float(seconds * j),
                               "stat_sites_seen": 20} for i, j in enumerate(jitter)])
    return str(path)


def test_two_runs_of_the_same_code_pass(tmp_path, capsys):
    base, same = _recorded(tmp_path / "base.csv", 0.05, 1), _recorded(tmp_path / "same.csv", 0.05, 2)
    assert main(["compare", base, same]) == 0
    assert "no regression in 1 compared case(s)" in capsys.readouterr().out


def test_slowed_implementation_is_flagged(capsys, tmp_path):
    base, slow = _recorded(tmp_path / "base.csv", 0.05, 1), _recorded(tmp_path / "slow.csv", 0.10, 2)
    report = tmp_path / "cmp.json"
    assert main(["compare", base, slow, "--json", str(report)]) == 1
    out = capsys.readouterr().out
    assert "slower" in out and "1 of 1 compared case(s) flagged" in out
    change = regress.compare_files(base, slow)[0]
    assert change.ratio > 1.5 and change.ci_low > 1.1 and change.p_value < 0.05
    assert not change.counters                    # the code got slower, it did not do more work
    assert '"flagged": true' in report.read_text()


def test_changed_counters_are_flagged_whatever_the_times(runs):
    change = regress.compare_files(runs["base"], runs["counters"])[0]
    assert change.counters == {"sites_seen": (20, 60)}
    assert any("counters changed" in f for f in change.flags)


# ------------------------------------------------------------------ without worker processes

def _frame(impl_times: dict, verdict="exact", status="ok", stats=None) -> pd.DataFrame:
    rows = []
    for impl, times in impl_times.items():
        for i, t in enumerate(times):
            row = {"impl": impl, "dataset": "uniform", "n": 100, "seed": 0, "repeat": i, "status": status,
                   "verdict": verdict, "time_s": t}
            row.update(stats or {})
            rows.append(row)
    return pd.DataFrame(rows)


def test_noise_inside_the_threshold_is_not_flagged():
    rng = np.random.default_rng(1)
    base = _frame({"a": 1.0 + 0.02 * rng.standard_normal(9)})
    new = _frame({"a": 1.05 + 0.02 * rng.standard_normal(9)})     # 5 % slower: under 10 %
    (change,) = regress.compare_frames(base, new)
    assert change.change == "same" and not change.flagged
    (change,) = regress.compare_frames(base, new, threshold=0.02)
    assert change.change == "slower" and change.flagged


def test_a_large_but_unclear_change_is_not_flagged():
    base = _frame({"a": [1.0, 1.0, 3.0, 1.0, 3.0]})
    new = _frame({"a": [1.0, 3.0, 3.0, 1.0, 3.0]})    # median 1 -> 3, but the samples overlap entirely
    (change,) = regress.compare_frames(base, new)
    assert change.ratio == pytest.approx(3.0)
    assert not change.flagged


def test_correctness_and_status_regressions_are_flagged():
    base = _frame({"a": [1.0, 1.0]}, verdict="exact")
    (worse,) = regress.compare_frames(base, _frame({"a": [1.0, 1.0]}, verdict="differs"))
    assert worse.flags == ["verdict exact -> differs"]
    (same,) = regress.compare_frames(base, _frame({"a": [1.0, 1.0]}, verdict="exact"))
    assert not same.flagged
    crashed = _frame({"a": [np.nan]}, verdict="crashed", status="crashed")
    (gone,) = regress.compare_frames(base, crashed)
    assert "status ok -> crashed" in gone.flags


def test_bootstrap_interval_is_seeded_and_brackets_the_ratio():
    rng = np.random.default_rng(3)
    base, new = 1.0 + 0.05 * rng.random(20), 2.0 + 0.1 * rng.random(20)
    a = timing_rule.bootstrap_ratio_ci(base, new, np.random.default_rng(0))
    b = timing_rule.bootstrap_ratio_ci(base, new, np.random.default_rng(0))
    assert a == b
    assert a[0] < np.median(new) / np.median(base) < a[1]
    assert 1.8 < a[0] and a[1] < 2.2


def test_cases_lost_by_new_are_flagged_new_cases_are_not():
    base = _frame({"a": [1.0, 1.0]})
    new = _frame({"b": [1.0, 1.0]})
    changes = regress.compare_frames(base, new)
    assert [(c.impl, c.base_status, c.new_status) for c in changes] == [("a", "ok", None), ("b", None, "ok")]
    assert [c.flags for c in changes] == [["missing in NEW"], []]
