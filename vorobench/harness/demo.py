"""The main job's plan: which implementations, datasets and sizes the demo runs.

The command line is :mod:`vorobench.cli.demo`; its help text describes the behaviour."""

from __future__ import annotations


import impls

__all__ = ["own_implementations", "demo_implementations", "DEMO_DATASETS",
           "DEMO_REFERENCES", "demo_sizes"]

#: Representative datasets: generic, non-uniform, clustered, exact degeneracies, big offset.
DEMO_DATASETS = ("uniform", "normal", "clusters", "grid", "cocircular", "duplicates", "huge_offset")

#: Outside libraries drawn as reference lines when installed (the ``peers`` extra).
DEMO_REFERENCES = ("triangle", "cgal", "boost", "geos")

#: Sizes when several implementations share the time; one more decade when qhull is alone.
_SIZES = (1_000, 3_000, 10_000, 30_000)
_SIZES_ALONE = (1_000, 3_000, 10_000, 30_000, 100_000, 300_000)


def own_implementations() -> list[str]:
    """The implementations written in this project (they declare ``kind="own"``)."""
    return impls.of_kind("own")


def demo_implementations() -> list[str]:
    """Own implementations plus the installed outside references of ``DEMO_REFERENCES``."""
    available = impls.available()
    return own_implementations() + [name for name in DEMO_REFERENCES if name in available]


def demo_sizes(n_impls: int) -> tuple[int, ...]:
    """The size ladder: four sizes over 1.5 decades, two more when only one method runs."""
    return _SIZES_ALONE if n_impls <= 1 else _SIZES
