"""The naive O(n^2) Voronoi and power-diagram construction: each cell is the intersection of n - 1 half-planes.

CONTRACT
--------
Why it is the oracle: it follows the definition directly. The cell of site i is the set of
points whose power |x - p_i|^2 - w_i is at most every other site's (w = 0 for the ordinary
diagram: points at least as close to i as to every other site), i.e. the intersection of the
half-planes bounded by the power bisectors of i and each other site j. A power bisector is
the line pow_i = pow_j, perpendicular to p_j - p_i, through the midpoint only when w_i = w_j;
i's half-plane is the side opposite to the direction p_j - p_i. Each cell is computed on its
own, from the whole plane, with no event queue, beach line, triangulation or neighbourhood
structure, so it shares no idea (and no bug) with the sweep or with the incremental
construction; cells are glued together only at the end.
Complexity: O(n^2) clips (every ordered pair), each O(cell size) in the worst case (exactly
cocircular sites: every test exact); with the filters below most clips cost a distance
comparison (uniform, 2 * 10^4 sites: 4 * 10^8 clips, 3 * 10^5 exact incircle calls).
Input: prepared sites (distinct, finite float64), any n >= 0, and for a power diagram one
finite weight per site; coordinates (and weights) within the range where
:mod:`vorobench.core.predicates` is exact.
Representation of a cell: the cyclic list of the sites whose bisectors bound it, in
counter-clockwise order, plus a marker for the arc at infinity if it is unbounded, so an
unbounded cell is an open chain with a ray at each end (no bounding box, no fake edges).
Its vertex between consecutive neighbours a, b is the point of equal power of (i, a, b)
(the circumcentre without weights), identified by that site triple, never by coordinates;
(i, a, b) is counter-clockwise, because cell i turns left there from the edge along
perp(a - i) into the edge along perp(b - i), whatever the weights.
Exact decisions: clipping cell i by the bisector of (i, j) cuts off vertex v = (i, a, b)
exactly when pow_j(v) < pow_i(v), i.e. when j's lifted point (x, y, x^2 + y^2 - w) lies
strictly below the plane through the lifted i, a, b: ``power_test(i, a, b, j) > 0`` (for
ordinary diagrams ``incircle(i, a, b, j) > 0``: j strictly inside the circle through i, a, b).
A ray along the bisector of (i, q) runs to infinity in direction perp(q - i); along any
direction u, pow_i - pow_j grows at the rate 2 u . (p_j - p_i), so the far end lies on j's
side exactly when perp(q - i) . (p_j - p_i) = ``orient2d(i, q, j)`` is > 0 (outgoing ray;
< 0 for the incoming one, which arrives from -perp(q - i)): the weights only move bisectors,
never turn them, so the rule is the ordinary one. When the ray is parallel to the new
bisector (== 0) pow_i - pow_j is constant along it and the ray shares the fate of its finite
vertex. A vertex exactly on the bisector (test == 0) is kept and the bisector adds no edge
there, so cells never hold zero-length edges. The first two clips use two sites not
collinear with i: their bisectors are not parallel (weights never make them so), so the cell
starts as a wedge, and a region inside a wedge is never a strip (all-collinear input gives
parallel lines directly, :func:`~vorobench.core.builder.collinear_diagram`).
New with unequal weights (neither case can arise when the weights are equal, where every
test above is the ordinary one): a cell may not contain its own site, and it may be EMPTY (a
*hidden* site): when no vertex and no end at infinity stays strictly on i's side, what is
left has no interior; clipping stops, the site gets no edge and appears in no ridge. A cell
reduced to a segment or a point counts as empty too (its lifted point lies on the lower
hull without being a corner of it), the convention of the weighted collinear diagram. And
two sites a, j collinear with i on the same side of it can have the same bisector with i
(their three lifted points collinear; the middle one is hidden): when no vertex is cut but
an edge lies on the new bisector (both its ends on it), the edge goes to whichever of a, j
is farther from i (exact coordinate comparisons), the one that owns the other side.
Filters (speed only, never a decision): vertex v is cut exactly when pow_j(v) < pow_i(v).
Each vertex is computed once in floats (circumcentre / power centre from i; its error is
far below the padding), and its distance D to site i is padded to r = D (1 + theta) + a few
ulps of the coordinates (theta = 1e-6), so r >= |v* - p_i| + delta for the exact vertex v*
and the rounding delta = |v - v*| <= r - D.
* Ordinary diagram: a site clearly outside the circle of radius r about v leaves v strictly
  kept without an incircle call, like the float stage of the predicates; a site farther
  from i than twice the largest padded radius is outside every circle
  (|v - j| >= |j - i| - |v - i| > |v - i|).
* Power diagram (rewritten for power distance, not disabled): pow_i(v*) <= r^2 - w_i, and
  |v* - p_j|^2 >= |v - p_j|^2 - 2 |v - p_j| delta >= |v - p_j|^2 (1 - theta) - delta^2 / theta,
  so v is strictly kept when |v - p_j|^2 (1 - theta) - w_j > T_v = r^2 + delta^2 / theta - w_i
  (computed with (1 - 2 theta), w_j rounded up and T_v padded for the roundings). Far sites:
  for every vertex |v* - p_j| >= d - R (d = |p_j - p_i|, R the largest padded radius), and
  (d - R)^2 >= d^2 / 2 - R^2 (for any d), so d^2 - 2 w_j > 2 (R^2 + max T_v) keeps every
  vertex. The bound keeps j's own weight (precomputed w_j rounded up: one multiply-subtract
  more per pair, no square root): a heavy site is never far, a very light one often is.
  With w = 0 both are the ordinary filters, slightly wider. Measured on 10^4 uniform sites
  (radii weights): 89% of the pairs are far and 1.6% of the vertex tests reach the power
  test (ordinary: 99% and 1.5% reach incircle); with equal weights the same pairs are far
  and 0.2% more vertex tests reach the power test than reach incircle without weights.
A far site is skipped for a bounded cell; for an unbounded one only the two ends at
infinity are tested (exact orient2d). Whatever the filters cannot settle goes to the exact
tests. Sites near i in Hilbert order are clipped first so cells shrink fast.
Gluing: a vertex is first the sorted site triple of its cell's own bisectors. With 4 or more
cocircular sites (lifted points coplanar: a corner of a lower-hull facet with 4 or more
corners), different cells see the same point as different triples; the two cells of each
edge must agree on its ends, so triples are merged along edges (union-find) into one vertex
of degree >= 4. Its coordinates come from the three smallest site ids on it (corners of one
facet: never collinear), the rule the incremental construction uses too (shared
``circumcentre`` / ``power_centre`` formula, identical bit for bit when the weights are equal:
arithmetic only, no decision), so the exact constructions agree bit for bit. Two cells that
disagree about a common edge raise an error instead of producing a diagram.
Counters: clips (sites clipped against: n - 1 per cell, fewer for an empty one),
prefiltered, cuts, vertex_tests, orient2d and incircle calls / exact fallbacks,
merged_vertices; a power diagram counts power_test calls / exact fallbacks in place of
incircle's (the same float-filter-then-exact split), plus ``hidden`` (empty cells) and
``relabelled`` (edges handed to a farther site with the same bisector).
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from impls.base import Implementation
from vorobench.core.builder import assemble, collinear_diagram
from vorobench.core.circumcentre import circumcentre, power_centre
from vorobench.core.diagram import Diagram
from vorobench.core.hull import all_collinear
from vorobench.core.predicates import (
    INCIRCLE_CALLS,
    INCIRCLE_EXACT,
    N_POWER_COUNTERS,
    ORIENT_CALLS,
    ORIENT_EXACT,
    POWER_TEST_CALLS,
    POWER_TEST_EXACT,
    incircle_counted,
    orient2d_counted,
    power_test_counted,
)
from vorobench.core.read_only import read_only
from vorobench.core.scaling import check_weight_range, exact_range_sites
from vorobench.core.spatial_order import HILBERT_BITS, hilbert_keys
from vorobench.core.union_find import find

__all__ = ["build", "build_weighted", "cells", "supports", "IMPLEMENTATION", "AT_INFINITY", "MAX_SITES"]

#: Marker in a cell's cyclic neighbour list for the arc at infinity of an unbounded cell.
AT_INFINITY = -1
#: Sites clipped first: this many on each side of i in Hilbert order.
NEAR_WINDOW = 24
#: Padding of the prefilter's radius: relative, and in ulps of the largest coordinate. The
#: relative one is also the theta of the power filter's bound 2 a b <= theta a^2 + b^2 / theta.
PREFILTER_REL_PAD = 1e-6
PREFILTER_ULPS = 64.0
#: Relative padding of weights and power thresholds in the power filters (covers their roundings).
WEIGHT_PAD = 1e-10
#: Operation counts returned by the cell kernel (the predicate counters come separately);
#: the last two are reported for power diagrams only.
#: (prefiltered: no exact test needed)
STAT_NAMES = ("clips", "prefiltered", "cuts", "vertex_tests", "hidden", "relabelled")
ORDINARY_STATS = 4

#: Vertices are keyed by their sorted site triple packed in one int64: n**3 < 2**63.
MAX_SITES = 2_000_000

_CUT, _ON, _KEPT = 1, 0, -1
_AT_END = 2                     # status placeholder of an end at infinity, decided second
#: _clip's results besides a new length: the bisector changes nothing, empties the cell, or
#: contains an edge (nothing cut; :func:`_relabel` decides who owns the edge).
_UNCHANGED, _EMPTY, _ON_EDGE = -1, 0, -2


@njit(cache=True)
def _vertex_status(sites, weights, i, a, b, j, counters):
    """+1 if the vertex (i, a, b) lies strictly on j's side of the bisector, 0 on it, -1 on i's side."""
    if weights is not None:
        return power_test_counted(sites[i, 0], sites[i, 1], weights[i], sites[a, 0], sites[a, 1], weights[a],
                                  sites[b, 0], sites[b, 1], weights[b], sites[j, 0], sites[j, 1], weights[j],
                                  counters)
    return incircle_counted(sites[i, 0], sites[i, 1], sites[a, 0], sites[a, 1],
                            sites[b, 0], sites[b, 1], sites[j, 0], sites[j, 1], counters)


@njit(cache=True)
def _farther(sites, i, a, j):
    """Whether j lies beyond a seen from i, for j on the ray from i through a (exact comparisons)."""
    c = 0 if sites[a, 0] != sites[i, 0] else 1
    if sites[a, c] > sites[i, c]:
        return sites[j, c] > sites[a, c]
    return sites[j, c] < sites[a, c]


@njit(cache=True)
def _relabel(sites, i, j, nb, k, out, status, counters, stats):
    """No vertex is cut and an edge lies on the bisector of (i, j) (its two ends on it): i, the
    edge's site a and j are collinear with the same bisector, and the edge goes to the farther
    of a, j (the middle one is hidden). Writes the list to ``out``; returns its length or
    _UNCHANGED. (Kept out of :func:`_clip`: inlined there it slowed the ordinary build by a third.)"""
    for m in range(k):
        if status[m] != _ON or status[(m - 1) % k] != _ON:
            continue
        a = nb[m]
        if a == AT_INFINITY:
            raise RuntimeError("halfplane: both rays of a cell lie on one bisector")
        o = orient2d_counted(sites[i, 0], sites[i, 1], sites[a, 0], sites[a, 1], sites[j, 0], sites[j, 1], counters)
        if o != 0:
            raise RuntimeError("halfplane: an edge lies on the bisector of a site not collinear with its own")
        if not _farther(sites, i, a, j):
            return _UNCHANGED
        for t in range(k):
            out[t] = nb[t]
        out[m] = j
        stats[5] += 1
        return k
    return _UNCHANGED


@njit(cache=True)
def _clip(sites, weights, i, j, nb, k, out, status, far, circles, w_up, counters, stats):
    """Clip the cell nb[:k] (cyclic, CCW, AT_INFINITY marks the arc at infinity) by the
    bisector of (i, j). Writes the new list into ``out``; returns its length, _UNCHANGED if
    the bisector changes nothing, _EMPTY if it leaves no interior (power diagrams only).
    ``far``: j is known to be too far to cut any finite vertex (see the prefilter), so only the
    ends at infinity are tested. ``circles[m]``: centre of vertex m and the threshold of the
    float filter of its test (padded squared radius; for power diagrams the bound T_v on the
    power of the exact vertex); ``w_up``: weights rounded up by WEIGHT_PAD."""
    cut = 0
    on = 0
    for m in range(k):
        a = nb[m]
        b = nb[(m + 1) % k]
        if a == AT_INFINITY or b == AT_INFINITY:
            status[m] = _AT_END                # an end at infinity: decided below
            continue
        if far:
            status[m] = _KEPT
            continue
        stats[3] += 1
        dx = sites[j, 0] - circles[m, 0]
        dy = sites[j, 1] - circles[m, 1]
        if w_up is not None:
            if (dx * dx + dy * dy) * (1.0 - 2.0 * PREFILTER_REL_PAD) - w_up[j] > circles[m, 2]:
                status[m] = _KEPT              # clearly of larger power than i at the vertex
                continue
        elif (dx * dx + dy * dy) * (1.0 - 1e-12) > circles[m, 2]:
            status[m] = _KEPT                  # clearly outside the vertex's circle
            continue
        s = _vertex_status(sites, weights, i, a, b, j, counters)
        status[m] = s
        if s == _CUT:
            cut += 1
        elif s == _ON:
            on += 1
    for m in range(k):
        if status[m] != _AT_END:
            continue
        if nb[(m + 1) % k] == AT_INFINITY:     # outgoing end: after nb[m], along perp(nb[m] - i)
            q = nb[m]
            o = orient2d_counted(sites[i, 0], sites[i, 1], sites[q, 0], sites[q, 1], sites[j, 0], sites[j, 1], counters)
            s = _CUT if o > 0 else (_KEPT if o < 0 else status[(m - 1) % k])
        else:                                  # incoming end: before nb[m + 1]
            q = nb[(m + 1) % k]
            o = orient2d_counted(sites[i, 0], sites[i, 1], sites[q, 0], sites[q, 1], sites[j, 0], sites[j, 1], counters)
            s = _CUT if o < 0 else (_KEPT if o > 0 else status[(m + 1) % k])
        status[m] = s
        if s == _CUT:
            cut += 1
        elif s == _ON:
            on += 1
    if cut + on == k:                          # nothing strictly on i's side
        if weights is not None:
            return _EMPTY
        raise RuntimeError("halfplane: a bisector cut off the whole cell")
    if cut == 0:
        if on < 2:
            return _UNCHANGED
        for m in range(k):
            if status[m] == _ON and status[(m - 1) % k] == _ON:
                return _ON_EDGE                # an edge lies on the bisector: see _relabel
        return _UNCHANGED
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
    if ((status[(q + 1) % k] == _ON and status[(q + 2) % k] == _ON)
            or (status[(p - 1) % k] == _ON and status[(p - 2) % k] == _ON)):
        # an edge on the bisector puts the whole cell on one side of it: nothing both cut and kept
        raise RuntimeError("halfplane: an edge lies on a bisector that cuts the cell")
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
def _vertex_circles(sites, weights, i, nb, k, slack, circles):
    """Fill circles[m] = (x, y, threshold) for each finite vertex m and return the squared
    distance beyond which a site is "far" (see the module docstring).

    Ordinary diagram: threshold = r**2, r = the vertex's distance to site i padded for rounding
    (PREFILTER_REL_PAD relative plus ``slack``); far: beyond (2 R + slack)**2, R the largest r.
    Power diagram: threshold = T_v >= pow_i(exact vertex) + delta**2 / theta; far: sites with
    |p_j - p_i|**2 - 2 w_j beyond 2 (R**2 + max T_v). Returns +inf with no finite vertex."""
    r2max = 0.0
    tmax = -np.inf
    for m in range(k):
        a = nb[m]
        b = nb[(m + 1) % k]
        if a == AT_INFINITY or b == AT_INFINITY:
            continue
        if weights is not None:
            x, y = power_centre(sites[i, 0], sites[i, 1], weights[i], sites[a, 0], sites[a, 1], weights[a],
                                sites[b, 0], sites[b, 1], weights[b])
        else:
            x, y = circumcentre(sites[i, 0], sites[i, 1], sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1])
        dx = x - sites[i, 0]
        dy = y - sites[i, 1]
        d = np.sqrt(dx * dx + dy * dy)
        r = d * (1.0 + PREFILTER_REL_PAD) + slack
        circles[m, 0] = x
        circles[m, 1] = y
        if weights is not None:
            e = r - d                          # >= the rounding delta of the centre, generously
            t = r * r + e * e / PREFILTER_REL_PAD - weights[i]
            t += WEIGHT_PAD * (r * r + abs(weights[i]))
            circles[m, 2] = t
            tmax = max(tmax, t)
        else:
            circles[m, 2] = r * r
        r2max = max(r2max, r * r)
    if weights is not None:
        if tmax == -np.inf:
            return np.inf
        return 2.0 * (r2max + tmax) + WEIGHT_PAD * (r2max + abs(tmax))
    d = 2.0 * np.sqrt(r2max) + slack
    return d * d * (1.0 + 1e-12)


@njit(cache=True)
def _cell(sites, weights, i, sequence, seen, nb, out, status, circles, w_up, counters, stats, slack):
    """Neighbour list of cell i (written to nb); returns its length (AT_INFINITY included),
    0 for an empty cell (a hidden site)."""
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
    stats[2] += 2
    seen[i] = i
    seen[j1] = i
    seen[j2] = i
    reach = _vertex_circles(sites, weights, i, nb, k, slack, circles)
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
        if w_up is not None:
            far = (dx * dx + dy * dy) * (1.0 - 1e-12) - 2.0 * w_up[j] > reach
        else:
            far = dx * dx + dy * dy > reach
        if far:
            prefiltered += 1
            if bounded:
                continue
        length = _clip(sites, weights, i, j, nb, k, out, status, far, circles, w_up, counters, stats)
        if length == _ON_EDGE:
            length = _relabel(sites, i, j, nb, k, out, status, counters, stats)
        if length == _UNCHANGED:
            continue
        if length == _EMPTY:
            k = 0
            break
        for m in range(length):
            nb[m] = out[m]
        k = length
        bounded = True
        for m in range(k):
            if nb[m] == AT_INFINITY:
                bounded = False
        reach = _vertex_circles(sites, weights, i, nb, k, slack, circles)
    stats[1] += prefiltered
    if k == 0:
        # a hidden site: clipping stopped early; count the sites clipped against so far
        stats[4] += 1
        for j in range(n):
            if seen[j] == i and j != i:
                stats[0] += 1
    else:
        stats[0] += n - 1                      # every other site is clipped against
    return k


@njit(cache=True)
def _cells(sites, weights, w_up, order, counters):
    """Kernel of :func:`cells`. ``weights``: None for the ordinary diagram (numba compiles that
    case apart, with the power branches pruned); ``w_up``: the weights rounded up by WEIGHT_PAD."""
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
        k = _cell(sites, weights, i, sequence[:ls], seen, nb, out, status, circles, w_up, counters,
                  stats, slack)
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


def cells(sites: NDArray[np.float64], order: NDArray[np.int64], counters: NDArray[np.int64],
          weights: Optional[NDArray[np.float64]] = None):
    """Every cell's neighbour list, CCW; unbounded cells start right after the arc at infinity
    (their first neighbour's bisector comes in from infinity, the last goes out); a hidden
    site's list is empty.

    Returns (ptr, neighbours, unbounded, stats): cell i is neighbours[ptr[i]:ptr[i + 1]].
    ``order`` is a spatial order of the sites (nearby sites are clipped first; any permutation
    gives the same cells). ``weights``: the power diagram's (``counters`` then needs
    N_POWER_COUNTERS entries, for the power tests); None for the ordinary diagram.
    """
    order = np.ascontiguousarray(order, dtype=np.int64)
    sites = read_only(np.ascontiguousarray(sites, dtype=np.float64))
    if weights is None:
        return _cells(sites, None, None, order, counters)
    if counters.shape[0] < N_POWER_COUNTERS:
        raise ValueError(f"counters must have {N_POWER_COUNTERS} entries for a power diagram")
    weights = read_only(np.ascontiguousarray(weights, dtype=np.float64))
    return _cells(sites, weights, _rounded_up(weights), order, counters)


def _rounded_up(weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """Each weight plus WEIGHT_PAD of its magnitude: above it even after a few roundings."""
    return weights + WEIGHT_PAD * np.abs(weights)


@njit(cache=True)
def _glue(sites, weights, ptr, neighbours, unbounded):
    """Turn independent cells into one edge list: vertices identified by site triple, then
    merged along edges whose two cells name their ends differently (cocircular sites, coplanar
    lifted points). A hidden site has no half-edge; ``weights``: None for the ordinary diagram.

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
            if weights is not None:
                x, y = power_centre(sites[a, 0], sites[a, 1], weights[a], sites[b, 0], sites[b, 1], weights[b],
                                    sites[c, 0], sites[c, 1], weights[c])
            else:
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


def _check(sites: ArrayLike) -> NDArray[np.float64]:
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    reason = supports(sites)
    if reason is not None:
        raise ValueError(f"halfplane cannot build this diagram: {reason}")
    return sites


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites``, one half-plane intersection per cell."""
    sites = read_only(_check(sites))          # one kind of array for the kernels, wherever it came from
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites)
    if all_collinear(sites):
        if stats is not None:
            stats.update(collinear=1)
        return collinear_diagram(sites)
    counters = np.zeros(4, dtype=np.int64)
    order = np.argsort(hilbert_keys(sites, HILBERT_BITS), kind="stable")
    ptr, neighbours, unbounded, counts = _cells(sites, None, None, order, counters)
    vertices, edge_sites, edge_vertices, merged = _glue(sites, None, ptr, neighbours, unbounded)
    if stats is not None:
        stats.update(zip(STAT_NAMES[:ORDINARY_STATS], (int(c) for c in counts[:ORDINARY_STATS])))
        stats.update(orient2d_calls=int(counters[ORIENT_CALLS]), orient2d_exact=int(counters[ORIENT_EXACT]),
                     incircle_calls=int(counters[INCIRCLE_CALLS]), incircle_exact=int(counters[INCIRCLE_EXACT]),
                     merged_vertices=int(merged))
    return assemble(sites, vertices, edge_sites, edge_vertices)


def build_weighted(sites: NDArray[np.float64], weights: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The power diagram of prepared ``sites`` with ``weights`` (power |x - p_i|^2 - w_i), one
    intersection of power half-planes per cell; hidden sites get no half-edge."""
    sites = read_only(_check(sites))
    n = sites.shape[0]
    weights = read_only(np.ascontiguousarray(weights, dtype=np.float64).reshape(-1))
    if weights.shape != (n,):
        raise ValueError(f"weights has shape {weights.shape}, there are {n} sites")
    if not np.isfinite(weights).all():
        raise ValueError("weights must be finite")
    check_weight_range(sites, weights)
    if n <= 1:
        return Diagram.empty(sites, weights)
    if all_collinear(sites):
        if stats is not None:
            stats.update(collinear=1)
        return collinear_diagram(sites, weights)
    counters = np.zeros(N_POWER_COUNTERS, dtype=np.int64)
    order = np.argsort(hilbert_keys(sites, HILBERT_BITS), kind="stable")
    ptr, neighbours, unbounded, counts = _cells(sites, weights, _rounded_up(weights), order, counters)
    vertices, edge_sites, edge_vertices, merged = _glue(sites, weights, ptr, neighbours, unbounded)
    if stats is not None:
        stats.update(zip(STAT_NAMES, (int(c) for c in counts)))
        stats.update(orient2d_calls=int(counters[ORIENT_CALLS]), orient2d_exact=int(counters[ORIENT_EXACT]),
                     power_test_calls=int(counters[POWER_TEST_CALLS]),
                     power_test_exact=int(counters[POWER_TEST_EXACT]), merged_vertices=int(merged))
    return assemble(sites, vertices, edge_sites, edge_vertices, weights=weights)


def build_disks(centres: NDArray[np.float64], radii: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The diagram of the disks: :func:`impls.halfplane_disks.build` (exact, in rationals)."""
    from impls import halfplane_disks        # rationals and their float filters: loaded for disks only

    return halfplane_disks.build(centres, radii, stats)


def warmup() -> None:
    """Compile the kernels (or load numba's cache) on tiny inputs covering every code path."""
    rng = np.random.default_rng(0)
    pts = rng.random((30, 2))
    build(pts)
    build(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [0.5, 0.5]]))
    build(np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))
    build_weighted(pts, 0.05 * rng.random(30))
    # a lattice lifted onto one plane: hidden sites, coincident bisectors, a vertex of degree 4
    grid = np.stack(np.meshgrid(np.arange(3.0), np.arange(3.0)), axis=-1).reshape(-1, 2)
    build_weighted(grid, (grid * grid).sum(axis=1))


IMPLEMENTATION = Implementation(
    name="halfplane",
    description="naive half-plane intersection per cell (the definition; oracle), exact incircle / power-test clipping; "
                "disks: clipping by bisector branches in rationals",
    complexity="O(n^2)",
    build=build,
    exact=True,
    warmup=warmup,
    supports=supports,
    kind="own",
    build_weighted=build_weighted,
    build_apollonius=build_disks,
)
