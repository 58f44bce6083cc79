"""Circle events in an indexed binary min-heap, ordered exactly by the top of their circle.

Site events need no queue: the sites are pre-sorted by (y, x) and the sweep compares the next
site with the heap's top. A circle event of arcs (a, b, c) lives in row e of ``ev_i``
(sites A, B, C, the vanishing ARC, its heap position POS) and ``ev_f`` (float top Y with its
error bound ERR, the circumcentre VX, VY). Rows are recycled through a free list, and the
heap stores row ids; POS makes removal of an invalidated event O(log n).

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
    """(ev_i, ev_f, heap, free): event tables with a free list holding every row."""
    capacity = max(capacity, 1)
    ev_i = np.full((capacity, 6), -1, dtype=np.int32)
    ev_f = np.zeros((capacity, 4), dtype=np.float64)
    heap = np.empty(capacity, dtype=np.int32)
    free = np.arange(capacity - 1, -1, -1).astype(np.int32)   # a stack: pop from the end
    return ev_i, ev_f, heap, free


@njit(cache=True)
def allocate(ev_i, free, nfree):
    """Take a row from the free list; returns (row, new nfree), row -1 if none is left."""
    if nfree == 0:
        return -1, 0
    nfree -= 1
    return free[nfree], nfree


@njit(cache=True)
def release(ev_i, free, nfree, e):
    """Return row e to the free list; returns the new nfree."""
    ev_i[e, POS] = -1
    free[nfree] = e
    return nfree + 1


@njit(cache=True)
def before(sites, ev_i, ev_f, e, g, counters):
    """True if circle event e must be processed before g (exact; ties by sequence number)."""
    counters[ORDER_CALLS] += 1
    d = ev_f[e, Y] - ev_f[g, Y]
    tol = ev_f[e, ERR] + ev_f[g, ERR]
    if d < -tol:
        return True
    if d > tol:
        return False
    counters[ORDER_EXACT] += 1
    a, b, c = ev_i[e, A], ev_i[e, B], ev_i[e, C]
    p, q, r = ev_i[g, A], ev_i[g, B], ev_i[g, C]
    s = circle_events_order_exact(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1],
                                  sites[p, 0], sites[p, 1], sites[q, 0], sites[q, 1], sites[r, 0], sites[r, 1])
    if s != 0:
        return s < 0
    return ev_i[e, SEQ] < ev_i[g, SEQ]


@njit(cache=True)
def before_site(sites, ev_i, ev_f, e, sy, counters):
    """True if circle event e comes no later than a site at height sy (ties: circle first)."""
    counters[ORDER_CALLS] += 1
    d = ev_f[e, Y] - sy
    tol = ev_f[e, ERR]
    if d < -tol:
        return True
    if d > tol:
        return False
    counters[ORDER_EXACT] += 1
    a, b, c = ev_i[e, A], ev_i[e, B], ev_i[e, C]
    s = circle_event_vs_site_exact(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1], sy)
    return s <= 0


@njit(cache=True)
def _sift_up(sites, ev_i, ev_f, heap, k, counters):
    e = heap[k]
    while k > 0:
        parent = (k - 1) >> 1
        g = heap[parent]
        if not before(sites, ev_i, ev_f, e, g, counters):
            break
        heap[k] = g
        ev_i[g, POS] = k
        k = parent
    heap[k] = e
    ev_i[e, POS] = k


@njit(cache=True)
def _sift_down(sites, ev_i, ev_f, heap, size, k, counters):
    e = heap[k]
    while True:
        child = 2 * k + 1
        if child >= size:
            break
        if child + 1 < size and before(sites, ev_i, ev_f, heap[child + 1], heap[child], counters):
            child += 1
        g = heap[child]
        if not before(sites, ev_i, ev_f, g, e, counters):
            break
        heap[k] = g
        ev_i[g, POS] = k
        k = child
    heap[k] = e
    ev_i[e, POS] = k


@njit(cache=True)
def push(sites, ev_i, ev_f, heap, size, e, counters):
    """Add event row e; returns the new heap size."""
    heap[size] = e
    ev_i[e, POS] = size
    _sift_up(sites, ev_i, ev_f, heap, size, counters)
    return size + 1


@njit(cache=True)
def pop(sites, ev_i, ev_f, heap, size, counters):
    """Remove the first event; returns (its row, new size). The heap must not be empty."""
    e = heap[0]
    size -= 1
    if size > 0:
        last = heap[size]
        heap[0] = last
        ev_i[last, POS] = 0
        _sift_down(sites, ev_i, ev_f, heap, size, 0, counters)
    ev_i[e, POS] = -1
    return e, size


@njit(cache=True)
def discard(sites, ev_i, ev_f, heap, size, e, counters):
    """Remove event row e from anywhere in the heap; returns the new size."""
    k = ev_i[e, POS]
    size -= 1
    if k != size:
        last = heap[size]
        heap[k] = last
        ev_i[last, POS] = k
        if k > 0 and before(sites, ev_i, ev_f, last, heap[(k - 1) >> 1], counters):
            _sift_up(sites, ev_i, ev_f, heap, k, counters)
        else:
            _sift_down(sites, ev_i, ev_f, heap, size, k, counters)
    ev_i[e, POS] = -1
    return size
