"""Hostile input files: ``--points`` (datasets_gen.load) and ``--weights file:PATH`` (load_weights)
refuse alike what is no regular file (``/dev/zero`` named ``.csv`` would be read until memory
runs out; a FIFO would wait for ever for a writer), and refuse integers that float64 cannot
hold rather than round two distinct values onto one.

Each hostile file is loaded in a child process with a memory cap and a time limit, so that a
loader that fails these tests fails them quickly, without taking the machine's memory.
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from datasets_gen.loaders import load_weights

#: Loads argv[2] with the loader argv[1], within 512 MiB more memory; prints the outcome.
LOAD_SCRIPT = textwrap.dedent("""
    import sys

    import datasets_gen
    from datasets_gen.loaders import load_weights
    from vorobench.judge.isolation import limit_memory

    loader = {"points": datasets_gen.load, "weights": load_weights}[sys.argv[1]]
    limit_memory(512)
    try:
        loader(sys.argv[2])
    except (ValueError, FileNotFoundError) as exc:
        print(f"refused: {exc}")
    except MemoryError:
        print("MemoryError")
    else:
        print("loaded")
""")

LOADERS = ["points", "weights"]


def _load_in_child(loader: str, path: Path, seconds: float = 60.0) -> str:
    """What loading ``path`` with ``loader`` does in a child process: its one line of outcome."""
    try:
        run = subprocess.run([sys.executable, "-c", LOAD_SCRIPT, loader, str(path)], capture_output=True,
                             text=True, timeout=seconds)
    except subprocess.TimeoutExpired:
        pytest.fail(f"loading {path.name} as {loader} did not end within {seconds:g} s")
    assert run.returncode == 0, run.stderr
    return run.stdout.strip()


@pytest.fixture
def fifo(tmp_path):
    """A FIFO named ``w.csv`` that nobody writes to; a reader stuck on it is let go at the end."""
    path = tmp_path / "w.csv"
    os.mkfifo(path)
    yield path
    try:                        # a writer that opens and closes at once ends a reader's wait with EOF
        os.close(os.open(path, os.O_WRONLY | os.O_NONBLOCK))
    except OSError:             # no reader waiting
        pass


@pytest.mark.parametrize("loader", LOADERS)
def test_dev_zero_named_csv_is_refused_not_read(loader, tmp_path):
    path = tmp_path / "w.csv"
    path.symlink_to("/dev/zero")
    assert _load_in_child(loader, path) == f"refused: {path}: not a regular file"


@pytest.mark.parametrize("loader", LOADERS)
def test_a_fifo_is_refused_not_waited_on(loader, fifo):
    assert _load_in_child(loader, fifo) == f"refused: {fifo}: not a regular file"


@pytest.mark.parametrize("loader", LOADERS)
def test_dev_zero_named_npy_is_refused(loader, tmp_path):
    path = tmp_path / "w.npy"
    path.symlink_to("/dev/zero")
    assert _load_in_child(loader, path) == f"refused: {path}: not a regular file"


def test_a_weights_file_too_large_is_refused_before_it_is_read(tmp_path, monkeypatch):
    from datasets_gen import loaders

    path = tmp_path / "w.csv"
    path.write_text("1.5\n" * 100)
    monkeypatch.setattr(loaders, "MAX_FILE_BYTES", 64)
    with pytest.raises(ValueError, match=r"w.csv: 400 bytes, more than the 64 read"):
        load_weights(path)


def test_a_missing_weights_file_is_still_a_value_error(tmp_path):
    with pytest.raises(ValueError, match="no such weights file"):
        load_weights(tmp_path / "nope.csv")


# ------------------------------------------------------------------ integers float64 cannot hold

BIG = 2**53 + 1        # the first integer float64 cannot hold: it would be read as 2**53


def test_weights_npy_of_int64_beyond_2_53_are_refused_naming_the_value(tmp_path):
    path = tmp_path / "w.npy"
    np.save(path, np.array([1, 2**53, BIG, 7], dtype=np.int64))
    with pytest.raises(ValueError, match=rf"w.npy: integer {BIG} at index 2 has no exact float64 value"):
        load_weights(path)


def test_weights_text_with_an_integer_beyond_2_53_is_refused_naming_the_line(tmp_path):
    path = tmp_path / "w.csv"
    path.write_text(f"# weights\n1\n{2**53}\n{BIG}\n")
    with pytest.raises(ValueError, match=rf"w.csv:4: integer {BIG} has no exact float64 value"):
        load_weights(path)


def test_weights_that_float64_holds_load_as_before(tmp_path):
    (tmp_path / "col.csv").write_text(f"1\n-2.5  # a comment\n\n{2**60}\n")
    assert load_weights(tmp_path / "col.csv").tolist() == [1.0, -2.5, float(2**60)]
    (tmp_path / "row.csv").write_text("1,2,3\n")
    assert load_weights(tmp_path / "row.csv").tolist() == [1.0, 2.0, 3.0]
    np.save(tmp_path / "w.npy", np.array([2**62, -(2**63), 5], dtype=np.int64))   # powers of two: exact
    assert load_weights(tmp_path / "w.npy").tolist() == [2.0**62, -(2.0**63), 5.0]
    (tmp_path / "table.csv").write_text("1,2\n3,4\n")
    with pytest.raises(ValueError, match=r"one number per point, got an array of shape \(2, 2\)"):
        load_weights(tmp_path / "table.csv")
    (tmp_path / "bad.csv").write_text("1\nheavy\n")
    with pytest.raises(ValueError, match=r"bad.csv:2: non-numeric value 'heavy'"):
        load_weights(tmp_path / "bad.csv")
