"""Fortune's sweep in one compiled pass: site events, circle events, edges recorded as they close.

The sweep line moves upward (increasing y, ties by x). Output, for :func:`vorobench.core.builder.assemble`:
``edge_sites`` (a, b) and ``edge_vertices`` (start, end) of a's half-edge, which runs along
perp(b - a), -1 = infinity; ``vertices`` are circumcentres. A breakpoint between a left arc p
and a right arc q moves along perp(q - p) (the decided region is below the beach line and p's
cell is on its left), so it traces the *end* of an edge whose first site is p, and the
*start* of an edge whose first site is q.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from impls.fortune import beach_line as bl
from impls.fortune import event_queue as eq
from vorobench.core.circumcentre import circumcentre
from vorobench.core.predicates import circle_top_relative, circle_top_to_y, orient2d_counted

__all__ = [
    "sweep", "arc_priority", "close_edge", "COUNTER_NAMES", "N_COUNTERS",
    "OK", "ERR_LOCATE", "ERR_CAPACITY", "ERR_ITERATIONS", "ERR_STATE",
]

# counters layout: 0-3 as in vorobench.core.predicates (orient2d calls / exact, incircle unused),
# 4-5 breakpoint tests (beach_line), 6-7 event comparisons (event_queue), then the sweep's own.
SITE_EVENTS = 8
CIRCLE_EVENTS = 9
FALSE_ALARMS = 10
VERTICES = 11
MAX_BEACH = 12
# 13: exact circle keys computed (event_queue.KEYS_EXACT)
N_COUNTERS = 14
COUNTER_NAMES = (
    "orient2d_calls", "orient2d_exact", "incircle_calls", "incircle_exact",
    "breakpoint_tests", "breakpoint_exact", "event_comparisons", "event_comparisons_exact",
    "site_events", "circle_events", "false_alarms", "vertices", "max_beach_line", "exact_keys",
)

#: A site event first walks at most FINGER_STEPS arcs from the arc of whichever of the last
#: N_FINGERS sites is nearest in x, before searching the tree; after failed walks it waits
#: (in site events) twice as long each time, up to FINGER_BACKOFF.
FINGER_STEPS = 2
N_FINGERS = 4
FINGER_BACKOFF = 255

OK = 0
ERR_LOCATE = 1
ERR_CAPACITY = 2
ERR_ITERATIONS = 3
ERR_STATE = 4


_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)


@njit(cache=True)
def arc_priority(k):
    # splitmix64 of the arc's serial number k: deterministic pseudo-random treap priorities
    # (so the counts in stats do not depend on the machine), 31 bits
    z = np.uint64(k) * _GOLDEN
    z = (z ^ (z >> np.uint64(30))) * _MIX1
    z = (z ^ (z >> np.uint64(27))) * _MIX2
    z = z ^ (z >> np.uint64(31))
    return np.int32(z >> np.uint64(33))


@njit(cache=True, inline='always')
def close_edge(edge_sites, edge_vertices, e, left_site, v):
    # the breakpoint with left arc `left_site` that traced edge e stops at vertex v
    if edge_sites[e, 0] == left_site:
        edge_vertices[e, 1] = v
    else:
        edge_vertices[e, 0] = v


def sweep(sites, counters):
    """Run the sweep over ``sites``, which must be sorted by y, then x (site i = i-th event).

    Returns (status, edge_sites, edge_vertices, vertices); status OK or an ERR_* code.
    ``counters`` (int64, N_COUNTERS) receives the operation counts.

    The output arrays, written in full, are numpy's (huge pages: see
    :func:`vorobench.core.delaunay_dual.voronoi_dcel`); the beach line's and the queue's rows are
    reused, so few of theirs are ever touched.
    """
    n = sites.shape[0]
    arc_cap = 2 * n + 2
    arcs = bl.new_arcs(arc_cap)
    # removed arcs' rows are reused (a stack), so the live beach line stays in few rows
    arc_free = np.empty(arc_cap, dtype=np.int32)
    ev_i, ev_f, heap, hkey, free = eq.new_queue(arc_cap)
    edge_cap = 3 * n + 2
    edge_sites = np.empty((edge_cap, 2), dtype=np.int32)
    edge_vertices = np.full((edge_cap, 2), -1, dtype=np.int32)
    vertices = np.empty((2 * n + 2, 2), dtype=np.float64)
    touched = np.empty(2, dtype=np.int64)
    fingers = np.full(N_FINGERS, -1, dtype=np.int32)
    status, ne, nv = _run(sites, counters, arcs, arc_free, ev_i, ev_f, heap, hkey, free, edge_sites, edge_vertices,
                          vertices, touched, fingers)
    return status, edge_sites[:ne], edge_vertices[:ne], vertices[:nv]


@njit(cache=True, _nrt=False)
def _run(sites, counters, arcs, arc_free, ev_i, ev_f, heap, hkey, free, edge_sites, edge_vertices, vertices,
         touched, fingers):
    """The sweep's events, in tables that :func:`sweep` allocates; returns (status, number of
    edges, number of vertices). Compiled without reference counting (``_nrt=False``): the
    helpers inlined here would otherwise count references to the tables at every event, with
    atomic instructions, more than half of the sweep's time in stack samples. A function first
    called from here inherits the flag unless it sets its own, so every exact stage reachable
    from here that allocates scratch space is marked ``_nrt=True``, and takes only floats: an
    ``_nrt=True`` function that is handed the tables counts references to them at each call
    (the heap's exact order did, and that was 40 % of near_grid's sweep)."""
    n = sites.shape[0]
    arc_cap = arcs.shape[0]
    edge_cap = edge_sites.shape[0]
    nafree = 0
    nfree = 0
    ne = 0
    nv = 0
    na = 0
    hsize = 0
    seq = 0
    beach = 0
    serial = 0
    root = -1
    status = OK
    nsite = 0
    wait = 0
    backoff = 0

    # First sweep position: every site with the lowest y is an arc; consecutive ones are
    # separated by vertical bisectors coming up from infinity.
    y0 = sites[0, 1]
    k = 0
    last = -1
    while k < n and sites[k, 1] == y0:
        serial += 1
        x = bl.add_arc(arcs, na, k, arc_priority(serial))
        na += 1
        root = bl.insert_after(arcs, root, last, x)
        if last != -1:
            edge_sites[ne, 0] = arcs[last, bl.SITE]
            edge_sites[ne, 1] = k
            arcs[last, bl.EDGE] = ne
            ne += 1
        last = x
        k += 1
    beach = k
    counters[SITE_EVENTS] += k
    counters[MAX_BEACH] = beach

    i = k
    iterations = 0
    max_iterations = 4 * n + 16
    while True:
        iterations += 1
        if iterations > max_iterations:
            status = ERR_ITERATIONS
            break
        if hsize > 0 and (i >= n or eq.before_site(sites, ev_i, ev_f, hkey[0, 0], hkey[0, 1], heap[0], sites[i, 1], counters)):
            # ---------------- circle event: arc b vanishes at the circumcentre of (a, b, c)
            e, hsize = eq.pop(sites, ev_i, ev_f, heap, hkey, hsize, counters)
            b = ev_i[e, eq.ARC]
            a = arcs[b, bl.PREV]
            c = arcs[b, bl.NEXT]
            if a < 0 or c < 0:
                status = ERR_STATE
                break
            if ne + 1 > edge_cap or nv + 1 > vertices.shape[0]:
                status = ERR_CAPACITY
                break
            v = nv
            vx = ev_f[e, eq.VX]
            vy = ev_f[e, eq.VY]
            if vx != vx:
                # marked ill-conditioned when scheduled: the float centre is not trustworthy
                sa = ev_i[e, eq.A]
                sb = ev_i[e, eq.B]
                sc = ev_i[e, eq.C]
                vx, vy = circumcentre(sites[sa, 0], sites[sa, 1], sites[sb, 0], sites[sb, 1],
                                               sites[sc, 0], sites[sc, 1])
            vertices[v, 0] = vx
            vertices[v, 1] = vy
            nv += 1
            counters[VERTICES] += 1
            nfree = eq.release(ev_i, free, nfree, e)
            arcs[b, bl.EVENT] = -1
            close_edge(edge_sites, edge_vertices, arcs[a, bl.EDGE], arcs[a, bl.SITE], v)
            close_edge(edge_sites, edge_vertices, arcs[b, bl.EDGE], arcs[b, bl.SITE], v)
            # the new breakpoint (a, c) starts at v and moves along perp(c - a): a's half-edge
            edge_sites[ne, 0] = arcs[a, bl.SITE]
            edge_sites[ne, 1] = arcs[c, bl.SITE]
            edge_vertices[ne, 0] = v
            arcs[a, bl.EDGE] = ne
            ne += 1
            root = bl.remove(arcs, root, b)
            # a removed arc's row may be reused: a finger on it moves to its left neighbour
            for f in range(N_FINGERS):
                if fingers[f] == b:
                    fingers[f] = a
            arc_free[nafree] = b
            nafree += 1
            beach -= 1
            touched[0] = a
            touched[1] = c
        elif i < n:
            # ---------------- site event: split the arc above s into (q, s, q)
            s = i
            i += 1
            counters[SITE_EVENTS] += 1
            sx = sites[s, 0]
            sy = sites[s, 1]
            # Sites that follow each other along the beach line (a row of a lattice taken in x
            # order, the two ends of a convex curve) lie under or next to the arcs of the last
            # sites: walk from those first. After a miss the next try waits twice as long, so
            # scattered sites pay one short walk in hundreds.
            x = -1
            if wait == 0:
                # the finger whose site is nearest in x (a guess: the walk decides exactly)
                best = -1
                gap = np.inf
                for f in range(N_FINGERS):
                    finger = fingers[f]
                    if finger != -1:
                        d = abs(sites[arcs[finger, bl.SITE], 0] - sx)
                        if d < gap:
                            gap = d
                            best = finger
                if best != -1:
                    x = bl.locate_near(arcs, sites, best, sx, sy, FINGER_STEPS, counters)
                if x < 0:
                    backoff = min(2 * backoff + 1, FINGER_BACKOFF)
                    wait = backoff
                else:
                    backoff = 0
            else:
                wait -= 1
            if x < 0:
                x = bl.locate(arcs, root, sites, sx, sy, counters)
            if x < 0:
                status = ERR_LOCATE
                break
            if na + 2 > arc_cap or ne + 1 > edge_cap:
                status = ERR_CAPACITY
                break
            # (x's pending circle event is cancelled below, with the other touched arc's)
            q = arcs[x, bl.SITE]
            serial += 1
            if nafree > 0:
                nafree -= 1
                xs = bl.add_arc(arcs, arc_free[nafree], s, arc_priority(serial))
            else:
                xs = bl.add_arc(arcs, na, s, arc_priority(serial))
                na += 1
            serial += 1
            if nafree > 0:
                nafree -= 1
                x2 = bl.add_arc(arcs, arc_free[nafree], q, arc_priority(serial))
            else:
                x2 = bl.add_arc(arcs, na, q, arc_priority(serial))
                na += 1
            root = bl.insert_after(arcs, root, x, xs)
            root = bl.insert_after(arcs, root, xs, x2)
            fingers[nsite % N_FINGERS] = xs
            nsite += 1
            edge_sites[ne, 0] = q
            edge_sites[ne, 1] = s
            arcs[x2, bl.EDGE] = arcs[x, bl.EDGE]
            arcs[x, bl.EDGE] = ne
            arcs[xs, bl.EDGE] = ne
            ne += 1
            beach += 2
            if beach > counters[MAX_BEACH]:
                counters[MAX_BEACH] = beach
            touched[0] = x
            touched[1] = x2
        else:
            break
        # ---------------- (re)schedule the circle events of the two arcs whose neighbours changed
        for t in range(2):
            x = touched[t]
            g = arcs[x, bl.EVENT]
            if g != -1:
                hsize = eq.discard(sites, ev_i, ev_f, heap, hkey, hsize, g, counters)
                nfree = eq.release(ev_i, free, nfree, g)
                arcs[x, bl.EVENT] = -1
                counters[FALSE_ALARMS] += 1
            p = arcs[x, bl.PREV]
            r = arcs[x, bl.NEXT]
            if p == -1 or r == -1:
                continue
            sa = arcs[p, bl.SITE]
            sb = arcs[x, bl.SITE]
            sc = arcs[r, bl.SITE]
            if sa == sc:
                continue
            ax = sites[sa, 0]
            ay = sites[sa, 1]
            bx = sites[sb, 0]
            by = sites[sb, 1]
            cx = sites[sc, 0]
            cy = sites[sc, 1]
            # the breakpoints (a, b) and (b, c) converge iff a, b, c turn counter-clockwise
            if orient2d_counted(ax, ay, bx, by, cx, cy, counters) <= 0:
                continue
            g, nfree = eq.allocate(ev_i, free, nfree)
            if g < 0:
                status = ERR_CAPACITY
                break
            q, errq, vx, vy = circle_top_relative(ax, ay, bx, by, cx, cy)
            yt, err = circle_top_to_y(ay, q, errq)
            ev_i[g, eq.A] = sa
            ev_i[g, eq.B] = sb
            ev_i[g, eq.C] = sc
            ev_i[g, eq.ARC] = x
            ev_i[g, eq.SEQ] = seq
            ev_i[g, eq.KEY] = eq.KEY_UNKNOWN
            seq += 1
            ev_f[g, eq.Y] = yt
            ev_f[g, eq.ERR] = err
            ev_f[g, eq.VX] = vx
            ev_f[g, eq.VY] = vy
            ev_f[g, eq.Q] = q
            ev_f[g, eq.ERRQ] = errq
            arcs[x, bl.EVENT] = g
            hsize = eq.push(sites, ev_i, ev_f, heap, hkey, hsize, g, counters)
            counters[CIRCLE_EVENTS] += 1
        if status != OK:
            break
    return status, ne, nv
