"""Randomized incremental Delaunay triangulation (Bowyer–Watson), Voronoi diagram as its dual.

CONTRACT
--------
Complexity: O(n log n) expected. Sites are inserted in a biased randomized insertion order
(random rounds of doubling size, Hilbert-sorted within each round), so the expected cost
does not depend on the input order (``sorted`` included), and each new site is located by a
visibility walk from the previous insertion, short because consecutive sites are close (a site
outside the hull, after one inserted on it, by a walk along the hull's ghost triangles first).
Input: prepared sites (distinct, finite float64), any n >= 0; coordinates within the range
where :mod:`vorobench.core.predicates` is exact (|x| in [2**-100, 2**100) or 0), where
``Implementation.run`` scales every input by a power of two (:mod:`vorobench.core.scaling`).
Exactness: every decision is an exact predicate (orient2d for the walk and for hull
conflicts, incircle for conflicts and for merging cocircular triangles); floating point is
used only for the vertex coordinates.
Hull: an infinite vertex closes the triangulation with ghost triangles, so hull growth and
collinear starts are ordinary insertions; all-collinear input (no triangle exists) gives
the n - 1 parallel bisector lines.
Degenerate cases: cocircular sites give one Voronoi vertex of degree >= 4 (triangles with
the same empty circle are merged exactly), never zero-length edges. Vertex coordinates come
from the three smallest site ids on the empty circle (:mod:`.circumcentre`), the same rule the
half-plane oracle uses, so the two exact constructions agree bit for bit.
Stats: predicate calls and exact fallbacks, insertions, walk steps, triangles removed and
created by cavities, triangles merged into cocircular vertices.

Weighted sites (``build_weighted``, power diagrams): the regular triangulation by insertion
and flips (:mod:`.regular`, Edelsbrunner-Shah: 1 -> 3 and 2 -> 4 splits, 2 -> 2 flips, 3 -> 1
and 4 -> 2 flips removing vertices that become hidden; a site whose lift is on or above the
triangulation's is hidden at insertion), in the same insertion order and with the same walks;
every decision exact (orient2d, power test). Its dual (:func:`~vorobench.core.delaunay_dual.power_dcel`)
merges neighbours with coplanar lifts into one vertex computed from the three smallest visible
site ids around it, and leaves without half-edges every site whose cell has no interior. Equal
weights give the Delaunay triangulation and the same diagram as ``build``, bit for bit.
Stats add the hidden sites (at insertion, removed by flips, found degenerate by the dual),
the flips of each kind and the power tests.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numpy.typing import NDArray

from impls.base import Implementation
from impls.incremental.regular import N_COUNTERS, regular_triangulation
from impls.incremental.regular import STAT_NAMES as WEIGHTED_STAT_NAMES
from impls.incremental.triangulate import STAT_NAMES, triangulate
from vorobench.core.builder import collinear_diagram
from vorobench.core.delaunay_dual import power_dcel, voronoi_dcel
from vorobench.core.diagram import Diagram
from vorobench.core.read_only import read_only
from vorobench.core.predicates import (
    INCIRCLE_CALLS,
    INCIRCLE_EXACT,
    ORIENT_CALLS,
    ORIENT_EXACT,
    POWER_TEST_CALLS,
    POWER_TEST_EXACT,
)
from vorobench.core.spatial_order import brio_order

__all__ = ["build", "build_weighted", "delaunay", "regular", "IMPLEMENTATION"]


def _predicate_stats(counters: NDArray[np.int64]) -> dict[str, int]:
    return {"orient2d_calls": int(counters[ORIENT_CALLS]), "orient2d_exact": int(counters[ORIENT_EXACT]),
            "incircle_calls": int(counters[INCIRCLE_CALLS]), "incircle_exact": int(counters[INCIRCLE_EXACT])}


def _triangulate(sites: NDArray[np.float64], stats: Optional[dict]):
    """Triangulate the sites copied into insertion order (consecutive insertions then touch
    nearby memory). Returns (points, ids, tri, opp, ntri, ok): ``ids[v]`` is point v's site id."""
    counters = np.zeros(4, dtype=np.int64)
    ids = brio_order(sites)
    points = np.ascontiguousarray(sites[ids])
    tri, opp, ntri, counts, ok = triangulate(points, np.arange(points.shape[0]), counters)
    if stats is not None:
        stats.update(zip(STAT_NAMES, (int(c) for c in counts)))
        stats.update(_predicate_stats(counters))
    return points, ids, tri, opp, ntri, ok


def delaunay(sites: NDArray[np.float64], stats: Optional[dict] = None
             ) -> Optional[tuple[NDArray[np.int64], NDArray[np.int64], int]]:
    """The Delaunay triangulation of prepared sites as (tri, opp, ntri), ghosts included
    (vertex n is the infinite vertex); None if the sites are all collinear (or n < 3)."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    _, ids, tri, opp, ntri, ok = _triangulate(sites, stats)
    if not ok:
        return None
    corners = tri[:3 * ntri]
    return np.where(corners < n, ids[np.minimum(corners, n - 1)], n), opp[:3 * ntri], ntri


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites``, dual to their Delaunay triangulation."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites)
    counts: dict = {}
    points, ids, tri, opp, ntri, ok = _triangulate(sites, counts)
    if not ok:
        if stats is not None:
            stats.update(counts, collinear=1)
        return collinear_diagram(sites)
    counters = np.zeros(4, dtype=np.int64)
    vertices, origin, twin, nxt, site, merged = voronoi_dcel(read_only(points), ids, tri, opp, ntri, counters)
    if stats is not None:
        stats.update(counts)
        stats["merged_triangles"] = int(merged)
        for key, value in _predicate_stats(counters).items():
            stats[key] += value
    return Diagram(sites, vertices, origin, twin, nxt, site)


def _weighted_stats(counters: NDArray[np.int64]) -> dict[str, int]:
    return {"orient2d_calls": int(counters[ORIENT_CALLS]), "orient2d_exact": int(counters[ORIENT_EXACT]),
            "power_test_calls": int(counters[POWER_TEST_CALLS]), "power_test_exact": int(counters[POWER_TEST_EXACT])}


def _regular(sites: NDArray[np.float64], weights: NDArray[np.float64], counters: NDArray[np.int64],
             stats: dict):
    """Regular triangulation of the weighted sites copied into insertion order: (points, point
    weights, ids, tri, opp, ntri, ok), ``ids[v]`` being point v's site id."""
    ids = brio_order(sites)
    points = np.ascontiguousarray(sites[ids])
    point_weights = np.ascontiguousarray(weights[ids])
    tri, opp, ntri, hidden, counts, ok = regular_triangulation(points, point_weights, counters)
    stats.update(zip(WEIGHTED_STAT_NAMES, (int(c) for c in counts)))
    stats["hidden_by_flips"] = int(counts[WEIGHTED_STAT_NAMES.index("flips_3_1")]
                                   + counts[WEIGHTED_STAT_NAMES.index("flips_4_2")])
    return points, point_weights, ids, tri, opp, ntri, ok


def regular(sites: NDArray[np.float64], weights: NDArray[np.float64], stats: Optional[dict] = None
            ) -> Optional[tuple[NDArray[np.int64], NDArray[np.int64], int]]:
    """The regular triangulation of prepared weighted sites as (tri, opp, ntri), ghosts included
    (vertex n is the infinite vertex; hidden sites appear in no triangle); None if the sites are
    all collinear (or n < 3)."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    weights = np.ascontiguousarray(weights, dtype=np.float64).reshape(-1)
    n = sites.shape[0]
    counters = np.zeros(N_COUNTERS, dtype=np.int64)
    counts: dict = {}
    _, _, ids, tri, opp, ntri, ok = _regular(sites, weights, counters, counts)
    if stats is not None:
        stats.update(counts)
        stats.update(_weighted_stats(counters))
    if not ok:
        return None
    corners = tri[:3 * ntri]
    return np.where(corners < n, ids[np.minimum(corners, n - 1)], n), opp[:3 * ntri], ntri


def build_weighted(sites: NDArray[np.float64], weights: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The power diagram of prepared ``sites`` with ``weights`` (power |x - p|^2 - w), dual to
    their regular triangulation; hidden sites have no half-edge."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    weights = np.ascontiguousarray(weights, dtype=np.float64).reshape(-1)
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites, weights)
    counters = np.zeros(N_COUNTERS, dtype=np.int64)
    counts: dict = {}
    points, point_weights, ids, tri, opp, ntri, ok = _regular(sites, weights, counters, counts)
    if not ok:
        diagram = collinear_diagram(sites, weights)
        counts.update(collinear=1, merged_triangles=0, hidden_degenerate=0)
    else:
        vertices, origin, twin, nxt, site, merged, degenerate = power_dcel(read_only(points), read_only(point_weights),
                                                                           ids, tri, opp, ntri, counters)
        diagram = Diagram(sites, vertices, origin, twin, nxt, site, weights=weights)
        counts.update(merged_triangles=int(merged), hidden_degenerate=int(degenerate))
    if stats is not None:
        stats.update(counts)
        stats["hidden"] = int(diagram.hidden.size)
        stats.update(_weighted_stats(counters))
    return diagram


def warmup() -> None:
    """Compile the kernels (and load numba's cache) on a tiny input with every code path."""
    rng = np.random.default_rng(0)
    build(rng.random((40, 2)))
    build(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [0.5, 0.5]]))
    build(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))
    build_weighted(rng.random((40, 2)), rng.random(40) * 0.01)
    lattice = np.array([[x, y] for x in range(4) for y in range(4)], dtype=np.float64)
    build_weighted(lattice, (lattice ** 2).sum(axis=1) - (lattice.sum(axis=1) % 2))
    build_weighted(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]), np.array([0.0, 5.0, 0.0]))


IMPLEMENTATION = Implementation(
    name="incremental",
    description="randomized incremental Delaunay (Bowyer-Watson, BRIO + Hilbert, ghost triangles), Voronoi as the "
                "dual; weighted: regular triangulation by insertion and flips, power diagram as the dual",
    complexity="O(n log n) expected",
    build=build,
    build_weighted=build_weighted,
    exact=True,
    warmup=warmup,
    kind="own",
)
