"""Bowyer–Watson Delaunay triangulation with an infinite vertex, compiled with numba.

Triangles are stored as flat arrays in the style of delaunator: corner ``e = 3 t + k`` holds
vertex ``tri[e]``, and half-edge ``e`` runs from ``tri[e]`` to the next corner of the same
triangle, counter-clockwise; ``opp[e]`` is the half-edge running the other way in the
neighbouring triangle. The convex hull is closed by *ghost* triangles that use the infinite
vertex ``n``: every hull edge has a ghost on its outer side, so the triangulation is a closed
surface and hull growth is the ordinary cavity update.

Conflict (the circumcircle contains the new site p, strictly):
* finite triangle (a, b, c): incircle(a, b, c, p) > 0;
* ghost triangle with finite edge u -> v (the outside on its left): p strictly left of u -> v,
  or on the line through u, v strictly between them (the limit of the circle through u, v and
  a point far away).
The triangles in conflict with p form a disc star-shaped from p; it is replaced by the fan of
triangles joining p to the disc's boundary edges.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from vorobench.core.predicates import incircle_counted, orient2d_counted

__all__ = ["triangulate", "STAT_NAMES"]

#: Operation counts returned by :func:`triangulate`, in order (the predicate counters come separately).
STAT_NAMES = ("insertions", "walk_steps", "cavity_triangles", "new_triangles")

_WALK_CAP_FACTOR = 4     # a walk visiting more than 4 * triangles + 64 triangles is a bug


# The walk's helpers only index the arrays they are given: compiled without reference counting
# (``_nrt=False``), which numba otherwise does with atomic instructions for every array argument
# of every call (a sixth of the build at 10^6 went there).
@njit(cache=True, _nrt=False)
def _ghost_edge(tri, t, inf):
    """For a ghost triangle, its finite edge (u, v) with the outside on the left; (-1, -1) if finite."""
    a = tri[3 * t]
    b = tri[3 * t + 1]
    c = tri[3 * t + 2]
    if a == inf:
        return b, c
    if b == inf:
        return c, a
    if c == inf:
        return a, b
    return -1, -1


@njit(cache=True, _nrt=False)
def _strictly_between(pts, u, v, px, py):
    """For p on the line through u and v: whether p lies strictly inside the segment uv."""
    ux, uy, vx, vy = pts[u, 0], pts[u, 1], pts[v, 0], pts[v, 1]
    if ux != vx:
        return min(ux, vx) < px < max(ux, vx)
    return min(uy, vy) < py < max(uy, vy)


@njit(cache=True, _nrt=False)
def _in_conflict(pts, tri, t, inf, px, py, counters):
    u, v = _ghost_edge(tri, t, inf)
    if u < 0:
        a = tri[3 * t]
        b = tri[3 * t + 1]
        c = tri[3 * t + 2]
        return incircle_counted(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1],
                                pts[c, 0], pts[c, 1], px, py, counters) > 0
    o = orient2d_counted(pts[u, 0], pts[u, 1], pts[v, 0], pts[v, 1], px, py, counters)
    if o != 0:
        return o > 0
    return _strictly_between(pts, u, v, px, py)


@njit(cache=True, _nrt=False)
def _locate(pts, tri, opp, start, inf, px, py, cap, counters, stats):
    """Visibility walk from finite triangle ``start`` to a triangle in conflict with p.

    Crosses any edge that has p strictly on its outer side; stops in the finite triangle
    containing p (closed), or in the ghost beyond the hull edge it crossed. Straight walks
    terminate in Delaunay triangulations; the cap turns a bug into an error, not a hang.
    """
    t = start
    came = -1
    for step in range(cap):
        stats[1] += 1
        moved = False
        for k in range(3):
            e = 3 * t + (k + step) % 3
            if e == came:
                continue
            a = tri[e]
            b = tri[3 * t + (e - 3 * t + 1) % 3]
            if orient2d_counted(pts[a, 0], pts[a, 1], pts[b, 0], pts[b, 1], px, py, counters) < 0:
                came = opp[e]
                t = came // 3
                moved = True
                break
        if not moved:
            return t
        if tri[3 * t] == inf or tri[3 * t + 1] == inf or tri[3 * t + 2] == inf:
            return t
    raise RuntimeError("incremental: point location walk exceeded its step cap")


#: Ghost triangles a hull walk crosses before it hands over to the visibility walk
_HULL_WALK_STEPS = 128


@njit(cache=True, _nrt=False)
def _walk_hull(pts, tri, opp, start, inf, px, py, counters, stats):
    """From ghost triangle ``start``, along the hull to a ghost whose edge sees p (in conflict
    with p, decided exactly); -1 if none within _HULL_WALK_STEPS ghosts (p inside the hull, or
    far along it). Sites on a convex curve are all inserted outside the hull, and the
    visibility walk to the edge that sees p crosses every sliver between: along the hull it is
    a step per hull edge. The direction at each ghost is only a guess (p's projection on the
    edge falling beyond one end), so floats suffice for it."""
    t = start
    for _ in range(_HULL_WALK_STEPS):
        stats[1] += 1
        if _in_conflict(pts, tri, t, inf, px, py, counters):
            return t
        k = 0
        while tri[3 * t + k] != inf:
            k += 1
        u = tri[3 * t + (k + 1) % 3]
        v = tri[3 * t + (k + 2) % 3]
        ex = pts[v, 0] - pts[u, 0]
        ey = pts[v, 1] - pts[u, 1]
        along = (px - pts[u, 0]) * ex + (py - pts[u, 1]) * ey
        if along > ex * ex + ey * ey:
            t = opp[3 * t + (k + 2) % 3] // 3      # across v -> inf: the next hull edge from v
        elif along < 0.0:
            t = opp[3 * t + k] // 3                # across inf -> u: the hull edge ending at u
        else:
            return -1
    return -1


@njit(cache=True, inline='always')
def _cell(x, y, x0, y0, scale, side):
    """Index of the cell of (x, y) in a side x side grid over the sites' bounding square."""
    i = min(side - 1, int((x - x0) * scale))
    j = min(side - 1, int((y - y0) * scale))
    return j * side + i


@njit(cache=True)
def _walk_grid(pts, seed):
    """The coarse grid of walk starts: (side, x0, y0, cell_scale, last vertex of each cell), about
    four sites a cell, the three seed vertices filed in their cells."""
    n = pts.shape[0]
    side = max(1, int(np.sqrt(n / 4.0)))
    x0 = pts[:, 0].min()
    y0 = pts[:, 1].min()
    span = max(pts[:, 0].max() - x0, pts[:, 1].max() - y0)
    cell_scale = side / span if span > 0.0 else 0.0
    cell_vertex = np.full(side * side, -1, dtype=np.int64)
    for k in range(3):
        cell_vertex[_cell(pts[seed[k], 0], pts[seed[k], 1], x0, y0, cell_scale, side)] = seed[k]
    return side, x0, y0, cell_scale, cell_vertex


def triangulate(pts, order, counters):
    """Delaunay triangulation of ``pts`` inserted in ``order``.

    Returns (tri, opp, ntri, stats, ok): ``ok`` is False when all sites are collinear (no
    triangle exists; the caller builds parallel lines instead). ``counters`` receives the
    predicate counts (see :mod:`vorobench.core.predicates`).

    The large arrays the insertion writes are numpy's: numpy asks for transparent huge pages,
    numba's allocator does not (see :func:`vorobench.core.delaunay_dual.voronoi_dcel`).
    """
    n = pts.shape[0]
    cap_t = 2 * n + 4
    tri = np.empty(3 * cap_t, dtype=np.int32)
    opp = np.empty(3 * cap_t, dtype=np.int32)
    # mark[t] == 2 m: t is in the cavity of insertion m; 2 m + 1: t was tested and is not
    mark = np.full(cap_t, -1, dtype=np.int32)
    fan_from = np.empty(n + 1, dtype=np.int32)  # new triangle whose first corner is this vertex
    vertex_tri = np.zeros(n + 1, dtype=np.int32)
    ntri, stats, ok = _insert_all(pts, order, counters, tri, opp, mark, fan_from, vertex_tri)
    return tri, opp, ntri, stats, ok


@njit(cache=True)
def _insert_all(pts, order, counters, tri, opp, mark, fan_from, vertex_tri):
    """The insertions of :func:`triangulate`, into its arrays: (ntri, stats, ok)."""
    n = pts.shape[0]
    inf = n
    stats = np.zeros(len(STAT_NAMES), dtype=np.int64)
    cap_t = 2 * n + 4
    if n < 3:
        return 0, stats, False
    # ---- seed triangle: the first two sites and the first one not collinear with them
    i0 = order[0]
    i1 = order[1]
    third = -1
    o = 0
    for m in range(2, n):
        o = orient2d_counted(pts[i0, 0], pts[i0, 1], pts[i1, 0], pts[i1, 1],
                             pts[order[m], 0], pts[order[m], 1], counters)
        if o != 0:
            third = m
            break
    if third < 0:
        return 0, stats, False
    i2 = order[third]
    if o < 0:
        i1, i2 = i2, i1
    seed = (i0, i1, i2)
    for k in range(3):
        tri[k] = seed[k]
    # ghost k lies beyond edge seed[k] -> seed[k+1]: (seed[k+1], seed[k], inf)
    for k in range(3):
        g = 1 + k
        tri[3 * g] = seed[(k + 1) % 3]
        tri[3 * g + 1] = seed[k]
        tri[3 * g + 2] = inf
        opp[k] = 3 * g
        opp[3 * g] = k
    for k in range(3):
        g = 1 + k
        gp = 1 + (k + 2) % 3         # the ghost beyond the edge ending at seed[k]
        opp[3 * g + 1] = 3 * gp + 2  # seed[k] -> inf  against  inf -> seed[k]
        opp[3 * gp + 2] = 3 * g + 1
    ntri = 4
    stats[0] = 3
    # ---- scratch for the cavity (little of these is touched: numba's allocator is fine)
    stack = np.empty(cap_t, dtype=np.int64)
    cavity = np.empty(cap_t, dtype=np.int64)
    bnd_u = np.empty(cap_t + 2, dtype=np.int64)
    bnd_v = np.empty(cap_t + 2, dtype=np.int64)
    bnd_o = np.empty(cap_t + 2, dtype=np.int64)
    # Where walks start: the previous site's triangle, or a triangle at the last site inserted
    # into p's cell of a coarse grid when that site is nearer. Space-filling orders jump
    # (between the arms of a parabola, say), and a straight walk across slivers is long; the
    # grid hands the walk a nearby vertex. ``vertex_tri[v]``: a finite triangle at vertex v.
    # After a site inserted on the hull, the walk first goes along the hull from one of its
    # ghosts (:func:`_walk_hull`); the grid keeps the ghost of each cell's last site too.
    side, x0, y0, cell_scale, cell_vertex = _walk_grid(pts, seed)
    last = 0
    last_ghost = -1             # a ghost at the previous site, if it was inserted on the hull
    cell_ghost = np.full(side * side, -1, dtype=np.int64)   # the same for each cell's last site
    previous = i2
    for m in range(2, n):
        if m == third:
            continue
        p = order[m]
        px = pts[p, 0]
        py = pts[p, 1]
        cell = _cell(px, py, x0, y0, cell_scale, side)
        start = last
        w = cell_vertex[cell]
        if w >= 0 and ((pts[w, 0] - px) ** 2 + (pts[w, 1] - py) ** 2
                       < (pts[previous, 0] - px) ** 2 + (pts[previous, 1] - py) ** 2):
            start = vertex_tri[w]
        # the located triangle contains p (or is the ghost beyond the hull edge p sees), so
        # its circle contains p strictly: it is in conflict without a test
        t0 = -1
        g = last_ghost if start == last else cell_ghost[cell]
        if g >= 0 and _ghost_edge(tri, g, inf)[0] >= 0:   # (a cell's ghost may have been reused since)
            t0 = _walk_hull(pts, tri, opp, g, inf, px, py, counters, stats)
        if t0 < 0:
            t0 = _locate(pts, tri, opp, start, inf, px, py, _WALK_CAP_FACTOR * ntri + 64, counters, stats)
        # ---- grow the cavity: triangles in conflict, connected to t0
        inside = 2 * m
        mark[t0] = inside
        stack[0] = t0
        sp = 1
        ncav = 0
        nb = 0
        while sp > 0:
            sp -= 1
            t = stack[sp]
            cavity[ncav] = t
            ncav += 1
            for k in range(3):
                e = 3 * t + k
                oe = opp[e]
                t2 = oe // 3
                if mark[t2] == inside:
                    continue
                if mark[t2] != inside + 1:
                    if _in_conflict(pts, tri, t2, inf, px, py, counters):
                        mark[t2] = inside
                        stack[sp] = t2
                        sp += 1
                        continue
                    mark[t2] = inside + 1
                bnd_u[nb] = tri[e]
                bnd_v[nb] = tri[3 * t + (k + 1) % 3]
                bnd_o[nb] = oe
                nb += 1
        if nb != ncav + 2:
            raise RuntimeError("incremental: the conflict region is not a topological disc")
        # ---- fill it with the fan from p: triangle (u, v, p) on each boundary edge u -> v
        last_ghost = -1
        for j in range(nb):
            if j < ncav:
                s = cavity[j]
            else:
                s = ntri
                ntri += 1
            u = bnd_u[j]
            tri[3 * s] = u
            tri[3 * s + 1] = bnd_v[j]
            tri[3 * s + 2] = p
            opp[3 * s] = bnd_o[j]
            opp[bnd_o[j]] = 3 * s
            fan_from[u] = s
            if u == inf or bnd_v[j] == inf:
                last_ghost = s
            else:
                last = s
                # every vertex of the cavity is on its boundary, so this renews all pointers
                # into the triangles just reused
                vertex_tri[u] = s
                vertex_tri[bnd_v[j]] = s
                vertex_tri[p] = s
        for j in range(nb):
            s = cavity[j] if j < ncav else ntri - (nb - j)
            s2 = fan_from[tri[3 * s + 1]]    # the fan triangle starting where this one's edge ends
            opp[3 * s + 1] = 3 * s2 + 2
            opp[3 * s2 + 2] = 3 * s + 1
        # the next walk starts in the fan triangle (u, v, p) whose angle at p faces the next
        # site: a short walk even where the triangles around p are long slivers (sites on a
        # convex curve). Only a starting guess, so plain float orientations suffice.
        nxt = m + 1 if m + 1 != third else m + 2
        if nxt < n:
            q = order[nxt]
            qx = pts[q, 0]
            qy = pts[q, 1]
            for j in range(nb):
                u = bnd_u[j]
                v = bnd_v[j]
                if u == inf or v == inf:
                    continue
                if ((pts[v, 0] - qx) * (py - qy) - (pts[v, 1] - qy) * (px - qx) >= 0.0
                        and (px - qx) * (pts[u, 1] - qy) - (py - qy) * (pts[u, 0] - qx) >= 0.0):
                    last = cavity[j] if j < ncav else ntri - (nb - j)
                    break
        cell_vertex[cell] = p
        cell_ghost[cell] = last_ghost
        previous = p
        stats[0] += 1
        stats[2] += ncav
        stats[3] += nb
    return ntri, stats, True
