"""Circle events in an indexed binary min-heap, ordered exactly by the top of their circle.

Site events need no queue: the sites are pre-sorted by (y, x) and the sweep compares the next
site with the heap's top. A circle event of arcs (a, b, c) lives in row e of ``ev_i``
(sites A, B, C, the vanishing ARC, its heap position POS) and ``ev_f`` (float top Y with its
error bound ERR, the circumcentre VX, VY). Rows are recycled through a free list (a stack,
so the live rows stay few and cache-resident). The heap stores row ids with a copy of their
float keys next to them (``hy``, ``herr``: comparisons touch one contiguous array); POS makes
removal of an invalidated event O(log n).

Order: the float tops decide when their error intervals are disjoint; otherwise
:func:`~vorobench.predicates.circle_events_order_exact` does; exact ties go to the older
event (smaller row id is not stable under recycling, so a sequence number SEQ is kept).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from vorobench.predicates import circle_event_vs_site_exact, circle_events_order_exact

__all__ = [
    "A", "B", "C", "ARC", "POS", "SEQ", "Y", "ERR", "VX", "VY",
    "ORDER_CALLS", "ORDER_EXACT",
    "new_queue", "allocate", "release", "push", "pop", "discard", "before", "before_site",
]

A, B, C, ARC, POS, SEQ = range(6)
Y, ERR, VX, VY = range(4)

#: Indices into the sweep's counters array for event comparisons (calls, exact fallbacks).
ORDER_CALLS = 6
ORDER_EXACT = 7


@njit(cache=True)
def new_queue(capacity):
    """(ev_i, ev_f, heap, hkey, free): event rows, the heap with its keys, a free-row stack.

    Allocated uninitialised: only the rows in use are ever touched (the beach line, and so
    the number of pending events, is typically O(sqrt n)).
    """
    capacity = max(capacity, 1)
    ev_i = np.empty((capacity, 6), dtype=np.int32)
    ev_f = np.empty((capacity, 4), dtype=np.float64)
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


@njit(cache=True)
def _exact_before(sites, ev_i, e, g):
    # exact order of two circle events; equal tops go to the older event (smaller SEQ).
    # Only scalars cross the call into the predicate (array arguments cost reference counts).
    a, b, c = ev_i[e, A], ev_i[e, B], ev_i[e, C]
    p, q, r = ev_i[g, A], ev_i[g, B], ev_i[g, C]
    s = circle_events_order_exact(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1],
                                  sites[p, 0], sites[p, 1], sites[q, 0], sites[q, 1], sites[r, 0], sites[r, 1])
    if s != 0:
        return s < 0
    return ev_i[e, SEQ] < ev_i[g, SEQ]


@njit(cache=True)
def before(sites, ev_i, ye, erre, e, yg, errg, g, counters):
    """True if circle event e (float top ye +- erre) must be processed before g (exact; ties by SEQ)."""
    counters[ORDER_CALLS] += 1
    o = _float_order(ye, erre, yg, errg)
    if o != 0:
        return o < 0
    counters[ORDER_EXACT] += 1
    return _exact_before(sites, ev_i, e, g)


@njit(cache=True, inline='always')
def before_site(sites, ev_i, ye, erre, e, sy, counters):
    """True if circle event e (float top ye +- erre) comes no later than a site at height sy
    (ties: circle first)."""
    counters[ORDER_CALLS] += 1
    o = _float_order(ye, erre, sy, 0.0)
    if o != 0:
        return o < 0
    counters[ORDER_EXACT] += 1
    a, b, c = ev_i[e, A], ev_i[e, B], ev_i[e, C]
    s = circle_event_vs_site_exact(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1], sy)
    return s <= 0


@njit(cache=True, inline='always')
def _sift_up(sites, ev_i, heap, hkey, k, counters):
    e = heap[k]
    ye = hkey[k, 0]
    erre = hkey[k, 1]
    while k > 0:
        parent = (k - 1) >> 1
        counters[ORDER_CALLS] += 1
        o = _float_order(ye, erre, hkey[parent, 0], hkey[parent, 1])
        if o == 0:
            counters[ORDER_EXACT] += 1
            o = -1 if _exact_before(sites, ev_i, e, heap[parent]) else 1
        if o > 0:
            break
        g = heap[parent]
        heap[k] = g
        hkey[k, 0] = hkey[parent, 0]
        hkey[k, 1] = hkey[parent, 1]
        ev_i[g, POS] = k
        k = parent
    heap[k] = e
    hkey[k, 0] = ye
    hkey[k, 1] = erre
    ev_i[e, POS] = k


@njit(cache=True, inline='always')
def _sift_down(sites, ev_i, heap, hkey, size, k, counters):
    e = heap[k]
    ye = hkey[k, 0]
    erre = hkey[k, 1]
    while True:
        child = 2 * k + 1
        if child >= size:
            break
        if child + 1 < size:
            counters[ORDER_CALLS] += 1
            o = _float_order(hkey[child + 1, 0], hkey[child + 1, 1], hkey[child, 0], hkey[child, 1])
            if o == 0:
                counters[ORDER_EXACT] += 1
                o = -1 if _exact_before(sites, ev_i, heap[child + 1], heap[child]) else 1
            if o < 0:
                child += 1
        counters[ORDER_CALLS] += 1
        o = _float_order(hkey[child, 0], hkey[child, 1], ye, erre)
        if o == 0:
            counters[ORDER_EXACT] += 1
            o = -1 if _exact_before(sites, ev_i, heap[child], e) else 1
        if o > 0:
            break
        g = heap[child]
        heap[k] = g
        hkey[k, 0] = hkey[child, 0]
        hkey[k, 1] = hkey[child, 1]
        ev_i[g, POS] = k
        k = child
    heap[k] = e
    hkey[k, 0] = ye
    hkey[k, 1] = erre
    ev_i[e, POS] = k


@njit(cache=True, inline='always')
def push(sites, ev_i, ev_f, heap, hkey, size, e, counters):
    """Add event row e (its key taken from ev_f); returns the new heap size."""
    heap[size] = e
    hkey[size, 0] = ev_f[e, Y]
    hkey[size, 1] = ev_f[e, ERR]
    ev_i[e, POS] = size
    _sift_up(sites, ev_i, heap, hkey, size, counters)
    return size + 1


@njit(cache=True, inline='always')
def pop(sites, ev_i, heap, hkey, size, counters):
    """Remove the first event; returns (its row, new size). The heap must not be empty."""
    e = heap[0]
    size -= 1
    if size > 0:
        last = heap[size]
        heap[0] = last
        hkey[0, 0] = hkey[size, 0]
        hkey[0, 1] = hkey[size, 1]
        ev_i[last, POS] = 0
        _sift_down(sites, ev_i, heap, hkey, size, 0, counters)
    ev_i[e, POS] = -1
    return e, size


@njit(cache=True, inline='always')
def discard(sites, ev_i, heap, hkey, size, e, counters):
    """Remove event row e from anywhere in the heap; returns the new size."""
    k = ev_i[e, POS]
    size -= 1
    if k != size:
        last = heap[size]
        heap[k] = last
        hkey[k, 0] = hkey[size, 0]
        hkey[k, 1] = hkey[size, 1]
        ev_i[last, POS] = k
        p = (k - 1) >> 1
        if k > 0 and before(sites, ev_i, hkey[k, 0], hkey[k, 1], last, hkey[p, 0], hkey[p, 1], heap[p], counters):
            _sift_up(sites, ev_i, heap, hkey, k, counters)
        else:
            _sift_down(sites, ev_i, heap, hkey, size, k, counters)
    ev_i[e, POS] = -1
    return size
