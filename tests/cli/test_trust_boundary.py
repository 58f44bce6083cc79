"""The judge trusts nothing it judges: hostile plugins (``tests/support/hostile``) attack it from
import time, through their declarations, their exceptions and their answers, and every attack
ends as that implementation's own failure, the other rows intact.

One ``validate`` run holds every attacker beside an honest implementation (fortune); each test
reads its part of the outcome. The run is a subprocess: its pid is the judge's.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

HERE = Path(__file__).parent
ROOT = HERE.parent.parent
HOSTILE = HERE.parent / "support" / "hostile"
PLUGINS = [HOSTILE / f"{name}.py" for name in ("judge_patcher", "two_faced", "refuses_in_build", "stray_bytes",
                                               "wire_bomb")]
ATTACKERS = ["judge_patcher", "two_faced", "refuses_unsupported", "refuses_outside", "stray_bytes", "unprintable",
             "bomb_shape", "bomb_deflate", "bomb_npz"]


def vorobench(args: list[str], tmp: Path, timeout: float = 300, plugins: list[Path] = PLUGINS
              ) -> tuple[subprocess.CompletedProcess, int, list[str]]:
    """Run ``vorobench args`` with the hostile ``plugins`` (default: all); (result, the judge's
    pid, the import log)."""
    log = tmp / "imports.log"
    env = {**os.environ, "VOROBENCH_TEST_IMPORT_LOG": str(log), "VOROBENCH_TEST_MARK": str(tmp / "first")}
    plugins = [arg for p in plugins for arg in ("--plugin", str(p))]
    proc = subprocess.Popen([sys.executable, "-m", "vorobench", *args, *plugins], cwd=ROOT, env=env,
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            errors="replace")
    try:
        out, err = proc.communicate(timeout=timeout)
    finally:
        proc.kill()
    lines = log.read_text().splitlines() if log.exists() else []
    return subprocess.CompletedProcess(proc.args, proc.returncode, out, err), proc.pid, lines


def imported_in(lines: list[str]) -> set[int]:
    return {int(line.split()[1]) for line in lines}


@pytest.fixture(scope="module")
def validated(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("trust")
    out = tmp / "out"
    run, pid, imports = vorobench(["validate", "--impls", ",".join(["fortune", *ATTACKERS]), "--datasets", "uniform",
                                   "--sizes", "12", "--timeout", "20", "--no-shrink", "--out", str(out),
                                   "--junit", str(tmp / "junit.xml"), "--markdown", str(tmp / "digest.md")], tmp)
    assert (out / "summary.json").exists(), run.stdout[-3000:] + run.stderr[-3000:]
    summary = json.loads((out / "summary.json").read_text())
    rows = {r["impl"]: r for r in summary.get("results", []) if not r.get("exact_peer")}
    return dict(run=run, pid=pid, imports=imports, summary=summary, rows=rows, tmp=tmp)


def test_the_run_fails_and_its_summary_is_complete(validated):
    run, summary = validated["run"], validated["summary"]
    assert run.returncode == 1, run.stdout[-3000:] + run.stderr[-3000:]
    assert summary["complete"] and not summary["passed"]
    assert sorted(summary["failed_impls"]) == sorted(ATTACKERS)


def test_no_plugin_is_imported_in_the_judging_process(validated):
    pids = imported_in(validated["imports"])
    assert pids, "the plugins were imported nowhere: the log is not written"
    assert validated["pid"] not in pids


def test_an_implementation_that_patches_the_judge_at_import_is_judged_by_the_real_judge(validated):
    row = validated["rows"]["judge_patcher"]
    assert not row["passed"] and row["verdict"] == "not_certified", row


def test_the_honest_implementation_keeps_its_pass(validated):
    rows = validated["rows"]
    assert rows["fortune"]["passed"] and rows["fortune"]["verdict"] == "exact", rows["fortune"]
    assert rows["qhull"]["passed"], rows["qhull"]


def test_a_declaration_that_changes_between_processes_is_refused(validated):
    row = validated["rows"]["two_faced"]
    assert row["verdict"] == "crashed" and "declared exact=False" in row["message"], row
    assert validated["summary"]["declarations"]["two_faced"]["exact"] is True      # pinned from the first reading


@pytest.mark.parametrize("name", ["refuses_unsupported", "refuses_outside"])
def test_a_refusal_raised_inside_build_is_a_crash(validated, name):
    row = validated["rows"][name]
    assert row["verdict"] == "crashed" and not row["passed"], row


def test_exception_text_with_stray_bytes_is_kept_readable_everywhere(validated):
    rows, tmp = validated["rows"], validated["tmp"]
    message = rows["stray_bytes"]["message"]
    assert rows["stray_bytes"]["verdict"] == "crashed" and "bad byte" in message, message
    assert "\\udcff" in message and "\x1b" not in message, message
    assert rows["unprintable"]["verdict"] == "crashed" and "_Unprintable" in rows["unprintable"]["message"]
    ET.parse(tmp / "junit.xml")                                   # well-formed
    assert "bad byte" in (tmp / "digest.md").read_text(encoding="utf-8")
    assert "\x1b" not in validated["run"].stdout


@pytest.mark.parametrize("name", ["bomb_shape", "bomb_deflate", "bomb_npz"])
def test_an_answer_the_wire_does_not_allow_is_the_implementations_crash(validated, name):
    row = validated["rows"][name]
    assert row["verdict"] == "crashed" and "refuses" in row["message"], row


def test_impls_lists_plugins_without_importing_them(tmp_path):
    run, pid, imports = vorobench(["impls"], tmp_path)
    assert run.returncode == 0, run.stderr
    assert "judge_patcher" in run.stdout and "bomb_shape" in run.stdout
    assert imports and pid not in imported_in(imports)


def test_build_runs_a_plugin_without_importing_it(tmp_path):
    run, pid, imports = vorobench(["build", "--impl", "bomb_npz", "--dataset", "uniform", "--n", "12"], tmp_path)
    assert run.returncode == 1 and "refuses" in run.stderr, run.stderr
    assert imports and pid not in imported_in(imports)


def test_demo_and_report_run_a_plugin_without_importing_it(tmp_path):
    out = tmp_path / "demo"
    run, pid, imports = vorobench(["demo", "--impls", "judge_patcher", "--datasets", "uniform", "--sizes", "20",
                                   "--repeat", "1", "--min-time", "0", "--quiet", "--out", str(out)], tmp_path)
    assert run.returncode == 0, run.stderr[-3000:]
    assert imports and pid not in imported_in(imports)
    results = __import__("pandas").read_csv(out / "results.csv")
    assert set(results["verdict"]) == {"not_certified"}          # the patched judge stayed in its sandbox
    (tmp_path / "imports.log").unlink()
    again, pid, imports = vorobench(["report", str(out / "results.csv"), "-o", str(tmp_path / "report")], tmp_path)
    assert again.returncode == 0, again.stderr[-3000:]
    assert pid not in imported_in(imports)
    assert "O(n log n)" in (tmp_path / "report" / "README.md").read_text()    # the complexity the run pinned


def test_fuzz_runs_plugins_without_importing_them(tmp_path):
    run, pid, imports = vorobench(["fuzz", "--impls", "fortune,judge_patcher", "--generators", "uniform", "--budget", "2",
                                   "--max-n", "10", "--no-shrink", "--out", str(tmp_path / "fuzz")], tmp_path)
    assert run.returncode == 1, run.stdout[-3000:] + run.stderr[-3000:]
    summary = json.loads((tmp_path / "fuzz" / "summary.json").read_text())
    assert summary["failed"] == 2 and summary["declarations"]["judge_patcher"]["exact"] is True
    assert imports and pid not in imported_in(imports)


def test_a_broken_exact_implementation_listed_first_is_the_only_one_blamed(tmp_path):
    """Item 7: with the broken exact implementation first, the exact comparison row of the
    honest one names the broken one, not itself."""
    out = tmp_path / "out"
    run, _, _ = vorobench(["validate", "--impls", "swapped_exact,fortune", "--datasets", "uniform", "--sizes", "12",
                           "--no-shrink", "--out", str(out)], tmp_path, plugins=[HOSTILE / "refuses_in_build.py"])
    assert run.returncode == 1, run.stdout[-3000:] + run.stderr[-3000:]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["failed_impls"] == ["swapped_exact"], summary["failed_impls"]
    fortune = [r for r in summary["results"] if r["impl"] == "fortune" and not r["exact_peer"]]
    assert fortune and all(r["passed"] for r in fortune)


def test_a_run_killed_while_it_starts_leaves_no_green_summary_behind(tmp_path):
    """Item 8: the previous run's green summary is gone before any implementation is loaded."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.json").write_text(json.dumps({"passed": True, "complete": True}))
    log = tmp_path / "imports.log"
    env = {**os.environ, "VOROBENCH_TEST_IMPORT_LOG": str(log), "VOROBENCH_TEST_MARK": str(tmp_path / "first")}
    proc = subprocess.Popen([sys.executable, "-m", "vorobench", "validate", "--plugin", str(PLUGINS[0]), "--impls",
                             "judge_patcher", "--datasets", "uniform", "--sizes", "12", "--out", str(out)], cwd=ROOT,
                            env=env, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        while not (log.exists() and log.read_text().strip()) and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.01)
        assert log.exists(), "the plugin was never loaded"
        os.kill(proc.pid, signal.SIGKILL)           # as soon as the first implementation is loaded anywhere
    finally:
        proc.kill()
        proc.wait()
    summary = json.loads((out / "summary.json").read_text())
    assert summary["passed"] is False and summary["complete"] is False
