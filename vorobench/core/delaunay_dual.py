"""The Voronoi diagram as the dual of the Delaunay triangulation, as edges for the DCEL builder.

Every finite triangle gives the Voronoi vertex at its circumcentre; a Delaunay edge between
two finite triangles gives the Voronoi edge joining their circumcentres, a hull edge a ray.
Cocircular sites triangulate their common empty circle in several triangles with the same
circumcentre: neighbours whose fourth site is exactly cocircular (incircle == 0) are merged
into one vertex (union-find), and the Delaunay edges inside the group give no Voronoi edge.
So the output has one vertex of degree >= 4 per empty circle through 4 or more sites and no
zero-length edges. Its coordinates come from the three smallest site ids on the circle.

The power diagram is dual to a regular triangulation in the same way (:func:`power_dcel`):
vertices at power centres, neighbours merged when their four lifted points are coplanar, and
sites whose cell has no interior (lift not a vertex of the lower hull) left without half-edges.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from vorobench.core.circumcentre import circumcentre, circumcentre_fast, power_centre
from vorobench.core.prefetch import prefetch
from vorobench.core.predicates import incircle_counted, orient2d_counted, power_test_counted
from vorobench.core.union_find import find

__all__ = ["voronoi_vertices", "voronoi_edges", "voronoi_dcel", "power_vertices", "power_dcel",
           "VISIBLE", "FLAT", "THROUGH"]


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


@njit(cache=True, inline='always')
def _circumcentre_of(pts, ids, a, b, c):
    """The circumcentre computed from a, b, c in increasing site id (the rule of the module).

    Only the first corner, the one of least id, changes the float formula's bits (see
    :func:`circumcentre_fast`), so it is found first and the other two follow in their own
    order; the full sort waits for the rare triple whose formula cancels. Fewer comparisons of
    ids, which miss the cache at 10**6 sites and stall the pass when mispredicted: about 8 %
    off the dual there."""
    ia, ib, ic = ids[a], ids[b], ids[c]
    if ib < ia and ib < ic:
        a, b, c = b, c, a
    elif ic < ia and ic < ib:
        a, b, c = c, a, b
    ok, x, y = circumcentre_fast(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1])
    if ok:
        return x, y
    return _circumcentre_sorted(pts, ids, a, b, c)


@njit(cache=True, inline='always')
def _circumcentre_sorted(pts, ids, a, b, c):
    """The circumcentre computed from a, b, c in increasing site id (all of them: the careful
    paths, for a formula that cancels, may depend on the order of the last two). Inlined like
    its caller: as a call, even one almost never made, it slowed the one pass by a fifth."""
    ax, ay, ia = pts[a, 0], pts[a, 1], ids[a]
    bx, by, ib = pts[b, 0], pts[b, 1], ids[b]
    cx, cy, ic = pts[c, 0], pts[c, 1], ids[c]
    if ia > ib:
        ax, ay, ia, bx, by, ib = bx, by, ib, ax, ay, ia
    if ib > ic:
        bx, by, ib, cx, cy, ic = cx, cy, ic, bx, by, ib
    if ia > ib:
        ax, ay, ia, bx, by, ib = bx, by, ib, ax, ay, ia
    return circumcentre(ax, ay, bx, by, cx, cy)


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
def _linked_half_edges(hid, H, tri, opp, ids, vid):
    """(origin, twin, next, site) of the H Voronoi half-edges numbered ``hid`` on the
    triangulation's half-edges (-1: none). Delaunay half-edge e = u -> v gives cell u's half-edge
    from the centre of the triangle across e to the centre of e's own; around cell u it is
    followed by the half-edge of the next Delaunay half-edge out of u that has one, turning
    through the triangles (past ghosts and merged neighbours)."""
    m = hid.size
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
            raise RuntimeError("the dual of the triangulation: a cell does not close up")
        nxt[h] = hid[f]
    twin = np.arange(H, dtype=np.int32) ^ 1
    return origin, twin, nxt, site


@njit(cache=True)
def _general_dcel(pts, ids, tri, opp, ntri, counters):
    """:func:`voronoi_dcel`'s diagram built another way, the way it was built before the one pass
    folded cocircular groups itself: the vertices (merged by the union-find over every pair of
    neighbours), then each Voronoi edge numbered as a twin pair 2k, 2k + 1 and linked by turning
    through the triangles. About four times slower; kept as the independent construction
    tests/core/test_delaunay_dual.py holds :func:`voronoi_dcel` to."""
    inf = pts.shape[0]
    vid, vertices, merged = _merged_vertices(pts, ids, tri, opp, ntri, counters)
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
    origin, twin, nxt, site = _linked_half_edges(hid, 2 * pairs, tri, opp, ids, vid)
    # int32 like the one pass's (numba widens int32 ^ 1 to int64)
    return vertices, origin, twin.astype(np.int32), nxt, site, merged


@njit(cache=True)
def _ghosts_last(tri, opp, ntri, inf):
    """Renumber the triangles in place so that the ghosts come last: returns the number of
    finite triangles. Each ghost among the first slots trades places with the last finite
    triangle, and the neighbours' ``opp`` entries follow the move: a scan of ``tri`` and one
    swap per such ghost (a few dozen at 10^6 random sites; half the triangles on convex input)."""
    # the ghost test written out, not :func:`_is_ghost`: LLVM vectorises this count, and the
    # call made the scan five times slower (0.041 s against 0.0085 s at 10^6)
    ghosts = 0
    for t in range(ntri):
        if tri[3 * t] == inf or tri[3 * t + 1] == inf or tri[3 * t + 2] == inf:
            ghosts += 1
    finite = ntri - ghosts
    # each ghost among the first ``finite`` slots trades places with a finite triangle after them
    hi = ntri - 1
    for t in range(finite):
        if tri[3 * t] == inf or tri[3 * t + 1] == inf or tri[3 * t + 2] == inf:
            while tri[3 * hi] == inf or tri[3 * hi + 1] == inf or tri[3 * hi + 2] == inf:
                hi -= 1
            _swap_triangles(tri, opp, t, hi)
            hi -= 1
    return finite


@njit(cache=True, inline='always')
def _moved(f, i, j):
    """Half-edge f's number once triangles i and j have traded places."""
    t = f // 3
    if t == i:
        return 3 * j + (f - 3 * t)
    if t == j:
        return 3 * i + (f - 3 * t)
    return f


@njit(cache=True)
def _swap_triangles(tri, opp, i, j):
    """Triangles i and j trade places; every opp entry that pointed at one points at the other."""
    for k in range(3):
        a, b = 3 * i + k, 3 * j + k
        tri[a], tri[b] = tri[b], tri[a]
        oa, ob = _moved(opp[b], i, j), _moved(opp[a], i, j)
        opp[a] = oa
        opp[b] = ob
    for k in range(3):
        opp[opp[3 * i + k]] = 3 * i + k
        opp[opp[3 * j + k]] = 3 * j + k


@njit(cache=True, inline='always')
def _number(t, finite):
    """Triangle t's vertex number once the ghosts come last (:func:`_ghosts_last`): t for a
    finite triangle, -1 - g for ghost number g = t - finite."""
    return t if t < finite else finite - 1 - t


@njit(cache=True, inline='always')
def _half_edge_of(finite, tri, f, inf):
    """The Voronoi half-edge of Delaunay half-edge f when no two triangles merge (-1 for an edge
    to the infinite vertex): finite triangle t's three are 3t, 3t + 1, 3t + 2, and ghost g's one
    finite edge (a hull edge seen from outside: a ray) is 3 * finite + g."""
    if f < 3 * finite:
        return f
    t = f // 3
    if tri[f] == inf or tri[3 * t + (f - 3 * t + 1) % 3] == inf:
        return -1
    return 2 * finite + t


#: Bounds on the error of a computed circumcentre (:func:`circumcentre`), per coordinate: at
#: most CENTRE_RADIUS_ERROR times an upper bound on the circumradius, plus CENTRE_ROUNDING_ERROR
#: times the coordinate's magnitude (the derivation is in :func:`_centres_apart`).
CENTRE_RADIUS_ERROR = 2.0 ** -32
CENTRE_ROUNDING_ERROR = 2.0 ** -50


@njit(cache=True, inline='always')
def _centres_apart(x1, y1, x2, y2, px, py):
    """Whether the exact circumcentres of two triangles with common corner p certainly differ,
    given their computed centres (x1, y1) and (x2, y2): then the triangles are not cocircular.

    Error of a computed centre, per coordinate (u = 2**-53). The fast path of
    :func:`circumcentre` is taken only when the determinant and both numerators keep more than
    T = 1e-4 of the sum of their two terms. Their rounding errors, the rounded differences
    b - a and c - a included, are at most 4u (determinant) and 7u (numerators) of that sum, so
    at most 4u/T and 7u/T of the computed values; after the division the offset from the
    first corner is within 1.2e5 u times its size of the exact offset, whose size is at most
    the circumradius R. The double-double and exact paths are within 3u. Adding the first
    corner rounds by u of the coordinate. R is bounded through the common corner:
    R <= |x - px| + |y - py|, computed, up to terms far inside the margins below: 2**-32 is
    more than 16 times 1.2e5 u and 2**-50 is 8 times u, so each side of the comparison may
    lose a few roundings (a test holds the constants to these margins, should T change).
    """
    r1 = abs(x1 - px) + abs(y1 - py)
    r2 = abs(x2 - px) + abs(y2 - py)
    m1 = max(abs(x1), abs(y1))
    m2 = max(abs(x2), abs(y2))
    bound = CENTRE_RADIUS_ERROR * (r1 + r2) + CENTRE_ROUNDING_ERROR * (m1 + m2)
    return abs(x1 - x2) > bound or abs(y1 - y2) > bound


#: ``parent`` of :func:`_unmerged_dcel` when it is to stop at the first cocircular pair
_NO_UNION_FIND = np.empty(0, dtype=np.int32)

#: How many triangles ahead the one pass asks for the rows it will read (:mod:`prefetch`): the
#: pass waits on cache misses (a triangle's corners and neighbours lie anywhere in memory) and
#: its body is too long for the processor to run ahead by itself. The neighbours' centres are
#: asked for nearer (both distances tuned at 10^6). About 10 % off the dual at 10^6.
CORNERS_AHEAD = 16
CENTRES_AHEAD = 8


@njit(cache=True)
def _unmerged_dcel(pts, ids, tri, opp, ntri, finite, vertices, origin, twin, nxt, site, counters, parent,
                   first):
    """Fill the DCEL of the triangulation with one vertex per finite triangle, in one pass over
    the triangles from triangle ``first``: (stop, merged).

    With ``parent`` empty the pass stops at the first cocircular pair of neighbours and returns
    its triangle as ``stop`` (the arrays filled up to it); otherwise it goes on to the end,
    joining the vertex numbers of every cocircular pair in the union-find ``parent`` (the root
    of a set its smallest number) and counting the joins in ``merged``; ``stop`` is then -1.
    Cocircular neighbours are left as vertices joined by edges of zero length, which
    :func:`_merged_dcel` folds.

    The ghosts come last (:func:`_ghosts_last`), so finite triangle t is vertex t and no table
    of numbers is read. With no merges every edge of a finite triangle gives a Voronoi
    half-edge, so they are numbered by triangle (:func:`_half_edge_of`): the twin of
    edge e's half-edge is the half-edge of ``opp[e]``, its origin the centre of ``opp[e]``'s
    triangle, and around its cell it is followed by the twin of the half-edge of prev(e). Each
    circumcentre is computed as its triangle is read. A pair of finite neighbours is checked
    when the second of them is read: their computed centres first (:func:`_centres_apart`),
    and the exact incircle test only when the centres cannot be told apart.
    """
    inf = pts.shape[0]
    merged = 0
    for t in range(first, ntri):
        if t + CORNERS_AHEAD < ntri:
            # the rows this pass will read for a later triangle: its corners, their ids, the
            # numbers of its neighbours, and (for a nearer one) its neighbours' centres
            u = t + CORNERS_AHEAD
            for k in range(3):
                corner = tri[3 * u + k]
                prefetch(pts, corner)
                prefetch(ids, corner)
        if t + CENTRES_AHEAD < finite:
            u = t + CENTRES_AHEAD
            for k in range(3):
                t2 = opp[3 * u + k] // 3
                if t2 < finite:
                    prefetch(vertices, t2)
        v = _number(t, finite)
        if v >= 0:
            a = tri[3 * t]
            b = tri[3 * t + 1]
            c = tri[3 * t + 2]
            x, y = _circumcentre_of(pts, ids, a, b, c)
            vertices[v, 0] = x
            vertices[v, 1] = y
            for k in range(3):
                e = 3 * t + k
                oe = opp[e]
                t2 = oe // 3
                v2 = _number(t2, finite)
                h = 3 * v + k
                if v2 >= 0:
                    twin[h] = 3 * v2 + oe - 3 * t2
                    origin[h] = v2
                    # the centres first, whatever v2's row holds yet: they are almost always
                    # apart, a branch the processor predicts, where v2 < v (the neighbour is
                    # read already) is a coin toss it would often get wrong; about 15 % of the
                    # pass at 10^6. A row not written yet gives an answer that v2 < v drops.
                    if not _centres_apart(x, y, vertices[v2, 0], vertices[v2, 1],
                                          pts[tri[e], 0], pts[tri[e], 1]) and v2 < v:
                        d = tri[3 * t2 + (oe - 3 * t2 + 2) % 3]   # t2's corner off the shared edge
                        if incircle_counted(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1],
                                            pts[d, 0], pts[d, 1], counters) == 0:
                            if parent.size == 0:
                                return t, 0
                            r1 = find(parent, v)
                            r2 = find(parent, v2)
                            if r1 != r2:
                                parent[max(r1, r2)] = min(r1, r2)
                                merged += 1
                else:
                    twin[h] = 3 * finite - 1 - v2      # a hull edge: the ghost's one half-edge, a ray
                    origin[h] = -1
                site[h] = ids[tri[e]]
            # around cell a, the half-edge of a -> b follows the one of a -> c, the twin of c -> a's
            nxt[3 * v] = twin[3 * v + 2]
            nxt[3 * v + 1] = twin[3 * v]
            nxt[3 * v + 2] = twin[3 * v + 1]
        else:
            k = 0
            while tri[3 * t + k] == inf or tri[3 * t + (k + 1) % 3] == inf:
                k += 1
            e = 3 * t + k                          # the hull edge u -> w, seen from outside
            h = 3 * finite - 1 - v
            oe = opp[e]
            twin[h] = _half_edge_of(finite, tri, oe, inf)
            origin[h] = _number(oe // 3, finite)
            site[h] = ids[tri[e]]
            # around cell u, past the ghost edges to the infinite vertex, to the ray coming back
            f = opp[3 * t + (k + 2) % 3]
            for _ in range(ntri):
                g = _half_edge_of(finite, tri, f, inf)
                if g >= 0:
                    nxt[h] = g
                    break
                tf = f // 3
                f = opp[3 * tf + (f - 3 * tf + 2) % 3]
            else:
                raise RuntimeError("the dual of the triangulation: a cell does not close up")
    return -1, merged


@njit(cache=True)
def _merged_dcel(pts, ids, tri, parent, vertices, origin, twin, nxt, site, low, vnew, newh,
                 out_vertices, out_origin, out_twin, out_nxt, out_site):
    """Fold the cocircular groups of :func:`_unmerged_dcel`'s DCEL (one vertex per triangle,
    ``parent`` its union-find) into one vertex each, into the ``out_`` arrays.

    A group's triangles share one empty circle, so their corners all lie on it: the group
    triangulates a convex polygon, its triangles joined by a tree of diagonals, and each
    diagonal is one edge of zero length (two half-edges) to drop. A group's vertex is numbered
    by its root (its first triangle) and computed from the three smallest site ids on its circle,
    as for any vertex; around each cell a kept half-edge is followed by the next kept one.
    ``low`` (rows of three points), ``vnew`` (a number per vertex, zeroed) and ``newh`` (per
    half-edge) are scratch. Returns the number of vertices written.
    """
    finite = parent.size
    # every entry on its root: a root is the smallest number of its set, so parent[v] <= v and
    # an ascending pass finds parent[parent[v]] already a root
    for v in range(finite):
        parent[v] = parent[parent[v]]
    # vnew[r] = 1 marks the roots of groups of two or more (vnew comes zeroed)
    for v in range(finite):
        if parent[v] != v:
            vnew[parent[v]] = 1
    # each group's three points of smallest id (finite triangle v is vertex v, so a root's own
    # triangle is met before the others of its group)
    for v in range(finite):
        r = parent[v]
        if r == v:
            if vnew[v] == 1:
                _sort3_by_id(low, v, tri[3 * v], tri[3 * v + 1], tri[3 * v + 2], ids)
        else:
            for k in range(3):
                _insert_by_id(low, r, tri[3 * v + k], ids)
    nv = 0
    for v in range(finite):
        if parent[v] != v:
            continue
        if vnew[v] == 1:
            i, j, k = low[v, 0], low[v, 1], low[v, 2]
            x, y = circumcentre(pts[i, 0], pts[i, 1], pts[j, 0], pts[j, 1], pts[k, 0], pts[k, 1])
        else:
            x, y = vertices[v, 0], vertices[v, 1]
        out_vertices[nv, 0] = x
        out_vertices[nv, 1] = y
        vnew[v] = nv
        nv += 1
    # the half-edges between two vertices of one group have zero length: dropped. Finite
    # triangle v's half-edges 3v, 3v + 1, 3v + 2 end at v; a ghost's runs out to infinity.
    H = origin.size
    kept = 0
    for h in range(H):
        o = origin[h]
        if h < 3 * finite and o >= 0 and parent[o] == parent[h // 3]:
            newh[h] = -1
        else:
            newh[h] = kept
            kept += 1
    if kept != out_origin.size:
        raise RuntimeError("the dual of the triangulation: a cocircular group is not a tree of triangles")
    for h in range(H):
        j = newh[h]
        if j < 0:
            continue
        o = origin[h]
        out_origin[j] = -1 if o < 0 else vnew[parent[o]]
        out_twin[j] = newh[twin[h]]
        out_site[j] = site[h]
        g = nxt[h]
        for _ in range(H):
            if newh[g] >= 0:
                break
            g = nxt[g]
        if newh[g] < 0:
            raise RuntimeError("the dual of the triangulation: a cell does not close up")
        out_nxt[j] = newh[g]
    return nv


def voronoi_dcel(pts, ids, tri, opp, ntri, counters):
    """The Voronoi diagram dual to a Delaunay triangulation as int32 DCEL arrays, without
    sorting: (vertices, origin, twin, next, site, merged).

    Delaunay half-edge e = u -> v (its triangle t on its left) gives cell u's Voronoi
    half-edge, which runs along perp(v - u) from the centre of the triangle on e's right
    (``opp[e]``'s; -1 for a ghost: from infinity) to t's centre; its twin is the one of
    ``opp[e]``. It is followed, around cell u, by the Voronoi half-edge of the next Delaunay
    half-edge out of u, turning through t: ``opp[prev(e)]``; edges to the infinite vertex and
    edges inside a cocircular group have no Voronoi half-edge and are turned past (after a ray
    out to infinity, this reaches the ray coming back, as the contract asks). Same vertices as
    :func:`voronoi_edges`.

    The triangles of ``tri`` and ``opp`` are first renumbered in place, the ghosts last
    (:func:`_ghosts_last`: a scan and a few swaps), so that finite triangle t is vertex t: the
    pass then reads no table of vertex numbers, three cache misses fewer per triangle (about
    10 % of the dual at 10^6). Without cocircular neighbours (almost every input) this is one
    pass over the triangles (:func:`_unmerged_dcel`). From the first cocircular pair on, the
    pass also joins such pairs in a union-find, and :func:`_merged_dcel` then folds each group
    into one vertex, dropping the edges of zero length inside it. (:func:`_general_dcel` builds the same diagram another
    way, by numbering the edges between different vertices first; the tests hold this one to it.)

    The output arrays are allocated here by numpy, not in the compiled pass: numpy asks the
    kernel for transparent huge pages on large arrays, numba's own allocator does not, and
    writing 128 MB of fresh DCEL arrays at 10^6 sites took 0.08-0.10 s of page faults from
    numba's allocator, 0.03 s from numpy's (with THP set to "madvise", as on most
    distributions; docs/architecture.md, ``delaunay_dual.py``).
    """
    inf = pts.shape[0]
    finite = _ghosts_last(tri, opp, ntri, inf)
    H = 3 * finite + (ntri - finite)
    vertices = np.empty((finite, 2), dtype=np.float64)
    origin, twin, nxt, site = (np.empty(H, dtype=np.int32) for _ in range(4))
    stop, _ = _unmerged_dcel(pts, ids, tri, opp, ntri, finite, vertices, origin, twin, nxt, site, counters,
                             _NO_UNION_FIND, 0)
    if stop < 0:
        return vertices, origin, twin, nxt, site, 0
    # a cocircular pair: the pass goes on from there, joining every such pair, and the groups
    # are folded (no triangle before ``stop`` was cocircular with an earlier neighbour)
    parent = np.arange(finite, dtype=np.int32)
    _, merged = _unmerged_dcel(pts, ids, tri, opp, ntri, finite, vertices, origin, twin, nxt, site,
                               counters, parent, stop)
    out_vertices = np.empty((finite - merged, 2), dtype=np.float64)
    out = [np.empty(H - 2 * merged, dtype=np.int32) for _ in range(4)]
    low = np.empty((finite, 3), dtype=np.int32)
    vnew = np.zeros(finite, dtype=np.int32)
    newh = np.empty(H, dtype=np.int32)
    _merged_dcel(pts, ids, tri, parent, vertices, origin, twin, nxt, site, low, vnew, newh,
                 out_vertices, *out)
    return (out_vertices, *out, merged)


# ---------------------------------------------------------------------------------------------
# Power diagrams: the dual of a regular triangulation
#
# A regular triangulation is the projection of the lower hull of the lifted points
# (x, y, x**2 + y**2 - w). Neighbouring triangles whose four lifts are coplanar lie in one facet
# of that hull and give one power vertex (union-find, as for cocircular Delaunay triangles). A
# vertex of the triangulation may still fail to be a vertex of the hull once facets are merged
# (its lift was inserted exactly onto a later facet or edge): its power cell has no interior, so
# the site is hidden. Around such a site v, the merged facets number
# * one (v's lift inside a facet): no edge of v separates two power vertices: no half-edge;
# * two, v inside the triangulation (v's lift inside an edge of the hull, the segment between
#   the lifts of two hull vertices u and x, through v and maybe more such sites): the power edge
#   between u and x is dual to the chain u - v - ... - x; it is made from the half-edges of
#   u -> v and x -> (last site before x), paired as twins ("through" sites);
# * one, v on the convex hull between collinear hull neighbours: likewise, a ray.
# Everything else is an ordinary site. A vertex's coordinates come from the three smallest ids
# among the visible sites around it (the corners of its facet), never three collinear sites.
# ---------------------------------------------------------------------------------------------

#: Site classes of :func:`power_vertices` (``state``): an ordinary site (or one absent from the
#: triangulation), a vertex whose lift lies inside a facet of the lower hull, one inside an edge.
VISIBLE = 0
FLAT = 1
THROUGH = 2


@njit(cache=True)
def _power_centre_of(pts, w, ids, a, b, c):
    # the power centre computed from a, b, c in increasing site id (the rule of the module)
    a, b, c = _by_id(ids, a, b, c)
    return power_centre(pts[a, 0], pts[a, 1], w[a], pts[b, 0], pts[b, 1], w[b], pts[c, 0], pts[c, 1], w[c])


@njit(cache=True, inline='always')
def _coplanar_across(pts, w, tri, t, d, counters):
    """Whether d's lift lies on the plane of the lifts of finite triangle t's corners."""
    a = tri[3 * t]
    b = tri[3 * t + 1]
    c = tri[3 * t + 2]
    return power_test_counted(pts[a, 0], pts[a, 1], w[a], pts[b, 0], pts[b, 1], w[b], pts[c, 0], pts[c, 1], w[c],
                              pts[d, 0], pts[d, 1], w[d], counters) == 0


@njit(cache=True)
def power_vertices(pts, w, ids, tri, opp, ntri, counters):
    """The power vertex of every triangle of a regular triangulation: (vid, vertices, merged,
    state, through).

    ``vid[t]``: triangle t's vertex (-1 for a ghost), shared by neighbours with coplanar lifts;
    ``merged`` counts triangles folded into a neighbour's vertex; ``state[v]`` classes point v
    (:data:`VISIBLE`, :data:`FLAT`, :data:`THROUGH`) and ``through[v]`` holds a through site's two
    half-edges that separate different vertices. One pass when no two neighbours are coplanar
    (then every vertex of the triangulation is visible); the first coplanar pair found hands
    over to :func:`_merged_power_vertices`. ``counters`` needs the power-test entries.
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
        x, y = _power_centre_of(pts, w, ids, a, b, c)
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
        d = tri[3 * t2 + (oe - 3 * t2 + 2) % 3]
        if _coplanar_across(pts, w, tri, t, d, tests):
            return _merged_power_vertices(pts, w, ids, tri, opp, ntri, counters)
    counters += tests
    return vid, vertices[:nv], 0, np.zeros(n, dtype=np.int8), np.full((n, 2), -1, dtype=np.int64)


@njit(cache=True)
def _classify_sites(pts, tri, opp, ntri, group, counters):
    """(state, through): count, around each vertex v of the triangulation, its out-edges whose two
    sides belong to different groups (ghosts form group -1). None: FLAT; two, v interior or a hull
    site between collinear hull neighbours: THROUGH, those two edges kept; else VISIBLE."""
    n = pts.shape[0]
    state = np.zeros(n, dtype=np.int8)
    through = np.full((n, 2), -1, dtype=np.int64)
    corner = np.full(n + 1, -1, dtype=np.int64)
    for e in range(3 * ntri):
        corner[tri[e]] = e
    for v in range(n):
        e0 = corner[v]
        if e0 < 0:
            continue
        e = e0
        count = 0
        hull = False
        for _ in range(3 * ntri):
            t = e // 3
            k = e - 3 * t
            g_left = group[t]
            g_right = group[opp[e] // 3]
            if g_left < 0:
                hull = True
            if g_left != g_right:
                if count < 2:
                    through[v, count] = e
                count += 1
            e = opp[3 * t + (k + 2) % 3]
            if e == e0:
                break
        if count == 0:
            state[v] = FLAT
        elif count == 2:
            if hull:
                # the two separating edges are the hull edges v -> u and v -> x
                e1 = through[v, 0]
                e2 = through[v, 1]
                u = tri[3 * (e1 // 3) + (e1 % 3 + 1) % 3]
                x = tri[3 * (e2 // 3) + (e2 % 3 + 1) % 3]
                if orient2d_counted(pts[u, 0], pts[u, 1], pts[v, 0], pts[v, 1], pts[x, 0], pts[x, 1], counters) == 0:
                    state[v] = THROUGH
            else:
                state[v] = THROUGH
        if state[v] != THROUGH:
            through[v, 0] = -1
            through[v, 1] = -1
    return state, through


@njit(cache=True)
def _merged_power_vertices(pts, w, ids, tri, opp, ntri, counters):
    """:func:`power_vertices` when some neighbours have coplanar lifts: union-find over them, the
    sites classified, one vertex per group from its visible corners."""
    n = pts.shape[0]
    inf = n
    parent = np.arange(ntri)
    ghost = np.zeros(ntri, dtype=np.bool_)
    for t in range(ntri):
        ghost[t] = _is_ghost(tri, t, inf)
    merged = 0
    for e in range(3 * ntri):
        oe = opp[e]
        if oe < e:
            continue
        t = e // 3
        t2 = oe // 3
        if ghost[t] or ghost[t2]:
            continue
        d = tri[3 * t2 + (oe - 3 * t2 + 2) % 3]
        if _coplanar_across(pts, w, tri, t, d, counters):
            r1 = find(parent, t)
            r2 = find(parent, t2)
            if r1 != r2:
                parent[max(r1, r2)] = min(r1, r2)
                merged += 1
    group = np.full(ntri, -1, dtype=np.int64)
    for t in range(ntri):
        if not ghost[t]:
            group[t] = find(parent, t)
    state, through = _classify_sites(pts, tri, opp, ntri, group, counters)
    # ---- the three visible corners of smallest site id of each group
    low = np.full((ntri, 3), -1, dtype=np.int64)
    nlow = np.zeros(ntri, dtype=np.int64)
    for t in range(ntri):
        r = group[t]
        if r < 0:
            continue
        for k in range(3):
            s = tri[3 * t + k]
            if state[s] != VISIBLE or s == low[r, 0] or s == low[r, 1] or s == low[r, 2]:
                continue
            if nlow[r] < 3:
                low[r, nlow[r]] = s
                nlow[r] += 1
                if nlow[r] == 3:
                    _sort3_by_id(low, r, low[r, 0], low[r, 1], low[r, 2], ids)
            else:
                _insert_by_id(low, r, s, ids)
    vid = np.full(ntri, -1, dtype=np.int64)
    nv = 0
    for t in range(ntri):
        if group[t] == t:
            vid[t] = nv
            nv += 1
    vertices = np.empty((nv, 2), dtype=np.float64)
    for t in range(ntri):
        if vid[t] < 0:
            continue
        if nlow[t] < 3:
            raise RuntimeError("power_vertices: a facet of the lower hull has fewer than three visible corners")
        x, y = _power_centre_of(pts, w, ids, low[t, 0], low[t, 1], low[t, 2])
        vertices[vid[t], 0] = x
        vertices[vid[t], 1] = y
    for t in range(ntri):
        if group[t] >= 0:
            vid[t] = vid[group[t]]
    return vid, vertices, merged, state, through


@njit(cache=True, inline='always')
def _head(tri, e):
    """The vertex half-edge e points to."""
    t = e // 3
    return tri[3 * t + (e - 3 * t + 1) % 3]


@njit(cache=True)
def _across_chain(tri, e, state, through, n):
    """For e = u -> v with v a THROUGH site: the last half-edge y -> x of the straight chain of
    through sites u - v - ... - y - x (x not a through site); its twin x -> y is the twin of
    e's power half-edge."""
    prev = tri[e]
    cur = _head(tri, e)
    for _ in range(n):
        # leave cur by its separating edge that does not lead back to prev
        out = through[cur, 0]
        if _head(tri, out) == prev:
            out = through[cur, 1]
        x = _head(tri, out)
        if state[x] != THROUGH:
            return out
        prev = cur
        cur = x
    raise RuntimeError("power_dcel: a chain of through sites does not end")


@njit(cache=True)
def power_dcel(pts, w, ids, tri, opp, ntri, counters):
    """The power diagram dual to a regular triangulation (ghosts included, as in
    :func:`voronoi_dcel`) as DCEL arrays: (vertices, origin, twin, next, site, merged, degenerate).

    ``pts``, ``w``: the weighted points the triangulation indexes, ``ids[v]`` their site ids. As in
    :func:`voronoi_dcel`, each Delaunay half-edge u -> v separating two different vertices gives
    cell u's half-edge from the vertex on its right to the one on its left, followed around u by
    turning through the triangles; its twin is the half-edge of v -> u, or, when v is a through
    site, of the half-edge closing the chain of through sites. Sites absent from the
    triangulation and FLAT or THROUGH sites get no half-edge (hidden); ``degenerate`` counts
    the latter two. ``counters`` needs the power-test entries.
    """
    n = pts.shape[0]
    inf = n
    vid, vertices, merged, state, through = power_vertices(pts, w, ids, tri, opp, ntri, counters)
    m = 3 * ntri
    hid = np.full(m, -1, dtype=np.int32)
    pairs = 0
    for e in range(m):
        if hid[e] >= 0:
            continue
        oe = opp[e]
        t = e // 3
        a = tri[e]
        b = tri[3 * t + (e - 3 * t + 1) % 3]
        if a == inf or b == inf or vid[t] == vid[oe // 3] or state[a] != VISIBLE:
            continue
        partner = oe
        if state[b] == THROUGH:
            partner = opp[_across_chain(tri, e, state, through, n)]
        elif state[b] != VISIBLE:
            raise RuntimeError("power_dcel: a flat site on an edge between two power vertices")
        hid[e] = 2 * pairs
        hid[partner] = 2 * pairs + 1
        pairs += 1
    degenerate = 0
    for v in range(n):
        if state[v] != VISIBLE:
            degenerate += 1
    origin, twin, nxt, site = _linked_half_edges(hid, 2 * pairs, tri, opp, ids, vid)
    return vertices, origin, twin, nxt, site, merged, degenerate
