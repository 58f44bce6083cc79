"""A run store: every benchmark run filed with its metadata in one SQLite file, for history and trends.

    vorobench bench ... --store DIR        # file the run when it ends
    vorobench history DIR [--json]         # one line per run
    vorobench compare DIR@latest~1 DIR@latest

``DIR/runs.sqlite`` holds two tables, both plain to query with pandas
(``pd.read_sql("select * from results", sqlite3.connect("DIR/runs.sqlite"))``):

* ``runs``: one row per run: ``run_id``, ``date``, ``commit``/``dirty`` of vorobench,
  ``machine_id`` (the hardware fingerprint that keeps timings apart), ``hostname``, the
  case counts, and ``meta``, the run's whole metadata as JSON (versions of every library,
  the commit and dirty flag of each implementation's code, plugins included).
* ``results``: the results table's rows (one per case and repeat), with their ``run_id``;
  a counter or timing column seen for the first time is added to the table.

A run is filed in one transaction: a crash leaves it filed or absent, never half there.
A reference ``DIR@REF`` names a run: ``latest``, ``latest~K`` (K runs before the latest),
a run id, or a commit (prefix) of vorobench or of an implementation's code, whose latest
run it means; ``#MACHINE`` after it keeps to the runs of one machine fingerprint.
"""

from __future__ import annotations

import json
import math
import re
import sqlite3
from contextlib import closing
from pathlib import Path
from typing import Any, Optional

import pandas as pd

from vorobench.harness import results
from vorobench.judge.outcomes import Status

__all__ = ["Store", "FILE_NAME", "is_reference", "split_reference", "load_reference"]

FILE_NAME = "runs.sqlite"

_RUN_COLUMNS = ("run_id", "date", "commit", "dirty", "machine_id", "hostname", "cpu", "cases", "failed",
                "complete", "meta")


def split_reference(text: str) -> Optional[tuple[Path, str]]:
    """``DIR@REF`` -> (DIR, REF) when DIR is a folder (reading it says if it is no store); None
    for anything else, such as a file whose name holds an ``@``."""
    if "@" not in text or Path(text).exists():
        return None
    folder, ref = text.rsplit("@", 1)
    if folder and Path(folder).is_dir():
        return Path(folder), ref or "latest"
    return None


def is_reference(text: str) -> bool:
    return split_reference(text) is not None


def load_reference(text: str):
    """The results rows and metadata of the run ``DIR@REF`` names: (DataFrame, metadata dict)."""
    parsed = split_reference(text)
    if parsed is None:
        raise ValueError(f"{text}: not a run store reference (DIR@latest, DIR@<run id>, DIR@<commit>)")
    store = Store(parsed[0])
    run_id = store.resolve(parsed[1])
    return store.results(run_id), store.metadata(run_id)


def _sql_type(dtype) -> str:
    kind = getattr(dtype, "kind", "O")
    return {"i": "INTEGER", "u": "INTEGER", "b": "INTEGER", "f": "REAL"}.get(kind, "TEXT")


def _plain(value: Any) -> Any:
    """A cell as SQLite takes it (numpy scalars to Python, NaN and NA to NULL)."""
    if value is None or value is pd.NA or value is pd.NaT:
        return None
    if hasattr(value, "item"):
        value = value.item()
    if isinstance(value, float) and math.isnan(value):
        return None
    return value


def _identifier(name: str) -> str:
    """``name`` as a quoted SQL identifier: any counter name (quotes included) is a column name."""
    if "\x00" in name:
        raise ValueError(f"column {name!r}: a NUL character cannot be in an SQLite column name")
    return '"' + name.replace('"', '""') + '"'


def _add_columns(con: sqlite3.Connection, rows) -> None:
    """Add the columns of ``rows`` that the results table lacks. SQLite column names ignore
    letter case: a name that differs from a stored one only in case is refused, not merged."""
    have = {r[1].lower(): r[1] for r in con.execute("pragma table_info(results)")}
    for column in map(str, rows.columns):
        stored = have.get(column.lower())
        if stored == column:
            continue
        if stored is not None:
            raise ValueError(f"column {column!r} differs from the store's column {stored!r} only in letter case, "
                             "which SQLite column names ignore")
        try:
            con.execute(f"alter table results add column {_identifier(column)} {_sql_type(rows[column].dtype)}")
        except sqlite3.OperationalError as exc:
            # Only a writer that bypassed the lock above could have added it; the column is there.
            if "duplicate column" not in str(exc):
                raise
        have[column.lower()] = column


class Store:
    """The run store in folder ``path`` (created on the first run filed)."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.file = self.path / FILE_NAME
        if self.path.exists() and not self.path.is_dir():
            raise ValueError(f"{self.path}: is a file, not a run store folder")

    def exists(self) -> bool:
        return self.file.is_file()

    def _connect(self, create: bool = False) -> sqlite3.Connection:
        if not create and not self.exists():
            raise ValueError(f"{self.path}: no run store here (no {FILE_NAME}); file runs with bench --store")
        self.path.mkdir(parents=True, exist_ok=True)
        con = sqlite3.connect(self.file, timeout=60)
        try:
            con.execute("create table if not exists runs (run_id text primary key, date text, \"commit\" text, "
                        "dirty integer, machine_id text, hostname text, cpu text, cases integer, failed integer, "
                        "complete integer, meta text)")
            con.execute("create table if not exists results (run_id text not null)")
            con.execute("create index if not exists results_run on results (run_id)")
        except sqlite3.DatabaseError as exc:
            con.close()
            raise ValueError(f"{self.file}: not a vorobench run store ({exc})") from None
        return con

    # ------------------------------------------------------------------ filing runs

    def add_results(self, results_path: str | Path) -> list[str]:
        """File every run of a results file (rows + the runs in its ``.meta.json``) that the
        store does not hold yet; returns the run ids filed."""
        frame = results.load_checked(results_path)
        runs = {str(r.get("run_id")): r for r in results.read_metadata(results_path).get("runs", [])}
        filed = []
        for run_id, rows in frame.groupby(frame["run_id"].astype(str), sort=False):
            meta = runs.get(run_id, {"run_id": run_id})
            if self.add_run(rows, meta):
                filed.append(run_id)
        return filed

    def add_run(self, rows, meta: dict[str, Any]) -> bool:
        """File one run (its rows and metadata) in one transaction; False if it is already filed."""
        run_id = str(meta.get("run_id") or rows["run_id"].iloc[0])
        rows = rows.assign(run_id=run_id).reset_index(drop=True)
        cases = rows.drop_duplicates([c for c in results.CASE_KEY if c in rows.columns])
        failed = int((cases["status"] != Status.OK).sum()
                     - cases["status"].isin([Status.UNSUPPORTED, Status.SKIPPED]).sum())
        record = {
            "run_id": run_id, "date": meta.get("date"), "commit": meta.get("commit"),
            "dirty": None if meta.get("dirty") is None else int(bool(meta.get("dirty"))),
            "machine_id": meta.get("machine_id"), "hostname": meta.get("hostname"), "cpu": meta.get("cpu"),
            "cases": int(len(cases)), "failed": failed,
            "complete": int(not meta.get("interrupted", False)),
            "meta": json.dumps(meta, default=str),
        }
        with closing(self._connect(create=True)) as con, con:
            # The write lock first: another process filing at once then waits here, instead of
            # adding the same column between our look at the table and our ALTER TABLE.
            con.execute("begin immediate")
            if con.execute("select 1 from runs where run_id = ?", (run_id,)).fetchone():
                return False
            _add_columns(con, rows)
            columns = list(rows.columns)
            marks = ", ".join("?" * len(columns))
            names = ", ".join(_identifier(c) for c in columns)
            con.executemany(f"insert into results ({names}) values ({marks})",
                            ([_plain(v) for v in row] for row in rows.itertuples(index=False, name=None)))
            con.execute(f"insert into runs ({', '.join(_identifier(c) for c in _RUN_COLUMNS)}) "
                        f"values ({', '.join('?' * len(_RUN_COLUMNS))})", [record[c] for c in _RUN_COLUMNS])
        return True

    # ------------------------------------------------------------------ reading

    def runs(self, machine_id: Optional[str] = None):
        """One row per run, oldest first (by date, then run id)."""
        with closing(self._connect()) as con:
            df = pd.read_sql("select * from runs order by date, run_id", con)
        if machine_id:
            df = df[df["machine_id"].fillna("").str.startswith(machine_id)]
        return df.reset_index(drop=True)

    def results(self, run_ids=None):
        """The results rows of the given runs (all runs when None), typed like ``results.load``."""
        with closing(self._connect()) as con:
            if run_ids is None:
                df = pd.read_sql("select * from results", con)
            else:
                ids = [run_ids] if isinstance(run_ids, str) else list(run_ids)
                df = pd.read_sql(f"select * from results where run_id in ({', '.join('?' * len(ids))})", con,
                                 params=ids)
        df = df.dropna(axis=1, how="all") if run_ids is not None else df
        return results.normalise(df)

    def metadata(self, run_id: str) -> dict[str, Any]:
        with closing(self._connect()) as con:
            row = con.execute("select meta from runs where run_id = ?", (run_id,)).fetchone()
        if row is None:
            raise ValueError(f"{self.path}: no run {run_id!r}")
        return json.loads(row[0] or "{}")

    def resolve(self, ref: str) -> str:
        """The run id a reference names (see the module docstring); ValueError if none or several."""
        ref, _, machine = ref.partition("#")
        runs = self.runs(machine_id=machine or None)
        where = f"{self.path}" + (f" (machine {machine})" if machine else "")
        if runs.empty:
            raise ValueError(f"{where}: holds no run")
        latest = re.fullmatch(r"latest(?:~(\d+))?", ref)
        if latest:
            back = int(latest.group(1) or 0)
            if back >= len(runs):
                raise ValueError(f"{where}: {ref} asks for run {back + 1} from the end, but it holds {len(runs)}")
            return str(runs["run_id"].iloc[-1 - back])
        if ref in set(runs["run_id"]):
            return ref
        if re.fullmatch(r"[0-9a-fA-F]{4,40}", ref):
            ref = ref.lower()
            hits = [r.run_id for r in runs.itertuples() if any(c.startswith(ref) for c in _commits(r))]
            if hits:
                return str(hits[-1])
        raise ValueError(f"{where}: no run matches {ref!r} (use latest, latest~K, a run id or a commit; "
                         f"`vorobench history {self.path}` lists them)")


def _commits(run) -> set[str]:
    """The commits a run was made of: vorobench's and every implementation's code."""
    found = {str(run.commit).lower()} if run.commit else set()
    try:
        meta = json.loads(run.meta or "{}")
    except json.JSONDecodeError:
        return found
    for info in (meta.get("implementations") or {}).values():
        if isinstance(info, dict) and info.get("commit"):
            found.add(str(info["commit"]).lower())
    return found
