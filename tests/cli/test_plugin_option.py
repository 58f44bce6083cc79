"""``--plugin`` on every command that runs or lists implementations: ``impls`` lists a plugin's
implementations (a ``.py`` file or a module name) for that command only, and ``report`` reads
their declared complexities. Commands that only read results files (``compare``, ``history``,
``trend``) load no implementation and take no ``--plugin``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import impls
from vorobench.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[2]
PLUGIN = '''\
from impls.qhull import build
from vorobench.plugin import Implementation

IMPLEMENTATIONS = [Implementation("qhull-quadratic", "qhull, declared quadratic", "O(n^2)", build, exact=False)]
'''
#: Each command with the positional arguments it needs.
RUNS_OR_LISTS = {"impls": [], "build": [], "validate": [], "bench": [], "fuzz": [], "demo": [],
                 "continuous": ["HEAD~1", "HEAD"], "report": ["results.csv"]}
READS_RESULTS_ONLY = {"compare": ["a.csv", "b.csv"], "history": ["runs"], "trend": ["runs"]}


@pytest.fixture
def plugin(tmp_path) -> Path:
    path = tmp_path / "quadratic.py"
    path.write_text(PLUGIN)
    return path


def _listed(stdout: str) -> list[str]:
    cells = [line.split("│")[1].strip() for line in stdout.splitlines() if line.startswith("│")]
    return [name for name in cells if name]


@pytest.mark.parametrize("command", RUNS_OR_LISTS)
def test_commands_that_run_or_list_implementations_take_plugins(command):
    args = build_parser().parse_args([command, *RUNS_OR_LISTS[command], "--plugin", "a.py", "--plugin", "pkg.mod"])
    assert args.plugin == ["a.py", "pkg.mod"]


@pytest.mark.parametrize("command", READS_RESULTS_ONLY)
def test_commands_that_read_results_only_do_not(command):
    assert build_parser().parse_args([command, *READS_RESULTS_ONLY[command]]).func is not None
    with pytest.raises(SystemExit):
        build_parser().parse_args([command, *READS_RESULTS_ONLY[command], "--plugin", "a.py"])


def test_impls_lists_a_plugin_file_for_that_command_only(plugin, capsys):
    assert main(["impls"]) == 0
    before = _listed(capsys.readouterr().out)
    assert main(["impls", "--plugin", str(plugin)]) == 0
    out = capsys.readouterr().out
    assert _listed(out) == before + ["qhull-quadratic"]
    assert "O(n^2)" in out
    assert "qhull-quadratic" not in impls.available()           # unregistered when the command ends


def test_impls_lists_a_plugin_module_by_name(monkeypatch, capsys):
    monkeypatch.syspath_prepend(str(ROOT / "examples" / "plugin"))
    assert main(["impls", "--plugin", "vorobench_scipy_delaunay"]) == 0
    assert "scipy-delaunay" in _listed(capsys.readouterr().out)
    assert "scipy-delaunay" not in impls.available()


def test_impls_with_a_missing_plugin_is_a_one_line_error(tmp_path, capsys):
    assert main(["impls", "--plugin", str(tmp_path / "nowhere.py")]) == 2
    err = capsys.readouterr().err
    assert "plugin file not found" in err and len(err.strip().splitlines()) == 1


def test_report_reads_the_declared_complexity_of_a_plugin_from_the_run(plugin, tmp_path, capsys):
    results = tmp_path / "run.csv"
    assert main(["bench", "--plugin", str(plugin), "--impls", "qhull-quadratic", "--sizes", "20,40,80", "--repeat", "1",
                 "--min-time", "0", "--no-check", "--out", str(results), "--quiet"]) == 0
    assert main(["report", str(results), "-o", str(tmp_path / "without")]) == 0
    assert main(["report", str(results), "-o", str(tmp_path / "with"), "--plugin", str(plugin)]) == 0
    without = (tmp_path / "without" / "README.md").read_text()
    with_plugin = (tmp_path / "with" / "README.md").read_text()
    # The run pinned what the plugin declared: the report needs no plugin (and imports none).
    assert "declared O(n^2), about n^2.00 over these sizes" in without
    assert "declared O(n^2), about n^2.00 over these sizes" in with_plugin
    meta = json.loads(results.with_suffix(".meta.json").read_text())
    assert meta["runs"][-1]["declarations"]["qhull-quadratic"]["complexity"] == "O(n^2)"
    for run in meta["runs"]:                   # a run recorded before declarations were pinned
        run.pop("declarations")
    results.with_suffix(".meta.json").write_text(json.dumps(meta))
    assert main(["report", str(results), "-o", str(tmp_path / "older")]) == 0
    assert "no declared complexity to compare with" in (tmp_path / "older" / "README.md").read_text()


def test_a_witness_of_a_plugin_names_the_plugin_in_its_command(tmp_path, capsys):
    doubles = ROOT / "tests" / "support" / "doubles.py"
    relative = doubles.relative_to(Path.cwd()) if doubles.is_relative_to(Path.cwd()) else doubles
    assert main(["validate", "--plugin", str(relative), "--impls", "wrong", "--datasets", "uniform", "--sizes", "30",
                 "--shrink-seconds", "20", "--out", str(tmp_path / "first")]) == 1
    (witness,) = json.loads((tmp_path / "first" / "summary.json").read_text())["witnesses"]
    command = Path(witness["command"]).read_text().splitlines()[0].split()
    assert command[:3] == ["vorobench", "validate", "--plugin"] and command[3] == str(doubles)
    capsys.readouterr()
    assert main(command[1:] + ["--out", str(tmp_path / "again")]) == 1          # it reproduces the failure
    assert "wrong" in capsys.readouterr().out
