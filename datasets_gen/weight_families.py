"""Seeded site-weight families for power (Laguerre) diagrams: ``weights(family, points, seed)``.

The power of x with respect to site i is |x - p_i|^2 - w_i, so a weight is a squared length,
and each family draws it relative to a spacing of the points, so that the same family gives
comparable diagrams on the unit square, on an integer lattice and at a huge offset:

* the *local* spacing of a point (``radii``, ``hidden``): the mean distance to its
  :data:`NEIGHBOURS` nearest other points, so that dense clusters and sparse tails get disks of
  their own size (a global spacing hides nearly every site of a heavy-tailed set);
* the *mean* spacing ``s = sqrt(area / n)`` over the bounding box (``equal``, ``integer``).

Like the point generators, only ``Generator.random`` and correctly rounded arithmetic are
used, so the weights are bit-identical on every machine. The stream is seeded from
``(seed, family)``, never from ``seed`` alone: a dataset drawn with the same seed would
otherwise reuse its own random numbers as weights (uniform points' x coordinates).
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._sampling import permutation

__all__ = ["WEIGHT_FAMILIES", "HIDDEN_FRACTION", "NEIGHBOURS", "local_spacing", "mean_spacing", "weights"]

#: ``hidden``: the fraction of sites (at least one) that get a large weight.
HIDDEN_FRACTION = 0.125
#: How many nearest neighbours the local spacing of a point averages over.
NEIGHBOURS = 6

Weights = NDArray[np.float64]


def mean_spacing(points: NDArray[np.float64]) -> float:
    """``sqrt(area / n)`` over the points' bounding box: the side of the square each point
    would own if they tiled it; a degenerate box uses its length / (n - 1), then 1."""
    n = points.shape[0]
    if n == 0:
        return 1.0
    width, height = (float(v) for v in points.max(axis=0) - points.min(axis=0))
    if width > 0 and height > 0:
        return math.sqrt(width * height / n)
    length = max(width, height)
    return length / (n - 1) if length > 0 else 1.0


def local_spacing(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per point, the mean distance to its :data:`NEIGHBOURS` nearest other rows (fewer when
    there are fewer); :func:`mean_spacing` where that is 0 (a point with only copies near it)."""
    n = points.shape[0]
    k = min(NEIGHBOURS, n - 1)
    if k < 1:
        return np.full(n, mean_spacing(points))
    from scipy.spatial import cKDTree  # imported here: generating points does not need scipy

    _, nearest = cKDTree(points).query(points, k + 1)
    # Distances recomputed with correctly rounded operations, sorted (ties are equal anyway),
    # so the result does not depend on the tree's own arithmetic.
    delta = points[nearest] - points[:, None, :]
    dist = np.sort(np.sqrt(delta[..., 0] * delta[..., 0] + delta[..., 1] * delta[..., 1]), axis=1)
    spacing = dist[:, 1:].sum(axis=1) / k
    return np.where(spacing > 0, spacing, mean_spacing(points))


def _radii(points: NDArray[np.float64], rng: np.random.Generator) -> Weights:
    # Disks of radius r < the local spacing: neighbours' disks overlap, and where a small disk
    # lies deep inside larger ones its cell vanishes (about 1 site in 9 on random sets).
    r = local_spacing(points) * rng.random(points.shape[0])
    return r * r


def _equal(points: NDArray[np.float64], rng: np.random.Generator) -> Weights:
    # One nonzero weight everywhere: every bisector is the ordinary one.
    s = mean_spacing(points)
    return np.full(points.shape[0], 0.25 * s * s)


def _integer(points: NDArray[np.float64], rng: np.random.Generator) -> Weights:
    # Integers 0..m with m = max(1, floor(s^2)): on the unit lattice (s = 1) the weights are 0
    # and 1, and a weight difference of 1 equals a squared neighbour distance, so a site sits
    # exactly on its neighbour's power bisector: exact degeneracies everywhere.
    s = mean_spacing(points)
    m = max(1, math.floor(s * s))
    w = np.floor(rng.random(points.shape[0]) * (m + 1))
    return np.minimum(w, float(m))


def _hidden(points: NDArray[np.float64], rng: np.random.Generator) -> Weights:
    # Most sites weigh 0; a few (HIDDEN_FRACTION) get disks of 1.5 to 3 local spacings, which
    # swallow the cells of the weightless sites they cover (most of them on random sets).
    n = points.shape[0]
    w = np.zeros(n)
    k = min(n, max(1, round(HIDDEN_FRACTION * n))) if n else 0
    heavy = permutation(rng, n)[:k]
    r = 1.5 * local_spacing(points)[heavy] * (1.0 + rng.random(k))
    w[heavy] = r * r
    return w


_FAMILIES: dict[str, tuple[str, Callable[[NDArray[np.float64], np.random.Generator], Weights]]] = {
    "radii": (f"w = r^2, r uniform in [0, local spacing) (mean distance to the {NEIGHBOURS} nearest points): "
              "overlapping disks, about 1 site in 9 hidden on random sets", _radii),
    "equal": ("every w = s^2/4 (one nonzero value, s = sqrt(box area / n)): exactly the ordinary Voronoi "
              "diagram", _equal),
    "integer": ("integers 0..max(1, floor(s^2)) uniform (s = sqrt(box area / n)); on integer lattices "
                "(0 or 1) sites lie exactly on power bisectors: exact degeneracies", _integer),
    "hidden": (f"w = 0 except for {HIDDEN_FRACTION:g} of the sites: w = r^2, r uniform in [1.5, 3) local "
               "spacings; most sites are hidden", _hidden),
}

#: Weight family name -> one-line description (``vorobench datasets`` lists them).
WEIGHT_FAMILIES: dict[str, str] = {name: text for name, (text, _) in _FAMILIES.items()}

# The second word of the seed: keeps weight streams apart from the point streams of a seed.
_STREAM = {name: 0x5745_0000 + i for i, name in enumerate(_FAMILIES)}


def weights(family: str, points: ArrayLike, seed: int = 0) -> Weights:
    """The (n,) float64 weights of family ``family`` for the (n, 2) ``points`` (one per row,
    duplicates included), deterministic in (family, points, seed)."""
    if family not in _FAMILIES:
        raise ValueError(f"unknown weight family {family!r}; available: {', '.join(_FAMILIES)}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if not np.isfinite(pts).all():
        raise ValueError("points must be finite to draw weights for them")
    rng = np.random.default_rng([int(seed), _STREAM[family]])
    w = _FAMILIES[family][1](pts, rng)
    return np.ascontiguousarray(w, dtype=np.float64).reshape(pts.shape[0])
