"""Fortune's sweep for disks (the additively weighted Voronoi diagram), exact, in rationals: the
first sweep of issue 26, written for correctness (docs/apollonius.md, "The sweep").

The sweep line y = L moves up. Under the distance |x - p_i| - r_i, the points that disk i claims
before the sweep line does satisfy |x - p_i| <= (L + r_i) - x_y: behind the parabola with focus
p_i and directrix y = L + r_i. So the sweep of disks is Fortune's with each site's directrix
raised by its radius (the hyperbolic arcs of the founding description are these parabolas seen
through Fortune's transformation):

* **site event** of disk i at L = p_y - r_i (the directrix reaches the focus): its parabola is
  the vertical ray below p_i, and its arc enters the beach line above x = p_x, splitting the arc
  there. Hidden disks (inside another) never enter: they are removed first (``hidden_disks``).
* **circle event** of consecutive arcs a, b, c: the middle arc vanishes at the vertex of the
  three disks in the order (a, b, c) (counter-clockwise around the vertex: b's cell below, c's
  right, a's left), when the sweep reaches the top of its circle, L = v_y + R.
* **beach line**: the upper envelope of the parabolas, arcs left to right. Two parabolas of
  different directrix distances cross twice; the breakpoint of a left arc a and a right arc b
  is the crossing where a stops being the higher one. Locating a site compares its x with
  breakpoints at a rational L: the sign of a quadratic with rational coefficients at a rational
  x, and which side of its vertex x lies: no square root.

Every decision is exact: breakpoints in rationals, circle events by the exact vertex predicate,
event times (rational or a + b sqrt(d)) ordered by ``compare``. Ties: at one time, circle events
come before site events, sites in order of x; a site exactly on a breakpoint splits the arc on
its left, leaving an arc of zero width that vanishes at once. Vertices at one exact point (four
or more disks on a circle) are merged and the zero-length edges between them dropped.

The beach line is a Python list (search by bisection over exact breakpoint tests, insertion and
removal O(n)): O(n^2) element moves and O(n log n) exact tests. A first sweep, exact and simple;
the compiled one with float filters is the next step (the speed goals are not met by this one).
"""

from __future__ import annotations

import heapq
import itertools
from typing import Optional, Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vorobench.core.diagram import Diagram
from vorobench.core.hidden_disks import hidden_disks
from vorobench.core.predicates.apollonius import (
    ApolloniusVertex,
    QuadraticNumber,
    asymptote,
    compare,
    direction_key,
    rational,
    vertex,
)

__all__ = ["build", "side", "meets", "link_half_edges"]

_CIRCLE, _SITE = 0, 1
_ZERO = rational(0)


class _Edge:
    """An edge of two cells u, w: where the half-edge of each (that cell on its left) ends."""

    __slots__ = ("u", "w", "end_u", "end_w")

    def __init__(self, u: int, w: int) -> None:
        self.u, self.w = u, w
        self.end_u: Optional[int] = None
        self.end_w: Optional[int] = None

    def close(self, cell: int, v: int) -> None:
        """The half-edge of ``cell`` ends at vertex ``v`` (its breakpoint stopped there)."""
        if cell == self.u and self.end_u is None:
            self.end_u = v
        elif cell == self.w and self.end_w is None:
            self.end_w = v
        else:
            raise RuntimeError(f"apollonius sweep: the edge of {self.u}, {self.w} closes twice for cell {cell}")


class _Arc:
    """An arc of the beach line: its site, the edge its right breakpoint traces, its event."""

    __slots__ = ("site", "right_edge", "event")

    def __init__(self, site: int, right_edge: Optional[_Edge] = None) -> None:
        self.site = site
        self.right_edge = right_edge
        self.event: Optional[_Event] = None


class _Event:
    """A heap entry: its time (exact), kind, order among sites, and the arc or site."""

    __slots__ = ("time", "kind", "x", "seq", "arc", "site", "point")

    def __init__(self, time: QuadraticNumber, kind: int, x, seq: int, arc: Optional[_Arc] = None,
                 site: int = -1, point: Optional[ApolloniusVertex] = None) -> None:
        self.time, self.kind, self.x, self.seq = time, kind, x, seq
        self.arc, self.site, self.point = arc, site, point

    def __lt__(self, other: "_Event") -> bool:
        c = compare(self.time, other.time)
        if c:
            return c < 0
        if self.kind != other.kind:
            return self.kind < other.kind           # circle events first
        if self.x != other.x:
            return self.x < other.x
        return self.seq < other.seq


def _q(value) -> QuadraticNumber:
    return QuadraticNumber(value, _ZERO, _ZERO)


def side(disks, L, x, a: int, b: int) -> int:
    """Sign of x - (the breakpoint of left arc a and right arc b) when the sweep is at the
    rational L (a site's time)."""
    (ax, ay, ar), (bx, by, br) = disks[a][:3], disks[b][:3]
    ha, hb = L + ar - ay, L + br - by          # distance from focus to directrix (0: a spike)
    if ha == 0 or hb == 0:
        spike = ax if ha == 0 else bx
        return (x > spike) - (x < spike)
    # g(x) = 2 ha hb (y_a(x) - y_b(x)): positive where a is the higher parabola
    alpha = ha - hb
    beta = 2 * (hb * ax - ha * bx)
    gamma = ha * hb * ((L + ar + ay) - (L + br + by)) - hb * ax * ax + ha * bx * bx
    g = (alpha * x + beta) * x + gamma
    if alpha == 0:                                # one crossing: a above on its left
        return -1 if g > 0 else 1 if g < 0 else 0
    # the breakpoint is the crossing where g goes from + to -: the smaller root when the
    # parabola of a is the wider (alpha > 0), else the larger
    apex_side = 2 * alpha * x + beta              # sign of x - vertex of g, times sign(alpha)
    if alpha > 0:
        if g > 0:
            return -1 if apex_side < 0 else 1
        return 1 if g < 0 or apex_side > 0 else 0
    if g > 0:
        return -1
    if g < 0:
        return -1 if apex_side > 0 else 1          # left of both roots, or right of both
    return 0 if apex_side <= 0 else -1


def meets(disks, a: int, b: int, v: ApolloniusVertex, top: QuadraticNumber) -> bool:
    """Whether the breakpoint of left arc a and right arc b is at v when the sweep is at
    ``top`` (v lies on both parabolas then): the crossing where g = 2 h_a h_b (y_a - y_b)
    goes from + to -, so g'(v_x) <= 0 (0: the parabolas touch there)."""
    (ax, ay, ar), (bx, by, br) = disks[a], disks[b]
    ha, hb = top + _q(ar - ay), top + _q(br - by)
    if ha.sign() == 0 or hb.sign() == 0:
        return True                               # a spike: its breakpoints are at its x
    alpha = (ar - ay) - (br - by)                 # h_a - h_b: the sweep's position cancels
    slope = v.x.scaled(2 * alpha) + (hb.scaled(ax) - ha.scaled(bx)).scaled(2)
    return slope.sign() <= 0


class _Sweep:
    def __init__(self, disks: list[tuple], visible: list[int]) -> None:
        self.disks = disks
        self.arcs: list[_Arc] = []
        self.heap: list[_Event] = []
        self.seq = itertools.count()
        self.edges: list[_Edge] = []
        self.points: list[ApolloniusVertex] = []
        self.L = None                                 # the sweep's position (rational at site events)
        self.first_row = None                         # the time of the first site event
        for i in visible:
            x, y, r = disks[i]
            heapq.heappush(self.heap, _Event(_q(y - r), _SITE, x, next(self.seq), site=i))

    # ------------------------------------------------------------------ breakpoints
    def _side(self, x, a: int, b: int) -> int:
        return side(self.disks, self.L, x, a, b)

    def _meets(self, a: int, b: int, v: ApolloniusVertex, top: QuadraticNumber) -> bool:
        return meets(self.disks, a, b, v, top)

    def _locate(self, x) -> tuple[int, bool]:
        """(k, on_breakpoint): the arc above x (or the breakpoint k | k + 1 that x is on)."""
        lo, hi = 0, len(self.arcs) - 1                # the answer is an arc index in [lo, hi]
        while lo < hi:
            mid = (lo + hi) // 2
            side = self._side(x, self.arcs[mid].site, self.arcs[mid + 1].site)
            if side == 0:
                return mid, True
            if side < 0:
                hi = mid
            else:
                lo = mid + 1
        return lo, False

    # ------------------------------------------------------------------ events
    def _schedule(self, k: int) -> None:
        """The circle event of arc k, if its neighbours' breakpoints meet ahead of the sweep."""
        arc = self.arcs[k]
        arc.event = None
        if k == 0 or k == len(self.arcs) - 1:
            return
        a, b, c = self.arcs[k - 1].site, arc.site, self.arcs[k + 1].site
        if a == c:
            return
        v = vertex(self.disks, a, b, c)
        if v is None:
            return
        top = v.y + v.radius
        if compare(top, self.L if isinstance(self.L, QuadraticNumber) else _q(self.L)) < 0:
            return
        # the vertex of (a, b, c) is where b's arc vanishes only if both of b's breakpoints
        # reach it: three disks can have a circle each way, and the beach line can hold
        # a, b, c, a, where arc b and arc c both see the circle (a, b, c)
        if not (self._meets(a, b, v, top) and self._meets(b, c, v, top)):
            return
        event = _Event(top, _CIRCLE, _ZERO, next(self.seq), arc=arc, point=v)
        arc.event = event
        heapq.heappush(self.heap, event)

    def _site_event(self, i: int) -> None:
        x = self.disks[i][0]
        if not self.arcs:
            self.arcs.append(_Arc(i))
            self.first_row = self.L
            return
        if self.L == self.first_row:
            # a first row of sites at one time (every arc so far entered now: spikes side by
            # side), coming in order of x
            if self.disks[self.arcs[-1].site][0] >= x:
                raise RuntimeError("apollonius sweep: the first row of sites came out of order")
            edge = _Edge(self.arcs[-1].site, i)
            self.edges.append(edge)
            self.arcs[-1].right_edge = edge
            self.arcs.append(_Arc(i))
            if len(self.arcs) >= 3:                  # parabolas of different radii widen apart:
                self._schedule(len(self.arcs) - 2)    # the middle spike's arc may close
            return
        k, _ = self._locate(x)
        above = self.arcs[k]
        if above.event is not None:
            above.event = None
        edge = _Edge(above.site, i)
        self.edges.append(edge)
        middle = _Arc(i, edge)
        right = _Arc(above.site, above.right_edge)
        above.right_edge = edge
        self.arcs[k + 1:k + 1] = [middle, right]
        for j in (k, k + 2):
            self._schedule(j)

    def _circle_event(self, event: _Event) -> None:
        arc = event.arc
        k = self.arcs.index(arc)
        left, right = self.arcs[k - 1], self.arcs[k + 1]
        v = len(self.points)
        self.points.append(event.point)
        left.right_edge.close(left.site, v)           # breakpoint (a | b): a's half-edge ends here
        arc.right_edge.close(arc.site, v)             # breakpoint (b | c): b's half-edge ends here
        edge = _Edge(left.site, right.site)
        edge.close(right.site, v)                     # the new breakpoint (a | c) starts here
        self.edges.append(edge)
        left.right_edge = edge
        del self.arcs[k]
        self._schedule(k - 1)
        self._schedule(k)

    def run(self) -> None:
        while self.heap:
            event = heapq.heappop(self.heap)
            if event.kind == _CIRCLE and event.arc.event is not event:
                continue                              # stale: the arc changed neighbours
            self.L = event.time.a if event.kind == _SITE else event.time
            if event.kind == _SITE:
                self._site_event(event.site)
            else:
                self._circle_event(event)


def _assemble(centres: NDArray[np.float64], radii: NDArray[np.float64], disks: list[tuple],
              sweep: _Sweep) -> Diagram:
    """The DCEL: vertices at one exact point merged, zero-length edges dropped, each cell's
    half-edges linked end to start, its rays to infinity linked in counter-clockwise order of
    their asymptotes."""
    # one vertex per exact point: exactly equal points round to the same floats
    floats = [(float(p.x), float(p.y)) for p in sweep.points]
    # equal points round to equal floats: they are looked for among those, exactly (distinct
    # points may round alike too: near-degenerate disks)
    seen: dict[tuple[float, float], list[int]] = {}          # floats -> points (indices) of distinct vertices
    vid, coordinates = [], []
    for t, key in enumerate(floats):
        p = sweep.points[t]
        same = [u for u in seen.get(key, []) if compare(p.x, sweep.points[u].x) == 0
                and compare(p.y, sweep.points[u].y) == 0]
        if same:
            vid.append(vid[same[0]])
            continue
        seen.setdefault(key, []).append(t)
        vid.append(len(coordinates))
        coordinates.append(key)
    vertices = np.array(coordinates, dtype=np.float64).reshape(-1, 2)
    site, origin, twin = [], [], []
    for e in sweep.edges:
        a = None if e.end_u is None else vid[e.end_u]
        b = None if e.end_w is None else vid[e.end_w]
        if a is not None and a == b:
            continue                                  # zero length: its ends are one vertex
        h = len(site)
        site += [e.u, e.w]
        origin += [-1 if b is None else b, -1 if a is None else a]
        twin += [h + 1, h]
    nxt = link_half_edges(disks, site, origin, twin)
    return Diagram(centres, vertices, np.array(origin, dtype=np.int64), np.array(twin, dtype=np.int64),
                   np.array(nxt, dtype=np.int64), np.array(site, dtype=np.int64), radii=radii)


def link_half_edges(disks, site: Sequence[int], origin: Sequence[int], twin: Sequence[int]) -> list[int]:
    """``next`` of each half-edge of a diagram of disks (``disks[i]`` the exact disk of site
    i): the half-edge of its cell that starts where it ends; around a cell, each ray out to
    infinity is followed by the next ray in, in counter-clockwise order of their asymptotes
    (a cell may have several: collinear disks' strips)."""
    H = len(site)
    dest = [origin[twin[h]] for h in range(H)]
    starting: dict[tuple[int, int], int] = {}
    rays_in: dict[int, list[int]] = {}
    rays_out: dict[int, list[int]] = {}
    for h in range(H):
        if origin[h] >= 0:
            if (site[h], origin[h]) in starting:
                raise RuntimeError(f"apollonius sweep: cell {site[h]} leaves vertex {origin[h]} twice")
            starting[(site[h], origin[h])] = h
        else:
            rays_in.setdefault(site[h], []).append(h)
        if dest[h] < 0:
            rays_out.setdefault(site[h], []).append(h)
    nxt = [-1] * H
    for h in range(H):
        if dest[h] >= 0:
            nxt[h] = starting[(site[h], dest[h])]
    for cell, outs in rays_out.items():
        ins = rays_in.get(cell, [])
        if len(ins) != len(outs):
            raise RuntimeError(f"apollonius sweep: cell {cell} has {len(outs)} rays out and {len(ins)} in")
        if len(outs) == 1:
            nxt[outs[0]] = ins[0]
            continue
        # around the cell, counter-clockwise: each ray out is followed by the next ray in
        tagged = [(direction_key(asymptote(disks, cell, site[twin[h]], 1)), 0, h) for h in outs] + \
                 [(direction_key(asymptote(disks, cell, site[twin[h]], -1)), 1, h) for h in ins]
        tagged.sort(key=lambda t: (t[0], t[1]))
        for pos, (_, kind, h) in enumerate(tagged):
            if kind == 0:
                following = next(tagged[(pos + s) % len(tagged)] for s in range(1, len(tagged) + 1)
                                 if tagged[(pos + s) % len(tagged)][1] == 1)
                nxt[h] = following[2]
    return nxt


def build(centres: ArrayLike, radii: ArrayLike, stats: Optional[dict] = None) -> Diagram:
    """The diagram of the disks by Fortune's sweep, exactly; hidden disks get no edge."""
    centres = np.ascontiguousarray(centres, dtype=np.float64).reshape(-1, 2)
    radii = np.ascontiguousarray(radii, dtype=np.float64).reshape(-1)
    if radii.shape != (centres.shape[0],):
        raise ValueError(f"radii has shape {radii.shape}, there are {centres.shape[0]} centres")
    visible = [int(i) for i in np.flatnonzero(~hidden_disks(centres, radii))]
    if len(visible) <= 1:
        return Diagram.empty(centres, radii=radii)
    disks = [(rational(float(x)), rational(float(y)), rational(float(r))) for (x, y), r in zip(centres, radii)]
    sweep = _Sweep(disks, visible)
    sweep.run()
    if stats is not None:
        stats.update(vertices_found=len(sweep.points), edges_traced=len(sweep.edges))
    return _assemble(centres, radii, disks, sweep).validate()
