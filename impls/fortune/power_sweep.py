"""Fortune's sweep for power diagrams, compiled: the probing sweep of the reference, in numba.

The same events and rules as :class:`impls.fortune.power_reference.ProbingSweep` (the
specification; docs/power.md, "The sweep for weighted sites"), so the two build the same
diagram. One difference in order: the reference queues again every event of an arc beside a
change, where this sweep keeps an event that would come back the same (:func:`_unchanged`), with
its age, so events tied exactly in time may be taken in another order.

Activations at y_i from the sites sorted by (y, x); probes, one per pending site, at the least
time of T_i over the polygon Q_i where i beats its watched sites; circle events at power
centres. Ties in time go circle, then activation, then probes (those whose partner is not on
the beach line first, to be ranked again by the arc they touch; then the farthest from its
partner first), then the older event. Each decision is a predicate of
:mod:`impls.fortune.power_predicates` (float and interval filters, exact stage in rationals).

The beach line is the ordinary sweep's treap (:mod:`impls.fortune.beach_line`), searched here
with the weighted breakpoint test; events sit in an indexed binary heap (cancelled when an arc
they involve changes, with copies of their time intervals beside their ids, as the ordinary
sweep's heap keeps its keys); a pending site's watched sites are a linked list in one pool. Vertices
are recorded with their spec (the three sites of their power centre); vertices at one exact
point, which the events of a co-power vertex create one per event, are merged after the sweep
along the edges of zero length between them, and those edges dropped.

The helpers (and the predicates) only index the arrays they are given, and are compiled with
numba's ``_nrt=False``: otherwise every call increments and decrements the reference count of
each array argument with an atomic instruction, which was half of the sweep's time (1.75 s of
sweep at 10^5 sites became 0.88 s). Only :func:`sweep`, which allocates, counts references; its
loop over events (:func:`_run`) does not, and hands back to it when the watch pool must grow.
numba compiles a callee first reached from such a function with the same flag, so nothing they
call may allocate arrays, unless it is marked ``_nrt=True`` (the exact stages in expansions);
the rational exact stage is reached through object mode, with scalars only.

The helpers called at every event (the heap's, the circle candidates, the walk along the
beach line, the watch lists' small steps) are inlined (``inline='always'``): a call passes
each array as a struct of about eight words, and these take up to a dozen arrays. That made
the sweep about 30 % faster (2x10^5 uniform sites, radii weights, medians of 9 alternating
builds: 0.789 s -> 0.556 s) for about 10 s more of compilation on a fresh cache.
:func:`_refresh` stays one function, always given five arcs (-1 for none), so its inlined
body is compiled once: inlined at its three call sites too, it cost 40 s more of compilation
for no clear gain. The predicates stay calls (see :mod:`impls.fortune.power_predicates`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from impls.fortune import beach_line as bl
from impls.fortune.power_predicates import (CENTRE, CONTACT, FILTERED, SITE, farther, keeps_middle, line_inside,
                                            power_gap, same_centre, side, spec_point, tied, time_order)
from impls.fortune.slabs import OWN_DEPTH, SIDE_DEPTH
from vorobench.core.predicates import orient2d

__all__ = ["sweep", "merge_vertices", "COUNTER_NAMES", "N_COUNTERS", "OK", "ERR_STATE", "ERR_ITERATIONS",
           "ERR_CAPACITY", "MAX_SITES"]

# counters: 0-1 in power_predicates (filtered, exact), then the sweep's own
ACTIVATIONS, CIRCLES, PROBES, IN_ARC, AT_VERTEX, NEVER_ENTERED, MAX_BEACH, MERGED, FIRST_ROW = range(2, 11)
N_COUNTERS = 11
#: first_row + contacts_in_arc + contacts_at_vertex + never_entered = n: every site starts the
#: beach line, enters it once, or is found hidden without entering (a site that enters and is
#: closed at once, a cell that is one point, is hidden too, but counted as a contact).
COUNTER_NAMES = ("weighted_filtered", "weighted_exact", "site_events", "circle_events", "probes",
                 "contacts_in_arc", "contacts_at_vertex", "never_entered", "max_beach_line",
                 "merged_vertices", "first_row")

OK = 0
ERR_STATE = 1           # a probe's bound above the beach line or watched twice, or a lost neighbour
ERR_ITERATIONS = 2
ERR_CAPACITY = 3        # more events, or rows of watch lists, than int32 ids can number

#: Ids of sites, arcs, events, edges and vertices are int32, as in the ordinary sweep: half the
#: memory of int64 (at 10^6 sites the sweep writes about 400 MB of tables). At most this many
#: sites, so that every table's rows fit (edges, the largest, 5 n + 16). The events' sequence
#: numbers and the watch pool's rows grow with the work, not with n: the loop stops with
#: ERR_CAPACITY before either passes :data:`_MAX_ID` (an event pushes at most six events).
MAX_SITES = (2 ** 31 - 17) // 5
_MAX_ID = 2 ** 31 - 1
#: The most rows the watch pool may grow to (read by :func:`sweep`, in Python: a test can
#: lower it, where a global of compiled code would be frozen into numba's cache)
MAX_WATCH_ROWS = _MAX_ID

# event rows: kind, time spec (k, a, b, c), point spec (k, a, b, c), sequence number, owner
# (the arc of a circle event, the site of a probe), partner (probes), position in the heap
_KIND, _TK, _TA, _TB, _TC, _PK, _PA, _PB, _PC, _SEQ, _OWNER, _PARTNER, _HPOS = range(13)
_EV_FIELDS = 13
_CIRCLE, _PROBE = 0, 2
#: A probe's partner when its bound's site is not on the beach line (pending or hidden: a
#: slab's site). Simultaneous probes at one point go farthest from the site whose arc they
#: touch first, and such a site is not that one: the probe goes before every keyed probe of
#: its time and, if its point is on the beach line, is queued again keyed by the arc's site.
_UNKEYED = -2
_NO_BOX = (0.0, 0.0, 0.0, 0.0)
#: The box of a vertex not known where it is made (an arc tied along a line closing where the
#: event at hand is): :func:`merge_vertices` computes it
_UNKNOWN_BOX = (np.nan, np.nan, np.nan, np.nan)

# scalar state
_ROOT, _SEQN, _NEDGE, _NVERT, _NARC, _HEAPN, _FREE, _NOWK, _NOWA, _NOWB, _NOWC, _HEREK, _HEREA, \
    _HEREB, _HEREC, _WUSED, _STATUS, _NARCS, _NXTACT, _GUARD, _BEACH, _EVROWS = range(22)
_S_FIELDS = 22
#: :func:`_run`'s answer when the watch pool must grow before the next event
_NEED_ROOM = -1
# float state: the interval of the time now
_SF_FIELDS = 2
#: An activation looks at the newest site of this many slabs (its own and one on each side),
#: then at the newest of its own slab at each coarser level (slabs four times as wide)
_SLAB_WATCH = 3
#: The most sites an activation adds to a watch list
_ACTIVATION_WATCH = 2 + _SLAB_WATCH + OWN_DEPTH + 2 * SIDE_DEPTH


@njit(cache=True, inline='always')
def _earlier(G, counters, ev, evf, e1, lo1, hi1, e2, lo2, hi2):
    # the heap's order: time, then kind (circle first), then for probes the farther from its
    # partner, then the older event; disjoint time intervals ([lo, hi], kept in the heap's
    # own rows) decide without a call
    if hi1 < lo2:
        return True
    if hi2 < lo1:
        return False
    return _earlier_overlapping(G, counters, ev, evf, e1, e2)


@njit(cache=True, _nrt=False)
def _earlier_overlapping(G, counters, ev, evf, e1, e2):
    # _earlier where the time intervals overlap
    c = time_order(G, counters, ev[e1, _TK], ev[e1, _TA], ev[e1, _TB], ev[e1, _TC], evf[e1, 0], evf[e1, 1],
                   ev[e2, _TK], ev[e2, _TA], ev[e2, _TB], ev[e2, _TC], evf[e2, 0], evf[e2, 1])
    if c != 0:
        return c < 0
    if ev[e1, _KIND] != ev[e2, _KIND]:
        return ev[e1, _KIND] < ev[e2, _KIND]
    if ev[e1, _KIND] == _PROBE:
        u1, u2 = ev[e1, _PARTNER] == _UNKEYED, ev[e2, _PARTNER] == _UNKEYED
        if u1 or u2:
            if u1 != u2:
                return u1
        else:
            f = farther(G, counters, ev[e1, _OWNER], ev[e1, _PARTNER], ev[e2, _OWNER], ev[e2, _PARTNER])
            if f != 0:
                return f > 0
    return ev[e1, _SEQ] < ev[e2, _SEQ]


@njit(cache=True, inline='always')
def _settle(G, counters, ev, evf, heap, hkey, pos, top, e, lo, hi):
    # put event e (times in [lo, hi]) into the hole at pos, moving it up while it is earlier
    # than its parent, never above slot top
    while pos > top:
        parent = (pos - 1) >> 1
        if not _earlier(G, counters, ev, evf, e, lo, hi, heap[parent], hkey[parent, 0], hkey[parent, 1]):
            break
        p = heap[parent]
        heap[pos] = p
        hkey[pos, 0], hkey[pos, 1] = hkey[parent, 0], hkey[parent, 1]
        ev[p, _HPOS] = pos
        pos = parent
    heap[pos] = e
    hkey[pos, 0], hkey[pos, 1] = lo, hi
    ev[e, _HPOS] = pos


@njit(cache=True, _nrt=False, inline='always')
def _sift_up(G, counters, ev, evf, heap, hkey, pos):
    _settle(G, counters, ev, evf, heap, hkey, pos, 0, heap[pos], hkey[pos, 0], hkey[pos, 1])


@njit(cache=True, _nrt=False, inline='always')
def _sift_down(G, counters, ev, evf, heap, hkey, n, pos):
    # e = heap[pos] goes into the subtree below pos (bottom-up, as the ordinary sweep's heap
    # does): the earlier child moves up into the hole until the hole is a leaf, one
    # comparison per level, then e settles up from there, never above pos
    e, lo, hi = heap[pos], hkey[pos, 0], hkey[pos, 1]
    top = pos
    while True:
        child = 2 * pos + 1
        if child >= n:
            break
        if child + 1 < n and _earlier(G, counters, ev, evf, heap[child + 1], hkey[child + 1, 0], hkey[child + 1, 1],
                                      heap[child], hkey[child, 0], hkey[child, 1]):
            child += 1
        c = heap[child]
        heap[pos] = c
        hkey[pos, 0], hkey[pos, 1] = hkey[child, 0], hkey[child, 1]
        ev[c, _HPOS] = pos
        pos = child
    _settle(G, counters, ev, evf, heap, hkey, pos, top, e, lo, hi)


@njit(cache=True, _nrt=False, inline='always')
def _push(G, counters, S, ev, evf, heap, hkey, free, kind, tk, ta, tb, tc, tlo, thi, pk, pa, pb, pc, box, owner,
          partner):
    # the row released last, else the next never used (only rows in use are touched)
    if S[_FREE] > 0:
        e = free[S[_FREE] - 1]
        S[_FREE] -= 1
    else:
        e = S[_EVROWS]
        S[_EVROWS] += 1
    ev[e, _KIND] = kind
    ev[e, _TK], ev[e, _TA], ev[e, _TB], ev[e, _TC] = tk, ta, tb, tc
    ev[e, _PK], ev[e, _PA], ev[e, _PB], ev[e, _PC] = pk, pa, pb, pc
    S[_SEQN] += 1
    ev[e, _SEQ] = S[_SEQN]
    ev[e, _OWNER] = owner
    ev[e, _PARTNER] = partner
    evf[e, 0], evf[e, 1] = tlo, thi
    evf[e, 2], evf[e, 3], evf[e, 4], evf[e, 5] = box
    n = S[_HEAPN]
    S[_HEAPN] = n + 1
    _settle(G, counters, ev, evf, heap, hkey, n, 0, e, tlo, thi)
    return e


@njit(cache=True, _nrt=False, inline='always')
def _remove(G, counters, S, ev, evf, heap, hkey, free, e):
    # take event e out of the heap and give its row back
    pos = ev[e, _HPOS]
    n = S[_HEAPN] - 1
    S[_HEAPN] = n
    if pos != n:
        last = heap[n]
        heap[pos] = last
        hkey[pos, 0], hkey[pos, 1] = hkey[n, 0], hkey[n, 1]
        ev[last, _HPOS] = pos
        # the last event goes up if it is earlier than the hole's parent, else down
        parent = (pos - 1) >> 1
        if pos > 0 and _earlier(G, counters, ev, evf, last, hkey[pos, 0], hkey[pos, 1],
                                heap[parent], hkey[parent, 0], hkey[parent, 1]):
            _sift_up(G, counters, ev, evf, heap, hkey, pos)
        else:
            _sift_down(G, counters, ev, evf, heap, hkey, n, pos)
    free[S[_FREE]] = e
    S[_FREE] += 1


@njit(cache=True, _nrt=False, inline='always')
def _cancel(G, counters, S, ev, evf, heap, hkey, free, arcs, k):
    if k >= 0 and arcs[k, bl.EVENT] >= 0:
        _remove(G, counters, S, ev, evf, heap, hkey, free, arcs[k, bl.EVENT])
        arcs[k, bl.EVENT] = -1


@njit(cache=True, _nrt=False, inline='always')
def _circle_candidate(G, counters, S, SF, ev, evf, heap, hkey, free, arcs, cand, k):
    """Schedule the vanishing of arc k if its breakpoints converge (Sweep.circle_candidate).

    Converging breakpoints meet at the power centre of the three sites, never earlier than now
    (docs/power.md, "Why the turn is enough"), so the turn decides, as in the ordinary sweep,
    and the event depends on k's three sites alone: row k of ``cand`` keeps the sites (left,
    right) its event was computed for, so that a refresh keeps the event of an arc whose
    neighbours' sites are unchanged (:func:`_unchanged`)."""
    if k < 0:
        return
    left, right = arcs[k, bl.PREV], arcs[k, bl.NEXT]
    if left < 0 or right < 0:
        return
    sl, sk, sr = arcs[left, bl.SITE], arcs[k, bl.SITE], arcs[right, bl.SITE]
    if sl == sr:
        return
    turn = orient2d(G[sl, 0], G[sl, 1], G[sk, 0], G[sk, 1], G[sr, 0], G[sr, 1])
    if turn == 0 and S[_HEREK] >= 0 and tied(G, counters, sl, sk, sr):
        # k has just met a neighbour that ties with it along a line: it closes now, here
        arcs[k, bl.EVENT] = _push(G, counters, S, ev, evf, heap, hkey, free, _CIRCLE,
                                  S[_NOWK], S[_NOWA], S[_NOWB], S[_NOWC], SF[0], SF[1],
                                  S[_HEREK], S[_HEREA], S[_HEREB], S[_HEREC], _UNKNOWN_BOX, k, -1)
        return
    if turn <= 0:
        return
    xl, xh, yl, yh, tl, th = spec_point(G, CENTRE, sl, sk, sr)
    cand[k, 0], cand[k, 1] = sl, sr
    arcs[k, bl.EVENT] = _push(G, counters, S, ev, evf, heap, hkey, free, _CIRCLE, CENTRE, sl, sk, sr, tl, th,
                              CENTRE, sl, sk, sr, (xl, xh, yl, yh), k, -1)


@njit(cache=True, _nrt=False, inline='always')
def _unchanged(arcs, cand, k):
    """Whether :func:`_circle_candidate` would give arc k the event it has: k's neighbours'
    sites are those its event was computed for. Such an arc keeps its event, unmoved in the
    heap."""
    if k < 0 or arcs[k, bl.EVENT] < 0:
        return False
    left, right = arcs[k, bl.PREV], arcs[k, bl.NEXT]
    return left >= 0 and right >= 0 and cand[k, 0] == arcs[left, bl.SITE] and cand[k, 1] == arcs[right, bl.SITE]


@njit(cache=True, _nrt=False)
def _refresh(G, counters, S, SF, ev, evf, heap, hkey, free, arcs, cand, todo):
    """The arcs in ``todo`` (five; -1 for none) changed neighbours or are next to ones that
    did: their circle events are recomputed, in the reference's order, except those that
    would come out the same (:func:`_unchanged`)."""
    keep, j = 0, 0
    for k in todo:
        if _unchanged(arcs, cand, k):
            keep |= 1 << j
        j += 1
    j = 0
    for k in todo:
        if not keep >> j & 1:
            _cancel(G, counters, S, ev, evf, heap, hkey, free, arcs, k)
        j += 1
    j = 0
    for k in todo:
        if not keep >> j & 1:
            _circle_candidate(G, counters, S, SF, ev, evf, heap, hkey, free, arcs, cand, k)
        j += 1


@njit(cache=True, _nrt=False, inline='always')
def _breakpoints_at(G, counters, arcs, found, left_side, kind, a, b, c, xl, xh, tl, th, at):
    """The left arcs of the breakpoints at the point of a spec, left to right, into ``at``,
    found being the arc over the point (the point strictly left of its right breakpoint):
    several where arcs of no width meet there. ``left_side`` is the point's side of found's
    left breakpoint when known (0 or 1), else 2. Returns their number."""
    m = 0
    p = arcs[found, bl.PREV]
    if p == -1 or left_side == 1:
        return 0
    cur = found
    if left_side == 0:
        at[0] = p
        m, cur, p = 1, p, arcs[p, bl.PREV]
    while p != -1 and side(G, counters, arcs[p, bl.SITE], arcs[cur, bl.SITE], kind, a, b, c, xl, xh, tl, th) == 0:
        at[m] = p
        m += 1
        cur = p
        p = arcs[p, bl.PREV]
    for j in range(m // 2):
        at[j], at[m - 1 - j] = at[m - 1 - j], at[j]
    return m


@njit(cache=True, _nrt=False)
def _locate(G, counters, arcs, root, kind, a, b, c, xl, xh, tl, th, at):
    """The arc over the point of a spec at its time, and in ``at`` the left arcs of the
    breakpoints at that point, left to right (several where arcs of no width meet); returns
    (arc, number of breakpoints)."""
    found = -1
    x = root
    depth = 0
    while x != -1 and depth < 10000:
        depth += 1
        nxt = arcs[x, bl.NEXT]
        if nxt == -1 or side(G, counters, arcs[x, bl.SITE], arcs[nxt, bl.SITE], kind, a, b, c, xl, xh, tl, th) < 0:
            found = x
            x = arcs[x, bl.LEFT]
        else:
            x = arcs[x, bl.RIGHT]
    if found < 0:
        return -1, 0                            # no arc: the tree is broken (a bug)
    return found, _breakpoints_at(G, counters, arcs, found, 2, kind, a, b, c, xl, xh, tl, th, at)


#: The most breakpoints :func:`_walk` crosses before it gives up for a descent from the root.
_WALK_STEPS = 6
#: The most removed arcs :func:`_walk` follows to a live one before it gives up.
_WALK_HOPS = 8


@njit(cache=True, _nrt=False, inline='always')
def _walk(G, counters, arcs, removed_at, x, kind, a, b, c, xl, xh, tl, th, at):
    """What :func:`_locate` returns, found by walking along the beach line from arc x (a
    site's arc found last, near the point) for one or two breakpoint tests per arc crossed
    instead of a descent from the root; (-1, 0) when the walk is long. An arc gone since
    stands for its left neighbour when it went (``removed_at``), which touched it there."""
    hops = 0
    while x >= 0 and removed_at[x] >= 0 and hops < _WALK_HOPS:
        x = removed_at[x]
        hops += 1
    if x < 0 or removed_at[x] >= 0:
        return -1, 0
    # the point's side of x's left breakpoint (2: not known), and whether it is known to be
    # strictly left of x's right breakpoint; found is the leftmost arc with the point strictly
    # left of its right breakpoint, as the descent defines it
    left_side, right_known = 2, False
    for _ in range(_WALK_STEPS):
        p = arcs[x, bl.PREV]
        if left_side == 2 and p != -1:
            left_side = side(G, counters, arcs[p, bl.SITE], arcs[x, bl.SITE], kind, a, b, c, xl, xh, tl, th)
            if left_side < 0:
                x, left_side, right_known = p, 2, True
                continue
        q = arcs[x, bl.NEXT]
        if right_known or q == -1:
            return x, _breakpoints_at(G, counters, arcs, x, left_side, kind, a, b, c, xl, xh, tl, th, at)
        o = side(G, counters, arcs[x, bl.SITE], arcs[q, bl.SITE], kind, a, b, c, xl, xh, tl, th)
        if o < 0:
            return x, _breakpoints_at(G, counters, arcs, x, left_side, kind, a, b, c, xl, xh, tl, th, at)
        x, left_side = q, o
    return -1, 0


@njit(cache=True, _nrt=False, inline='always')
def _new_edge(edges, S, a, b, start):
    e = S[_NEDGE]
    edges[e, 0], edges[e, 1], edges[e, 2], edges[e, 3] = a, b, start, -1
    S[_NEDGE] = e + 1
    return e


@njit(cache=True, _nrt=False, inline='always')
def _close(edges, e, left_site, v):
    # the breakpoint with left arc `left_site` that traced edge e stops at vertex v
    if edges[e, 0] == left_site:
        edges[e, 3] = v
    else:
        edges[e, 2] = v


@njit(cache=True, _nrt=False, inline='always')
def _new_vertex(vspec, vbox, S, a, b, c, box):
    # box: a box around the vertex's point, kept for the merge (NaN: not known)
    v = S[_NVERT]
    vspec[v, 0], vspec[v, 1], vspec[v, 2] = a, b, c
    vbox[v, 0], vbox[v, 1], vbox[v, 2], vbox[v, 3] = box
    S[_NVERT] = v + 1
    return v


@njit(cache=True, _nrt=False, inline='always')
def _new_arc(arcs, S, site):
    x = S[_NARCS]
    S[_NARCS] = x + 1
    # splitmix-like deterministic priorities: counts do not depend on the machine
    z = np.uint64(x + 1) * np.uint64(0x9E3779B97F4A7C15)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = z ^ (z >> np.uint64(31))
    return bl.add_arc(arcs, x, site, np.int32(z >> np.uint64(33)))


@njit(cache=True)
def _grown(wsite, wnext):
    """The watch pool, twice as large (its rows kept)."""
    grown_site = np.empty(2 * wsite.shape[0], dtype=np.int32)
    grown_next = np.empty(2 * wsite.shape[0], dtype=np.int32)
    grown_site[:wsite.shape[0]] = wsite
    grown_next[:wsite.shape[0]] = wnext
    return grown_site, grown_next


@njit(cache=True, _nrt=False, inline='always')
def _watch(wsite, wnext, whead, S, i, s):
    """Site s joins the head of pending site i's watch list (the caller makes room: _grown), so
    the list runs newest first: the newest sites are the nearest, whose constraints are the
    tightest, and :func:`_lowest_on_line` meets them first."""
    w = S[_WUSED]
    S[_WUSED] = w + 1
    wsite[w], wnext[w] = s, whead[i]
    whead[i] = w


@njit(cache=True, _nrt=False, inline='always')
def _watched(wsite, wnext, whead, i, s):
    """Whether site s is in pending site i's watch list."""
    j = whead[i]
    while j != -1:
        if wsite[j] == s:
            return True
        j = wnext[j]
    return False


@njit(cache=True, _nrt=False)
def _lowest_point(G, counters, wsite, wnext, whead, i):
    """The least time of T_i over Q_i (ProbingSweep.lowest_point): (kind, a, b, c, partner,
    tlo, thi) of its spec, kind -1 if Q_i is empty."""
    best_k, best_a, best_b, best_c, partner = -1, -1, -1, -1, -1
    blo, bhi = 0.0, 0.0
    box = _NO_BOX
    j = whead[i]
    while j != -1:
        sj = np.int64(wsite[j])
        if G[sj, 1] < G[i, 1]:
            xl, xh, yl, yh, tl, th = spec_point(G, CONTACT, i, sj, -1)
            if best_k < 0 or time_order(G, counters, CONTACT, i, sj, -1, tl, th, best_k, best_a, best_b, best_c,
                                        blo, bhi) < 0:
                if _in_q(G, counters, wsite, wnext, whead, i, CONTACT, i, sj, -1, xl, xh, yl, yh):
                    best_k, best_a, best_b, best_c, partner, blo, bhi = CONTACT, i, sj, -1, sj, tl, th
                    box = (xl, xh, yl, yh)
        j = wnext[j]
    ja = whead[i]
    while ja != -1:
        jb = wnext[ja]
        while jb != -1:
            sa, sb = np.int64(wsite[ja]), np.int64(wsite[jb])
            if orient2d(G[i, 0], G[i, 1], G[sa, 0], G[sa, 1], G[sb, 0], G[sb, 1]) != 0:
                xl, xh, yl, yh, tl, th = spec_point(G, CENTRE, i, sa, sb)
                if best_k < 0 or time_order(G, counters, CENTRE, i, sa, sb, tl, th, best_k, best_a, best_b,
                                            best_c, blo, bhi) < 0:
                    if _in_q(G, counters, wsite, wnext, whead, i, CENTRE, i, sa, sb, xl, xh, yl, yh):
                        best_k, best_a, best_b, best_c, partner, blo, bhi = CENTRE, i, sa, sb, -1, tl, th
                        box = (xl, xh, yl, yh)
            jb = wnext[jb]
        ja = wnext[ja]
    return best_k, best_a, best_b, best_c, partner, blo, bhi, box


@njit(cache=True, _nrt=False)
def _lowest_on_line(G, counters, wsite, wnext, whead, i, k):
    """The least time of T_i over Q_i after site k joined S_i because the old least point
    broke k's constraint: as in Seidel's linear programming, the new least point is on k's
    bisector line L_k, within the interval the other sites leave of it, so one pass over S_i
    finds it (instead of every corner of Q_i). Returns what :func:`_lowest_point` returns;
    ``found`` is False (and the rest to be ignored) when the pass cannot tell, and the caller
    falls back to :func:`_lowest_point`."""
    lo, hi = -1, -1         # the sites whose lines end L_k on either side (along perp(p_k - p_i))
    lo_box = hi_box = _NO_BOX   # the boxes of those ends (power centres of i, k and lo or hi)
    lo_time = hi_time = (0.0, 0.0)      # and the intervals of their times
    j = wnext[whead[i]]     # k heads the list; the rest, newest first, are the tightest first
    while j != -1:
        sj = np.int64(wsite[j])
        j = wnext[j]
        if sj == k:
            # k was watched already, so the old least point was inside k's constraint and
            # yet below k's arc: a bug, which would probe the same point forever
            return True, -2, -1, -1, -1, -1, 0.0, 0.0, _NO_BOX
        o = orient2d(G[i, 0], G[i, 1], G[k, 0], G[k, 1], G[sj, 0], G[sj, 1])
        if o == 0:
            # j's line is parallel to L_k: all of L_k is allowed by j, or none of it
            if not line_inside(G, counters, i, k, sj):
                return True, -1, -1, -1, -1, -1, 0.0, 0.0, _NO_BOX
            continue
        # the end of L_k that j sets is the power centre of i, k, j; of two ends on one side,
        # the one inside the other's constraint is the nearer
        end, (xl, xh, yl, yh) = (hi, hi_box) if o > 0 else (lo, lo_box)
        if end >= 0 and power_gap(G, counters, sj, i, CENTRE, i, k, end, xl, xh, yl, yh) >= 0:
            continue
        xl, xh, yl, yh, tl, th = spec_point(G, CENTRE, i, k, sj)
        if o > 0:
            hi, hi_box, hi_time = sj, (xl, xh, yl, yh), (tl, th)
        else:
            lo, lo_box, lo_time = sj, (xl, xh, yl, yh), (tl, th)
    if lo >= 0 and hi >= 0:
        xl, xh, yl, yh = lo_box
        if power_gap(G, counters, hi, i, CENTRE, i, k, lo, xl, xh, yl, yh) < 0:
            return True, -1, -1, -1, -1, -1, 0.0, 0.0, _NO_BOX          # the ends cross: Q_i is empty
    if G[k, 1] < G[i, 1]:
        # T_i along L_k is least at c_ik: the answer if it lies between the ends
        xl, xh, yl, yh, tl, th = spec_point(G, CONTACT, i, k, -1)
        inside = True
        for end in (lo, hi):
            if end >= 0 and power_gap(G, counters, end, i, CONTACT, i, k, -1, xl, xh, yl, yh) < 0:
                inside = False
        if inside:
            return True, CONTACT, i, k, -1, k, tl, th, (xl, xh, yl, yh)
    # T_i is monotone between the ends: the least is at one of them
    best, blo, bhi, box = -1, 0.0, 0.0, _NO_BOX
    for end, end_box, (tl, th) in ((lo, lo_box, lo_time), (hi, hi_box, hi_time)):
        if end < 0:
            continue
        if best < 0 or time_order(G, counters, CENTRE, i, k, end, tl, th, CENTRE, i, k, best, blo, bhi) < 0:
            best, blo, bhi, box = end, tl, th, end_box
    if best < 0:
        return False, -1, -1, -1, -1, -1, 0.0, 0.0, _NO_BOX
    return True, CENTRE, i, k, best, -1, blo, bhi, box


@njit(cache=True, _nrt=False, inline='always')
def _tighten(G, counters, wsite, wnext, whead, S, i, s, bk, ba, bb, bc, partner, blo, bhi, box):
    """Site s joins pending site i's watch if the least point of its bound (the rest of the
    arguments, as :func:`_lowest_point` returns them) is where s beats i, and the bound moves
    onto s's line (Seidel's step); returns the bound, moved or not."""
    if bk < 0 or s < 0 or s == i or _watched(wsite, wnext, whead, i, s):
        return bk, ba, bb, bc, partner, blo, bhi, box
    if power_gap(G, counters, s, i, bk, ba, bb, bc, box[0], box[1], box[2], box[3]) >= 0:
        return bk, ba, bb, bc, partner, blo, bhi, box
    _watch(wsite, wnext, whead, S, i, s)
    found, bk, ba, bb, bc, partner, blo, bhi, box = _lowest_on_line(G, counters, wsite, wnext, whead, i, np.int64(s))
    if not found:
        bk, ba, bb, bc, partner, blo, bhi, box = _lowest_point(G, counters, wsite, wnext, whead, i)
    return bk, ba, bb, bc, partner, blo, bhi, box


@njit(cache=True, _nrt=False, inline='always')
def _in_q(G, counters, wsite, wnext, whead, i, kind, a, b, c, xl, xh, yl, yh):
    # i has no more power than any watched site at the spec's point
    j = whead[i]
    while j != -1:
        if power_gap(G, counters, wsite[j], i, kind, a, b, c, xl, xh, yl, yh) < 0:
            return False
        j = wnext[j]
    return True


def sweep(G, order, row, counters, slab, watch_rows):
    """Run the weighted sweep. ``G`` is the site table of :mod:`power_predicates`, ``order``
    the sites sorted by (y, x), ``row`` the number of them on the lowest y, ``slab`` each
    site's vertical slab (:func:`impls.fortune.slabs.slabs`): a pending site's first bound
    also looks at the sites activated last in its slab, in the two beside it and in its slab
    at coarser levels. ``watch_rows`` is the first size of the pool of watch-list rows, which
    grows (doubling) as needed.

    Returns (status, edges (a, b, start, end), vertex specs (a, b, c), a box around each
    vertex), ids in int32; :func:`merge_vertices` then merges vertices at one point and drops
    the edges of no length.

    The tables are numpy's: numpy asks for transparent huge pages, numba's allocator does not
    (see :func:`vorobench.core.delaunay_dual.voronoi_dcel`), and at 10^6 sites these are hundreds of
    megabytes written once each."""
    n = G.shape[0]
    if n > MAX_SITES:
        raise ValueError(f"the weighted sweep takes at most {MAX_SITES} sites (its ids are int32); got {n}")
    # numpy's too (bl.new_arcs, compiled, took about 15,000 page faults more at 10^6)
    arcs = np.empty((2 * n + 4, bl.ARC_FIELDS), dtype=np.int32)
    cap_ev = 3 * n + 16
    ev = np.empty((cap_ev, _EV_FIELDS), dtype=np.int32)
    evf = np.empty((cap_ev, 6), dtype=np.float64)     # time interval, then the point's box
    heap = np.empty(cap_ev, dtype=np.int32)
    hkey = np.empty((cap_ev, 2), dtype=np.float64)     # the time interval of heap[j], beside it
    free = np.empty(cap_ev, dtype=np.int32)     # released event rows, a stack
    edges = np.empty((5 * n + 16, 4), dtype=np.int32)
    vspec = np.empty((3 * n + 16, 3), dtype=np.int32)
    vbox = np.empty((vspec.shape[0], 4), dtype=np.float64)
    whead = np.full(n, -1, dtype=np.int32)
    # each slab's newest activation, at each level: level L's slab of a site is slab >> 2 L
    slabs_count = int(slab.max()) + 1 if n > 0 else 1
    levels = 1
    while (slabs_count - 1) >> (2 * levels) > 0:
        levels += 1
    last = np.full((levels, slabs_count), -1, dtype=np.int32)
    before = np.full(n, -1, dtype=np.int32)     # the site activated before each in its slab (level 0)
    wsite = np.empty(max(watch_rows, _ACTIVATION_WATCH + levels), dtype=np.int32)
    wnext = np.empty(wsite.shape[0], dtype=np.int32)
    state = np.zeros(n, dtype=np.int8)          # 0 waiting, 1 pending, 2 present, 3 hidden
    last_arc = np.full(n, -1, dtype=np.int32)   # each site's arc found last: where its next search starts
    removed_at = np.full(arcs.shape[0], -1, dtype=np.int32)
    cand = np.full((arcs.shape[0], 2), -1, dtype=np.int32)     # see _circle_candidate
    at = np.empty(2 * n + 4, dtype=np.int32)
    S = np.zeros(_S_FIELDS, dtype=np.int64)
    SF = np.zeros(_SF_FIELDS, dtype=np.float64)
    S[_ROOT] = -1
    S[_HEREK] = -1
    S[_STATUS] = OK
    _lowest_row(G, order, row, counters, slab, arcs, edges, last, before, state, S)
    while True:
        status = _run(G, order, counters, arcs, ev, evf, heap, hkey, free, edges, vspec, vbox, wsite, wnext, whead,
                      slab, last, before, state, last_arc, removed_at, cand, at, S, SF)
        if status != _NEED_ROOM:
            break
        if 2 * wsite.shape[0] > MAX_WATCH_ROWS:
            status = ERR_CAPACITY
            break
        wsite, wnext = _grown(wsite, wnext)
    return status, edges[:S[_NEDGE]], vspec[:S[_NVERT]], vbox[:S[_NVERT]]


@njit(cache=True)
def _lowest_row(G, order, row, counters, slab, arcs, edges, last, before, state, S):
    """The beach line of the lowest row, the upper envelope of the lines 2 x_i X - x_i^2 - s_i
    (slopes increasing along the row); the others there are hidden for good."""
    hull = np.empty(row, dtype=np.int64)
    m = 0
    for r in range(row):
        i = order[r]
        while m >= 2 and not keeps_middle(G, counters, hull[m - 2], hull[m - 1], i):
            m -= 1
        hull[m] = i
        m += 1
    previous = -1
    levels = last.shape[0]
    for r in range(row):
        state[order[r]] = 3
        before[order[r]] = last[0, slab[order[r]]]
        for level in range(levels):
            last[level, slab[order[r]] >> (2 * level)] = order[r]
    for h in range(m):
        i = hull[h]
        state[i] = 2
        x = _new_arc(arcs, S, i)
        S[_ROOT] = bl.insert_after(arcs, S[_ROOT], previous, x)
        if previous >= 0:
            arcs[previous, bl.EDGE] = _new_edge(edges, S, arcs[previous, bl.SITE], i, -1)
        previous = x
    counters[NEVER_ENTERED] += row - m
    counters[FIRST_ROW] = m
    counters[MAX_BEACH] = m
    S[_NXTACT], S[_GUARD], S[_BEACH] = row, 0, m


@njit(cache=True, _nrt=False)
def _run(G, order, counters, arcs, ev, evf, heap, hkey, free, edges, vspec, vbox, wsite, wnext, whead, slab, last,
         before, state, last_arc, removed_at, cand, at, S, SF):
    """The sweep's loop over events, on the arrays :func:`sweep` made: without reference
    counting, which allocates nothing. Returns the sweep's status, or ``_NEED_ROOM`` (before
    an event is taken) when the watch pool may be too small for the next one: the caller grows
    it and calls again, the state being all in the arrays."""
    n = G.shape[0]
    head = 0                                    # the leftmost arc never changes
    nxt_act, guard, beach = S[_NXTACT], S[_GUARD], S[_BEACH]

    # activations (n), circle events (one per arc removed, at most 2n) and probes (each adds a
    # new site to a pending site's watch, so at most n per site; a repeat stops the sweep)
    limit = 4 * n + n * n + 1000
    sparse_gap = 2 * n // last.shape[1]         # twice the activations per slab: see the looks below
    while guard < limit:
        if S[_SEQN] > _MAX_ID - 6:
            S[_STATUS] = ERR_CAPACITY
            break
        if S[_WUSED] + _ACTIVATION_WATCH + last.shape[0] > wsite.shape[0]:
            # an event watches at most two more sites, and an activation the slabs' sites too:
            # room first, the event after
            S[_NXTACT], S[_GUARD], S[_BEACH] = nxt_act, guard, beach
            return _NEED_ROOM
        guard += 1
        use_heap = False
        beside = (np.int64(-1), np.int64(-1))
        if S[_HEAPN] > 0:
            if nxt_act >= n:
                use_heap = True
            else:
                top = heap[0]
                i = order[nxt_act]
                # the top's time interval against the site's y decides without a call (as
                # time_order's first steps would), nearly always
                if hkey[0, 1] < G[i, 1]:
                    counters[FILTERED] += 1
                    use_heap = True
                elif G[i, 1] < hkey[0, 0]:
                    counters[FILTERED] += 1
                    use_heap = False
                else:
                    c = time_order(G, counters, ev[top, _TK], ev[top, _TA], ev[top, _TB], ev[top, _TC],
                                   evf[top, 0], evf[top, 1], SITE, i, -1, -1, G[i, 1], G[i, 1])
                    use_heap = c < 0 or (c == 0 and ev[top, _KIND] == _CIRCLE)
        elif nxt_act >= n:
            break
        if not use_heap:
            # activation of site i: it watches the arc over it (and the leftmost, of the lowest
            # row, if that arc's site is not lower: a bound needs a lower site)
            i = order[nxt_act]
            nxt_act += 1
            counters[ACTIVATIONS] += 1
            S[_NOWK], S[_NOWA], S[_NOWB], S[_NOWC] = SITE, i, -1, -1
            SF[0], SF[1] = G[i, 1], G[i, 1]
            state[i] = 1
            # the search starts from the arc found last for the slab's newest site, near i
            newest = last[0, slab[i]]
            arc, _ = _walk(G, counters, arcs, removed_at, last_arc[newest] if newest >= 0 else -1, SITE, i, -1, -1,
                           G[i, 0], G[i, 0], G[i, 1], G[i, 1], at)
            if arc < 0:
                arc, _ = _locate(G, counters, arcs, S[_ROOT], SITE, i, -1, -1, G[i, 0], G[i, 0], G[i, 1], G[i, 1], at)
            if arc < 0:
                S[_STATUS] = ERR_STATE
                break
            last_arc[i] = arc
            first = arcs[arc, bl.SITE]
            for t in range(2):
                if t == 1 and G[first, 1] < G[i, 1]:
                    break
                s = first if t == 0 else arcs[head, bl.SITE]
                _watch(wsite, wnext, whead, S, i, s)
            schedule = i
            line = -1
            activated = True
        else:
            e = heap[0]
            _remove(G, counters, S, ev, evf, heap, hkey, free, e)
            S[_NOWK], S[_NOWA], S[_NOWB], S[_NOWC] = ev[e, _TK], ev[e, _TA], ev[e, _TB], ev[e, _TC]
            SF[0], SF[1] = evf[e, 0], evf[e, 1]
            schedule = -1
            line = -1
            activated = False
            if ev[e, _KIND] == _CIRCLE:
                k = ev[e, _OWNER]
                arcs[k, bl.EVENT] = -1
                left, right = arcs[k, bl.PREV], arcs[k, bl.NEXT]
                if left < 0 or right < 0:
                    S[_STATUS] = ERR_STATE
                    break
                counters[CIRCLES] += 1
                S[_HEREK], S[_HEREA], S[_HEREB], S[_HEREC] = ev[e, _PK], ev[e, _PA], ev[e, _PB], ev[e, _PC]
                v = _new_vertex(vspec, vbox, S, ev[e, _PA], ev[e, _PB], ev[e, _PC],
                                (evf[e, 2], evf[e, 3], evf[e, 4], evf[e, 5]))
                _close(edges, arcs[left, bl.EDGE], arcs[left, bl.SITE], v)
                _close(edges, arcs[k, bl.EDGE], arcs[k, bl.SITE], v)
                arcs[left, bl.EDGE] = _new_edge(edges, S, arcs[left, bl.SITE], arcs[right, bl.SITE], v)
                S[_ROOT] = bl.remove(arcs, S[_ROOT], k)
                removed_at[k] = left
                beach -= 1
                # refresh(left, right): lo..hi is left, right; then left's left, right's right
                _refresh(G, counters, S, SF, ev, evf, heap, hkey, free, arcs, cand,
                         (np.int64(left), np.int64(right), np.int64(arcs[left, bl.PREV]),
                          np.int64(arcs[right, bl.NEXT]), np.int64(-1)))
            else:
                # a probe of site i at the point q of its lower bound: the arc over q decides
                i = ev[e, _OWNER]
                pk, pa, pb, pc = ev[e, _PK], ev[e, _PA], ev[e, _PB], ev[e, _PC]
                counters[PROBES] += 1
                # the box of the probe's point, kept from _lowest_point
                xl, xh, yl, yh, tl, th = evf[e, 2], evf[e, 3], evf[e, 4], evf[e, 5], evf[e, 0], evf[e, 1]
                # from the arc found last for a site on the beach line that defines q (it has
                # i's power at q, and its arc is often near q), else for i (at its activation or
                # its last probe): in a dense cluster, i's bound moves far along the beach line
                # from the arc i was found under
                near = pb if pb >= 0 and state[pb] == 2 else (pc if pc >= 0 and state[pc] == 2 else -1)
                arc, nat = -1, 0
                if near >= 0:
                    arc, nat = _walk(G, counters, arcs, removed_at, last_arc[near], pk, pa, pb, pc, xl, xh, tl, th,
                                     at)
                if arc < 0:
                    arc, nat = _walk(G, counters, arcs, removed_at, last_arc[i], pk, pa, pb, pc, xl, xh, tl, th, at)
                if arc < 0:
                    arc, nat = _locate(G, counters, arcs, S[_ROOT], pk, pa, pb, pc, xl, xh, tl, th, at)
                if arc < 0:
                    S[_STATUS] = ERR_STATE
                    break
                last_arc[i] = arc
                above = arcs[arc, bl.SITE]
                gap = power_gap(G, counters, above, i, pk, pa, pb, pc, xl, xh, yl, yh)
                if gap < 0:
                    # q is below the beach line: the arc's site joins the watch, the bound moves on
                    _watch(wsite, wnext, whead, S, i, above)
                    schedule = i
                    line = above
                    left, right = arcs[arc, bl.PREV], arcs[arc, bl.NEXT]
                    beside = (np.int64(arcs[left, bl.SITE] if left >= 0 else -1),
                              np.int64(arcs[right, bl.SITE] if right >= 0 else -1))
                elif gap > 0:
                    S[_STATUS] = ERR_STATE
                    break
                elif ev[e, _PARTNER] == _UNKEYED and S[_HEAPN] > 0 and not evf[heap[0], 0] > th:
                    # q is on the beach line, and another probe may come at this time: queued
                    # again, now ranked by the arc's site
                    _push(G, counters, S, ev, evf, heap, hkey, free, _PROBE, ev[e, _TK], ev[e, _TA], ev[e, _TB],
                          ev[e, _TC], tl, th, pk, pa, pb, pc, (xl, xh, yl, yh), i, above)
                elif nat == 0:
                    # inside the arc: it splits around i, one edge starts both ways
                    S[_HEREK] = -1
                    counters[IN_ARC] += 1
                    state[i] = 2
                    k_site = arcs[arc, bl.SITE]
                    x = _new_arc(arcs, S, i)
                    twin = _new_arc(arcs, S, k_site)
                    arcs[twin, bl.EDGE] = arcs[arc, bl.EDGE]
                    arcs[arc, bl.EDGE] = _new_edge(edges, S, k_site, i, -1)
                    arcs[x, bl.EDGE] = arcs[arc, bl.EDGE]
                    S[_ROOT] = bl.insert_after(arcs, S[_ROOT], arc, x)
                    S[_ROOT] = bl.insert_after(arcs, S[_ROOT], x, twin)
                    beach += 2
                    _refresh(G, counters, S, SF, ev, evf, heap, hkey, free, arcs, cand,
                             (np.int64(arc), np.int64(x), np.int64(twin), np.int64(arcs[arc, bl.PREV]),
                              np.int64(arcs[twin, bl.NEXT])))
                else:
                    entered = False
                    for j in range(nat):
                        la = at[j]
                        ra = arcs[la, bl.NEXT]
                        sa, sb = arcs[la, bl.SITE], arcs[ra, bl.SITE]
                        if orient2d(G[sa, 0], G[sa, 1], G[i, 0], G[i, 1], G[sb, 0], G[sb, 1]) < 0:
                            # at the breakpoint (a, b): a vertex; (a, b) ends, (a, i), (i, b) start
                            S[_HEREK], S[_HEREA], S[_HEREB], S[_HEREC] = CENTRE, sa, i, sb
                            counters[AT_VERTEX] += 1
                            state[i] = 2
                            v = _new_vertex(vspec, vbox, S, sa, i, sb, (xl, xh, yl, yh))
                            _close(edges, arcs[la, bl.EDGE], sa, v)
                            x = _new_arc(arcs, S, i)
                            arcs[la, bl.EDGE] = _new_edge(edges, S, sa, i, v)
                            arcs[x, bl.EDGE] = _new_edge(edges, S, i, sb, v)
                            S[_ROOT] = bl.insert_after(arcs, S[_ROOT], la, x)
                            beach += 1
                            _refresh(G, counters, S, SF, ev, evf, heap, hkey, free, arcs, cand,
                                     (np.int64(la), np.int64(x), np.int64(ra), np.int64(arcs[la, bl.PREV]),
                                      np.int64(arcs[ra, bl.NEXT])))
                            entered = True
                            break
                    if not entered:
                        state[i] = 3            # squeezed out at once: a cell of no area
                        counters[NEVER_ENTERED] += 1
            if beach > counters[MAX_BEACH]:
                counters[MAX_BEACH] = beach
        if schedule >= 0:
            i = schedule
            found = False
            if line >= 0:
                found, bk, ba, bb, bc, partner, blo, bhi, box = _lowest_on_line(G, counters, wsite, wnext, whead,
                                                                                i, line)
            if not found:
                bk, ba, bb, bc, partner, blo, bhi, box = _lowest_point(G, counters, wsite, wnext, whead, i)
            if activated:
                # the sites activated last in i's slab and the two beside it are near i, most of
                # them pending: their constraints bound Q_i close to i's cell at once, where the
                # beach line alone (far below a dense cluster, whose sites enter late) would take
                # a probe per cell on the way up. Each that the bound breaks joins S_i, and the
                # bound moves onto its line (Seidel's step, as after a probe).
                sl = slab[i]
                watched = S[_WUSED]
                for d in range(_SLAB_WATCH):
                    near = sl - _SLAB_WATCH // 2 + d
                    if bk < 0 or near < 0 or near >= last.shape[1]:
                        continue
                    bk, ba, bb, bc, partner, blo, bhi, box = _tighten(G, counters, wsite, wnext, whead, S, i,
                                                                      last[0, near], bk, ba, bb, bc, partner,
                                                                      blo, bhi, box)
                moved = S[_WUSED] > watched
                # Where i is sparser than its slab's densest part (above or below a cluster),
                # the newest in its slab may be far below it: a slab gets an activation every
                # n / slabs on average, and i's came more than twice that after the last. Then,
                # and where they moved the bound (i is in a dense part), the newest of each
                # coarser slab (four times as wide each level) is looked at too
                own = last[0, sl]
                if moved or own < 0 or i - own > sparse_gap:
                    for level in range(1, last.shape[0]):
                        if bk < 0:
                            break
                        bk, ba, bb, bc, partner, blo, bhi, box = _tighten(G, counters, wsite, wnext, whead, S, i,
                                                                          last[level, sl >> (2 * level)], bk, ba,
                                                                          bb, bc, partner, blo, bhi, box)
                # where any of them moved the bound (on a uniform set, about one activation in
                # five), the ones activated before the newest, in i's slab and beside it
                for d in range(3 if S[_WUSED] > watched else 0):
                    near = sl + d - 1
                    if near < 0 or near >= last.shape[1]:
                        continue
                    s = last[0, near]
                    for _ in range(OWN_DEPTH if d == 1 else SIDE_DEPTH):
                        if bk < 0 or s < 0:
                            break
                        s = before[s]
                        bk, ba, bb, bc, partner, blo, bhi, box = _tighten(G, counters, wsite, wnext, whead, S, i, s,
                                                                          bk, ba, bb, bc, partner, blo, bhi, box)
                before[i] = last[0, sl]
                for level in range(last.shape[0]):
                    last[level, sl >> (2 * level)] = i
            elif line >= 0:
                # a probe below the beach line: the arcs beside the one over its point are the
                # beach line around it too, and bound Q_i as that arc's site does
                for s in beside:
                    if bk < 0:
                        break
                    bk, ba, bb, bc, partner, blo, bhi, box = _tighten(G, counters, wsite, wnext, whead, S, i, s,
                                                                      bk, ba, bb, bc, partner, blo, bhi, box)
            if bk == -2:
                S[_STATUS] = ERR_STATE
                break
            if bk < 0:
                state[i] = 3                    # Q_i is empty: hidden
                counters[NEVER_ENTERED] += 1
            else:
                if partner >= 0 and state[partner] != 2:
                    partner = _UNKEYED
                _push(G, counters, S, ev, evf, heap, hkey, free, _PROBE, bk, ba, bb, bc, blo, bhi,
                      bk, ba, bb, bc, box, i, partner)
    if guard >= limit:
        S[_STATUS] = ERR_ITERATIONS
    return S[_STATUS]


@njit(cache=True, _nrt=False)
def _first_joinable(counters, edges, box):
    # the first edge whose two ends are one vertex or have boxes that meet (edges.shape[0] if
    # none); each edge before it with two ends counts as one filtered decision
    for e in range(edges.shape[0]):
        a, b = edges[e, 2], edges[e, 3]
        if a < 0 or b < 0:
            continue
        if a == b or not (box[a, 1] < box[b, 0] or box[b, 1] < box[a, 0] or box[a, 3] < box[b, 2]
                          or box[b, 3] < box[a, 2]):
            return e
        counters[FILTERED] += 1
    return edges.shape[0]


@njit(cache=True)
def merge_vertices(G, counters, edges, vspec, box):
    """Vertices at one exact point, joined by edges between them, become one, and the edges
    of no length go: returns (edges with renumbered ends, the spec of each vertex kept).
    ``box`` holds a box around each vertex (NaN where not known, computed here)."""
    nv = vspec.shape[0]
    for v in range(nv):
        if np.isnan(box[v, 0]):
            xl, xh, yl, yh, _, _ = spec_point(G, CENTRE, vspec[v, 0], vspec[v, 1], vspec[v, 2])
            box[v, 0], box[v, 1], box[v, 2], box[v, 3] = xl, xh, yl, yh
    # until the first edge whose ends may be one point, no vertex is merged: those edges are
    # only counted (as same_centre would count its filtered test), with no union-find
    first = _first_joinable(counters, edges, box)
    if first == edges.shape[0]:
        return edges, vspec                 # nothing to merge or drop (a set in general position)
    parent = np.arange(nv)
    joined = 0                              # merges, and edges whose ends are one vertex
    for e in range(first, edges.shape[0]):
        a, b = edges[e, 2], edges[e, 3]
        if a < 0 or b < 0:
            continue
        while parent[a] != a:
            a = parent[a]
        while parent[b] != b:
            b = parent[b]
        if a == b:
            joined += 1
            continue
        if same_centre(counters, vspec[a, 0], vspec[a, 1], vspec[a, 2],
                       (box[a, 0], box[a, 1], box[a, 2], box[a, 3]),
                       vspec[b, 0], vspec[b, 1], vspec[b, 2], (box[b, 0], box[b, 1], box[b, 2], box[b, 3])):
            parent[max(a, b)] = min(a, b)
            counters[MERGED] += 1
            joined += 1
    if joined == 0:
        return edges, vspec
    new_id = np.full(nv, -1, dtype=np.int64)
    kept = 0
    for v in range(nv):
        r = v
        while parent[r] != r:
            r = parent[r]
        if r == v:
            new_id[v] = kept
            kept += 1
        else:
            new_id[v] = new_id[r]           # r < v: already numbered
    specs = np.empty((kept, 3), dtype=np.int32)
    for v in range(nv):
        specs[new_id[v]] = vspec[v]
    out = np.empty_like(edges)
    m = 0
    for e in range(edges.shape[0]):
        a, b = edges[e, 2], edges[e, 3]
        a = new_id[a] if a >= 0 else -1
        b = new_id[b] if b >= 0 else -1
        if a >= 0 and a == b:
            continue                        # no length: the sites of a co-power vertex
        out[m, 0], out[m, 1], out[m, 2], out[m, 3] = edges[e, 0], edges[e, 1], a, b
        m += 1
    return out[:m], specs
