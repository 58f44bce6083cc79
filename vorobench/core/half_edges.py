"""Edges in, linked half-edges out: the arrays behind :func:`vorobench.core.builder.assemble`.

Half-edges come in pairs (twin of h is h ^ 1); ``next`` is linked in one pass: the successor
of h in cell a is the half-edge of a that starts where h ends, and a cell's half-edge that
runs out to infinity is followed by the one that comes back. Ridges given without an
orientation are oriented first, exactly (:func:`orient_ridges`). Kept apart from the
builder so that :class:`~vorobench.core.diagram.Diagram` itself can use it (``from_scipy``).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from vorobench.core.errors import InvalidDiagramError
from vorobench.core.predicates import orient2d_many
from vorobench.core.tolerances import RIDGE_DIRECTION_REL_TOL, data_scale

__all__ = ["link_edges", "orient_ridges", "index_pairs"]


def link_edges(n: int, vertices: NDArray[np.float64], ab: NDArray[np.int64], se: NDArray[np.int64], *,
               sites: NDArray[np.float64], oriented: bool = True, compact_vertices: bool = False
               ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], NDArray[np.int64],
                          NDArray[np.int64]]:
    """``(vertices, origin, twin, next, site)`` of the E >= 1 edges (a, b) with ends (start,
    end) of a's half-edge (either order when not ``oriented``); ids are checked first."""
    bad = (ab < 0) | (ab >= n)
    if bad.any():
        e = int(np.flatnonzero(bad.any(axis=1))[0])
        raise InvalidDiagramError(f"edge {e} names site {int(ab[e][bad[e]][0])}, outside [0, {n})")
    bad = (se < -1) | (se >= vertices.shape[0])
    if bad.any():
        e = int(np.flatnonzero(bad.any(axis=1))[0])
        raise InvalidDiagramError(f"edge {e} names vertex {int(se[e][bad[e]][0])}, outside [-1, {vertices.shape[0]})")
    if not oriented:
        se = orient_ridges(sites, vertices, ab, se)
    if compact_vertices:
        used = np.zeros(vertices.shape[0], dtype=bool)
        used[se[se >= 0]] = True
        new_id = np.cumsum(used) - 1
        se = np.where(se >= 0, new_id[np.maximum(se, 0)], -1)
        vertices = vertices[used]
    H = 2 * ab.shape[0]
    # int32 ids wherever they fit: half the memory of int64 (the DCEL of 10^6 sites is 6 million
    # half-edges, and linking them needs as many again in scratch)
    ids = np.int32 if max(H, n, vertices.shape[0]) < 2**31 - 1 else np.int64
    # copies: the Diagram must not share memory with arrays the caller may change afterwards
    site = ab.astype(ids).reshape(H)                # half-edge 2e: cell a; 2e + 1: cell b
    origin = se.astype(ids).reshape(H)              # 2e starts at `start`, 2e + 1 at `end`
    twin = np.arange(H, dtype=ids) ^ 1
    nxt = _link_next(site, origin, twin, n, vertices.shape[0], hint=oriented)
    return vertices, origin, twin, nxt, site


def index_pairs(values: ArrayLike, name: str) -> NDArray[np.integer]:
    """An (E, 2) int64 array of ids (int32 ones are kept as they are, not copied); a ValueError
    naming ``name`` for anything else."""
    arr = np.asarray(values)
    if arr.size == 0:
        return np.zeros((0, 2), dtype=np.int64)
    if arr.dtype.kind not in "iu":
        raise ValueError(f"{name} must hold integer ids, got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{name} must have shape (E, 2), got {arr.shape}")
    if arr.dtype == np.int32:
        return arr
    return arr.astype(np.int64, copy=False)


def _third_sites(ridge_sites: NDArray[np.int64], ridge_vertices: NDArray[np.int64]) -> NDArray[np.int64]:
    """For each finite ridge end, a site of that vertex other than the ridge's two sites.

    Any other ridge meeting at the same vertex separates a different pair of the vertex's
    sites, so one of its two sites is the third site we need.
    """
    E = ridge_sites.shape[0]
    v = ridge_vertices.reshape(-1)                     # incidence k = 2 * ridge + end
    finite = np.flatnonzero(v >= 0)
    order = finite[np.argsort(v[finite], kind="stable")]
    sorted_v = v[order]
    # Pair each incidence with its neighbour in vertex order (the previous one for the last).
    partner = np.empty_like(order)
    partner[:-1] = order[1:]
    partner[-1:] = order[-2:-1] if order.size > 1 else order[-1:]
    last = np.ones(order.size, dtype=bool)
    last[:-1] = sorted_v[1:] != sorted_v[:-1]
    partner[last] = np.concatenate([order[:1], order[:-1]])[last]
    if np.any(v[partner] != sorted_v):
        bad = int(sorted_v[np.flatnonzero(v[partner] != sorted_v)[0]])
        raise InvalidDiagramError(f"vertex {bad} lies on a single ridge")
    ridge, other = order // 2, partner // 2
    p, q = ridge_sites[ridge, 0], ridge_sites[ridge, 1]
    r0, r1 = ridge_sites[other, 0], ridge_sites[other, 1]
    third = np.full(2 * E, -1, dtype=np.int64)
    third[order] = np.where((r0 != p) & (r0 != q), r0, r1)
    return third.reshape(E, 2)


def orient_ridges(sites: NDArray[np.float64], vertices: NDArray[np.float64], ridge_sites: NDArray[np.int64],
                  ridge_vertices: NDArray[np.int64]) -> NDArray[np.int64]:
    """(start, end) of site a's half-edge for each ridge (a, b) given with its two vertex ids
    in either order (-1 = infinity).

    Decided combinatorially, not from float coordinates, so tiny ridges cannot be flipped by
    rounding: a vertex is the centre of a circle through a, b and a third site r; p's
    half-edge runs along perp(b - a), to the left of a->b, from the vertex whose r lies right
    of a->b to the one whose r lies left (exact orient2d). A ridge whose float direction is
    unambiguous (long against the coordinates' rounding) follows that direction instead, so
    a floating-point library's ridge between non-Delaunay sites (Qhull merges nearly
    collinear hull sites into one facet) still closes up. A line with both ends at infinity
    keeps its order.
    """
    rv = np.asarray(ridge_vertices, dtype=np.int64).reshape(-1, 2)
    rp = np.asarray(ridge_sites, dtype=np.int64).reshape(-1, 2)
    third = _third_sites(rp, rv)
    p, q = rp[:, 0], rp[:, 1]
    side = np.zeros(rv.shape, dtype=np.int8)       # orient2d(p, q, third site of each end)
    for end in (0, 1):
        ok = rv[:, end] >= 0
        side[ok, end] = orient2d_many(sites[p[ok]], sites[q[ok]], sites[third[ok, end]])
    if np.any((rv >= 0) & (side == 0)):
        e = int(np.flatnonzero(((rv >= 0) & (side == 0)).any(axis=1))[0])
        raise InvalidDiagramError(f"ridge {e} between sites {int(p[e])} and {int(q[e])}: a vertex's third site "
                                  f"lies on the line through them")
    # The start is the end whose third site is on the right (negative).
    end0_is_start = np.where(rv[:, 0] >= 0, side[:, 0] < 0, side[:, 1] > 0)
    both = np.flatnonzero((rv[:, 0] >= 0) & (rv[:, 1] >= 0))
    if both.size:
        v0, v1 = vertices[rv[both, 0]], vertices[rv[both, 1]]
        step = v1 - v0
        pq = sites[q[both]] - sites[p[both]]
        along = step[:, 1] * pq[:, 0] - step[:, 0] * pq[:, 1]        # step . perp(q - p)
        length = np.hypot(step[:, 0], step[:, 1])
        magnitude = np.maximum(np.abs(v0).max(axis=1), np.abs(v1).max(axis=1)) + data_scale(sites)
        clear = ((length > RIDGE_DIRECTION_REL_TOL * magnitude)
                 & (np.abs(along) > 0.5 * length * np.hypot(pq[:, 0], pq[:, 1])))
        end0_is_start[both[clear]] = along[clear] > 0
    start = np.where(end0_is_start, rv[:, 0], rv[:, 1])
    end = np.where(end0_is_start, rv[:, 1], rv[:, 0])
    return np.stack([start, end], axis=1)


_BIG_VERTEX = 16   # vertices of higher degree (many cocircular sites) are sorted and bisected


@njit(cache=True)
def _link_next_compiled(site, origin, twin, n, V, first, from_infinity, fill, members, cells, nxt, taken):
    """Fast path of :func:`_link_next`. Half-edges are bucketed by start vertex (counting
    sort; ~3 per vertex), so next[h] is the member of dest(h)'s bucket in cell site[h];
    a ray's successor is its cell's one half-edge from infinity. Sequential when vertex ids
    follow the edge order. Returns (next, ok); ok is False on anything unusual (a strip
    cell's two lines, a cell that does not close), which the numpy path then handles or reports.
    The buckets are int32 (H < 2^31): a quarter of the build's peak memory at 10^6 sites.
    Its arrays come from :func:`_link_next` (numpy's, on huge pages: see
    :func:`vorobench.core.delaunay_dual.voronoi_dcel`); ``first``, ``taken`` zero and
    ``from_infinity`` -1."""
    H = site.size
    for h in range(H):
        v = origin[h]
        if v >= 0:
            first[v + 1] += 1
        elif from_infinity[site[h]] >= 0:
            return nxt, False
        else:
            from_infinity[site[h]] = h
    for v in range(V):
        first[v + 1] += first[v]
        fill[v] = first[v]
    for h in range(H):
        v = origin[h]
        if v >= 0:
            members[fill[v]] = h
            fill[v] += 1
    # cells: the site of each bucket member, buckets sorted by it
    for v in range(V):
        lo, hi = first[v], first[v + 1]
        if hi - lo > _BIG_VERTEX:
            part = members[lo:hi].copy()
            order = np.argsort(site[part])
            for k in range(hi - lo):
                members[lo + k] = part[order[k]]
        for k in range(lo, hi):
            cells[k] = site[members[k]]
    for h in range(H):
        c = site[h]
        v = origin[twin[h]]
        if v < 0:
            g = from_infinity[c]
            if g < 0:
                return nxt, False
        else:
            lo, hi = first[v], first[v + 1]
            if hi - lo > _BIG_VERTEX:
                k = lo + np.searchsorted(cells[lo:hi], c)
                if k >= hi or cells[k] != c or (k + 1 < hi and cells[k + 1] == c):
                    return nxt, False
            else:
                k = -1
                for m in range(lo, hi):
                    if cells[m] == c:
                        if k >= 0:
                            return nxt, False
                        k = m
                if k < 0:
                    return nxt, False
            g = members[k]
        if taken[g]:                            # next would not be a permutation
            return nxt, False
        taken[g] = True
        nxt[h] = g
    return nxt, True


def _link_next(site: NDArray[np.int64], origin: NDArray[np.int64], twin: NDArray[np.int64],
               n: int, V: int, hint: bool = True) -> NDArray[np.int64]:
    """next[h] = the half-edge of cell site[h] starting at destination(h); ``hint``: say in
    the error that unoriented ridges need ``oriented=False``."""
    H = site.size
    if 0 < H < 2**31 - 1 and site.min() >= 0 and site.max() < n and origin.min() >= -1 and origin.max() < V:
        nxt, ok = _link_next_compiled(site, origin, twin, n, V, np.zeros(V + 1, np.int32), np.full(n, -1, np.int32),
                                      np.empty(V, np.int32), np.empty(H, np.int32), np.empty(H, np.int32),
                                      np.empty(H, site.dtype), np.zeros(H, np.bool_))
        if ok:
            return nxt
    # (cell, start vertex) as one int64 key (n (V + 1) passes 2**31 from about 46,000 sites);
    # infinity sorts first
    site64, origin64 = site.astype(np.int64), origin.astype(np.int64)
    key = site64 * (V + 1) + (origin64 + 1)
    order = np.argsort(key, kind="stable")
    sorted_key = key[order]
    want = site64 * (V + 1) + (origin64[twin] + 1)
    pos = np.searchsorted(sorted_key, want)
    pos_ok = np.minimum(pos, H - 1)
    found = (pos < H) & (sorted_key[pos_ok] == want)
    if not found.all():
        h = int(np.flatnonzero(~found)[0])
        end = int(origin[twin[h]])
        where = "infinity" if end < 0 else f"vertex {end}"
        raise InvalidDiagramError(
            f"cell {int(site[h])} does not close: half-edge {h} ends at {where}, "
            f"and no half-edge of the cell starts there"
            + (" (ridges whose two vertices come in either order, as scipy's do, need "
               "assemble(..., oriented=False))" if hint else ""))
    nxt = order[pos_ok].astype(site.dtype)
    # Repeated (cell, start) keys: legal only for a strip cell's two full lines.
    repeated = np.flatnonzero(sorted_key[1:] == sorted_key[:-1])
    if repeated.size:
        g1, g2 = order[repeated], order[repeated + 1]
        strip = (origin[g1] < 0) & (origin[twin[g1]] < 0) & (origin[twin[g2]] < 0)
        if not strip.all():
            k = int(np.flatnonzero(~strip)[0])
            v = int(origin[g1[k]])
            raise InvalidDiagramError(
                f"cell {int(site[g1[k]])} has two half-edges ({int(g1[k])}, {int(g2[k])}) starting at "
                f"{'infinity' if v < 0 else f'vertex {v}'}")
        triple = np.flatnonzero(np.diff(repeated) == 1)
        if triple.size:
            k = int(order[repeated[triple[0]]])
            raise InvalidDiagramError(f"cell {int(site[k])} has three or more half-edges from infinity")
        nxt[g1], nxt[g2] = g2, g1
    return nxt
