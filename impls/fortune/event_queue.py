"""Circle events in an indexed binary min-heap, ordered exactly by the top of their circle.

Site events need no queue: the sites are pre-sorted by (y, x) and the sweep compares the next
site with the heap's top. A circle event of arcs (a, b, c) lives in row e of ``ev_i`` (sites
A, B, C, the vanishing ARC, its heap position POS, sequence number SEQ, exact-key state KEY)
and ``ev_f`` (float top Y with its error bound ERR, the circumcentre VX, VY, the top relative
to a_y, Q with bound ERRQ, and the exact key CY, R2). Rows are recycled through a free stack,
so the live rows stay few and cache-resident. The heap stores row ids with a copy of their
float keys next to them (``hkey``: comparisons touch one contiguous array); POS makes removal
of a cancelled event O(log n).

Order, in stages: (1) the float tops when their error intervals are disjoint; (2) the same
with the base heights a_y subtracted separately (large offsets); (3) once per event, exact
arithmetic finds its key (:func:`~vorobench.core.predicates.circle_event_key`): a refined relative
top, the top in double-double with a certified error of ~1e-29 of its terms, and, when the
centre's y and squared radius are floats exactly (lattices and cocircular lattice points,
where ties abound), the exact key (cy, r2). Then: equal exact keys are a tie at once (the
common case on lattices, checked before anything else once both events have keys); (2)
again; the double-double tops; exact keys compared as cy + sqrt(r2) in a few exact
operations; and only for tops closer than ~1e-29 without exact keys,
:func:`~vorobench.core.predicates.circle_events_order_exact`. Exact ties go to the older event
(smaller SEQ), which keeps the order total.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from vorobench.core.predicates import (
    KEY_FOUND,
    KEY_NOT_SOUGHT,
    UNDECIDED,
    circle_event_key,
    circle_event_top,
    circle_event_vs_site_exact,
    circle_events_order_exact,
    tops_dd_order,
    tops_key_order,
    tops_order_filter,
)

__all__ = [
    "A", "B", "C", "ARC", "POS", "SEQ", "KEY", "Y", "ERR", "VX", "VY", "Q", "ERRQ", "CY", "R2", "TH", "TL", "TERR",
    "ORDER_CALLS", "ORDER_EXACT", "KEYS_EXACT",
    "new_queue", "allocate", "release", "push", "pop", "discard", "before", "before_site",
]

A, B, C, ARC, POS, SEQ, KEY = range(7)
Y, ERR, VX, VY, Q, ERRQ, CY, R2, TH, TL, TERR = range(11)
I_FIELDS = 7
F_FIELDS = 11
# KEY states: nothing computed yet; exact key (CY, R2) found; no exact key exists (the
# double-double top is from exact expansions or exact floats); double-double top from
# double-double arithmetic, exact key not looked for yet
KEY_UNKNOWN, KEY_EXACT, KEY_NONE, KEY_DD = 0, 1, 2, 3

#: Indices into the sweep's counters array: event comparisons, those that still needed exact
#: arithmetic after the refinement, and refinements (exact keys, at most one per event).
ORDER_CALLS = 6
ORDER_EXACT = 7
KEYS_EXACT = 13


@njit(cache=True)
def new_queue(capacity):
    """(ev_i, ev_f, heap, hkey, free): event rows, the heap with its keys, a free-row stack.

    Allocated uninitialised: only the rows in use are ever touched (the beach line, and so
    the number of pending events, is typically O(sqrt n)).
    """
    capacity = max(capacity, 1)
    ev_i = np.empty((capacity, I_FIELDS), dtype=np.int32)
    ev_f = np.empty((capacity, F_FIELDS), dtype=np.float64)
    heap = np.empty(capacity, dtype=np.int32)
    hkey = np.empty((capacity, 2), dtype=np.float64)           # (Y, ERR) of heap[k]
    free = np.empty(capacity + 1, dtype=np.int32)               # [0]: rows ever used; then a stack
    free[0] = 0
    return ev_i, ev_f, heap, hkey, free


@njit(cache=True, inline='always')
def allocate(ev_i, free, nfree):
    """Take a row: the last one released if any, else a never used one; returns (row, new
    nfree), row -1 if the table is full. ``nfree`` counts the released rows on the stack."""
    if nfree > 0:
        return free[nfree], nfree - 1
    e = free[0]
    if e >= ev_i.shape[0]:
        return -1, 0
    free[0] = e + 1
    return e, 0


@njit(cache=True, inline='always')
def release(ev_i, free, nfree, e):
    """Put row e back on the free stack; returns the new nfree."""
    ev_i[e, POS] = -1
    nfree += 1
    free[nfree] = e
    return nfree


@njit(cache=True, inline='always')
def _float_order(ye, erre, yg, errg):
    # -1: e first, +1: g first, 0: the float tops cannot decide (scalars only: no array
    # arguments, so the call inlines and costs no reference counting)
    d = ye - yg
    tol = erre + errg
    if d < -tol:
        return -1
    if d > tol:
        return 1
    return 0


@njit(cache=True, inline='always')
def _store_key(ev_i, ev_f, e, state, cy, r2, q, errq, th, tl, terr):
    ev_i[e, KEY] = state
    ev_f[e, CY] = cy
    ev_f[e, R2] = r2
    ev_f[e, TH] = th
    ev_f[e, TL] = tl
    ev_f[e, TERR] = terr
    if errq < ev_f[e, ERRQ]:
        ev_f[e, Q] = q
        ev_f[e, ERRQ] = errq


@njit(cache=True, _nrt=False)
def _refine(sites, ev_i, ev_f, e, counters):
    # on first use: the cheap key of event e (see the module docstring); returns True if
    # (CY, R2) hold an exact key
    if ev_i[e, KEY] == KEY_UNKNOWN:
        counters[KEYS_EXACT] += 1
        a, b, c = ev_i[e, A], ev_i[e, B], ev_i[e, C]
        state, cy, r2, q, errq, th, tl, terr = circle_event_top(sites[a, 0], sites[a, 1], sites[b, 0],
                                                                sites[b, 1], sites[c, 0], sites[c, 1])
        kind = KEY_EXACT if state == KEY_FOUND else KEY_DD if state == KEY_NOT_SOUGHT else KEY_NONE
        _store_key(ev_i, ev_f, e, kind, cy, r2, q, errq, th, tl, terr)
    return ev_i[e, KEY] == KEY_EXACT


@njit(cache=True, _nrt=False)
def _refine_exact(sites, ev_i, ev_f, e):
    # when the cheap key could not decide: the key from exact expansions (exact key found or
    # ruled out, double-double top from exact values); returns True if it is an exact key
    if ev_i[e, KEY] == KEY_DD:
        a, b, c = ev_i[e, A], ev_i[e, B], ev_i[e, C]
        ok, cy, r2, q, errq, th, tl, terr = circle_event_key(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1],
                                                             sites[c, 0], sites[c, 1])
        _store_key(ev_i, ev_f, e, KEY_EXACT if ok else KEY_NONE, cy, r2, q, errq, th, tl, terr)
    return ev_i[e, KEY] == KEY_EXACT


@njit(cache=True, inline='always')
def _same_exact_key(ev_i, ev_f, e, g):
    # both events have exact keys and they are equal: the tops tie exactly (a lattice tie,
    # decided by comparing four floats; inlined into the heap's loops)
    return (ev_i[e, KEY] == KEY_EXACT and ev_i[g, KEY] == KEY_EXACT and ev_f[e, CY] == ev_f[g, CY]
            and ev_f[e, R2] == ev_f[g, R2])


@njit(cache=True, _nrt=False)
def _exact_before(sites, ev_i, ev_f, e, g, counters):
    # stages 2-4 of the order (see the module docstring), after the heap keys could not decide
    if _same_exact_key(ev_i, ev_f, e, g):
        return ev_i[e, SEQ] < ev_i[g, SEQ]
    a, b, c = ev_i[e, A], ev_i[e, B], ev_i[e, C]
    p, q, r = ev_i[g, A], ev_i[g, B], ev_i[g, C]
    s = tops_order_filter(sites[a, 1], ev_f[e, Q], ev_f[e, ERRQ], sites[p, 1], ev_f[g, Q], ev_f[g, ERRQ])
    if s == UNDECIDED:
        _refine(sites, ev_i, ev_f, e, counters)
        _refine(sites, ev_i, ev_f, g, counters)
        if _same_exact_key(ev_i, ev_f, e, g):
            return ev_i[e, SEQ] < ev_i[g, SEQ]
        s = tops_order_filter(sites[a, 1], ev_f[e, Q], ev_f[e, ERRQ], sites[p, 1], ev_f[g, Q], ev_f[g, ERRQ])
        if s == UNDECIDED:
            s = tops_dd_order(ev_f[e, TH], ev_f[e, TL], ev_f[e, TERR], ev_f[g, TH], ev_f[g, TL], ev_f[g, TERR])
        if s == UNDECIDED:
            keyed = _refine_exact(sites, ev_i, ev_f, e)
            keyed = _refine_exact(sites, ev_i, ev_f, g) and keyed
            if _same_exact_key(ev_i, ev_f, e, g):
                return ev_i[e, SEQ] < ev_i[g, SEQ]
            s = tops_dd_order(ev_f[e, TH], ev_f[e, TL], ev_f[e, TERR], ev_f[g, TH], ev_f[g, TL], ev_f[g, TERR])
            if s == UNDECIDED:
                counters[ORDER_EXACT] += 1
                if keyed:
                    s = tops_key_order(ev_f[e, CY], ev_f[e, R2], ev_f[g, CY], ev_f[g, R2])
                else:
                    s = circle_events_order_exact(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0],
                                                  sites[c, 1], sites[p, 0], sites[p, 1], sites[q, 0], sites[q, 1],
                                                  sites[r, 0], sites[r, 1])
    if s != 0:
        return s < 0
    return ev_i[e, SEQ] < ev_i[g, SEQ]


@njit(cache=True, inline='always')
def before(sites, ev_i, ev_f, ye, erre, e, yg, errg, g, counters):
    """True if circle event e (float top ye +- erre) must be processed before g (exact; ties by SEQ).

    The heap's comparison: the float keys first, then equal exact keys (a lattice tie, four
    floats, inlined into the heap's loops), then the refinements of ``_exact_before``."""
    counters[ORDER_CALLS] += 1
    o = _float_order(ye, erre, yg, errg)
    if o != 0:
        return o < 0
    if _same_exact_key(ev_i, ev_f, e, g):
        return ev_i[e, SEQ] < ev_i[g, SEQ]
    return _exact_before(sites, ev_i, ev_f, e, g, counters)


@njit(cache=True, _nrt=False)
def _exact_before_site(sites, ev_i, ev_f, e, sy, counters):
    a, b, c = ev_i[e, A], ev_i[e, B], ev_i[e, C]
    s = tops_order_filter(sites[a, 1], ev_f[e, Q], ev_f[e, ERRQ], sy, 0.0, 0.0)
    if s == UNDECIDED:
        _refine(sites, ev_i, ev_f, e, counters)
        s = tops_order_filter(sites[a, 1], ev_f[e, Q], ev_f[e, ERRQ], sy, 0.0, 0.0)
        if s == UNDECIDED:
            s = tops_dd_order(ev_f[e, TH], ev_f[e, TL], ev_f[e, TERR], sy, 0.0, 0.0)
        if s == UNDECIDED:
            keyed = _refine_exact(sites, ev_i, ev_f, e)
            s = tops_dd_order(ev_f[e, TH], ev_f[e, TL], ev_f[e, TERR], sy, 0.0, 0.0)
            if s == UNDECIDED:
                counters[ORDER_EXACT] += 1
                if keyed:
                    s = tops_key_order(ev_f[e, CY], ev_f[e, R2], sy, 0.0)
                else:
                    s = circle_event_vs_site_exact(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1],
                                                   sites[c, 0], sites[c, 1], sy)
    return s <= 0


@njit(cache=True, inline='always')
def before_site(sites, ev_i, ev_f, ye, erre, e, sy, counters):
    """True if circle event e (float top ye +- erre) comes no later than a site at height sy
    (ties: circle first)."""
    counters[ORDER_CALLS] += 1
    o = _float_order(ye, erre, sy, 0.0)
    if o != 0:
        return o < 0
    return _exact_before_site(sites, ev_i, ev_f, e, sy, counters)


@njit(cache=True, inline='always')
def _move(ev_i, heap, hkey, src, dst):
    # heap slot src's event (and its key copy) goes to slot dst
    g = heap[src]
    heap[dst] = g
    hkey[dst, 0] = hkey[src, 0]
    hkey[dst, 1] = hkey[src, 1]
    ev_i[g, POS] = dst


@njit(cache=True, inline='always')
def _settle(sites, ev_i, ev_f, heap, hkey, hole, top, e, ye, erre, counters):
    # put event e (key ye +- erre) into the hole at slot `hole`, moving it up while it
    # precedes its parent but never above slot `top`
    while hole > top:
        parent = (hole - 1) >> 1
        if not before(sites, ev_i, ev_f, ye, erre, e, hkey[parent, 0], hkey[parent, 1], heap[parent], counters):
            break
        _move(ev_i, heap, hkey, parent, hole)
        hole = parent
    heap[hole] = e
    hkey[hole, 0] = ye
    hkey[hole, 1] = erre
    ev_i[e, POS] = hole


@njit(cache=True, inline='always')
def _sift_up(sites, ev_i, ev_f, heap, hkey, k, counters):
    _settle(sites, ev_i, ev_f, heap, hkey, k, 0, heap[k], hkey[k, 0], hkey[k, 1], counters)


@njit(cache=True, inline='always')
def _refill(sites, ev_i, ev_f, heap, hkey, size, k, e, ye, erre, counters):
    # slot k is empty and e (key ye +- erre, no earlier than k's parent) must go into the
    # subtree below it: the earlier child moves up into the hole until the hole is a leaf,
    # then e settles up from there. One comparison per level on the way down instead of two:
    # the element that fills a hole is usually one of the latest, so it belongs near a leaf
    # (bottom-up deletion, as in bottom-up heapsort)
    hole = k
    while True:
        child = 2 * hole + 1
        if child >= size:
            break
        if child + 1 < size and before(sites, ev_i, ev_f, hkey[child + 1, 0], hkey[child + 1, 1], heap[child + 1],
                                          hkey[child, 0], hkey[child, 1], heap[child], counters):
            child += 1
        _move(ev_i, heap, hkey, child, hole)
        hole = child
    _settle(sites, ev_i, ev_f, heap, hkey, hole, k, e, ye, erre, counters)


@njit(cache=True, inline='always')
def push(sites, ev_i, ev_f, heap, hkey, size, e, counters):
    """Add event row e (its key taken from ev_f); returns the new heap size."""
    heap[size] = e
    hkey[size, 0] = ev_f[e, Y]
    hkey[size, 1] = ev_f[e, ERR]
    ev_i[e, POS] = size
    _sift_up(sites, ev_i, ev_f, heap, hkey, size, counters)
    return size + 1


@njit(cache=True, inline='always')
def pop(sites, ev_i, ev_f, heap, hkey, size, counters):
    """Remove the first event; returns (its row, new size). The heap must not be empty."""
    e = heap[0]
    size -= 1
    if size > 0:
        _refill(sites, ev_i, ev_f, heap, hkey, size, 0, heap[size], hkey[size, 0], hkey[size, 1], counters)
    ev_i[e, POS] = -1
    return e, size


@njit(cache=True, inline='always')
def discard(sites, ev_i, ev_f, heap, hkey, size, e, counters):
    """Remove event row e from anywhere in the heap; returns the new size."""
    k = ev_i[e, POS]
    size -= 1
    if k != size:
        last = heap[size]
        ye = hkey[size, 0]
        erre = hkey[size, 1]
        p = (k - 1) >> 1
        if k > 0 and before(sites, ev_i, ev_f, ye, erre, last, hkey[p, 0], hkey[p, 1], heap[p], counters):
            _settle(sites, ev_i, ev_f, heap, hkey, k, 0, last, ye, erre, counters)
        else:
            _refill(sites, ev_i, ev_f, heap, hkey, size, k, last, ye, erre, counters)
    ev_i[e, POS] = -1
    return size
