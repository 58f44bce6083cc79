"""A diagram from a bare list of triangles: what a program that triangulates hands over.

A Delaunay (or regular) triangulation given only as site-index triples, in any orientation
and order, is checked to be a triangulation at all (indices in range, no flat triangle, no
directed edge used twice, one closed hull cycle), each triangle is turned counter-clockwise
with the exact orientation predicate, neighbours are found by pairing each directed edge with
its reverse, and the hull is closed with ghosts (:mod:`vorobench.core.ghosts`). The dual is then
taken by the same routines as our own triangulations (:mod:`vorobench.core.delaunay_dual`):
whether the triangles were Delaunay is the certifier's question, not this module's.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from vorobench.core.builder import collinear_diagram
from vorobench.core.delaunay_dual import power_dcel, voronoi_dcel
from vorobench.core.diagram import Diagram
from vorobench.core.read_only import read_only
from vorobench.core.ghosts import ghost_layout
from vorobench.core.hull import all_collinear
from vorobench.core.predicates import N_POWER_COUNTERS, orient2d

__all__ = ["diagram_from_triangles", "NotATriangulation"]

class NotATriangulation(ValueError):
    """Triangles that do not form a triangulation of the sites (said with the first offence)."""


@njit(cache=True)
def _counter_clockwise(pts, tri):
    """Turn every triangle counter-clockwise in place (exact orientation); the index of the
    first flat one, or -1."""
    for t in range(tri.shape[0]):
        a, b, c = tri[t, 0], tri[t, 1], tri[t, 2]
        s = orient2d(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1])
        if s == 0:
            return t
        if s < 0:
            tri[t, 1], tri[t, 2] = c, b
    return -1


@njit(cache=True)
def _hull_cycles(tri, neighbours, n):
    """How many closed cycles the unpaired (hull) edges form; -1 if some site starts two of them."""
    nxt = np.full(n, -1, dtype=np.int64)
    count = 0
    for t in range(tri.shape[0]):
        for k in range(3):
            if neighbours[t, (k + 2) % 3] < 0:
                a = tri[t, k]
                if nxt[a] >= 0:
                    return -1
                nxt[a] = tri[t, (k + 1) % 3]
                count += 1
    seen = np.zeros(n, dtype=np.bool_)
    cycles = 0
    for start in range(n):
        if nxt[start] < 0 or seen[start]:
            continue
        cycles += 1
        v = start
        steps = 0
        while not seen[v]:
            seen[v] = True
            v = nxt[v]
            steps += 1
            if v < 0 or steps > count:
                return -1
    return cycles


@njit(cache=True)
def _pair_edges(tri, n):
    """Per corner k of each triangle, the triangle across the edge opposite it (-1 on the hull),
    by the out-edges of each site (a site has few); (neighbours, -1) or (_, the first half-edge
    3 t + k whose directed edge another triangle also holds)."""
    m = tri.shape[0]
    start = np.zeros(n + 1, dtype=np.int64)
    for t in range(m):
        for k in range(3):
            start[tri[t, k] + 1] += 1
    for v in range(n):
        start[v + 1] += start[v]
    fill = start[:-1].copy()
    edge_of = np.empty(3 * m, dtype=np.int64)      # half-edges e = 3 t + k grouped by their tail site
    for t in range(m):
        for k in range(3):
            a = tri[t, k]
            edge_of[fill[a]] = 3 * t + k
            fill[a] += 1
    across = np.full((m, 3), -1, dtype=np.int64)
    for t in range(m):
        for k in range(3):
            a, b = tri[t, k], tri[t, (k + 1) % 3]
            for j in range(start[a], start[a + 1]):        # the same directed edge twice: overlap
                f = edge_of[j]
                if f != 3 * t + k and tri[f // 3, (f % 3 + 1) % 3] == b:
                    return across, 3 * t + k
            for j in range(start[b], start[b + 1]):        # its reverse b -> a, in the triangle across
                f = edge_of[j]
                if tri[f // 3, (f % 3 + 1) % 3] == a:
                    across[t, (k + 2) % 3] = f // 3        # edge k -> k + 1 is opposite corner k + 2
    return across, -1


def _neighbours(tri: NDArray[np.int64], n: int) -> NDArray[np.int64]:
    """Per corner k of each (counter-clockwise) triangle, the triangle across the edge opposite
    it (-1 on the hull); raises when a directed edge belongs to two triangles (they overlap)."""
    across, twice = _pair_edges(tri, n)
    if twice >= 0:
        t, k = divmod(int(twice), 3)
        a, b = int(tri[t, k]), int(tri[t, (k + 1) % 3])
        raise NotATriangulation(f"triangles overlap: triangle {t} and another both hold the edge {a} -> {b} with "
                                f"the same orientation")
    return across


def diagram_from_triangles(sites: NDArray[np.float64], triangles: ArrayLike,
                           weights: Optional[ArrayLike] = None) -> Diagram:
    """The Voronoi (with ``weights``: power) diagram dual to ``triangles`` of ``sites``.

    ``triangles``: (m, 3) site indices, any orientation and order. No triangles: the empty
    diagram (n <= 1) or the collinear one, when the sites are all collinear (decided exactly).
    Sites in no triangle are hidden in a power diagram and an error otherwise. Raises
    :class:`NotATriangulation` for anything that is not a triangulation.
    """
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    w = None if weights is None else np.ascontiguousarray(weights, dtype=np.float64).reshape(-1)
    tri = np.array(triangles, dtype=np.int64, copy=True).reshape(-1, 3)
    if tri.shape[0] == 0:
        if n <= 1:
            return Diagram.empty(sites, w)
        if all_collinear(sites):
            return collinear_diagram(sites, w)
        raise NotATriangulation(f"no triangles for {n} sites that are not all collinear")
    bad = np.flatnonzero(((tri < 0) | (tri >= n)).any(axis=1))
    if bad.size:
        raise NotATriangulation(f"triangle {int(bad[0])} has a site index outside 0..{n - 1}: {tri[bad[0]].tolist()}")
    repeated = np.flatnonzero((tri[:, 0] == tri[:, 1]) | (tri[:, 1] == tri[:, 2]) | (tri[:, 0] == tri[:, 2]))
    if repeated.size:
        raise NotATriangulation(f"triangle {int(repeated[0])} names a site twice: {tri[repeated[0]].tolist()}")
    flat = int(_counter_clockwise(sites, tri))
    if flat >= 0:
        raise NotATriangulation(f"triangle {flat} is flat: sites {tri[flat].tolist()} are collinear")
    used = np.zeros(n, dtype=bool)
    used[tri.reshape(-1)] = True
    if w is None and not used.all():
        raise NotATriangulation(f"site {int(np.flatnonzero(~used)[0])} is in no triangle "
                                f"({int(np.count_nonzero(~used))} of {n} sites are missing)")
    neighbours = _neighbours(tri, n)
    cycles = int(_hull_cycles(tri, neighbours, n))
    if cycles != 1:
        raise NotATriangulation("the triangles' outer edges do not form one closed cycle (a hole, or "
                                "pieces that touch at a site)" if cycles != 0 else "the triangles have no outer edge")
    try:
        ghosted, opp, count = ghost_layout(tri, neighbours, n)
    except RuntimeError as exc:
        raise NotATriangulation(str(exc)) from None
    ids = np.arange(n, dtype=np.int64)
    counters = np.zeros(N_POWER_COUNTERS, dtype=np.int64)
    if w is None:
        vertices, origin, twin, nxt, site, _ = voronoi_dcel(read_only(sites), ids, ghosted, opp, count, counters)
    else:
        vertices, origin, twin, nxt, site, _, _ = power_dcel(read_only(sites), read_only(w), ids, ghosted, opp, count,
                                                     counters)
    return Diagram(sites, vertices, origin, twin, nxt, site, weights=w)
