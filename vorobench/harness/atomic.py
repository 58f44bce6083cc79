"""Files that are either whole or absent: written to a fresh temporary name, then renamed."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import IO, Any, Callable

__all__ = ["replace_atomically", "write_json", "json_value"]


def replace_atomically(target: str | os.PathLike, write: Callable[[IO[Any]], None], *, binary: bool = False) -> None:
    """Write ``target`` through a new temporary file in its folder, then rename it over ``target``.

    A reader never sees half a file. ``mkstemp`` creates a file no one else can have prepared
    (O_EXCL, random name): a fixed name such as ``.results.csv.tmp`` could be a symlink planted
    by someone else, and writing it would overwrite whatever the link points to.
    """
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    try:
        with (os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", newline="", encoding="utf-8")) as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        # mkstemp makes the file private (0600); keep the permissions the file had, else the usual ones.
        os.chmod(tmp, target.stat().st_mode & 0o777 if target.exists() else 0o644)
        os.replace(tmp, target)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def json_value(x: Any) -> Any:
    """numpy scalars and arrays as plain JSON values; anything else by its text."""
    if hasattr(x, "tolist"):
        return x.tolist()
    return str(x)


def write_json(path: str | os.PathLike, data: dict) -> None:
    """Write ``data`` as JSON atomically: a reader never sees half a summary."""
    replace_atomically(path, lambda f: json.dump(data, f, indent=1, default=json_value))
