"""Argument types of the command line: each checks its value and says in one line what is wrong.

Used as argparse ``type=`` functions, so a bad value ends the command with exit status 2 and
one line on standard error (see :class:`OneLineParser`), never a traceback.
"""

from __future__ import annotations

import argparse
import math
import re
from typing import Callable, NoReturn, Optional

from vorobench.core.framing import Box, checked_box

__all__ = ["OneLineParser", "names", "sizes", "seeds", "positive_float", "non_negative_float", "positive_int",
           "non_negative_int", "fraction", "size", "bounds", "MAX_SIZE", "plain_help"]

#: Largest point count a command accepts: 10^8 points are 1.6 GB of coordinates before any
#: construction; beyond that a run cannot finish on any machine this tool targets.
MAX_SIZE = 100_000_000


class OneLineParser(argparse.ArgumentParser):
    """An argument parser whose errors are one line (``prog: error: ...``) and exit status 2."""

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {message} (see --help)\n")


def plain_help(docstring: Optional[str]) -> Optional[str]:
    """A module docstring as ``--help`` text: reST roles, literals and bold become plain words
    (``:mod:`a.b``` -> a.b, ````x```` -> x, ``**x**`` -> x); line breaks are kept."""
    if not docstring:
        return docstring
    text = re.sub(r":[a-z]+:`~?([^`]+)`", r"\1", docstring)
    text = re.sub(r"``([^`]+)``", r"\1", text)
    return re.sub(r"\*\*([^*]+)\*\*", r"\1", text)


def names(text: str) -> list[str]:
    """Comma-separated names, blanks dropped, each kept once in its first place."""
    items = [t.strip() for t in text.split(",") if t.strip()]
    if not items:
        raise argparse.ArgumentTypeError(f"no names in {text!r}")
    return list(dict.fromkeys(items))


def selection(asked: list[str], available: list[str], what: str) -> list[str]:
    """Names from a ``names`` list that may say ``all`` and exclude with a leading minus
    (``all,-near_grid``; a list of exclusions alone starts from all). ValueError on a name
    that is not available, excluded or not."""
    keep = [a for a in asked if not a.startswith("-")]
    drop = [a[1:] for a in asked if a.startswith("-")]
    unknown = [a for a in [*keep, *drop] if a != "all" and a not in available]
    if unknown:
        raise ValueError(f"unknown {what}(s) {', '.join(unknown)}; see `vorobench {what}s`")
    chosen = available if not keep or "all" in keep else keep
    chosen = [c for c in chosen if c not in drop]
    if not chosen:
        raise ValueError(f"no {what} left after excluding {', '.join(drop)}")
    return chosen


def _number(text: str, kind: Callable, what: str):
    try:
        value = kind(text)
    except (TypeError, ValueError, OverflowError):
        raise argparse.ArgumentTypeError(f"not {what}: {text!r}") from None
    if isinstance(value, float) and not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


def _at_least(text: str, kind: Callable, what: str, low, strict: bool):
    value = _number(text, kind, what)
    if value < low or (strict and value == low):
        raise argparse.ArgumentTypeError(f"must be {'greater than' if strict else 'at least'} {low}: {text!r}")
    return value


def positive_float(text: str) -> float:
    return _at_least(text, float, "a number", 0, strict=True)


def non_negative_float(text: str) -> float:
    return _at_least(text, float, "a number", 0, strict=False)


def positive_int(text: str) -> int:
    return _at_least(text, int, "a whole number", 1, strict=False)


def non_negative_int(text: str) -> int:
    return _at_least(text, int, "a whole number", 0, strict=False)


def fraction(text: str) -> float:
    """A number strictly between 0 and 1 (a significance level)."""
    value = _number(text, float, "a number")
    if not 0 < value < 1:
        raise argparse.ArgumentTypeError(f"must lie strictly between 0 and 1: {text!r}")
    return value


def bounds(text: str) -> Box:
    """A box XMIN,YMIN,XMAX,YMAX: four finite numbers with XMIN < XMAX and YMIN < YMAX."""
    parts = text.split(",")
    if len(parts) != 4:
        raise argparse.ArgumentTypeError(f"a box is four numbers XMIN,YMIN,XMAX,YMAX; got {text!r}")
    try:
        return checked_box([_number(part.strip(), float, "a number") for part in parts])
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def size(text: str) -> int:
    """One point count: 1000, 1e4, 10k, 1M; at most :data:`MAX_SIZE`."""
    low = text.strip().lower()
    mult = 1
    if low and low[-1] in "km":
        mult = 1000 if low[-1] == "k" else 1_000_000
        low = low[:-1]
    value = _number(low, float, "a size") * mult
    if value < 0 or value != int(value):
        raise argparse.ArgumentTypeError(f"size must be a non-negative whole number: {text!r}")
    if value > MAX_SIZE:
        raise argparse.ArgumentTypeError(f"size {text!r} is more than the {MAX_SIZE:,} points a run can hold")
    return int(value)


def sizes(text: str) -> list[int]:
    """Comma-separated point counts (see :func:`size`), each kept once, in order."""
    return list(dict.fromkeys(size(item) for item in names(text)))


def seeds(text: str) -> list[int]:
    """Comma-separated non-negative dataset seeds, each kept once."""
    return list(dict.fromkeys(non_negative_int(item) for item in names(text)))
