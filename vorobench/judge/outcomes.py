"""The results schema: what each column of a results table is, and the one ranking of outcomes.

Four kinds of column, told apart by name:

* **counters** ``stat_<name>``: machine-independent integers an implementation counts (events,
  predicate calls). Equal code on equal input gives equal counters, so they gate exactly.
* **timings** ``time_s`` (the build) and ``time_<phase>_s`` (a part of it, e.g. the outside
  library's own call): seconds, which differ from run to run, so they gate statistically.
* **measurements**: other machine-dependent numbers (memory, set-up and check seconds).
* **identity and outcome**: the case key, status, verdict, messages.

An implementation fills ``stats`` with counters only (the rule: :mod:`vorobench.core.counters`),
and timings go through :func:`impls.base.record_timing` instead. ``Status`` and
``Verdict`` rank outcomes once for the runner, the report and the regression compare.
"""

from __future__ import annotations

import re
from enum import Enum
from typing import Optional

from vorobench.core.counters import DURATION_NAME

__all__ = [
    "Status",
    "Verdict",
    "OutcomeKind",
    "CertificateLevel",
    "VERDICT_RANK",
    "STATUS_RANK",
    "COUNTER_PREFIX",
    "counter_columns",
    "timing_columns",
    "timing_column",
    "verdict_rank",
    "status_rank",
    "upgrade_legacy",
    "check_table",
]

COUNTER_PREFIX = "stat_"


class Status(str, Enum):
    """How a benchmark case ended."""

    OK = "ok"
    UNSUPPORTED = "unsupported"    # the implementation declared the input out of its scope
    SKIPPED = "skipped"            # not run: a smaller n failed, or it would exceed the budget
    ERROR = "error"                # an exception in the build (or a broken contract)
    LOST = "lost"                  # its executor worker died on every try
    OOM = "oom"
    TIMEOUT = "timeout"
    CRASHED = "crashed"            # the process died (signal, exit)

    def __str__(self) -> str:
        return self.value


class Verdict(str, Enum):
    """What the judge said of a diagram, from best to worst (declaration order)."""

    EXACT = "exact"
    WITHIN_TOLERANCE = "within_tolerance"
    CERTIFIED = "certified"            # no comparison possible, but the diagram certifies
    NO_REFERENCE = "no_reference"
    UNSUPPORTED = "unsupported"
    SKIPPED = "skipped"                # not checked
    DIFFERS = "differs"
    NOT_CERTIFIED = "not_certified"
    CHECK_ERROR = "check_error"
    WRONG_SITES = "wrong_sites"
    INVALID_OUTPUT = "invalid_output"  # an executable printed what the protocol does not allow
    MUTATED_INPUT = "mutated_input"
    OOM = "oom"
    TIMEOUT = "timeout"
    CRASHED = "crashed"

    def __str__(self) -> str:
        return self.value


class CertificateLevel(str, Enum):
    """What the certifier says of one diagram, on its own (``vorobench.judge.certificate``).

    ``certified``: its topology is exactly the diagram of its sites (every decision checked with
    exact predicates) and its coordinates within tolerance; required of exact implementations.
    ``certified_within_tolerance``: it differs from that only at near-degenerate configurations
    (``NEAR_DEGENERATE_ULPS``); the standard for floating-point libraries.
    """

    CERTIFIED = "certified"
    WITHIN_TOLERANCE = "certified_within_tolerance"
    NOT_CERTIFIED = "not_certified"

    def __str__(self) -> str:
        return self.value


class OutcomeKind(str, Enum):
    """How one request to a sandbox ended (:class:`vorobench.judge.sandbox.Outcome`)."""

    OK = "ok"                      # it answered (the outcome's ``value``)
    ERROR = "error"                # the function raised
    CRASHED = "crashed"            # the process died or exited, or answered what the wire does not allow
    TIMEOUT = "timeout"
    OOM = "oom"

    def __str__(self) -> str:
        return self.value


#: Correctness rank of a verdict, 0 = exact; None = says nothing about correctness.
VERDICT_RANK: dict[str, Optional[int]] = {
    Verdict.EXACT: 0,
    Verdict.WITHIN_TOLERANCE: 1,
    Verdict.CERTIFIED: 1,
    Verdict.NO_REFERENCE: 1,
    Verdict.UNSUPPORTED: None,
    Verdict.SKIPPED: None,
    Verdict.DIFFERS: 2,
    Verdict.NOT_CERTIFIED: 3,
    Verdict.CHECK_ERROR: 3,
    Verdict.WRONG_SITES: 3,
    Verdict.INVALID_OUTPUT: 3,
    Verdict.MUTATED_INPUT: 4,
    Verdict.OOM: 4,
    Verdict.TIMEOUT: 4,
    Verdict.CRASHED: 5,
}

#: Rank of a status, 0 = ran; None = did not run by choice (declared or planned).
STATUS_RANK: dict[str, Optional[int]] = {
    Status.OK: 0, Status.UNSUPPORTED: None, Status.SKIPPED: None, Status.ERROR: 1, Status.LOST: 2, Status.OOM: 2,
    Status.TIMEOUT: 2, Status.CRASHED: 3,
}

assert set(VERDICT_RANK) == {v.value for v in Verdict} and set(STATUS_RANK) == {s.value for s in Status}


def _missing(value: object) -> bool:
    return value is None or value == "" or (isinstance(value, float) and value != value)


def verdict_rank(verdict: object) -> Optional[int]:
    """Rank of a verdict (0 = exact, higher = worse); an unknown verdict ranks as a failed check."""
    if _missing(verdict):
        return None
    return VERDICT_RANK.get(str(verdict), VERDICT_RANK[Verdict.CHECK_ERROR])


def status_rank(status: object) -> Optional[int]:
    """Rank of a status (0 = ran); an unknown status ranks as an error."""
    if _missing(status):
        return None
    return STATUS_RANK.get(str(status), STATUS_RANK[Status.ERROR])


def timing_column(phase: str) -> str:
    """The column of a part of the build time: ``library`` -> ``time_library_s``."""
    return f"time_{phase}_s"


def counter_columns(columns) -> list[str]:
    """The counter columns among ``columns``, sorted."""
    return sorted(c for c in columns if str(c).startswith(COUNTER_PREFIX))


def timing_columns(columns) -> list[str]:
    """The timing columns among ``columns``: ``time_s`` first, then its parts, sorted."""
    parts = sorted(c for c in columns if re.fullmatch(r"time_.+_s", str(c)))
    return (["time_s"] if "time_s" in columns else []) + parts


def upgrade_legacy(df):
    """Results written before counters and timings were told apart kept the outside libraries'
    ``library_s``/``convert_s`` seconds among the counters (``stat_library_s``): move every
    counter column whose name says it is a duration to its timing column. Returns ``df``."""
    renames = {}
    for column in counter_columns(df.columns):
        name = column[len(COUNTER_PREFIX):]
        if DURATION_NAME.search(name):
            phase = re.sub(r"_(s|ms|us|ns|sec|secs|seconds)$", "", name)
            target = timing_column(phase)
            if target not in df.columns:
                renames[column] = target
    return df.rename(columns=renames) if renames else df


def check_table(df, source: str = "results") -> None:
    """Refuse a table whose counters are not integers (ValueError naming the first bad cell):
    such a column would make the regression compare flag noise, or miss a change."""
    import numpy as np        # here, not at the top: the enums above are imported by light modules
    import pandas as pd       # (the command-line parser, the sandbox's isolation) that need no pandas

    for column in counter_columns(df.columns):
        values = pd.to_numeric(df[column], errors="coerce")
        bad = (values.notna() & (values != np.round(values))) | (values.isna() & df[column].notna())
        if bad.any():
            row = int(np.flatnonzero(bad.to_numpy())[0])
            raise ValueError(f"{source}: counter column {column} holds {str(df[column].iloc[row])!r} on data row "
                             f"{row + 1}; counters are machine-independent integers")
