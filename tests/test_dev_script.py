"""dev.py, the README's two commands: how many test workers it asks pytest-xdist for."""

import importlib.util
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
