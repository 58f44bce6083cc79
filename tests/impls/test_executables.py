"""Programs in any language, judged like built-in implementations (``impls.executable``).

The programs are small Python scripts in ``tests/support/executables`` (run with the
interpreter running vorobench, ``{python}``): a correct one (scipy's Delaunay, and the regular
triangulation as a lower hull for weights) and fault doubles that segfault, hang, exit 0
without an answer, print prose, print the diagram of other sites, or print 10 GB. The C
example of ``docs/executables.md`` is compiled and judged where a C compiler is present.
"""

from __future__ import annotations

import json
import os
import shlex
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import impls
from impls.executable import implementation_of, read_manifest
from impls.plugins import plugins_registered
from vorobench.judge.engine import Judge

ROOT = Path(__file__).resolve().parents[2]
DOUBLES = ROOT / "tests" / "support" / "executables"
C_EXAMPLE = ROOT / "examples" / "executable" / "c" / "impl.toml"
JS_EXAMPLE = ROOT / "examples" / "executable" / "js" / "impl.toml"

#: Each test program and the verdict it must get on 30 uniform sites.
EXPECTED = {"scipy-triangles": {"exact", "within_tolerance"}, "segfault": {"crashed"}, "hang": {"timeout"},
            "silent": {"invalid_output"}, "garbage": {"invalid_output"}, "other-sites": {"not_certified"},
            "flood": {"invalid_output"}, "hider": {"exact", "within_tolerance"},
            "daemon": {"exact", "within_tolerance"}}


def _peak_mib(pid: int, readings: list) -> None:
    """Follow the peak resident size of process ``pid`` itself (VmHWM: its own high-water mark,
    not its children's) until it ends."""
    status = Path(f"/proc/{pid}/status")
    while True:
        try:
            line = next(x for x in status.read_text().splitlines() if x.startswith("VmHWM:"))
        except (OSError, StopIteration):
            return
        readings.append(int(line.split()[1]) / 1024)
        time.sleep(0.05)


def _vorobench(args: list[str], env_extra: dict) -> tuple[int, float, str]:
    """Run the CLI in a process of its own: (exit status, the judging process's own peak
    resident MiB, output)."""
    env = {**os.environ, **env_extra}
    proc = subprocess.Popen([sys.executable, "-m", "vorobench", *args], cwd=ROOT, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
    readings: list = []
    follower = threading.Thread(target=_peak_mib, args=(proc.pid, readings), daemon=True)
    follower.start()
    out = proc.stdout.read().decode()
    proc.wait()
    follower.join(5)
    return proc.returncode, max(readings, default=float("nan")), out


@pytest.fixture(scope="module")
def judged(tmp_path_factory):
    """One validate run of every test program on 30 uniform sites; (summary, peak MiB, witnesses)."""
    out = tmp_path_factory.mktemp("validate")
    status, peak_mb, text = _vorobench(
        ["validate", "--impls", ",".join(EXPECTED), "--datasets", "uniform", "--sizes", "30", "--timeout", "8",
         "--no-shrink", "--out", str(out)], {"VOROBENCH_IMPLS_PATH": str(DOUBLES),
                                             "DAEMON_PID_FILE": str(out / "daemon.pid")})
    assert status == 1, text                               # the doubles fail, and say so
    return json.loads((out / "summary.json").read_text()), peak_mb, out / "witnesses"


def test_a_daemon_the_program_leaves_behind_is_ended(judged):
    from tests.support.processes import alive

    pid_file = judged[2].parent / "daemon.pid"
    assert pid_file.exists()                               # it did start one
    assert not alive(int(pid_file.read_text()))


@pytest.mark.parametrize("name", EXPECTED)
def test_each_program_gets_its_verdict(judged, name):
    summary, _, _ = judged
    rows = [r for r in summary["results"] if r["impl"] == name]
    assert len(rows) == 1 and rows[0]["verdict"] in EXPECTED[name], rows


def test_what_the_failures_say(judged):
    message = {r["impl"]: r["message"] for r in judged[0]["results"]}
    assert "SIGSEGV" in message["segfault"]
    assert "no triangles for 30 sites" in message["silent"]
    assert "'triangulation'" in message["garbage"]
    assert "printed more than" in message["flood"]


def test_a_10_gb_answer_leaves_the_judge_under_1_gb(judged):
    assert 50 < judged[1] < 1024                               # read, and far from 10 GB


def test_executables_are_declared_as_such(judged):
    declared = judged[0]["declarations"]["scipy-triangles"]
    assert declared["kind"] == "executable" and declared["weighted"] is True and declared["exact"] is False


def test_a_witness_carries_the_command_that_reruns_the_program(judged):
    witnesses = judged[2]
    text = (witnesses / "garbage-uniform-n30-s0.txt").read_text()
    assert f"--plugin {DOUBLES / 'garbage.toml'}" in text          # found through VOROBENCH_IMPLS_PATH
    rerun = next(line for line in text.splitlines() if line.startswith("cd "))
    done = subprocess.run(rerun, shell=True, capture_output=True, text=True, timeout=60)
    assert done.stdout.startswith("triangulation complete")        # the program's answer, reproduced
    assert (witnesses / "garbage-uniform-n30-s0.stdin").read_bytes().startswith(b"30\n")


def test_a_power_diagram_program_is_judged_on_weighted_sites():
    with plugins_registered([str(DOUBLES / "scipy-triangles.toml")]), Judge(["scipy-triangles"], "qhull") as judge:
        sites = np.random.default_rng(3).random((60, 2))
        weights = np.random.default_rng(4).random(60) * 0.01
        case = judge.judge(sites, weights=weights)
        row = next(v for name, v, _ in case.rows if name == "scipy-triangles")
        assert row.passed, row.message
        assert row.result.diagram.hidden.size > 0                  # some sites are hidden, as in qhull's


def test_bench_times_the_program_and_keeps_the_protocol_apart(tmp_path):
    results = tmp_path / "results.csv"
    status, _, text = _vorobench(["bench", "--plugin", str(DOUBLES / "scipy-triangles.toml"), "--plugin",
                                  str(DOUBLES / "garbage.toml"), "--plugin", str(DOUBLES / "hider.toml"),
                                  "--impls", "scipy-triangles,garbage,hider",
                                  "--datasets", "uniform", "--sizes", "200", "--repeat", "2", "--min-time", "0", "--out",
                                  str(results)], {})
    df = pd.read_csv(results)
    ok = df[df.impl == "scipy-triangles"]
    assert len(ok) == 2 and (ok.status == "ok").all(), text
    assert (ok.time_protocol_s > 0).all() and (ok.time_library_s > 0).all() and (ok.cpu_s > 0).all()
    assert (ok.time_library_s < ok.time_s).all()                  # scipy's call is part of the process
    assert (ok.peak_rss_mb > 10).all()                             # a Python process with numpy
    hidden = df[df.impl == "hider"]                               # its grandchild's CPU is its own
    assert (hidden.cpu_s >= 0.4).all(), hidden[["time_s", "cpu_s"]]
    bad = df[df.impl == "garbage"]
    assert set(bad.verdict) == {"invalid_output"}, text


#: The complete examples of docs/executables.md, each with the programs its toolchain needs.
EXAMPLES = {"c-example": (C_EXAMPLE, ("cc",)), "js-example": (JS_EXAMPLE, ("node", "npm"))}


@pytest.mark.parametrize("name", EXAMPLES)
def test_the_docs_examples_are_set_up_once_and_judged(tmp_path, name):
    manifest, tools = EXAMPLES[name]
    if any(shutil.which(tool) is None for tool in tools):
        pytest.skip(f"{name} needs {', '.join(tools)}, not all here")
    env = {"VOROBENCH_CACHE_DIR": str(tmp_path / "cache")}
    status, _, text = _vorobench(["validate", "--plugin", str(manifest), "--impls", name, "--datasets",
                                  "uniform,collinear", "--sizes", "10,100", "--out", str(tmp_path / "v")], env)
    assert status == 0, text
    summary = json.loads((tmp_path / "v" / "summary.json").read_text())
    rows = [r for r in summary["results"] if r["impl"] == name]
    assert len(rows) == 4 and all(r["verdict"] in ("exact", "within_tolerance") for r in rows), rows
    built = list((tmp_path / "cache" / "executables").glob(f"{name}-*/.setup.json"))
    assert len(built) == 1


SETUP_COUNTER = """[implementation]
name = "counted"
command = ["{{python}}", "prog.py"]
output = "triangles"
exact = false
complexity = "O(n)"
setup = ["{{python}}", "-c", "open({count!r}, 'a').write('x'); open('built.txt', 'w').write('in place')"]
"""


def test_setup_runs_once_then_again_only_when_a_source_changes(tmp_path, monkeypatch):
    """Files a setup or a run leaves in the folder (an in-place build, a log) are no reason to
    set up again; a changed source is."""
    import impls.executable as executable

    monkeypatch.setenv("VOROBENCH_CACHE_DIR", str(tmp_path / "cache"))
    folder, count = tmp_path / "prog", tmp_path / "count"
    folder.mkdir()
    (folder / "impl.toml").write_text(SETUP_COUNTER.format(count=str(count)))
    (folder / "prog.py").write_text("print('v1')\n")
    manifest = read_manifest(folder / "impl.toml")

    def set_up() -> int:
        executable._READY.discard(manifest.folder)          # as a new sandbox would
        executable.ensure_setup(manifest)
        return len(count.read_text())

    assert set_up() == 1 and (folder / "built.txt").exists()
    (folder / "run.log").write_text("a program's log")
    assert set_up() == 1
    (folder / "prog.py").write_text("print('v2')\n")
    assert set_up() == 2


def test_a_setup_killed_half_way_starts_again_from_an_empty_cache(tmp_path, monkeypatch):
    import impls.executable as executable

    monkeypatch.setenv("VOROBENCH_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "impl.toml").write_text(SETUP_COUNTER.format(count=str(tmp_path / "count")).replace(
        "open('built.txt', 'w').write('in place')", "import os; os.mkdir(os.environ['VOROBENCH_CACHE'] + '/out')"))
    (tmp_path / "prog.py").write_text("")
    manifest = read_manifest(tmp_path / "impl.toml")
    (manifest.cache() / "out").mkdir(parents=True)          # what a killed setup left, without its stamp
    executable.ensure_setup(manifest)                        # mkdir would fail on the leftover
    assert (manifest.cache() / ".setup.json").exists()


@pytest.mark.parametrize("command, says", [
    ('["prog.py"]', 'write "./prog.py"'), ('["./prog.py"]', "not executable"),
    ('["./missing"]', "does not exist"), ('["no-such-program-xyz"]', "not on PATH")])
def test_a_command_that_cannot_run_is_said_before_any_build(tmp_path, command, says):
    (tmp_path / "impl.toml").write_text(f'[implementation]\nname = "c"\ncommand = {command}\n'
                                        'output = "triangles"\nexact = false\ncomplexity = "O(n)"\n')
    (tmp_path / "prog.py").write_text("")
    with pytest.raises(RuntimeError, match=says):
        implementation_of(read_manifest(tmp_path / "impl.toml")).warmup()


def test_a_setup_that_fails_is_the_implementations_failure_said_once(tmp_path, monkeypatch):
    monkeypatch.setenv("VOROBENCH_CACHE_DIR", str(tmp_path / "cache"))
    (tmp_path / "impl.toml").write_text('[implementation]\nname = "broken-build"\ncommand = ["./nothing"]\n'
                                        'output = "triangles"\nexact = true\ncomplexity = "O(n)"\n'
                                        f'setup = [{json.dumps(sys.executable)}, "-c", "import sys; '
                                        f'sys.exit(\'cannot compile: missing header\')"]\n')
    impl = implementation_of(read_manifest(tmp_path / "impl.toml"))
    with pytest.raises(RuntimeError, match="setup of broken-build .* failed with status 1: cannot compile.*setup.log"):
        impl.warmup()
    impls.unregister("broken-build")


def test_rerun_command_quotes_its_paths(tmp_path):
    from impls.executable import rerun_command

    folder = tmp_path / "a folder"
    folder.mkdir()
    (folder / "impl.toml").write_text('[implementation]\nname = "q"\ncommand = ["./my prog", "-x"]\n'
                                      'output = "voronoi"\nexact = false\ncomplexity = "O(n)"\n')
    line = rerun_command(read_manifest(folder / "impl.toml"), tmp_path / "in put.txt")
    assert shlex.split(line.split(" && ")[1])[:2] == [str(folder / "my prog"), "-x"]


def test_impls_lists_a_manifest_as_an_executable(capsys):
    from vorobench.cli import main

    assert main(["impls", "--plugin", str(DOUBLES / "garbage.toml")]) == 0
    row = next(line for line in capsys.readouterr().out.splitlines() if line.startswith("│ garbage "))
    assert [cell.strip() for cell in row.split("│")[2:5]] == ["executable", "no", "no"]
    assert "garbage" not in impls.available()                  # registered for that command only
