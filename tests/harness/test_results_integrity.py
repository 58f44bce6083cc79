"""The results file survives the faults of real runs: a crash mid-row, a second run writing the
same file, and a symlink planted where a temporary file goes.

Fault doubles: a file cut at every byte of its last row (what a crash or a full disk leaves),
another process holding the writer lock, and symlinks to a victim file at the temporary names
the old code used.
"""

from __future__ import annotations

import csv
import os
import subprocess
import sys

import pandas as pd
import pytest

from vorobench.cli import main
from vorobench.harness import results
from vorobench.harness.results import ResultsFile


def _case(impl: str, repeats: int = 2, **extra) -> list[dict]:
    return [{"run_id": "r1", "impl": impl, "dataset": "uniform", "n": 10, "seed": 0, "repeat": i,
             "status": "ok", "time_s": 0.5 + i, **extra} for i in range(repeats)]


def _records(path) -> list[list[str]]:
    with open(path, newline="") as f:
        return list(csv.reader(f))


def _bench(out, sizes: str, *extra: str) -> int:
    return main(["bench", "--min-time", "0", "--impls", "qhull", "--datasets", "uniform", "--sizes", sizes, "--repeat", "2",
                 "--no-check", "--quiet", "--out", str(out), *extra])


# ------------------------------------------------------------------ a torn last row

def test_every_cut_inside_the_last_row_drops_its_whole_case_and_the_next_append_repairs(tmp_path):
    path = tmp_path / "r.csv"
    # case a carries an error text over two lines and a non-ASCII character: one record, three lines
    ResultsFile(path).append(_case("a", error="first line\nsecond µ line, \"quoted\""))
    ResultsFile(path).append(_case("b"))
    whole = path.read_bytes()
    last_row_start = whole.rindex(b"\n", 0, len(whole) - 1) + 1
    kept = _records(path)[:3]                     # header and the two rows of case a
    for cut in range(last_row_start + 1, len(whole)):
        path.write_bytes(whole[:cut])
        store = ResultsFile(path)
        # b's first row is complete but its case is not: it goes too, so that b is run again
        assert [r["impl"] for r in store.rows()] == ["a", "a"], cut
        assert store.done_keys() == {("a", "uniform", 10, 0)}
        assert results.load(path)["impl"].tolist() == ["a", "a"], cut
        store.append(_case("b"))
        after = _records(path)
        assert after[:3] == kept and [r[1] for r in after[3:]] == ["b", "b"], cut
        assert all(len(r) == len(kept[0]) for r in after), cut


def test_a_last_row_with_too_few_fields_is_torn_even_with_its_newline(tmp_path):
    path = tmp_path / "r.csv"
    ResultsFile(path).append(_case("a"))
    with path.open("a", newline="") as f:
        f.write("r2,b,uniform,10,0,0,ok\r\n")
    assert [r["impl"] for r in ResultsFile(path).rows()] == ["a", "a"]
    ResultsFile(path).append(_case("c"))
    assert [r[1] for r in _records(path)[1:]] == ["a", "a", "c", "c"]


def test_resume_after_a_crash_mid_row_reruns_the_case_and_keeps_the_file_readable(tmp_path):
    out = tmp_path / "r.csv"
    assert _bench(out, "100,200") == 0
    out.write_bytes(out.read_bytes()[:-30])       # the run died while writing the last row of n=200
    assert _bench(out, "100,200,300", "--resume") == 0
    header, *rows = _records(out)
    assert rows and all(len(r) == len(header) for r in rows)
    df = results.load(out)
    assert df.groupby("n").size().to_dict() == {100: 2, 200: 2, 300: 2}
    assert df["status"].eq("ok").all() and df["time_s"].notna().all()


# ------------------------------------------------------------------ one writer at a time

def _lock_holder(lock_path) -> subprocess.Popen:
    """Another process that holds the writer lock (flock on ``<out>.lock``) until its stdin closes."""
    code = ("import fcntl, os, sys\n"
            f"f = open({str(lock_path)!r}, 'a+')\n"
            "fcntl.flock(f, fcntl.LOCK_EX)\n"
            "f.truncate(0); f.write(str(os.getpid())); f.flush()\n"
            "print('held', flush=True)\n"
            "sys.stdin.read()\n")
    holder = subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    assert holder.stdout.readline().strip() == "held"
    return holder


def test_a_second_run_on_the_same_out_is_refused_while_the_first_writes(tmp_path, capsys):
    out = tmp_path / "r.csv"
    holder = _lock_holder(tmp_path / "r.csv.lock")
    try:
        assert _bench(out, "100") == 2
        err = capsys.readouterr().err
        assert "being written by another run" in err and f"pid {holder.pid}" in err
        assert len(err.strip().splitlines()) == 1
        assert not out.exists() and not results.metadata_path(out).exists()
        assert _bench(out, "100", "--overwrite") == 2      # nor may it delete what the other run writes
    finally:
        holder.stdin.close()
        holder.wait()
    assert _bench(out, "100") == 0                     # once the other run is gone, it goes ahead
    assert not (tmp_path / "r.csv.lock").exists()


def test_writer_lock_is_exclusive_and_released(tmp_path):
    out = tmp_path / "r.csv"
    with results.writer_lock(out):
        with pytest.raises(ValueError, match=rf"being written by another run \(pid {os.getpid()}\)"):
            with results.writer_lock(out):
                pass
    assert not (tmp_path / "r.csv.lock").exists()
    with results.writer_lock(out):                     # free again
        pass


def test_writer_lock_does_not_follow_a_planted_symlink(tmp_path):
    victim = tmp_path / "victim"
    victim.write_text("precious")
    (tmp_path / "r.csv.lock").symlink_to(victim)
    with pytest.raises(ValueError, match="symbolic link"):
        with results.writer_lock(tmp_path / "r.csv"):
            pass
    assert victim.read_text() == "precious"


# ------------------------------------------------------------------ temporary files

def test_rewrite_and_metadata_do_not_write_through_planted_symlinks(tmp_path):
    victim = tmp_path / "victim"
    victim.write_text("precious")
    out = tmp_path / "r.csv"
    (tmp_path / ".r.csv.tmp").symlink_to(victim)           # the names the old code wrote to
    (tmp_path / ".r.meta.json.tmp").symlink_to(victim)
    store = ResultsFile(out)
    store.append(_case("a"))
    store.append(_case("b", stat_events=3))                 # a new column: the file is rewritten
    results.append_run_metadata(out, {"run_id": "r1"})
    results.update_run_metadata(out, "r1", finished="now")
    assert victim.read_text() == "precious"
    assert not out.is_symlink() and not results.metadata_path(out).is_symlink()
    assert pd.read_csv(out)["impl"].tolist() == ["a", "a", "b", "b"]
    assert results.read_metadata(out) == {"runs": [{"run_id": "r1", "finished": "now"}]}
    # nothing left behind but the planted links themselves
    assert sorted(p.name for p in tmp_path.iterdir()) == [".r.csv.tmp", ".r.meta.json.tmp", "r.csv",
                                                           "r.meta.json", "victim"]


def test_damage_in_the_middle_is_not_cut_away(tmp_path):
    path = tmp_path / "r.csv"
    garbage = bytes(range(256)) * 4                # bare carriage returns: not a tear at the end
    path.write_bytes(garbage)
    assert ResultsFile(path).drop_torn_tail() == 0
    assert path.read_bytes() == garbage
