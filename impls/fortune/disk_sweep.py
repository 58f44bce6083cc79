"""Fortune's sweep for disks, compiled: the sweep of :mod:`impls.fortune.apollonius_sweep`
(each directrix raised by its disk's radius), with its beach line in the ordinary sweep's treap
(:mod:`impls.fortune.beach_line`), circle events in an indexed binary heap, and every decision
first made by a float filter with a running error bound
(:mod:`vorobench.core.predicates.apollonius_filter`); the filter's open cases go to the
rational predicates (:mod:`impls.fortune.disk_exact`, from numba's object mode), so the
decisions, and the diagram, are the rational sweep's.

Speed notes: the loop and its helpers are compiled without reference counting (as the
ordinary sweep's); a site is located with one breakpoint test per level of the treap; a heap
removal moves its hole to a leaf (one comparison per level) before the last entry settles.

Sites are the visible disks in event order (time y - r, then x: exact, see :func:`event_order`).
An event's time is kept as an enclosure [lo, hi]; two events whose enclosures overlap are
ordered by the exact stage. At one time circle events come first, and circle events among
themselves in the order they were scheduled, as in the rational sweep.

Vertices: each circle event makes one, with the enclosure of its point. Four or more disks
tangent to one circle give several circle events at one point, joined by edges of zero
length; :func:`merge_vertices` joins every edge's two ends that are one point (an overlap of
their enclosures, then the exact test) and drops those edges.
"""

from __future__ import annotations

import numpy as np
from numba import njit, objmode

from impls.fortune import beach_line as bl
from impls.fortune import disk_exact
from impls.fortune.sweep import ERR_CAPACITY, ERR_ITERATIONS, ERR_LOCATE, ERR_STATE, OK, arc_priority, close_edge
from vorobench.core.predicates import interval as iv
from vorobench.core.predicates import running_error
from vorobench.core.predicates.apollonius_filter import NO_VERTEX, UNDECIDED, breakpoint_side, meets, vertex_box
from vorobench.core.union_find import find

__all__ = ["sweep", "merge_vertices", "event_order", "COUNTER_NAMES", "N_COUNTERS", "OK", "ERR_LOCATE",
           "ERR_CAPACITY", "ERR_ITERATIONS", "ERR_STATE"]

# counters
BP_CALLS, BP_EXACT, EV_CALLS, EV_EXACT, CIRCLE_CALLS, CIRCLE_EXACT, SITE_EVENTS, CIRCLE_EVENTS, FALSE_ALARMS, \
    VERTICES, MERGED, POINTS_EXACT, MAX_BEACH = range(13)
N_COUNTERS = 13
COUNTER_NAMES = (
    "breakpoint_tests", "breakpoint_exact", "event_comparisons", "event_comparisons_exact",
    "circle_tests", "circle_tests_exact", "site_events", "circle_events", "false_alarms", "vertices",
    "merged_vertices", "same_point_exact", "max_beach_line",
)

# event table: ev_i's columns, then ev_f's
EV_A, EV_B, EV_C, EV_ARC, EV_SEQ, EV_EXACT_POINT = range(6)
EV_INTS = 6
T_LO, T_HI, X_LO, X_HI, Y_LO, Y_HI = range(6)
EV_FLOATS = 6

SITE_KIND = disk_exact.SITE_KIND
CIRCLE_KIND = disk_exact.CIRCLE_KIND

#: A vertex's filtered enclosure gives its coordinates (the midpoint) when it is at most this
#: wide relative to the input's magnitude; a wider one is rounded from the exact vertex.
POINT_WIDTH = 2.0 ** -40


def event_order(xs: np.ndarray, ys: np.ndarray, rs: np.ndarray) -> tuple[np.ndarray, int]:
    """The disks' order as site events, by time y - r, then x, exactly, and how many share the
    first time. The time is the exact pair (hi, lo) of Knuth's two-difference (hi the rounded
    y - r, lo its error), which sorts as the exact value does: distinct values that round to
    one float are told apart by lo, and one value always rounds to one hi. Sorted by hi, then
    each run of equal hi (rare but for lattices) by (lo, x)."""
    hi = ys - rs
    back = ys - hi
    lo = (ys - (hi + back)) + (back - rs)
    order = np.argsort(hi, kind="stable")
    return order, _settle_runs(order, hi, lo, xs)


@njit(cache=True)
def _settle_runs(order, hi, lo, xs):
    """Sort each run of equal hi in ``order`` by (lo, x) (insertion sort: runs are short but
    for rows of a lattice); returns the length of the first run, the first row of sites."""
    n = order.size
    first = n
    i = 0
    while i < n:
        j = i + 1
        while j < n and hi[order[j]] == hi[order[i]]:
            j += 1
        if j - i > 1:
            for k in range(i + 1, j):
                v = order[k]
                m = k - 1
                while m >= i and (lo[order[m]] > lo[v] or (lo[order[m]] == lo[v] and xs[order[m]] > xs[v])):
                    order[m + 1] = order[m]
                    m -= 1
                order[m + 1] = v
        if i == 0:
            first = j
            # the first row: the run's sites with the least lo
            for k in range(1, j):
                if lo[order[k]] != lo[order[0]]:
                    first = k
                    break
        i = j
    return first


# ---------------------------------------------------------------------------------- exact stage
@njit(cache=True)
def _exact_side(s, a, b):
    with objmode(r='int64'):
        r = disk_exact.breakpoint_side(s, a, b)
    return r


@njit(cache=True)
def _exact_compare(k1, i1, a1, b1, c1, k2, i2, a2, b2, c2):
    with objmode(r='int64'):
        r = disk_exact.compare_events(k1, i1, a1, b1, c1, k2, i2, a2, b2, c2)
    return r


@njit(cache=True)
def _exact_circle(a, b, c, kind, i, ea, eb, ec):
    with objmode(ok='boolean', x='float64', y='float64', top='float64'):
        ok, x, y, top = disk_exact.circle_event(a, b, c, kind, i, ea, eb, ec)
    return ok, x, y, top


@njit(cache=True)
def _exact_same_point(a1, b1, c1, a2, b2, c2):
    with objmode(r='boolean'):
        r = disk_exact.same_point(a1, b1, c1, a2, b2, c2)
    return r


@njit(cache=True)
def _exact_vertex(a, b, c):
    with objmode(x='float64', y='float64'):
        x, y = disk_exact.vertex_floats(a, b, c)
    return x, y


@njit(cache=True)
def _around(x):
    """An enclosure of the exact value that the float x rounds to within an ulp or two."""
    d = abs(x) * 2.0 ** -50 + 2.0 ** -1022
    return x - d, x + d


# ---------------------------------------------------------------------------------- decisions
@njit(cache=True, _nrt=False)
def _side(arcs, xs, ys, rs, p, x, s, L, e_L, counters):
    """Sign of site s's x against the breakpoint of arcs p (left) and x (right), at its time L
    (known within e_L)."""
    a = arcs[p, bl.SITE]
    b = arcs[x, bl.SITE]
    counters[BP_CALLS] += 1
    side = breakpoint_side(xs[s], L, e_L, xs[a], ys[a], rs[a], xs[b], ys[b], rs[b])
    if side == UNDECIDED:
        counters[BP_EXACT] += 1
        side = _exact_side(s, a, b)
    return side


@njit(cache=True, _nrt=False)
def _locate(arcs, root, xs, ys, rs, s, counters):
    """The arc above site s at its time: the last arc whose left breakpoint is left of the
    site (a site exactly on a breakpoint splits the arc on its left, as in the rational sweep),
    found with one breakpoint test per level of the treap. -1 if the search finds none (an
    inconsistency: never expected)."""
    L, e_L = running_error.sub(ys[s], 0.0, rs[s], 0.0)       # once per site, not per test
    x = root
    found = -1
    steps = 0
    limit = arcs.shape[0] + 1
    while x != -1:
        steps += 1
        if steps > limit:
            return -1
        p = arcs[x, bl.PREV]
        if p != -1 and _side(arcs, xs, ys, rs, p, x, s, L, e_L, counters) <= 0:
            x = arcs[x, bl.LEFT]
        else:
            found = x
            x = arcs[x, bl.RIGHT]
    return found


@njit(cache=True, _nrt=False)
def _order(ev_i, ev_f, e, kind2, i2, a2, b2, c2, lo2, hi2, counters):
    """Sign of time(circle event e) - time(the event named by kind2 ...)."""
    counters[EV_CALLS] += 1
    if ev_f[e, T_HI] < lo2:
        return -1
    if hi2 < ev_f[e, T_LO]:
        return 1
    counters[EV_EXACT] += 1
    return _exact_compare(CIRCLE_KIND, -1, ev_i[e, EV_A], ev_i[e, EV_B], ev_i[e, EV_C], kind2, i2, a2, b2, c2)


@njit(cache=True, _nrt=False)
def _before(ev_i, ev_f, e1, e2, counters):
    """Whether circle event e1 comes before e2: earlier, or at one time scheduled first."""
    c = _order(ev_i, ev_f, e1, CIRCLE_KIND, -1, ev_i[e2, EV_A], ev_i[e2, EV_B], ev_i[e2, EV_C],
               ev_f[e2, T_LO], ev_f[e2, T_HI], counters)
    if c != 0:
        return c < 0
    return ev_i[e1, EV_SEQ] < ev_i[e2, EV_SEQ]


# ---------------------------------------------------------------------------------- the heap
@njit(cache=True, _nrt=False)
def _swap(heap, where, i, j):
    a = heap[i]
    b = heap[j]
    heap[i] = b
    heap[j] = a
    where[b] = i
    where[a] = j


@njit(cache=True, _nrt=False)
def _sift_up(ev_i, ev_f, heap, where, k, counters):
    while k > 0:
        parent = (k - 1) // 2
        if not _before(ev_i, ev_f, heap[k], heap[parent], counters):
            break
        _swap(heap, where, k, parent)
        k = parent


@njit(cache=True, _nrt=False)
def _remove_at(ev_i, ev_f, heap, where, k, size, counters):
    """Take the entry at heap position k out; returns the new size. The hole goes down to a
    leaf along the earlier child (one comparison per level), and the last entry, moved into
    it, settles upward: about half the comparisons of sifting it down from k."""
    size -= 1
    where[heap[k]] = -1
    if k == size:
        return size
    while True:
        child = 2 * k + 1
        if child >= size:
            break
        if child + 1 < size and _before(ev_i, ev_f, heap[child + 1], heap[child], counters):
            child += 1
        heap[k] = heap[child]
        where[heap[k]] = k
        k = child
    heap[k] = heap[size]
    where[heap[k]] = k
    _sift_up(ev_i, ev_f, heap, where, k, counters)
    return size


# ---------------------------------------------------------------------------------- the sweep
def sweep(xs: np.ndarray, ys: np.ndarray, rs: np.ndarray, first_row: int, scale: float,
          counters: np.ndarray):
    """Run the sweep over visible disks in event order (:func:`event_order`); the first
    ``first_row`` of them share the first time. Call it inside ``disk_exact.exact_context`` of
    the same disks. Returns (status, edge_sites, edge_vertices, vertices, vertex_triples,
    vertex_boxes): edges as the ordinary sweep's (a's half-edge from start to end, -1 =
    infinity), each vertex's disks and the enclosure (x_lo, x_hi, y_lo, y_hi) of its point."""
    n = xs.shape[0]
    arc_cap = 2 * n + 2
    arcs = bl.new_arcs(arc_cap)
    arc_free = np.empty(arc_cap, dtype=np.int32)
    ev_i = np.empty((arc_cap, EV_INTS), dtype=np.int64)
    ev_f = np.empty((arc_cap, EV_FLOATS), dtype=np.float64)
    heap = np.empty(arc_cap, dtype=np.int64)
    where = np.full(arc_cap, -1, dtype=np.int64)
    free = np.empty(arc_cap, dtype=np.int64)
    edge_cap = 3 * n + 2
    edge_sites = np.empty((edge_cap, 2), dtype=np.int64)
    edge_vertices = np.full((edge_cap, 2), -1, dtype=np.int64)
    vertex_cap = 2 * n + 2
    vertices = np.empty((vertex_cap, 2), dtype=np.float64)
    triples = np.empty((vertex_cap, 3), dtype=np.int64)
    boxes = np.empty((vertex_cap, 4), dtype=np.float64)
    status, ne, nv = _run(xs, ys, rs, first_row, scale, counters, arcs, arc_free, ev_i, ev_f, heap, where, free,
                          edge_sites, edge_vertices, vertices, triples, boxes, np.empty(2, dtype=np.int64))
    return status, edge_sites[:ne], edge_vertices[:ne], vertices[:nv], triples[:nv], boxes[:nv]


@njit(cache=True, _nrt=False)
def _new_arc(arcs, arc_free, nafree, na, site, serial):
    """A detached arc of ``site`` in a free row (reused rows first): (row, nafree, na)."""
    if nafree > 0:
        nafree -= 1
        return bl.add_arc(arcs, arc_free[nafree], site, arc_priority(serial)), nafree, na
    return bl.add_arc(arcs, na, site, arc_priority(serial)), nafree, na + 1


@njit(cache=True, _nrt=False)
def _run(xs, ys, rs, first_row, scale, counters, arcs, arc_free, ev_i, ev_f, heap, where, free,
         edge_sites, edge_vertices, vertices, triples, boxes, touched):
    """The sweep's events, in tables that :func:`sweep` allocates; returns (status, number of
    edges, number of vertices). Compiled without reference counting (``_nrt=False``), as the
    ordinary sweep's loop is and for its reason (:func:`impls.fortune.sweep._run`): the exact
    stage's calls take numbers only."""
    n = xs.shape[0]
    arc_cap = arcs.shape[0]
    edge_cap = edge_sites.shape[0]
    nafree = 0
    nfree = 0
    next_event = 0
    ne = 0
    nv = 0
    na = 0
    hsize = 0
    seq = 0
    beach = 0
    serial = 0
    root = -1
    rightmost = -1
    status = OK
    i = 0
    iterations = 0
    max_iterations = 4 * n + 16
    while True:
        iterations += 1
        if iterations > max_iterations:
            status = ERR_ITERATIONS
            break
        circle_first = False
        if hsize > 0:
            if i >= n:
                circle_first = True
            else:
                lo_s, hi_s = iv.sub(ys[i], ys[i], rs[i], rs[i])
                circle_first = _order(ev_i, ev_f, heap[0], SITE_KIND, i, -1, -1, -1, lo_s, hi_s, counters) <= 0
        if circle_first:
            # ---------------- circle event: arc b vanishes at the vertex of (a, b, c)
            e = heap[0]
            hsize = _remove_at(ev_i, ev_f, heap, where, 0, hsize, counters)
            b = ev_i[e, EV_ARC]
            a = arcs[b, bl.PREV]
            c = arcs[b, bl.NEXT]
            if a < 0 or c < 0:
                status = ERR_STATE
                break
            if ne + 1 > edge_cap or nv + 1 > vertices.shape[0]:
                status = ERR_CAPACITY
                break
            now_kind, now_i = CIRCLE_KIND, -1
            now_a, now_b, now_c = ev_i[e, EV_A], ev_i[e, EV_B], ev_i[e, EV_C]
            now_lo, now_hi = ev_f[e, T_LO], ev_f[e, T_HI]
            v = nv
            nv += 1
            if ev_i[e, EV_EXACT_POINT] == 1:
                vertices[v, 0], vertices[v, 1] = _exact_vertex(now_a, now_b, now_c)
            else:
                vertices[v, 0] = 0.5 * (ev_f[e, X_LO] + ev_f[e, X_HI])
                vertices[v, 1] = 0.5 * (ev_f[e, Y_LO] + ev_f[e, Y_HI])
            triples[v, 0], triples[v, 1], triples[v, 2] = now_a, now_b, now_c
            for k in range(4):
                boxes[v, k] = ev_f[e, X_LO + k]
            counters[VERTICES] += 1
            free[nfree] = e
            nfree += 1
            arcs[b, bl.EVENT] = -1
            close_edge(edge_sites, edge_vertices, arcs[a, bl.EDGE], arcs[a, bl.SITE], v)
            close_edge(edge_sites, edge_vertices, arcs[b, bl.EDGE], arcs[b, bl.SITE], v)
            # the new breakpoint (a, c) starts at v: the start of a's half-edge
            edge_sites[ne, 0] = arcs[a, bl.SITE]
            edge_sites[ne, 1] = arcs[c, bl.SITE]
            edge_vertices[ne, 0] = v
            arcs[a, bl.EDGE] = ne
            ne += 1
            root = bl.remove(arcs, root, b)
            arc_free[nafree] = b
            nafree += 1
            beach -= 1
            touched[0] = a
            touched[1] = c
        elif i < n:
            # ---------------- site event
            s = i
            i += 1
            counters[SITE_EVENTS] += 1
            now_kind, now_i, now_a, now_b, now_c = SITE_KIND, s, -1, -1, -1
            now_lo, now_hi = iv.sub(ys[s], ys[s], rs[s], rs[s])
            if na + 2 > arc_cap or ne + 1 > edge_cap:
                status = ERR_CAPACITY
                break
            if s < first_row:
                # the first row: spikes side by side in order of x, separated by edges from
                # infinity below; a middle spike's arc may close (parabolas of different
                # radii widen apart)
                xnew, nafree, na = _new_arc(arcs, arc_free, nafree, na, s, serial)
                serial += 1
                root = bl.insert_after(arcs, root, rightmost, xnew)
                beach += 1
                if rightmost != -1:
                    edge_sites[ne, 0] = arcs[rightmost, bl.SITE]
                    edge_sites[ne, 1] = s
                    arcs[rightmost, bl.EDGE] = ne
                    ne += 1
                rightmost = xnew
                touched[0] = arcs[xnew, bl.PREV]
                touched[1] = -1
            else:
                x = _locate(arcs, root, xs, ys, rs, s, counters)
                if x < 0:
                    status = ERR_LOCATE
                    break
                q = arcs[x, bl.SITE]
                xs_arc, nafree, na = _new_arc(arcs, arc_free, nafree, na, s, serial)
                serial += 1
                x2, nafree, na = _new_arc(arcs, arc_free, nafree, na, q, serial)
                serial += 1
                root = bl.insert_after(arcs, root, x, xs_arc)
                root = bl.insert_after(arcs, root, xs_arc, x2)
                if x == rightmost:
                    rightmost = x2
                edge_sites[ne, 0] = q
                edge_sites[ne, 1] = s
                arcs[x2, bl.EDGE] = arcs[x, bl.EDGE]
                arcs[x, bl.EDGE] = ne
                arcs[xs_arc, bl.EDGE] = ne
                ne += 1
                beach += 2
                touched[0] = x
                touched[1] = x2
            if beach > counters[MAX_BEACH]:
                counters[MAX_BEACH] = beach
        else:
            break
        # ---------------- (re)schedule the circle events of the arcs whose neighbours changed
        for t in range(2):
            x = touched[t]
            if x < 0:
                continue
            g = arcs[x, bl.EVENT]
            if g != -1:
                hsize = _remove_at(ev_i, ev_f, heap, where, where[g], hsize, counters)
                free[nfree] = g
                nfree += 1
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
            counters[CIRCLE_CALLS] += 1
            found, x_lo, x_hi, y_lo, y_hi, t_lo, t_hi = vertex_box(xs[sa], ys[sa], rs[sa], xs[sb], ys[sb], rs[sb],
                                                                   xs[sc], ys[sc], rs[sc])
            if found == NO_VERTEX:
                continue
            exact_point = 0
            decided = False
            if found != UNDECIDED:
                if t_hi < now_lo:
                    continue                   # the circle's top is behind the sweep
                m1 = meets(xs[sa], ys[sa], rs[sa], xs[sb], ys[sb], rs[sb], x_lo, x_hi, t_lo, t_hi)
                m2 = meets(xs[sb], ys[sb], rs[sb], xs[sc], ys[sc], rs[sc], x_lo, x_hi, t_lo, t_hi)
                if m1 == 0 or m2 == 0:
                    continue                   # a breakpoint of b does not reach the vertex
                decided = t_lo > now_hi and m1 == 1 and m2 == 1
                width = max(x_hi - x_lo, y_hi - y_lo)
                if decided and width > POINT_WIDTH * scale:
                    exact_point = 1
            if not decided:
                counters[CIRCLE_EXACT] += 1
                ok, vx, vy, top = _exact_circle(sa, sb, sc, now_kind, now_i, now_a, now_b, now_c)
                if not ok:
                    continue
                x_lo, x_hi = _around(vx)
                y_lo, y_hi = _around(vy)
                t_lo, t_hi = _around(top)
            if nfree == 0:
                g = next_event
                next_event += 1
                if g >= ev_i.shape[0]:
                    status = ERR_CAPACITY
                    break
            else:
                nfree -= 1
                g = free[nfree]
            ev_i[g, EV_A] = sa
            ev_i[g, EV_B] = sb
            ev_i[g, EV_C] = sc
            ev_i[g, EV_ARC] = x
            ev_i[g, EV_SEQ] = seq
            ev_i[g, EV_EXACT_POINT] = exact_point
            seq += 1
            ev_f[g, T_LO] = t_lo
            ev_f[g, T_HI] = t_hi
            ev_f[g, X_LO] = x_lo
            ev_f[g, X_HI] = x_hi
            ev_f[g, Y_LO] = y_lo
            ev_f[g, Y_HI] = y_hi
            arcs[x, bl.EVENT] = g
            heap[hsize] = g
            where[g] = hsize
            hsize += 1
            _sift_up(ev_i, ev_f, heap, where, hsize - 1, counters)
            counters[CIRCLE_EVENTS] += 1
        if status != OK:
            break
    return status, ne, nv


@njit(cache=True)
def _boxes_meet(boxes, u, v):
    return not (boxes[u, 1] < boxes[v, 0] or boxes[v, 1] < boxes[u, 0]
                or boxes[u, 3] < boxes[v, 2] or boxes[v, 3] < boxes[u, 2])


@njit(cache=True)
def _merge(edge_vertices, triples, boxes, counters):
    """Union-find of the vertices joined by an edge of zero length; returns the parent array
    with every entry on its root (the smallest vertex of its point)."""
    nv = triples.shape[0]
    parent = np.arange(nv)
    for e in range(edge_vertices.shape[0]):
        u = edge_vertices[e, 0]
        v = edge_vertices[e, 1]
        if u < 0 or v < 0 or u == v or not _boxes_meet(boxes, u, v):
            continue
        ru = find(parent, u)
        rv = find(parent, v)
        if ru == rv:
            continue
        counters[POINTS_EXACT] += 1
        if _exact_same_point(triples[u, 0], triples[u, 1], triples[u, 2], triples[v, 0], triples[v, 1],
                             triples[v, 2]):
            parent[max(ru, rv)] = min(ru, rv)
            counters[MERGED] += 1
    for v in range(nv):
        parent[v] = find(parent, v)
    return parent


def merge_vertices(edge_sites: np.ndarray, edge_vertices: np.ndarray, vertices: np.ndarray, triples: np.ndarray,
                   boxes: np.ndarray, counters: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """One vertex per point (call inside the sweep's ``exact_context``): the ends of every
    edge of zero length joined, such edges dropped, vertices renumbered. Returns (edge_sites,
    edge_vertices, vertices)."""
    parent = _merge(edge_vertices, triples, boxes, counters)
    roots = np.flatnonzero(parent == np.arange(parent.size))
    number = np.full(parent.size, -1, dtype=np.int64)
    number[roots] = np.arange(roots.size)
    if parent.size == 0:
        return edge_sites, edge_vertices, vertices
    ends = np.where(edge_vertices >= 0, number[parent[np.maximum(edge_vertices, 0)]], -1)
    kept = ~((ends[:, 0] >= 0) & (ends[:, 0] == ends[:, 1]))
    return edge_sites[kept], ends[kept], vertices[roots]
