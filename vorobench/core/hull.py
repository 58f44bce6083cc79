"""The convex hull of sites, exactly: its boundary (collinear points on hull edges included)
and the all-collinear test, for the certifier and for adapters that must check an outside
library's unbounded cells."""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

from vorobench.core.predicates import orient2d, orient2d_many
from vorobench.core.sorting import sorted_unique

__all__ = ["convex_hull_polygon", "convex_hull_boundary", "all_collinear"]


def all_collinear(sites: NDArray[np.float64]) -> bool:
    """Exact test: every site lies on the line through the first two (always True for n <= 2)."""
    return sites.shape[0] <= 2 or not orient2d_many(sites[0], sites[1], sites[2:]).any()


@njit(cache=True)
def _chain(xs, ys, order, out):
    """Monotone chain over ``order`` (sorted lexicographically); pops only strict right turns,
    so collinear points on the chain are kept. Writes the chain to ``out``, returns its length."""
    k = 0
    for i in order:
        while k >= 2 and orient2d(xs[out[k - 2]], ys[out[k - 2]], xs[out[k - 1]], ys[out[k - 1]], xs[i], ys[i]) < 0:
            k -= 1
        out[k] = i
        k += 1
    return k


def convex_hull_polygon(sites: NDArray[np.float64]) -> NDArray[np.int64]:
    """Site ids around the convex hull, counter-clockwise, including collinear points on hull
    edges (exact orient2d; distinct sites). For collinear sites: all of them, there and back."""
    n = sites.shape[0]
    if n <= 2:
        return np.arange(n, dtype=np.int64)
    xs, ys = np.ascontiguousarray(sites[:, 0]), np.ascontiguousarray(sites[:, 1])
    cand = _hull_candidates(np.ascontiguousarray(sites, dtype=np.float64))
    order = cand[np.lexsort((ys[cand], xs[cand]))]
    out = np.empty(order.size, dtype=np.int64)
    lower = out[:_chain(xs, ys, order, out)].copy()
    upper = out[:_chain(xs, ys, order[::-1].copy(), out)].copy()
    return np.concatenate([lower[:-1], upper[:-1]])


def _hull_candidates(sites: NDArray[np.float64]) -> NDArray[np.int64]:
    """Sites that may lie on the hull boundary: all but those strictly left of every edge of
    the polygon of extreme sites in eight directions (counter-clockwise). A point strictly left
    of every edge of a closed polygon of sites is wound around, so strictly inside the hull;
    the test is exact (orient2d), the choice of extreme sites need not be."""
    x, y = sites[:, 0], sites[:, 1]
    extremes = [np.argmin(y), np.argmax(x - y), np.argmax(x), np.argmax(x + y),
                np.argmax(y), np.argmax(y - x), np.argmin(x), np.argmin(x + y)]
    ring = [int(i) for k, i in enumerate(extremes) if i != extremes[k - 1]]
    everything = np.arange(sites.shape[0], dtype=np.int64)
    if len(set(ring)) < 3:
        return everything
    inside = np.ones(sites.shape[0], dtype=bool)
    for p, q in zip(ring, ring[1:] + ring[:1]):
        inside &= orient2d_many(sites[p], sites[q], sites) > 0
    return everything[~inside]


def convex_hull_boundary(sites: NDArray[np.float64]) -> NDArray[np.int64]:
    """Sorted ids of the sites on the convex-hull boundary, collinear boundary points included."""
    return sorted_unique(convex_hull_polygon(sites))
