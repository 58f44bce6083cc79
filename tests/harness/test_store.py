"""The run store: bench --store files each run with its metadata, history lists them, compare
and the store agree on references, and a run is filed whole or not at all."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pandas as pd
import pytest

from vorobench.cli import main
from vorobench.harness.store import Store

DOUBLES = str(Path(__file__).resolve().parents[1] / "support" / "doubles.py")


def _bench(folder: Path, name: str, store: Path, *extra: str) -> Path:
    out = folder / f"{name}.csv"
    code = main(["bench", "--plugin", DOUBLES, "--impls", "steady,timed_parts", "--sizes", "20,40", "--repeat", "5", "--min-time", "0",
                 "--no-check", "--quiet", "--out", str(out), "--store", str(store), *extra])
    assert code == 0
    return out


@pytest.fixture(scope="module")
def store(tmp_path_factory) -> Path:
    folder = tmp_path_factory.mktemp("store")
    path = folder / "runs"
    for name in ("r1", "r2", "r3"):
        _bench(folder, name, path)
    return path


def test_three_runs_show_up_in_history(store, capsys):
    assert main(["history", str(store)]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 3
    assert all("4 cases, 0 failed" in line and "steady,timed_parts" in line for line in lines)
    assert main(["history", str(store), "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    assert [r["run_id"] for r in runs] == [line.split()[0] for line in lines]
    meta = runs[-1]["meta"]
    # what a later reader needs to trust the numbers: versions, machine, code provenance
    assert meta["machine_id"] and meta["libraries"]["qhull"].startswith("bundled with scipy")
    assert set(meta["implementations"]) == {"steady", "timed_parts"}
    assert meta["implementations"]["steady"]["file"].endswith("doubles.py")
    assert {"numpy", "numba", "shapely", "triangle"} <= set(meta["versions"])


def test_the_store_is_queryable_with_pandas(store):
    with sqlite3.connect(store / "runs.sqlite") as con:
        rows = pd.read_sql("select * from results", con)
        runs = pd.read_sql("select * from runs", con)
    assert len(runs) == 3 and rows["run_id"].nunique() == 3
    assert len(rows) == 3 * 4 * 5                            # runs x cases x repeats
    timed = rows[rows["impl"] == "timed_parts"]
    assert (timed["time_library_s"] > 0).all() and (timed["stat_calls"] == 1).all()


def _recorded_run(run_id: str, calls: int) -> pd.DataFrame:
    """Recorded rows of a run (no timing run): two cases, the same times in every run, and a
    counter that tells the runs apart."""
    return pd.DataFrame([{"run_id": run_id, "impl": impl, "dataset": "uniform", "n": 20, "seed": 0, "repeat": r,
                          "status": "ok", "verdict": "exact", "time_s": 0.01 * (1 + r / 100), "stat_calls": calls}
                         for impl in ("steady", "timed_parts") for r in range(5)])


@pytest.fixture()
def recorded_store(tmp_path) -> Path:
    """A store of three recorded runs on one machine: the first counts 1 call, the others 2."""
    path = tmp_path / "recorded"
    for i, (run_id, calls) in enumerate([("run-a", 1), ("run-b", 2), ("run-c", 2)]):
        meta = {"run_id": run_id, "date": f"2024-01-0{i + 1}T00:00:00", "commit": f"{i + 1}" * 40,
                "machine_id": "m1"}
        assert Store(path).add_run(_recorded_run(run_id, calls), meta)
    return path


def test_compare_accepts_store_references(recorded_store, capsys):
    store = recorded_store
    assert main(["compare", f"{store}@latest~1", f"{store}@latest"]) == 0          # run-b vs run-c: alike
    assert "no regression in 2 compared case(s)" in capsys.readouterr().out
    assert main(["compare", f"{store}@run-a", f"{store}@latest"]) == 1             # 1 call -> 2: flagged
    assert "calls 1 -> 2" in capsys.readouterr().out
    assert main(["compare", f"{store}@{'1' * 8}", f"{store}@{'3' * 8}"]) == 1       # runs named by commit
    assert Store(store).resolve("2" * 8) == "run-b"
    capsys.readouterr()
    assert main(["compare", f"{store}@latest~3", f"{store}@latest"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "holds 3" in err
    assert main(["compare", f"{store}@nonsense", f"{store}@latest"]) == 2
    assert "no run matches 'nonsense'" in capsys.readouterr().err


def test_benched_runs_are_found_by_commit(store):
    runs = Store(store).runs()
    commit = runs["commit"].iloc[-1]
    if commit:                                           # a git checkout: runs are found by commit
        assert Store(store).resolve(commit[:8]) == runs["run_id"].iloc[-1]


def test_a_run_is_filed_once(store, tmp_path):
    results = sorted(store.parent.glob("r1.csv"))[0]
    assert Store(store).add_results(results) == []
    assert len(Store(store).runs()) == 3


def test_a_failed_filing_leaves_no_half_run(store, tmp_path, monkeypatch):
    copy = tmp_path / "copy"
    copy.mkdir()
    (copy / "runs.sqlite").write_bytes((store / "runs.sqlite").read_bytes())
    rows = Store(copy).results(Store(copy).resolve("latest")).assign(run_id="broken")
    rows["unstorable"] = [object()] * len(rows)               # sqlite cannot take it: the insert fails
    with pytest.raises(Exception):
        Store(copy).add_run(rows, {"run_id": "broken"})
    assert "broken" not in set(Store(copy).runs()["run_id"])
    with sqlite3.connect(copy / "runs.sqlite") as con:
        assert con.execute("select count(*) from results where run_id = 'broken'").fetchone()[0] == 0


def test_history_of_a_folder_that_is_no_store_is_one_line(tmp_path, capsys):
    assert main(["history", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "no run store here" in err
    (tmp_path / "file").write_text("x")
    assert main(["history", str(tmp_path / "file")]) == 2
