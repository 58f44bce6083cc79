"""Fortune's sweep line: exact, degenerate-proof, compiled with numba, O(n log n).

CONTRACT
--------
Complexity: O(n log n) time (sorting the sites, O(n) events each costing O(log n) in the
beach-line treap and the event heap, both expected/worst-case logarithmic), O(n) memory.

Input: prepared sites (distinct, finite float64), any n >= 0. The predicates are exact as
long as their float filters and expansion products neither overflow nor underflow: site
coordinates of magnitude 0 or in [2**-100, 2**100) (about [7.9e-31, 1.3e30]; the degree-6
circle tops are the binding ones), where ``Implementation.run`` scales every input by a
power of two (:mod:`vorobench.core.scaling`); the degree-20 comparison of two circle events
rescales its differences by a power of two itself. Offsets of 1e9 with spacing 1e-3, and
spacing 1e-9 near 0, are well inside.

Structure (three separate files, as in Boost.Polygon's builder / predicates / output):
* ``sweep.py``: the sweep. Sites are pre-sorted by (y, x); the sweep line moves upward. A
  site event finds the arc above the new site (first by a walk of at most two arcs from the
  arc of the recent site nearest in x, while such walks keep succeeding: lattice rows and
  the two ends of a convex curve; else from the treap's root), splits it into (q, s, q),
  starts one edge traced by the two new breakpoints, cancels the split arc's circle event and checks the
  two new triples. A circle event puts a vertex at the circumcentre, removes the vanishing
  arc, closes the two edges its breakpoints traced, starts the edge of the new breakpoint,
  cancels the neighbours' stale events (false alarms) and checks the two new triples.
* ``beach_line.py``: the arcs in a treap over one int32 array (insert next to an arc,
  delete, search), keyed by breakpoints evaluated at the current sweep position.
* ``event_queue.py``: circle events in an indexed binary heap (removal of cancelled events
  in O(log n); a removal's hole goes down to a leaf, one comparison per level, before the
  last event settles into it); site events are the pre-sorted array.
The DCEL is filled by the shared :func:`vorobench.core.builder.assemble` from the recorded edges
(a, b, start, end); unbounded edges keep -1 (no clipping box).

Exactness: every decision is a predicate of ``vorobench.core.predicates``, float-filtered with an
exact expansion fallback: arc location (``breakpoint_side``: sign of a degree-3 polynomial
plus exact coordinate comparisons saying which intersection of the two parabolas is meant),
circle-event existence (``orient2d`` of the three sites: the breakpoints converge iff the
triple turns counter-clockwise), event order (tops of two circumcircles, A + sqrt(B) against
C + sqrt(D), decided by squaring with sign analysis in ``circle_events_order_exact``, after
float filters, an exact refinement of each event's top computed once, and exact keys
cy + sqrt(r2) that settle lattice ties cheaply; see ``event_queue``; circle against site:
``circle_event_vs_site_exact``). Vertex coordinates are rounded circumcentres (not exact;
the combinatorics do not depend on them).

Degenerate cases, and why they come out right:
* n = 0, 1: no edges. n = 2: one full line (both ends -1).
* Several sites on the first sweep position: all sites with the lowest y start the beach
  line in x order, separated by vertical bisectors from infinity. Later sites on a common
  y: a site on the sweep line has a vertical-ray arc, its breakpoints are at its x, and
  sites on one y are taken in increasing x, so the search never lands on a zero-width arc.
* All sites collinear (horizontal, vertical, diagonal): no triple turns, no circle event;
  every edge keeps both ends at infinity, giving n - 1 parallel lines.
* A site exactly below a breakpoint (``breakpoint_side`` = 0): the site goes to the right
  arc, splitting it at its left end; the zero-width piece's circle event is at the current
  sweep position and fires at once (circle events go before sites on ties), so the vertex
  is created where the three cells meet.
* k >= 4 cocircular sites: their circle events tie exactly; each removes one arc and
  creates one degree-3 vertex at the common centre, so the degree-k vertex comes out as
  k - 2 vertices joined by zero-length edges (allowed by the contract; ``compare``
  normalises it). Ties between circle events go to the older event.
* Iteration caps: every loop is bounded (search depth, number of events); exceeding a cap,
  or an inconsistent search, raises RuntimeError instead of hanging.

Stats (machine independent): site_events, circle_events (scheduled), false_alarms,
vertices, max_beach_line, breakpoint_tests / breakpoint_exact, event_comparisons /
event_comparisons_exact, exact_keys (events refined in exact arithmetic), orient2d_calls /
orient2d_exact.

Weighted sites (``build_weighted``, power diagrams): the weighted sweep of docs/power.md, in
``power_sweep.py`` (events: activations, probes for each pending site's first contact, circle
events at power centres), deciding through ``power_predicates.py`` (float and interval filters) and
``power_exact.py`` (the exact stage, in the rationals of ``power_reference.py``, the
specification). Equal weights go to the ordinary sweep (its diagram bit for bit). Stats add
weighted_filtered / weighted_exact, probes, contacts_in_arc / contacts_at_vertex,
never_entered, first_row, merged_vertices and hidden_sites.

Disks (``build_disks``, Apollonius diagrams): the sweep with each directrix raised by its disk's
radius (docs/apollonius.md), compiled in ``disk_sweep.py`` with float filters
(``vorobench/core/predicates/apollonius_filter.py``) and its exact stage in ``disk_exact.py``
(the rationals of ``apollonius_sweep.py``, the specification). Hidden disks are found first
(``hidden_disks``) and never enter; equal radii go to the ordinary sweep. Stats: breakpoint_tests / breakpoint_exact,
event_comparisons / event_comparisons_exact, circle_tests / circle_tests_exact, site_events,
circle_events, false_alarms, vertices, merged_vertices, same_point_exact, max_beach_line and
hidden_sites.

Speed notes: the sweep runs on a copy of the sites in event order (memory locality; ids are
mapped back after the DCEL is built), removed arcs' and events' rows are reused, and the
heap and treap kernels are inlined into the sweep (numba reference-counts arrays passed to
non-inlined calls; that was a fifth of the run time). numba caches each file by its own
content: after editing ``vorobench/core/predicates/__init__.py`` or a kernel module here, delete
``impls/fortune/__pycache__/*.nb[ic]`` so the inlined copies are recompiled.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numpy.typing import NDArray

from impls.base import Implementation
from numba import njit

from impls.fortune import apollonius_sweep, disk_exact, disk_sweep, power_sweep
from impls.fortune.power_exact import exact_context
from impls.fortune.slabs import slabs
from impls.fortune.sweep import COUNTER_NAMES, N_COUNTERS, OK, sweep
from vorobench.core.circumcentre import power_centre
from vorobench.core.builder import assemble
from vorobench.core.diagram import Diagram, InvalidDiagramError
from vorobench.core.half_edges import link_edges
from vorobench.core.hidden_disks import hidden_disks
from vorobench.core.predicates.apollonius import rational

__all__ = ["build", "build_weighted", "warmup", "IMPLEMENTATION"]

_ERRORS = {1: "the search for the arc above a site left the beach line",
           2: "an internal table ran out of capacity",
           3: "the event loop exceeded its iteration cap",
           4: "a circle event's arc lost a neighbour"}

_WEIGHTED_ERRORS = {power_sweep.ERR_STATE: "a probe found its bound above the beach line or under a site it watched, "
                                           "or an arc lost a neighbour",
                    power_sweep.ERR_ITERATIONS: "the event loop exceeded its iteration cap"}

#: The weighted sweep's first pool of watch-list rows, per site (it doubles when full: a site
#: watches one or two sites of the beach line at its activation, the slabs' sites that move its
#: first bound, and one more per probe that moves its bound)
WATCH_ROWS_PER_SITE = 4
_STATS_KEPT = ("site_events", "circle_events", "false_alarms", "vertices", "max_beach_line",
               "breakpoint_tests", "breakpoint_exact", "event_comparisons", "event_comparisons_exact",
               "orient2d_calls", "orient2d_exact", "exact_keys")


def _event_order(sites: NDArray[np.float64]) -> NDArray[np.int64]:
    """Indices of the sites sorted by y, then x, then index: one quicksort of y, then each run
    of equal y sorted on its own (lattice rows; a lexsort of 10^6 sites costs ten quicksorts)."""
    order = np.argsort(sites[:, 1])
    y = sites[order, 1]
    if np.any(y[1:] == y[:-1]):
        _order_runs_by_x(order, sites[:, 0], y)
    return order


#: Runs of equal y up to this length are sorted by insertion, longer ones by numpy.
_SHORT_RUN = 16


@njit(cache=True)
def _order_runs_by_x(order, x, y_sorted):
    # within each run of equal y (y_sorted = y[order]), order the indices by (x, index)
    n = order.shape[0]
    i = 0
    while i < n:
        j = i + 1
        while j < n and y_sorted[j] == y_sorted[i]:
            j += 1
        if j - i <= _SHORT_RUN:
            for k in range(i + 1, j):
                v = order[k]
                m = k - 1
                while m >= i and (x[order[m]] > x[v] or (x[order[m]] == x[v] and order[m] > v)):
                    order[m + 1] = order[m]
                    m -= 1
                order[m + 1] = v
        elif j - i > 1:
            run = np.sort(order[i:j])                          # by index, then stably by x
            order[i:j] = run[np.argsort(x[run], kind='mergesort')]
        i = j


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites`` by Fortune's sweep."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    if n <= 1:
        if stats is not None:
            stats.update({k: 0 for k in _STATS_KEPT}, site_events=n)
        return Diagram.empty(sites)
    # The sweep runs on the sites in event order (y, then x): site i is the i-th event, which
    # keeps its memory accesses local; site ids are mapped back after the DCEL is built.
    order = _event_order(sites)
    swept = np.ascontiguousarray(sites[order])
    counters = np.zeros(N_COUNTERS, dtype=np.int64)
    status, edge_sites, edge_vertices, vertices = sweep(swept, counters)
    if status != OK:
        raise RuntimeError(f"fortune: {_ERRORS.get(status, 'unknown error')} (n = {n}); this is a bug")
    if stats is not None:
        named = dict(zip(COUNTER_NAMES, counters.tolist()))
        stats.update({k: int(named[k]) for k in _STATS_KEPT})
    d = assemble(swept, vertices, edge_sites, edge_vertices)
    return Diagram(sites, d.vertices, d.origin, d.twin, d.next, order.astype(d.site.dtype)[d.site])


def _shift_table(sites: NDArray[np.float64], weights: NDArray[np.float64]) -> NDArray[np.float64]:
    """The weighted sweep's site table: x, y, the shift s_i = max(w) - w_i >= 0 as an interval
    [s_lo, s_hi] (one point when the float subtraction is exact, as it is for weights of
    similar size), and w."""
    # numpy's allocation (with huge pages; numba's took 0.08 s more of page faults at 10^6)
    table = np.empty((weights.shape[0], 5), dtype=np.float64)
    _shift_rows(sites, weights, weights.max(), table)
    return table


@njit(cache=True)
def _shift_rows(sites, weights, top, table):
    # one pass (numpy's column_stack and where took about 0.1 s at 10^6 sites)
    for i in range(weights.shape[0]):
        w = weights[i]
        s = top - w
        # the rounding error of top - w, exactly (Knuth's two-difference)
        bvirt = top - s
        tail = (top - (s + bvirt)) + (bvirt - w)
        table[i, 0], table[i, 1], table[i, 4] = sites[i, 0], sites[i, 1], w
        if tail == 0:
            table[i, 2], table[i, 3] = s, s
        else:
            table[i, 2], table[i, 3] = max(np.nextafter(s, -np.inf), 0.0), np.nextafter(s, np.inf)


def _vertex_points(sites: NDArray[np.float64], weights: NDArray[np.float64],
                   specs: NDArray[np.integer]) -> NDArray[np.float64]:
    """The rounded power centre of each vertex spec (a, b, c), in an array numpy allocates."""
    out = np.empty((specs.shape[0], 2), dtype=np.float64)
    _power_centres(sites, weights, specs, out)
    return out


@njit(cache=True)
def _power_centres(sites, weights, specs, out):
    for v in range(specs.shape[0]):
        a, b, c = specs[v, 0], specs[v, 1], specs[v, 2]
        out[v, 0], out[v, 1] = power_centre(sites[a, 0], sites[a, 1], weights[a], sites[b, 0], sites[b, 1],
                                            weights[b], sites[c, 0], sites[c, 1], weights[c])


def build_weighted(sites: NDArray[np.float64], weights: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The power diagram of prepared ``sites`` with ``weights`` (power |x - p|^2 - w) by the
    weighted sweep (:mod:`impls.fortune.power_sweep`); equal weights go to the ordinary sweep,
    so its diagram comes out bit for bit. Its decisions are exact for sites and weights in the
    exact range of :mod:`vorobench.core.scaling`, where ``Implementation.run`` scales every input;
    far outside it (sites near 2**-300 called directly) a build can stop with an error."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    weights = np.ascontiguousarray(weights, dtype=np.float64).reshape(-1)
    n = sites.shape[0]
    if n <= 1 or np.all(weights == weights[0]):
        d = build(sites, stats)
        if stats is not None:
            stats["hidden_sites"] = 0
        return Diagram(sites, d.vertices, d.origin, d.twin, d.next, d.site, weights=weights)
    # as in the ordinary sweep, site i of the sweep is the i-th in event order (local memory
    # accesses); the sites of edges and vertices are mapped back after the sweep
    order = _event_order(sites)
    swept, swept_weights = np.ascontiguousarray(sites[order]), weights[order]
    row = int(np.searchsorted(swept[:, 1], swept[0, 1], side="right"))
    table = _shift_table(swept, swept_weights)
    counters = np.zeros(power_sweep.N_COUNTERS, dtype=np.int64)
    with exact_context(swept, swept_weights):
        status, edges, specs, boxes = power_sweep.sweep(table, np.arange(n, dtype=np.int64), row, counters,
                                                        slabs(swept[:, 0]), WATCH_ROWS_PER_SITE * n + 16)
        if status == power_sweep.ERR_CAPACITY:
            raise RuntimeError(f"fortune (weighted): more events or rows of watch lists than the sweep's int32 ids "
                               f"can number (n = {n})")
        if status != power_sweep.OK:
            raise RuntimeError(f"fortune (weighted): {_WEIGHTED_ERRORS.get(status, 'unknown error')} (n = {n}); "
                               "this is a bug")
        edges, specs = power_sweep.merge_vertices(table, counters, edges, specs, boxes)
    if stats is not None:
        stats.update(dict(zip(power_sweep.COUNTER_NAMES, counters.tolist())))
    # vertices and cells are made in event order too, where a vertex's sites are near each
    # other in memory, and the sites mapped back last (as the ordinary sweep does)
    vertices = _vertex_points(swept, swept_weights, specs)
    d = assemble(swept, vertices, edges[:, :2], edges[:, 2:], weights=swept_weights)
    diagram = Diagram(sites, d.vertices, d.origin, d.twin, d.next, order.astype(d.site.dtype)[d.site], weights=weights)
    if stats is not None:
        stats["hidden_sites"] = int(diagram.hidden.size)
    return diagram


def warmup() -> None:
    """Compile (or load from numba's cache) every kernel, including the exact paths."""
    # a grid has exact ties (exact event comparisons) and sites below breakpoints
    g = np.array([[x, y] for y in range(3) for x in range(3)], dtype=np.float64)
    build(g)
    build(np.array([[0.1, 0.2], [0.7, 0.3], [0.4, 0.9], [0.5, 0.5]]))
    rng = np.random.default_rng(0)
    build_weighted(rng.random((40, 2)), rng.random(40) * 0.01)
    build_weighted(g, np.arange(9.0) % 2)
    # equal disks on a grid reach every exact stage of the sweep of disks, and merge vertices
    build_disks(g, np.full(9, 0.25))
    build_disks(rng.random((40, 2)), rng.random(40) * 0.05)


class _ExactDisks:
    """Disk i as exact rationals (x, y, r), made when first asked for."""

    def __init__(self, centres: NDArray[np.float64], radii: NDArray[np.float64]) -> None:
        self.centres, self.radii = centres, radii

    def __getitem__(self, i: int) -> tuple:
        return tuple(rational(float(v)) for v in (self.centres[i, 0], self.centres[i, 1], self.radii[i]))


def build_disks(centres: NDArray[np.float64], radii: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The diagram of the disks by Fortune's sweep with each directrix raised by its disk's radius
    (:mod:`impls.fortune.disk_sweep`, compiled: float filters, then the rational predicates).
    Hidden disks never enter the sweep and get no edge."""
    centres = np.ascontiguousarray(centres, dtype=np.float64).reshape(-1, 2)
    radii = np.ascontiguousarray(radii, dtype=np.float64).reshape(-1)
    if radii.shape != (centres.shape[0],):
        raise ValueError(f"radii has shape {radii.shape}, there are {centres.shape[0]} centres")
    n = centres.shape[0]
    visible = np.flatnonzero(~hidden_disks(centres, radii))
    if visible.size <= 1:
        if stats is not None:
            stats.update(hidden_sites=int(n - visible.size))
        return Diagram.empty(centres, radii=radii)
    if np.all(radii == radii[0]):
        # equal radii: every bisector is the centres' own, and the diagram the ordinary one
        # (only copies of one disk are hidden); the ordinary sweep decides lattices' ties
        # without the rationals
        d = build(centres[visible], stats)
        if stats is not None:
            stats["hidden_sites"] = int(n - visible.size)
        return Diagram(centres, d.vertices, d.origin, d.twin, d.next, visible.astype(d.site.dtype)[d.site],
                       radii=radii)
    # the sweep runs on the visible disks in event order; sites are mapped back afterwards
    order, first_row = disk_sweep.event_order(centres[visible, 0], centres[visible, 1], radii[visible])
    order = visible[order]
    xs, ys, rs = (np.ascontiguousarray(a) for a in (centres[order, 0], centres[order, 1], radii[order]))
    scale = float(max(np.abs(centres).max(), radii.max()))
    counters = np.zeros(disk_sweep.N_COUNTERS, dtype=np.int64)
    with disk_exact.exact_context(xs, ys, rs):
        status, edge_sites, edge_vertices, vertices, triples, boxes = disk_sweep.sweep(xs, ys, rs, first_row, scale,
                                                                                       counters)
        if status != disk_sweep.OK:
            raise RuntimeError(f"fortune (disks): {_ERRORS.get(status, 'unknown error')} (n = {n}); this is a bug")
        edge_sites, edge_vertices, vertices = disk_sweep.merge_vertices(edge_sites, edge_vertices, vertices, triples,
                                                                        boxes, counters)
    edge_sites = order[edge_sites]
    if stats is not None:
        stats.update(dict(zip(disk_sweep.COUNTER_NAMES, counters.tolist())), hidden_sites=int(n - visible.size))
    try:
        vertices, origin, twin, nxt, site = link_edges(n, vertices, edge_sites, edge_vertices, sites=centres)
    except InvalidDiagramError:
        # a cell with several rays out to infinity, between vertices (collinear centres): its
        # rays are linked in the order of their asymptotes, exactly
        site, origin = edge_sites.reshape(-1), edge_vertices.reshape(-1)
        twin = np.arange(site.size) ^ 1
        nxt = np.array(apollonius_sweep.link_half_edges(_ExactDisks(centres, radii), site.tolist(), origin.tolist(),
                                                        twin.tolist()), dtype=np.int64)
    return Diagram(centres, vertices, origin, twin, nxt, site, radii=radii)


IMPLEMENTATION = Implementation(
    name="fortune",
    description="Fortune's sweep line with exact predicates (numba): treap beach line, indexed event heap; "
                "power diagrams by its own weighted sweep; disks by its sweep with raised directrices",
    complexity="O(n log n)",
    build=build,
    build_weighted=build_weighted,
    build_apollonius=build_disks,
    exact=True,
    warmup=warmup,
    kind="own",
)
