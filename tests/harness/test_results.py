"""The tidy results file: append case by case, new counter columns, resume keys, metadata, pandas."""

from __future__ import annotations

import json

import pandas as pd

from vorobench.harness import results, sysinfo
from vorobench.harness.results import ResultsFile


def _row(impl="a", n=10, repeat=0, status="ok", time_s=0.25, **extra):
    row = {"run_id": "r1", "impl": impl, "dataset": "uniform", "n": n, "seed": 0, "repeat": repeat,
           "status": status, "time_s": time_s}
    row.update(extra)
    return row


def test_append_then_read_with_pandas(tmp_path):
    store = ResultsFile(tmp_path / "r.csv")
    assert not store.exists() and store.done_keys() == set()
    store.append([_row(repeat=0, time_s=0.1), _row(repeat=1, time_s=0.2)])
    store.append([_row(impl="b", status="crashed", time_s=None, error="worker killed by SIGSEGV")])
    df = pd.read_csv(tmp_path / "r.csv")
    assert list(df["impl"]) == ["a", "a", "b"]
    assert list(df["time_s"][:2]) == [0.1, 0.2]
    assert pd.isna(df["time_s"][2]) and df["error"][2] == "worker killed by SIGSEGV"
    assert store.done_keys() == {("a", "uniform", 10, 0), ("b", "uniform", 10, 0)}


def test_new_counter_columns_rewrite_without_losing_rows(tmp_path):
    store = ResultsFile(tmp_path / "r.csv")
    store.append([_row(stat_events=5)])
    store.append([_row(impl="b", stat_circles=7)])
    store.append([_row(impl="c")])
    header = store.header()
    # fixed columns first, in their declared order, then the counters sorted
    assert header[:3] == ["run_id", "impl", "dataset"]
    assert header[-2:] == ["stat_circles", "stat_events"]
    df = results.load(tmp_path / "r.csv")
    assert list(df["impl"]) == ["a", "b", "c"]
    assert df["stat_events"].tolist()[0] == 5 and pd.isna(df["stat_events"][1])
    assert df["stat_circles"][1] == 7
    assert not list(tmp_path.glob(".*tmp"))          # the atomic rewrite leaves no temporary file


def test_floats_round_trip_exactly(tmp_path):
    store = ResultsFile(tmp_path / "r.csv")
    value = 0.1 + 0.2
    store.append([_row(time_s=value)])
    assert pd.read_csv(tmp_path / "r.csv")["time_s"][0] == value


def test_metadata_sidecar_keeps_every_run(tmp_path):
    out = tmp_path / "bench.csv"
    assert results.metadata_path(out).name == "bench.meta.json"
    results.append_run_metadata(out, {"run_id": "r1", **sysinfo.run_metadata()})
    results.append_run_metadata(out, {"run_id": "r2"})
    meta = json.loads(results.metadata_path(out).read_text())
    assert [r["run_id"] for r in meta["runs"]] == ["r1", "r2"]
    first = meta["runs"][0]
    for key in ("date", "commit", "python", "cpu", "cores", "hostname"):
        assert key in first
    for package in ("numpy", "scipy", "numba"):
        assert first["versions"][package]


def test_parquet_copy_matches_csv(tmp_path):
    store = ResultsFile(tmp_path / "r.csv")
    store.append([_row(repeat=i, time_s=0.1 * (i + 1), stat_events=3) for i in range(3)])
    pq = results.to_parquet(tmp_path / "r.csv")
    a, b = results.load(tmp_path / "r.csv"), pd.read_parquet(pq)
    assert list(a.columns) == list(b.columns)
    assert a["time_s"].tolist() == b["time_s"].tolist()


def test_sysinfo_reports_this_machine():
    import os

    meta = sysinfo.run_metadata()
    assert meta["cores"] == os.cpu_count()
    assert meta["python"].count(".") == 2
    assert isinstance(meta["cpu"], str) and meta["cpu"]
