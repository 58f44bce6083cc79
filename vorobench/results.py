"""The tidy results table: one CSV row per case and repeat, appended case by case, plus metadata.

Layout: fixed leading columns (:data:`COLUMNS`), then the implementations' counters
(``stat_<name>``) in sorted order. A failed case has one row with its status and no time.
Every append is flushed and fsynced before the next case starts, and a change of columns
rewrites the file atomically, so an interrupted run never leaves a damaged file. Run metadata
(date, commit, versions, machine) lives in a sidecar JSON, ``<results stem>.meta.json``, with
one entry per run (``run_id`` column).
"""

from __future__ import annotations

import csv
import json
import math
import os
from pathlib import Path
from typing import Any, Iterable, Optional

__all__ = [
    "COLUMNS",
    "STATUSES",
    "ResultsFile",
    "load",
    "metadata_path",
    "read_metadata",
    "append_run_metadata",
    "update_run_metadata",
    "to_parquet",
    "case_key",
]

#: Outcome of a case. "skipped": not run because a smaller n of it timed out or ran out of
#: memory, or its extrapolated time exceeds the run's budget. "lost": its (executor) worker died
#: on every try, so nothing of the case came back.
STATUSES = ("ok", "crashed", "timeout", "oom", "error", "unsupported", "skipped", "lost")

#: Leading columns, in order; ``stat_*`` columns follow.
COLUMNS = (
    "run_id", "impl", "dataset", "n", "seed", "repeat", "status", "verdict", "check_passed", "blame",
    "time_s", "warmup_s", "setup_s", "check_s", "case_s",
    "n_points", "n_sites", "V", "E",
    "rss_base_mb", "peak_rss_mb", "mem_mb",
    "phase", "error", "verdict_detail", "finished_at", "host",
)

_TEXT = {"run_id", "impl", "dataset", "status", "verdict", "check_passed", "blame", "phase", "error",
         "verdict_detail", "finished_at", "host"}

#: The columns that identify a case.
KEY = ("impl", "dataset", "n", "seed")


def case_key(row: dict) -> tuple[str, str, int, int]:
    """(impl, dataset, n, seed) of a row, typed (CSV gives strings back)."""
    return (str(row["impl"]), str(row["dataset"]), int(float(row["n"])), int(float(row["seed"])))


def _ordered(columns: Iterable[str]) -> list[str]:
    cols = set(columns)
    lead = [c for c in COLUMNS if c in cols]
    rest = sorted(c for c in cols if c not in COLUMNS)
    return lead + rest


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return "" if math.isnan(value) else repr(value)
    return str(value)


class ResultsFile:
    """A results CSV opened for reading what is done and appending what finishes."""

    def __init__(self, path: str | os.PathLike) -> None:
        self.path = Path(path)

    def exists(self) -> bool:
        return self.path.exists() and self.path.stat().st_size > 0

    def header(self) -> list[str]:
        """The current column names ([] if the file is missing or empty)."""
        if not self.exists():
            return []
        with self.path.open(newline="") as f:
            return next(csv.reader(f), [])

    def rows(self) -> list[dict[str, str]]:
        """Every row as a dict of strings (for resuming; use :func:`load` for analysis)."""
        if not self.exists():
            return []
        with self.path.open(newline="") as f:
            return list(csv.DictReader(f))

    def done_keys(self) -> set[tuple[str, str, int, int]]:
        """Cases that already have a row, whatever their status."""
        return {case_key(r) for r in self.rows()}

    def append(self, rows: list[dict[str, Any]]) -> None:
        """Append the rows of one finished case, durably, before the caller moves on."""
        if not rows:
            return
        header = self.header()
        wanted = set().union(*(r.keys() for r in rows))
        if header and wanted <= set(header):
            with self.path.open("a", newline="") as f:
                writer = csv.writer(f)
                for row in rows:
                    writer.writerow([_cell(row.get(c)) for c in header])
                f.flush()
                os.fsync(f.fileno())
            return
        # New columns (a counter not seen before): rewrite with the union of the columns.
        old = self.rows()
        columns = _ordered(set(header) | wanted)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        tmp = self.path.with_name(f".{self.path.name}.tmp")
        with tmp.open("w", newline="") as f:
            writer = csv.writer(f)
            writer.writerow(columns)
            for row in old + rows:
                writer.writerow([_cell(row.get(c)) for c in columns])
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, self.path)


def load(path: str | os.PathLike):
    """The results as a pandas DataFrame (CSV or Parquet), failed cases included.

    Standard columns missing from the file (e.g. no case ever succeeded) are added, empty.
    """
    import pandas as pd

    path = Path(path)
    df = pd.read_parquet(path) if path.suffix == ".parquet" else pd.read_csv(path)
    for column in COLUMNS:
        if column not in df.columns:
            df[column] = pd.Series(float("nan"), index=df.index, dtype=object if column in _TEXT else float)
    return df


def to_parquet(csv_path: str | os.PathLike, parquet_path: Optional[str | os.PathLike] = None) -> Path:
    """Write a Parquet copy of a results CSV (same table); returns its path."""
    csv_path = Path(csv_path)
    out = Path(parquet_path) if parquet_path else csv_path.with_suffix(".parquet")
    load(csv_path).to_parquet(out, index=False)
    return out


def metadata_path(results_path: str | os.PathLike) -> Path:
    """The sidecar JSON of a results file: ``results.csv`` -> ``results.meta.json``."""
    p = Path(results_path)
    return p.with_name(p.stem + ".meta.json")


def read_metadata(results_path: str | os.PathLike) -> dict[str, Any]:
    """The sidecar metadata ({"runs": [...]}), empty if there is none."""
    p = metadata_path(results_path)
    if not p.exists():
        return {"runs": []}
    return json.loads(p.read_text())


def append_run_metadata(results_path: str | os.PathLike, run: dict[str, Any]) -> Path:
    """Add one run's metadata (it carries its ``run_id``) to the sidecar, atomically."""
    p = metadata_path(results_path)
    meta = read_metadata(results_path)
    meta.setdefault("runs", []).append(run)
    p.parent.mkdir(parents=True, exist_ok=True)
    tmp = p.with_name(f".{p.name}.tmp")
    tmp.write_text(json.dumps(meta, indent=2, default=str) + "\n")
    os.replace(tmp, p)
    return p


def update_run_metadata(results_path: str | os.PathLike, run_id: str, **fields: Any) -> None:
    """Add fields (end time, load at the end, counts) to the sidecar entry of run ``run_id``."""
    p = metadata_path(results_path)
    meta = read_metadata(results_path)
    for run in meta.get("runs", []):
        if run.get("run_id") == run_id:
            run.update(fields)
    tmp = p.with_name(f".{p.name}.tmp")
    tmp.write_text(json.dumps(meta, indent=2, default=str) + "\n")
    os.replace(tmp, p)
