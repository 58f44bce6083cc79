"""Are two diagrams the same Voronoi diagram? A combinatorial comparison after exact normalisation.

Canonical form of a DCEL: a vertex is the set of sites whose cells touch it; an edge is its
site pair (a, b) plus its two end vertices in the direction perp(b - a) (infinity included);
a cell is the cyclic sequence of its neighbours, stored as "after neighbour x comes y".
None of these depend on how an implementation numbers its vertices or half-edges.

Normalisation: a Voronoi vertex of degree k >= 4 (k cocircular sites) may be one vertex or
k - 2 vertices joined by zero-length edges. An edge is contracted when *all* the sites of
both its end vertices are cocircular, decided with the exact ``incircle`` predicate on the
sites (never from the rounded vertex coordinates), so both forms compare equal ("exact").
Floating-point libraries (Qhull) also decide *nearly* degenerate configurations either way,
so if the exact comparison fails, an edge is contracted in both diagrams as well when its
configuration is near-degenerate by the certifier's rule: every site of its two end vertices
is within ``ulps`` roundings of the data (``NEAR_DEGENERATE_ULPS``) of lying on the circle of
the edge's sites and a third, or that third on their line
(:mod:`vorobench.core.predicates.degeneracy`). A vertex whose sites are all within ``ulps``
roundings of one line (a sliver's circumcentre, far out) is taken to be at infinity, as a
floating-point library may put it: its edges become rays, and an edge between two such
vertices is dropped. That is decided per configuration from the sites, never from an edge's length, so it is the same at 10 and at 10^6 sites; then the
comparison is repeated ("within_tolerance"). A vertex merged under tolerance may then lie
anywhere within its members' spread when coordinates are matched.

Any magnitude: both diagrams are compared at their coordinates times one power of two (exact),
the largest site coordinate in [0.5, 1) (:func:`vorobench.core.scaling.comfortable_shift`), where
incircle is exact and no distance or tolerance underflows or overflows (at subnormal and
1e-200 scale the exact contraction's incircle tests underflowed); subnormal coordinates'
absolute rounding (2**-1075) is allowed for. Reported coordinates and lengths are in the
diagrams' own units.

Everything is sorting and array indexing; n = 10^6 takes seconds.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Any, Optional

import numpy as np
from numba import njit
from numpy.typing import NDArray
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from vorobench.core.diagram import Diagram
from vorobench.core.incidence import vertex_site_lists
from vorobench.core.predicates import incircle, orient2d, power_test
from vorobench.core.predicates.degeneracy import incircle_ulps, lift_extent, orient2d_ulps, power_test_ulps
from vorobench.core.read_only import read_only
from vorobench.core.scaling import comfortable_shift, scale_points, smallest_normal
from vorobench.core.sorting import argsort_keys, dense_rank, is_member, sorted_unique
from vorobench.core.tolerances import (
    COINCIDENCE_FILTER_REL_TOL,
    COINCIDENCE_FILTER_ULPS,
    NEAR_DEGENERATE_ULPS,
    VERTEX_MATCH_REL_TOL,
    circumcentre_tolerance,
    data_scale,
)
from vorobench.judge.outcomes import Verdict

__all__ = ["compare", "Comparison", "Difference", "VERDICTS", "DIFFERENCE_KINDS"]

#: Possible values of :attr:`Comparison.verdict`.
VERDICTS = (Verdict.EXACT, Verdict.WITHIN_TOLERANCE, Verdict.DIFFERS)

#: Kinds of difference counted in :attr:`Comparison.counts`, with a readable label.
DIFFERENCE_KINDS: dict[str, str] = {
    "site_mismatch": "sites only in one diagram",
    "weight_mismatch": "sites whose weights differ (beyond one constant added to all)",
    "hidden_only_in_a": "sites hidden (no cell) only in {a}",
    "hidden_only_in_b": "sites hidden (no cell) only in {b}",
    "invalid_structure": "diagrams that are not valid DCELs",
    "vertices_only_in_a": "vertices (site sets) only in {a}",
    "vertices_only_in_b": "vertices (site sets) only in {b}",
    "duplicate_vertices": "site sets used by two vertices of one diagram",
    "edges_only_in_a": "edges (site pairs) only in {a}",
    "edges_only_in_b": "edges (site pairs) only in {b}",
    "duplicate_edges": "site pairs with two edges in one diagram",
    "edges_with_different_ends": "edges whose end vertices or direction differ",
    "cells_with_different_neighbours": "cells whose cyclic neighbour sequence differs",
    "coordinate_mismatches": "matched vertices farther apart than the tolerance",
}

_MAX_LISTED = 5          # differences listed per kind
_MAX_SHORT_LISTED = 10   # short edges listed per diagram


@dataclass
class Difference:
    """One difference, with the site indices involved and the relevant coordinates."""

    kind: str
    sites: tuple[int, ...]
    detail: str
    points: list[tuple[float, float]] = field(default_factory=list)

    def __str__(self) -> str:
        return f"{self.kind}: sites {list(self.sites)}: {self.detail}"


@dataclass
class Comparison:
    """Result of :func:`compare`: the verdict, counts of each kind of difference, examples."""

    equal: bool
    verdict: Verdict
    counts: dict[str, int]
    differences: list[Difference]
    labels: tuple[str, str] = ("a", "b")
    n_sites: int = 0
    sizes: dict[str, dict[str, int]] = field(default_factory=dict)
    scale: float = 1.0
    #: near-degenerate: within this many roundings of the data of a degenerate configuration
    ulps: float = NEAR_DEGENERATE_ULPS
    coord_tol: float = VERTEX_MATCH_REL_TOL
    max_vertex_error: float = 0.0
    #: Largest vertex error as a multiple of its allowed error (<= 1: within tolerance).
    max_vertex_error_ratio: float = 0.0
    sites_reordered: bool = False
    zero_length_edges: dict[str, int] = field(default_factory=dict)
    short_edge_counts: dict[str, int] = field(default_factory=dict)
    short_edges: list[dict[str, Any]] = field(default_factory=list)
    structure_errors: dict[str, str] = field(default_factory=dict)
    #: Half-edge ids (in each diagram's own numbering) of the differing edges, for plotting.
    highlight_a: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, np.int64), repr=False)
    highlight_b: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, np.int64), repr=False)

    @property
    def n_differences(self) -> int:
        return int(sum(self.counts.values()))

    def to_dict(self) -> dict[str, Any]:
        """JSON-serialisable summary (highlight arrays as lists)."""
        out = {k: _plain(v) for k, v in asdict(self).items() if k not in ("highlight_a", "highlight_b", "differences")}
        out["differences"] = [_plain(asdict(d)) for d in self.differences]
        out["highlight_a"] = self.highlight_a.tolist()
        out["highlight_b"] = self.highlight_b.tolist()
        return out

    def __str__(self) -> str:
        a, b = self.labels
        sa, sb = self.sizes.get(a, {}), self.sizes.get(b, {})
        head = {Verdict.EXACT: "EQUAL (exact)",
                Verdict.WITHIN_TOLERANCE: "EQUAL within tolerance"}.get(self.verdict, "DIFFERENT")
        lines = [f"compare {a} vs {b}: {head}  [n={self.n_sites}; V={sa.get('V', '?')}/{sb.get('V', '?')}, "
                 f"E={sa.get('E', '?')}/{sb.get('E', '?')}]"]
        if self.sites_reordered:
            lines.append("  sites are the same set in a different order (matched by sorting)")
        for name, msg in self.structure_errors.items():
            lines.append(f"  {name} is not a valid DCEL: {msg}")
        zl = {k: v for k, v in self.zero_length_edges.items() if v}
        if zl:
            lines.append("  zero-length edges contracted exactly (cocircular sites): "
                         + ", ".join(f"{k}: {v}" for k, v in zl.items()))
        if self.short_edge_counts and any(self.short_edge_counts.values()):
            lines.append(f"  contracted under tolerance (near-degenerate: sites within {self.ulps:g} roundings of "
                         f"the data of one circle): "
                         + ", ".join(f"{k}: {v}" for k, v in self.short_edge_counts.items()))
            for s in self.short_edges[:_MAX_SHORT_LISTED]:
                lines.append(f"    {s['diagram']}: edge between sites {s['sites']}, length {s['length']:.3g}")
        lines.append(f"  max vertex error {self.max_vertex_error:.3g} of the local scale, "
                     f"{self.max_vertex_error_ratio:.3g} x the allowed error (tolerance {self.coord_tol:g})")
        for kind, count in self.counts.items():
            if count:
                lines.append(f"  {count} {DIFFERENCE_KINDS[kind].format(a=a, b=b)}")
        if self.differences:
            lines.append("  first differences:")
            lines.extend(f"    {d}" for d in self.differences)
        return "\n".join(lines)


def _plain(x: Any) -> Any:
    """numpy scalars/arrays and tuples to plain JSON types."""
    if isinstance(x, dict):
        return {str(k): _plain(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_plain(v) for v in x]
    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    return x


# ---------------------------------------------------------------------------------- sites
def _site_matching(a: Diagram, b: Diagram) -> tuple[Optional[NDArray[np.int64]], list[Difference], int]:
    """Map b's site ids to a's. Returns (map or None if the sets differ, differences, count)."""
    sa, sb = np.asarray(a.sites, np.float64), np.asarray(b.sites, np.float64)
    if sa.shape == sb.shape and np.array_equal(sa, sb):
        return np.arange(sa.shape[0], dtype=np.int64), [], 0
    oa, ob = np.lexsort((sa[:, 1], sa[:, 0])), np.lexsort((sb[:, 1], sb[:, 0]))
    if sa.shape == sb.shape and np.array_equal(sa[oa], sb[ob]):
        mapping = np.empty(sb.shape[0], dtype=np.int64)
        mapping[ob] = oa
        return mapping, [], 0
    # Different sets: list the sites found in one diagram only.
    va = np.ascontiguousarray(sa + 0.0).view(np.dtype((np.void, 16))).ravel()
    vb = np.ascontiguousarray(sb + 0.0).view(np.dtype((np.void, 16))).ravel()
    only_a = np.flatnonzero(~np.isin(va, vb))
    only_b = np.flatnonzero(~np.isin(vb, va))
    diffs = [Difference("site_mismatch", (int(i),), f"site {tuple(sa[i].tolist())} only in a",
                        [tuple(sa[i].tolist())]) for i in only_a[:_MAX_LISTED]]
    diffs += [Difference("site_mismatch", (int(i),), f"site {tuple(sb[i].tolist())} only in b",
                         [tuple(sb[i].tolist())]) for i in only_b[:_MAX_LISTED]]
    count = int(only_a.size + only_b.size)
    if count == 0:  # same set with repeats (not prepared sites)
        count = abs(sa.shape[0] - sb.shape[0]) or 1
        diffs.append(Difference("site_mismatch", (), f"{sa.shape[0]} sites in a, {sb.shape[0]} in b"))
    return None, diffs, count


def _indices_usable(d: Diagram) -> bool:
    """Whether the index arrays can be used for indexing at all (shapes and ranges)."""
    H, V, n = d.n_half_edges, d.n_vertices, d.n_sites
    arrays = (d.origin, d.twin, d.next, d.site)
    if any(np.shape(x) != (H,) or np.asarray(x).dtype.kind not in "iu" for x in arrays):
        return False
    if H == 0:
        return True
    return bool(d.origin.min() >= -1 and d.origin.max() < V and d.twin.min() >= 0 and d.twin.max() < H
                and d.next.min() >= 0 and d.next.max() < H and d.site.min() >= 0 and d.site.max() < n)


def _structure_error(d: Diagram) -> Optional[str]:
    """The first broken local DCEL invariant, or None. Cheap O(H) checks only (twins, cells,
    ``next``); :func:`vorobench.certify` runs the full :meth:`Diagram.validate`."""
    if not _indices_usable(d):
        return "index arrays have the wrong shape or an index out of range"
    finite = np.isfinite(np.asarray(d.vertices, np.float64)).all(axis=1)
    if not finite.all():
        return f"vertex {int(np.flatnonzero(~finite)[0])} is not finite ({int((~finite).sum())} in all)"
    H = d.n_half_edges
    if H == 0:
        return None if d.n_sites <= 1 or d.weights is not None else f"{d.n_sites} sites but no edges"
    h = np.arange(H)
    twin, nxt, site, origin = (np.asarray(x, np.int64) for x in (d.twin, d.next, d.site, d.origin))
    for bad, text in (
            (lambda: (twin == h) | (twin[twin] != h), "twin is not an involution without fixed points"),
            (lambda: site[twin] == site, "a half-edge and its twin bound the same cell"),
            (lambda: site[nxt] != site, "next leaves the cell"),
            (lambda: np.bincount(nxt, minlength=H) != 1, "next is not a permutation"),
            (lambda: origin[nxt] != origin[twin], "a half-edge's next does not start where it ends")):
        mask = bad()
        if mask.any():
            return f"{text} (half-edge {int(np.flatnonzero(mask)[0])})"
    return None


# ---------------------------------------------------------------------------------- canonical form
@dataclass
class _Form:
    """One diagram after contraction, in the common site numbering."""

    m_ptr: NDArray[np.int64]          # (M+1,) CSR of merged vertices' sorted site lists
    m_sites: NDArray[np.int64]
    m_xy: NDArray[np.float64]         # (M, 2) mean coordinates of the merged vertices
    m_extent: NDArray[np.float64]     # (M,) largest distance of a member from that mean
    h: NDArray[np.int64]              # kept half-edges (original ids)
    tw: NDArray[np.int64]             # position of each kept half-edge's twin among the kept ones
    cell: NDArray[np.int64]
    nb: NDArray[np.int64]
    start: NDArray[np.int64]          # merged vertex id, -1 = infinity
    end: NDArray[np.int64]
    succ_nb: NDArray[np.int64]        # neighbour across the next kept half-edge of the cell
    n_exact: int                      # edges contracted as exactly zero-length
    short: list[tuple[int, int, float]]  # edges contracted under tolerance: (a, b, length)
    n_short: int
    m_cv: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, np.int64))

    def __post_init__(self) -> None:
        # Read-only views of the arrays given (the diagram's own, or new ones): the kernels that
        # read them then see one kind of array. ``m_cv`` is filled in later and stays writable.
        for name, value in vars(self).items():
            if isinstance(value, np.ndarray) and name != "m_cv":
                setattr(self, name, read_only(value))


def _exactly_coincident(sites, xy, ptr, s, a, b, u, v, scale: float, normal_min: float,
                        weights: Optional[NDArray[np.float64]] = None) -> NDArray[np.bool_]:
    """Edges (a, b) from vertex u to v whose end vertices coincide: all sites of u and v on one circle.

    Decided exactly on the sites: with c a third site of u, every site x of u and v other
    than a, b, c must satisfy incircle(a, b, c, x) == 0, and a, b, c must not be collinear.
    With ``weights`` (a power diagram) the test is ``power_test == 0``: the lifted points
    (x, y, x^2 + y^2 - w) of all of them lie in one plane.
    Vertices whose coordinates lie farther apart than any rounding of a circumcentre could
    explain (``COINCIDENCE_FILTER_*``) are not tested: that settles almost every edge cheaply.
    ``normal_min``: the smallest normal float in these units (subnormals are rounded absolutely).
    """
    out = np.zeros(a.size, dtype=bool)
    if a.size:
        weighted = weights is not None
        w = np.asarray(weights, np.float64) if weighted else np.zeros(sites.shape[0])
        _coincident_kernel(sites, xy, ptr, s, a, b, u, v, scale, normal_min, COINCIDENCE_FILTER_REL_TOL,
                           COINCIDENCE_FILTER_ULPS * np.finfo(np.float64).eps, out, w, weighted)
    return out


@njit(cache=True)
def _coincident_kernel(sites, xy, ptr, s, a, b, u, v, scale, normal_min, filter_rel, filter_abs, out, wt,
                       weighted):
    for k in range(a.size):
        aa, bb, uu, vv = a[k], b[k], u[k], v[k]
        ax, ay, bx, by = sites[aa, 0], sites[aa, 1], sites[bb, 0], sites[bb, 1]
        # Float filter: two roundings of one circumcentre (radius R, sites a, b at distance L)
        # lie within ~eps R^2 / L of each other, and certify() accepts no vertex off by more
        # than a small fraction of R; far more than both means two different vertices.
        px, py, qx, qy = xy[uu, 0], xy[uu, 1], xy[vv, 0], xy[vv, 1]
        radius = np.hypot(px - ax, py - ay)
        if weighted:        # the power circle's radius: sqrt of the vertex's power
            radius = np.sqrt(max(radius * radius - wt[aa], 0.0)) + radius
        magnitude = max(abs(px), abs(py), abs(qx), abs(qy), normal_min)
        bound = filter_rel * max(radius, scale) + \
            filter_abs * (magnitude + radius * radius / max(np.hypot(ax - bx, ay - by), 1e-300))
        if np.hypot(px - qx, py - qy) > bound:
            continue
        c, hits = -1, 0
        for j in range(ptr[uu], ptr[uu + 1]):
            if s[j] == aa or s[j] == bb:
                hits += 1
            elif c < 0:
                c = s[j]
        for j in range(ptr[vv], ptr[vv + 1]):
            if s[j] == aa or s[j] == bb:
                hits += 1
        # Both ends must touch both cells a and b, and u needs a third site off the line ab.
        if hits != 4 or c < 0:
            continue
        cx, cy = sites[c, 0], sites[c, 1]
        if orient2d(ax, ay, bx, by, cx, cy) == 0:
            continue
        same = True
        for w in (uu, vv):
            for j in range(ptr[w], ptr[w + 1]):
                x = s[j]
                if x == aa or x == bb or x == c:
                    continue
                if weighted:
                    side = power_test(ax, ay, wt[aa], bx, by, wt[bb], cx, cy, wt[c], sites[x, 0], sites[x, 1], wt[x])
                else:
                    side = incircle(ax, ay, bx, by, cx, cy, sites[x, 0], sites[x, 1])
                if side != 0:
                    same = False
                    break
            if not same:
                break
        out[k] = same


def _merge_labels(V: int, u: NDArray[np.int64], v: NDArray[np.int64]) -> NDArray[np.int64]:
    """Union-find of vertices joined by contracted edges (connected components), as labels."""
    if u.size == 0:
        return np.arange(V, dtype=np.int64)

    graph = coo_matrix((np.ones(u.size, dtype=np.int8), (u, v)), shape=(V, V))
    _, labels = connected_components(graph, directed=False)
    return labels.astype(np.int64)


def _successor(nxt: NDArray[np.int64], kept: NDArray[np.bool_]) -> NDArray[np.int64]:
    """For each half-edge, the first kept half-edge strictly after it along ``next``
    (pointer doubling over removed half-edges); -1 if the cycle has no kept half-edge."""
    H = nxt.size
    jump = np.where(kept, np.arange(H), nxt)
    for _ in range(64):
        if kept[jump].all():
            break
        jump = jump[jump]
    succ = jump[nxt]
    return np.where(kept[succ], succ, -1)


@njit(cache=True)
def _flat_vertex_kernel(sites, ptr, s, ulps, extent, out):
    """out[v]: every site of vertex v is within ``ulps`` roundings of the data of one line."""
    for v in range(ptr.size - 1):
        if ptr[v + 1] - ptr[v] < 3:
            continue
        a, b = s[ptr[v]], s[ptr[v] + 1]
        flat = True
        for j in range(ptr[v] + 2, ptr[v + 1]):
            c = s[j]
            if orient2d_ulps(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1],
                             extent) > ulps:
                flat = False
                break
        out[v] = flat


@njit(cache=True)
def _near_degenerate_kernel(sites, ptr, s, a, b, u, v, ulps, extent, lifted, out, weights, weighted):
    """out[k]: edge (a, b) from u to v joins vertices of nearly cocircular sites, as a
    floating-point library may merge them: with c a third site of u, every other site x of u
    and v is within ``ulps`` roundings of the data of the circle (lifted plane) of a, b, c."""
    for k in range(a.size):
        aa, bb = a[k], b[k]
        c = -1
        for j in range(ptr[u[k]], ptr[u[k] + 1]):
            if s[j] != aa and s[j] != bb:
                c = s[j]
                break
        if c < 0:
            continue
        ax, ay, bx, by, cx, cy = sites[aa, 0], sites[aa, 1], sites[bb, 0], sites[bb, 1], sites[c, 0], sites[c, 1]
        near = True
        for z in (u[k], v[k]):
            for j in range(ptr[z], ptr[z + 1]):
                x = s[j]
                if x == aa or x == bb or x == c:
                    continue
                px, py = sites[x, 0], sites[x, 1]
                if weighted:
                    m = power_test_ulps(ax, ay, weights[aa], bx, by, weights[bb], cx, cy, weights[c], px, py,
                                        weights[x], extent, lifted)
                else:
                    m = incircle_ulps(ax, ay, bx, by, cx, cy, px, py, extent, lifted)
                if m > ulps:
                    near = False
                    break
            if not near:
                break
        out[k] = near


def _canonical(d: Diagram, site_map: NDArray[np.int64], n: int, ulps: Optional[float], scale: float,
               consistent: bool, normal_min: float = 0.0, weights: Optional[NDArray[np.float64]] = None) -> _Form:
    """Canonical form of ``d``: contract exactly-zero edges (and, with ``ulps``, edges of
    near-degenerate configurations, :func:`_near_degenerate_kernel`), merge
    their vertices, list the kept half-edges with their merged ends. ``consistent``: the
    local DCEL invariants hold, so origins alone give every vertex-cell incidence."""
    sites = np.asarray(d.sites, np.float64)
    identity = bool(np.array_equal(site_map, np.arange(site_map.size)))
    site = np.asarray(d.site, np.int64) if identity else site_map[np.asarray(d.site, np.int64)]
    common_sites = sites if identity else np.empty_like(sites)
    if not identity:
        common_sites[site_map] = sites
    origin = np.asarray(d.origin, np.int64)
    twin = np.asarray(d.twin, np.int64)
    nxt = np.asarray(d.next, np.int64)
    V, H = d.n_vertices, d.n_half_edges
    dest = origin[twin] if H else origin
    common_sites = read_only(common_sites)      # one compilation of the kernels below
    ptr, s = vertex_site_lists(site, origin, None if consistent else dest, V, max(n, 1))
    at_infinity = np.zeros(H, dtype=bool)
    extent = scale / 2.0
    if ulps is not None and V and H:
        # A vertex of nearly collinear sites (a sliver's circumcentre, far out) is nearly at
        # infinity: a floating-point library may put it there. Its edges become rays, and an
        # edge between two such vertices lies at infinity and is dropped.
        flat = np.zeros(V, dtype=bool)
        _flat_vertex_kernel(common_sites, ptr, s, float(ulps), extent, flat)
        if flat.any():
            was_infinite = (origin < 0) & (dest < 0)
            origin = np.where((origin >= 0) & flat[np.maximum(origin, 0)], -1, origin)
            dest = origin[twin]
            at_infinity = (origin < 0) & (dest < 0) & ~was_infinite
            ptr, s = vertex_site_lists(site, origin, None if consistent else dest, V, max(n, 1))
    # Candidate edges for contraction: one half-edge per pair, both ends finite.
    e = np.flatnonzero((np.arange(H) < twin) & (origin >= 0) & (dest >= 0))
    u, v = origin[e], dest[e]
    loop = u == v
    a, b = site[e], site[twin[e]]
    exact = loop.copy()
    xy = read_only(np.asarray(d.vertices, np.float64).reshape(-1, 2))
    exact[~loop] = _exactly_coincident(common_sites, xy, ptr, s, a[~loop], b[~loop], u[~loop], v[~loop], scale,
                                       normal_min, weights)
    contract = exact.copy()
    short: list[tuple[int, int, float]] = []
    n_short = 0
    if ulps is not None and e.size:
        length = np.hypot(*(xy[u] - xy[v]).T)
        is_short = np.zeros(e.size, dtype=bool)
        weighted = weights is not None
        w = np.asarray(weights, np.float64) if weighted else np.zeros(0)
        lifted = lift_extent(extent, float(np.abs(w).max()) if weighted and w.size else 0.0)
        _near_degenerate_kernel(common_sites, ptr, s, a, b, u, v, float(ulps), extent, lifted, is_short, w, weighted)
        is_short &= ~exact
        n_short = int(is_short.sum())
        for k in np.flatnonzero(is_short)[:_MAX_SHORT_LISTED]:
            short.append((int(min(a[k], b[k])), int(max(a[k], b[k])), float(length[k])))
        contract |= is_short
    merge = contract & ~loop
    labels = _merge_labels(V, u[merge], v[merge])
    M = int(labels.max()) + 1 if V else 0
    if not merge.any():                       # nothing merged: the vertices are their own classes
        m_ptr, m_sites, m_xy, m_extent = ptr, s, xy, np.zeros(M)
    else:
        # Merged vertices: union of the members' site lists, mean of their coordinates.
        member = np.repeat(np.arange(V), np.diff(ptr))
        m_ptr, m_sites = vertex_site_lists(s, labels[member], None, M, max(n, 1))
        used = np.diff(ptr) > 0
        weight = np.bincount(labels[used], minlength=M).astype(np.float64)
        m_xy = np.zeros((M, 2))
        for k in range(2):
            m_xy[:, k] = np.bincount(labels[used], weights=xy[used, k], minlength=M) / np.maximum(weight, 1)
        m_extent = np.zeros(M)
        with np.errstate(invalid="ignore"):
            np.maximum.at(m_extent, labels[used], np.hypot(*(xy[used] - m_xy[labels[used]]).T))
    # Kept half-edges with merged ends and the neighbour that follows along the cell.
    nb_all = site[twin] if H else site
    if not contract.any() and not at_infinity.any():   # every half-edge kept, every vertex its own class
        return _Form(m_ptr, m_sites, m_xy, m_extent, np.arange(H, dtype=np.int64), twin, site, nb_all, origin, dest,
                     nb_all[nxt] if H else nb_all, 0, short, n_short)
    removed = at_infinity.copy()
    removed[e[contract]] = True
    removed[twin[e[contract]]] = True
    kept = ~removed
    succ = _successor(nxt, kept)
    h = np.flatnonzero(kept)
    succ_h = succ[h]
    succ_nb = np.where(succ_h >= 0, nb_all[np.maximum(succ_h, 0)], -1) if h.size else np.zeros(0, np.int64)
    start = np.where(origin[h] >= 0, labels[np.maximum(origin[h], 0)] if V else -1, -1)
    end = np.where(dest[h] >= 0, labels[np.maximum(dest[h], 0)] if V else -1, -1)
    position = np.full(H, -1, dtype=np.int64)
    position[h] = np.arange(h.size)
    return _Form(m_ptr, m_sites, m_xy, m_extent, h, position[twin[h]], site[h], nb_all[h], start.astype(np.int64),
                 end.astype(np.int64), succ_nb.astype(np.int64), int(exact.sum()), short, n_short)


def _rank_rows(rows: NDArray[np.int64], base: int) -> NDArray[np.int64]:
    """Dense ranks of the rows of an (N, d) matrix with entries in [0, base): equal rows, equal ranks."""
    N, d = rows.shape
    if N == 0:
        return np.zeros(0, np.int64)
    code = rows[:, 0].copy()
    bound = base
    for j in range(1, d):
        if bound > (2**62) // base:                # compress before the code overflows
            code = dense_rank(code)
            bound = int(code.max()) + 1
        code = code * base + rows[:, j]
        bound *= base
    return dense_rank(code)


def _joint_vertex_ids(forms: list[_Form], n: int) -> None:
    """Give every merged vertex of every form an id shared by equal site sets (``m_cv``)."""
    degs = [np.diff(f.m_ptr) for f in forms]
    all_degs = sorted_unique(np.concatenate(degs)) if degs else np.zeros(0, np.int64)
    for f, dg in zip(forms, degs):
        f.m_cv = np.full(dg.size, -1, dtype=np.int64)
    offset = 0
    for d in all_degs:
        if d == 0:
            continue
        parts, owners = [], []
        for k, (f, dg) in enumerate(zip(forms, degs)):
            idx = np.flatnonzero(dg == d)
            parts.append(f.m_sites[f.m_ptr[idx][:, None] + np.arange(d)])
            owners.append(idx)
        rank = _rank_rows(np.concatenate(parts), max(n, 1))
        pos = 0
        for f, idx in zip(forms, owners):
            f.m_cv[idx] = offset + rank[pos:pos + idx.size]
            pos += idx.size
        offset += int(rank.max()) + 1 if rank.size else 0


# ---------------------------------------------------------------------------------- differences
@dataclass
class _Diff:
    counts: dict[str, int]
    differences: list[Difference]
    highlight_a: NDArray[np.int64]
    highlight_b: NDArray[np.int64]
    max_vertex_error: float
    max_vertex_error_ratio: float

    @property
    def combinatorial(self) -> int:
        return sum(v for k, v in self.counts.items() if k != "coordinate_mismatches")


def _site_tuple(f: _Form, m: int) -> tuple[int, ...]:
    return tuple(int(x) for x in f.m_sites[f.m_ptr[m]:f.m_ptr[m + 1]])


def _own_units(xy: NDArray[np.float64], shift: int) -> list[float]:
    """Coordinates judged at 2**shift times the diagram's, back in its own units."""
    return np.ldexp(np.asarray(xy, dtype=np.float64), -shift).tolist()


def _end_text(f: _Form, m: int, shift: int = 0) -> str:
    if m < 0:
        return "infinity"
    x, y = _own_units(f.m_xy[m], shift)
    return f"{list(_site_tuple(f, m))} at ({x:.6g}, {y:.6g})"


def _cycle(f: _Form, cell: int) -> list[int]:
    """Neighbour sequence of a cell in form f, starting from its smallest neighbour."""
    mask = f.cell == cell
    after = dict(zip(f.nb[mask].tolist(), f.succ_nb[mask].tolist()))
    if not after:
        return []
    x0 = min(after)
    out, x = [x0], after[x0]
    while x != x0 and x in after and len(out) <= len(after):
        out.append(x)
        x = after[x]
    return out


def _differences(fa: _Form, fb: _Form, sites: NDArray[np.float64], n: int, scale: float,
                 coord_tol: float, labels: tuple[str, str], shift: int = 0, normal_min: float = 0.0) -> _Diff:
    la, lb = labels
    counts = {k: 0 for k in DIFFERENCE_KINDS}
    diffs: list[Difference] = []
    # Vertices: by canonical id.
    total = int(max(fa.m_cv.max(initial=-1), fb.m_cv.max(initial=-1))) + 1
    where_a = np.full(total, -1, np.int64)
    where_b = np.full(total, -1, np.int64)
    live_a, live_b = np.flatnonzero(fa.m_cv >= 0), np.flatnonzero(fb.m_cv >= 0)
    where_a[fa.m_cv[live_a]] = live_a
    where_b[fb.m_cv[live_b]] = live_b
    dup = (np.bincount(fa.m_cv[live_a], minlength=total) > 1).sum() + \
        (np.bincount(fb.m_cv[live_b], minlength=total) > 1).sum()
    counts["duplicate_vertices"] = int(dup)
    for kind, f, live, other, label in (("vertices_only_in_a", fa, live_a, where_b, la),
                                        ("vertices_only_in_b", fb, live_b, where_a, lb)):
        only = live[other[f.m_cv[live]] < 0]
        counts[kind] = int(only.size)
        for m in only[:_MAX_LISTED]:
            xy = tuple(_own_units(f.m_xy[m], shift))
            diffs.append(Difference(kind, _site_tuple(f, int(m)), f"vertex at ({xy[0]:.12g}, {xy[1]:.12g}) "
                                    f"only in {label}", [xy]))
    # Coordinates of matched vertices.
    ma = live_a[where_b[fa.m_cv[live_a]] >= 0]
    mb = where_b[fa.m_cv[ma]]
    max_err = max_ratio = 0.0
    if ma.size:
        pa, pb = fa.m_xy[ma], fb.m_xy[mb]
        err = np.hypot(*(pa - pb).T)
        radius = np.hypot(*(pa - sites[fa.m_sites[fa.m_ptr[ma]]]).T)
        local = np.maximum(scale, radius)
        rel = err / local
        max_err = float(rel.max())
        # The allowed error is at least coord_tol * local (plus extents); work it out in full
        # only for the vertices above that floor.
        extent = fa.m_extent[ma] + fb.m_extent[mb]
        floor = coord_tol * local + extent
        max_ratio = float((err / floor).max())
        cand = np.flatnonzero(~(err <= floor))          # NaN coordinates are candidates too
        if cand.size:
            first, last = fa.m_ptr[ma[cand]], fa.m_ptr[ma[cand] + 1] - 1
            s0, s1, s2 = (sites[fa.m_sites[np.minimum(first + k, last)]] for k in range(3))
            shortest = np.minimum(np.minimum(np.hypot(*(s0 - s1).T), np.hypot(*(s1 - s2).T)), np.hypot(*(s0 - s2).T))
            shortest = np.where(shortest > 0, shortest, scale)
            magnitude = np.maximum(np.maximum(np.abs(pa[cand]).max(1), np.abs(pb[cand]).max(1)), normal_min)
            # A vertex merged under tolerance may lie anywhere within its members' spread.
            allowed = circumcentre_tolerance(coord_tol, local[cand], radius[cand], shortest, magnitude) + extent[cand]
            ratio = err[cand] / allowed
            max_ratio = float(max(ratio.max(), (err / floor)[err <= floor].max(initial=0.0)))
            over = ~(ratio <= 1)
            bad = cand[over]
            counts["coordinate_mismatches"] = int(bad.size)
            for k, r in zip(bad[:_MAX_LISTED], ratio[over][:_MAX_LISTED]):
                xa, xb = tuple(_own_units(pa[k], shift)), tuple(_own_units(pb[k], shift))
                diffs.append(Difference("coordinate_mismatches", _site_tuple(fa, int(ma[k])),
                                        f"vertex at {xa} in {la}, {xb} in {lb} "
                                        f"(error {rel[k]:.3g} of the local scale, {r:.3g} x allowed)", [xa, xb]))
    # Edges by site pair, each represented by its half-edge with cell < neighbour (the twin
    # carries the same pair reversed): ends, and the next neighbour on both sides.
    low_a = np.flatnonzero(fa.cell < fa.nb)
    low_b = np.flatnonzero(fb.cell < fb.nb)
    key_a = fa.cell[low_a] * n + fa.nb[low_a]
    key_b = fb.cell[low_b] * n + fb.nb[low_b]
    oa, ob = low_a[argsort_keys(key_a)], low_b[argsort_keys(key_b)]
    ka, kb = fa.cell[oa] * n + fa.nb[oa], fb.cell[ob] * n + fb.nb[ob]
    dup_a = np.flatnonzero(ka[1:] == ka[:-1])
    dup_b = np.flatnonzero(kb[1:] == kb[:-1])
    counts["duplicate_edges"] = int(dup_a.size + dup_b.size)
    for f, o, dups, label in ((fa, oa, dup_a, la), (fb, ob, dup_b, lb)):
        for k in dups[:_MAX_LISTED]:
            x, y = int(f.cell[o[k]]), int(f.nb[o[k]])
            diffs.append(Difference("duplicate_edges", (x, y), f"two edges between sites {x} and {y} in {label}"))
    if ka.size == kb.size and np.array_equal(ka, kb) and dup_a.size == 0:
        ia, ib = oa, ob
        only_a = only_b = np.zeros(0, np.int64)
    else:
        first_a, first_b = _first_of_runs(ka), _first_of_runs(kb)
        ua, ub = ka[first_a], kb[first_b]
        in_b = is_member(ua, ub)
        in_a = is_member(ub, ua)
        ia, ib = oa[first_a[in_b]], ob[first_b[in_a]]   # both ordered by key
        only_a = oa[first_a[~in_b]]
        only_b = ob[first_b[~in_a]]
    hl_a, hl_b = [fa.h[only_a], fa.h[fa.tw[only_a]]], [fb.h[only_b], fb.h[fb.tw[only_b]]]
    for kind, f, only, label in (("edges_only_in_a", fa, only_a, la), ("edges_only_in_b", fb, only_b, lb)):
        counts[kind] = int(only.size)
        for k in only[:_MAX_LISTED]:
            diffs.append(Difference(kind, (int(f.cell[k]), int(f.nb[k])),
                                    f"edge from {_end_text(f, int(f.start[k]), shift)} to "
                                    f"{_end_text(f, int(f.end[k]), shift)} only in {label}", _edge_points(f, k, shift)))
    # Matched edges: same ends, and the same next neighbour on both sides?
    diff_ends = np.zeros(ia.size, dtype=bool)
    succ_differs = np.zeros(ia.size, dtype=bool)
    twin_succ_differs = np.zeros(ia.size, dtype=bool)
    _matched_kernel(ia, ib, fa.tw, fb.tw, fa.start, fa.end, fb.start, fb.end, fa.m_cv, fb.m_cv, fa.succ_nb,
                    fb.succ_nb, diff_ends, succ_differs, twin_succ_differs)
    bad_edges = np.flatnonzero(diff_ends)
    counts["edges_with_different_ends"] = int(bad_edges.size)
    for k in bad_edges[:_MAX_LISTED]:
        x, y = ia[k], ib[k]
        diffs.append(Difference("edges_with_different_ends", (int(fa.cell[x]), int(fa.nb[x])),
                                f"{la}: {_end_text(fa, int(fa.start[x]), shift)} -> "
                                f"{_end_text(fa, int(fa.end[x]), shift)}; "
                                f"{lb}: {_end_text(fb, int(fb.start[y]), shift)} -> "
                                f"{_end_text(fb, int(fb.end[y]), shift)}",
                                _edge_points(fa, x, shift) + _edge_points(fb, y, shift)))
    for f, idx in ((fa, ia), (fb, ib)):
        hl = hl_a if f is fa else hl_b
        hl += [f.h[idx[bad_edges]], f.h[f.tw[idx[bad_edges]]], f.h[idx[succ_differs]], f.h[f.tw[idx[twin_succ_differs]]]]
    bad_cells = sorted_unique(np.concatenate([fa.cell[ia[succ_differs]], fa.nb[ia[twin_succ_differs]],
                                              fa.cell[only_a], fa.nb[only_a], fb.cell[only_b], fb.nb[only_b]]))
    counts["cells_with_different_neighbours"] = int(bad_cells.size)
    for c in bad_cells[:_MAX_LISTED]:
        diffs.append(Difference("cells_with_different_neighbours", (int(c),),
                                f"neighbours {_cycle(fa, int(c))} in {la}, {_cycle(fb, int(c))} in {lb}",
                                [tuple(_own_units(sites[c], shift))]))
    return _Diff(counts, diffs, sorted_unique(np.concatenate(hl_a)), sorted_unique(np.concatenate(hl_b)),
                 max_err, max_ratio)


@njit(cache=True)
def _matched_kernel(ia, ib, tw_a, tw_b, start_a, end_a, start_b, end_b, cv_a, cv_b, succ_a, succ_b,
                    ends_differ, succ_differ, twin_succ_differ):
    """For matched edges, half-edge ia[k] in a and ib[k] in b: do their end vertices (by
    canonical vertex id, -1 = infinity) differ, and the neighbour after them along the cell
    on either side (the half-edge's and its twin's)?"""
    for k in range(ia.size):
        x, y = ia[k], ib[k]
        sa = cv_a[start_a[x]] if start_a[x] >= 0 else -1
        sb = cv_b[start_b[y]] if start_b[y] >= 0 else -1
        ea = cv_a[end_a[x]] if end_a[x] >= 0 else -1
        eb = cv_b[end_b[y]] if end_b[y] >= 0 else -1
        ends_differ[k] = sa != sb or ea != eb
        succ_differ[k] = succ_a[x] != succ_b[y]
        twin_succ_differ[k] = succ_a[tw_a[x]] != succ_b[tw_b[y]]


def _first_of_runs(sorted_keys: NDArray[np.int64]) -> NDArray[np.int64]:
    """Index of the first element of each run of equal keys in a sorted array."""
    if sorted_keys.size == 0:
        return np.zeros(0, np.int64)
    return np.flatnonzero(np.concatenate([[True], sorted_keys[1:] != sorted_keys[:-1]]))


def _edge_points(f: _Form, k: int, shift: int = 0) -> list[tuple[float, float]]:
    return [tuple(_own_units(f.m_xy[m], shift)) for m in (int(f.start[k]), int(f.end[k])) if m >= 0]


# ---------------------------------------------------------------------------------- weights
def _varying_weights(d: Diagram) -> Optional[NDArray[np.float64]]:
    """The site weights of a power diagram, or None for an ordinary one (no weights, or all
    equal: adding one constant to every weight changes no power comparison)."""
    if d.weights is None:
        return None
    w = np.asarray(d.weights, np.float64).reshape(-1)
    return None if w.size == 0 or (w == w[0]).all() else w


def _common_weights(a: Diagram, b: Diagram, site_map: NDArray[np.int64], labels: tuple[str, str]
                    ) -> tuple[Optional[NDArray[np.float64]], list[Difference]]:
    """(the weights both diagrams are of, in a's site numbering, or None for ordinary diagrams;
    differences when they are of different weights). Weights that differ by one constant
    give the same diagram, so they are the same weights here."""
    wa, wb = _varying_weights(a), _varying_weights(b)
    if wa is None and wb is None:
        return None, []
    n = site_map.size
    common_a = np.zeros(n) if wa is None else wa
    common_b = np.zeros(n)
    if wb is not None:
        common_b[site_map] = wb
    offset = common_a - common_b
    # the constant is the offset most sites share, so a swap of two weights names those two
    values, counts = np.unique(offset, return_counts=True)
    bad = np.flatnonzero(offset != values[np.argmax(counts)])
    if bad.size == 0:
        return common_a, []
    la, lb = labels
    return common_a, [Difference("weight_mismatch", (int(i),), f"weight {common_a[i]:.17g} in {la} "
                                 f"({'ordinary' if wa is None else 'power'} diagram), {common_b[i]:.17g} in {lb} "
                                 f"({'ordinary' if wb is None else 'power'} diagram)") for i in bad]


def _hidden_differences(a: Diagram, b: Diagram, site_map: NDArray[np.int64], diff: "_Diff",
                        labels: tuple[str, str], shift: int) -> None:
    """Count and list the sites hidden (no half-edge) in one diagram but not in the other."""
    n = site_map.size
    if n <= 1:
        return
    visible_a = np.zeros(n, dtype=bool)
    visible_a[np.asarray(a.site, np.int64)] = True
    visible_b = np.zeros(n, dtype=bool)
    visible_b[site_map[np.asarray(b.site, np.int64)]] = True
    sites = np.asarray(a.sites, np.float64)
    for kind, only, label in (("hidden_only_in_a", visible_b & ~visible_a, labels[0]),
                              ("hidden_only_in_b", visible_a & ~visible_b, labels[1])):
        ids = np.flatnonzero(only)
        diff.counts[kind] = int(ids.size)
        for i in ids[:_MAX_LISTED]:
            xy = tuple(_own_units(sites[i], shift))
            diff.differences.append(Difference(kind, (int(i),), f"site at ({xy[0]:.12g}, {xy[1]:.12g}) has no "
                                               f"cell in {label}", [xy]))


# ---------------------------------------------------------------------------------- entry point
def _scaled(d: Diagram, shift: int) -> Diagram:
    """``d`` with sites and vertices times 2**shift (exact inside the float range)."""
    if shift == 0:
        return d
    with np.errstate(over="ignore", under="ignore"):
        return Diagram(scale_points(np.asarray(d.sites, np.float64).reshape(-1, 2), shift),
                       scale_points(np.asarray(d.vertices, np.float64).reshape(-1, 2), shift),
                       d.origin, d.twin, d.next, d.site,
                       weights=None if d.weights is None else np.ldexp(np.asarray(d.weights, np.float64), 2 * shift))


def compare(a: Diagram, b: Diagram, *, ulps: float = NEAR_DEGENERATE_ULPS, coord_tol: Optional[float] = None,
            labels: tuple[str, str] = ("a", "b")) -> Comparison:
    """Compare two diagrams of the same sites combinatorially and by vertex coordinates.

    ``ulps``: edges of configurations within this many roundings of the data of degenerate
    are contracted for the ``within_tolerance`` verdict (0: exact comparison only). ``coord_tol``: matched vertices may
    differ by this fraction of their local scale (default ``VERTEX_MATCH_REL_TOL``).
    ``labels`` name the two diagrams in the report. Never raises on a broken diagram:
    that is reported as a difference.

    >>> import impls, datasets_gen
    >>> d = impls.build("qhull", datasets_gen.generate("grid", 16))
    >>> print(compare(d, d).verdict)
    exact
    """
    coord_tol = VERTEX_MATCH_REL_TOL if coord_tol is None else float(coord_tol)
    la, lb = labels
    sizes = {la: a.counts(), lb: b.counts()}
    n = a.n_sites
    scale = data_scale(np.asarray(a.sites, np.float64).reshape(-1, 2))
    base = dict(labels=(la, lb), n_sites=n, sizes=sizes, scale=scale, ulps=ulps, coord_tol=coord_tol)
    counts = {k: 0 for k in DIFFERENCE_KINDS}
    site_map, site_diffs, site_count = _site_matching(a, b)
    if site_map is None:
        counts["site_mismatch"] = site_count
        return Comparison(False, Verdict.DIFFERS, counts, site_diffs, **base)
    reordered = not np.array_equal(site_map, np.arange(site_map.size))
    weights, weight_diffs = _common_weights(a, b, site_map, (la, lb))
    if weight_diffs:
        counts["weight_mismatch"] = len(weight_diffs)
        return Comparison(False, Verdict.DIFFERS, counts, weight_diffs[:_MAX_LISTED], sites_reordered=reordered,
                          **base)
    err_a, err_b = _structure_error(a), _structure_error(b)
    structure = {name: msg for name, msg in ((la, err_a), (lb, err_b)) if msg}
    counts["invalid_structure"] = int(err_a is not None) + int(err_b is not None)
    if not (_indices_usable(a) and _indices_usable(b)):
        return Comparison(False, Verdict.DIFFERS, counts, [], sites_reordered=reordered, structure_errors=structure,
                          **base)
    identity = np.arange(n, dtype=np.int64)
    # Compared at 2**shift times the coordinates (largest site coordinate in [0.5, 1)): exact.
    shift, _ = comfortable_shift(np.asarray(a.sites, np.float64).reshape(-1, 2))
    a, b = _scaled(a, shift), _scaled(b, shift)
    if weights is not None:
        weights = np.ldexp(weights, 2 * shift)
    normal_min = smallest_normal(shift)
    sites = np.asarray(a.sites, np.float64)
    unit_scale = data_scale(sites)
    result = None
    for stage, tol in ((Verdict.EXACT, None), (Verdict.WITHIN_TOLERANCE, ulps)):
        forms = [_canonical(a, identity, n, tol, unit_scale, err_a is None, normal_min, weights),
                 _canonical(b, site_map, n, tol, unit_scale, err_b is None, normal_min, weights)]
        _joint_vertex_ids(forms, n)
        diff = _differences(forms[0], forms[1], sites, n, unit_scale, coord_tol, (la, lb), shift, normal_min)
        _hidden_differences(a, b, site_map, diff, (la, lb), shift)
        result = (stage, forms, diff)
        if diff.combinatorial == 0 or ulps <= 0:
            break
    stage, forms, diff = result
    diff.counts["invalid_structure"] = counts["invalid_structure"]
    ok = diff.combinatorial == 0 and diff.counts["coordinate_mismatches"] == 0 and err_a is None and err_b is None
    short = [dict(diagram=lbl, sites=[x, y], length=math.ldexp(length, -shift))
             for lbl, f in zip((la, lb), forms) for x, y, length in f.short]
    return Comparison(
        equal=ok, verdict=stage if ok else Verdict.DIFFERS, counts=diff.counts, differences=diff.differences,
        max_vertex_error=diff.max_vertex_error, max_vertex_error_ratio=diff.max_vertex_error_ratio,
        sites_reordered=reordered,
        zero_length_edges={la: forms[0].n_exact, lb: forms[1].n_exact},
        short_edge_counts={la: forms[0].n_short, lb: forms[1].n_short} if stage != Verdict.EXACT else {},
        short_edges=short, structure_errors=structure,
        highlight_a=diff.highlight_a, highlight_b=diff.highlight_b, **base)
