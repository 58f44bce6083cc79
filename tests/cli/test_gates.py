"""The gates cannot be fooled: every fault of an implementation is its own verdict, the run and
the summary survive it, and nothing outlives a run.

Fault doubles (``doubles.py``) segfault, exit with status 0 or 3, raise ``SystemExit(0)``, hang,
exhaust memory, change their input, or hang in a grandchild process. Commands whose own process
a fault could kill or hang run as subprocesses with a time limit, so a regression fails these
tests instead of taking pytest down.
"""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from processes import alive

import datasets_gen
import impls
from impls.base import InputMutated, UnsupportedInput
from impls.plugins import plugins_registered
from vorobench.cli import main
from vorobench.judge.engine import Judge

HERE = Path(__file__).parent
SUPPORT = HERE.parent / "support"
DOUBLES = str(SUPPORT / "doubles.py")
ROOT = HERE.parent.parent

#: Each fault double and the verdict it must get, on its own row only.
FAULTS = {
    "crash_segfault": "crashed",
    "crash_exit": "crashed",
    "exit_zero": "crashed",
    "system_exit": "crashed",
    "hang": "timeout",
    "hog": "oom",
    "mutate": "mutated_input",
    "other_sites": "wrong_sites",
    "booby_trapped": "crashed",
    "kill_group": "crashed",
}


def _vorobench(*args: str, timeout: float = 240, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "vorobench", *args], cwd=ROOT, capture_output=True, text=True,
                          timeout=timeout, env={**os.environ, **(env or {})})


def test_validate_fails_with_a_summary_naming_every_fault_and_only_them(tmp_path):
    # One run with every fault double: each gets its own verdict and blame, none harms the run,
    # the reference or another double's row (one CLI run, not one per fault: each costs seconds).
    run = _vorobench("validate", "--plugin", DOUBLES, "--impls", ",".join(["fortune", *FAULTS]), "--datasets",
                     "uniform", "--sizes", "10", "--timeout", "10", "--no-shrink", "--out", str(tmp_path))
    assert run.returncode == 1, run.stdout + run.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["passed"] is False and summary["complete"] is True
    assert sorted(summary["failed_impls"]) == sorted(FAULTS)
    rows = {(r["impl"], r["exact_peer"]): r for r in summary["results"]}
    assert rows[("fortune", None)]["verdict"] == "exact" and rows[("fortune", None)]["passed"]
    assert rows[("qhull", None)]["passed"]
    for fault, verdict in FAULTS.items():
        assert rows[(fault, None)]["verdict"] == verdict and not rows[(fault, None)]["passed"], fault
        assert rows[(fault, None)]["blame"] == "impl", fault


def test_judge_keeps_every_fault_to_its_own_row():
    names = ["fortune", "incremental", *FAULTS, "wrong", "refuse"]
    with plugins_registered([DOUBLES]):
        with Judge(names, timeout=5, plugins=[DOUBLES]) as judge:
            judged = judge.judge(datasets_gen.generate("uniform", 30, seed=2))
            again = judge.judge(datasets_gen.generate("grid", 25))     # sandboxes restart after faults
    for case in (judged, again):
        verdicts = {(name, peer): v for name, v, peer in case.rows}
        assert verdicts[("fortune", None)].verdict == "exact"
        assert verdicts[("incremental", "fortune")].verdict == "exact"
        for fault, expected in FAULTS.items():
            assert verdicts[(fault, None)].verdict == expected, verdicts[(fault, None)].message
        assert verdicts[("wrong", None)].verdict == "not_certified"
        assert verdicts[("refuse", None)].verdict == "unsupported" and verdicts[("refuse", None)].passed
        assert not case.passed


def test_a_diagram_of_other_sites_fails_where_qhull_is_only_within_tolerance(tmp_path):
    # near_grid n=1000: qhull certifies within tolerance only, which once excused any difference.
    run = _vorobench("validate", "--plugin", DOUBLES, "--impls", "other_sites", "--datasets", "near_grid",
                     "--sizes", "1000", "--no-shrink", "--out", str(tmp_path))
    assert run.returncode == 1, run.stdout + run.stderr
    rows = {r["impl"]: r for r in json.loads((tmp_path / "summary.json").read_text())["results"]}
    assert rows["other_sites"]["verdict"] == "wrong_sites" and not rows["other_sites"]["passed"]


@pytest.mark.parametrize("scale", [1.0, 2.0**-1060, 1e-200, 1e300])
def test_a_diagram_of_other_sites_is_caught_at_every_scale(scale):
    from vorobench.judge.engine import build_and_certify

    with plugins_registered([DOUBLES]):
        res = build_and_certify("other_sites", datasets_gen.generate("grid", 36) * scale)
    assert res.failure == "wrong_sites" and "moved" in res.error and res.diagram is None


def test_an_implementation_that_supports_nothing_is_no_pass(tmp_path):
    run = _vorobench("validate", "--plugin", DOUBLES, "--impls", "refuse", "--datasets", "uniform",
                     "--sizes", "10", "--no-shrink", "--out", str(tmp_path))
    assert run.returncode == 1, run.stdout + run.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["never_judged"] == ["refuse"] and summary["passed"] is False


def test_a_child_left_by_a_dead_sandbox_is_killed(tmp_path, monkeypatch):
    pidfile = tmp_path / "pid"
    monkeypatch.setenv("VOROBENCH_TEST_PIDFILE", str(pidfile))
    with plugins_registered([DOUBLES]):
        with Judge(["fork_and_die"], timeout=20, plugins=[DOUBLES]) as judge:
            res = judge.build("fork_and_die", datasets_gen.generate("uniform", 10))
            assert res.failure == "crashed" and "status 3" in res.error
            child = int(pidfile.read_text())
            assert not _wait_gone([child], 10), "the sandbox's child outlived it"


def test_validate_on_two_workers_blames_the_segfault_alone(tmp_path):
    run = _vorobench("validate", "--plugin", DOUBLES, "--impls", "fortune,crash_segfault", "--datasets",
                     "uniform,grid", "--sizes", "10", "--workers", "2", "--no-shrink", "--out", str(tmp_path))
    assert run.returncode == 1, run.stdout + run.stderr
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["judged"] == summary["cases"] == 2 and summary["lost"] == 0
    for r in summary["results"]:
        assert r["passed"] == (r["impl"] != "crash_segfault"), r
    assert sorted(r["verdict"] for r in summary["results"] if r["impl"] == "crash_segfault") == ["crashed"] * 2


def test_fuzz_finishes_on_a_hanging_implementation(tmp_path):
    run = _vorobench("fuzz", "--plugin", DOUBLES, "--impls", "fortune,hang", "--generators", "uniform",
                     "--budget", "2", "--max-n", "12", "--timeout", "3", "--no-shrink", "--out", str(tmp_path),
                     timeout=180)
    assert run.returncode == 1, run.stdout + run.stderr
    records = [json.loads(line) for line in (tmp_path / "cases.jsonl").read_text().splitlines()]
    records = [r for r in records if r["kind"] == "case"]
    assert len(records) == 2
    # The hang costs one timeout: later cases of the run do not build it again, and say so.
    first, *later = records
    verdicts = {v["impl"]: v["verdict"] for v in first["results"] if v["peer"] is None}
    assert verdicts["hang"] == "timeout" and verdicts["fortune"] == "exact"
    for record in later:
        verdicts = {v["impl"]: v["verdict"] for v in record["results"] if v["peer"] is None}
        assert "hang" in record["skipped"] and verdicts["fortune"] == "exact"


def test_fuzz_gate_covers_earlier_runs_and_refuses_another_setup(tmp_path, capsys):
    argv = ["fuzz", "--plugin", DOUBLES, "--impls", "other_sites", "--generators", "uniform", "--budget", "2",
            "--max-n", "10", "--no-shrink", "--out", str(tmp_path)]
    assert main(argv) == 1
    assert main(argv) == 1                      # nothing new checked, but the campaign has failures
    assert json.loads((tmp_path / "summary.json").read_text())["passed"] is False
    capsys.readouterr()
    assert main([*argv[:4], "fortune", *argv[5:]]) == 2      # another implementation: not this log
    assert "another setup" in capsys.readouterr().err


# ------------------------------------------------------------------------ inputs are read-only

def test_build_refuses_a_mutated_input_and_keeps_the_callers_array():
    points = datasets_gen.generate("uniform", 20)
    before = points.copy()
    with plugins_registered([DOUBLES]):
        with pytest.raises(InputMutated, match="changed the sites"):
            impls.build("mutate", points)
    assert np.array_equal(points, before)


def test_bench_records_a_mutating_implementation_as_a_failure(tmp_path):
    out = tmp_path / "r.csv"
    code = main(["bench", "--min-time", "0", "--plugin", DOUBLES, "--impls", "mutate,fortune", "--sizes", "50", "--repeat", "2",
                 "--out", str(out), "--quiet"])
    assert code == 0
    import pandas as pd

    df = pd.read_csv(out)
    mutate = df[df.impl == "mutate"]
    assert list(mutate.verdict) == ["mutated_input"] and mutate.time_s.isna().all()
    assert set(df[df.impl == "fortune"].verdict) == {"exact"}


# ------------------------------------------------------------------------------- supports()

def test_impls_build_honours_supports():
    near_grid = datasets_gen.generate("near_grid", 1000)
    if "boost" in impls.available():
        with pytest.raises(UnsupportedInput, match="boost does not support"):
            impls.build("boost", near_grid)
    with plugins_registered([DOUBLES]):
        with pytest.raises(ValueError, match="refuses every input"):
            impls.build("refuse", near_grid)


def test_build_command_refuses_unsupported_input(capsys):
    code = main(["build", "--plugin", DOUBLES, "--impl", "refuse", "--n", "20"])
    err = capsys.readouterr().err
    assert code == 2 and "refuses every input" in err and len(err.strip().splitlines()) == 1


def test_build_command_survives_a_segfault(capsys):
    code = main(["build", "--plugin", DOUBLES, "--impl", "crash_segfault", "--n", "20"])
    err = capsys.readouterr().err
    assert code == 1 and "SIGSEGV" in err


# ------------------------------------------------------------------------- clean shutdown

_alive = alive


def _wait_gone(pids, seconds: float) -> list[int]:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        alive = [p for p in pids if _alive(p)]
        if not alive:
            return []
        time.sleep(0.2)
    return [p for p in pids if _alive(p)]


@pytest.mark.usefixtures("sigint_reaches_children")
@pytest.mark.parametrize("command,sig", [("bench", signal.SIGTERM), ("bench", signal.SIGKILL),
                                         ("validate", signal.SIGKILL), ("validate", signal.SIGINT)])
def test_no_worker_or_grandchild_outlives_the_run(command, sig, tmp_path):
    pidfile = tmp_path / "pids"
    out = ["--out", str(tmp_path / "r.csv")] if command == "bench" else ["--out", str(tmp_path), "--no-shrink"]
    proc = subprocess.Popen([sys.executable, "-m", "vorobench", command, "--plugin", DOUBLES, "--impls",
                             "hang_with_grandchild", "--datasets", "uniform", "--sizes", "100", "--timeout", "600",
                             *out], cwd=ROOT, env={**os.environ, "VOROBENCH_TEST_PIDFILE": str(pidfile)},
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        while not pidfile.exists() and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.2)
        assert pidfile.exists(), "the double never started"
        pids = [int(p) for p in pidfile.read_text().split()]
        assert all(_alive(p) for p in pids)
        proc.send_signal(sig)
        proc.wait(timeout=60)
        assert not _wait_gone(pids, 15), "a worker or its child outlived the run"
    finally:
        if proc.poll() is None:
            proc.kill()
    if command == "validate":      # a run that did not finish never leaves a passing summary
        summary = json.loads((tmp_path / "summary.json").read_text())
        assert summary["passed"] is False


# --------------------------------------------------------------------------- executors

def test_dask_to_a_closed_port_fails_fast_in_one_line(tmp_path):
    pytest.importorskip("distributed")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]                  # closed again when the block ends
    t0 = time.monotonic()
    run = _vorobench("validate", "--impls", "qhull", "--datasets", "uniform", "--sizes", "10", "--executor",
                     f"dask://127.0.0.1:{port}", "--out", str(tmp_path), timeout=60)
    assert run.returncode == 2 and time.monotonic() - t0 < 30
    assert "Traceback" not in run.stderr and len(run.stderr.strip().splitlines()) == 1, run.stderr
    assert "refused" in run.stderr, run.stderr      # said at once, not after the connect timeout


def test_dask_to_a_port_that_never_answers_fails_within_seconds(tmp_path):
    pytest.importorskip("distributed")
    with socket.socket() as silent:
        silent.bind(("127.0.0.1", 0))
        silent.listen(8)                            # accepts connections, never says a word
        t0 = time.monotonic()
        run = _vorobench("fuzz", "--impls", "qhull", "--budget", "1", "--executor",
                         f"dask://127.0.0.1:{silent.getsockname()[1]}", "--out", str(tmp_path), timeout=90)
    assert run.returncode == 2 and time.monotonic() - t0 < 45, run.stderr
    assert "Traceback" not in run.stderr and len(run.stderr.strip().splitlines()) == 1, run.stderr


# ------------------------------------------------------------------------- CLI arguments

BAD_ARGUMENTS = [
    ["bench", "--sizes", "inf"],
    ["bench", "--sizes", "nan"],
    ["build", "--n", "1e12"],
    ["validate", "--sizes", "1e12"],
    ["bench", "--timeout", "nan"],
    ["bench", "--timeout", "-1"],
    ["bench", "--memory-limit", "-5"],
    ["bench", "--repeat", "0"],
    ["bench", "--min-time", "inf"],
    ["bench", "--workers", "0"],
    ["bench", "--seeds", "-1"],
    ["validate", "--probes", "-1"],
    ["validate", "--timeout", "0"],
    ["validate", "--memory-limit", "-1"],
    ["validate", "--workers", "two"],
    ["fuzz", "--budget", "nans"],
    ["fuzz", "--probes", "-3"],
    ["fuzz", "--timeout", "inf"],
    ["demo", "--sizes", "1e12"],
    ["build", "--impl", "no_such_impl", "--n", "10"],
    ["validate", "--impls", "no_such_impl"],
    ["validate", "--executor", "carrier-pigeon://x"],
]


@pytest.mark.parametrize("argv", BAD_ARGUMENTS, ids=lambda a: " ".join(a))
def test_bad_arguments_get_one_line_and_exit_2(argv, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    err = capsys.readouterr().err
    assert code == 2, err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err


@pytest.mark.parametrize("source", ["raise RuntimeError('boom')", "def broken(:", "IMPLEMENTATIONS = [1]",
                                    "X = 1"])
def test_a_plugin_that_cannot_load_is_one_line(source, tmp_path, capsys):
    plugin = tmp_path / "bad_plugin.py"
    plugin.write_text(source + "\n")
    code = main(["validate", "--plugin", str(plugin), "--impls", "qhull", "--sizes", "10", "--datasets", "uniform",
                 "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and "Traceback" not in err and len(err.strip().splitlines()) == 1, err


def test_an_out_that_is_a_file_is_one_line(tmp_path, capsys):
    taken = tmp_path / "taken"
    taken.write_text("")
    code = main(["validate", "--impls", "qhull", "--sizes", "10", "--datasets", "uniform", "--out", str(taken)])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err


def test_repeated_names_run_once(tmp_path):
    out = tmp_path / "r.csv"
    assert main(["bench", "--min-time", "0", "--impls", "qhull,qhull", "--datasets", "uniform,uniform", "--sizes", "20,20",
                 "--seeds", "0,0", "--repeat", "1", "--out", str(out), "--quiet"]) == 0
    import pandas as pd

    df = pd.read_csv(out)
    assert len(df) == 1 and df.impl.tolist() == ["qhull"]
