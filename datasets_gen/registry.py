"""The dataset registry: one frozen ``Dataset`` record per named family."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Literal

import numpy as np
from numpy.typing import NDArray

from . import degenerate as dg
from . import random_sets as rs

__all__ = ["DATASETS", "Dataset", "Family", "get"]

Family = Literal["random", "degenerate"]
GeneratorFn = Callable[[int, np.random.Generator], NDArray[np.float64]]

EXACT = "exactly n rows"


@dataclass(frozen=True, slots=True)
class Dataset:
    """A named point-set family: ``generate(n, rng)`` returns its (m, 2) float64 points.

    ``exact_n`` says whether m == n always; otherwise ``note`` says how n is rounded
    and ``size(n)`` computes m.
    """

    name: str
    description: str
    family: Family
    generate: GeneratorFn
    exact_n: bool = True
    note: str = EXACT
    size: Callable[[int], int] | None = None

    def count(self, n: int) -> int:
        """Rows that ``generate(n, rng)`` returns."""
        return n if self.size is None else self.size(n)


_GRID_NOTE = "k*k rows with k = ceil(sqrt(n)) (smallest square >= n)"

_ALL: tuple[Dataset, ...] = (
    # --- random: generic position, varying shape and density ---
    Dataset("uniform", "uniform in the unit square [0,1)^2", "random", rs.uniform),
    Dataset("disk", "uniform in the unit disk", "random", rs.disk),
    Dataset("normal", "standard bivariate Gaussian", "random", rs.normal),
    Dataset(
        "clusters",
        "Gaussian clusters: max(1, isqrt(n)//4) centres in the unit square, sigma 0.1/sqrt(#clusters)",
        "random",
        rs.clusters,
    ),
    Dataset("kuzmin", "Kuzmin disk, density ~ (1+r^2)^-1.5: heavy-tailed radii", "random", rs.kuzmin),
    Dataset("corners", "half-Gaussian blobs (sigma 0.05) at the four corners of the unit square", "random", rs.corners),
    Dataset("diagonal", "near the line y = x on [0,1], normal noise sigma 1e-3", "random", rs.diagonal),
    Dataset("cross", "near the crossing lines y = x and y = 1 - x, normal noise sigma 1e-3", "random", rs.cross),
    Dataset(
        "parabola",
        "exactly on y = x^2 with distinct x in [-1,1]: all points in convex position",
        "random",
        rs.parabola,
        note="exactly n rows; n <= 2**25",
    ),
    # --- degenerate: exact degeneracies and numerically hostile inputs ---
    Dataset(
        "grid",
        "integer lattice {0..k-1}^2, k = ceil(sqrt(n)), rows in seeded random order",
        "degenerate",
        dg.grid,
        exact_n=False,
        note=_GRID_NOTE,
        size=dg.grid_size,
    ),
    Dataset(
        "lattice_rotated",
        "integer lattice i*(3,4) + j*(-4,3), 0 <= i,j < k: rotated but exactly degenerate",
        "degenerate",
        dg.lattice_rotated,
        exact_n=False,
        note=_GRID_NOTE,
        size=dg.grid_size,
    ),
    Dataset(
        "near_grid",
        "integer lattice {0..k-1}^2 with each coordinate nudged by uniform noise of 1e-12",
        "degenerate",
        dg.near_grid,
        exact_n=False,
        note=_GRID_NOTE,
        size=dg.grid_size,
    ),
    Dataset(
        "cocircular",
        "distinct integer points on one circle x^2 + y^2 = R2 about the origin, R < 2^26",
        "degenerate",
        dg.cocircular,
        exact_n=False,
        note=f"min(n, {dg.COCIRCULAR_MAX_N}) rows: the largest circle with R2 < 2^53 has "
        f"{dg.COCIRCULAR_MAX_N} integer points",
        size=dg.cocircular_size,
    ),
    Dataset(
        "cocircular_many",
        "integer points on 4 concentric circles of radii R, 2R, 3R, 4R about the origin",
        "degenerate",
        dg.cocircular_many,
        exact_n=False,
        note=f"min(n, {dg.COCIRCULAR_MANY_MAX_N}) rows, split evenly over the circles "
        "(each base circle has at most 2048 points with 4R < 2^26)",
        size=dg.cocircular_many_size,
    ),
    Dataset(
        "collinear",
        "distinct integer points on the line (-5,11) + t*(3,7)",
        "degenerate",
        dg.collinear,
    ),
    Dataset(
        "duplicates",
        "uniform unit square where about 30% of the rows are exact copies of other rows",
        "degenerate",
        dg.duplicates,
        note="exactly n rows, repeats included (min(ceil(0.3 n), n - 1) of them are copies)",
    ),
    Dataset("huge_offset", "uniform unit square shifted by +1e9 in x and y", "degenerate", dg.huge_offset),
    Dataset("tiny_spacing", "uniform in [0, 1e-9)^2: tiny absolute scale", "degenerate", dg.tiny_spacing),
    Dataset("sorted", "uniform unit square sorted by x: adversarial insertion order", "degenerate", dg.sorted_x),
)

#: Name -> Dataset, in a fixed order (random families first, then degenerate ones).
DATASETS: dict[str, Dataset] = {d.name: d for d in _ALL}


def get(name: str) -> Dataset:
    """Return the registered dataset ``name`` or raise ValueError listing the valid names."""
    try:
        return DATASETS[name]
    except (KeyError, TypeError):
        raise ValueError(
            f"unknown dataset {name!r}; available: {', '.join(DATASETS)} (or file:PATH)"
        ) from None
