"""The run store files any counter name and survives writers filing at once.

Fault doubles: counters whose names hold SQL quoting characters (an ``ALTER TABLE`` built by
pasting the name breaks on them, or runs what follows), and two processes filing runs with
different new counter columns into one new store at the same moment.
"""

from __future__ import annotations

import multiprocessing
import sqlite3

import pandas as pd
import pytest

from vorobench.harness.store import Store

HOSTILE_COUNTERS = ['stat_a"b', 'stat_"', "stat_it's", 'stat_x"; drop table runs; --', "stat_[x]", "stat_`x`",
                    "stat_two words"]


def _rows(run_id: str, counter: str, value: int = 7, repeats: int = 3) -> pd.DataFrame:
    """A recorded run: one case, ``repeats`` rows, one counter column."""
    return pd.DataFrame([{"run_id": run_id, "impl": "a", "dataset": "uniform", "n": 10, "seed": 0, "repeat": r,
                          "status": "ok", "verdict": "exact", "time_s": 0.01, counter: value}
                         for r in range(repeats)])


@pytest.mark.parametrize("counter", HOSTILE_COUNTERS)
def test_a_counter_name_with_quotes_is_stored_as_it_is(counter, tmp_path):
    store = Store(tmp_path / "s")
    assert store.add_run(_rows("r1", counter), {"run_id": "r1"})
    back = store.results("r1")
    assert list(back[counter]) == [7, 7, 7]
    assert list(store.runs()["run_id"]) == ["r1"]            # nothing else ran, nothing was dropped


def test_a_counter_name_differing_only_in_case_is_refused_not_merged(tmp_path):
    store = Store(tmp_path / "s")
    store.add_run(_rows("r1", "stat_Sites"), {"run_id": "r1"})
    with pytest.raises(ValueError, match="stat_sites.*stat_Sites"):
        store.add_run(_rows("r2", "stat_sites"), {"run_id": "r2"})
    assert list(store.runs()["run_id"]) == ["r1"]


def _file(path: str, run_id: str, counter: str, start) -> None:
    """One writer: open the new store, wait for the other, then file a run with a counter column
    of its own (both then look at the empty table's columns at the same moment)."""
    Store(path)._connect(create=True).close()
    start.wait()
    Store(path).add_run(_rows(run_id, counter, repeats=20), {"run_id": run_id})


@pytest.mark.parametrize("attempt", range(6))
def test_two_processes_filing_into_a_new_store_both_get_filed(attempt, tmp_path):
    ctx = multiprocessing.get_context("fork")            # no re-import: the two start within microseconds
    start = ctx.Barrier(2)
    path = str(tmp_path / "s")
    writers = [ctx.Process(target=_file, args=(path, f"run{i}", f"stat_only_{i}", start)) for i in range(2)]
    for w in writers:
        w.start()
    for w in writers:
        w.join(120)
    assert [w.exitcode for w in writers] == [0, 0]
    with sqlite3.connect(tmp_path / "s" / "runs.sqlite") as con:
        assert sorted(r[0] for r in con.execute("select run_id from runs")) == ["run0", "run1"]
    for i in range(2):
        rows = Store(path).results(f"run{i}")
        assert len(rows) == 20 and (rows[f"stat_only_{i}"] == 7).all()
