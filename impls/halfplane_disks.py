"""The diagram of disks by its definition: each disk's cell clipped by the bisector branch of every
other disk, exactly (the oracle for Apollonius diagrams, docs/apollonius.md).

CONTRACT
--------
Why it is the oracle: it follows the definition. The cell of disk i is the set of points whose
distance |x - p_i| - r_i is at most every other disk's: the intersection of the regions bounded
by the bisector branches of i and each other disk j. It is computed for each cell on its own,
from the whole plane, with no event queue, beach line or dual graph, and cells are glued only
at the end.
Why clipping works: the region of i against j meets every ray from p_i in a segment from p_i
(along direction u it ends at t = (|a|^2 - s^2) / (2 (s + u . a)), a = p_j - p_i, s = r_j - r_i,
or never), so every cell is star-shaped about its own centre, which lies inside it (a visible
disk is inside no other). Its boundary is a cycle of pieces of branches in counter-clockwise
order about p_i, with gaps at infinity between pieces that run out to it.
Representation of a cell: ``None`` for the whole plane, else the list of its edges in that
order, each the neighbour a (the edge lies on the branch of i and a, with cell i on its left)
and its two ends: exact points (:class:`ApolloniusVertex`) or ``None`` for infinity.
Exact decisions (:mod:`vorobench.core.predicates.apollonius`): along the branch of (i, a), disk
j becomes closer than i exactly at the vertex (i, a, j) and stops being closer at (i, j, a)
(cell i turns from a to j there, or from j to a); the points of one branch are ordered by
``branch_order``. So each edge splits into kept and cut pieces from at most two vertices and,
where neither exists, the sign of one point of the branch (an end of the edge or the branch's
apex: ``conflict``). A maximal run of cut pieces around the cycle is replaced by the part of
j's branch between the run's two ends: one edge if the first comes first along j's branch,
else two edges running out to infinity with a gap between them. Nothing cut and j's branch
lying inside the cell (the direction of p_j from p_i lies strictly inside a gap at infinity:
``turn`` against the gap's asymptotes) puts the whole branch into that gap. Bisectors that touch without crossing (a double root) are
refused with :class:`DegenerateDisks`, not guessed.
Gluing: a vertex is first named by its cell's consecutive neighbours (i, a, b), rotated to
start at the smallest site; the two cells of an edge name its ends, and names of one point
(four or more disks on one circle) are merged along edges (union-find), and checked to be
one point exactly. Two cells may share several edges (a third disk cutting a branch twice):
they are matched in their order along the branch.
Filters (speed only): disk j cannot reach a point x of cell i unless (|a| - s) / 2 < |x - p_i|
(the nearest point of j's branch to p_i is its apex), nor a direction outside the arc of
directions its branch spans; an edge whose ends are both within that radius, or whose arc of
directions (from p_i, padded) misses j's, keeps every point, and the disks are clipped in the
order of (|a| - s) / 2, so a bounded cell stops at the first disk beyond twice its radius.
Complexity: O(n^2) distance keys and sorting, O(n k) exact clips (k a few times the number of
neighbours) in Python rationals: for tests and the judge, up to a few thousand disks.
Input: centres (n, 2) and radii (n,) finite, radii >= 0; hidden disks (inside another, or
identical to an earlier one) get no edge.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vorobench.core.branch_reach import RADIUS_PAD, DiskFloats, apart, arc_between, nearest_reach, tail_apart
from vorobench.core.diagram import Diagram
from vorobench.core.hidden_disks import hidden_disks
from vorobench.core.scaling import exact_shift, scale_back_vertices, scale_points
from vorobench.core.predicates.apollonius import (
    ApolloniusVertex,
    QuadraticNumber,
    apex,
    asymptote,
    branch_order,
    compare,
    conflict,
    rational,
    turn,
    vertex,
)
from vorobench.core.union_find import find

__all__ = ["build", "cells", "DegenerateDisks", "Edge"]

class DegenerateDisks(ValueError):
    """Bisector branches that touch without crossing: the oracle refuses them rather than guess."""


@dataclass(frozen=True)
class Edge:
    """A piece of the bisector branch of the cell's disk and ``site``, from ``start`` to ``end``
    (exact points; None: infinity), with the cell on its left."""

    site: int
    start: Optional[ApolloniusVertex]
    end: Optional[ApolloniusVertex]


_KEPT, _CUT = 1, -1


class _Disks:
    """The disks as exact rationals, with the vertices and apexes already computed."""

    def __init__(self, centres: NDArray[np.float64], radii: NDArray[np.float64]) -> None:
        self.disks = [(rational(float(x)), rational(float(y)), rational(float(r)))
                      for (x, y), r in zip(centres, radii)]
        self.vertex = functools.lru_cache(maxsize=None)(lambda i, a, b: vertex(self.disks, i, a, b))
        self.apex = functools.lru_cache(maxsize=None)(lambda i, a: apex(self.disks, i, a))

    def order(self, i: int, a: int, u: ApolloniusVertex, w: ApolloniusVertex) -> int:
        return branch_order(self.disks, i, a, u, w)

    def closer(self, point: ApolloniusVertex, j: int) -> int:
        """-1 where disk j is strictly closer to ``point`` than its own disks, 0 on a tie, +1 farther."""
        return conflict(self.disks, point, j)


def _segments(ex: _Disks, i: int, edge: Edge, j: int) -> list[tuple[int, Optional[ApolloniusVertex], Optional[ApolloniusVertex]]]:
    """The edge split into pieces kept (closer to i than to j) and cut: (state, start, end) in
    order along the edge, no two neighbours in one state."""
    a, s, e = edge.site, edge.start, edge.end
    flips = []
    for triple, after in (((i, a, j), _CUT), ((i, j, a), _KEPT)):
        v = ex.vertex(*triple)
        if v is not None:
            if v.double:
                raise DegenerateDisks(f"the bisector branches of disks {i}, {a} and {i}, {j} touch without crossing")
            flips.append((v, after))
    if len(flips) == 2:
        gap = ex.order(i, a, flips[0][0], flips[1][0])
        if gap == 0:
            raise DegenerateDisks(f"disks {i}, {a}, {j}: both vertices at one point")
        if gap > 0:
            flips.reverse()
    if flips:
        before = -flips[0][1]                  # a crossing changes the state
    else:
        before = 0
        for point in (s, e):
            if point is not None and before == 0:
                before = ex.closer(point, j)
        if before == 0:
            before = ex.closer(ex.apex(i, a), j)
        if before == 0:
            raise DegenerateDisks(f"the bisector branches of disks {i}, {a} and {i}, {j} touch without crossing")
        before = _CUT if before < 0 else _KEPT
    # the state just after s: every flip at or before s applies
    state, inside = before, []
    for v, after in flips:
        if s is not None and ex.order(i, a, v, s) <= 0:
            state = after
        elif e is None or ex.order(i, a, v, e) < 0:
            inside.append((v, after))
    pieces, start = [], s
    for v, after in inside:
        if after != state:
            pieces.append((state, start, v))
            state, start = after, v
    pieces.append((state, start, e))
    return pieces


def _gap_holds(ex: _Disks, i: int, before: Edge, after: Edge, direction) -> bool:
    """Whether ``direction`` (from p_i) lies strictly inside the gap at infinity between an edge
    running out along ``before``'s branch and the next one coming in along ``after``'s."""
    u1 = asymptote(ex.disks, i, before.site, 1)
    u2 = asymptote(ex.disks, i, after.site, -1)
    across, along = turn(u1, u2)
    into, _ = turn(u1, direction)
    out, _ = turn(direction, u2)
    if across > 0:
        return into > 0 and out > 0
    if across == 0 and along > 0:              # both run out in one direction: an empty gap
        return False
    return into > 0 or out > 0


def _insert_whole_branch(ex: _Disks, i: int, j: int, edges: list[Edge]) -> Optional[list[Edge]]:
    """Nothing of the cell is cut: j's branch lies inside it, in one of its gaps at infinity, or
    outside it. The new edge list, or None if the cell is unchanged.

    Without a crossing, the branch is inside exactly when the direction of p_j from p_i (the
    middle of the directions the branch spans) lies strictly inside a gap: the ray that way
    leaves the cell nowhere and meets the branch."""
    (xi, yi, _), (xj, yj, _) = ex.disks[i], ex.disks[j]
    zero = rational(0)
    direction = (QuadraticNumber(xj - xi, zero, zero), QuadraticNumber(yj - yi, zero, zero))
    holding = [k for k, edge in enumerate(edges)
               if edge.end is None and _gap_holds(ex, i, edge, edges[(k + 1) % len(edges)], direction)]
    if not holding:
        return None
    if len(holding) > 1:
        raise RuntimeError(f"halfplane_disks: the direction of disk {j} lies in {len(holding)} gaps of cell {i}")
    k = holding[0]
    return edges[:k + 1] + [Edge(j, None, None)] + edges[k + 1:]


def clip(ex: _Disks, i: int, j: int, edges: Optional[list[Edge]], keep: Optional[set[int]] = None) -> Optional[list[Edge]]:
    """Cell i (``edges``, None for the whole plane) clipped by the branch of i and j: the new
    edge list, or None if nothing changes. ``keep``: edges the filters showed j cannot reach."""
    if edges is None:
        return [Edge(j, None, None)]
    runs: list[tuple[int, int, Optional[ApolloniusVertex], Optional[ApolloniusVertex]]] = []
    for k, edge in enumerate(edges):
        pieces = [(_KEPT, edge.start, edge.end)] if keep is not None and k in keep else _segments(ex, i, edge, j)
        for state, start, end in pieces:
            runs.append((state, edge.site, start, end))
    if all(state == _KEPT for state, *_ in runs):
        return _insert_whole_branch(ex, i, j, edges)
    if all(state == _CUT for state, *_ in runs):
        return [Edge(j, None, None)]
    # rotate so that the cycle starts with a kept piece after a cut one
    first = next(k for k in range(len(runs)) if runs[k][0] == _KEPT and runs[k - 1][0] == _CUT)
    runs = runs[first:] + runs[:first]
    out: list[Edge] = []
    k = 0
    while k < len(runs):
        state, site, start, end = runs[k]
        if state == _KEPT:
            out.append(Edge(site, start, end))
            k += 1
            continue
        cut_start = start
        while k < len(runs) and runs[k][0] == _CUT:
            cut_end = runs[k][3]
            k += 1
        out.extend(_branch_between(ex, i, j, cut_start, cut_end))
    return out


def _branch_between(ex: _Disks, i: int, j: int, start: Optional[ApolloniusVertex],
                    end: Optional[ApolloniusVertex]) -> list[Edge]:
    """The part of j's branch that replaces a run of cut pieces from ``start`` to ``end``."""
    if start is None or end is None:
        return [Edge(j, start, end)]
    order = ex.order(i, j, start, end)
    if order < 0:
        return [Edge(j, start, end)]
    if order == 0:
        raise DegenerateDisks(f"disk {j} cuts cell {i} between two ends at one point")
    return [Edge(j, start, None), Edge(j, None, end)]


def _ends_apart(fl: DiskFloats, reach: "_Reach", i: int, k: int, j: int) -> bool:
    """Whether disk j cannot reach edge k, an edge running out to infinity, by its parts: the
    finite part within the radius of its finite end (or of the apex), and each tail beyond."""
    edge = reach.edges[k]
    if edge.start is not None or edge.end is not None:
        finite = edge.start if edge.start is not None else edge.end
        side = 1 if edge.end is None else -1
        near = fl.distance(i, finite)
        centre, half = fl.spread(i, j)
        norm, s = fl.norm_and_gap(i, j)
        arc = reach.arcs[k]
        within = arc is not None and half is not None and nearest_reach(arc, centre, norm, s) > near * (1 + RADIUS_PAD) + fl.slack
        return within and tail_apart(fl, i, edge.site, side, near, j)
    norm_a, s_a = fl.norm_and_gap(i, edge.site)
    near = (norm_a - s_a) / 2 * (1 - RADIUS_PAD)        # the apex: the branch's nearest point
    return all(tail_apart(fl, i, edge.site, side, near, j) for side in (1, -1))


class _Reach:
    """Float summaries of one cell for the filters: per edge, the farthest distance of its ends
    from p_i (inf for an edge to infinity) and its arc of directions seen from p_i (centre,
    half-width; None where angles are not trustworthy); the same arcs for the gaps."""

    def __init__(self, ex: DiskFloats, i: int, edges: list[Edge]) -> None:
        self.radius: list[float] = []
        self.arcs: list[Optional[tuple[float, float]]] = []
        self.gap_arcs: list[Optional[tuple[float, float]]] = []
        self.edges = edges
        px, py = ex.centres[i]
        for k, edge in enumerate(edges):
            ends = []
            far = 0.0
            for point, side in ((edge.start, -1), (edge.end, 1)):
                if point is None:
                    ends.append(ex.asymptote_angle(i, edge.site, side))
                    far = math.inf
                else:
                    x, y = ex.point(point)
                    dist = math.hypot(x - px, y - py)
                    far = max(far, dist)
                    ends.append(math.atan2(y - py, x - px) if dist > ex.near else None)
            self.radius.append(far)
            self.arcs.append(arc_between(*ends))
            if edge.end is None:
                following = edges[(k + 1) % len(edges)]
                self.gap_arcs.append(arc_between(ends[1], ex.asymptote_angle(i, following.site, -1)))
        self.bounded = not self.gap_arcs
        self.farthest = max(self.radius)


def _reaches(fl: DiskFloats, reach: _Reach, i: int, j: int, key: float) -> Optional[set[int]]:
    """The edges disk j cannot reach (all of them: j changes nothing), from the filters; None
    when some gap at infinity may hold j's branch, so the exact test must look."""
    centre, half = fl.spread(i, j)
    norm, s = fl.norm_and_gap(i, j)
    keep = set()
    for k, (far, arc) in enumerate(zip(reach.radius, reach.arcs)):
        if key > far * (1 + RADIUS_PAD) + fl.slack or (half is not None and apart(arc, centre, half)):
            keep.add(k)
        elif half is not None and nearest_reach(arc, centre, norm, s) > far * (1 + RADIUS_PAD) + fl.slack:
            keep.add(k)
        elif far == math.inf and _ends_apart(fl, reach, i, k, j):
            keep.add(k)
    if reach.gap_arcs and (half is None or not all(apart(arc, centre, half) for arc in reach.gap_arcs)):
        return keep if len(keep) < len(reach.radius) else None
    return keep


def cells(ex: "_Disks", centres: NDArray[np.float64], radii: NDArray[np.float64], visible: NDArray[np.int64],
          stats: Optional[dict] = None) -> dict[int, list[Edge]]:
    """The cell of each visible disk (ids into ``centres``): its edges in counter-clockwise order."""
    fl = DiskFloats(centres, radii)
    counts = dict(clips=0, prefiltered=0, exact_clips=0, cuts=0)
    out = {}
    for i in visible:
        i = int(i)
        others = visible[visible != i]
        gap = np.hypot(*(centres[others] - centres[i]).T)
        keys = (gap - radii[others] + radii[i]) / 2          # distance from p_i to each branch's apex
        order = np.argsort(keys, kind="stable")
        edges: Optional[list[Edge]] = None
        reach: Optional[_Reach] = None
        for position, t in enumerate(order):
            j, key = int(others[t]), float(keys[t])
            counts["clips"] += 1
            keep = None
            if reach is not None:
                if reach.bounded and key > reach.farthest * (1 + RADIUS_PAD) + fl.slack:
                    counts["prefiltered"] += len(order) - position
                    counts["clips"] += len(order) - position - 1
                    break                                     # every later disk is farther still
                keep = _reaches(fl, reach, i, j, key)
                if keep is not None and len(keep) == len(edges):
                    counts["prefiltered"] += 1
                    continue
            counts["exact_clips"] += 1
            clipped = clip(ex, i, j, edges, keep)
            if clipped is not None:
                counts["cuts"] += 1
                edges = clipped
                reach = _Reach(fl, i, edges)
        out[i] = edges if edges is not None else []
    if stats is not None:
        stats.update(counts)
    return out


def _rotated(triple: tuple[int, int, int]) -> tuple[int, int, int]:
    """A cyclic triple turned to start at its smallest site (the two orientations stay apart)."""
    k = triple.index(min(triple))
    return triple[k:] + triple[:k]


def _along(ex: _Disks, i: int, a: int, point: Optional[ApolloniusVertex]):
    """A sort key placing points of the branch of (i, a) in order, infinity (None) first."""
    return functools.cmp_to_key(lambda u, w: -1 if u is None and w is not None else 1 if u is not None and w is None
                                else 0 if u is None else ex.order(i, a, u, w))(point)


def glue(ex: _Disks, centres: NDArray[np.float64], radii: NDArray[np.float64],
         cell_edges: dict[int, list[Edge]]) -> Diagram:
    """One DCEL from independent cells: vertices named by their cells' consecutive neighbours,
    merged along edges, each checked to be one exact point."""
    n = centres.shape[0]
    site, nxt, start_name, end_name, points, edge_of = [], [], [], [], {}, []
    by_pair: dict[tuple[int, int], list[int]] = {}
    for i in sorted(cell_edges):
        edges = cell_edges[i]
        first = len(site)
        for k, edge in enumerate(edges):
            h = len(site)
            site.append(i)
            edge_of.append(edge)
            nxt.append(first + (k + 1) % len(edges))
            following = edges[(k + 1) % len(edges)]
            if (edge.end is None) != (following.start is None):
                raise RuntimeError(f"halfplane_disks: cell {i} does not close between edges {k} and {k + 1}")
            name = None if edge.end is None else _rotated((i, edge.site, following.site))
            if name is not None:
                known = points.setdefault(name, edge.end)
                if known is not edge.end and (compare(known.x, edge.end.x) != 0 or compare(known.y, edge.end.y) != 0):
                    raise RuntimeError(f"halfplane_disks: two cells put the vertex {name} at different points")
            end_name.append(name)
            by_pair.setdefault((i, edge.site), []).append(h)
        for k in range(len(edges)):
            start_name.append(end_name[first + (k - 1) % len(edges)])
    names = sorted(points)
    index = {name: t for t, name in enumerate(names)}
    parent = np.arange(len(names))
    twin = np.full(len(site), -1, dtype=np.int64)
    for (i, a), mine in by_pair.items():
        if i > a:
            continue
        theirs = by_pair.get((a, i), [])
        if len(theirs) != len(mine):
            raise RuntimeError(f"halfplane_disks: cells {i} and {a} disagree about their common edges "
                               f"({len(mine)} against {len(theirs)})")
        if len(mine) > 1:                          # several pieces of one branch: in order along it
            mine = sorted(mine, key=lambda h: _along(ex, i, a, edge_of[h].start))
            theirs = sorted(theirs, key=lambda h: _along(ex, i, a, edge_of[h].end))
        for h, g in zip(mine, theirs):
            twin[h], twin[g] = g, h
            for u, w in ((start_name[h], end_name[g]), (end_name[h], start_name[g])):
                if (u is None) != (w is None):
                    raise RuntimeError(f"halfplane_disks: the edge of cells {i} and {a} runs to infinity in one only")
                if u is not None:
                    ru, rw = find(parent, index[u]), find(parent, index[w])
                    if ru != rw:
                        parent[max(ru, rw)] = min(ru, rw)
    roots = [find(parent, t) for t in range(len(names))]
    vertex_id, vertices = {}, []
    for t, root in enumerate(roots):
        here, there = points[names[t]], points[names[root]]
        if compare(here.x, there.x) != 0 or compare(here.y, there.y) != 0:
            raise RuntimeError(f"halfplane_disks: vertices {names[t]} and {names[root]} are merged but differ")
        if root not in vertex_id:
            vertex_id[root] = len(vertices)
            vertices.append((float(there.x), float(there.y)))
    origin = [-1 if name is None else vertex_id[roots[index[name]]] for name in start_name]
    return Diagram(centres, np.array(vertices, dtype=np.float64).reshape(-1, 2), np.array(origin, dtype=np.int64),
                   twin, np.array(nxt, dtype=np.int64), np.array(site, dtype=np.int64), radii=radii)


def _check(centres: ArrayLike, radii: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    centres = np.ascontiguousarray(centres, dtype=np.float64)
    if centres.size == 0:
        centres = centres.reshape(0, 2)
    if centres.ndim != 2 or centres.shape[1] != 2:
        raise ValueError(f"centres must have shape (n, 2), got {centres.shape}")
    radii = np.ascontiguousarray(radii, dtype=np.float64).reshape(-1)
    if radii.shape != (centres.shape[0],):
        raise ValueError(f"radii has shape {radii.shape}, there are {centres.shape[0]} centres")
    if not (np.isfinite(centres).all() and np.isfinite(radii).all()):
        raise ValueError("centres and radii must be finite")
    if (radii < 0).any():
        raise ValueError(f"radii must be >= 0; disk {int(np.flatnonzero(radii < 0)[0])} has {float(radii[radii < 0][0])}")
    return centres, radii


def build(centres: ArrayLike, radii: ArrayLike, stats: Optional[dict] = None) -> Diagram:
    """The diagram of the disks (centres, radii): hidden disks get no edge. Disks outside the
    exact range are built scaled into it by a power of two (the float filters' products would
    overflow or underflow there; the exact stages do not care) and scaled back."""
    centres, radii = _check(centres, radii)
    shift = exact_shift(np.vstack([centres, np.column_stack([radii, radii])]))
    if shift:
        d = _build(scale_points(centres, shift), np.ldexp(radii, shift), stats)
        return Diagram(centres, scale_back_vertices(d.vertices, shift), d.origin, d.twin, d.next, d.site, radii=radii)
    return _build(centres, radii, stats)


def _build(centres: NDArray[np.float64], radii: NDArray[np.float64], stats: Optional[dict]) -> Diagram:
    visible = np.flatnonzero(~hidden_disks(centres, radii))
    if visible.size <= 1:
        return Diagram.empty(centres, radii=radii)
    ex = _Disks(centres, radii)
    cell_edges = cells(ex, centres, radii, visible, stats)
    return glue(ex, centres, radii, cell_edges)
