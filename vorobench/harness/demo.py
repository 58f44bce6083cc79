"""The main job's plan: which implementations, datasets and sizes the demo runs.

The command line is :mod:`vorobench.cli.demo`; its help text describes the behaviour."""

from __future__ import annotations

from typing import Iterable, Sequence

import datasets_gen
import impls

__all__ = ["own_implementations", "demo_implementations", "DEMO_DATASETS", "FULL_DATASETS",
           "DEMO_REFERENCES", "demo_sizes", "size_notes", "skipped_notes"]

#: Representative datasets: generic, clustered, exact degeneracies, big offset (the default).
DEMO_DATASETS = ("uniform", "clusters", "grid", "cocircular", "huge_offset")

#: ``--full``: two more (non-uniform, repeated rows).
FULL_DATASETS = ("uniform", "normal", "clusters", "grid", "cocircular", "duplicates", "huge_offset")

#: Outside libraries drawn as reference lines when installed (the ``peers`` extra).
DEMO_REFERENCES = ("triangle", "cgal", "boost", "geos")

#: Sizes when several implementations share the time; one more decade when qhull is alone.
_SIZES = (1_000, 3_000, 10_000)
_SIZES_ALONE = (1_000, 3_000, 10_000, 30_000, 100_000)

#: ``--full``: half a decade more.
_FULL_SIZES = (1_000, 3_000, 10_000, 30_000)
_FULL_SIZES_ALONE = (1_000, 3_000, 10_000, 30_000, 100_000, 300_000)


def own_implementations() -> list[str]:
    """The implementations written in this project (they declare ``kind="own"``)."""
    return impls.of_kind("own")


def demo_implementations() -> list[str]:
    """Own implementations plus the installed outside references of ``DEMO_REFERENCES``."""
    available = impls.available()
    return own_implementations() + [name for name in DEMO_REFERENCES if name in available]


def demo_sizes(n_impls: int, full: bool = False) -> tuple[int, ...]:
    """The size ladder: three sizes over a decade (four with ``full``), more when only one
    method runs."""
    if full:
        return _FULL_SIZES_ALONE if n_impls <= 1 else _FULL_SIZES
    return _SIZES_ALONE if n_impls <= 1 else _SIZES


def size_notes(datasets: Sequence[str], sizes: Sequence[int]) -> list[str]:
    """One line per dataset whose sizes are not what was asked: how many points each n gives,
    and which n are not run because they give the same points as a smaller one."""
    notes = []
    for d in datasets:
        actual, same = [], []
        seen: dict[int, int] = {}
        for n in sorted(set(sizes)):
            rows = datasets_gen.actual_n(d, n)
            if rows in seen:
                same.append(f"n={n} (the same {rows} points as n={seen[rows]})")
                continue
            seen[rows] = n
            if rows != n:
                actual.append(f"n={n} runs {rows} points")
        if actual or same:
            notes.append(f"{d}: " + "; ".join(actual + ([f"not run: {', '.join(same)}"] if same else [])))
    return notes


def skipped_notes(rows: Iterable[dict]) -> list[str]:
    """One line per case the run skipped or could not run, with its reason (the rows of the
    results file)."""
    out = []
    for r in rows:
        status = str(r.get("status") or "")
        if status in ("skipped", "unsupported"):
            why = str(r.get("error") or r.get("verdict_detail") or "no reason recorded")
            out.append(f"{r.get('impl')} on {r.get('dataset')} n={r.get('n')}: {status}: {why}")
    return list(dict.fromkeys(out))
