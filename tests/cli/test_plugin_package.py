"""``pip install examples/plugin`` adds an implementation that every command sees without
options: ``vorobench impls`` lists it, ``validate`` judges it, ``bench`` times it and records
where its code comes from, and the example's own tests pass against the installed copy.

The package is installed into a temporary folder put on ``PYTHONPATH`` of subprocesses, never
into the project's environment.
"""

from __future__ import annotations

import csv
import json
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest
from installing import environment_with, pip_install_into

from vorobench.harness.sysinfo import git_commit

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "plugin"
PROJECT = tomllib.loads((EXAMPLE / "pyproject.toml").read_text())["project"]
NAME = "scipy-delaunay"


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> Path:
    """The folder the example plugin is installed into."""
    target = tmp_path_factory.mktemp("site")
    pip_install_into(EXAMPLE, target, tmp_path_factory.mktemp("build"))
    return target


def _vorobench(*args: str, env: dict, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "vorobench", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=240)


def _listed(stdout: str) -> list[str]:
    """The names in the first column of `vorobench impls`'s table (a wrapped row continues with
    an empty name)."""
    cells = [line.split("│")[1].strip() for line in stdout.splitlines() if line.startswith("│")]
    return [name for name in cells if name]


def test_the_entry_point_is_what_pip_installs(installed):
    assert PROJECT["entry-points"]["vorobench.impls"] == {NAME: "vorobench_scipy_delaunay:IMPLEMENTATION"}
    (info,) = installed.glob("vorobench_scipy_delaunay-*.dist-info")
    assert f"{NAME} = vorobench_scipy_delaunay:IMPLEMENTATION" in (info / "entry_points.txt").read_text()


def test_installing_it_makes_impls_list_it(installed, tmp_path):
    before = _vorobench("impls", env=environment_with(), cwd=tmp_path)
    after = _vorobench("impls", env=environment_with(installed), cwd=tmp_path)
    assert before.returncode == 0 and after.returncode == 0, before.stderr + after.stderr
    assert NAME not in _listed(before.stdout)
    assert _listed(after.stdout) == _listed(before.stdout) + [NAME]


def test_validate_judges_the_installed_plugin(installed, tmp_path):
    run = _vorobench("validate", "--impls", NAME, "--datasets", "uniform,grid,collinear", "--sizes", "3,40",
                     "--out", str(tmp_path / "validate"), env=environment_with(installed), cwd=tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    rows = [r for r in json.loads((tmp_path / "validate" / "summary.json").read_text())["results"] if r["impl"] == NAME]
    assert len(rows) == 6
    assert all(r["passed"] and r["verdict"] in ("exact", "within_tolerance") for r in rows), rows


def test_bench_times_it_and_records_its_distribution(installed, tmp_path):
    out = tmp_path / "run.csv"
    run = _vorobench("bench", "--impls", NAME, "--datasets", "uniform", "--sizes", "50,100", "--repeat", "2",
                     "--min-time", "0", "--out", str(out), "--quiet", env=environment_with(installed), cwd=tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    with out.open() as f:
        rows = list(csv.DictReader(f))
    assert {(r["impl"], r["n"], r["status"], r["verdict"]) for r in rows} == {(NAME, "50", "ok", "exact"),
                                                                              (NAME, "100", "ok", "exact")}
    assert all(int(r["stat_triangles"]) > 0 and float(r["time_library_s"]) > 0 for r in rows)
    meta = json.loads(out.with_suffix(".meta.json").read_text())["runs"][-1]
    code = meta["implementations"][NAME]
    assert (code["distribution"], code["version"]) == (PROJECT["name"], PROJECT["version"])
    assert code["module"] == "vorobench_scipy_delaunay"
    assert Path(code["file"]).is_relative_to(installed.resolve())
    assert code["commit"] == git_commit(installed)["commit"]          # None: an installed copy is in no git tree


def test_the_example_passes_its_own_tests_installed(installed, tmp_path):
    tests = tmp_path / "tests"
    tests.mkdir()
    (tests / "test_plugin.py").write_text((EXAMPLE / "tests" / "test_plugin.py").read_text())
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--rootdir", str(tmp_path),
                          str(tests)], cwd=tmp_path, env=environment_with(installed), capture_output=True, text=True,
                         timeout=240)
    assert run.returncode == 0, run.stdout + run.stderr
    assert " passed" in run.stdout and "skipped" not in run.stdout     # the entry-point test ran too
