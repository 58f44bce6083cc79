"""Seeded disk-radius families for additively weighted (Apollonius) diagrams: ``radii(family, points, seed)``.

A site is the disk of centre p_i and radius r_i >= 0; the distance from x to it is
|x - p_i| - r_i (CGAL's convention, docs/apollonius.md), so a disk inside another disk has no
cell (it is *hidden*). As with :mod:`.weight_families`, each family draws radii relative to a
spacing of the points (the local one, or ``s = sqrt(area / n)``), so that one family gives
comparable diagrams on the unit square, on a lattice and at a huge offset; only
``Generator.random`` and correctly rounded operations are used, and the stream is seeded from
``(seed, family)``. Families that need a centre layout of their own take it from the point
dataset: cocircular centres with ``equal`` radii are ``cocircular`` points with ``equal``; the
chains of tangent disks are ``tangent`` on a lattice.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._sampling import permutation
from .weight_families import local_spacing, mean_spacing

__all__ = ["RADIUS_FAMILIES", "NESTING_FRACTION", "MAX_COORDINATE", "radii", "nearest_distance"]

#: ``nested``: the fraction of disks (at least one) that are grown over their neighbours.
NESTING_FRACTION = 0.125
#: Larger coordinates are refused: an area or a squared distance of them overflows a double.
MAX_COORDINATE = 1e150

Radii = NDArray[np.float64]


def nearest_distance(points: NDArray[np.float64]) -> NDArray[np.float64]:
    """Per point, the distance to the nearest point at another place (copies of a point share
    its distance; correctly rounded from the coordinates); :func:`mean_spacing` where every
    row is at one place."""
    distinct, where = np.unique(points, axis=0, return_inverse=True)
    m = distinct.shape[0]
    if m < 2:
        return np.full(points.shape[0], mean_spacing(points))
    from scipy.spatial import cKDTree  # imported here: generating points does not need scipy

    _, nearest = cKDTree(distinct).query(distinct, 2)
    # the tree's second hit is the nearest other point; the distance is recomputed here so
    # that it does not depend on the tree's arithmetic
    other = np.where(nearest[:, 0] == np.arange(m), nearest[:, 1], nearest[:, 0])
    delta = distinct[other] - distinct
    d = np.sqrt(delta[:, 0] * delta[:, 0] + delta[:, 1] * delta[:, 1])
    return d[where.reshape(-1)]


def _random(points: NDArray[np.float64], rng: np.random.Generator) -> Radii:
    # r uniform below the local spacing: neighbouring disks overlap, and a small disk deep
    # inside a larger neighbour is hidden
    return local_spacing(points) * rng.random(points.shape[0])


def _separate(points: NDArray[np.float64], rng: np.random.Generator) -> Radii:
    # r below 0.499 of the nearest distance: r_i + r_j < d_ij for every pair at different
    # centres (d_ij is at least both nearest distances, and 0.499 leaves room for the
    # roundings), so no two such disks meet and none hides another (copies of a point share
    # its centre: the larger hides the smaller, as a heavier copy does in a power diagram)
    return 0.499 * nearest_distance(points) * rng.random(points.shape[0])


def _equal(points: NDArray[np.float64], rng: np.random.Generator) -> Radii:
    # one radius everywhere: |x - p_i| - r against |x - p_j| - r is the ordinary bisector
    return np.full(points.shape[0], 0.25 * mean_spacing(points))


def _nested(points: NDArray[np.float64], rng: np.random.Generator) -> Radii:
    # small disks, and a few (NESTING_FRACTION) grown to 1.5 to 3 local spacings, which swallow
    # the small disks near them: those are hidden
    n = points.shape[0]
    spacing = local_spacing(points)
    r = 0.25 * spacing * rng.random(n)
    k = min(n, max(1, round(NESTING_FRACTION * n))) if n else 0
    big = permutation(rng, n)[:k]
    r[big] = 1.5 * spacing[big] * (1.0 + rng.random(k))
    return r


def _tangent(points: NDArray[np.float64], rng: np.random.Generator) -> Radii:
    # half the nearest distance: a disk touches the disk of its nearest neighbour when that one
    # is nearest to it as well, and overlaps no other (r_i + r_j <= (d_i + d_j) / 2 <= d_ij), to
    # within the rounding of the distances. On an integer lattice every neighbour is at
    # distance 1 and r = 0.5: rows and columns of tangent disks, each tangency exact
    return 0.5 * nearest_distance(points)


def _integer(points: NDArray[np.float64], rng: np.random.Generator) -> Radii:
    # integers 0..m, m = max(1, floor(s / 2)): on the unit lattice radii 0 and 1, so a point
    # disk next to a disk of radius 1 lies on its circle (hidden, its cell a ray): exact
    # degeneracies everywhere
    m = max(1, math.floor(0.5 * mean_spacing(points)))
    r = np.floor(rng.random(points.shape[0]) * (m + 1))
    return np.minimum(r, float(m))


def _huge(points: NDArray[np.float64], rng: np.random.Generator) -> Radii:
    # small disks, and one of a quarter of the bounding box's diagonal, which hides the sites
    # it covers and bends every bisector around it
    n = points.shape[0]
    r = 0.25 * local_spacing(points) * rng.random(n)
    if n:
        width, height = (float(v) for v in points.max(axis=0) - points.min(axis=0))
        diagonal = math.hypot(width, height) or mean_spacing(points)
        r[int(permutation(rng, n)[0])] = 0.25 * diagonal
    return r


def _last_bit(points: NDArray[np.float64], rng: np.random.Generator) -> Radii:
    # one radius, and the next float above it for a random half of the disks: bisectors that
    # are nearly, but not exactly, the ordinary ones (hyperbolas a few ulps from straight)
    r = np.full(points.shape[0], 0.25 * mean_spacing(points))
    up = rng.random(points.shape[0]) < 0.5
    r[up] = np.nextafter(r[up], np.inf)
    return r


_FAMILIES: dict[str, tuple[str, Callable[[NDArray[np.float64], np.random.Generator], Radii]]] = {
    "random": ("r uniform in [0, local spacing) (mean distance to the 6 nearest points): overlapping disks, "
               "some inside others (hidden)", _random),
    "separate": ("r uniform in [0, 0.499 nearest distance): disks at different centres never meet, none hidden",
                 _separate),
    "equal": ("every r = s/4 (s = sqrt(box area / n)): exactly the ordinary Voronoi diagram", _equal),
    "nested": (f"small disks (r < local spacing / 4) and {NESTING_FRACTION:g} of them grown to 1.5-3 local "
               "spacings: the small disks they cover are hidden", _nested),
    "tangent": ("r = half the nearest distance: each disk touches its nearest neighbour's when that is "
                "mutual; on integer lattices, rows of exactly tangent disks", _tangent),
    "integer": ("integers 0..max(1, floor(s/2)) uniform; on the unit lattice (0 or 1) point disks lie on "
                "their neighbours' circles: exact degeneracies", _integer),
    "huge": ("one disk of a quarter of the bounding box's diagonal among small ones (r < local spacing / 4)",
             _huge),
    "last_bit": ("every r = s/4, and the next float above it for a random half: radii differing in the "
                 "last bit", _last_bit),
}

#: Radius family name -> one-line description.
RADIUS_FAMILIES: dict[str, str] = {name: text for name, (text, _) in _FAMILIES.items()}

# The second word of the seed: keeps radius streams apart from the point and weight streams.
_STREAM = {name: 0x5241_0000 + i for i, name in enumerate(_FAMILIES)}


def radii(family: str, points: ArrayLike, seed: int = 0) -> Radii:
    """The (n,) float64 radii (finite, >= 0) of family ``family`` for the disks centred at the
    (n, 2) ``points`` (one per row, duplicates included), deterministic in (family, points, seed)."""
    if family not in _FAMILIES:
        raise ValueError(f"unknown radius family {family!r}; available: {', '.join(_FAMILIES)}")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    pts = np.asarray(points, dtype=np.float64)
    if pts.size == 0:
        pts = pts.reshape(0, 2)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2), got {pts.shape}")
    if not np.isfinite(pts).all():
        raise ValueError("points must be finite to draw radii for them")
    if pts.size and np.abs(pts).max() > MAX_COORDINATE:
        raise ValueError(f"coordinates beyond {MAX_COORDINATE:g} in magnitude: the spacings the radii are drawn from "
                         "would overflow")
    rng = np.random.default_rng([int(seed), _STREAM[family]])
    r = _FAMILIES[family][1](pts, rng)
    return np.ascontiguousarray(r, dtype=np.float64).reshape(pts.shape[0])
