"""Read 2D point files (.npy, .csv, whitespace text) into (m, 2) float64 arrays.

Errors are ``FileNotFoundError`` (missing file) or ``ValueError`` whose message starts
with the file name and, for text formats, the 1-based line number of the bad line.

Only a regular file of at most :data:`MAX_FILE_BYTES` is read (never a device such as
``/dev/zero`` nor a FIFO, which would fill memory or wait for ever), and an integer that
float64 cannot hold exactly is refused, not rounded onto its neighbour. The helpers that
enforce this (:func:`open_regular_file`, :func:`read_text`, :func:`read_npy`,
:func:`exact_float`, :func:`first_inexact_integer`, :func:`number_table`) serve other
loaders of numbers too (the weights of ``--weights file:PATH``).
"""

from __future__ import annotations

import csv
import io
import math
import os
import re
import stat
from collections.abc import Iterable, Iterator
from pathlib import Path
from typing import BinaryIO, Optional

import numpy as np
from numpy.typing import NDArray

__all__ = ["TEXT_SUFFIXES", "MAX_FILE_BYTES", "load", "load_weights", "load_disks", "open_regular_file", "read_text", "read_npy", "exact_float",
           "first_inexact_integer", "number_table"]

#: Suffixes read as whitespace-separated text (any suffix other than .npy/.csv is too).
TEXT_SUFFIXES = (".txt", ".xy", ".pts")

#: The largest file read (bytes): a bigger one is refused before it fills memory.
MAX_FILE_BYTES = 1 << 30

#: An integer literal (Python's: digits, underscores between them, a sign).
_INTEGER = re.compile(r"[+-]?\d+(?:_\d+)*")

Row = tuple[int, list[str]]


def load(path: str | os.PathLike[str]) -> NDArray[np.float64]:
    """Load points from ``path`` by suffix: .npy, .csv, else whitespace-separated text."""
    p = Path(path)
    if p.suffix.lower() == ".npy":
        return _load_npy(p)
    text = read_text(p)
    if p.suffix.lower() == ".csv":
        return parse_rows(_csv_rows(text), p)
    return parse_rows(_whitespace_rows(text), p)


def load_weights(path: str | os.PathLike[str]) -> NDArray[np.float64]:
    """One weight per point from ``.npy`` (a 1-D array) or text (one number per line, or one
    line of comma-separated numbers). Read as :func:`load` reads points: only a regular file of
    bounded size, and no integer float64 cannot hold exactly (it is refused, never rounded)."""
    path = Path(path)
    try:
        if path.suffix.lower() == ".npy":
            w = read_npy(path, "weights file")
            inexact = first_inexact_integer(w)
            if inexact is not None:
                raise ValueError(f"{path}: integer {inexact[1]} at index {', '.join(map(str, inexact[0]))} "
                                 f"has no exact float64 value (it would be read as {float(inexact[1])!r})")
        else:
            w = number_table(read_text(path, "weights file"), path)
            if 1 in w.shape or w.size == 0:     # a column, a single row or nothing: the list of weights
                w = w.ravel()
    except FileNotFoundError:
        raise ValueError(f"{path}: no such weights file") from None
    w = np.asarray(w, dtype=np.float64)
    if w.ndim != 1:
        raise ValueError(f"{path}: weights must be one number per point, got an array of shape {w.shape}")
    return w


def load_disks(path: str | os.PathLike[str]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``(centres (m, 2), radii (m,))`` of the disks in ``path``: ``.npy`` of shape (m, 3), or text
    with one disk ``x y r`` per line (fields separated by spaces, tabs or commas; blank lines and
    ``#`` comments skipped). Read as :func:`load` reads points; a radius must be finite and
    >= 0 (a ValueError names the file and the line, or the row, otherwise)."""
    path = Path(path)
    try:
        if path.suffix.lower() == ".npy":
            table = read_npy(path, "disk file")
            if table.dtype.kind not in "iuf":
                raise ValueError(f"{path}: expected a real numeric array, got dtype {table.dtype}")
            inexact = first_inexact_integer(table)
            if inexact is not None:
                raise ValueError(f"{path}: integer {inexact[1]} at index {', '.join(map(str, inexact[0]))} "
                                 f"has no exact float64 value (it would be read as {float(inexact[1])!r})")
            table = np.asarray(table, dtype=np.float64)
            if table.size == 0:
                table = table.reshape(0, 3)
            if table.ndim != 2 or table.shape[1] != 3:
                raise ValueError(f"{path}: expected an array of shape (m, 3) (x, y, r per disk), got {table.shape}")
            where = [f"{path}: row {i}" for i in range(table.shape[0])]
        else:
            table, where = _disk_rows(read_text(path, "disk file"), path)
    except FileNotFoundError:
        raise ValueError(f"{path}: no such disk file") from None
    for row, place in zip(table, where):
        if not np.isfinite(row).all():
            raise ValueError(f"{place}: non-finite value")
        if row[2] < 0:
            raise ValueError(f"{place}: negative radius {float(row[2])!r}")
    return np.ascontiguousarray(table[:, :2]), np.ascontiguousarray(table[:, 2])


def _disk_rows(text: str, path: Path) -> tuple[NDArray[np.float64], list[str]]:
    """The ``x y r`` rows of a disk file's text, and where each came from (file:line)."""
    rows: list[list[float]] = []
    where: list[str] = []
    for line_no, line in enumerate(text.splitlines(), start=1):
        content = line.split("#", 1)[0].strip()
        if not content:
            continue
        # commas separate fields where there are any (an empty field is an error), else spaces
        fields = [f.strip() for f in content.split(",")] if "," in content else content.split()
        if len(fields) != 3:
            raise ValueError(f"{path}:{line_no}: expected 3 numbers (x y r), found {len(fields)}")
        try:
            rows.append([_field_value(f, col) for col, f in enumerate(fields)])
        except ValueError as exc:
            raise ValueError(f"{path}:{line_no}: {exc}") from None
        where.append(f"{path}:{line_no}")
    return np.array(rows, dtype=np.float64).reshape(len(rows), 3), where


def open_regular_file(path: str | os.PathLike[str], what: str = "point file") -> BinaryIO:
    """``path`` opened for binary reading if it is a regular file of at most :data:`MAX_FILE_BYTES`.

    FileNotFoundError if it is missing; ValueError if it is anything else (a directory, a
    device such as ``/dev/zero``, a FIFO: read, they never end or never start) or too large.
    The type is checked before opening (opening some devices acts on them) and again on the
    open file, which is what is read, whatever the path names by then.
    """
    p = Path(path)
    try:
        _check_regular(p, os.stat(p))
        # O_NONBLOCK: a FIFO put in the file's place meanwhile opens at once instead of waiting for a writer.
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0))
    except FileNotFoundError:
        raise FileNotFoundError(f"{p}: {what} not found") from None
    try:
        _check_regular(p, os.fstat(fd))
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def _check_regular(p: Path, st: os.stat_result) -> None:
    """ValueError unless ``st`` is a regular file of at most :data:`MAX_FILE_BYTES`."""
    if not stat.S_ISREG(st.st_mode):
        raise ValueError(f"{p}: not a regular file")
    if st.st_size > MAX_FILE_BYTES:
        raise ValueError(f"{p}: {st.st_size} bytes, more than the {MAX_FILE_BYTES} read from one file")


def read_text(path: str | os.PathLike[str], what: str = "point file") -> str:
    """The UTF-8 text of a regular file (see :func:`open_regular_file`), a byte-order mark dropped."""
    p = Path(path)
    with open_regular_file(p, what) as f:
        data = f.read(MAX_FILE_BYTES + 1)      # a file that says it is small may still grow while read
    if len(data) > MAX_FILE_BYTES:
        raise ValueError(f"{p}: more than the {MAX_FILE_BYTES} bytes read from one file")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ValueError(f"{p}: not UTF-8 text ({exc.reason} at byte {exc.start})") from None


def read_npy(path: str | os.PathLike[str], what: str = "point file") -> np.ndarray:
    """The array of a regular .npy file (see :func:`open_regular_file`); ValueError for anything
    else, a header announcing more data than the file holds included (it would be allocated first)."""
    p = Path(path)
    with open_regular_file(p, what) as f:
        try:
            _check_npy_fits(f, os.fstat(f.fileno()).st_size)
            arr = np.load(f, allow_pickle=False)
        except (ValueError, OSError, EOFError) as exc:
            raise ValueError(f"{p}: cannot read .npy file: {exc}") from None
    if not isinstance(arr, np.ndarray):
        raise ValueError(f"{p}: expected a single .npy array")
    return arr


def _check_npy_fits(f: BinaryIO, size: int) -> None:
    """ValueError unless the .npy header at the start of ``f`` announces at most the data that
    follows it in a file of ``size`` bytes; ``f`` is left at its start."""
    fmt = np.lib.format
    version = fmt.read_magic(f)
    if version == (1, 0):
        shape, _, dtype = fmt.read_array_header_1_0(f)
    elif version == (2, 0):
        shape, _, dtype = fmt.read_array_header_2_0(f)
    else:                       # 3.0 only adds UTF-8 names of record fields: no array of numbers needs it
        raise ValueError(f".npy format version {version[0]}.{version[1]} is not read here")
    needed = math.prod(shape) * dtype.itemsize
    if needed > size - f.tell():
        raise ValueError(f"its header announces shape {shape} of {dtype} ({needed} bytes); "
                         f"the file holds {size - f.tell()}")
    f.seek(0)


def exact_float(field: str) -> float:
    """``float(field)``, except that an integer float64 cannot hold exactly (beyond 2**53, most
    are rounded to a neighbour) is a ValueError naming it rather than a silent change of value."""
    value = float(field)
    if _INTEGER.fullmatch(field.strip()):
        whole = int(field)
        if not math.isfinite(value) or value != whole:     # int == float compares exactly
            raise ValueError(f"integer {field.strip()} has no exact float64 value (it would be read as {value!r})")
    return value


def first_inexact_integer(arr: np.ndarray) -> Optional[tuple[tuple[int, ...], int]]:
    """(index, value) of the first integer of ``arr`` that float64 cannot hold exactly, or None
    (always None for floats and for integers of 32 bits or less)."""
    if arr.dtype.kind not in "iu" or arr.dtype.itemsize <= 4 or arr.size == 0:
        return None
    as_float = arr.astype(np.float64)
    # Rounding up to 2**63 (2**64 unsigned) leaves the type's range: no value in it has that float.
    in_range = as_float < float(np.iinfo(arr.dtype).max)
    back = np.where(in_range, as_float, 0.0).astype(arr.dtype)
    inexact = ~in_range | (back != arr)
    if not inexact.any():
        return None
    index = tuple(int(i) for i in np.argwhere(inexact)[0])
    return index, int(arr[index])


def number_table(text: str, path: str | os.PathLike[str]) -> NDArray[np.float64]:
    """The numbers of comma-separated text as a (rows, columns) array, one row per line (blank
    lines and ``#`` comments skipped); ValueError naming file and line for a value that is not
    a number or an inexact integer (see :func:`exact_float`), or a row of another width."""
    p = Path(path)
    rows: list[list[float]] = []
    for line_no, line in enumerate(text.splitlines(), start=1):
        content = line.split("#", 1)[0].strip()
        if not content:
            continue
        fields = [f.strip() for f in content.split(",")]
        if rows and len(fields) != len(rows[0]):
            raise ValueError(f"{p}:{line_no}: expected {len(rows[0])} columns, found {len(fields)}")
        try:
            rows.append([_field_value(f, col) for col, f in enumerate(fields)])
        except ValueError as exc:
            raise ValueError(f"{p}:{line_no}: {exc}") from None
    width = len(rows[0]) if rows else 0
    return np.array(rows, dtype=np.float64).reshape(len(rows), width)


def _field_value(field: str, col: int) -> float:
    """The number in ``field`` (of 0-based column ``col``); ValueError saying what is wrong with it."""
    try:
        return exact_float(field)
    except ValueError as exc:
        if not _is_number(field):
            raise ValueError(f"non-numeric value {field!r} in column {col + 1}") from None
        raise ValueError(f"{exc} in column {col + 1}") from None


def _load_npy(p: Path) -> NDArray[np.float64]:
    """Read a .npy array of shape (m, 2) (or an empty array) with a real numeric dtype."""
    arr = read_npy(p)
    if arr.dtype.kind not in "iuf":
        raise ValueError(f"{p}: expected a real numeric array, got dtype {arr.dtype}")
    if arr.size == 0:
        return np.zeros((0, 2), dtype=np.float64)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{p}: expected an array of shape (m, 2), got {arr.shape}")
    inexact = first_inexact_integer(arr)
    if inexact is not None:
        (row, col), value = inexact
        raise ValueError(f"{p}: integer {value} in row {row}, column {col + 1} has no exact float64 value "
                         f"(it would be read as {float(value)!r})")
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
                v = _field_value(fields[col], col)
            except ValueError as exc:
                raise ValueError(f"{p}:{line}: {exc}") from None
            if not math.isfinite(v):
                raise ValueError(f"{p}:{line}: non-finite value {fields[col]!r} in column {col + 1}")
            values.append(v)
    return np.array(values, dtype=np.float64).reshape(-1, 2)
