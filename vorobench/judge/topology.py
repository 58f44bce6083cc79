"""The certificate's exact topology check: every decision about which sites meet is taken with
exact predicates, on the sites themselves; only the vertices' coordinates are floats.

* A vertex's sites are exactly cocircular (``incircle`` == 0; ``power_test`` == 0 in a power
  diagram: their lifts are coplanar) and not all on one line: a vertex of four or more cells
  exists only where the sites are exactly cocircular, so an epsilon merge of nearly
  cocircular sites is caught.
* Every finite edge (a, b) between vertices u and w is locally Delaunay (locally regular): a
  site d of w (other than a and b) lies on or outside the circle through a, b and a site c
  of u, i.e. ``incircle(a, b, c, d) * orient2d(a, b, c) <= 0``; positive means d is inside
  (an empty circle is violated). Zero means u and w are one circle: the zero-length edge of
  a vertex of four or more cocircular sites given as degree-3 vertices, which the DCEL
  conventions allow (docs/dcel.md). Local Delaunay on every edge of a valid subdivision (the
  structure, orientation and hull checks) implies the global empty-circle property.

* In a power diagram, a hidden site (no cell) is located exactly in a triangle of the dual
  (the sites of a vertex) and must not be in conflict with it (its lift on or above their
  plane, the exact power test): a wrongly hidden site is caught.

A floating-point library may break these only at near-degenerate configurations: the
violation is then "within tolerance" when changing the configuration's sites and their lifts by
at most ``NEAR_DEGENERATE_ULPS`` roundings of the data's extents makes it degenerate: its four sites
cocircular (lifts coplanar) or a triangle of it collinear
(:mod:`vorobench.core.predicates.degeneracy`). That is decided per configuration, from the same
determinants, the same at any size and scale. It is the same computation for exact and
floating-point implementations; only what passes differs (``Check.ok`` for exact code).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

from vorobench.core.predicates import incircle, orient2d, power_test
from vorobench.core.predicates.degeneracy import incircle_ulps, orient2d_ulps, power_test_ulps
from vorobench.core.tolerances import NEAR_DEGENERATE_ULPS

__all__ = ["topology_violations", "judge_topology", "wrongly_hidden", "collinear_ulps"]

#: Why a vertex fails: its sites are not exactly cocircular, or all on one line.
NOT_COCIRCULAR = 1
COLLINEAR = 2


@njit(cache=True)
def _in_circle(sites, weights, weighted, a, b, c, d):
    """Exact: for counter-clockwise a, b, c, +1 if d is inside their (power) circle, -1 outside,
    0 on it; the sign flipped for clockwise a, b, c."""
    if weighted:
        return power_test(sites[a, 0], sites[a, 1], weights[a], sites[b, 0], sites[b, 1], weights[b],
                          sites[c, 0], sites[c, 1], weights[c], sites[d, 0], sites[d, 1], weights[d])
    return incircle(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1],
                    sites[d, 0], sites[d, 1])


@njit(cache=True)
def _lifted_ulps(sites, weights, weighted, extent, lift_extent, a, b, c, d):
    """How far a, b, c, d are from cocircular (coplanar lifts), in roundings of the data."""
    if weighted:
        return power_test_ulps(sites[a, 0], sites[a, 1], weights[a], sites[b, 0], sites[b, 1], weights[b],
                               sites[c, 0], sites[c, 1], weights[c], sites[d, 0], sites[d, 1], weights[d],
                               extent, lift_extent)
    return incircle_ulps(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1],
                         sites[d, 0], sites[d, 1], extent, lift_extent)


@njit(cache=True)
def _line_ulps(sites, extent, a, b, c):
    """How far a, b, c are from collinear, in roundings of the data."""
    return orient2d_ulps(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1], extent)


@njit(cache=True)
def _farthest_off_line(sites, extent, a, b):
    """The largest distance from the line ab of any site, in roundings of the data (0: all on it)."""
    worst = 0.0
    for c in range(sites.shape[0]):
        if c != a and c != b and orient2d(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1],
                                          sites[c, 0], sites[c, 1]) != 0:
            worst = max(worst, _line_ulps(sites, extent, a, b, c))
    return worst


def collinear_ulps(sites: NDArray[np.float64], a: int, b: int, extent: float) -> float:
    """Exact: 0 when every site lies on the line through sites a and b, else how far the
    farthest one is from it, in roundings of the data. An edge that is a whole line (both ends
    at infinity) exists only between neighbours of sites that are all collinear."""
    return float(_farthest_off_line(sites, float(extent), int(a), int(b)))


@njit(cache=True)
def _quad_ulps(sites, weights, weighted, extent, lift_extent, a, b, c, d):
    """How far the decision "is d inside the circle of a, b, c" is from changing: the nearest of
    a, b, c, d cocircular, a, b, c collinear and a, b, d collinear, in roundings of the data."""
    return min(_lifted_ulps(sites, weights, weighted, extent, lift_extent, a, b, c, d),
               _line_ulps(sites, extent, a, b, c), _line_ulps(sites, extent, a, b, d))


@njit(cache=True)
def _first_off_line(sites, ptr, s, v, a, b):
    """A site of vertex v not on the line ab (-1 if there is none)."""
    for j in range(ptr[v], ptr[v + 1]):
        x = s[j]
        if x != a and x != b and orient2d(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1],
                                          sites[x, 0], sites[x, 1]) != 0:
            return x
    return -1


@njit(cache=True)
def _other_site(ptr, s, v, a, b):
    for j in range(ptr[v], ptr[v + 1]):
        if s[j] != a and s[j] != b:
            return s[j]
    return -1


@njit(cache=True)
def _kernel(sites, weights, weighted, extent, lift_extent, ptr, s, ea, eb, eu, ew, v_bad, v_ulps, e_bad, e_ulps):
    for v in range(ptr.size - 1):
        if ptr[v + 1] - ptr[v] < 3:
            continue                    # fewer than three cells: the vertices check says so
        a, b = s[ptr[v]], s[ptr[v] + 1]
        c = _first_off_line(sites, ptr, s, v, a, b)
        if c < 0:
            v_bad[v] = COLLINEAR
            continue
        for j in range(ptr[v], ptr[v + 1]):
            x = s[j]
            if x == a or x == b or x == c:
                continue
            if _in_circle(sites, weights, weighted, a, b, c, x) != 0:
                v_bad[v] = NOT_COCIRCULAR
                v_ulps[v] = max(v_ulps[v], min(_lifted_ulps(sites, weights, weighted, extent, lift_extent,
                                                            a, b, c, x), _line_ulps(sites, extent, a, b, c)))
    for k in range(ea.size):
        u, w, a, b = eu[k], ew[k], ea[k], eb[k]
        if u < 0 or w < 0 or u == w:
            continue                    # rays: the hull check; a loop: the structure check
        c, d = _other_site(ptr, s, u, a, b), _other_site(ptr, s, w, a, b)
        if c < 0 or d < 0:
            continue
        o = orient2d(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1])
        if o == 0:
            continue                    # a vertex of collinear sites: already its failure
        if _in_circle(sites, weights, weighted, a, b, c, d) * o > 0:
            e_bad[k] = True
            e_ulps[k] = _quad_ulps(sites, weights, weighted, extent, lift_extent, a, b, c, d)


def topology_violations(sites: NDArray[np.float64], weights: NDArray[np.float64], weighted: bool,
                        ptr: NDArray[np.int64], s: NDArray[np.int64], a: NDArray[np.int64], b: NDArray[np.int64],
                        u: NDArray[np.int64], w: NDArray[np.int64], extent: float, lift_extent: float):
    """Per vertex (0, NOT_COCIRCULAR or COLLINEAR, and how near its worst offending site is to
    its circle, in roundings of the data) and per edge (a's half-edge from u to w: not locally
    Delaunay, a site strictly inside the circle across it, and how near that decision is to
    degenerate, in roundings of the data). ``extent``: half the longer side of the sites'
    bounding box; ``lift_extent``: the lifted coordinates' (``degeneracy.lift_extent``)."""
    V, E = ptr.size - 1, a.size
    v_bad = np.zeros(V, dtype=np.int64)
    v_ulps = np.zeros(V)
    e_bad = np.zeros(E, dtype=np.bool_)
    e_ulps = np.zeros(E)
    wt = weights if weighted else np.zeros(sites.shape[0])
    _kernel(sites, wt, weighted, float(extent), float(lift_extent), ptr, s, a, b, u, w, v_bad, v_ulps, e_bad, e_ulps)
    return v_bad, v_ulps, e_bad, e_ulps


def judge_topology(sites, weights, weighted, ptr, s, a, b, u, w, extent: float, lift_extent: float) -> dict:
    """The exact topology verdict: counts and ids of the failing vertices and edges, whether
    every failure is near-degenerate (within ``NEAR_DEGENERATE_ULPS`` roundings of a degenerate
    configuration), and the largest such distance (``worst_ulps``)."""
    v_bad, v_ulps, e_bad, e_ulps = topology_violations(sites, weights, weighted, ptr, s, a, b, u, w, extent,
                                                       lift_extent)
    bad_v = np.flatnonzero(v_bad)
    bad_e = np.flatnonzero(e_bad)
    ulps = np.concatenate([np.where(v_bad[bad_v] == COLLINEAR, np.inf, v_ulps[bad_v]), e_ulps[bad_e]])
    worst = float(ulps.max()) if ulps.size else 0.0
    return dict(not_cocircular=bad_v[v_bad[bad_v] == NOT_COCIRCULAR], collinear=bad_v[v_bad[bad_v] == COLLINEAR],
                not_delaunay=bad_e, within=bool(worst <= NEAR_DEGENERATE_ULPS), worst_ulps=worst)


@njit(cache=True)
def _in_triangle(sites, a, b, c, x):
    """Exact: x lies in the closed triangle abc (any orientation, not degenerate)."""
    o = orient2d(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1], sites[c, 0], sites[c, 1])
    if o == 0:
        return False
    for p, q in ((a, b), (b, c), (c, a)):
        if orient2d(sites[p, 0], sites[p, 1], sites[q, 0], sites[q, 1], sites[x, 0], sites[x, 1]) * o < 0:
            return False
    return True


@njit(cache=True)
def _hidden_kernel(sites, weights, extent, lift_extent, ptr, s, hidden, candidates, cell_ptr, cell_half_edges,
                   origin, bad, ulps):
    """For each hidden site h: the triangle of the regular triangulation that holds it (a
    vertex's sites around a candidate cell, exact point location), then the exact power test:
    h in conflict with that triangle (its lift strictly below their plane) should have a cell."""
    for i in range(hidden.size):
        h = hidden[i]
        located = False
        for j in range(candidates.shape[1]):
            cell = candidates[i, j]
            if cell < 0 or located:
                continue
            for e in range(cell_ptr[cell], cell_ptr[cell + 1]):
                u = origin[cell_half_edges[e]]
                if u < 0 or located:
                    continue
                lo, hi = ptr[u], ptr[u + 1]
                for p in range(lo, hi):
                    for q in range(p + 1, hi):
                        for r in range(q + 1, hi):
                            a, b, c = s[p], s[q], s[r]
                            if located or not _in_triangle(sites, a, b, c, h):
                                continue
                            located = True
                            o = orient2d(sites[a, 0], sites[a, 1], sites[b, 0], sites[b, 1],
                                         sites[c, 0], sites[c, 1])
                            if _in_circle(sites, weights, True, a, b, c, h) * o > 0:
                                bad[i] = True
                                # near: the four lifts nearly coplanar, the triangle nearly
                                # flat, or h nearly on one of its sides (another triangle's)
                                ulps[i] = min(_lifted_ulps(sites, weights, True, extent, lift_extent,
                                                           a, b, c, h), _line_ulps(sites, extent, a, b, c),
                                              _line_ulps(sites, extent, a, b, h), _line_ulps(sites, extent, b, c, h),
                                              _line_ulps(sites, extent, c, a, h))


def wrongly_hidden(sites, weights, ptr, s, hidden, candidates, site_of_half_edge, origin, extent: float,
                   lift_extent: float) -> tuple[NDArray[np.int64], float]:
    """(the hidden sites that the exact power test says have a cell, the largest distance of
    those decisions from degenerate in roundings of the data): each hidden site is located
    exactly in a triangle of the diagram's dual around its ``candidates`` (sites of smallest
    power at it, nearest first); one that no candidate's triangles hold is left to the float
    checks."""
    order = np.argsort(site_of_half_edge, kind="stable")
    cell_ptr = np.zeros(sites.shape[0] + 1, dtype=np.int64)
    np.cumsum(np.bincount(site_of_half_edge, minlength=sites.shape[0]), out=cell_ptr[1:])
    bad = np.zeros(hidden.size, dtype=np.bool_)
    ulps = np.zeros(hidden.size)
    _hidden_kernel(sites, weights, float(extent), float(lift_extent), ptr, s, hidden, candidates, cell_ptr,
                   order.astype(np.int64), origin, bad, ulps)
    return hidden[bad], float(ulps[bad].max()) if bad.any() else 0.0
