"""The Voronoi diagram as the dual of the Delaunay triangulation, as edges for the DCEL builder.

Every finite triangle gives the Voronoi vertex at its circumcentre; a Delaunay edge between
two finite triangles gives the Voronoi edge joining their circumcentres, a hull edge a ray.
Cocircular sites triangulate their common empty circle in several triangles with the same
circumcentre: neighbours whose fourth site is exactly cocircular (incircle == 0) are merged
into one vertex (union-find), and the Delaunay edges inside the group give no Voronoi edge.
So the output has one vertex of degree >= 4 per empty circle through 4 or more sites and no
zero-length edges. Its coordinates come from the three smallest site ids on the circle.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from vorobench.core.circumcentre import circumcentre
from vorobench.core.predicates import incircle_counted
from vorobench.core.union_find import find

__all__ = ["voronoi_vertices", "voronoi_edges", "voronoi_dcel"]


@njit(cache=True)
def _is_ghost(tri, t, inf):
    return tri[3 * t] == inf or tri[3 * t + 1] == inf or tri[3 * t + 2] == inf


@njit(cache=True, inline='always')
def _by_id(ids, a, b, c):
    """Points a, b, c ordered by site id."""
    if ids[a] > ids[b]:
        a, b = b, a
    if ids[b] > ids[c]:
        b, c = c, b
    if ids[a] > ids[b]:
        a, b = b, a
    return a, b, c


@njit(cache=True)
def _sort3_by_id(low, r, a, b, c, ids):
    """low[r] = points a, b, c ordered by site id."""
    a, b, c = _by_id(ids, a, b, c)
    low[r, 0] = a
    low[r, 1] = b
    low[r, 2] = c


@njit(cache=True)
def _insert_by_id(low, r, s, ids):
    """Keep in low[r] the three points of smallest site id seen so far (s not yet counted)."""
    if s == low[r, 0] or s == low[r, 1] or s == low[r, 2]:
        return
    if ids[s] < ids[low[r, 0]]:
        low[r, 2] = low[r, 1]
        low[r, 1] = low[r, 0]
        low[r, 0] = s
    elif ids[s] < ids[low[r, 1]]:
        low[r, 2] = low[r, 1]
        low[r, 1] = s
    elif ids[s] < ids[low[r, 2]]:
        low[r, 2] = s


@njit(cache=True)
def _circumcentre_of(pts, ids, a, b, c):
    # the circumcentre computed from a, b, c in increasing site id (the rule of the module)
    a, b, c = _by_id(ids, a, b, c)
    return circumcentre(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1])


@njit(cache=True)
def voronoi_vertices(pts, ids, tri, opp, ntri, counters):
    """The Voronoi vertex of every triangle: (vid, vertices, merged).

    ``vid[t]`` is triangle t's vertex (-1 for a ghost); cocircular neighbours share one
    vertex; ``merged`` counts triangles folded into a neighbour's vertex. One pass when no two
    neighbouring triangles are cocircular (each interior edge tested on the way); the first
    cocircular pair found hands over to :func:`_merged_vertices`.
    """
    n = pts.shape[0]
    inf = n
    vid = np.full(ntri, -1, dtype=np.int64)
    vertices = np.empty((ntri, 2), dtype=np.float64)
    nv = 0
    for t in range(ntri):
        a = tri[3 * t]
        b = tri[3 * t + 1]
        c = tri[3 * t + 2]
        if a == inf or b == inf or c == inf:
            continue
        x, y = _circumcentre_of(pts, ids, a, b, c)
        vertices[nv, 0] = x
        vertices[nv, 1] = y
        vid[t] = nv
        nv += 1
    tests = np.zeros_like(counters)        # added to counters only if this pass completes
    for e in range(3 * ntri):
        oe = opp[e]
        if oe < e:
            continue
        t = e // 3
        t2 = oe // 3
        if vid[t] < 0 or vid[t2] < 0:
            continue
        a = tri[e]
        b = tri[3 * t + (e - 3 * t + 1) % 3]
        c = tri[3 * t + (e - 3 * t + 2) % 3]
        d = tri[3 * t2 + (oe - 3 * t2 + 2) % 3]
        if incircle_counted(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1],
                            pts[d, 0], pts[d, 1], tests) == 0:
            return _merged_vertices(pts, ids, tri, opp, ntri, counters)
    counters += tests
    return vid, vertices[:nv], 0


@njit(cache=True)
def _merged_vertices(pts, ids, tri, opp, ntri, counters):
    """:func:`voronoi_vertices` when some neighbouring triangles share their circumcircle:
    union-find over cocircular neighbours, one vertex per group."""
    n = pts.shape[0]
    inf = n
    parent = np.arange(ntri)
    ghost = np.zeros(ntri, dtype=np.bool_)
    for t in range(ntri):
        ghost[t] = _is_ghost(tri, t, inf)
    # ---- merge finite neighbours with the same circumcircle
    merged = 0
    for e in range(3 * ntri):
        oe = opp[e]
        if oe < e:
            continue
        t = e // 3
        t2 = oe // 3
        if ghost[t] or ghost[t2]:
            continue
        d = tri[3 * t2 + (oe - 3 * t2 + 2) % 3]   # the corner of t2 off the shared edge
        a = tri[3 * t]
        b = tri[3 * t + 1]
        c = tri[3 * t + 2]
        if incircle_counted(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1],
                            pts[d, 0], pts[d, 1], counters) == 0:
            r1 = find(parent, t)
            r2 = find(parent, t2)
            if r1 != r2:
                parent[max(r1, r2)] = min(r1, r2)
                merged += 1
    # ---- the three points of smallest site id on each group's circle (point indices)
    low = np.empty((ntri, 3), dtype=np.int64)
    for t in range(ntri):
        if ghost[t]:
            continue
        r = find(parent, t) if merged else t
        if r == t:
            _sort3_by_id(low, t, tri[3 * t], tri[3 * t + 1], tri[3 * t + 2], ids)
    if merged:
        for t in range(ntri):
            r = find(parent, t)
            if ghost[t] or r == t:
                continue
            for k in range(3):
                _insert_by_id(low, r, tri[3 * t + k], ids)
    # ---- one vertex per group
    vid = np.full(ntri, -1, dtype=np.int64)
    nv = 0
    for t in range(ntri):
        if not ghost[t] and parent[t] == t:
            vid[t] = nv
            nv += 1
    vertices = np.empty((nv, 2), dtype=np.float64)
    for t in range(ntri):
        if vid[t] >= 0:
            i, j, k = low[t, 0], low[t, 1], low[t, 2]
            x, y = circumcentre(pts[i, 0], pts[i, 1], pts[j, 0], pts[j, 1], pts[k, 0], pts[k, 1])
            vertices[vid[t], 0] = x
            vertices[vid[t], 1] = y
    if merged:
        for t in range(ntri):
            if not ghost[t]:
                vid[t] = vid[find(parent, t)]
    return vid, vertices, merged


@njit(cache=True)
def voronoi_edges(pts, ids, tri, opp, ntri, counters):
    """Vertices and edges of the Voronoi diagram dual to a Delaunay triangulation.

    ``pts`` are the points the triangulation indexes (in insertion order, for locality) and
    ``ids[v]`` the caller's site id of point v: output edges use those ids, and a vertex's
    coordinates come from its three smallest ids. Returns (vertices (V, 2),
    edge_sites (E, 2), edge_vertices (E, 2), merged): the edge arrays in the form
    :func:`vorobench.core.builder.assemble` takes; ``merged`` counts triangles folded into a
    cocircular neighbour's vertex. (:func:`voronoi_dcel` gives the DCEL itself, faster.)
    """
    inf = pts.shape[0]
    vid, vertices, merged = voronoi_vertices(pts, ids, tri, opp, ntri, counters)
    # ---- one Voronoi edge per Delaunay edge between different vertices (or a vertex and a ray)
    ne = 0
    edge_sites = np.empty((3 * ntri // 2, 2), dtype=np.int64)
    edge_vertices = np.empty((3 * ntri // 2, 2), dtype=np.int64)
    for e in range(3 * ntri):
        oe = opp[e]
        if oe < e:
            continue
        t = e // 3
        a = tri[e]
        b = tri[3 * t + (e - 3 * t + 1) % 3]
        if a == inf or b == inf:
            continue
        left = vid[t]              # -1 for a ghost: the edge runs out to infinity
        right = vid[oe // 3]
        if left == right:
            continue               # inside a cocircular group: zero length
        # a's half-edge runs along perp(b - a), i.e. from the right triangle's centre to the left's
        edge_sites[ne, 0] = ids[a]
        edge_sites[ne, 1] = ids[b]
        edge_vertices[ne, 0] = right
        edge_vertices[ne, 1] = left
        ne += 1
    return vertices, edge_sites[:ne], edge_vertices[:ne], merged


@njit(cache=True)
def voronoi_dcel(pts, ids, tri, opp, ntri, counters):
    """The Voronoi diagram dual to a Delaunay triangulation as DCEL arrays, in one pass over
    the triangulation's half-edges (no sort): (vertices, origin, twin, next, site, merged).

    Delaunay half-edge e = u -> v (its triangle t on its left) gives cell u's Voronoi
    half-edge, which runs along perp(v - u) from the centre of the triangle on e's right
    (``opp[e]``'s; -1 for a ghost: from infinity) to t's centre; its twin is the one of
    ``opp[e]`` (numbered as the pair 2k, 2k + 1). It is followed, around cell u, by the
    Voronoi half-edge of the next Delaunay half-edge out of u, turning through t:
    ``opp[prev(e)]``; edges to the infinite vertex and edges inside a cocircular group have
    no Voronoi half-edge and are turned past (after a ray out to infinity, this reaches the
    ray coming back, as the contract asks). Same vertices as :func:`voronoi_edges`.
    """
    inf = pts.shape[0]
    vid, vertices, merged = voronoi_vertices(pts, ids, tri, opp, ntri, counters)
    m = 3 * ntri
    # int32 throughout: half the memory traffic of these mostly cache-missing passes
    hid = np.full(m, -1, dtype=np.int32)
    pairs = 0
    for e in range(m):
        oe = opp[e]
        if oe < e:
            continue
        t = e // 3
        a = tri[e]
        b = tri[3 * t + (e - 3 * t + 1) % 3]
        if a == inf or b == inf or vid[t] == vid[oe // 3]:
            continue
        hid[e] = 2 * pairs
        hid[oe] = 2 * pairs + 1
        pairs += 1
    H = 2 * pairs
    origin = np.empty(H, dtype=np.int32)
    nxt = np.empty(H, dtype=np.int32)
    site = np.empty(H, dtype=np.int32)
    for e in range(m):
        h = hid[e]
        if h < 0:
            continue
        t = e // 3
        origin[h] = vid[opp[e] // 3]
        site[h] = ids[tri[e]]
        f = opp[3 * t + (e - 3 * t + 2) % 3]
        for _ in range(m):
            if hid[f] >= 0:
                break
            g = f // 3
            f = opp[3 * g + (f - 3 * g + 2) % 3]
        if hid[f] < 0:
            raise RuntimeError("voronoi_dcel: a cell does not close up")
        nxt[h] = hid[f]
    twin = np.arange(H, dtype=np.int32) ^ 1
    return vertices, origin, twin, nxt, site, merged
