"""Regular (weighted Delaunay) triangulation by incremental insertion and flips, compiled with numba.

A weighted point (x, y, w) lifts to (x, y, x**2 + y**2 - w); the regular triangulation is the
projection of the lower convex hull of the lifted points. A point whose lift lies on or above
that hull is *hidden*: it is no vertex, and its power cell is empty (or has no interior).

Storage is the one of :mod:`.triangulate` (corner ``e = 3 t + k``, half-edge ``e`` from
``tri[e]`` to the next corner, ``opp[e]`` its twin, ghost triangles on the infinite vertex
``n``), with two additions: a triangle slot freed by a vertex removal is marked dead
(``tri[3 t] = -1``) and reused, and every triangle created while inserting p is written with p
at its first corner, so that its edge opposite p (the *link edge*) is corner 1.

Insertion of p (Edelsbrunner & Shah, "Incremental topological flipping works for regular
triangulations", 1996), every decision an exact predicate:

1. Walk to the triangle containing p (or to the ghost beyond the hull edge p sees).
2. Inside the hull, if p's lift is on or above the lifted triangle (``power_test <= 0``), p is
   hidden: skip it. Outside the hull a point is never hidden.
3. Split: 1 -> 3 in a triangle, 2 -> 4 on an edge (a hull edge splits its ghost too).
4. Restore regularity edge by edge from a stack of triangles at p. The link edge ab of
   triangle (p, a, b), with d across it, is *non-regular* when d's lift lies strictly below the
   plane through the lifts of a, b, p (``power_test(a, b, p, d) > 0``). Then
   * quadrilateral p, a, d, b strictly convex: 2 -> 2 flip (ab becomes pd);
   * reflex at a (b) of degree 3: 3 -> 1 flip, the vertex is removed (hidden);
   * a (b) on the segment pd, of degree 4: 4 -> 2 flip, the vertex is removed (its lift is
     above the segment between the lifts of p and d);
   * otherwise nothing: a later flip around p settles it (Edelsbrunner-Shah).
   A ghost link edge (a or b infinite) is non-regular when p lies strictly outside the hull
   edge across it (2 -> 2 flip, the hull grows), or on its line with the finite end h strictly
   between p and d and h's lift above the segment between the lifts of p and d (4 -> 2 flip).

With equal weights the lifts lie on the paraboloid: no point is ever hidden, no vertex removed,
and the result is the Delaunay triangulation.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from impls.incremental.triangulate import _WALK_CAP_FACTOR, _cell, _ghost_edge, _strictly_between, _walk_grid
from vorobench.core.predicates import N_POWER_COUNTERS, orient2d_counted, power_test_counted

__all__ = ["regular_triangulation", "STAT_NAMES", "N_COUNTERS"]

#: Operation counts returned by :func:`regular_triangulation`, in order.
STAT_NAMES = ("insertions", "walk_steps", "hidden_at_insertion", "flips", "flips_3_1", "flips_4_2")
_INSERTIONS, _WALK, _HIDDEN_AT_INSERTION, _FLIPS, _FLIPS_3_1, _FLIPS_4_2 = range(6)

#: Length of the predicate counters array (orient2d, incircle, power test, bisector blocks).
N_COUNTERS = N_POWER_COUNTERS

_DEAD = -1


@njit(cache=True, inline='always')
def _orient(pts, a, b, c, counters):
    return orient2d_counted(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], pts[c, 0], pts[c, 1], counters)


@njit(cache=True, inline='always')
def _power(pts, w, a, b, c, d, counters):
    """Exact power test of d against (a, b, c): for a, b, c counter-clockwise, +1 when d's lift is
    strictly below the plane of their lifts."""
    return power_test_counted(pts[a, 0], pts[a, 1], w[a], pts[b, 0], pts[b, 1], w[b],
                              pts[c, 0], pts[c, 1], w[c], pts[d, 0], pts[d, 1], w[d], counters)


@njit(cache=True, inline='always')
def _has_inf(tri, t, inf):
    return tri[3 * t] == inf or tri[3 * t + 1] == inf or tri[3 * t + 2] == inf


@njit(cache=True)
def _locate(pts, tri, opp, start, inf, px, py, cap, counters, stats):
    """Visibility walk from finite triangle ``start``: (t, e). t is the finite triangle containing
    p (closed), with e the half-edge whose line p lies on (-1 if none), or the ghost beyond the
    hull edge p sees (e = -1). Regular triangulations admit no cycle of visibility walks."""
    t = start
    came = -1
    for step in range(cap):
        stats[_WALK] += 1
        moved = False
        on_edge = -1
        for k in range(3):
            e = 3 * t + (k + step) % 3
            if e == came:       # p is strictly inside the edge just crossed
                continue
            a = tri[e]
            b = tri[3 * t + (e - 3 * t + 1) % 3]
            o = orient2d_counted(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py, counters)
            if o < 0:
                came = opp[e]
                t = came // 3
                moved = True
                break
            if o == 0:
                on_edge = e
        if not moved:
            return t, on_edge
        if _has_inf(tri, t, inf):
            return t, -1
    raise RuntimeError("incremental (weighted): point location walk exceeded its step cap")


@njit(cache=True)
def _alloc(free, meta):
    """A triangle slot: a dead one if any (meta[1] of them on ``free``), else a new one (meta[0])."""
    if meta[1] > 0:
        meta[1] -= 1
        return free[meta[1]]
    s = meta[0]
    meta[0] += 1
    return s


@njit(cache=True)
def _release(tri, free, meta, s):
    tri[3 * s] = _DEAD
    free[meta[1]] = s
    meta[1] += 1


@njit(cache=True, inline='always')
def _write(tri, s, x, y, z):
    tri[3 * s] = x
    tri[3 * s + 1] = y
    tri[3 * s + 2] = z


@njit(cache=True, inline='always')
def _link(opp, e, f):
    opp[e] = f
    opp[f] = e


@njit(cache=True, inline='always')
def _fan(tri, opp, p, us, vs, outer, slots, k):
    """Close the polygon us[0] -> us[1] -> ... (vs[j] == us[j + 1], cyclically) around p: triangle
    (p, us[j], vs[j]) in slot slots[j], its link edge twinned with ``outer[j]``."""
    for j in range(k):
        s = slots[j]
        _write(tri, s, p, us[j], vs[j])
        _link(opp, 3 * s + 1, outer[j])
    for j in range(k):
        # edge vs[j] -> p of triangle j against edge p -> us[j + 1] of the next one
        _link(opp, 3 * slots[j] + 2, 3 * slots[(j + 1) % k])


@njit(cache=True, inline='always')
def _flip(tri, opp, t, n, oe, p, a, b, d):
    """2 -> 2 flip of link edge a -> b of (p, a, b) in slot t, across ``oe`` (b -> a in slot n,
    whose third corner is d): (p, a, d) in t and (p, d, b) in n."""
    ka = 3 * t + 1
    kb = 3 * t + 2
    j = oe - 3 * n
    x_bp = opp[kb]                       # beyond b -> p
    x_pa = opp[3 * t]                    # beyond p -> a
    y_ad = opp[3 * n + (j + 1) % 3]      # beyond a -> d
    y_db = opp[3 * n + (j + 2) % 3]      # beyond d -> b
    _write(tri, t, p, a, d)
    _write(tri, n, p, d, b)
    _link(opp, 3 * t, x_pa)
    _link(opp, ka, y_ad)
    _link(opp, kb, 3 * n)                # d -> p  against  p -> d
    _link(opp, 3 * n + 1, y_db)
    _link(opp, 3 * n + 2, x_bp)


@njit(cache=True)
def _star(tri, opp, e, X, T, O, cap):
    """Circulate counter-clockwise around the vertex at corner e: its neighbours X, triangles T and,
    for each, the twin O of the edge X[i] -> X[i+1] facing the vertex; the degree, or -1 if above cap."""
    start = e
    for i in range(cap + 1):
        t = e // 3
        k = e - 3 * t
        if i == cap:
            return -1
        X[i] = tri[3 * t + (k + 1) % 3]
        T[i] = t
        O[i] = opp[3 * t + (k + 1) % 3]
        e = opp[3 * t + (k + 2) % 3]     # the edge from the vertex to X[i + 1], in the next triangle
        if e == start:
            return i + 1
    return -1


@njit(cache=True)
def _remove_vertex(tri, opp, free, meta, deg, p, v, ev, d, X, T, O):
    """Remove vertex v (corner ev) of degree 3, or of degree 4 lying on the segment from p to d: its
    star becomes one triangle, or the two triangles on either side of pd. Returns a slot at p, or
    -1 if the star is not as expected (nothing changed)."""
    m = _star(tri, opp, ev, X, T, O, 4)
    if m < 3:
        return -1
    r = -1
    for i in range(m):
        if X[i] == p:
            r = i
    if r < 0:
        return -1
    x0 = X[r]
    x1 = X[(r + 1) % m]
    x2 = X[(r + 2) % m]
    o0 = O[r]
    o1 = O[(r + 1) % m]
    o2 = O[(r + 2) % m]
    if m == 3:
        s = T[0]
        _write(tri, s, x0, x1, x2)
        _link(opp, 3 * s, o0)
        _link(opp, 3 * s + 1, o1)
        _link(opp, 3 * s + 2, o2)
        _release(tri, free, meta, T[1])
        _release(tri, free, meta, T[2])
        for i in range(3):
            deg[X[i]] -= 1
        return s
    if x2 != d:
        return -1
    x3 = X[(r + 3) % m]
    o3 = O[(r + 3) % m]
    s = T[0]
    s2 = T[1]
    _write(tri, s, x0, x1, x2)            # p, x1, d
    _write(tri, s2, x0, x2, x3)           # p, d, x3
    _link(opp, 3 * s, o0)
    _link(opp, 3 * s + 1, o1)
    _link(opp, 3 * s + 2, 3 * s2)        # d -> p  against  p -> d
    _link(opp, 3 * s2 + 1, o2)
    _link(opp, 3 * s2 + 2, o3)
    _release(tri, free, meta, T[2])
    _release(tri, free, meta, T[3])
    deg[x1] -= 1
    deg[x3] -= 1
    return s


@njit(cache=True)
def _above_segment(pts, w, tri, opp, p, h, d, ghost, inf, counters):
    """For h strictly inside segment pd on a hull edge h-d (ghost triangle ``ghost`` beyond it):
    whether h's lift lies strictly above the segment between the lifts of p and d.

    With x any point off the line, the lifted 4x4 determinant of (p, d, x, h) factors as the
    height of h's lift above that segment times orient2d(p, d, x) (times -1): one exact power
    test decides it, whatever x's weight. x is the apex of the finite triangle on hull edge h-d.
    """
    for k in range(3):
        e = 3 * ghost + k
        if tri[e] != inf and tri[3 * ghost + (k + 1) % 3] != inf:
            f = opp[e]
            g = f // 3
            x = tri[3 * g + (f - 3 * g + 2) % 3]
            o = _orient(pts, p, d, x, counters)
            return _power(pts, w, p, d, x, h, counters) * o < 0
    return False


@njit(cache=True)
def _other_at_p(tri, opp, s):
    """After a 4 -> 2 flip wrote (p, x1, d) in slot s: the slot of its partner (p, d, x3)."""
    return opp[3 * s + 2] // 3


@njit(cache=True)
def _corner_of(tri, t, v):
    for k in range(3):
        if tri[3 * t + k] == v:
            return 3 * t + k
    return -1


@njit(cache=True, inline='always')
def _flip_and_push(tri, opp, deg, stack, sp, t, nb, oe, p, a, b, d):
    """2 -> 2 flip of the link edge of t (see :func:`_flip`), both new triangles pushed; new sp."""
    _flip(tri, opp, t, nb, oe, p, a, b, d)
    deg[a] -= 1
    deg[b] -= 1
    deg[p] += 1
    deg[d] += 1
    stack[sp] = t
    stack[sp + 1] = nb
    return sp + 2


@njit(cache=True)
def regular_triangulation(pts, w, counters):
    """Regular triangulation of weighted points inserted in their given order.

    Returns (tri, opp, ntri, hidden, stats, ok): live triangles compacted to slots [0, ntri);
    ``hidden[i]`` for points skipped or removed; ``ok`` False when all points are collinear (no
    triangle exists). ``counters`` (length :data:`N_COUNTERS`) receives the predicate counts.
    """
    n = pts.shape[0]
    inf = n
    stats = np.zeros(len(STAT_NAMES), dtype=np.int64)
    hidden = np.zeros(n, dtype=np.bool_)
    cap_t = 2 * n + 8
    tri = np.empty(3 * cap_t, dtype=np.int32)
    opp = np.empty(3 * cap_t, dtype=np.int32)
    if n < 3:
        return tri, opp, 0, hidden, stats, False
    # ---- seed triangle: the first two points and the first one not collinear with them; all
    # three are vertices of their own regular triangulation (a triangle's lower hull is itself)
    third = -1
    o = 0
    for m in range(2, n):
        o = _orient(pts, 0, 1, m, counters)
        if o != 0:
            third = m
            break
    if third < 0:
        return tri, opp, 0, hidden, stats, False
    i1 = 1
    i2 = third
    if o < 0:
        i1, i2 = i2, i1
    seed = (0, i1, i2)
    deg = np.zeros(n + 1, dtype=np.int32)
    for k in range(3):
        tri[k] = seed[k]
        deg[seed[k]] = 3
    deg[inf] = 3
    for k in range(3):
        g = 1 + k                       # ghost beyond seed[k] -> seed[k+1]
        tri[3 * g] = seed[(k + 1) % 3]
        tri[3 * g + 1] = seed[k]
        tri[3 * g + 2] = inf
        _link(opp, k, 3 * g)
    for k in range(3):
        g = 1 + k
        gp = 1 + (k + 2) % 3
        _link(opp, 3 * g + 1, 3 * gp + 2)
    meta = np.zeros(2, dtype=np.int64)   # high-water mark of slots, number of free slots
    meta[0] = 4
    stats[_INSERTIONS] = 3
    free = np.empty(cap_t, dtype=np.int64)
    stack = np.empty(4 * cap_t + 16, dtype=np.int64)
    us = np.empty(4, dtype=np.int64)
    vs = np.empty(4, dtype=np.int64)
    outer = np.empty(4, dtype=np.int64)
    slots = np.empty(4, dtype=np.int64)
    X = np.empty(4, dtype=np.int64)
    T = np.empty(4, dtype=np.int64)
    O = np.empty(4, dtype=np.int64)
    # walk starts: as in :mod:`.triangulate`, the previous insertion's triangle facing this point,
    # or a triangle at the last vertex inserted into p's cell of a coarse grid when nearer
    vertex_tri = np.zeros(n + 1, dtype=np.int32)
    side, x0, y0, cell_scale, cell_vertex = _walk_grid(pts, seed)
    last = 0
    previous = i2
    for p in range(2, n):
        if p == third:
            continue
        px = pts[p, 0]
        py = pts[p, 1]
        cell = _cell(px, py, x0, y0, cell_scale, side)
        start = last
        u = cell_vertex[cell]
        if u >= 0 and not hidden[u] and ((pts[u, 0] - px) ** 2 + (pts[u, 1] - py) ** 2
                                         < (pts[previous, 0] - px) ** 2 + (pts[previous, 1] - py) ** 2):
            s = vertex_tri[u]
            if tri[3 * s] != _DEAD and not _has_inf(tri, s, inf):
                start = s
        t, on_edge = _locate(pts, tri, opp, start, inf, px, py,
                             _WALK_CAP_FACTOR * meta[0] + 64, counters, stats)
        # ---- hidden at insertion: p inside (or on) finite triangle t, its lift on or above t's
        ghost = _has_inf(tri, t, inf)
        if not ghost:
            a = tri[3 * t]
            b = tri[3 * t + 1]
            c = tri[3 * t + 2]
            if _power(pts, w, a, b, c, p, counters) <= 0:
                hidden[p] = True
                stats[_HIDDEN_AT_INSERTION] += 1
                last = t
                continue
        # ---- split (1 -> 3 in t, or 2 -> 4 on its half-edge on_edge with the triangle across):
        # p's star is the fan over the boundary of the region, written p first into ``slots``.
        # (Inline, as is the flipping below: as separate numba functions they cost 25% here.)
        if on_edge < 0:
            for k in range(3):
                e = 3 * t + k
                us[k] = tri[e]
                vs[k] = tri[3 * t + (k + 1) % 3]
                outer[k] = opp[e]
                deg[tri[e]] += 1
            slots[0] = t
            slots[1] = _alloc(free, meta)
            slots[2] = _alloc(free, meta)
            nfan = 3
        else:
            ka = on_edge - 3 * t
            oe = opp[on_edge]
            nb = oe // 3
            jb = oe - 3 * nb
            a = tri[on_edge]
            b = tri[3 * t + (ka + 1) % 3]
            c = tri[3 * t + (ka + 2) % 3]
            d = tri[3 * nb + (jb + 2) % 3]
            # the boundary b -> c -> a (in t), a -> d -> b (across); a and b keep their degree
            us[0] = b
            vs[0] = c
            outer[0] = opp[3 * t + (ka + 1) % 3]
            us[1] = c
            vs[1] = a
            outer[1] = opp[3 * t + (ka + 2) % 3]
            us[2] = a
            vs[2] = d
            outer[2] = opp[3 * nb + (jb + 1) % 3]
            us[3] = d
            vs[3] = b
            outer[3] = opp[3 * nb + (jb + 2) % 3]
            deg[c] += 1
            deg[d] += 1
            slots[0] = t
            slots[1] = nb
            slots[2] = _alloc(free, meta)
            slots[3] = _alloc(free, meta)
            nfan = 4
        _fan(tri, opp, p, us, vs, outer, slots, nfan)
        deg[p] = nfan
        # ---- flip until every link edge of p is regular (Edelsbrunner-Shah), from a stack of
        # triangles at p (p at their first corner; a popped slot no longer at p is skipped)
        sp = 0
        for j in range(nfan):
            stack[sp] = slots[j]
            sp += 1
        at_p = slots[0]
        budget = 8 * n + 64       # pops; a correct run needs at most 6 n + 4
        while sp > 0:
            sp -= 1
            t = stack[sp]
            if tri[3 * t] != p:
                continue
            budget -= 1
            if budget < 0:
                raise RuntimeError("incremental (weighted): flipping did not terminate")
            a = tri[3 * t + 1]
            b = tri[3 * t + 2]
            oe = opp[3 * t + 1]
            nb = oe // 3
            d = tri[3 * nb + (oe - 3 * nb + 2) % 3]
            v = -1                          # a vertex to remove, of degree 3 or 4
            if a == inf or b == inf:
                # ghost link edge: the ghost across holds the hull edge from h (its finite end) to d
                uu, vv = _ghost_edge(tri, nb, inf)
                o = _orient(pts, uu, vv, p, counters)
                if o > 0:                   # p sees that hull edge: the hull grows over it
                    sp = _flip_and_push(tri, opp, deg, stack, sp, t, nb, oe, p, a, b, d)
                    stats[_FLIPS] += 1
                    at_p = t
                    continue
                h = b if a == inf else a
                # p on the hull edge's line beyond h: h is hidden if its lift is above the segment
                if (o == 0 and deg[h] == 4 and _strictly_between(pts, p, d, pts[h, 0], pts[h, 1])
                        and _above_segment(pts, w, tri, opp, p, h, d, nb, inf, counters)):
                    v = h
            elif d == inf:                  # hull edge ab, p inside: regular
                continue
            else:
                if _power(pts, w, a, b, p, d, counters) <= 0:
                    continue                # d's lift on or above the plane of a, b, p: regular
                oa = _orient(pts, p, a, d, counters)
                ob = _orient(pts, d, b, p, counters)
                if oa > 0 and ob > 0:       # convex quadrilateral p, a, d, b
                    sp = _flip_and_push(tri, opp, deg, stack, sp, t, nb, oe, p, a, b, d)
                    stats[_FLIPS] += 1
                    at_p = t
                    continue
                # reflex at a (b) of degree 3: a lies inside triangle p, d, b and its lift above it;
                # a on the segment pd, of degree 4: its lift is above the segment between p's and d's
                if oa < 0 and deg[a] == 3:
                    v = a
                elif ob < 0 and deg[b] == 3:
                    v = b
                elif oa == 0 and deg[a] == 4:
                    v = a
                elif ob == 0 and deg[b] == 4:
                    v = b
            if v < 0:
                continue                    # not yet removable: a later flip at p settles it
            s = _remove_vertex(tri, opp, free, meta, deg, p, v, _corner_of(tri, t, v), d, X, T, O)
            if s < 0:
                continue
            hidden[v] = True
            stack[sp] = s
            sp += 1
            if deg[v] == 3:
                stats[_FLIPS_3_1] += 1
            else:
                stats[_FLIPS_4_2] += 1
                stack[sp] = _other_at_p(tri, opp, s)
                sp += 1
            at_p = s


        # ---- bookkeeping: walk starts, the grid, the triangle facing the next point
        e = _corner_of(tri, at_p, p)
        nxt = p + 1 if p + 1 != third else p + 2
        qx = pts[nxt, 0] if nxt < n else px
        qy = pts[nxt, 1] if nxt < n else py
        chosen = -1
        for _ in range(deg[p] + 1):
            s = e // 3
            k = e - 3 * s
            x = tri[3 * s + (k + 1) % 3]
            y = tri[3 * s + (k + 2) % 3]
            if x != inf and y != inf:
                vertex_tri[x] = s
                vertex_tri[y] = s
                if chosen < 0:
                    chosen = s
                # the wedge at p from x to y holds the direction to q (a starting guess: floats)
                if ((pts[x, 0] - px) * (qy - py) - (pts[x, 1] - py) * (qx - px) >= 0.0
                        and (qx - px) * (pts[y, 1] - py) - (qy - py) * (pts[y, 0] - px) >= 0.0):
                    chosen = s
                    break
            e = opp[3 * s + (k + 2) % 3]
        vertex_tri[p] = chosen
        last = chosen
        cell_vertex[cell] = p
        previous = p
        stats[_INSERTIONS] += 1
    tri, opp, ntri = _compact(tri, opp, meta[0])
    return tri, opp, ntri, hidden, stats, True


@njit(cache=True)
def _compact(tri, opp, high):
    """The live triangles renumbered into slots [0, ntri), twins remapped."""
    new_id = np.empty(high, dtype=np.int64)
    ntri = 0
    for s in range(high):
        if tri[3 * s] != _DEAD:
            new_id[s] = ntri
            ntri += 1
        else:
            new_id[s] = -1
    if ntri == high:
        return tri, opp, ntri
    tri2 = np.empty(3 * ntri, dtype=np.int32)
    opp2 = np.empty(3 * ntri, dtype=np.int32)
    for s in range(high):
        r = new_id[s]
        if r < 0:
            continue
        for k in range(3):
            tri2[3 * r + k] = tri[3 * s + k]
            f = opp[3 * s + k]
            g = f // 3
            opp2[3 * r + k] = 3 * new_id[g] + (f - 3 * g)
    return tri2, opp2, ntri
