"""Read 2D point files (.npy, .csv, whitespace text) into (m, 2) float64 arrays.

Errors are ``FileNotFoundError`` (missing file) or ``ValueError`` whose message starts
with the file name and, for text formats, the 1-based line number of the bad line.
"""

from __future__ import annotations

import csv
import io
import math
import os
from collections.abc import Iterable, Iterator
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

__all__ = ["TEXT_SUFFIXES", "load"]

#: Suffixes read as whitespace-separated text (any suffix other than .npy/.csv is too).
TEXT_SUFFIXES = (".txt", ".xy", ".pts")

Row = tuple[int, list[str]]


def load(path: str | os.PathLike[str]) -> NDArray[np.float64]:
    """Load points from ``path`` by suffix: .npy, .csv, else whitespace-separated text."""
    p = Path(path)
    if not p.exists():
        raise FileNotFoundError(f"{p}: point file not found")
    if not p.is_file():
        raise ValueError(f"{p}: not a regular file")
    if p.suffix.lower() == ".npy":
        return _load_npy(p)
    try:
        text = p.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{p}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    if p.suffix.lower() == ".csv":
        return parse_rows(_csv_rows(text), p)
    return parse_rows(_whitespace_rows(text), p)


def _load_npy(p: Path) -> NDArray[np.float64]:
    """Read a .npy array of shape (m, 2) (or an empty array) with a real numeric dtype."""
    try:
        arr = np.load(p, allow_pickle=False)
    except (ValueError, OSError, EOFError) as exc:
        raise ValueError(f"{p}: cannot read .npy file: {exc}") from None
    if not isinstance(arr, np.ndarray):
        raise ValueError(f"{p}: expected a single .npy array")
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{p}: expected a real numeric array, got dtype {arr.dtype}")
    if arr.size == 0:
        return np.zeros((0, 2), dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{p}: expected an array of shape (m, 2), got {arr.shape}")
    out = np.ascontiguousarray(arr, dtype=np.float64)
    bad = ~np.isfinite(out)
    if bad.any():
        row = int(np.argwhere(bad)[0][0])
        raise ValueError(f"{p}: non-finite value in row {row}")
    return out


def _csv_rows(text: str) -> Iterator[Row]:
    """Yield (line number, stripped fields) of CSV records, skipping blank and # lines."""
    reader = csv.reader(io.StringIO(text, newline=""))
    start = 1
    for record in reader:
        fields = [f.strip() for f in record]
        line, start = start, reader.line_num + 1
        if not any(fields) or fields[0].startswith("#"):
            continue
        yield line, fields


def _whitespace_rows(text: str) -> Iterator[Row]:
    """Yield (line number, fields) of whitespace-separated lines; '#' starts a comment."""
    for line_no, line in enumerate(text.splitlines(), start=1):
        fields = line.split("#", 1)[0].split()
        if fields:
            yield line_no, fields


def _is_number(field: str) -> bool:
    """True if ``field`` parses as a Python float (including nan/inf)."""
    try:
        float(field)
    except ValueError:
        return False
    return True


def _header_columns(p: Path, line: int, names: list[str]) -> tuple[int, int]:
    """Return the (x, y) column indices selected by a header row."""
    lowered = [n.lower() for n in names]
    if "x" in lowered and "y" in lowered:
        if lowered.count("x") > 1 or lowered.count("y") > 1:
            raise ValueError(f"{p}:{line}: header names column x or y more than once: {names}")
        return lowered.index("x"), lowered.index("y")
    if len(names) == 2:
        return 0, 1
    raise ValueError(
        f"{p}:{line}: header has {len(names)} columns {names}; "
        "expected 2 columns or columns named x and y"
    )


def parse_rows(rows: Iterable[Row], path: str | os.PathLike[str]) -> NDArray[np.float64]:
    """Turn (line, fields) rows into points; the first row is a header if nothing in it is numeric."""
    p = Path(path)
    values: list[float] = []
    width, cx, cy = 2, 0, 1
    first = True
    for line, fields in rows:
        if first:
            first = False
            if not any(_is_number(f) for f in fields):
                width = len(fields)
                cx, cy = _header_columns(p, line, fields)
                continue
        if len(fields) != width:
            raise ValueError(f"{p}:{line}: expected {width} columns, found {len(fields)}")
        for col in (cx, cy):
            try:
                v = float(fields[col])
            except ValueError:
                raise ValueError(
                    f"{p}:{line}: non-numeric value {fields[col]!r} in column {col + 1}"
                ) from None
            if not math.isfinite(v):
                raise ValueError(f"{p}:{line}: non-finite value {fields[col]!r} in column {col + 1}")
            values.append(v)
    return np.array(values, dtype=np.float64).reshape(-1, 2)
