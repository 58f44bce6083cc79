"""Exact screening of inputs an outside library cannot represent, on the sites' own triangulation.

Some libraries can only answer for something close to the sites: Boost.Polygon for the
sites rounded to its integer grid, GEOS for the part of the diagram inside its finite
frame; Triangle's sweep fails on nearly collinear sites. These limits are decided here on
the Delaunay triangulation of the true sites (built by our exact incremental
construction), so that ``supports`` can refuse the inputs whose diagram the library cannot
give, instead of letting them fail cross-validation.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np
from numba import njit
from numpy.typing import NDArray

from impls.incremental import delaunay
from vorobench.core.circumcentre import circumcentre
from vorobench.core.predicates import incircle_many, orient2d_many

__all__ = ["Triangulation", "triangulation", "changed_decisions", "flattest_triangle", "smallest_incircle_margin",
           "circumcentres"]


@dataclass(frozen=True)
class Triangulation:
    """The finite triangles (CCW site ids), the interior edges as quadruples, the hull cycle."""

    triangles: NDArray[np.int64]   # (T, 3)
    quads: NDArray[np.int64]       # (Q, 4): (a, b, c) a triangle, d the far corner across a-b
    hull: NDArray[np.int64]        # (h,): hull vertices in cycle order


def triangulation(sites: NDArray[np.float64]) -> Optional[Triangulation]:
    """The Delaunay triangulation of prepared sites; None when they are all collinear."""
    n = sites.shape[0]
    result = delaunay(sites) if n >= 3 else None
    if result is None:
        return None
    corners, opp, ntri = result
    tri = corners.reshape(ntri, 3)
    ghost = np.any(tri == n, axis=1)
    e = np.arange(3 * ntri)
    t, k = e // 3, e % 3
    oe = opp[e]
    a, b, c = tri[t, k], tri[t, (k + 1) % 3], tri[t, (k + 2) % 3]
    inner = ~ghost[t] & ~ghost[oe // 3] & (e < oe)
    d = tri[oe // 3, (oe % 3 + 2) % 3]
    quads = np.stack([a, b, c, d], axis=1)[inner]
    # a finite half-edge a -> b whose twin lies in a ghost is a hull edge (interior on its left)
    on_hull = ~ghost[t] & ghost[oe // 3]
    succ = np.full(n, -1, dtype=np.int64)
    succ[a[on_hull]] = b[on_hull]
    start = int(a[on_hull][0])
    cycle = [start]
    v = int(succ[start])
    while v != start:
        if v < 0 or len(cycle) > n:
            raise RuntimeError("screen: the triangulation's hull edges do not form one cycle")
        cycle.append(v)
        v = int(succ[v])
    return Triangulation(tri[~ghost], quads, np.array(cycle, dtype=np.int64))


def changed_decisions(tr: Triangulation, sites: NDArray[np.float64], moved: NDArray[np.float64]) -> Optional[str]:
    """Why ``moved`` (the sites displaced, same ids) may have another Delaunay triangulation,
    or None if every decision that makes ``tr`` Delaunay comes out the same for them.

    Same sign for every triangle's orientation, every hull turn and every interior edge's
    in-circle test means ``tr`` is still a valid triangulation of a convex region whose
    boundary holds the same sites, locally Delaunay, hence Delaunay, with the same
    cocircular groups: the diagram keeps its combinatorics.
    """
    for what, idx, test in _decisions(tr):
        before = test(*(sites[idx[:, j]] for j in range(idx.shape[1])))
        after = test(*(moved[idx[:, j]] for j in range(idx.shape[1])))
        changed = np.flatnonzero(before != after)
        if changed.size:
            ids = [int(x) for x in idx[changed[0]]]
            return f"{what} changes sign (sites {ids}; {changed.size} such decisions)"
    return None


def _decisions(tr: Triangulation) -> tuple[tuple[str, NDArray[np.int64], object], ...]:
    """(what, site-id rows, exact predicate) for every decision that makes ``tr`` Delaunay."""
    turns = np.stack([tr.hull, np.roll(tr.hull, -1), np.roll(tr.hull, -2)], axis=1)
    return (("a triangle's orientation", tr.triangles, orient2d_many),
            ("a hull turn", turns, orient2d_many),
            ("an in-circle test", tr.quads, incircle_many))


def flattest_triangle(tr: Triangulation, sites: NDArray[np.float64]) -> tuple[float, NDArray[np.int64]]:
    """The smallest flatness of a triangle of ``tr`` (its height over its longest side:
    ~1e-13 for three sites collinear to within 1e-13) and that triangle's site ids."""
    t = tr.triangles
    if t.shape[0] == 0:
        return float("inf"), np.zeros(3, dtype=np.int64)
    a, b, c = sites[t[:, 0]], sites[t[:, 1]], sites[t[:, 2]]
    ab, ac, bc = b - a, c - a, c - b
    twice_area = np.abs(ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    longest2 = np.maximum(np.maximum((ab * ab).sum(axis=1), (ac * ac).sum(axis=1)), (bc * bc).sum(axis=1))
    flatness = twice_area / longest2            # = height / longest side
    k = int(np.argmin(flatness))
    return float(flatness[k]), t[k]


def smallest_incircle_margin(tr: Triangulation, sites: NDArray[np.float64]) -> tuple[float, NDArray[np.int64]]:
    """How close to cocircular the most nearly cocircular Delaunay neighbours are, without
    being exactly so: min over interior edges of |incircle| / its scale (products of the
    lengths involved), exact zeros (true cocircularity, exact sign) left out; and the four
    site ids. ~1e-17 for sites on a circle to within 1e-16."""
    q = tr.quads
    if q.shape[0] == 0:
        return float("inf"), np.zeros(4, dtype=np.int64)
    A, B, C = (sites[q[:, j]] - sites[q[:, 3]] for j in range(3))
    la, lb, lc = (A * A).sum(axis=1), (B * B).sum(axis=1), (C * C).sum(axis=1)
    det = (la * (B[:, 0] * C[:, 1] - C[:, 0] * B[:, 1]) + lb * (C[:, 0] * A[:, 1] - A[:, 0] * C[:, 1])
           + lc * (A[:, 0] * B[:, 1] - B[:, 0] * A[:, 1]))
    na, nb, nc = np.sqrt(la), np.sqrt(lb), np.sqrt(lc)
    margin = np.abs(det) / (la * nb * nc + lb * nc * na + lc * na * nb)
    exact_zero = incircle_many(sites[q[:, 0]], sites[q[:, 1]], sites[q[:, 2]], sites[q[:, 3]]) == 0
    margin[exact_zero] = np.inf
    k = int(np.argmin(margin))
    return float(margin[k]), q[k]


@njit(cache=True)
def _circumcentres(sites, triangles):
    out = np.empty((triangles.shape[0], 2))
    for t in range(triangles.shape[0]):
        i, j, k = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        out[t, 0], out[t, 1] = circumcentre(sites[i, 0], sites[i, 1], sites[j, 0], sites[j, 1],
                                            sites[k, 0], sites[k, 1])
    return out


def circumcentres(sites: NDArray[np.float64], triangles: NDArray[np.int64]) -> NDArray[np.float64]:
    """Circumcentre of each triangle, computed from its sites in the order given (rows of ids)."""
    return _circumcentres(np.ascontiguousarray(sites, dtype=np.float64),
                          np.ascontiguousarray(triangles, dtype=np.int64))
