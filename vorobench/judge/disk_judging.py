"""Judging diagrams of disks (docs/apollonius.md): an exact certificate of one diagram, and an
exact comparison of two. Neither trusts the construction: every vertex is recomputed from the
disks around it, and every decision is one of the exact Apollonius predicates (float filters
only skip what they prove far).

Certificate checks:

* ``structure``: the DCEL invariants (:meth:`Diagram.validate`), and radii on the diagram.
* ``hidden``: the disks without edges are exactly those inside another (``hidden_disks``).
* ``vertices``: around each vertex, the cells in counter-clockwise order a, b, c, ... have an
  Apollonius circle in that order (``vertex(a, b, c)``), every other cell there touches it
  (``conflict`` 0), no disk is strictly closer to its centre (k-d tree, then exact), and the
  reported point lies within tolerance of the exact one. A disk that touches the circle
  without a cell there fails too: the vertex lost a cell.
* ``edges``: each edge (a, b) runs from its start to its end along the branch with a on its
  left (``branch_order``), and no disk cuts it: a crossing of the branch with a third disk's
  (the vertices (a, b, m) and (a, m, b)) strictly inside the edge means that disk is closer
  there, and an edge to infinity must not run into a disk that is closer at infinity along
  the branch's asymptote. With the vertices, this certifies every edge locally.
* ``euler``: V - E + k = 1 for k >= 2 visible disks.
"""

from __future__ import annotations

import math
import time
from collections import Counter
from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np
from scipy.spatial import cKDTree

from vorobench.core.branch_reach import RADIUS_PAD, DiskFloats, arc_between, nearest_reach, tail_apart
from vorobench.core.diagram import Diagram
from vorobench.core.errors import InvalidDiagramError
from vorobench.core.hidden_disks import hidden_disks
from vorobench.core.predicates.apollonius import (
    ApolloniusVertex,
    QuadraticNumber,
    asymptote,
    branch_order,
    compare,
    conflict,
    direction_key,
    rational,
    vertex,
)
from vorobench.core.scaling import comfortable_shift, scale_points
from vorobench.core.tolerances import VERTEX_MATCH_REL_TOL
from vorobench.core.union_find import find
from vorobench.judge.certificate import Certificate, Check
from vorobench.judge.outcomes import Verdict

__all__ = ["DISK_CHECKS", "certify_disks", "compare_disks", "DiskComparison", "cells_around"]

DISK_CHECKS = ("structure", "hidden", "vertices", "edges", "rays", "euler")
#: Offending ids kept per check.
_MAX_IDS = 10


def cells_around(d: Diagram) -> list[list[int]]:
    """For each vertex, the cells around it in counter-clockwise order (from the DCEL: turning
    from a half-edge leaving v to the one after its twin goes clockwise)."""
    first = np.full(d.n_vertices, -1, dtype=np.int64)
    for h in range(d.n_half_edges - 1, -1, -1):
        if d.origin[h] >= 0:
            first[d.origin[h]] = h
    out = []
    for v in range(d.n_vertices):
        h, clockwise = int(first[v]), []
        for _ in range(d.n_half_edges):
            clockwise.append(int(d.site[h]))
            h = int(d.next[d.twin[h]])
            if h == first[v]:
                break
        out.append(clockwise[::-1])
    return out


class _Points:
    """The diagram's vertices as exact points, and the points they make: vertices joined by an
    edge of length zero at one exact point are one point (docs/dcel.md lets a vertex of degree
    >= 4 come as vertices of degree 3 joined so, as ``fortune`` gives them). Each vertex's point
    is computed from the first three cells around it, counter-clockwise (None where they have no
    Apollonius circle in that order: the vertex check says so)."""

    def __init__(self, d: Diagram, disks: list) -> None:
        around = cells_around(d)
        self.exact: list[Optional[ApolloniusVertex]] = [
            vertex(disks, *cells[:3]) if len(cells) >= 3 else None for cells in around]
        origin, twin, nxt, site = (np.asarray(a, dtype=np.int64) for a in (d.origin, d.twin, d.next, d.site))
        parent = np.arange(d.n_vertices)
        self.internal = np.zeros(d.n_half_edges, dtype=bool)
        for h in range(d.n_half_edges):
            u, w = int(origin[h]), int(origin[twin[h]])
            if u < 0 or w < 0 or self.exact[u] is None or self.exact[w] is None:
                continue
            p, q = self.exact[u], self.exact[w]
            if compare(p.x, q.x) == 0 and compare(p.y, q.y) == 0:
                self.internal[h] = True
                ru, rw = find(parent, u), find(parent, w)
                if ru != rw:
                    parent[max(ru, rw)] = min(ru, rw)
        self.of = [int(find(parent, v)) for v in range(d.n_vertices)]
        # the cells around each point, counter-clockwise: turning clockwise from a half-edge
        # leaving the point, through the zero-length edges inside it
        self.cells: dict[int, list[int]] = {}
        for h in range(d.n_half_edges):
            v = int(origin[h])
            if v < 0 or self.internal[h] or self.of[v] in self.cells:
                continue
            clockwise, g = [], h
            for _ in range(d.n_half_edges + 1):
                clockwise.append(int(site[g]))
                g = int(nxt[twin[g]])
                while self.internal[g]:
                    g = int(nxt[g])
                if g == h:
                    break
            self.cells[self.of[v]] = clockwise[::-1]
        for v, cells in enumerate(around):                 # a vertex with no edge out of its point
            self.cells.setdefault(self.of[v], cells)

    def name(self, v: int) -> tuple[int, ...]:
        """The point of vertex v named by the cells around it, counter-clockwise from the smallest."""
        cells = self.cells[self.of[v]]
        k = cells.index(min(cells))
        return tuple(cells[k:] + cells[:k])


class _Disks:
    """The diagram's disks: exact rationals for the predicates, floats and a k-d tree for the filters."""

    def __init__(self, d: Diagram) -> None:
        self.centres = np.ascontiguousarray(d.sites, dtype=np.float64)
        self.radii = np.ascontiguousarray(d.radii, dtype=np.float64)
        self.exact = [(rational(float(x)), rational(float(y)), rational(float(r)))
                      for (x, y), r in zip(self.centres, self.radii)]
        self.floats = DiskFloats(self.centres, self.radii)
        self.tree = cKDTree(self.centres)
        self.r_max = float(self.radii.max()) if self.radii.size else 0.0
        self.scale = float(np.abs(self.centres).max() + self.r_max) if self.centres.size else 1.0
        self.visible = np.ones(self.centres.shape[0], dtype=bool)

    def near(self, x: float, y: float, reach: float) -> list[int]:
        """Visible disks that may be closer than ``reach`` to (x, y) (distance |x - p| - r): a
        hidden disk is never closer than the one around it, and may touch what that one touches."""
        radius = reach + self.r_max + 1e-9 * self.scale
        if not math.isfinite(radius):
            return [int(m) for m in np.flatnonzero(self.visible)]
        return [] if radius < 0 else [m for m in self.tree.query_ball_point([x, y], radius) if self.visible[m]]


def _fail(name: str, problems: list[tuple[int, str]], total: str, id_kind: str) -> Check:
    if not problems:
        return Check(name, True, total)
    first = problems[0][1]
    more = f" ({len(problems)} in all)" if len(problems) > 1 else ""
    return Check(name, False, first + more, [k for k, _ in problems[:_MAX_IDS]], id_kind)


def _check_hidden(d: Diagram, disks: _Disks, visible_mask: np.ndarray) -> Check:
    want = np.flatnonzero(~visible_mask)
    got = np.asarray(d.hidden, dtype=np.int64)
    if int(visible_mask.sum()) <= 1:
        ok = d.n_half_edges == 0
        return Check("hidden", ok, "one visible disk or none: no edges" if ok else
                     f"{int(visible_mask.sum())} visible disk(s) but {d.n_edges} edges")
    wrong = sorted(set(want.tolist()) ^ set(got.tolist()))
    if wrong:
        k = wrong[0]
        why = "lies inside another disk but has edges" if k in set(want.tolist()) else \
            "lies inside no other disk but has no edge"
        return Check("hidden", False, f"disk {k} {why} ({len(wrong)} such disks)", wrong[:_MAX_IDS], "site")
    return Check("hidden", True, f"{want.size} hidden disks, exactly those inside another")


def _check_vertices(d: Diagram, disks: _Disks, points: _Points) -> Check:
    problems = []
    members: dict[int, list[int]] = {}
    for v in range(d.n_vertices):
        members.setdefault(points.of[v], []).append(v)
    for root, group in members.items():
        cells = points.cells[root]
        v = group[0]
        if len(cells) < 3:
            problems.append((v, f"vertex {v} touches {len(cells)} cells"))
            continue
        point = vertex(disks.exact, *cells[:3])
        if point is None:
            problems.append((v, f"vertex {v}: disks {cells[:3]} have no Apollonius circle in that order"))
            continue
        bad = [m for m in cells[3:] if conflict(disks.exact, point, m) != 0]
        if bad:
            problems.append((v, f"vertex {v}: disk {bad[0]} has a cell there but does not touch the circle of {cells[:3]}"))
            continue
        x, y, radius = point.as_floats()
        far = [(math.dist((x, y), tuple(d.vertices[u])), u) for u in group]
        gap, u = max(far)
        if not gap <= VERTEX_MATCH_REL_TOL * max(disks.scale, abs(x), abs(y)):
            problems.append((u, f"vertex {u} is {gap:.3g} from the centre of its Apollonius circle {cells[:3]}"))
            continue
        own = set(cells)
        for m in disks.near(x, y, radius):
            if m in own:
                continue
            gap = math.hypot(x - disks.centres[m, 0], y - disks.centres[m, 1]) - disks.radii[m] - radius
            if gap > 1e-9 * max(disks.scale, abs(radius)):
                continue
            side = conflict(disks.exact, point, m)
            if side < 0:
                problems.append((v, f"vertex {v}: disk {m} is closer to it than its own disks {cells}"))
                break
            if side == 0:
                problems.append((v, f"vertex {v}: disk {m} touches its circle but has no cell there"))
                break
    return _fail("vertices", problems, f"{d.n_vertices} vertices at {len(members)} points: empty Apollonius "
                 f"circles of their cells", "vertex")


def _crosses_inside(disks: _Disks, a: int, b: int, m: int, start: Optional[ApolloniusVertex],
                    end: Optional[ApolloniusVertex]) -> bool:
    """Whether the branch of disk m with a crosses the branch of (a, b) strictly between start
    and end (None: infinity), where m becomes closer than a and b."""
    for triple in ((a, b, m), (a, m, b)):
        point = vertex(disks.exact, *triple)
        if point is None or point.double:
            continue
        after_start = start is None or branch_order(disks.exact, a, b, start, point) < 0
        before_end = end is None or branch_order(disks.exact, a, b, point, end) < 0
        if after_start and before_end:
            return True
    return False


def _closer_at_infinity(disks: _Disks, a: int, b: int, end: int, m: int) -> bool:
    """Whether disk m is strictly closer than a (and b) far along the end of their branch: along
    direction u, |x - p_m| - |x - p_a| tends to -u . (p_m - p_a) / |u|."""
    ux, uy = asymptote(disks.exact, a, b, end)
    (xa, ya, ra), (xm, ym, rm), (xb, yb, _) = disks.exact[a], disks.exact[m], disks.exact[b]
    length = (xb - xa) ** 2 + (yb - ya) ** 2                     # |u| (asymptote scales by |p_b - p_a|^2)
    value = ux.scaled(xm - xa) + uy.scaled(ym - ya) + QuadraticNumber((rm - ra) * length, rational(0), rational(0))
    return value.sign() > 0


def _check_edges(d: Diagram, disks: _Disks, points: _Points, visible: list[int]) -> Check:
    problems = []
    exact = points.exact
    for h in range(d.n_half_edges):
        g = int(d.twin[h])
        if g < h or points.internal[h]:
            continue                                   # (an edge of length zero inside one point)
        a, b, u, w = int(d.site[h]), int(d.site[g]), int(d.origin[h]), int(d.origin[g])
        ends = [None if k < 0 else exact[k] for k in (u, w)]
        if any(k >= 0 and exact[k] is None for k in (u, w)):
            continue                                   # its vertex failed already
        start, end = ends
        if start is not None and end is not None and branch_order(disks.exact, a, b, start, end) >= 0:
            problems.append((h, f"half-edge {h} (cells {a}, {b}) runs backwards along its branch"))
            continue
        finite = [p for p in ends if p is not None]
        if len(finite) == 2:
            reach = max(float(p.radius) for p in finite)
            x, y = disks.centres[a]
            candidates = disks.near(x, y, 2 * reach + disks.radii[a])
        else:
            candidates = visible
        cut = None
        for m in candidates:
            if m in (a, b) or not _may_reach(disks, a, b, start, end, m):
                continue
            if _crosses_inside(disks, a, b, m, start, end):
                cut = f"half-edge {h} (cells {a}, {b}) is crossed by disk {m}, closer inside it"
            elif (start is None and _closer_at_infinity(disks, a, b, -1, m)) or \
                    (end is None and _closer_at_infinity(disks, a, b, 1, m)):
                cut = f"half-edge {h} (cells {a}, {b}) runs to infinity into disk {m}'s cell"
            if cut:
                break
        if cut:
            problems.append((h, cut))
    return _fail("edges", problems, f"{d.n_edges} edges on their branches, crossed by no disk", "half-edge")


def _may_reach(disks: _Disks, a: int, b: int, start: Optional[ApolloniusVertex], end: Optional[ApolloniusVertex],
               m: int) -> bool:
    """False when the float bounds prove disk m farther than a on the whole edge: seen from p_a,
    m's branch lies beyond the edge's farthest end over the edge's arc of directions, or (an
    edge to infinity) beyond its finite part and never reaching its tail."""
    fl = disks.floats
    if start is not None and end is not None:
        far = max(fl.distance(a, start), fl.distance(a, end)) * (1 + RADIUS_PAD) + fl.slack
        norm_m, s_m = fl.norm_and_gap(a, m)
        if (norm_m - s_m) / 2 > far:
            return False
        centre, half = fl.spread(a, m)
        if half is None:
            return True
        arc = arc_between(fl.angle(a, start), fl.angle(a, end))
        return nearest_reach(arc, centre, norm_m, s_m) <= far
    finite = start if start is not None else end
    if finite is None:
        norm, s = fl.norm_and_gap(a, b)
        near = (norm - s) / 2 * (1 - RADIUS_PAD)        # the apex, nearest point of the branch to p_a
        return not all(tail_apart(fl, a, b, side, near, m) for side in (1, -1))
    near = fl.distance(a, finite)
    # the part within |finite - p_a| of p_a: m must come that close (its apex distance bounds it)
    norm_m, s_m = fl.norm_and_gap(a, m)
    if (norm_m - s_m) / 2 <= near * (1 + RADIUS_PAD) + fl.slack:
        return True
    return not tail_apart(fl, a, b, 1 if end is None else -1, near, m)


def _check_rays(d: Diagram, disks: _Disks) -> Check:
    """Around a cell with several gaps at infinity, each edge that runs out to infinity is
    followed by the one that comes back next counter-clockwise, by their asymptotes (seen from
    the cell's centre, the cell's directions at infinity come in that order)."""
    outs: dict[int, list[int]] = {}
    ins: dict[int, list[int]] = {}
    origin, twin, site = (np.asarray(a, dtype=np.int64) for a in (d.origin, d.twin, d.site))
    for h in range(d.n_half_edges):
        if origin[twin[h]] < 0:
            outs.setdefault(int(site[h]), []).append(h)
        if origin[h] < 0:
            ins.setdefault(int(site[h]), []).append(h)
    problems = []
    for cell, out in outs.items():
        if len(out) < 2:
            continue
        tagged = sorted([(direction_key(asymptote(disks.exact, cell, int(site[twin[h]]), 1)), 0, h) for h in out]
                        + [(direction_key(asymptote(disks.exact, cell, int(site[twin[h]]), -1)), 1, h)
                           for h in ins.get(cell, [])], key=lambda t: (t[0], t[1]))
        for pos, (_, kind, h) in enumerate(tagged):
            if kind:
                continue
            following = next((t[2] for t in tagged[pos + 1:] + tagged[:pos] if t[1] == 1), None)
            if following is None or int(d.next[h]) != following:
                problems.append((h, f"half-edge {h} of cell {cell} runs out to infinity and is followed by "
                                    f"half-edge {int(d.next[h])}, not by the next edge coming back "
                                    f"counter-clockwise ({following})"))
                break
    cells = sum(1 for out in outs.values() if len(out) >= 2)
    return _fail("rays", problems, f"{cells} cells with several gaps at infinity, linked counter-clockwise",
                 "half-edge")


def _check_euler(d: Diagram, visible: int) -> Check:
    if visible <= 1:
        return Check("euler", True, "fewer than two visible disks")
    total = d.n_vertices - d.n_edges + visible
    return Check("euler", total == 1, f"V - E + k = {d.n_vertices} - {d.n_edges} + {visible} = {total}"
                 + ("" if total == 1 else " (must be 1)"))


def certify_disks(diagram: Diagram) -> Certificate:
    """Every check of this module on ``diagram`` (a diagram with ``radii``); never raises on a
    broken diagram."""
    d = diagram
    counts = {"n": d.n_sites, "V": d.n_vertices, "E": d.n_edges}
    try:
        if d.radii is None:
            raise InvalidDiagramError("the diagram has no radii: it is not a diagram of disks")
        d.validate()
    except (InvalidDiagramError, ValueError) as exc:
        checks = [Check("structure", False, str(exc))]
        checks += [Check(name, False, "not run: the structure is broken") for name in DISK_CHECKS[1:]]
        return Certificate(False, checks, counts)
    checks = [Check("structure", True, "valid DCEL with radii")]
    # judged at a power of two that puts the disks where the float filters' products neither
    # overflow nor underflow (exact: the same diagram; distances in messages are in these units)
    shift, _ = comfortable_shift(np.vstack([np.asarray(d.sites, np.float64),
                                            np.column_stack([d.radii, d.radii]).astype(np.float64)]))
    if shift:
        with np.errstate(over="ignore", under="ignore"):
            d = Diagram(scale_points(d.sites, shift), scale_points(d.vertices, shift), d.origin, d.twin, d.next,
                        d.site, radii=np.ldexp(np.asarray(d.radii, np.float64), shift))
    disks = _Disks(d)
    try:
        visible_mask = ~hidden_disks(disks.centres, disks.radii)
    except ValueError as exc:                          # outside the exact range
        checks += [Check(name, False, f"not judged: {exc}") for name in DISK_CHECKS[1:]]
        return Certificate(False, checks, counts)
    visible = [int(m) for m in np.flatnonzero(visible_mask)]
    disks.visible = visible_mask
    points = _Points(d, disks.exact)
    runners: dict[str, Callable[[], Check]] = {
        "hidden": lambda: _check_hidden(d, disks, visible_mask),
        "vertices": lambda: _check_vertices(d, disks, points),
        "edges": lambda: _check_edges(d, disks, points, visible),
        "rays": lambda: _check_rays(d, disks),
        "euler": lambda: _check_euler(d, len(visible)),
    }
    for name in DISK_CHECKS[1:]:
        t0 = time.perf_counter()
        try:
            check = runners[name]()
        except Exception as exc:  # noqa: BLE001 - a check that cannot run on this diagram has failed
            check = Check(name, False, f"could not run: {type(exc).__name__}: {exc}")
        check.seconds = time.perf_counter() - t0
        checks.append(check)
    return Certificate(all(c.ok for c in checks), checks, counts)


@dataclass
class DiskComparison:
    """Two diagrams of the same disks: ``verdict`` exact when their half-edges join the same
    cells between the same vertices (each named by the cells around it, counter-clockwise) and
    matched vertices lie within tolerance; else differs, with ``detail`` saying where."""

    verdict: Verdict
    detail: str
    differences: int = 0

    @property
    def equal(self) -> bool:
        """Whether they agree (the engine's word for it; ``verdict`` says how)."""
        return self.verdict is Verdict.EXACT

    @property
    def n_differences(self) -> int:
        return self.differences

    def to_dict(self) -> dict:
        return {"verdict": self.verdict.value, "detail": self.detail, "n_differences": self.differences}


def _half_edge_keys(d: Diagram) -> tuple[Counter, dict]:
    """Each half-edge (not inside one point) as (cell, neighbour, start point, end point), points
    named by their cells; and each point's coordinates."""
    disks = [(rational(float(x)), rational(float(y)), rational(float(r))) for (x, y), r in zip(d.sites, d.radii)]
    points = _Points(d, disks)
    keys = Counter()
    for h in range(d.n_half_edges):
        if points.internal[h]:
            continue
        u, w = int(d.origin[h]), int(d.origin[d.twin[h]])
        after = None
        if w < 0:               # out to infinity: which edge comes back next (a cell's gaps' order)
            g = int(d.next[h])
            end = int(d.origin[d.twin[g]])
            after = (int(d.site[d.twin[g]]), points.name(end) if end >= 0 else None)
        keys[(int(d.site[h]), int(d.site[d.twin[h]]), points.name(u) if u >= 0 else None,
              points.name(w) if w >= 0 else None, after)] += 1
    return keys, {points.name(v): tuple(d.vertices[v]) for v in range(d.n_vertices)}


def compare_disks(first: Diagram, second: Diagram) -> DiskComparison:
    """Whether two diagrams of disks agree exactly (combinatorially; coordinates within tolerance)."""
    if first.radii is None or second.radii is None:
        return DiskComparison(Verdict.DIFFERS, "not both diagrams of disks")
    if not (np.array_equal(first.sites, second.sites) and np.array_equal(first.radii, second.radii)):
        return DiskComparison(Verdict.WRONG_SITES, "the diagrams are of different disks")
    keys_a, points_a = _half_edge_keys(first)
    keys_b, points_b = _half_edge_keys(second)
    if keys_a != keys_b:
        only_a, only_b = keys_a - keys_b, keys_b - keys_a
        example = next(iter(only_a or only_b))
        side = "first" if only_a else "second"
        return DiskComparison(Verdict.DIFFERS, f"{sum(only_a.values())} half-edges only in the first, "
                              f"{sum(only_b.values())} only in the second; e.g. cells {example[0]}, {example[1]} "
                              f"from {example[2]} to {example[3]} (in the {side})",
                              sum(only_a.values()) + sum(only_b.values()))
    # each vertex within a relative tolerance of the larger of the data's size and its own
    scale = float(np.abs(first.sites).max(initial=0) + np.abs(first.radii).max(initial=0))
    apart = [(math.dist(p, points_b[name]), name) for name, p in points_a.items()
             if not math.dist(p, points_b[name]) <= VERTEX_MATCH_REL_TOL * max(scale, abs(p[0]), abs(p[1]))]
    if apart:
        gap, name = max(apart)
        return DiskComparison(Verdict.DIFFERS, f"same topology, but {len(apart)} vertices apart: the vertex of "
                              f"cells {name} by {gap:.3g}", len(apart))
    return DiskComparison(Verdict.EXACT, f"{len(points_a)} vertices and {sum(keys_a.values()) // 2} edges agree")
