"""The naive O(n^2) Voronoi construction: each cell is the intersection of n - 1 half-planes.

CONTRACT
--------
Why it is the oracle: it follows the definition directly. The cell of site i is the set of
points at least as close to i as to every other site, i.e. the intersection of the
half-planes bounded by the bisectors of i and each other site j. Each cell is computed on
its own, from the whole plane, with no event queue, beach line, triangulation or
neighbourhood structure, so it shares no idea (and no bug) with the sweep or with the
incremental construction; cells are glued together only at the end.
Complexity: O(n^2) clips (every ordered pair), each O(cell size) in the worst case (exactly
cocircular sites: every test exact); with the filters below most clips cost a distance
comparison (uniform, 2 * 10^4 sites: 4 * 10^8 clips, 3 * 10^5 exact incircle calls).
Input: prepared sites (distinct, finite float64), any n >= 0; coordinates within the range
where :mod:`vorobench.core.predicates` is exact.
Representation of a cell: the cyclic list of the sites whose bisectors bound it, in
counter-clockwise order, plus a marker for the arc at infinity if it is unbounded, so an
unbounded cell is an open chain with a ray at each end (no bounding box, no fake edges).
Its vertex between consecutive neighbours a, b is the circumcentre of (i, a, b), identified
by that site triple, never by coordinates.
Exact decisions: clipping cell i by the bisector of (i, j) cuts off vertex (i, a, b) exactly
when j lies strictly inside the circle through i, a, b: ``incircle(i, a, b, j) > 0`` ((i, a, b)
is counter-clockwise for every vertex). A ray along the bisector of (i, q) runs to infinity
in direction perp(q - i); its far end is cut when ``orient2d(i, q, j)`` says perp(q - i)
points towards j (> 0 for the outgoing ray, < 0 for the incoming one); when the ray is
parallel to the new bisector (== 0) it shares the fate of its finite vertex. A vertex exactly
on the bisector (incircle == 0) is kept and the bisector adds no edge there, so cells never
hold zero-length edges. The first two clips use two sites not collinear with i, so a cell is
never a strip (all-collinear input gives the n - 1 parallel lines directly).
Filters (speed only, never a decision): vertex v is cut exactly when j lies inside the
circle centred at v through i. Each vertex's circle is computed once (rounded centre, radius
padded by 1e-6 relative plus a few ulps of the coordinates, far beyond the circumcentre's
error), so a site clearly outside it leaves v strictly kept without an incircle call, like
the float stage of the predicates. A site farther from i than twice the largest padded
radius is outside every circle (|v - j| >= |j - i| - |v - i| > |v - i|): it is skipped for a
bounded cell, and for an unbounded one only the two ends at infinity are tested (exact
orient2d). Whatever the filters cannot settle goes to the exact tests. Sites near i in
Hilbert order are clipped first so cells shrink fast.
Gluing: a vertex is first the sorted site triple of its cell's own bisectors. With 4 or more
cocircular sites, different cells see the same point as different triples; the two cells of
each edge must agree on its ends, so triples are merged along edges (union-find) into one
vertex of degree >= 4 per empty circle. Its coordinates come from the three smallest site ids
on the circle, the rule the incremental construction uses too (shared circumcentre formula:
arithmetic only, no decision), so the two exact constructions agree bit for bit. Two cells
that disagree about a common edge raise an error instead of producing a diagram.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numba import njit
from numpy.typing import NDArray

from impls.base import Implementation
from vorobench.core.builder import assemble, collinear_diagram
from vorobench.core.circumcentre import circumcentre
from vorobench.core.diagram import Diagram
from vorobench.core.hull import all_collinear
from vorobench.core.predicates import (
    INCIRCLE_CALLS,
    INCIRCLE_EXACT,
    ORIENT_CALLS,
    ORIENT_EXACT,
    incircle_counted,
    orient2d_counted,
)
from vorobench.core.scaling import exact_range_sites
from vorobench.core.spatial_order import HILBERT_BITS, hilbert_keys
from vorobench.core.union_find import find

__all__ = ["build", "cells", "supports", "IMPLEMENTATION", "AT_INFINITY", "MAX_SITES"]

#: Marker in a cell's cyclic neighbour list for the arc at infinity of an unbounded cell.
AT_INFINITY = -1
#: Sites clipped first: this many on each side of i in Hilbert order.
NEAR_WINDOW = 24
#: Padding of the prefilter's radius: relative, and in ulps of the largest coordinate.
PREFILTER_REL_PAD = 1e-6
PREFILTER_ULPS = 64.0
#: Operation counts returned by the cell kernel (the predicate counters come separately).
STAT_NAMES = ("clips", "prefiltered", "cuts", "vertex_tests")  # prefiltered: no incircle needed

#: Vertices are keyed by their sorted site triple packed in one int64: n**3 < 2**63.
MAX_SITES = 2_000_000

_CUT, _ON, _KEPT = 1, 0, -1


@njit(cache=True)
def _vertex_status(sites, i, a, b, j, counters):
    """+1 if the vertex (i, a, b) lies strictly on j's side of the bisector, 0 on it, -1 on i's side."""
    return incircle_counted(sites[i, 0], sites[i, 1], sites[a, 0], sites[a, 1],
                            sites[b, 0], sites[b, 1], sites[j, 0], sites[j, 1], counters)


@njit(cache=True)
def _clip(sites, i, j, nb, k, out, status, far, circles, counters, stats):
    """Clip the cell nb[:k] (cyclic, CCW, AT_INFINITY marks the arc at infinity) by the
    bisector of (i, j). Writes the new list into ``out``; returns its length, or -1 if the
    bisector cuts nothing. ``far``: j is known to be too far to cut any finite vertex (see
    the prefilter), so only the ends at infinity are tested. ``circles[m]``: centre and
    padded squared radius of vertex m's circle, for the float filter of each vertex test."""
    cut = 0
    for m in range(k):
        a = nb[m]
        b = nb[(m + 1) % k]
        if a == AT_INFINITY or b == AT_INFINITY:
            status[m] = 2                      # an end at infinity: decided below
            continue
        if far:
            status[m] = _KEPT
            continue
        stats[3] += 1
        dx = sites[j, 0] - circles[m, 0]
        dy = sites[j, 1] - circles[m, 1]
        if (dx * dx + dy * dy) * (1.0 - 1e-12) > circles[m, 2]:
            status[m] = _KEPT                  # clearly outside the vertex's circle
            continue
        s = _vertex_status(sites, i, a, b, j, counters)
        status[m] = s
        if s == _CUT:
            cut += 1
    for m in range(k):
        if status[m] != 2:
            continue
        if nb[(m + 1) % k] == AT_INFINITY:     # outgoing end: after nb[m], along perp(nb[m] - i)
            q = nb[m]
            o = orient2d_counted(sites[i, 0], sites[i, 1], sites[q, 0], sites[q, 1], sites[j, 0], sites[j, 1], counters)
            s = _CUT if o > 0 else (_KEPT if o < 0 else status[(m - 1) % k])
        else:                                  # incoming end: before nb[m + 1]
            q = nb[(m + 1) % k]
            o = orient2d_counted(sites[i, 0], sites[i, 1], sites[q, 0], sites[q, 1], sites[j, 0], sites[j, 1], counters)
            s = _CUT if o < 0 else (_KEPT if o > 0 else status[(m + 1) % k])
        if s == _ON:
            raise RuntimeError("halfplane: a ray lies on a bisector it is parallel to")
        status[m] = s
        if s == _CUT:
            cut += 1
    if cut == 0:
        return -1
    if cut == k:
        raise RuntimeError("halfplane: a bisector cut off the whole cell")
    # the cut vertices form one cyclic run p..q; find its start
    p = -1
    for m in range(k):
        if status[m] == _CUT and status[(m - 1) % k] != _CUT:
            if p >= 0:
                raise RuntimeError("halfplane: the cut part of a cell is not connected")
            p = m
    q = p
    while status[(q + 1) % k] == _CUT:
        q = (q + 1) % k
    # keep the edges from the exit edge nb[q + 1] round to the entry edge nb[p], then j;
    # an entry or exit edge whose other end lies exactly on the bisector shrinks to a point
    length = 0
    m = (q + 1) % k
    while True:
        drop = (m == (q + 1) % k and status[(q + 1) % k] == _ON) or (m == p and status[(p - 1) % k] == _ON)
        if not drop:
            out[length] = nb[m]
            length += 1
        if m == p:
            break
        m = (m + 1) % k
    out[length] = j
    length += 1
    stats[2] += 1
    return length


@njit(cache=True)
def _vertex_circles(sites, i, nb, k, slack, circles):
    """Fill circles[m] = (x, y, r**2) for each finite vertex m (centre, and its distance to
    site i padded for rounding: PREFILTER_REL_PAD relative plus ``slack``); return the largest
    padded radius, squared (0 if there is no finite vertex)."""
    r2max = 0.0
    for m in range(k):
        a = nb[m]
        b = nb[(m + 1) % k]
        if a == AT_INFINITY or b == AT_INFINITY:
            continue
        x, y = circumcentre(sites[i, 0], sites[i, 1], sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1])
        dx = x - sites[i, 0]
        dy = y - sites[i, 1]
        r = np.sqrt(dx * dx + dy * dy) * (1.0 + PREFILTER_REL_PAD) + slack
        circles[m, 0] = x
        circles[m, 1] = y
        circles[m, 2] = r * r
        r2max = max(r2max, r * r)
    return r2max


@njit(cache=True)
def _reach(r2, slack):
    """Squared distance from site i beyond which a site is outside every vertex circle:
    (2 r + slack)**2 for the largest padded radius r, rounded up."""
    d = 2.0 * np.sqrt(r2) + slack
    return d * d * (1.0 + 1e-12)


@njit(cache=True)
def _cell(sites, i, sequence, seen, nb, out, status, circles, counters, stats, slack):
    """Neighbour list of cell i (written to nb); returns its length (AT_INFINITY included)."""
    n = sites.shape[0]
    # two first sites not collinear with i: the cell becomes a wedge, never a strip
    j1 = -1
    j2 = -1
    o = 0
    for t in range(sequence.shape[0] + n):
        j = sequence[t] if t < sequence.shape[0] else t - sequence.shape[0]
        if j == i or j == j1:
            continue
        if j1 < 0:
            j1 = j
            continue
        o = orient2d_counted(sites[i, 0], sites[i, 1], sites[j1, 0], sites[j1, 1], sites[j, 0], sites[j, 1], counters)
        if o != 0:
            j2 = j
            break
    if j2 < 0:
        raise RuntimeError("halfplane: all sites collinear with the cell's site")
    # the wedge: bisector a runs in from infinity, turns left into bisector b, out to infinity
    if o > 0:
        nb[0], nb[1] = j1, j2
    else:
        nb[0], nb[1] = j2, j1
    nb[2] = AT_INFINITY
    k = 3
    stats[0] += n - 1                          # every other site is clipped against
    stats[2] += 2
    seen[i] = i
    seen[j1] = i
    seen[j2] = i
    reach = _reach(_vertex_circles(sites, i, nb, k, slack, circles), slack)
    bounded = False
    prefiltered = 0
    xi = sites[i, 0]
    yi = sites[i, 1]
    for t in range(sequence.shape[0] + n):
        j = sequence[t] if t < sequence.shape[0] else t - sequence.shape[0]
        if seen[j] == i:
            continue
        seen[j] = i
        dx = sites[j, 0] - xi
        dy = sites[j, 1] - yi
        far = dx * dx + dy * dy > reach
        if far:
            prefiltered += 1
            if bounded:
                continue
        length = _clip(sites, i, j, nb, k, out, status, far, circles, counters, stats)
        if length < 0:
            continue
        for m in range(length):
            nb[m] = out[m]
        k = length
        bounded = True
        for m in range(k):
            if nb[m] == AT_INFINITY:
                bounded = False
        reach = _reach(_vertex_circles(sites, i, nb, k, slack, circles), slack)
    stats[1] += prefiltered
    return k


@njit(cache=True)
def cells(sites, order, counters):
    """Every cell's neighbour list, CCW; unbounded cells start right after the arc at infinity
    (their first neighbour's bisector comes in from infinity, the last goes out).

    Returns (ptr, neighbours, unbounded, stats): cell i is neighbours[ptr[i]:ptr[i + 1]].
    ``order`` is a spatial order of the sites (nearby sites are clipped first).
    """
    n = sites.shape[0]
    stats = np.zeros(len(STAT_NAMES), dtype=np.int64)
    position = np.empty(n, dtype=np.int64)
    for t in range(n):
        position[order[t]] = t
    seen = np.full(n, -1, dtype=np.int64)
    nb = np.empty(n + 2, dtype=np.int64)
    out = np.empty(n + 2, dtype=np.int64)
    status = np.empty(n + 2, dtype=np.int64)
    circles = np.empty((n + 2, 3), dtype=np.float64)
    sequence = np.empty(2 * NEAR_WINDOW, dtype=np.int64)
    magnitude = 0.0
    for t in range(n):
        magnitude = max(magnitude, abs(sites[t, 0]), abs(sites[t, 1]))
    slack = PREFILTER_ULPS * magnitude * 2.0 ** -52
    ptr = np.zeros(n + 1, dtype=np.int64)
    neighbours = np.empty(8 * n, dtype=np.int64)
    unbounded = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        # Hilbert neighbours of i first, nearest in the order first
        ls = 0
        pos = position[i]
        for w in range(1, NEAR_WINDOW + 1):
            if pos + w < n:
                sequence[ls] = order[pos + w]
                ls += 1
            if pos - w >= 0:
                sequence[ls] = order[pos - w]
                ls += 1
        k = _cell(sites, i, sequence[:ls], seen, nb, out, status, circles, counters, stats, slack)
        # store it rotated so that an unbounded cell's list ends at the arc at infinity
        start = 0
        for m in range(k):
            if nb[m] == AT_INFINITY:
                start = m + 1
                unbounded[i] = True
        size = k - 1 if unbounded[i] else k
        if ptr[i] + size > neighbours.shape[0]:
            grown = np.empty(2 * neighbours.shape[0] + size, dtype=np.int64)
            grown[:ptr[i]] = neighbours[:ptr[i]]
            neighbours = grown
        for m in range(size):
            neighbours[ptr[i] + m] = nb[(start + m) % k]
        ptr[i + 1] = ptr[i] + size
    return ptr, neighbours[:ptr[n]], unbounded, stats


@njit(cache=True)
def _glue(sites, ptr, neighbours, unbounded):
    """Turn independent cells into one edge list: vertices identified by site triple, then
    merged along edges whose two cells name their ends differently (cocircular sites).

    Returns (vertices, edge_sites, edge_vertices, merged) for :func:`vorobench.core.builder.assemble`.
    """
    n = sites.shape[0]
    H = ptr[n]
    owner = np.empty(H, dtype=np.int64)
    for i in range(n):
        for h in range(ptr[i], ptr[i + 1]):
            owner[h] = i
    # the vertex at the end of half-edge h (between neighbours[h] and the next one), as a
    # sorted triple key; -1 where h runs out to infinity
    end_key = np.full(H, -1, dtype=np.int64)
    for i in range(n):
        lo, hi = ptr[i], ptr[i + 1]
        for h in range(lo, hi):
            if h == hi - 1 and unbounded[i]:
                continue
            a = neighbours[h]
            b = neighbours[lo + (h - lo + 1) % (hi - lo)]
            x, y, z = i, a, b
            if x > y:
                x, y = y, x
            if y > z:
                y, z = z, y
            if x > y:
                x, y = y, x
            end_key[h] = (x * n + y) * n + z
    keys = np.unique(end_key[end_key >= 0])
    T = keys.shape[0]
    end_id = np.full(H, -1, dtype=np.int64)
    for h in range(H):
        if end_key[h] >= 0:
            end_id[h] = np.searchsorted(keys, end_key[h])
    start_id = np.empty(H, dtype=np.int64)
    for i in range(n):
        lo, hi = ptr[i], ptr[i + 1]
        for h in range(lo, hi):
            if h == lo and unbounded[i]:
                start_id[h] = -1
            else:
                start_id[h] = end_id[lo + (h - lo - 1) % (hi - lo)]
    # pair each half-edge with its twin in the neighbour's cell
    pair_key = np.empty(H, dtype=np.int64)
    for h in range(H):
        a, b = owner[h], neighbours[h]
        pair_key[h] = (min(a, b) * n + max(a, b)) * 2 + (1 if a > b else 0)
    by_pair = np.argsort(pair_key)
    if H % 2:
        raise RuntimeError("halfplane: cells disagree about their common edges (odd count)")
    parent = np.arange(T)
    E = H // 2
    edge_sites = np.empty((E, 2), dtype=np.int64)
    edge_ends = np.empty((E, 2), dtype=np.int64)
    for e in range(E):
        h1 = by_pair[2 * e]
        h2 = by_pair[2 * e + 1]
        if pair_key[h1] // 2 != pair_key[h2] // 2 or pair_key[h1] % 2 != 0 or pair_key[h2] % 2 != 1:
            raise RuntimeError("halfplane: two cells disagree about their common edge")
        # h1 in cell a < b, h2 in cell b: h2 runs backwards along h1
        for u, v in ((start_id[h1], end_id[h2]), (end_id[h1], start_id[h2])):
            if (u < 0) != (v < 0):
                raise RuntimeError("halfplane: an edge is a ray in one cell and bounded in the other")
            if u >= 0:
                ru = find(parent, u)
                rv = find(parent, v)
                if ru != rv:
                    parent[max(ru, rv)] = min(ru, rv)
        edge_sites[e, 0] = owner[h1]
        edge_sites[e, 1] = neighbours[h1]
        edge_ends[e, 0] = start_id[h1]
        edge_ends[e, 1] = end_id[h1]
    # the three smallest sites of each merged vertex
    low = np.full((T, 3), n, dtype=np.int64)
    merged = 0
    for t in range(T):
        r = find(parent, t)
        if r != t:
            merged += 1
        key = keys[t]
        trio = (key // (n * n), (key // n) % n, key % n)
        for s in trio:
            if s == low[r, 0] or s == low[r, 1] or s == low[r, 2]:
                continue
            if s < low[r, 0]:
                low[r, 2] = low[r, 1]
                low[r, 1] = low[r, 0]
                low[r, 0] = s
            elif s < low[r, 1]:
                low[r, 2] = low[r, 1]
                low[r, 1] = s
            elif s < low[r, 2]:
                low[r, 2] = s
    vid = np.full(T, -1, dtype=np.int64)
    nv = 0
    for t in range(T):
        if parent[t] == t:
            vid[t] = nv
            nv += 1
    vertices = np.empty((nv, 2), dtype=np.float64)
    for t in range(T):
        if parent[t] == t:
            a, b, c = low[t, 0], low[t, 1], low[t, 2]
            x, y = circumcentre(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1])
            vertices[vid[t], 0] = x
            vertices[vid[t], 1] = y
    edge_vertices = np.empty((E, 2), dtype=np.int64)
    for e in range(E):
        for side in range(2):
            t = edge_ends[e, side]
            edge_vertices[e, side] = -1 if t < 0 else vid[find(parent, t)]
        if edge_vertices[e, 0] >= 0 and edge_vertices[e, 0] == edge_vertices[e, 1]:
            raise RuntimeError("halfplane: an edge has both ends at the same vertex")
    return vertices, edge_sites, edge_vertices, merged


def supports(sites: NDArray[np.float64]) -> Optional[str]:
    """None if the sites can be processed, else why not: too many, or magnitudes that no
    power of two brings into the predicates' exact range (``run`` scales the rest)."""
    _, problem = exact_range_sites(sites)
    if problem:
        return problem
    if sites.shape[0] > MAX_SITES:
        return f"more than {MAX_SITES} sites (vertex keys pack a site triple in an int64)"
    return None


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites``, one half-plane intersection per cell."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    reason = supports(sites)
    if reason is not None:
        raise ValueError(f"halfplane cannot build this diagram: {reason}")
    if n <= 1:
        return Diagram.empty(sites)
    if all_collinear(sites):
        if stats is not None:
            stats.update(collinear=1)
        return collinear_diagram(sites)
    counters = np.zeros(4, dtype=np.int64)
    order = np.argsort(hilbert_keys(sites, HILBERT_BITS), kind="stable")
    ptr, neighbours, unbounded, counts = cells(sites, order, counters)
    vertices, edge_sites, edge_vertices, merged = _glue(sites, ptr, neighbours, unbounded)
    if stats is not None:
        stats.update(zip(STAT_NAMES, (int(c) for c in counts)))
        stats.update(orient2d_calls=int(counters[ORIENT_CALLS]), orient2d_exact=int(counters[ORIENT_EXACT]),
                     incircle_calls=int(counters[INCIRCLE_CALLS]), incircle_exact=int(counters[INCIRCLE_EXACT]),
                     merged_vertices=int(merged))
    return assemble(sites, vertices, edge_sites, edge_vertices)


def warmup() -> None:
    """Compile the kernels (or load numba's cache) on tiny inputs covering every code path."""
    rng = np.random.default_rng(0)
    build(rng.random((30, 2)))
    build(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [0.5, 0.5]]))
    build(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))


IMPLEMENTATION = Implementation(
    name="halfplane",
    description="naive half-plane intersection per cell (the definition; oracle), exact incircle clipping",
    complexity="O(n^2)",
    build=build,
    exact=True,
    warmup=warmup,
    supports=supports,
    kind="own",
)
