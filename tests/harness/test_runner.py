"""The benchmark runner: a worker per case survives crashes, hangs and MemoryError; resume; Ctrl-C."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from vorobench.cli import main
from vorobench.harness import runner
from vorobench.harness.runner import Case, CaseOutcome, RunConfig

DOUBLES = str(Path(__file__).resolve().parents[1] / "support" / "doubles.py")
ROOT = Path(__file__).resolve().parents[2]


def _bench(out: Path, impls: str, *extra: str) -> int:
    return main(["bench", "--min-time", "0", "--plugin", DOUBLES, "--impls", impls, "--datasets", "uniform", "--quiet",
                 "--out", str(out), *extra])


@pytest.fixture(scope="module")
def faulty_run(tmp_path_factory) -> pd.DataFrame:
    """One run mixing healthy implementations with every kind of failure."""
    out = tmp_path_factory.mktemp("faulty") / "results.csv"
    impls = "qhull,crash_exit,crash_segfault,hang_after_warmup,hog,fail,refuse,steady,hungry"
    code = _bench(out, impls, "--sizes", "80", "--repeat", "2", "--timeout", "2", "--no-check")
    assert code == 0
    return pd.read_csv(out)


def _rows(df: pd.DataFrame, impl: str) -> pd.DataFrame:
    return df[df["impl"] == impl]


def test_every_case_is_recorded_and_healthy_rows_kept(faulty_run):
    assert set(faulty_run["impl"]) == {"qhull", "crash_exit", "crash_segfault", "hang_after_warmup", "hog",
                                       "fail", "refuse", "steady", "hungry"}
    for healthy in ("qhull", "steady", "hungry"):
        rows = _rows(faulty_run, healthy)
        assert list(rows["status"]) == ["ok", "ok"]
        assert sorted(rows["repeat"]) == [0, 1]
        assert (rows["time_s"] > 0).all()
        assert (rows["warmup_s"] > 0).all()
        assert (rows["n_sites"] == 80).all()
        assert (rows["V"] > 0).all() and (rows["E"] > 0).all()
        assert (rows["case_s"] > rows["time_s"].sum() + rows["warmup_s"]).all()   # the whole case, start-up included


def test_hard_crashes_are_recorded(faulty_run):
    exit_row = _rows(faulty_run, "crash_exit").iloc[0]
    assert exit_row["status"] == "crashed"
    assert "status 3" in exit_row["error"]
    segv = _rows(faulty_run, "crash_segfault").iloc[0]
    assert segv["status"] == "crashed"
    assert "SIGSEGV" in segv["error"]
    assert len(_rows(faulty_run, "crash_exit")) == 1 and pd.isna(exit_row["time_s"])


def test_hang_past_timeout_is_recorded_with_its_step(faulty_run):
    row = _rows(faulty_run, "hang_after_warmup").iloc[0]
    assert row["status"] == "timeout"
    assert row["phase"].startswith("repeat 1")
    assert row["warmup_s"] > 0               # the warm-up finished before the timed build hung


def test_memory_error_exception_and_refusal(faulty_run):
    assert _rows(faulty_run, "hog").iloc[0]["status"] == "oom"
    fail = _rows(faulty_run, "fail").iloc[0]
    assert fail["status"] == "error" and "deliberate failure" in fail["error"]
    refuse = _rows(faulty_run, "refuse").iloc[0]
    assert refuse["status"] == "unsupported" and "refuses" in refuse["error"]


def test_counters_and_peak_memory_are_measured(faulty_run):
    from doubles import HUNGRY_MB

    steady = _rows(faulty_run, "steady")
    assert (steady["stat_sites_seen"] == 80).all()
    hungry = _rows(faulty_run, "hungry")
    assert (hungry["mem_mb"] > 0.8 * HUNGRY_MB).all()
    assert (_rows(faulty_run, "qhull")["mem_mb"] < 0.5 * HUNGRY_MB).all()


def test_check_gives_a_verdict_against_the_reference(tmp_path):
    out = tmp_path / "r.csv"
    assert _bench(out, "qhull,steady,wrong", "--sizes", "60", "--repeat", "1", "--timeout", "60") == 0
    df = pd.read_csv(out)
    # The reference's own row is judged on its certificate; steady returns Qhull's own diagram,
    # so it must certify and agree with the reference exactly; wrong's diagram belongs to other sites.
    assert list(df["impl"]) == ["steady", "wrong", "qhull"]          # the reference runs last
    assert list(df["verdict"]) == ["exact", "not_certified", "certified"], df["verdict_detail"].tolist()
    # steady hands back Qhull's diagram: certified (uniform: no near-degenerate rounding); wrong's not
    assert list(df["certificate"]) == ["certified", "not_certified", "certified"]
    assert df["check_passed"].tolist() == [True, False, True]
    assert df["blame"].fillna("").tolist() == ["", "impl", ""]
    assert (df["check_s"] > 0).all()


def test_resume_skips_finished_cases(tmp_path):
    out = tmp_path / "r.csv"
    assert _bench(out, "qhull", "--sizes", "30", "--repeat", "1", "--no-check") == 0
    # Without --resume (or --overwrite) an existing file is not touched.
    assert _bench(out, "qhull", "--sizes", "30,40", "--repeat", "1", "--no-check") == 2
    assert _bench(out, "qhull", "--sizes", "30,40", "--repeat", "1", "--no-check", "--resume") == 0
    df = pd.read_csv(out)
    assert sorted(df["n"]) == [30, 40]
    assert df["run_id"].nunique() <= 2
    from vorobench.harness.results import read_metadata

    assert [r["cases_to_run"] for r in read_metadata(out)["runs"]] == [1, 1]


def test_skip_after_timeout_and_budget_extrapolation():
    history = {("a", "uniform", 0): [(1000, "timeout", None)],
               ("b", "uniform", 0): [(1000, "ok", 0.01), (2000, "ok", 0.04)]}
    cfg = RunConfig(budget=1.0)
    assert "timeout" in runner._skip_reason(Case("a", "uniform", 4000), history, cfg)
    # b grows like n^2 (0.01 -> 0.04 for doubling): n = 8000 -> 0.64 s, n = 16000 -> 2.56 s.
    assert runner._skip_reason(Case("b", "uniform", 8000), history, cfg) is None
    reason = runner._skip_reason(Case("b", "uniform", 16000), history, cfg)
    assert reason is not None and "2.56" in reason
    assert runner._skip_reason(Case("b", "uniform", 16000), history, RunConfig()) is None


def test_interrupt_keeps_finished_cases(tmp_path, monkeypatch):
    from vorobench.cli import bench as bench_cmd

    calls = []

    def fake_run_case(case, config, on_step=None):
        if calls:
            raise KeyboardInterrupt
        calls.append(case)
        row = {"run_id": config.run_id, "impl": case.impl, "dataset": case.dataset, "n": case.n,
               "seed": case.seed, "repeat": 0, "status": "ok", "time_s": 0.5}
        return CaseOutcome(case, "ok", [row], 0.5)

    monkeypatch.setattr(runner, "run_case", fake_run_case)
    out = tmp_path / "r.csv"
    code, _ = bench_cmd.execute(["qhull"], ["uniform"], [10, 20, 30], [0], out,
                                RunConfig(repeat=1, check=False), progress=False, verbose=False)
    assert code == 130
    df = pd.read_csv(out)
    assert list(df["n"]) == [10] and list(df["time_s"]) == [0.5]


@pytest.mark.usefixtures("sigint_reaches_children")
def test_ctrl_c_in_a_real_run_loses_nothing_finished(tmp_path):
    out = tmp_path / "r.csv"
    cmd = [sys.executable, "-m", "vorobench", "bench", "--min-time", "0", "--plugin", DOUBLES, "--impls", "qhull,hang",
           "--sizes", "50", "--repeat", "1", "--no-check", "--quiet", "--timeout", "120",
           "--warmup-timeout", "120", "--out", str(out)]
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and not (out.exists() and "qhull" in out.read_text()):
            time.sleep(0.2)
        assert out.exists(), "the first case never finished"
        time.sleep(0.5)                       # the hanging case is running now
        os.kill(proc.pid, signal.SIGINT)
        _, err = proc.communicate(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130, err
    assert "--resume" in err
    df = pd.read_csv(out)
    assert list(df["impl"]) == ["qhull"] and list(df["status"]) == ["ok"]


def test_spawned_worker_also_isolates_a_hard_crash():
    config = RunConfig(repeat=1, check=False, plugins=(DOUBLES,), start_method="spawn")
    crash = runner.run_case(Case("crash_exit", "uniform", 20), config)
    assert crash.status == "crashed" and "status 3" in crash.error
    healthy = runner.run_case(Case("steady", "uniform", 20), config)
    assert healthy.status == "ok" and healthy.rows[0]["time_s"] > 0


def test_test_doubles_do_not_outlive_the_run(faulty_run):
    import impls

    # Other tests iterate impls.available(): a crashing double left registered would kill them.
    assert not {"crash_exit", "hang", "hog", "steady"} & set(impls.available())


def test_short_builds_are_repeated_to_fill_min_time():
    """Builds of ~0.02 s are repeated until 0.15 s are timed: judged on the times the run
    recorded, so a busy machine (slower builds, fewer repeats) keeps the rule, not a count."""
    config = RunConfig(repeat=2, min_time=0.15, check=False, plugins=(DOUBLES,))
    outcome = runner.run_case(Case("steady", "uniform", 20), config)    # ~0.02 s per build
    assert outcome.status == "ok"
    times = [r["time_s"] for r in outcome.rows]
    assert len(times) >= config.repeat
    if len(times) > config.repeat:
        assert sum(times[:-1]) < config.min_time                        # the last build was still needed
    assert sum(times) >= config.min_time or len(times) == runner.MAX_REPEAT      # and then no more
    assert [r["repeat"] for r in outcome.rows] == list(range(len(outcome.rows)))


def test_the_reference_runs_wherever_another_implementation_ran():
    history = {("qhull", "uniform", 0): [(1000, "ok", 1.0), (2000, "ok", 4.0)],
               ("other", "uniform", 0): [(1000, "ok", 1.0), (2000, "ok", 4.0)],
               ("fast", "uniform", 0): [(1000, "ok", 0.1), (2000, "ok", 0.2), (4000, "ok", 0.4)]}
    cfg = RunConfig(budget=1.0, reference="qhull")
    assert runner._skip_reason(Case("other", "uniform", 4000), history, cfg) is not None
    assert runner._skip_reason(Case("qhull", "uniform", 4000), history, cfg) is None      # fast needs it
    assert runner._skip_reason(Case("qhull", "uniform", 8000), history, cfg) is not None  # nobody does


def test_plan_puts_the_reference_last_and_drops_sizes_that_repeat_an_input():
    import datasets_gen

    cap = datasets_gen.actual_n("cocircular", 10**9)          # the most points one circle holds
    cases = runner.plan_cases(["qhull", "a", "b"], ["uniform", "cocircular"], [100, cap, 2 * cap], [0],
                              reference="qhull")
    assert [c.impl for c in cases[:3]] == ["a", "b", "qhull"]
    cocircular = sorted({c.n for c in cases if c.dataset == "cocircular"})
    assert cocircular == [100, cap]                            # 2 * cap gives the same points as cap
    assert sorted({c.n for c in cases if c.dataset == "uniform"}) == [100, cap, 2 * cap]


def test_memory_limit_turns_a_large_allocation_into_oom(tmp_path):
    out = tmp_path / "r.csv"
    assert _bench(out, "hungry", "--sizes", "50", "--repeat", "1", "--no-check", "--memory-limit", "100") == 0
    row = pd.read_csv(out).iloc[0]
    assert row["status"] == "oom" and "MemoryError" in row["error"]


def test_one_size_is_extrapolated_with_the_declared_complexity():
    """From one size nothing is measured about growth: an O(n^2) method is extrapolated as n^2
    (0.1 s at n=1000 -> 10 s at 10,000), not as n (1 s); an unreadable declaration says it assumed n."""
    from vorobench.judge.declarations import Declaration

    def declared(complexity):
        return (("quad", Declaration("quad", True, False, complexity, "python", "", "")),)

    history = {("quad", "uniform", 0): [(1000, "ok", 0.1)]}
    reason = runner._skip_reason(Case("quad", "uniform", 10_000), history,
                                 RunConfig(budget=5.0, declarations=declared("O(n^2)")))
    assert reason is not None and "declared O(n^2) exponent 2.00" in reason and "10 s" in reason
    reason = runner._skip_reason(Case("quad", "uniform", 10_000), history,
                                 RunConfig(budget=0.5, declarations=declared("fast")))
    assert reason is not None and "assumed exponent 1.00" in reason
