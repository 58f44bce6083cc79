"""The tidy results table: one CSV row per case and repeat, appended case by case, plus metadata.

Layout: fixed leading columns (:data:`COLUMNS`), then the implementations' counters
(``stat_<name>``, integers) and the parts of the build time (``time_<phase>_s``) in sorted
order; :mod:`vorobench.judge.outcomes` says what each kind of column is. A failed case has one row with its status and no time.
A weighted case (a power diagram, ``bench --weights FAMILY``) names its weight family in the
``weights`` column, a case of disks (``bench --radii FAMILY``, docs/apollonius.md) its radius
family in the ``radii`` column; both are empty for an ordinary case and absent from files
written before them. They are part of the case key, so ordinary, weighted and disk cases never
meet in a comparison.
Every append is flushed and fsynced before the next case starts, and a change of columns
rewrites the file atomically. A crash (or a full disk) in the middle of an append can still
leave a torn last row: readers ignore it together with the rest of its case, and the next
append cuts it away, so the case runs again and the file stays readable. One run writes a
file at a time (:func:`writer_lock`). Run metadata (date, commit, versions, machine) lives in a
sidecar JSON, ``<results stem>.meta.json``, with one entry per run (``run_id`` column).
"""

from __future__ import annotations

import csv
import errno
import fcntl
import io
import json
import math
import os
from contextlib import contextmanager
from pathlib import Path
from typing import IO, Any, Iterable, Iterator, Optional

import pandas as pd

from vorobench.harness.atomic import replace_atomically
from vorobench.judge.outcomes import Status, check_table, upgrade_legacy

__all__ = [
    "COLUMNS",
    "STATUSES",
    "ResultsFile",
    "writer_lock",
    "load",
    "load_checked",
    "normalise",
    "metadata_path",
    "read_metadata",
    "append_run_metadata",
    "update_run_metadata",
    "to_parquet",
    "case_key",
    "CASE_KEY",
    "SITE_ATTRIBUTES",
    "dataset_label",
    "with_families_in_dataset",
]

#: Outcome of a case (:class:`vorobench.judge.outcomes.Status`). "skipped": not run because a smaller n
#: of it timed out or ran out of memory, or its extrapolated time exceeds the run's budget.
#: "lost": its (executor) worker died on every try, so nothing of the case came back.
STATUSES = tuple(s.value for s in Status)

#: Leading columns, in order; ``stat_*`` columns follow.
COLUMNS = (
    "run_id", "impl", "dataset", "weights", "radii", "n", "seed", "repeat", "status", "verdict", "certificate",
    "check_passed", "blame", "time_s", "cpu_s", "warmup_s", "setup_s", "check_s", "case_s",
    "n_points", "n_sites", "V", "E",
    "rss_base_mb", "peak_rss_mb", "mem_mb",
    "phase", "error", "verdict_detail", "finished_at", "host",
)

_TEXT = {"run_id", "impl", "dataset", "weights", "radii", "status", "verdict", "certificate", "check_passed", "blame",
         "phase", "error", "verdict_detail", "finished_at", "host"}

#: The columns every results table has (and that identify an ordinary case).
KEY = ("impl", "dataset", "n", "seed")

#: The columns naming what a case's sites carry besides their coordinates: the weight family
#: (power diagrams) or the radius family (disks); "" for none, and either may be absent.
SITE_ATTRIBUTES = ("weights", "radii")

#: The columns that identify a case.
CASE_KEY = KEY + SITE_ATTRIBUTES


def _family(value: Any) -> str:
    """A ``weights`` or ``radii`` cell as a family name: "" for none (missing, empty, NaN)."""
    if value is None or (isinstance(value, float) and value != value):
        return ""
    return str(value)


def case_key(row: dict) -> tuple[str, str, int, int]:
    """(impl, dataset, n, seed) of a row, typed (CSV gives strings back); the dataset of a
    weighted case or a case of disks is named with its family (:func:`dataset_label`)."""
    return (str(row["impl"]), dataset_label(str(row["dataset"]), _family(row.get("weights")),
                                            _family(row.get("radii"))),
            int(float(row["n"])), int(float(row["seed"])))


def dataset_label(dataset: str, weights: str = "", radii: str = "") -> str:
    """How reports and comparisons name the dataset of a case: ``uniform``; ``uniform (radii
    weights)`` for the power diagram of its points with ``radii`` weights; ``uniform (random
    radii)`` for the disks centred at its points with ``random`` radii."""
    families = [f"{family} {column}" for column, family in zip(SITE_ATTRIBUTES, (weights, radii)) if family]
    return f"{dataset} ({', '.join(families)})" if families else dataset


def with_families_in_dataset(df):
    """``df`` with the ``dataset`` of every weighted row and every row of disks renamed by
    :func:`dataset_label`, for the views that group cases by dataset (report, compare, trend):
    such a case is then a dataset of its own, never mixed with the ordinary one or with each
    other. Returns a copy."""
    df = df.copy()
    if not any(c in df.columns for c in SITE_ATTRIBUTES) or df.empty:
        return df
    families = pd.DataFrame({c: df[c].map(_family) if c in df.columns else "" for c in SITE_ATTRIBUTES}, index=df.index)
    carried = (families != "").any(axis=1)
    if carried.any():
        df["dataset"] = df["dataset"].astype(object)
        df.loc[carried, "dataset"] = [dataset_label(str(d), *named) for d, named in zip(
            df.loc[carried, "dataset"], families[carried].itertuples(index=False))]
    return df


def _ordered(columns: Iterable[str]) -> list[str]:
    cols = set(columns)
    lead = [c for c in COLUMNS if c in cols]
    rest = sorted(c for c in cols if c not in COLUMNS)
    return lead + rest


def _cell(value: Any) -> str:
    if value is None:
        return ""
    if isinstance(value, float):         # numpy's floats too: repr of a Python float, never "np.float64(...)"
        return "" if math.isnan(value) else repr(float(value))
    return str(value)


def _scan(data: bytes) -> list[tuple[int, list[str]]]:
    """The CSV records of ``data``, each with the byte offset where it starts (blank lines skipped).

    Lines are split on ``\\n`` only: a field with a line break is quoted and spans several lines,
    and the csv reader joins them; its ``line_num`` tells where each record ends.
    """
    pieces = data.split(b"\n")
    lines = [p + b"\n" for p in pieces[:-1]] + ([pieces[-1]] if pieces[-1] else [])
    starts = [0]
    for line in lines:
        starts.append(starts[-1] + len(line))
    # "replace": a crash can cut a multi-byte character in two; that row is dropped anyway.
    reader = csv.reader(line.decode("utf-8", "replace") for line in lines)
    records, consumed = [], 0
    for fields in reader:
        if fields:
            records.append((starts[consumed], fields))
        consumed = reader.line_num
    return records


def _intact_length(data: bytes) -> int:
    """How many leading bytes of a results CSV to keep: all of them unless the last row is torn.

    A torn row (no line end, or a field count other than the header's) is what a crash or a
    full disk leaves in the middle of an append. The rows written before it by the same append
    (same run and case) go with it, so that resuming runs the case again instead of keeping
    part of its repeats. When the torn row is too short to name its case, the last complete
    case of the file goes too: running a finished case again costs time, keeping half of one
    would be wrong.
    """
    if not data:
        return 0
    try:
        records = _scan(data)
    except csv.Error:
        # Damage in the middle (e.g. a bare carriage return), not a tear at the end: nothing to
        # repair, and cutting here could drop many rows; readers report the damage instead.
        return len(data)
    if not records:
        return len(data)
    header = records[0][1]
    start, last_fields = records[-1]
    if data.endswith(b"\n") and len(last_fields) == len(header):
        return len(data)
    if len(records) == 1:                          # the header itself is torn
        return 0
    where = [header.index(c) for c in ("run_id",) + CASE_KEY if c in header]

    def group(fields: list[str]) -> Optional[tuple[str, ...]]:
        # The last key field is complete only if the field after it was started.
        if not set(KEY) <= set(header) or len(fields) <= max(where) + 1:
            return None
        return tuple(fields[i] for i in where)

    cut = start
    target = group(last_fields) or (group(records[-2][1]) if len(records) > 2 else None)
    for start, fields in reversed(records[1:-1]):
        if target is None or group(fields) != target:
            break
        cut = start
    return cut


class ResultsFile:
    """A results CSV opened for reading what is done and appending what finishes.

    Reading ignores a torn last row (and the rest of its case); the first append cuts it away.
    Hold :func:`writer_lock` while appending, so that no other run writes the file meanwhile.
    """

    def __init__(self, path: str | os.PathLike) -> None:
        self.path = Path(path)
        self._repaired = False

    def exists(self) -> bool:
        return self.path.exists() and self.path.stat().st_size > 0

    def header(self) -> list[str]:
        """The current column names ([] if the file is missing or empty)."""
        if not self.exists():
            return []
        with self.path.open(newline="", encoding="utf-8") as f:
            return next(csv.reader(f), [])

    def rows(self) -> list[dict[str, str]]:
        """Every intact row as a dict of strings (for resuming; use :func:`load` for analysis)."""
        if not self.exists():
            return []
        data = self.path.read_bytes()
        try:
            text = data[:_intact_length(data)].decode("utf-8")
            return list(csv.DictReader(io.StringIO(text, newline="")))
        except (UnicodeDecodeError, csv.Error) as exc:
            raise ValueError(f"{self.path}: not a readable results CSV ({exc})") from None

    def done_keys(self) -> set[tuple[str, str, int, int]]:
        """Cases that already have a row, whatever their status."""
        return {case_key(r) for r in self.rows()}

    def drop_torn_tail(self) -> int:
        """Cut a torn last row (and the rest of its case) off the file; returns the bytes removed."""
        if not self.exists():
            return 0
        with self.path.open("r+b") as f:
            data = f.read()
            keep = _intact_length(data)
            if keep < len(data):
                f.truncate(keep)
                f.flush()
                os.fsync(f.fileno())
        return len(data) - keep

    def append(self, rows: list[dict[str, Any]]) -> None:
        """Append the rows of one finished case, durably, before the caller moves on."""
        if not rows:
            return
        if not self._repaired:
            # Once per opening: a torn row can only come from an earlier process; ours end whole.
            self.drop_torn_tail()
            self._repaired = True
        header = self.header()
        wanted = set().union(*(r.keys() for r in rows))
        if header and wanted <= set(header):
            with self.path.open("a", newline="", encoding="utf-8") as f:
                writer = csv.writer(f)
                for row in rows:
                    writer.writerow([_cell(row.get(c)) for c in header])
                f.flush()
                os.fsync(f.fileno())
            return
        # New columns (a counter not seen before): rewrite with the union of the columns.
        old = self.rows()
        columns = _ordered(set(header) | wanted)

        def write(f: IO[str]) -> None:
            writer = csv.writer(f)
            writer.writerow(columns)
            for row in old + rows:
                writer.writerow([_cell(row.get(c)) for c in columns])

        replace_atomically(self.path, write)


@contextmanager
def writer_lock(results_path: str | os.PathLike) -> Iterator[Path]:
    """Be the only run writing ``results_path`` while the block runs; refuse if another run is.

    Two runs appending to one file would each skip what the other had not finished yet and
    write the same cases twice (or lose rows in a rewrite). The lock is an ``flock`` on
    ``<results>.lock``, which holds our pid for the message the other run gets; the kernel
    drops it if we die, so a crash leaves no stale lock. Raises ValueError when another run
    holds it (the command line prints it as one line, exit status 2).
    """
    target = Path(results_path)
    lock_path = target.with_name(target.name + ".lock")
    lock_path.parent.mkdir(parents=True, exist_ok=True)
    while True:
        try:
            # O_NOFOLLOW: a symlink planted at the lock's name must not make us write elsewhere.
            fd = os.open(lock_path, os.O_RDWR | os.O_CREAT | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
        except OSError as exc:
            if exc.errno == errno.ELOOP:
                raise ValueError(f"{lock_path} is a symbolic link, not a lock file; remove it") from None
            raise
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 32).decode("ascii", "replace").strip() or "unknown"
            os.close(fd)
            raise ValueError(f"{target} is being written by another run (pid {holder}); "
                             "wait for it or choose another --out") from None
        # The last holder removes the file on release: if it did so between our open and our
        # flock, we hold a lock on a deleted file that guards nothing, so open the new one.
        try:
            now = os.stat(lock_path, follow_symlinks=False)
            mine = os.fstat(fd)
            current = (now.st_dev, now.st_ino) == (mine.st_dev, mine.st_ino)
        except FileNotFoundError:
            current = False
        if current:
            break
        os.close(fd)
    try:
        os.ftruncate(fd, 0)
        os.write(fd, str(os.getpid()).encode("ascii"))
        yield lock_path
    finally:
        lock_path.unlink(missing_ok=True)        # before unlocking: see the check above
        os.close(fd)


def _read(path: Path):
    if path.suffix == ".parquet":
        return pd.read_parquet(path)
    data = path.read_bytes()
    # A torn last row (a crash mid-append) is not a result: read what precedes it.
    return pd.read_csv(io.BytesIO(data[:_intact_length(data)]))


def _with_all_columns(df):
    df = upgrade_legacy(df)
    for column in COLUMNS:
        if column not in df.columns:
            df[column] = pd.Series(float("nan"), index=df.index, dtype=object if column in _TEXT else float)
    # "" rather than NaN for an ordinary case: the families are part of the case key, and pandas
    # groupby drops NaN keys.
    for column in SITE_ATTRIBUTES:
        df[column] = df[column].map(_family).astype(object)
    return df


def normalise(df):
    """A results frame from anywhere (a file, the run store) in today's schema: old columns
    upgraded, standard columns that are missing added, empty."""
    return _with_all_columns(df)


def load(path: str | os.PathLike):
    """The results as a pandas DataFrame (CSV or Parquet), failed cases included.

    Standard columns missing from the file (e.g. no case ever succeeded) are added, empty.
    """
    return _with_all_columns(_read(Path(path)))


def _refuse_foreign(path: Path) -> None:
    """A JSON file (pytest-benchmark's output, say) is named for what it is, not parsed as CSV."""
    with path.open("rb") as f:
        head = f.read(4096).lstrip()
    if not head.startswith(b"{") and path.suffix.lower() != ".json":
        return
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError):
        raise ValueError(f"{path}: not a results table (a .json file that is not valid JSON)") from None
    if isinstance(doc, dict) and "benchmarks" in doc and ("machine_info" in doc or "commit_info" in doc):
        raise ValueError(f"{path}: a pytest-benchmark file, not a vorobench results table; compare two of those "
                         "with `pytest-benchmark compare`, or time implementations with `vorobench bench`")
    raise ValueError(f"{path}: a JSON file, not a vorobench results table (.csv or .parquet from `vorobench bench`)")


def load_checked(path: str | os.PathLike):
    """:func:`load` for commands that judge a file: anything that is not a results table with at
    least one case is a ValueError that names the file and the problem in one line.

    Without it an empty, header-only or unrelated file reads as a table of zero cases (or of
    cases with no key), and a comparison or report of it "passes".
    """
    path = Path(path)
    if not path.exists():
        raise ValueError(f"{path}: no such file")
    if path.is_dir():
        raise ValueError(f"{path}: is a directory, not a results file")
    _refuse_foreign(path)
    try:
        df = _read(path)
    except pd.errors.EmptyDataError:
        raise ValueError(f"{path}: is empty, not a results file") from None
    except (OSError, ValueError) as exc:       # pandas' and pyarrow's parse errors are ValueErrors
        reason = " ".join(str(exc).split())[:200] or type(exc).__name__
        raise ValueError(f"{path}: cannot be read as a results table ({reason})") from None
    missing = [c for c in KEY + ("status",) if c not in df.columns]
    if missing:
        raise ValueError(f"{path}: not a results table (no {', '.join(missing)} column)")
    if df.empty:
        raise ValueError(f"{path}: has no result rows (header only)")
    numbers = df[["n", "seed"]].apply(pd.to_numeric, errors="coerce")
    bad = df[["impl", "dataset"]].isna().any(axis=1) | numbers.isna().any(axis=1)
    if bad.any():
        raise ValueError(f"{path}: {int(bad.sum())} of {len(df)} row(s) lack a case key "
                         f"(impl, dataset, n, seed), the first on data row {int(bad.to_numpy().argmax()) + 1}")
    df = _with_all_columns(df)
    check_table(df, str(path))
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
    try:
        meta = json.loads(p.read_text(encoding="utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{p}: not valid JSON metadata ({exc})") from None
    runs = meta.get("runs") if isinstance(meta, dict) else None
    if not isinstance(runs, list) or not all(isinstance(r, dict) for r in runs):
        raise ValueError(f"{p}: metadata without a list of runs")
    return meta


def _write_metadata(p: Path, meta: dict[str, Any]) -> None:
    replace_atomically(p, lambda f: f.write(json.dumps(meta, indent=2, default=str) + "\n"))


def append_run_metadata(results_path: str | os.PathLike, run: dict[str, Any]) -> Path:
    """Add one run's metadata (it carries its ``run_id``) to the sidecar, atomically."""
    p = metadata_path(results_path)
    meta = read_metadata(results_path)
    meta.setdefault("runs", []).append(run)
    _write_metadata(p, meta)
    return p


def update_run_metadata(results_path: str | os.PathLike, run_id: str, **fields: Any) -> None:
    """Add fields (end time, load at the end, counts) to the sidecar entry of run ``run_id``."""
    p = metadata_path(results_path)
    meta = read_metadata(results_path)
    for run in meta.get("runs", []):
        if run.get("run_id") == run_id:
            run.update(fields)
    _write_metadata(p, meta)
