"""dev.py, the README's two commands: how many test workers it asks pytest-xdist for, and the
kernels it compiles before the tests."""

import importlib.util
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def dev():
    spec = importlib.util.spec_from_file_location("dev_script", ROOT / "dev.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)               # defines functions only; main() is not run
    return module


@pytest.mark.parametrize(("cores", "expected"), [(None, []), (1, []), (2, ["-n", "2"]), (3, ["-n", "3"]),
                                                 (64, ["-n", "4"])])
def test_one_worker_per_core_up_to_four(dev, monkeypatch, cores, expected):
    monkeypatch.setattr(dev.os, "cpu_count", lambda: cores)
    assert dev.pytest_workers([]) == expected
    assert dev.pytest_workers(["tests/core", "-q"]) == expected


@pytest.mark.parametrize("chosen", [["-n", "0"], ["-n0"], ["--numprocesses", "3"], ["--numprocesses=auto"]])
def test_a_worker_count_given_on_the_command_line_wins(dev, monkeypatch, chosen):
    monkeypatch.setattr(dev.os, "cpu_count", lambda: 8)
    assert dev.pytest_workers(["tests", *chosen]) == []


@pytest.mark.parametrize("one_process", [["--pdb"], ["--trace"], ["-s"], ["--capture=no"], ["-p", "no:xdist"]])
def test_a_debugger_uncaptured_output_or_xdist_turned_off_keeps_one_process(dev, monkeypatch, one_process):
    monkeypatch.setattr(dev.os, "cpu_count", lambda: 8)
    assert dev.pytest_workers(["tests/core", *one_process]) == []


def _groups(dev, monkeypatch, tmp_path, cores, first, second):
    monkeypatch.setattr(dev.os, "cpu_count", lambda: cores)
    monkeypatch.setattr(dev, "PYTHON", sys.executable)
    monkeypatch.setattr(dev, "WARM_KERNELS", (first, second))
    dev.warm_kernels()


# the first group waits (up to 30 s, a bound, not a timing) for a file the second writes:
# it ends well only if both run at once
_WAITS = ("import pathlib, sys, time\nend = time.monotonic() + 30\n"
          "while not pathlib.Path({mark!r}).exists():\n"
          "    if time.monotonic() > end: sys.exit('the second group did not run beside the first')\n"
          "    time.sleep(0.05)\n")
_WRITES = "import pathlib; pathlib.Path({mark!r}).write_text('ran')"


def test_on_two_cores_the_groups_compile_side_by_side(dev, monkeypatch, tmp_path, capsys):
    mark = str(tmp_path / "second")
    _groups(dev, monkeypatch, tmp_path, 2, _WAITS.format(mark=mark), _WRITES.format(mark=mark))
    out = capsys.readouterr().out
    assert "compiling the numba kernels" in out and "failed" not in out


def test_on_one_core_they_run_one_after_the_other(dev, monkeypatch, tmp_path, capsys):
    # the first writes its file after a second: run side by side, the second would look first
    mark = str(tmp_path / "first")
    second = f"import pathlib, sys; sys.exit(0 if pathlib.Path({mark!r}).exists() else 'ran before the first')"
    _groups(dev, monkeypatch, tmp_path, 1, "import time; time.sleep(1); " + _WRITES.format(mark=mark), second)
    assert "failed" not in capsys.readouterr().out


def test_a_group_that_fails_is_said_and_the_others_still_run(dev, monkeypatch, tmp_path, capsys):
    mark = tmp_path / "second"
    _groups(dev, monkeypatch, tmp_path, 2, "import sys; sys.exit('no compiler today')", _WRITES.format(mark=str(mark)))
    out = capsys.readouterr().out
    assert "warming the kernels failed (exit 1): no compiler today; the tests will show why" in out
    assert mark.read_text() == "ran"
