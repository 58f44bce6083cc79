"""Named, seeded 2D point-set generators and point-file loaders for vorobench.

    >>> import datasets_gen as dg
    >>> dg.available()[:3]
    ['uniform', 'disk', 'normal']
    >>> dg.generate("grid", 10, seed=1).shape      # grids round n up to a square
    (16, 2)
    >>> dg.actual_n("grid", 10)
    16

``generate(name, n, seed)`` is deterministic: the same arguments give bit-identical
float64 arrays on every run and machine (a fresh ``numpy.random.default_rng(seed)`` is
passed to the family's generator, which uses only platform-stable operations).

``weights(family, points, seed)`` draws site weights for power diagrams from one of
``WEIGHT_FAMILIES`` (``radii``, ``equal``, ``integer``, ``hidden``), just as deterministic;
``radii(family, points, seed)`` draws disk radii for Apollonius diagrams from one of
``RADIUS_FAMILIES``, and ``load_disks(PATH)`` reads disks from an ``x y r`` file.

A name of the form ``file:PATH`` loads points with ``load(PATH)`` and returns its first
``min(n, rows)`` rows; the seed is ignored.
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .loaders import load, load_disks, load_weights
from .radius_families import RADIUS_FAMILIES, radii
from .registry import DATASETS, Dataset, Family, get
from .weight_families import WEIGHT_FAMILIES, weights

__all__ = [
    "DATASETS",
    "FILE_PREFIX",
    "RADIUS_FAMILIES",
    "WEIGHT_FAMILIES",
    "Dataset",
    "Family",
    "actual_n",
    "available",
    "describe",
    "generate",
    "load",
    "load_disks",
    "load_weights",
    "radii",
    "weights",
]

#: Prefix of dataset names that refer to a point file instead of a generator.
FILE_PREFIX = "file:"


def available(family: Family | None = None) -> list[str]:
    """Return the registered dataset names (random families first), optionally of one family."""
    if family is not None and family not in ("random", "degenerate"):
        raise ValueError(f"unknown family {family!r}; expected 'random' or 'degenerate'")
    return [name for name, d in DATASETS.items() if family is None or d.family == family]


def describe(name: str) -> str:
    """Return the one-line description of dataset ``name``."""
    path = _file_path(name)
    if path is not None:
        return f"points loaded from {path}"
    return get(name).description


def _check_int(value: Any, what: str) -> int:
    """Return ``value`` as a non-negative int, or raise ValueError (bools and floats rejected)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{what} must be a non-negative integer, got {value!r}")
    if value < 0:
        raise ValueError(f"{what} must be a non-negative integer, got {value!r}")
    return int(value)


def _file_path(name: Any) -> str | None:
    """Return PATH for a ``file:PATH`` name, else None."""
    if isinstance(name, str) and name.startswith(FILE_PREFIX):
        path = name[len(FILE_PREFIX):]
        if not path:
            raise ValueError(f"dataset name {name!r} has an empty file path")
        return path
    return None


def generate(name: str, n: int, seed: int = 0) -> NDArray[np.float64]:
    """Return the (actual_n(name, n), 2) float64 C-contiguous points of dataset ``name``."""
    n = _check_int(n, "n")
    seed = _check_int(seed, "seed")
    path = _file_path(name)
    if path is not None:
        return np.ascontiguousarray(load(path)[:n])
    dataset = get(name)
    points = dataset.generate(n, np.random.default_rng(seed))
    return np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)


def actual_n(name: str, n: int) -> int:
    """Return how many rows ``generate(name, n)`` gives (e.g. k*k for grids), without generating."""
    n = _check_int(n, "n")
    path = _file_path(name)
    if path is not None:
        return min(n, len(load(path)))
    return get(name).count(n)

