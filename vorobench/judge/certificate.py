"""Is a diagram the Voronoi diagram of its sites? Checks that trust no implementation.

Each check looks at the diagram from a different side, so that a wrong diagram cannot pass
by being wrong consistently:

* ``structure``: the DCEL invariants (:meth:`Diagram.validate`).
* ``vertices``: every vertex touches >= 3 cells, is equidistant from their sites, and no
  site is strictly closer (k-d tree): the empty-circle property.
* ``edges``: each finite end of an edge (a, b) is equidistant from a and b (the bisector),
  and the edge runs the right way along perp(b - a): the other sites of its start vertex lie
  strictly right of a->b and those of its end vertex strictly left (exact orient2d; this
  also orients rays and zero-length edges, where coordinates cannot).
* ``topology`` (exact): every vertex joins exactly cocircular sites (``incircle`` == 0; the
  power test for a power diagram), and every finite edge is locally Delaunay (no site strictly
  inside the circle across it): :mod:`vorobench.judge.topology`. An epsilon merge of nearly
  cocircular sites fails it; a floating-point library's such merge is near-degenerate
  ("within tolerance").
* ``euler``: V - E + n == 1 and the edge graph plus the point at infinity is connected.
* ``hull``: the unbounded cells are exactly the sites on the convex-hull boundary, collinear
  boundary points included (monotone chain with exact orient2d).
* ``probes``: random points of the bounding box, and every site, lie in the cell (polygon of
  the diagram's own vertices) of their nearest site, and random points lie strictly inside no
  cell of their next nearest sites (no cell claims a neighbour's territory).

Any magnitude: the diagram is first scaled by a power of two (exact) so that its largest site
coordinate lies in [0.5, 1) (:func:`vorobench.core.scaling.comfortable_shift`). There orient2d is
exact and no distance, probe or tolerance underflows or overflows: at subnormal or 1e-200
scale the orientation tests and probe sides used to underflow to 0, and n - 1 parallel lines
for a grid were certified; at 1e300 squared distances overflowed. Coordinates rounded to
subnormals (vertices of subnormal input) carry an absolute error of up to 2**-1075, allowed
for in every tolerance (``_Context.normal_min``). Sites whose magnitudes span more than the exact
range (1.0 with 1e-300) cannot be judged exactly: the structure check fails, saying so.
Messages give coordinates in the diagram's own units.

Power diagrams (a diagram with varying ``weights``): every check is the power version.
Powers |x - p|^2 - w are compared directly, and a power difference dp at a point x is judged
as the length dp / (2R), R = sqrt(|x - p|^2 + |w|) the local radius of the sites concerned
(their distance, in an ordinary diagram), so one heavy site elsewhere never widens the
tolerance of the small cells. The sites of smallest power come from a k-d tree over the
lifted points (p_x, p_y, sqrt(W - w)), W the largest weight, whose candidates are then
ranked by their powers. Vertices have equal power from their sites and no site of smaller
power (the empty power circle: orthogonality), edge ends lie on the power bisector, Euler's
relation counts the visible sites, the unbounded cells are the visible sites on the hull
boundary and no hull corner is hidden, and probes (random points and the hidden sites' own
positions) lie in the cell of their smallest power. A wrongly hidden site has smaller power
than its surroundings at some vertex of the diagram (the region where it wins is convex and
the lower envelope of the others is concave), so the vertex check sees it. A site need not
lie in its own power cell, so that probe is left out.

Geometric tolerances come from :mod:`vorobench.core.tolerances`. O(n log n).
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field
from typing import Any, Callable, Optional

import numpy as np
from numba import njit
from numpy.typing import NDArray
from scipy.spatial import cKDTree

from vorobench.core.diagram import Diagram
from vorobench.core.hull import convex_hull_polygon
from vorobench.core.incidence import vertex_site_lists
from vorobench.core.predicates import orient2d
from vorobench.core.scaling import comfortable_shift, scale_points, smallest_normal
from vorobench.core.sorting import argsort_keys, sorted_unique
from vorobench.core.predicates.degeneracy import lift_extent, orient2d_ulps
from vorobench.core.predicates.expansion import EPSILON
from vorobench.core.read_only import read_only
from vorobench.core.tolerances import (
    EQUIDISTANCE_REL_TOL,
    NEAR_DEGENERATE_REL_TOL,
    NEAR_DEGENERATE_ULPS,
    PROBE_REL_TOL,
    allowed_error,
    data_scale,
    length_tolerance,
)
from vorobench.judge.defaults import DEFAULT_PROBES
from vorobench.judge.outcomes import CertificateLevel, Verdict
from vorobench.judge.topology import collinear_ulps, judge_topology, wrongly_hidden

__all__ = ["certify", "Certificate", "Check", "CHECKS"]

#: The checks, in the order they run.
CHECKS = ("structure", "vertices", "edges", "topology", "euler", "hull", "probes")


_MAX_IDS = 10


@dataclass
class Check:
    """Result of one check: whether it passed, what it found, and the first offending ids."""

    name: str
    ok: bool
    detail: str
    offending: list[int] = field(default_factory=list)
    id_kind: str = ""
    seconds: float = 0.0
    #: Passed, or failed only on near-degenerate decisions that a floating-point library may
    #: get wrong (``NEAR_DEGENERATE_ULPS`` for topology, ``NEAR_DEGENERATE_REL_TOL`` for
    #: coordinates). None: same as ``ok``.
    within_tolerance: Optional[bool] = None

    def __post_init__(self) -> None:
        if self.within_tolerance is None:
            self.within_tolerance = self.ok

    def __str__(self) -> str:
        mark = "ok  " if self.ok else "tol " if self.within_tolerance else "FAIL"
        ids = f" (first {self.id_kind} ids: {self.offending})" if self.offending else ""
        return f"{mark} {self.name}: {self.detail}{ids}"


@dataclass
class Certificate:
    """Result of :func:`certify`: ``ok`` when every check passed exactly.

    ``ok_within_tolerance``: every check passed, or failed only on near-degenerate decisions
    (the standard for floating-point libraries such as Qhull, never for exact code).
    """

    ok: bool
    checks: list[Check]
    counts: dict[str, int]

    @property
    def ok_within_tolerance(self) -> bool:
        return all(c.within_tolerance for c in self.checks)

    @property
    def level(self) -> CertificateLevel:
        """``certified`` (exact topology), ``certified_within_tolerance`` or ``not_certified``."""
        return (CertificateLevel.CERTIFIED if self.ok else CertificateLevel.WITHIN_TOLERANCE
                if self.ok_within_tolerance else CertificateLevel.NOT_CERTIFIED)

    @property
    def verdict(self) -> Verdict:
        """"certified", "within_tolerance" or "not_certified"."""
        return (Verdict.CERTIFIED if self.ok else Verdict.WITHIN_TOLERANCE if self.ok_within_tolerance
                else Verdict.NOT_CERTIFIED)

    def check(self, name: str) -> Check:
        """The result of the check called ``name``."""
        for c in self.checks:
            if c.name == name:
                return c
        raise KeyError(f"no check {name!r}; checks: {', '.join(c.name for c in self.checks)}")

    @property
    def failed(self) -> list[str]:
        """Names of the checks that failed."""
        return [c.name for c in self.checks if not c.ok]

    def to_dict(self) -> dict[str, Any]:
        """JSON-serialisable summary."""
        return {"ok": self.ok, "ok_within_tolerance": self.ok_within_tolerance, "level": self.level.value,
                "verdict": self.verdict,
                "counts": dict(self.counts), "checks": [asdict(c) for c in self.checks]}

    def __str__(self) -> str:
        c = self.counts
        head = "CERTIFIED" if self.ok else (
            f"CERTIFIED WITHIN TOLERANCE (near-degenerate errors in {', '.join(self.failed)})"
            if self.ok_within_tolerance else
            f"NOT CERTIFIED ({', '.join(c.name for c in self.checks if not c.within_tolerance)} failed)")
        lines = [f"certificate: {head}  [n={c.get('n')}, V={c.get('V')}, E={c.get('E')}]"]
        lines += [f"  {check}" for check in self.checks]
        return "\n".join(lines)


def _ids(mask_or_ids: NDArray, limit: int = _MAX_IDS) -> list[int]:
    arr = np.asarray(mask_or_ids)
    idx = np.flatnonzero(arr) if arr.dtype == bool else arr
    return [int(i) for i in idx[:limit]]


# ---------------------------------------------------------------------------------- context
@dataclass
class _Context:
    """Arrays shared by the checks, computed once."""

    d: Diagram
    sites: NDArray[np.float64]
    xy: NDArray[np.float64]
    origin: NDArray[np.int64]
    twin: NDArray[np.int64]
    site: NDArray[np.int64]
    dest: NDArray[np.int64]
    scale: float
    n: int
    V: int
    H: int
    seed: int
    probes: int
    #: the diagram is judged times 2**shift; ``normal_min``: the smallest normal float in those
    #: units (coordinates below it were subnormals, rounded to absolute multiples of 2**-1074)
    shift: int = 0
    normal_min: float = 0.0
    #: why the sites cannot be judged exactly at any scale, or None
    range_problem: Optional[str] = None
    structure_ok: bool = False
    #: power diagram: each site's weight (scaled by 2**(2 shift)) and W - w, the square of its
    #: lift (W the largest weight); zeros and False for an ordinary diagram
    weights: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    lift2: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    weighted: bool = False
    _tree: Any = None
    _lists: Optional[tuple[NDArray[np.int64], NDArray[np.int64]]] = None

    def unscaled(self, x: float) -> float:
        """A length or coordinate back in the diagram's own units (for messages)."""
        return math.ldexp(float(x), -self.shift)

    def magnitude(self, mag: NDArray[np.float64]) -> NDArray[np.float64]:
        """Coordinate magnitudes for :func:`length_tolerance`, at least ``normal_min``: the ulps
        of subnormal coordinates are the absolute 2**-1074, not relative."""
        return np.maximum(mag, self.normal_min)

    @property
    def extents(self) -> tuple[float, float]:
        """(half the longer side of the sites' bounding box, the lifted coordinates' extent): the
        units of a floating-point library's rounding (:mod:`vorobench.core.predicates.degeneracy`)."""
        weight = float(np.abs(self.weights).max()) if self.weighted and self.weights.size else 0.0
        return self.scale / 2.0, lift_extent(self.scale / 2.0, weight)

    @property
    def tree(self):
        """k-d tree of the sites; lifted to (x, y, sqrt(W - w)) for a power diagram, so that a
        query at (x, y, 0) finds the site of smallest power."""
        if self._tree is None:
            points = self.sites if not self.weighted else np.column_stack([self.sites, np.sqrt(self.lift2)])
            self._tree = cKDTree(points, balanced_tree=False, compact_nodes=False)  # 3x faster build
        return self._tree

    def query(self, pts: NDArray[np.float64], k: int = 1):
        """(lifted distances, site ids) of the k sites of smallest power at ``pts``."""
        if self.weighted:
            pts = np.column_stack([pts, np.zeros(pts.shape[0])])
        return self.tree.query(pts, k=k, workers=-1)

    @property
    def visible(self) -> NDArray[np.bool_]:
        """Sites with a cell (every site of an ordinary diagram with edges)."""
        has = np.zeros(self.n, dtype=bool)
        has[self.site] = True
        return has

    @property
    def vertex_sites(self) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
        if self._lists is None:
            # Origins alone list every incidence when the structure is valid (origin[next] == dest).
            dest = None if self.structure_ok else self.dest
            self._lists = vertex_site_lists(self.site, self.origin, dest, self.V, self.n)
        return self._lists


def _usable(d: Diagram) -> Optional[str]:
    """Why the index arrays cannot even be used for indexing, or None."""
    H, V, n = d.n_half_edges, d.n_vertices, d.n_sites
    if np.ndim(d.sites) != 2 or np.shape(d.sites)[1] != 2 or np.ndim(d.vertices) != 2 or np.shape(d.vertices)[1] != 2:
        return "sites and vertices must be (k, 2) arrays"
    for name in ("origin", "twin", "next", "site"):
        arr = np.asarray(getattr(d, name))
        if arr.shape != (H,) or arr.dtype.kind not in "iu":
            return f"{name} is not an integer array of shape ({H},)"
    if H and not (d.origin.min() >= -1 and d.origin.max() < V and d.twin.min() >= 0 and d.twin.max() < H
                  and d.next.min() >= 0 and d.next.max() < H and d.site.min() >= 0 and d.site.max() < n):
        return "an index is out of range"
    return None


# ---------------------------------------------------------------------------------- checks
#: The forgiven change of a number, per unit of its extent (``_Context.extents``): a
#: coordinate per unit of the sites' extent, a power (lifted coordinate) per unit of the lifts'.
_FORGIVEN = NEAR_DEGENERATE_ULPS * EPSILON


def _ulps(x: float) -> str:
    """A distance from degenerate, in roundings of the data, for messages."""
    return "infinitely many roundings" if not np.isfinite(x) else f"{x:.3g} roundings"


def _check_structure(ctx: _Context) -> Check:
    try:
        ctx.d.validate()
    except Exception as exc:  # validate's message names the broken invariant and its ids
        return Check("structure", False, f"{type(exc).__name__}: {exc}")
    if ctx.range_problem:
        return Check("structure", False, f"valid DCEL, but the sites cannot be judged exactly: {ctx.range_problem}")
    return Check("structure", True, f"valid DCEL ({ctx.H} half-edges, {ctx.V} vertices)")


@njit(cache=True)
def _vertex_kernel(xy, sites, ptr, s, r_min, r_max, magnitude):
    """Per vertex: smallest and largest distance to its sites, and the largest coordinate."""
    for v in range(ptr.size - 1):
        lo, hi = np.inf, 0.0
        mag = max(abs(xy[v, 0]), abs(xy[v, 1]))
        for j in range(ptr[v], ptr[v + 1]):
            x = s[j]
            d = np.hypot(xy[v, 0] - sites[x, 0], xy[v, 1] - sites[x, 1])
            lo, hi = min(lo, d), max(hi, d)
            mag = max(mag, abs(sites[x, 0]), abs(sites[x, 1]))
        r_min[v], r_max[v], magnitude[v] = lo, hi, mag


@njit(cache=True)
def _power(px, py, sites, weights, x):
    """|p - site x|^2 - w_x."""
    dx, dy = px - sites[x, 0], py - sites[x, 1]
    return dx * dx + dy * dy - weights[x]


@njit(cache=True)
def _local_radius(px, py, sites, weights, x):
    """sqrt(|p - x|^2 + |w_x|): the length by which a power difference at p is judged; the
    distance itself in an ordinary diagram, and never inflated by other sites' weights."""
    dx, dy = px - sites[x, 0], py - sites[x, 1]
    return np.sqrt(dx * dx + dy * dy + abs(weights[x]))


@njit(cache=True)
def _power_vertex_kernel(xy, sites, weights, ptr, s, p_min, p_max, radius, magnitude):
    """Per vertex of a power diagram: smallest and largest power of its sites there, the local
    radius (largest of theirs) that turns a power difference dp into a length dp / (2 radius),
    and the largest coordinate."""
    for v in range(ptr.size - 1):
        lo, hi, r = np.inf, -np.inf, 0.0
        mag = max(abs(xy[v, 0]), abs(xy[v, 1]))
        for j in range(ptr[v], ptr[v + 1]):
            x = s[j]
            p = _power(xy[v, 0], xy[v, 1], sites, weights, x)
            lo, hi = min(lo, p), max(hi, p)
            r = max(r, _local_radius(xy[v, 0], xy[v, 1], sites, weights, x))
            mag = max(mag, abs(sites[x, 0]), abs(sites[x, 1]))
        p_min[v], p_max[v], radius[v], magnitude[v] = lo, hi, r, mag


def _smallest_powers(ctx: "_Context", pts: NDArray[np.float64], k: int) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The k sites of smallest power at each point, by power (float, recomputed for the
    candidates the lifted k-d tree returns), as (powers, site ids), each (m, k)."""
    k = min(k, ctx.n)
    _, near = ctx.query(pts, k=k)
    near = np.asarray(near, dtype=np.int64).reshape(pts.shape[0], k)
    diff = pts[:, None, :] - ctx.sites[near]
    powers = (diff ** 2).sum(axis=2) - ctx.weights[near]
    order = np.argsort(powers, axis=1, kind="stable")
    return np.take_along_axis(powers, order, axis=1), np.take_along_axis(near, order, axis=1)


def _check_vertices(ctx: _Context) -> Check:
    ptr, s = ctx.vertex_sites
    deg = np.diff(ptr)
    used = np.flatnonzero(deg > 0)
    if used.size == 0:
        return Check("vertices", True, "no vertices")
    few = used[deg[used] < 3]
    r_min, r_max, mag = np.empty(ctx.V), np.empty(ctx.V), np.empty(ctx.V)
    if ctx.weighted:
        # Powers become lengths by the vertex's own local radius R: f(p) = R + (p - p_max) / (2R),
        # so that the ordinary rules below read "equal power" and "no smaller power".
        p_min, p_max = np.empty(ctx.V), np.empty(ctx.V)
        _power_vertex_kernel(ctx.xy, ctx.sites, ctx.weights, ptr, s, p_min, p_max, r_max, mag)
        p_min, p_max = p_min[used], p_max[used]
        radius = np.maximum(r_max[used], 1e-300)
        r_min, r_max, mag = radius + (p_min - p_max) / (2 * radius), radius, ctx.magnitude(mag[used])
    else:
        _vertex_kernel(ctx.xy, ctx.sites, ptr, s, r_min, r_max, mag)
        r_min, r_max, mag = r_min[used], r_max[used], ctx.magnitude(mag[used])
    # Strict: relative to the vertex's own radius. Near-degenerate (a floating-point library
    # merging nearly cocircular sites): relative to the data scale.
    tol = length_tolerance(EQUIDISTANCE_REL_TOL, r_max, mag)
    tol_near = length_tolerance(NEAR_DEGENERATE_REL_TOL, np.maximum(ctx.scale, r_max), mag)
    unequal = ~(r_max - r_min <= tol)           # NaN coordinates count as violations
    # Empty circle: no site strictly closer than the vertex's own (k-d tree nearest site).
    nearest = np.full(used.size, np.nan)
    finite = np.isfinite(ctx.xy[used]).all(axis=1)
    if ctx.weighted:
        smallest = _smallest_powers(ctx, ctx.xy[used[finite]], 6)[0][:, 0]
        nearest[finite] = (radius + (smallest - p_max) / (2 * radius))[finite]
    else:
        nearest[finite] = ctx.query(ctx.xy[used[finite]])[0]
    with np.errstate(invalid="ignore"):         # inf - inf of a vertex out at infinity: a violation, said below
        closer = ~(nearest >= r_min - tol)
    spread = (r_max - r_min) / np.maximum(r_max, 1e-300)
    problems = []
    if few.size:
        problems.append(f"{few.size} vertices touch fewer than 3 cells")
    if unequal.any():
        k = int(np.argmax(spread))
        problems.append(f"{int(unequal.sum())} vertices are not equidistant from their sites "
                        f"(worst: vertex {int(used[k])}, distances {ctx.unscaled(r_min[k]):.6g} .. "
                        f"{ctx.unscaled(r_max[k]):.6g})")
    if closer.any():
        problems.append(f"{int(closer.sum())} vertices have a site strictly closer than their own "
                        f"(empty circle violated)")
    if problems:
        # A floating-point library holds powers (lifted coordinates) to roundings of their
        # extent: a power difference within NEAR_DEGENERATE_ULPS of them, as a length at the
        # vertex's radius, is near-degenerate too.
        tol_near = tol_near + _FORGIVEN * ctx.extents[1] / (2 * np.maximum(r_max, 1e-300))
        within = few.size == 0 and bool(((r_max - r_min <= tol_near) & (nearest >= r_min - tol_near)).all())
        if within:
            problems.append("all within the near-degenerate tolerance of the data scale")
        bad = sorted_unique(np.concatenate([few, used[unequal], used[closer]]))
        return Check("vertices", False, "; ".join(problems), _ids(bad), "vertex", within_tolerance=within)
    return Check("vertices", True, f"{used.size} vertices: empty circles, distances agree to "
                 f"{float(spread.max()):.2g} (relative)")


@njit(cache=True)
def _edge_kernel(sites, xy, ptr, s, a, b, u, v, wrong_way, worst, gap, radius, magnitude, weights, weighted, extent):
    """Per edge k (a's half-edge from vertex u to v, -1 = infinity):
    wrong_way[k]: not oriented along perp(b - a), so a's cell does not run counter-clockwise:
    some other site of u is not strictly right of a->b, or some other site of v not strictly
    left (exact); worst[k]: how far the farthest such site is from the line ab, in roundings
    of the data (``orient2d_ulps``; small = near-degenerate);
    gap[k]: largest |d(w, a) - d(w, b)| over the finite ends w (0 on the bisector), with the
    distance (radius) and coordinate magnitude to judge it by."""
    for k in range(a.size):
        aa, bb = a[k], b[k]
        ax, ay, bx, by = sites[aa, 0], sites[aa, 1], sites[bb, 0], sites[bb, 1]
        for w, want in ((u[k], -1), (v[k], 1)):
            if w < 0:
                continue
            for j in range(ptr[w], ptr[w + 1]):
                x = s[j]
                if x != aa and x != bb and orient2d(ax, ay, bx, by, sites[x, 0], sites[x, 1]) != want:
                    wrong_way[k] = True
                    worst[k] = max(worst[k], orient2d_ulps(ax, ay, bx, by, sites[x, 0], sites[x, 1], extent))
            px, py = xy[w, 0], xy[w, 1]
            if weighted:        # the power difference as a length, by the local radius
                r = max(_local_radius(px, py, sites, weights, aa), _local_radius(px, py, sites, weights, bb))
                off = abs(_power(px, py, sites, weights, aa) - _power(px, py, sites, weights, bb)) / (2 * max(r, 1e-300))
            else:
                da, db = np.hypot(px - ax, py - ay), np.hypot(px - bx, py - by)
                off, r = abs(da - db), max(da, db)
            if not off <= gap[k]:          # NaN (a non-finite vertex) sticks
                gap[k] = off
                radius[k] = r
                magnitude[k] = max(abs(px), abs(py), abs(ax), abs(ay), abs(bx), abs(by))


def _check_edges(ctx: _Context) -> Check:
    if ctx.H == 0:
        return Check("edges", True, "no edges")
    e = np.flatnonzero(np.arange(ctx.H) < ctx.twin)
    a, b = ctx.site[e], ctx.site[ctx.twin[e]]
    u, v = ctx.origin[e], ctx.dest[e]
    ptr, s = ctx.vertex_sites
    wrong_way = np.zeros(e.size, dtype=bool)
    worst, gap, radius, mag = (np.zeros(e.size) for _ in range(4))
    wt = ctx.weights if ctx.weighted else np.zeros(ctx.n)
    _edge_kernel(ctx.sites, ctx.xy, ptr, s, a, b, u, v, wrong_way, worst, gap, radius, mag, wt, ctx.weighted,
                 ctx.extents[0])
    mag = ctx.magnitude(mag)
    off = ~(gap <= length_tolerance(EQUIDISTANCE_REL_TOL, radius, mag))     # NaN is off
    off_far = ~(gap <= length_tolerance(NEAR_DEGENERATE_REL_TOL, np.maximum(ctx.scale, radius), mag))
    problems = []
    within = True
    if wrong_way.any():
        # Near-degenerate: every offending site within NEAR_DEGENERATE_ULPS roundings of the
        # data of the line ab (decided on the sites, never from the edge's length).
        bad = np.flatnonzero(wrong_way)
        tolerated = worst[bad] <= NEAR_DEGENERATE_ULPS
        near = int(tolerated.sum())
        problems.append(f"{bad.size} edges run the wrong way (or join vertices that do not "
                        f"surround them)" + (f", {near} of them near-degenerate" if near else ""))
        within = bool(tolerated.all())
    if off.any():
        problems.append(f"{int(off.sum())} edges have an end off their sites' bisector"
                        + ("" if off_far.any() else " (within the near-degenerate tolerance of the data scale)"))
        within = within and not off_far.any()
    if problems:
        return Check("edges", False, "; ".join(problems), _ids(e[wrong_way | off]), "half-edge", within_tolerance=within)
    return Check("edges", True, f"{e.size} edges on their bisectors, oriented along perp(b - a)")


def _check_topology(ctx: _Context) -> Check:
    """Exact: every vertex's sites cocircular, every finite edge locally Delaunay, a whole line
    only between sites that are all collinear (:mod:`vorobench.judge.topology`)."""
    e = np.flatnonzero(np.arange(ctx.H) < ctx.twin)
    lines = e[(ctx.origin[e] < 0) & (ctx.dest[e] < 0)]
    if lines.size:
        # A line with no vertex on it separates two cells only when all sites are on one line.
        off = collinear_ulps(ctx.sites, ctx.site[lines[0]], ctx.site[ctx.twin[lines[0]]], ctx.extents[0])
        if off > 0:
            return Check("topology", False, f"{lines.size} edges are whole lines (no vertex), but the sites are not "
                         f"all collinear (the farthest is {_ulps(off)} of the data off the line of sites "
                         f"{int(ctx.site[lines[0]])} and {int(ctx.site[ctx.twin[lines[0]]])}; "
                         f"{NEAR_DEGENERATE_ULPS:.0f} are forgiven a floating-point library)",
                         _ids(lines), "half-edge", within_tolerance=bool(off <= NEAR_DEGENERATE_ULPS))
    if ctx.H == 0 or ctx.V == 0:
        return Check("topology", True, "no finite vertex" + (f"; {lines.size} lines between collinear sites"
                                                             if lines.size else ""))
    ptr, s = ctx.vertex_sites
    extent, lifted = ctx.extents
    found = judge_topology(ctx.sites, ctx.weights, ctx.weighted, ptr, s, ctx.site[e], ctx.site[ctx.twin[e]],
                           ctx.origin[e], ctx.dest[e], extent, lifted)
    circle = "power circle" if ctx.weighted else "circle"
    problems = []
    worst = found["worst_ulps"]
    wrongly = np.zeros(0, dtype=np.int64)
    if ctx.weighted:
        hidden = np.flatnonzero(~ctx.visible)
        if hidden.size:
            visible = np.flatnonzero(ctx.visible)
            k = min(visible.size, 4)
            _, near = _smallest_powers(ctx, ctx.sites[hidden], min(ctx.n, k + 1))
            near = np.where(near == hidden[:, None], -1, near)   # its own (empty) cell is no candidate
            wrongly, hidden_ulps = wrongly_hidden(ctx.sites, ctx.weights, ptr, s, hidden, near, ctx.site,
                                                  ctx.origin, extent, lifted)
            if wrongly.size:
                worst = max(worst, hidden_ulps)
                problems.append(f"{wrongly.size} hidden sites are in conflict with the triangle of the dual that "
                                f"holds them (exact power test): they have a cell")
    within = bool(worst <= NEAR_DEGENERATE_ULPS)
    if found["not_cocircular"].size:
        problems.append(f"{found['not_cocircular'].size} vertices join sites that are not exactly on one {circle} "
                        f"(nearly cocircular sites merged into one vertex)")
    if found["collinear"].size:
        problems.append(f"{found['collinear'].size} vertices join sites that all lie on one line")
    if found["not_delaunay"].size:
        problems.append(f"{found['not_delaunay'].size} edges are not locally Delaunay (a site strictly inside "
                        f"the {circle} of the vertex across the edge: an empty {circle} violated)")
    if problems:
        problems.append(f"{'all' if within else 'not all'} near-degenerate (the farthest is {_ulps(worst)} of the "
                        f"data from a degenerate configuration; {NEAR_DEGENERATE_ULPS:.0f} are forgiven a "
                        f"floating-point library)")
        ids = np.concatenate([found["not_cocircular"], found["collinear"]])
        kind = "vertex" if ids.size else "half-edge" if found["not_delaunay"].size else "site"
        if not ids.size:
            ids = e[found["not_delaunay"]] if found["not_delaunay"].size else wrongly
        return Check("topology", False, "; ".join(problems), _ids(ids), kind, within_tolerance=within)
    return Check("topology", True, f"exact: {int((np.diff(ptr) > 0).sum())} vertices on exact {circle}s, "
                 f"{e.size} edges locally Delaunay")


def _check_euler(ctx: _Context) -> Check:
    n, H = ctx.n, ctx.H
    if ctx.weighted:                    # hidden sites have no cell: count the visible ones
        n = int(ctx.visible.sum()) if H else min(n, 1)
    E = H // 2
    used = np.zeros(ctx.V, dtype=bool)
    used[ctx.origin[ctx.origin >= 0]] = True
    V = int(used.sum())
    if n == 0:
        ok = V == 0 and E == 0
        return Check("euler", ok, f"n = 0: V = {V}, E = {E}" + ("" if ok else " (expected none)"))
    # Components of the edge graph with one extra node for the point at infinity.
    inf = ctx.V
    u = np.where(ctx.origin >= 0, ctx.origin, inf)
    w = np.where(ctx.dest >= 0, ctx.dest, inf)
    comps = _count_components(np.append(used, True), u, w)
    value = V - E + n
    ok = value == 1 and comps == 1
    name = "n_visible" if ctx.weighted else "n"
    detail = f"V - E + {name} = {V} - {E} + {n} = {value}" + ("" if value == 1 else " (expected 1)")
    detail += f"; {comps} connected component{'s' if comps != 1 else ''}" + ("" if comps == 1 else " (expected 1)")
    return Check("euler", ok, detail)


@njit(cache=True)
def _count_components(used, u, w):
    """Connected components among the ``used`` nodes of the graph with edges (u[k], w[k])
    (union-find with path halving)."""
    parent = np.arange(used.size)
    for k in range(u.size):
        a, b = u[k], w[k]
        while parent[a] != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        while parent[b] != b:
            parent[b] = parent[parent[b]]
            b = parent[b]
        if a != b:
            parent[a] = b
    count = 0
    for i in range(used.size):
        if used[i] and parent[i] == i:
            count += 1
    return count


def _segment_distance(p: NDArray[np.float64], q0: NDArray[np.float64], q1: NDArray[np.float64]) -> NDArray[np.float64]:
    """Distance from points p (k, 2) to segments q0 -> q1 (each (k, 2), or broadcastable)."""
    d = q1 - q0
    t = np.clip(np.sum((p - q0) * d, axis=-1) / np.maximum(np.sum(d * d, axis=-1), 1e-300), 0.0, 1.0)
    return np.hypot(*np.moveaxis(p - q0 - t[..., None] * d, -1, 0))


def _check_hull(ctx: _Context) -> Check:
    n = ctx.n
    if n <= 1:
        return Check("hull", True, f"n = {n}: nothing to check")
    polygon = convex_hull_polygon(ctx.sites)
    hull = np.zeros(n, dtype=bool)
    hull[polygon] = True
    unbounded = np.zeros(n, dtype=bool)
    unbounded[ctx.site[(ctx.origin < 0) | (ctx.dest < 0)]] = True
    hidden_corners = np.zeros(0, dtype=np.int64)
    if ctx.weighted:
        if ctx.H == 0:
            extreme = np.unique(polygon[[0, -1]]) if polygon.size else polygon
            return Check("hull", False, "no edge, so at most one site has a cell, but the extreme sites of the hull "
                         "always have one", _ids(extreme), "site")
        # The lifted point of a hull corner is a vertex of the lower hull: never hidden. A site
        # on a hull edge may be hidden; if visible, its cell is unbounded.
        visible = ctx.visible
        prev, nxt = np.roll(polygon, 1), np.roll(polygon, -1)
        corner = np.array([orient2d(*ctx.sites[p], *ctx.sites[c], *ctx.sites[q]) != 0
                           for p, c, q in zip(prev, polygon, nxt)], dtype=bool) if polygon.size > 2 else \
            np.ones(polygon.size, dtype=bool)
        hidden_corners = polygon[corner & ~visible[polygon]]
        hull &= visible
    missing = np.flatnonzero(hull & ~unbounded)
    extra = np.flatnonzero(unbounded & ~hull)
    if hidden_corners.size:
        # Near-degenerate: each hidden corner nearly on the line of its hull neighbours (a
        # corner by a hair: a floating-point library sees a hull edge there).
        pos = np.full(n, -1, dtype=np.int64)
        pos[polygon] = np.arange(polygon.size)
        k = pos[hidden_corners]
        prev, nxt = polygon[(k - 1) % polygon.size], polygon[(k + 1) % polygon.size]
        extent = ctx.extents[0]
        ulps = [orient2d_ulps(*ctx.sites[p], *ctx.sites[c], *ctx.sites[q], extent)
                for p, c, q in zip(prev, hidden_corners, nxt)]
        within = bool(max(ulps) <= NEAR_DEGENERATE_ULPS)
        return Check("hull", False, f"{hidden_corners.size} corners of the convex hull are hidden (a hull corner "
                     f"always has a cell)" + ("; all corners by a hair (near-degenerate)" if within else ""),
                     _ids(hidden_corners), "site", within_tolerance=within)
    if not (missing.size or extra.size):
        what = "visible sites on the convex-hull boundary" if ctx.weighted else "sites on the convex-hull boundary"
        return Check("hull", True, f"{int(hull.sum())} unbounded cells = {what}")
    # Near-degenerate: an interior site, or a hull site, that a move of NEAR_DEGENERATE_ULPS
    # roundings of the data puts on the hull boundary (the segment joining its hull neighbours).
    limit = _FORGIVEN * ctx.extents[0]
    within = True
    q0, q1 = ctx.sites[polygon], ctx.sites[np.roll(polygon, -1)]
    for chunk in np.array_split(extra, max(1, extra.size * polygon.size // 4_000_000)):
        if chunk.size:
            dist = _segment_distance(ctx.sites[chunk][:, None, :], q0[None], q1[None]).min(axis=1)
            within &= bool((dist <= limit).all())
    if missing.size:
        pos = np.full(n, -1, dtype=np.int64)
        pos[polygon] = np.arange(polygon.size)
        k = pos[missing]
        prev, nxt = polygon[(k - 1) % polygon.size], polygon[(k + 1) % polygon.size]
        dist = _segment_distance(ctx.sites[missing], ctx.sites[prev], ctx.sites[nxt])
        within &= bool((dist <= limit).all())
    parts = []
    if missing.size:
        parts.append(f"{missing.size} hull sites have bounded cells")
    if extra.size:
        parts.append(f"{extra.size} interior sites have unbounded cells")
    if within:
        parts.append("all within tolerance of the hull boundary (near-degenerate)")
    return Check("hull", False, "; ".join(parts), _ids(np.concatenate([missing, extra])), "site", within_tolerance=within)


def _random_probes(ctx: _Context) -> NDArray[np.float64]:
    """``ctx.probes`` uniform points in the sites' bounding box, widened by 5% of the scale."""
    rng = np.random.default_rng(ctx.seed)
    lo, hi = ctx.sites.min(axis=0), ctx.sites.max(axis=0)
    pad = 0.05 * ctx.scale
    return rng.uniform(lo - pad, hi + pad, size=(ctx.probes, 2))


#: Besides its nearest site's cell, a random probe must not lie strictly inside the cells of
#: its next nearest sites (a cell that claims a neighbour's territory).
_PROBE_NEIGHBOURS = 3


@njit(cache=True)
def _probe_kernel(pts, cell, cptr, by_cell, sites, xy, site, twin, origin, scale, normal_min, rel_tol, outside,
                  strictly_inside, weights):
    """Where probe pts[i] lies relative to the polygon of cell[i] as the diagram draws it: each
    half-edge h bounds the cell by the line through its finite end (the diagram's own
    vertex), or through the sites' midpoint for a full line, in direction perp(b - a), with
    the cell on its left. outside[i]: beyond the tolerance outside some line;
    strictly_inside[i]: inside every line by more than the tolerance."""
    for i in range(pts.shape[0]):
        c = cell[i]
        px, py = pts[i, 0], pts[i, 1]
        if cptr[c + 1] == cptr[c]:
            outside[i] = True
            continue
        out, strictly_in = False, True
        for j in range(cptr[c], cptr[c + 1]):
            h = by_cell[j]
            a, b = site[h], site[twin[h]]
            dx, dy = -(sites[b, 1] - sites[a, 1]), sites[b, 0] - sites[a, 0]
            w = origin[h] if origin[h] >= 0 else origin[twin[h]]
            if w >= 0:
                ax, ay = xy[w, 0], xy[w, 1]
            else:
                # a full line: the (power) bisector, through the midpoint moved towards the
                # lighter site by (w_a - w_b) / (2 |b - a|^2) of b - a
                ex, ey = sites[b, 0] - sites[a, 0], sites[b, 1] - sites[a, 1]
                t = 0.5 + 0.5 * (weights[a] - weights[b]) / (ex * ex + ey * ey)
                ax, ay = sites[a, 0] + t * ex, sites[a, 1] + t * ey
            side = (dx * (py - ay) - dy * (px - ax)) / np.hypot(dx, dy)   # signed distance, + = left
            radius = np.hypot(ax - sites[a, 0], ay - sites[a, 1])
            tol = allowed_error(rel_tol, max(scale, radius), max(abs(px), abs(py), abs(ax), abs(ay), normal_min))
            if not side >= -tol:                 # NaN counts as outside
                out = True
            if not side > tol:
                strictly_in = False
        outside[i], strictly_inside[i] = out, strictly_in


@njit(cache=True)
def _site_probe_kernel(sites, xy, site, twin, origin, scale, normal_min, rel_tol, outside):
    """outside[i]: site i is outside the polygon of its own cell (same lines as
    :func:`_probe_kernel`); one pass over the half-edges in order."""
    for h in range(site.size):
        a, b = site[h], site[twin[h]]
        dx, dy = -(sites[b, 1] - sites[a, 1]), sites[b, 0] - sites[a, 0]
        w = origin[h] if origin[h] >= 0 else origin[twin[h]]
        if w >= 0:
            ax, ay = xy[w, 0], xy[w, 1]
        else:
            ax, ay = 0.5 * (sites[a, 0] + sites[b, 0]), 0.5 * (sites[a, 1] + sites[b, 1])
        px, py = sites[a, 0], sites[a, 1]
        side = (dx * (py - ay) - dy * (px - ax)) / np.hypot(dx, dy)
        radius = np.hypot(ax - px, ay - py)
        tol = allowed_error(rel_tol, max(scale, radius), max(abs(px), abs(py), abs(ax), abs(ay), normal_min))
        if not side >= -tol:
            outside[a] = True


#: The most tied candidates a probe is checked against when every nearer one ties.
_MAX_TIES = 256


def _nearest_cells(ctx: _Context, pts: NDArray[np.float64], k: int) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """(distances, site ids), each (m, k): the k sites nearest each point (smallest power, the
    power differences as lengths by the local radius of the smallest, in a power diagram)."""
    if ctx.weighted:
        # by power, recomputed for the tree's candidates; differences as lengths by the local
        # radius of the smallest (never by the largest weight anywhere)
        powers, near = _smallest_powers(ctx, pts, k)
        diff0 = pts - ctx.sites[near[:, 0]]
        local = np.sqrt((diff0 ** 2).sum(axis=1) + np.abs(ctx.weights[near[:, 0]]))
        return (powers - powers[:, :1]) / (2 * np.maximum(local, 1e-300))[:, None], near
    dist, near = ctx.query(pts, k=k)
    return dist.reshape(pts.shape[0], k), near.reshape(pts.shape[0], k).astype(np.int64)


def _probes_near_degenerate(ctx: _Context, pts: NDArray[np.float64], near: NDArray[np.int64],
                            tie: NDArray[np.bool_], out_q: NDArray[np.bool_], in_q: NDArray[np.bool_],
                            bad_own: NDArray[np.int64]) -> bool:
    """Whether the probes' failures are near-degenerate: each probe's cell is one of a site whose
    power (squared distance) there is within NEAR_DEGENERATE_ULPS roundings of the lifted
    coordinates of the smallest, and so is every cell that claims it: ties, as far as a
    floating-point library can tell. A probe whose cell is none of its first candidates' is
    asked again with up to ``_MAX_TIES`` of them, as the strict check does."""
    limit = _FORGIVEN * ctx.extents[1]
    near_tie = (_power_gaps(ctx, pts, near) <= limit) | tie
    if (in_q & ~near_tie).any():
        return False
    lost = bad_own[~(near_tie[bad_own] & ~out_q[bad_own]).any(axis=1)]
    if lost.size and near.shape[1] < ctx.n:
        _, near2 = _nearest_cells(ctx, pts[lost], min(ctx.n, _MAX_TIES))
        out2, _ = _probe_cells(ctx, pts[lost], near2)
        lost = lost[~((_power_gaps(ctx, pts[lost], near2) <= limit) & ~out2).any(axis=1)]
    return lost.size == 0


def _power_gaps(ctx: _Context, pts: NDArray[np.float64], near: NDArray[np.int64]) -> NDArray[np.float64]:
    """(m, k): each candidate's power at its point (squared distance in an ordinary diagram)
    above the first candidate's."""
    diff = pts[:, None, :] - ctx.sites[near]
    powers = (diff ** 2).sum(axis=2) - (ctx.weights[near] if ctx.weighted else 0.0)
    return powers - powers[:, :1]


def _probe_cells(ctx: _Context, pts: NDArray[np.float64], near: NDArray[np.int64]
                 ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """(outside, strictly inside), each (m, k): where each point lies relative to the cells of
    its candidate sites ``near``, as the diagram draws them (:func:`_probe_kernel`)."""
    n, k = ctx.n, near.shape[1]
    rows = np.repeat(pts, k, axis=0)
    cell = near.reshape(-1)
    # Through the half-edges of the cells touched, grouped by cell.
    touched = np.zeros(n, dtype=bool)
    touched[cell] = True
    hs = np.flatnonzero(touched[ctx.site])
    by_cell = hs[argsort_keys(ctx.site[hs])]
    cptr = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(ctx.site[hs], minlength=n), out=cptr[1:])
    outside = np.zeros(rows.shape[0], dtype=bool)
    strictly_inside = np.zeros(rows.shape[0], dtype=bool)
    xy = ctx.xy if ctx.V else read_only(np.zeros((1, 2)))
    wt = ctx.weights if ctx.weighted else np.zeros(n)
    _probe_kernel(rows, cell, cptr, by_cell, ctx.sites, xy, ctx.site, ctx.twin, ctx.origin,
                  ctx.scale, ctx.normal_min, PROBE_REL_TOL, outside, strictly_inside, wt)
    return outside.reshape(-1, k), strictly_inside.reshape(-1, k)


def _check_probes(ctx: _Context) -> Check:
    n = ctx.n
    if n <= 1:
        return Check("probes", True, f"n = {n}: one cell is the whole plane")
    random = _random_probes(ctx)
    if ctx.weighted:
        # The hidden sites' own positions are probed too: were one wrongly hidden, its
        # position may well be where its power is the smallest.
        hidden = np.flatnonzero(~ctx.visible) if ctx.H else np.arange(n)
        random = np.concatenate([random, ctx.sites[hidden]])
        if ctx.H == 0:
            owner = np.unique(ctx.query(random)[1])
            return Check("probes", False, f"the diagram has no edge, but {owner.size} different sites have the "
                         f"smallest power among {random.shape[0]} probes", _ids(owner), "site")
    k = min(n, 1 + _PROBE_NEIGHBOURS)
    dist, near = _nearest_cells(ctx, random, k)
    # Sites as near as the nearest one, to float precision, are ties: the probe may be in any
    # of their cells (on their common boundary, as far as floats can tell).
    slack = length_tolerance(PROBE_REL_TOL, ctx.scale, ctx.magnitude(np.abs(random).max(1)))
    tie = dist - dist[:, :1] <= slack[:, None]
    out_q, in_q = _probe_cells(ctx, random, near)
    bad_own = np.flatnonzero(~(tie & ~out_q).any(axis=1))      # in no cell of a nearest site
    # Every candidate a tie: sites far closer to each other than to the probe (a cluster seen
    # from afar, 2**62 away) tie beyond the k the tree returned, and the probe's own cell may
    # be one of those. Ask again, with every tie.
    crowded = bad_own[tie[bad_own].all(axis=1)] if k < n else bad_own[:0]
    if crowded.size:
        kk = min(n, _MAX_TIES)
        dist2, near2 = _nearest_cells(ctx, random[crowded], kk)
        tie2 = dist2 - dist2[:, :1] <= slack[crowded, None]
        out2, _ = _probe_cells(ctx, random[crowded], near2)
        found = (tie2 & ~out2).any(axis=1)
        bad_own = np.setdiff1d(bad_own, crowded[found])
    claims = in_q & ~tie                                        # strictly inside a farther site's cell
    bad_other = np.flatnonzero(claims.reshape(-1))
    xy = ctx.xy if ctx.V else read_only(np.zeros((1, 2)))
    site_outside = np.zeros(n, dtype=bool)
    if not ctx.weighted:                # a power cell need not hold its own site
        site_outside[np.bincount(ctx.site, minlength=n) == 0] = True          # a site without a cell
        _site_probe_kernel(ctx.sites, xy, ctx.site, ctx.twin, ctx.origin, ctx.scale, ctx.normal_min, PROBE_REL_TOL,
                           site_outside)
    bad_sites = np.flatnonzero(site_outside)
    within = bad_sites.size == 0 and _probes_near_degenerate(ctx, random, near, tie, out_q, in_q, bad_own)
    if bad_own.size or bad_other.size or bad_sites.size:
        parts, ids = [], []
        if bad_sites.size:
            parts.append(f"{bad_sites.size} sites lie outside their own cell")
            ids += _ids(bad_sites)
        if bad_own.size:
            q = int(bad_own[0])
            parts.append(f"{bad_own.size} of {ctx.probes} random probes lie outside the cell of their nearest "
                         f"site (first: ({ctx.unscaled(random[q, 0]):.6g}, {ctx.unscaled(random[q, 1]):.6g}) "
                         f"nearest to site {int(near[q, 0])})")
            ids += _ids(near[bad_own, 0])
        if bad_other.size:
            q, j = divmod(int(bad_other[0]), k)
            parts.append(f"{bad_other.size} times a cell claims a random probe nearer to another site (first: "
                         f"({ctx.unscaled(random[q, 0]):.6g}, {ctx.unscaled(random[q, 1]):.6g}) inside cell "
                         f"{int(near[q, j])}, nearest site "
                         f"{int(near[q, 0])})")
            ids += _ids(near.reshape(-1)[bad_other])
        if within:
            parts.append("all near-degenerate (ties within roundings of the lifted coordinates)")
        return Check("probes", False, "; ".join(parts), [int(i) for i in dict.fromkeys(ids)][:_MAX_IDS], "site",
                     within_tolerance=within)
    if ctx.weighted:
        return Check("probes", True, f"{random.shape[0]} probes ({ctx.probes} random, the rest at hidden sites) lie "
                                     f"in the cell of their smallest power and no other of the {k} smallest")
    return Check("probes", True, f"{ctx.probes} random probes lie in their nearest site's cell and no other of "
                                 f"the {k} nearest; all {n} sites lie in their own cell")


_RUNNERS: dict[str, Callable[[_Context], Check]] = {
    "structure": _check_structure,
    "vertices": _check_vertices,
    "edges": _check_edges,
    "topology": _check_topology,
    "euler": _check_euler,
    "hull": _check_hull,
    "probes": _check_probes,
}


# ---------------------------------------------------------------------------------- entry point
def certify(diagram: Diagram, *, probes: int = DEFAULT_PROBES, seed: int = 0) -> Certificate:
    """Run every check of this module on ``diagram``; never raises on a broken diagram.

    ``probes``: number of random probe points (every site is probed too); ``seed`` seeds them.

    >>> import impls, datasets_gen
    >>> certify(impls.build("qhull", datasets_gen.generate("uniform", 100))).ok
    True
    """
    d = diagram
    counts = {"n": d.n_sites, "V": d.n_vertices, "E": d.n_edges}
    problem = _usable(d)
    if problem is not None:
        checks = [Check("structure", False, problem)]
        checks += [Check(name, False, "not run: the index arrays are unusable") for name in CHECKS[1:]]
        return Certificate(False, checks, counts)
    origin = np.asarray(d.origin, np.int64)
    twin = np.asarray(d.twin, np.int64)
    sites = np.ascontiguousarray(d.sites, dtype=np.float64)
    xy = np.ascontiguousarray(d.vertices, dtype=np.float64)
    # Judged at sites * 2**shift, largest coordinate in [0.5, 1): exact, no under/overflow.
    shift, range_problem = comfortable_shift(sites[np.isfinite(sites).all(axis=1)])
    if shift:
        sites = scale_points(sites, shift)
        with np.errstate(over="ignore", under="ignore"):
            xy = scale_points(xy, shift)
    # read-only views throughout: the kernels see one kind of array whichever diagram it is
    sites, xy, origin, twin = read_only(sites), read_only(xy), read_only(origin), read_only(twin)
    ctx = _Context(d, sites, xy, origin, twin, read_only(np.asarray(d.site, np.int64)), read_only(origin[twin]),
                   data_scale(sites), d.n_sites, d.n_vertices, d.n_half_edges, seed, int(probes), shift,
                   smallest_normal(shift), range_problem)
    if d.weights is not None and np.shape(d.weights) == (d.n_sites,):
        w = np.ldexp(np.asarray(d.weights, np.float64), 2 * shift)
        if w.size and not (w == w[0]).all():        # equal weights: the ordinary diagram
            ctx.weights, ctx.lift2, ctx.weighted = w, w.max() - w, True
    checks = []
    for name in CHECKS:
        t0 = time.perf_counter_ns()
        try:
            check = _RUNNERS[name](ctx)
        except Exception as exc:  # a check that cannot run on this diagram has failed
            check = Check(name, False, f"could not run: {type(exc).__name__}: {exc}")
        check.seconds = (time.perf_counter_ns() - t0) / 1e9
        checks.append(check)
        if name == "structure":
            ctx.structure_ok = check.ok
    return Certificate(all(c.ok for c in checks), checks, counts)
