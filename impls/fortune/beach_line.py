"""The beach line: a treap of parabolic arcs over one int32 array, searched by exact breakpoints.

Each row of ``arcs`` is one arc: its treap links (LEFT, RIGHT, PARENT), its neighbours along
the beach line (PREV, NEXT, a doubly linked list in left-to-right order), its SITE, the EDGE
traced by the breakpoint to its right, its pending circle EVENT (-1 = none) and its random
treap priority PRIO (a min-heap on PRIO keeps the expected depth O(log n)). The tree is not
keyed by stored values: the order is the left-to-right order of the arcs, and a search
compares the new site with breakpoints evaluated at the current sweep position (exact
:func:`~vorobench.core.predicates.breakpoint_side`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from vorobench.core.predicates import UNDECIDED, breakpoint_side_exact, breakpoint_side_filter

__all__ = [
    "LEFT", "RIGHT", "PARENT", "PREV", "NEXT", "SITE", "EDGE", "EVENT", "PRIO", "ARC_FIELDS",
    "BP_CALLS", "BP_EXACT",
    "new_arcs", "add_arc", "insert_after", "remove", "locate", "locate_near", "depth",
]

LEFT, RIGHT, PARENT, PREV, NEXT, SITE, EDGE, EVENT, PRIO = range(9)
ARC_FIELDS = 9

#: Indices into the sweep's counters array for the breakpoint tests (calls, exact fallbacks).
BP_CALLS = 4
BP_EXACT = 5


@njit(cache=True)
def new_arcs(capacity):
    """An arc table with room for ``capacity`` arcs; rows are filled by :func:`add_arc` (left
    uninitialised here, so untouched rows cost no memory)."""
    return np.empty((max(capacity, 1), ARC_FIELDS), dtype=np.int32)


@njit(cache=True, inline='always')
def add_arc(arcs, x, site, prio):
    """Fill row x as a detached arc of ``site`` with treap priority ``prio``; returns x."""
    for f in range(ARC_FIELDS):
        arcs[x, f] = -1
    arcs[x, SITE] = site
    arcs[x, PRIO] = prio
    return x


@njit(cache=True, inline='always')
def _rotate_up(arcs, root, y):
    # Rotate y above its parent p, keeping the in-order (left-to-right) sequence; returns the root.
    p = arcs[y, PARENT]
    g = arcs[p, PARENT]
    if arcs[p, LEFT] == y:
        b = arcs[y, RIGHT]
        arcs[p, LEFT] = b
        arcs[y, RIGHT] = p
    else:
        b = arcs[y, LEFT]
        arcs[p, RIGHT] = b
        arcs[y, LEFT] = p
    if b != -1:
        arcs[b, PARENT] = p
    arcs[p, PARENT] = y
    arcs[y, PARENT] = g
    if g == -1:
        return y
    if arcs[g, LEFT] == p:
        arcs[g, LEFT] = y
    else:
        arcs[g, RIGHT] = y
    return root


@njit(cache=True)
def insert_after(arcs, root, x, y):
    """Insert detached arc y immediately right of arc x (x = -1: y becomes the whole, empty,
    beach line). Returns the new root."""
    if x == -1:
        return y
    # in-order successor slot: x's right child if free, else the leftmost of x's right subtree
    z = arcs[x, RIGHT]
    if z == -1:
        arcs[x, RIGHT] = y
        arcs[y, PARENT] = x
    else:
        while arcs[z, LEFT] != -1:
            z = arcs[z, LEFT]
        arcs[z, LEFT] = y
        arcs[y, PARENT] = z
    nx = arcs[x, NEXT]
    arcs[y, PREV] = x
    arcs[y, NEXT] = nx
    arcs[x, NEXT] = y
    if nx != -1:
        arcs[nx, PREV] = y
    while arcs[y, PARENT] != -1 and arcs[y, PRIO] < arcs[arcs[y, PARENT], PRIO]:
        root = _rotate_up(arcs, root, y)
    return root


@njit(cache=True)
def remove(arcs, root, x):
    """Remove arc x from the tree and the neighbour list; returns the new root."""
    while True:
        lc = arcs[x, LEFT]
        rc = arcs[x, RIGHT]
        if lc == -1 and rc == -1:
            break
        if lc == -1:
            c = rc
        elif rc == -1:
            c = lc
        else:
            c = lc if arcs[lc, PRIO] < arcs[rc, PRIO] else rc
        root = _rotate_up(arcs, root, c)
    p = arcs[x, PARENT]
    if p == -1:
        root = -1
    elif arcs[p, LEFT] == x:
        arcs[p, LEFT] = -1
    else:
        arcs[p, RIGHT] = -1
    pv = arcs[x, PREV]
    nx = arcs[x, NEXT]
    if pv != -1:
        arcs[pv, NEXT] = nx
    if nx != -1:
        arcs[nx, PREV] = pv
    arcs[x, PARENT] = -1
    arcs[x, PREV] = -1
    arcs[x, NEXT] = -1
    return root


@njit(cache=True, inline='always')
def _side(arcs, sites, p, x, sx, sy, counters):
    # exact side of (sx, sy) against the breakpoint of arcs p (left) and x (right)
    a = arcs[p, SITE]
    b = arcs[x, SITE]
    counters[BP_CALLS] += 1
    side = breakpoint_side_filter(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sx, sy)
    if side == UNDECIDED:
        counters[BP_EXACT] += 1
        side = breakpoint_side_exact(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sx, sy)
    return side


@njit(cache=True)
def locate(arcs, root, sites, sx, sy, counters):
    """The arc directly above the new site (sx, sy) at sweep position y = sy.

    A site exactly below a breakpoint goes to the arc on its right (it then splits that arc
    at its left end, and the zero-width piece vanishes at once in a circle event).
    Returns -1 if the search leaves the tree (an inconsistency: never expected).
    """
    x = root
    steps = 0
    limit = arcs.shape[0] + 1
    while x != -1:
        steps += 1
        if steps > limit:
            return -1
        p = arcs[x, PREV]
        if p != -1 and _side(arcs, sites, p, x, sx, sy, counters) < 0:
            x = arcs[x, LEFT]
            continue
        q = arcs[x, NEXT]
        if q != -1 and _side(arcs, sites, x, q, sx, sy, counters) >= 0:
            x = arcs[x, RIGHT]
            continue
        return x
    return -1


@njit(cache=True)
def locate_near(arcs, sites, x, sx, sy, steps, counters):
    """:func:`locate`'s arc, looked for by walking along the beach line from arc x, at most
    ``steps`` arcs; -1 if it is further. The arc is the one whose left breakpoint is not right
    of the site and whose right breakpoint is right of it, so the answer is locate's."""
    went = 0                    # -1: came from the right neighbour, +1: from the left one
    for _ in range(steps + 1):
        if went <= 0:
            p = arcs[x, PREV]
            if p != -1 and _side(arcs, sites, p, x, sx, sy, counters) < 0:
                x = p
                went = -1
                continue
            if went < 0:
                return x        # its right breakpoint was the one just passed
        q = arcs[x, NEXT]
        if q != -1 and _side(arcs, sites, x, q, sx, sy, counters) >= 0:
            x = q
            went = 1
            continue
        return x
    return -1


@njit(cache=True)
def depth(arcs, root):
    """Height of the treap (number of arcs on the longest root-to-leaf path); for tests."""
    if root == -1:
        return 0
    best = 0
    stack = [(root, 1)]
    while len(stack) > 0:
        x, d = stack.pop()
        if d > best:
            best = d
        if arcs[x, LEFT] != -1:
            stack.append((arcs[x, LEFT], d + 1))
        if arcs[x, RIGHT] != -1:
            stack.append((arcs[x, RIGHT], d + 1))
    return best
