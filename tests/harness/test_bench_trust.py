"""``bench`` judges every timed repeat, in the judge's process, on inputs a cache cannot key:
the faults of ``tests/support/hostile/bench_faults.py`` end as failures or honest timings, and
the plugin is never imported where the verdicts are decided."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[2]
FAULTS = ROOT / "tests" / "support" / "hostile" / "bench_faults.py"


@pytest.fixture(scope="module")
def benched(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("bench-trust")
    out, log = tmp / "run.csv", tmp / "imports.log"
    proc = subprocess.Popen([sys.executable, "-m", "vorobench", "bench", "--plugin", str(FAULTS), "--impls",
                             "fortune,late_right,check_patcher,input_cache", "--datasets", "uniform", "--sizes", "30",
                             "--repeat", "5", "--min-time", "0", "--timeout", "30", "--quiet", "--out", str(out)],
                            cwd=ROOT, env={**os.environ, "VOROBENCH_TEST_IMPORT_LOG": str(log)},
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        stdout, stderr = proc.communicate(timeout=300)
    finally:
        proc.kill()
    assert proc.returncode == 0, stdout + stderr
    imports = log.read_text().splitlines() if log.exists() else []
    return pd.read_csv(out), proc.pid, imports


def _rows(df: pd.DataFrame, impl: str) -> pd.DataFrame:
    return df[df["impl"] == impl].sort_values("repeat")


def test_a_build_wrong_on_all_but_its_last_repeat_fails_on_those_repeats(benched):
    rows = _rows(benched[0], "late_right")
    assert list(rows["verdict"])[:4] == ["not_certified"] * 4, rows[["repeat", "verdict"]]
    assert not rows["check_passed"].iloc[:4].any()


def test_judging_code_replaced_in_the_implementations_process_changes_nothing(benched):
    rows = _rows(benched[0], "check_patcher")
    assert (rows["verdict"] == "not_certified").all() and not rows["check_passed"].any()


def test_a_cache_keyed_by_the_input_cannot_fake_a_timing(benched):
    rows = _rows(benched[0], "input_cache")
    # every repeat gets other bytes: each pays the 0.2 s build (a sleep: a lower bound on any machine)
    assert (rows["time_s"] >= 0.19).all(), rows[["repeat", "time_s", "input_scale_log2"]]
    assert rows["input_scale_log2"].nunique() == 5


def test_honest_rows_pass_on_every_repeat(benched):
    rows = _rows(benched[0], "fortune")
    assert (rows["verdict"] == "exact").all() and rows["check_passed"].all()


def test_the_plugin_is_imported_only_in_sandboxes(benched):
    _, pid, imports = benched
    pids = {int(line.split()[1]) for line in imports}
    assert pids and pid not in pids
