"""The results schema: counters are integers, timings are not counters, one ranking of outcomes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import impls
from impls.plugins import plugins_registered
from vorobench.core import counters
from vorobench.harness import results
from vorobench.harness.runner import Case, RunConfig, run_case
from vorobench.judge import engine as crossval
from vorobench.judge import outcomes as schema

DOUBLES = str(Path(__file__).resolve().parents[1] / "support" / "doubles.py")


@pytest.mark.parametrize("stats", [{"events": 3}, {"flag": True}, {"n": np.int64(7)}, {"x": 4.0}, {}])
def test_integers_are_counters(stats):
    assert counters.check_counters(stats) == {k: int(v) for k, v in stats.items()}


@pytest.mark.parametrize("stats", [{"library_s": 0.01}, {"convert_s": 0}, {"elapsed": 3}, {"ratio": 0.5},
                                   {"name": "fast"}, {"build_time": 2}, {"t_ms": 1}])
def test_times_and_non_integers_are_refused_as_counters(stats):
    with pytest.raises(counters.CounterError, match="counters"):
        counters.check_counters(stats)


def test_an_implementation_cannot_put_a_timing_into_its_counters():
    with plugins_registered([DOUBLES]):
        sites = np.random.default_rng(0).random((30, 2))
        with pytest.raises(counters.CounterError, match="build_seconds"):
            impls.get("timing_in_counters").run(sites, {})
        timings: dict = {}
        stats: dict = {}
        impls.get("timed_parts").run(sites, stats, timings=timings)
    assert stats["calls"] == 1 and set(timings) == {"library", "convert"}


def test_a_benchmark_case_puts_counters_and_timings_in_their_own_columns():
    config = RunConfig(repeat=2, check=False, plugins=(DOUBLES,))
    bad = run_case(Case("timing_in_counters", "uniform", 40), config)
    assert bad.status == "error" and "build_seconds" in bad.rows[0]["error"]
    good = run_case(Case("timed_parts", "uniform", 40), config)
    assert good.status == "ok" and len(good.rows) == 2
    for row in good.rows:
        assert row["time_library_s"] > 0 and row["time_convert_s"] == pytest.approx(1e-6)
        assert row["stat_calls"] == 1
    # each repeat keeps its own parts of the time
    assert good.rows[0]["time_library_s"] != good.rows[1]["time_library_s"]


def test_old_results_with_seconds_among_counters_are_read_as_timings(tmp_path):
    path = tmp_path / "old.csv"
    pd.DataFrame({"impl": ["geos"], "dataset": ["uniform"], "n": [10], "seed": [0], "status": ["ok"],
                  "time_s": [0.1], "stat_library_s": [0.05], "stat_convert_s": [0.04],
                  "stat_envelope_attempts": [1]}).to_csv(path, index=False)
    df = results.load_checked(path)
    assert {"time_library_s", "time_convert_s", "stat_envelope_attempts"} <= set(df.columns)
    assert schema.counter_columns(df.columns) == ["stat_envelope_attempts"]


def test_a_results_file_with_fractional_counters_is_refused(tmp_path):
    path = tmp_path / "bad.csv"
    pd.DataFrame({"impl": ["x", "x"], "dataset": ["uniform"] * 2, "n": [10, 10], "seed": [0, 0],
                  "status": ["ok", "ok"], "time_s": [0.1, 0.1], "stat_ratio": [2, 0.37]}).to_csv(path, index=False)
    with pytest.raises(ValueError, match=r"stat_ratio holds '0.37' on data row 2"):
        results.load_checked(path)


def test_one_ranking_of_verdicts_and_statuses():
    assert set(schema.VERDICT_RANK) == {v.value for v in schema.Verdict}
    assert set(results.STATUSES) == {s.value for s in schema.Status}
    # the judge's verdicts are the schema's, in the schema's order (best to worst)
    order = [v.value for v in schema.Verdict]
    assert list(crossval.VERDICTS) == sorted(crossval.VERDICTS, key=order.index)
    ranked = [schema.verdict_rank(v) for v in crossval.VERDICTS if schema.verdict_rank(v) is not None]
    assert ranked == sorted(ranked)
    assert schema.verdict_rank("exact") == 0 < schema.verdict_rank("differs") < schema.verdict_rank("crashed")
    assert schema.verdict_rank("something new") == schema.verdict_rank("check_error")
    assert schema.status_rank("ok") == 0 < schema.status_rank("crashed")
