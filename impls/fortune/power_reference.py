"""Fortune's sweep for power diagrams, in exact rational arithmetic: the specification.

The weighted sweep of ``docs/power.md`` ("The sweep for weighted sites"), written to be read
and checked rather than to be fast: every quantity is a :class:`~fractions.Fraction` or
``a + b sqrt(H)`` with rational a, b, H, so every decision is exact with no filter to
analyse. It is the oracle for the compiled sweep and the place where the event rules are
stated once.

Shift the weights so the largest is 0: site i gets s_i = max(w) - w_i >= 0 and the lifted
power l_i(x) = |x - p_i|^2 + s_i (the power plus a constant: the same diagram). A point x at
height Y is reached at time T_i(x) = Y + sqrt(l_i(x)); the level curve T_i = t is a parabola
opening downwards (the *wavefront* of i), and the beach line is the upper envelope of the
wavefronts of the sites present. Three kinds of event, in exact order of time:

* ``CIRCLE``: consecutive arcs (l, k, m) whose breakpoints meet at the power centre v of the
  three sites, at time T(v); arc k vanishes, v is a vertex. As in the ordinary sweep.
* ``CONTACT``: a pending site i (its time y_i has come, its wavefront is below the beach line)
  first touches the beach line: either at a breakpoint (a, b), at the power centre of
  (a, i, b) (a vertex: the edge (a, b) ends, (a, i) and (i, b) start there), or inside an
  arc k whose site is lower (y_k < y_i), at the point c_ik of the bisector of i and k where
  T_k is least: the arc k splits into (k, i, k) and one edge starts there in both directions.
  A site with s_i = 0 touches at time y_i right above itself: the ordinary site event.
* ``ACTIVATION``: at time y_i site i becomes pending (before that its wavefront is empty).

A site still pending when the events run out is hidden. Two ways to find contacts, judged
alike by the tests: :class:`Sweep` computes candidates for every pending site against every
breakpoint and arc of the beach line whenever either appears (O(n (b + p)) for a beach line
of b arcs and p pending sites; a candidate is only valid while its breakpoint or arc keeps its
neighbours, and is dropped when popped otherwise); :class:`ProbingSweep` queues one lower
bound per pending site and looks at one arc per probe (about three per site on uniform sets).
Not registered as a construction: it is slow (Python, rationals), and stands as the oracle for
the compiled sweep.
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass, field
from enum import IntEnum
from fractions import Fraction
from typing import Optional

import numpy as np
from numpy.typing import NDArray

from impls.fortune.slabs import OWN_DEPTH, SIDE_DEPTH, slabs
from vorobench.core.builder import assemble
from vorobench.core.diagram import Diagram

#: A probe's partner when the site of its bound is not on the beach line (pending or hidden,
#: from a slab): it is not the site whose arc the probe touches, so it cannot rank the probe
#: among simultaneous ones (:meth:`Sweep.push`)
UNKEYED = -2

__all__ = ["build_weighted", "Event", "ProbingSweep", "Sweep", "Time", "surd_sign"]


def _sign(x: Fraction) -> int:
    return (x > 0) - (x < 0)


def surd_sign(a: Fraction, b: Fraction, h: Fraction) -> int:
    """The sign of a + b sqrt(h), h >= 0, exactly."""
    if b == 0 or h == 0:
        return _sign(a)
    sa, sb = _sign(a), _sign(b)
    if sa == 0:
        return sb
    if sa == sb:
        return sa
    # opposite signs: |a| against |b| sqrt(h), compared squared
    return sa * _sign(a * a - b * b * h)


class Time:
    """An event time a + sqrt(b) (b >= 0), ordered exactly (equal means equal as numbers, so
    ties between events fall to their kinds)."""

    __slots__ = ("a", "b")

    def __init__(self, a: Fraction, b: Fraction = Fraction(0)) -> None:
        self.a, self.b = a, b

    def compare(self, other: "Time") -> int:
        """-1, 0 or 1 as self is before, at or after ``other``."""
        d = self.a - other.a
        sd, sr = _sign(d), _sign(self.b - other.b)    # sr: the sign of sqrt(b1) - sqrt(b2)
        if sr == 0 or sd == sr:
            return sd if sd != 0 else sr
        if sd == 0:
            return sr
        # opposite signs: |d| against |sqrt(b1) - sqrt(b2)|, squared:
        # d^2 - b1 - b2 + 2 sqrt(b1 b2)
        return sd * surd_sign(d * d - self.b - other.b, Fraction(2), self.b * other.b)

    def __lt__(self, other: "Time") -> bool:
        return self.compare(other) < 0

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Time) and self.compare(other) == 0

    __hash__ = None         # equal times have different (a, b)

    def __float__(self) -> float:
        return float(self.a) + float(self.b) ** 0.5


class Event(IntEnum):
    """Event kinds. At equal times circle events go first (as in the ordinary sweep), then
    activations, then contacts, in increasing s (see :meth:`Sweep.push`)."""

    CIRCLE = 0
    ACTIVATION = 1
    CONTACT_VERTEX = 2
    CONTACT_ARC = 3
    PROBE = 4


@dataclass
class _Arc:
    site: int
    edge: int = -1            # the edge traced by the breakpoint on this arc's right
    version: int = 0          # bumped whenever a neighbour changes: stale events are skipped
    alive: bool = True


@dataclass(order=True)
class _Queued:
    time: Time
    rank: tuple
    seq: int
    kind: int = field(compare=False)
    payload: tuple = field(compare=False)


class Sweep:
    """One run of the exact weighted sweep over prepared ``sites`` with ``weights``."""

    def __init__(self, sites: NDArray[np.float64], weights: NDArray[np.float64]) -> None:
        self.n = n = sites.shape[0]
        self.x = [Fraction(float(v)) for v in sites[:, 0]]
        self.y = [Fraction(float(v)) for v in sites[:, 1]]
        w = [Fraction(float(v)) for v in weights]
        top = max(w)
        self.s = [top - v for v in w]
        # q_i = |p_i|^2 + s_i: the bisector of i and j is 2 x . (p_j - p_i) = q_j - q_i
        self.q = [self.x[i] ** 2 + self.y[i] ** 2 + self.s[i] for i in range(n)]
        self.arcs: list[_Arc] = []
        self.beach: list[int] = []          # arc ids, left to right
        self.pending: set[int] = set()
        self.present: set[int] = set()
        self.heap: list[_Queued] = []
        self.seq = 0
        self.now = Time(Fraction(0))
        self.edges: list[list[int]] = []    # [a, b, start, end]
        self.vertices: list[tuple[Fraction, Fraction]] = []
        self.vertex_ids: dict[tuple[Fraction, Fraction], int] = {}
        self.here: Optional[tuple[Fraction, Fraction]] = None   # the point of the event at hand
        self.log: Optional[list] = None     # a list to record the events processed in (for tests)
        self.counts = {"circle_events": 0, "contacts_at_vertex": 0, "contacts_in_arc": 0,
                       "candidates": 0, "stale": 0}

    # ------------------------------------------------------------------ geometry (exact)

    def ell(self, i: int, zx: Fraction, zy: Fraction) -> Fraction:
        """The lifted power l_i(z) = |z - p_i|^2 + s_i of a rational point."""
        return (zx - self.x[i]) ** 2 + (zy - self.y[i]) ** 2 + self.s[i]

    def power_centre(self, a: int, b: int, c: int) -> Optional[tuple[Fraction, Fraction]]:
        """The point of equal power for three sites; None if they are collinear."""
        x, y, q = self.x, self.y, self.q
        a11, a12, r1 = 2 * (x[b] - x[a]), 2 * (y[b] - y[a]), q[b] - q[a]
        a21, a22, r2 = 2 * (x[c] - x[a]), 2 * (y[c] - y[a]), q[c] - q[a]
        det = a11 * a22 - a12 * a21
        if det == 0:
            return None
        return (r1 * a22 - a12 * r2) / det, (a11 * r2 - r1 * a21) / det

    def vertex_of_wavefronts(self, a: int, b: int, x0: Fraction, x1: Fraction, t0: Fraction,
                             h: Fraction) -> int:
        """Where a point on the wavefronts of both a and b at time t = t0 + sqrt(h) lies
        against the apex of their difference: the sign of z_x - X_g(t), z_x = x0 + x1 sqrt(h).

        The wavefront of i at time t is Y = V_i - (X - x_i)^2 / (2 (t - y_i)); the difference of
        two of them is a quadratic in X with its extremum at
        X_g = (x_a (t - y_b) - x_b (t - y_a)) / (y_a - y_b) (y_a != y_b)."""
        x, y = self.x, self.y
        dy = y[a] - y[b]
        g0 = ((x[a] - x[b]) * t0 - x[a] * y[b] + x[b] * y[a]) / dy
        g1 = (x[a] - x[b]) / dy
        return surd_sign(x0 - g0, x1 - g1, h)

    def side_of_breakpoint(self, l: int, r: int, cx: tuple, t0: Fraction, h: Fraction) -> int:
        """Where x = cx0 + cx1 sqrt(h) lies against the breakpoint (l, r) at time t0 + sqrt(h):
        -1 left of it, 0 at it, 1 right of it.

        g(x) = P_l(x) - P_r(x), times 2 (t - y_l)(t - y_r) > 0, is
        G = ((t^2 - y_l^2) - s_l - (x - x_l)^2)(t - y_r) - ((t^2 - y_r^2) - s_r - (x - x_r)^2)(t - y_l)
        (at t = y_r, a site entering at its own height, G still has g's sign: r's wavefront is
        the ray x = x_r). r is on top right of the breakpoint. If l is the narrower (y_l > y_r),
        l is on top between the two crossings, so the breakpoint is the right one; if l is the
        wider, the left one; equal heights: the curves cross once. Which side of the apex of g
        x lies on (:meth:`vertex_of_wavefronts`) tells the two crossings apart."""
        x, y, sq = self.x, self.y, self.s

        def mul(u, v):
            return (u[0] * v[0] + u[1] * v[1] * h, u[0] * v[1] + u[1] * v[0])

        t = (t0, Fraction(1)) if h != 0 else (t0, Fraction(0))

        def wave(k, other):
            # ((t^2 - y_k^2) - s_k - (x - x_k)^2) (t - y_other)
            tt = mul(t, t)
            dx = (cx[0] - x[k], cx[1])
            dd = mul(dx, dx)
            left = (tt[0] - y[k] ** 2 - sq[k] - dd[0], tt[1] - dd[1])
            return mul(left, (t[0] - y[other], t[1]))

        gl, gr = wave(l, r), wave(r, l)
        g = surd_sign(gl[0] - gr[0], gl[1] - gr[1], h)
        if y[l] == y[r]:
            return -g
        side = self.vertex_of_wavefronts(l, r, cx[0], cx[1], t0, h)
        if y[l] > y[r]:                         # the right root: g > 0 between the roots
            if g > 0 or (g == 0 and side < 0) or (g < 0 and side < 0):
                return -1
            return 0 if g == 0 else 1
        if g > 0 and side < 0:                  # the left root: g < 0 between the roots
            return -1
        return 0 if (g == 0 and side <= 0) else 1

    def is_breakpoint(self, a: int, b: int, x0: Fraction, x1: Fraction, t0: Fraction, h: Fraction) -> bool:
        """Whether a point on the wavefronts of both a and b at time t0 + sqrt(h), at
        x = x0 + x1 sqrt(h), is the breakpoint with a's arc on its left (not the other crossing
        of the two curves; at the apex, where they are born, the two are one)."""
        return self.side_of_breakpoint(a, b, (x0, x1), t0, h) == 0

    def tied(self, a: int, b: int, c: int) -> bool:
        """Collinear a, b, c with b between a and c, and the bisectors (a, b) and (b, c) one
        line: the three have equal power all along it, so b's cell lies in the line (no area)."""
        x, y, q = self.x, self.y, self.q
        ux, uy, uq = x[b] - x[a], y[b] - y[a], q[b] - q[a]
        vx, vy, vq = x[c] - x[b], y[c] - y[b], q[c] - q[b]
        return (ux * vy == uy * vx and ux * vq == uq * vx and uy * vq == uq * vy
                and ux * vx + uy * vy > 0)

    def orient(self, a: int, b: int, c: int) -> int:
        """The sign of the turn a -> b -> c (positive: counter-clockwise)."""
        x, y = self.x, self.y
        return _sign((x[b] - x[a]) * (y[c] - y[a]) - (y[b] - y[a]) * (x[c] - x[a]))

    def power_gap(self, j: int, k: int, cx: tuple, cy: tuple, h: Fraction) -> int:
        """The sign of l_j(c) - l_k(c) at c = (cx0 + cx1 sqrt h, cy0 + cy1 sqrt h): positive
        where k has the smaller power (the difference of two powers is affine in c)."""
        ux, uy = self.x[j] - self.x[k], self.y[j] - self.y[k]
        a = self.q[j] - self.q[k] - 2 * (cx[0] * ux + cy[0] * uy)
        b = -2 * (cx[1] * ux + cy[1] * uy)
        return surd_sign(a, b, h)

    def arc_contact(self, i: int, k: int) -> Optional[tuple[Time, tuple, tuple, Fraction]]:
        """Where and when the wavefront of i first touches that of a lower site k:
        (time, c_x, c_y, h) with c = (c0 + c1 sqrt h) and time f_y + sqrt h.

        On the bisector L of i and k (normal n = p_k - p_i), T_k is least at
        c = f + sqrt(h) (n_x / n_y, -n_x^2 / n_y^2), where f is p_k's projection on L and
        h = (|f - p_k|^2 + s_k) n_y^2 / |n|^2, at time f_y + sqrt(h)."""
        if not self.y[k] < self.y[i]:
            return None
        x, y = self.x, self.y
        nx, ny = x[k] - x[i], y[k] - y[i]
        nn = nx * nx + ny * ny
        cst = (self.q[k] - self.q[i]) / 2
        lam = (cst - (nx * x[k] + ny * y[k])) / nn
        fx, fy = x[k] + lam * nx, y[k] + lam * ny
        h = (lam * lam * nn + self.s[k]) * ny * ny / nn
        return Time(fy, h), (fx, nx / ny), (fy, -(nx * nx) / (ny * ny)), h

    # ------------------------------------------------------------------ queue

    def push(self, time: Time, kind: Event, payload: tuple, partner: int = -1) -> None:
        """Queue an event. Contacts (and probes) at one time go farthest from their partner
        first: a contact inside the arc of a site k has partner k. Sites that touch k's arc at
        one point together and tie with k along a line (collinear, equal power all along it)
        own cells there only if outermost: the one farthest from k enters first and leaves the
        ones between no room (their cells lie in the line). A probe whose partner is
        ``UNKEYED`` goes before every other contact of its time; on the beach line, it is
        queued again with the arc's site as its partner."""
        self.seq += 1
        if partner == UNKEYED:
            # the site of its bound is not on the beach line: first, to be ranked at its point
            rank = (int(Event.CONTACT_VERTEX), 0, Fraction(0))
        elif kind in (Event.CONTACT_VERTEX, Event.CONTACT_ARC, Event.PROBE):
            i = payload[1]
            far = (self.x[i] - self.x[partner]) ** 2 + (self.y[i] - self.y[partner]) ** 2 if partner >= 0 else 0
            rank = (int(Event.CONTACT_VERTEX), 1, -far)
        else:
            rank = (int(kind), 1, Fraction(0))
        heapq.heappush(self.heap, _Queued(time, rank, self.seq, int(kind), payload))

    def neighbours(self, pos: int) -> tuple[int, int]:
        left = self.beach[pos - 1] if pos > 0 else -1
        right = self.beach[pos + 1] if pos + 1 < len(self.beach) else -1
        return left, right

    def stamp(self, *arcs: int) -> tuple:
        return tuple((a, self.arcs[a].version) for a in arcs)

    def fresh(self, stamps: tuple) -> bool:
        return all(self.arcs[a].alive and self.arcs[a].version == v for a, v in stamps)

    # ------------------------------------------------------------------ candidates

    def circle_candidate(self, pos: int) -> None:
        """Schedule the vanishing of the arc at ``pos`` if its breakpoints converge."""
        left, right = self.neighbours(pos)
        if left < 0 or right < 0:
            return
        k = self.beach[pos]
        sl, sk, sr = self.arcs[left].site, self.arcs[k].site, self.arcs[right].site
        # the breakpoints (l, k) and (k, m) converge iff l, k, m turn counter-clockwise, weights
        # or not: k's cell among the three is then the wedge their paths have already traced
        if sl == sr:
            return
        turn = self.orient(sl, sk, sr)
        if turn == 0 and self.here is not None and self.tied(sl, sk, sr):
            # k has just met a neighbour that ties with it along a line: its arc has no width and
            # never will; it closes now, where the event at hand is (its cell is hidden)
            self.push(self.now, Event.CIRCLE, (self.stamp(left, k, right), self.here))
            return
        if turn <= 0:
            return
        v = self.power_centre(sl, sk, sr)
        if v is None:
            return
        t = Time(v[1], self.ell(sk, *v))
        if t < self.now:
            return
        zero = Fraction(0)
        if v == self.here and t == self.now:
            # an arc with no width at the point of the event at hand, between neighbours that
            # close on it: it has no room (another site co-power there enters around it) and
            # closes now, whichever crossings its breakpoints were born on
            self.push(t, Event.CIRCLE, (self.stamp(left, k, right), v))
        elif self.is_breakpoint(sl, sk, v[0], zero, t.a, t.b) and self.is_breakpoint(sk, sr, v[0], zero, t.a, t.b):
            self.push(t, Event.CIRCLE, (self.stamp(left, k, right), v))

    def vertex_candidate(self, pos: int, i: int) -> None:
        """Schedule site i's contact at the breakpoint between ``pos`` and its right neighbour."""
        a_arc, b_arc = self.beach[pos], self.beach[pos + 1]
        a, b = self.arcs[a_arc].site, self.arcs[b_arc].site
        # i's arc must be born growing: its breakpoints with a and b diverge (a, i, b turn
        # clockwise). Converging ones would close at once: i's cell is the point v alone, and
        # a cell of no area is hidden.
        if self.orient(a, i, b) >= 0:
            return
        v = self.power_centre(a, i, b)
        if v is None:
            return
        t = Time(v[1], self.ell(a, *v))
        self.counts["candidates"] += 1
        if t < self.now or not self.is_breakpoint(a, b, v[0], Fraction(0), t.a, t.b):
            return
        self.push(t, Event.CONTACT_VERTEX, (self.stamp(a_arc, b_arc), i, v))

    def arc_candidate(self, pos: int, i: int) -> None:
        """Schedule site i's contact inside the arc at ``pos`` (its site lower than i)."""
        k_arc = self.beach[pos]
        k = self.arcs[k_arc].site
        found = self.arc_contact(i, k)
        self.counts["candidates"] += 1
        if found is None:
            return
        t, cx, cy, h = found
        if t < self.now:
            return
        # c must lie strictly inside the arc at time t (on its ends the contact is at a
        # breakpoint: a vertex candidate)
        if not self.inside_arc(pos, cx, t.a, h):
            return
        self.push(t, Event.CONTACT_ARC, (self.stamp(k_arc), i), partner=k)

    def inside_arc(self, pos: int, cx: tuple, t0: Fraction, h: Fraction) -> bool:
        """Whether x = cx0 + cx1 sqrt(h) lies strictly between the breakpoints of the arc at
        ``pos`` at time t0 + sqrt(h)."""
        left, right = self.neighbours(pos)
        k = self.arcs[self.beach[pos]].site
        if left >= 0 and self.side_of_breakpoint(self.arcs[left].site, k, cx, t0, h) <= 0:
            return False
        return right < 0 or self.side_of_breakpoint(k, self.arcs[right].site, cx, t0, h) < 0

    def candidates_at(self, pos: int) -> None:
        """Everything that depends on the arc at ``pos`` and its neighbours: its circle event,
        and every pending site's contacts inside it and at its right breakpoint."""
        self.circle_candidate(pos)
        for i in sorted(self.pending):
            self.arc_candidate(pos, i)
            if pos + 1 < len(self.beach):
                self.vertex_candidate(pos, i)

    def contacts_at_breakpoint(self, pos: int) -> None:
        """Every pending site's contact at the breakpoint right of ``pos``."""
        for i in sorted(self.pending):
            self.vertex_candidate(pos, i)

    def refresh(self, lo: int, hi: int) -> None:
        """Bump and reschedule the arcs at positions lo..hi (clipped to the beach line), the
        breakpoint left of lo and the circle events of the arcs on either side (their triples
        hold a bumped arc)."""
        lo, hi = max(lo, 0), min(hi, len(self.beach) - 1)
        for pos in range(lo, hi + 1):
            self.arcs[self.beach[pos]].version += 1
        for pos in range(lo, hi + 1):
            self.candidates_at(pos)
        if lo > 0:
            self.circle_candidate(lo - 1)
            self.contacts_at_breakpoint(lo - 1)
        if hi + 1 < len(self.beach):
            self.circle_candidate(hi + 1)

    # ------------------------------------------------------------------ events

    def new_arc(self, site: int) -> int:
        self.arcs.append(_Arc(site))
        return len(self.arcs) - 1

    def new_edge(self, a: int, b: int, start: int = -1) -> int:
        self.edges.append([a, b, start, -1])
        return len(self.edges) - 1

    def close(self, edge: int, left_site: int, vertex: int) -> None:
        """The breakpoint with ``left_site`` on its left stops tracing ``edge`` at ``vertex``
        (it traces the end of an edge whose first site is its left arc's, else the start)."""
        if self.edges[edge][0] == left_site:
            self.edges[edge][3] = vertex
        else:
            self.edges[edge][2] = vertex

    def add_vertex(self, v: tuple[Fraction, Fraction]) -> int:
        """The id of the vertex at exact point v (one id per point: the events of a degenerate
        vertex share it, and the zero-length edges between them are dropped at the end)."""
        if v not in self.vertex_ids:
            self.vertex_ids[v] = len(self.vertices)
            self.vertices.append(v)
        return self.vertex_ids[v]

    def start(self) -> None:
        """The first sweep position: the lowest sites whose wavefronts are on top somewhere
        along the bottom (a 1-D power diagram: upper envelope of 2 x_i X - x_i^2 - s_i) start
        the beach line, separated by vertical bisectors; the others are hidden for good."""
        order = sorted(range(self.n), key=lambda i: (self.y[i], self.x[i]))
        y0 = self.y[order[0]]
        lowest = [i for i in order if self.y[i] == y0]
        hull: list[int] = []
        for i in lowest:                        # slopes 2 x_i increase along ``lowest``
            while len(hull) >= 2 and not self._keeps_middle(hull[-2], hull[-1], i):
                hull.pop()
            hull.append(i)
        previous = -1
        for i in hull:
            arc = self.new_arc(i)
            self.beach.append(arc)
            self.present.add(i)
            if previous >= 0:
                self.arcs[previous].edge = self.new_edge(self.arcs[previous].site, i)
            previous = arc
        for pos in range(len(self.beach)):
            self.circle_candidate(pos)
        for i in order[len(lowest):]:
            self.push(Time(self.y[i]), Event.ACTIVATION, (i,))

    def _keeps_middle(self, a: int, b: int, c: int) -> bool:
        # line b is on the upper envelope of lines a, b, c (slopes increasing) strictly: b beats
        # a at the crossing of a and c
        f = lambda i, X: 2 * self.x[i] * X - self.x[i] ** 2 - self.s[i]
        xa, xc = self.x[a], self.x[c]
        X = (f(c, 0) - f(a, 0)) / (2 * (xa - xc))
        return f(b, X) > f(a, X)

    def activate(self, i: int) -> None:
        self.pending.add(i)
        for pos in range(len(self.beach)):
            self.arc_candidate(pos, i)
            if pos + 1 < len(self.beach):
                self.vertex_candidate(pos, i)

    def circle(self, stamps: tuple, v: tuple) -> None:
        left, k, right = (a for a, _ in stamps)
        pos = self.beach.index(k)
        vid = self.add_vertex(v)
        self.counts["circle_events"] += 1
        la, ka = self.arcs[left], self.arcs[k]
        self.close(la.edge, la.site, vid)
        self.close(ka.edge, ka.site, vid)
        la.edge = self.new_edge(la.site, self.arcs[right].site, vid)
        ka.alive = False
        del self.beach[pos]
        self.refresh(pos - 1, pos)

    def contact_vertex(self, stamps: tuple, i: int, v: tuple) -> None:
        self.insert_at_breakpoint(self.beach.index(stamps[0][0]), i, v)

    def insert_at_breakpoint(self, pos: int, i: int, v: tuple) -> None:
        """Site i enters at vertex v, between the arc at ``pos`` and the next."""
        a_arc, b_arc = self.beach[pos], self.beach[pos + 1]
        vid = self.add_vertex(v)
        self.counts["contacts_at_vertex"] += 1
        self.pending.discard(i)
        self.present.add(i)
        aa = self.arcs[a_arc]
        self.close(aa.edge, aa.site, vid)
        arc = self.new_arc(i)
        aa.edge = self.new_edge(aa.site, i, vid)
        self.arcs[arc].edge = self.new_edge(i, self.arcs[b_arc].site, vid)
        self.beach.insert(pos + 1, arc)
        self.refresh(pos, pos + 2)

    def contact_arc(self, stamps: tuple, i: int) -> None:
        self.split_arc(self.beach.index(stamps[0][0]), i)

    def split_arc(self, pos: int, i: int) -> None:
        """Site i enters inside the arc at ``pos``, which splits in two around it."""
        k_arc = self.beach[pos]
        self.counts["contacts_in_arc"] += 1
        self.pending.discard(i)
        self.present.add(i)
        ka = self.arcs[k_arc]
        arc, twin = self.new_arc(i), self.new_arc(ka.site)
        # the split arc's right part keeps its old right breakpoint's edge
        self.arcs[twin].edge = ka.edge
        ka.edge = self.new_edge(ka.site, i)
        self.arcs[arc].edge = ka.edge
        self.beach[pos + 1:pos + 1] = [arc, twin]
        self.refresh(pos, pos + 2)

    def run(self) -> None:
        if self.n == 0:
            return
        self.start()
        while self.heap:
            item = heapq.heappop(self.heap)
            self.handle(Event(item.kind), item)

    def handle(self, kind: Event, item: _Queued) -> None:
        """Carry out one popped event (stale ones are counted and dropped)."""
        if kind == Event.ACTIVATION:
            self.now = item.time
            self.activate(item.payload[0])
            return
        stamps = item.payload[0]
        if not self.fresh(stamps) or (kind != Event.CIRCLE and item.payload[1] not in self.pending):
            self.counts["stale"] += 1
            return
        self.now = item.time
        self.here = None if kind == Event.CONTACT_ARC else item.payload[-1]
        self.log_event(kind, item.time,
                       [self.arcs[a].site for a, _ in stamps] + ([] if kind == Event.CIRCLE else [item.payload[1]]))
        if kind == Event.CIRCLE:
            self.circle(*item.payload)
        elif kind == Event.CONTACT_VERTEX:
            self.contact_vertex(*item.payload)
        else:
            self.contact_arc(*item.payload)

    def log_event(self, kind: Event, time: Time, sites: list) -> None:
        if self.log is not None:
            self.log.append((kind, float(time), sites, self.here))

    @property
    def hidden(self) -> list[int]:
        """Sites with no edge of positive length (never touched, or a cell of no area)."""
        owners = {s for e in self.edges if e[2] < 0 or e[2] != e[3] for s in e[:2]}
        return sorted(set(range(self.n)) - owners) if self.n > 1 else []


class ProbingSweep(Sweep):
    """The same sweep, finding each pending site's contact by *probes* instead of trying it
    against the whole beach line (docs/power.md, the last section).

    Pending site i keeps a few sites S_i (present, pending or hidden: any site bounds its
    cell; the first come from the beach line and from the slabs, see :meth:`activate`). Its
    cell lies in Q_i, where i has less power than every site of S_i, so the lowest time of T_i
    over Q_i, at a point q, bounds its contact from below; a probe is queued then. At the probe
    q is on or below the beach line, and the arc over q alone says which: the beach line at q's
    x is that arc's wavefront, so q is below it iff that arc's site has less power at q than i.
    Below: that site joins S_i (q leaves Q_i, so the next bound is later). On it: i enters at
    q, inside that arc or at the breakpoint there. A site whose Q_i becomes empty is hidden. (The arc is found here by
    walking the beach line; the compiled sweep would search its tree.)
    """

    def __init__(self, sites: NDArray[np.float64], weights: NDArray[np.float64]) -> None:
        super().__init__(sites, weights)
        self.watch: dict[int, list[int]] = {}       # S_i, newest first (as the compiled list)
        self.counts.update(probes=0)
        # vertical slabs of about sqrt(n) sites (level 0; level L's slab is slab >> 2 L, four
        # times as wide as level L - 1's), and the site activated last in each
        order = sorted(range(self.n), key=lambda i: (self.y[i], self.x[i]))
        self.rank = [0] * self.n                    # each site's place in the order of activations
        for r, i in enumerate(order):
            self.rank[i] = r
        self.slab = [0] * self.n
        for i, slab in zip(order, slabs(np.asarray(sites, dtype=np.float64).reshape(-1, 2)[order, 0])):
            self.slab[i] = int(slab)
        # a slab gets an activation every n / slabs on average; a site whose slab's last came
        # more than twice that before it is sparser than its slab's densest part
        self.sparse_gap = 2 * self.n // (max(self.slab, default=0) + 1)
        self.levels = 1
        while max(self.slab, default=0) >> (2 * self.levels) > 0:
            self.levels += 1
        self.last_in_slab: dict[tuple[int, int], int] = {}
        self.before_in_slab: dict[int, int] = {}    # the site activated before each in its slab (level 0)

    def _activated(self, i: int) -> None:
        below = self.last_in_slab.get((0, self.slab[i]))
        if below is not None:
            self.before_in_slab[i] = below
        for level in range(self.levels):
            self.last_in_slab[level, self.slab[i] >> (2 * level)] = i

    def start(self) -> None:
        super().start()
        y0 = min(self.y)
        for i in sorted(range(self.n), key=lambda i: (self.y[i], self.x[i])):
            if self.y[i] != y0:
                break
            self._activated(i)                      # the lowest row counts as activated

    # no candidates against the whole beach line: only circle events when arcs change
    def candidates_at(self, pos: int) -> None:
        self.circle_candidate(pos)

    def contacts_at_breakpoint(self, pos: int) -> None:
        return None

    def activate(self, i: int) -> None:
        self.pending.add(i)
        zero = Fraction(0)
        pos, _ = self.locate((self.x[i], zero), self.y[i], zero)
        watch = [self.arcs[self.beach[pos]].site]
        if self.y[watch[0]] >= self.y[i]:
            # a bound needs a lower site (else T_i falls forever straight down): the leftmost
            # arc belongs to the lowest row
            watch.insert(0, self.arcs[self.beach[0]].site)
        self.watch[i] = watch
        # the sites activated last in i's slab and the two beside it are near i (most of them
        # pending, below it): each that the bound breaks joins S_i, so the first bound is near
        # i's cell, not far below a dense cluster whose sites have not entered yet. So are the
        # last of its coarser slabs where i is sparser than its slab's densest part (its slab's
        # newest came more than twice n / slabs activations before i), or in a dense part (the
        # bound moved). Where it moved, so may the sites activated before the newest, in i's
        # slab and in the two beside it: in a dense cluster, the sites that close the lowest
        # corner of i's cell
        low = self.lowest_point(i)
        watched = len(watch)
        low = self._tightened(i, watch, low, [self.last_in_slab.get((0, self.slab[i] + d)) for d in (-1, 0, 1)])
        own = self.last_in_slab.get((0, self.slab[i]))
        if len(watch) > watched or own is None or self.rank[i] - self.rank[own] > self.sparse_gap:
            coarser = [self.last_in_slab.get((level, self.slab[i] >> (2 * level))) for level in range(1, self.levels)]
            low = self._tightened(i, watch, low, coarser)
        if len(watch) > watched:
            deeper = []
            for d, depth in ((-1, SIDE_DEPTH), (0, OWN_DEPTH), (1, SIDE_DEPTH)):
                s = self.last_in_slab.get((0, self.slab[i] + d))
                for _ in range(depth):
                    s = self.before_in_slab.get(s)
                    deeper.append(s)
            self._tightened(i, watch, low, deeper)
        self._activated(i)
        self.schedule_probe(i)

    def _tightened(self, i: int, watch: list[int], low, nearby: list) -> object:
        """Each site of ``nearby`` (None: none) that i's bound ``low`` breaks joins its watch
        list, and the bound moves; returns the bound."""
        for s in nearby:
            if low is None:
                break
            if s is None or s in watch:
                continue
            (_, cx, cy, h), _ = low
            if self.power_gap(s, i, cx, cy, h) < 0:
                watch.insert(0, s)
                low = self.lowest_point(i)
        return low

    def locate(self, cx: tuple, t0: Fraction, h: Fraction) -> tuple[int, list[int]]:
        """The arc over x = cx0 + cx1 sqrt(h) at time t0 + sqrt(h), and the breakpoints at x
        (positions of their left arcs; several where arcs of no width meet)."""
        at = []
        for pos in range(len(self.beach) - 1):
            l, r = self.arcs[self.beach[pos]].site, self.arcs[self.beach[pos + 1]].site
            side = self.side_of_breakpoint(l, r, cx, t0, h)
            if side < 0:
                return pos, at
            if side == 0:
                at.append(pos)
        return len(self.beach) - 1, at

    def lowest_point(self, i: int) -> Optional[tuple[tuple[Time, tuple, tuple, Fraction], int]]:
        """The least time of T_i over Q_i and where: ((time, c_x, c_y, h) as in
        :meth:`arc_contact`, the site of S_i whose bisector it is on, -1 at a corner); None if
        Q_i is empty. T_i is strictly convex and grows in every
        direction but straight down, which a lower site in S_i closes off, so the least is on
        an edge of Q_i (a point c_ij) or at a corner (a power centre with two of S_i)."""
        watch = self.watch[i]
        zero = Fraction(0)

        def in_q(cx, cy, h):
            return all(self.power_gap(k, i, cx, cy, h) >= 0 for k in watch)

        best = None
        for j in watch:
            found = self.arc_contact(i, j)
            if found is not None and in_q(*found[1:]) and (best is None or found[0] < best[0]):
                best, partner = found, j
        for a in range(len(watch)):
            for b in range(a + 1, len(watch)):
                v = self.power_centre(i, watch[a], watch[b])
                if v is None:
                    continue
                h = self.ell(i, *v)
                cx, cy = (v[0], zero), (v[1], zero)
                if in_q(cx, cy, h) and (best is None or Time(v[1], h) < best[0]):
                    best, partner = (Time(v[1], h), cx, cy, h), -1
        return None if best is None else (best, partner)

    def schedule_probe(self, i: int) -> None:
        low = self.lowest_point(i)
        if low is None:
            self.pending.discard(i)         # its cell is empty: hidden
            return
        low, partner = low
        if partner >= 0 and partner not in self.present:
            partner = UNKEYED
        self.push(low[0], Event.PROBE, (None, i, low, partner), partner=partner)

    def probe(self, i: int, low: tuple, partner: int) -> None:
        t, cx, cy, h = low
        self.counts["probes"] += 1
        pos, at_breakpoints = self.locate(cx, t.a, h)
        above = self.arcs[self.beach[pos]].site
        gap = self.power_gap(above, i, cx, cy, h)
        if gap < 0:
            # q is below the beach line: the bound moves on
            self.watch[i].insert(0, above)
            self.schedule_probe(i)
            return
        if gap > 0:
            raise RuntimeError(f"probe of site {i}: its lower bound is above the beach line (a bug)")
        if partner == UNKEYED and self.heap and not t < self.heap[0].time:
            # q is on the beach line, and another contact may come at this time: queued again,
            # ranked now by the site whose arc it touches
            self.push(t, Event.PROBE, (None, i, low, above), partner=above)
            return
        # q is on the beach line: inside the arc above it, or at the breakpoints there
        if not at_breakpoints:
            self.here = None
            self.log_event(Event.CONTACT_ARC, t, [above, i])
            self.pending.discard(i)
            self.present.add(i)
            self.split_arc(pos, i)
            return
        for left in at_breakpoints:
            a, b = self.arcs[self.beach[left]].site, self.arcs[self.beach[left + 1]].site
            if self.orient(a, i, b) < 0:        # i's arc is born growing there
                v = self.power_centre(a, i, b)
                self.here = v
                self.log_event(Event.CONTACT_VERTEX, t, [a, b, i])
                self.pending.discard(i)
                self.present.add(i)
                self.insert_at_breakpoint(left, i, v)
                return
        self.pending.discard(i)             # squeezed out at once: a cell of no area, hidden

    def handle(self, kind: Event, item: _Queued) -> None:
        if kind == Event.PROBE:
            self.now = item.time
            self.probe(*item.payload[1:])
        else:
            super().handle(kind, item)


def build_weighted(sites: NDArray[np.float64], weights: NDArray[np.float64],
                   stats: Optional[dict] = None, probing: bool = False) -> Diagram:
    """The power diagram of prepared ``sites`` with ``weights`` by the exact weighted sweep
    (``probing``: contacts found by probes, :class:`ProbingSweep`)."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    weights = np.ascontiguousarray(weights, dtype=np.float64).reshape(-1)
    if sites.shape[0] <= 1:
        return Diagram.empty(sites, weights)
    sweep = (ProbingSweep if probing else Sweep)(sites, weights)
    sweep.run()
    if stats is not None:
        stats.update(sweep.counts, hidden_sites=len(sweep.hidden))
    # an edge from a vertex to itself has no length: the sites of a degenerate vertex, and a
    # site whose cell is that point alone (hidden)
    edges = np.array([e for e in sweep.edges if e[2] < 0 or e[2] != e[3]], dtype=np.int64).reshape(-1, 4)
    vertices = np.array([(float(vx), float(vy)) for vx, vy in sweep.vertices], dtype=np.float64).reshape(-1, 2)
    return assemble(sites, vertices, edges[:, :2], edges[:, 2:], weights=weights)
