"""The one DCEL builder shared by every implementation: edges in, linked half-edges out.

An implementation reports each Voronoi edge once, as the pair of sites (a, b) it separates
and the two vertex ids (start, end) of the half-edge whose cell is a, oriented along
perp(b - a) (-1 = infinity). The builder allocates half-edges in pairs (twin of h is h ^ 1)
and links ``next`` in a finishing pass: the successor of h in cell a is the half-edge of a
that starts where h ends; a cell's half-edge that runs out to infinity is followed by the
one that comes back. Cells between two parallel lines (collinear sites) have two half-edges
from infinity, each followed by the other.

Libraries that report ridges without orienting them (scipy's ``ridge_vertices``, a Delaunay
triangulation's pairs of neighbouring triangles) pass ``oriented=False``:
:func:`orient_ridges` then decides each ridge's direction from its sites, exactly.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from vorobench.core.diagram import Diagram, InvalidDiagramError
from vorobench.core.half_edges import index_pairs, link_edges, orient_ridges
from vorobench.core.predicates import (
    EPSILON,
    compress_expansion,
    diff_expansion,
    diff_product_expansion,
    expansion_diff,
    expansion_product,
    expansion_sign,
    expansion_sum,
)

__all__ = ["assemble", "orient_ridges", "collinear_diagram"]


def assemble(sites: NDArray[np.float64], vertices: ArrayLike, edge_sites: ArrayLike,
             edge_vertices: ArrayLike, *, compact_vertices: bool = False, oriented: bool = True,
             weights: Optional[ArrayLike] = None) -> Diagram:
    """Build a :class:`Diagram` from a list of edges.

    ``edge_sites``: (E, 2) site pairs (a, b); ``edge_vertices``: (E, 2) vertex ids
    (start, end) of a's half-edge, which runs in direction perp(b - a); -1 = infinity.
    With ``oriented=False`` the two vertex ids may come in either order (as in scipy's
    ``ridge_vertices``), and :func:`orient_ridges` orders them. With ``compact_vertices``,
    vertices no edge uses are dropped and ids renumbered. ``weights`` (one per site) makes
    it a power diagram, whose hidden sites have no edge. Raises :class:`InvalidDiagramError`
    if the edges do not close up into cells.
    """
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    vertices = np.ascontiguousarray(vertices, dtype=np.float64).reshape(-1, 2)
    ab = index_pairs(edge_sites, "edge_sites")
    se = index_pairs(edge_vertices, "edge_vertices")
    if ab.shape != se.shape:
        raise ValueError(f"edge_sites {ab.shape} and edge_vertices {se.shape} differ in shape")
    n = sites.shape[0]
    if weights is not None:
        weights = np.ascontiguousarray(weights, dtype=np.float64).reshape(-1)
        if weights.shape != (n,):
            raise ValueError(f"weights has shape {weights.shape}, there are {n} sites")
    if n <= 1 or ab.shape[0] == 0:
        if n >= 2 and weights is None:
            raise InvalidDiagramError(f"{n} sites but no edges")
        return Diagram.empty(sites, weights)
    vertices, origin, twin, nxt, site = link_edges(n, vertices, ab, se, sites=sites, oriented=oriented,
                                                   compact_vertices=compact_vertices)
    return Diagram(sites, vertices, origin, twin, nxt, site, weights=weights)


def collinear_diagram(sites: NDArray[np.float64], weights: Optional[ArrayLike] = None) -> Diagram:
    """The diagram of n >= 2 collinear sites: parallel lines, no vertex.

    Sites are ordered along their common line (lexicographically, which is monotone along
    any line); consecutive sites are separated by their bisector, a full line: n - 1 lines.

    With ``weights``, the power diagram: a site keeps a cell when its lifted point
    (position along the line, |p|^2 - w) is a vertex of the lower convex hull of the lifted
    points, decided exactly (:func:`collinear_power_test`); consecutive visible sites are
    separated by their power bisector, and the other sites are hidden (no edge). A site
    whose lifted point lies exactly on the segment between its neighbours' is hidden too:
    its cell would be a line (where the neighbours' powers tie), not a region. Equal
    weights give the ordinary diagram's edges, in the same order.
    """
    sites = np.ascontiguousarray(sites, dtype=np.float64)
    order = np.lexsort((sites[:, 1], sites[:, 0]))
    if weights is not None:
        weights = np.ascontiguousarray(weights, dtype=np.float64).reshape(-1)
        if weights.shape != (sites.shape[0],):
            raise ValueError(f"weights has shape {weights.shape}, there are {sites.shape[0]} sites")
        chain = np.empty(order.size, dtype=np.int64)
        k = _lower_chain(sites[:, 0].copy(), sites[:, 1].copy(), weights, order.astype(np.int64), chain)
        order = chain[:k]
    pairs = np.stack([order[:-1], order[1:]], axis=1)
    ends = np.full(pairs.shape, -1, dtype=np.int64)
    return assemble(sites, np.zeros((0, 2)), pairs, ends, weights=weights)


# ---------------------------------------------------------------------------------------------
# Power diagrams of collinear sites: the lower hull of a 1-D lifting, decided exactly.
#
# Three collinear sites a < b < c along their line, b = a + s (c - a) with 0 < s < 1. Lifted
# heights h = |p|^2 - w; along the line |p|^2 is a parabola of curvature |c - a|^2, so
#     h_b - ((1 - s) h_a + s h_c) = (1 - s)(w_a - w_b) + s (w_c - w_b) - s (1 - s) |c - a|^2.
# With L = (b - a).(c - a) = s D and M = (c - b).(c - a) = (1 - s) D (exact for collinear
# sites, D = |c - a|^2 > 0), D times it is the polynomial
#     F = M (w_a - w_b) + L (w_c - w_b) - L M,
# of degree 4 (weights count as degree 2): b's lifted point lies above the chord of a's and c's
# when F > 0, on it when F = 0; then pow_b >= min(pow_a, pow_c) everywhere and b is hidden.
# ---------------------------------------------------------------------------------------------

#: Relative error bound of the float evaluation of F: each difference rounds once (u), each
#: dot product L, M adds three roundings (two products, one sum: gamma_4 of |L|-permanent),
#: each of the three terms one more product (gamma_6, gamma_6, gamma_9 with the weight
#: differences' rounding), and the two final sums one each: gamma_11 of the permanent
#: |M||dw_a| + |L||dw_c| + |L||M| (absolute values inside L, M). 12u covers gamma_11 and the
#: permanent's own seven roundings (tests/core/test_collinear_power.py checks it with fractions).
COLLINEAR_POWER_ERRBOUND = 12.0 * EPSILON


@njit(cache=True)
def _collinear_power_exact(ax, ay, aw, bx, by, bw, cx, cy, cw):
    # F from exact differences: L, M <= 16 components, the products <= 64, 64, 512; the sums are
    # compressed on the way (the exact stage is rare: ties and near ties only).
    p = np.empty(8)
    q = np.empty(8)
    lx = np.empty(16)
    mx = np.empty(16)
    n_p = diff_product_expansion(bx, ax, cx, ax, p)
    n_q = diff_product_expansion(by, ay, cy, ay, q)
    n_l = compress_expansion(lx, expansion_sum(p, n_p, q, n_q, lx), lx)
    n_p = diff_product_expansion(cx, bx, cx, ax, p)
    n_q = diff_product_expansion(cy, by, cy, ay, q)
    n_m = compress_expansion(mx, expansion_sum(p, n_p, q, n_q, mx), mx)
    dwa = np.empty(2)
    dwc = np.empty(2)
    n_dwa = diff_expansion(aw, bw, dwa)
    n_dwc = diff_expansion(cw, bw, dwc)
    t1 = np.empty(2 * n_m * n_dwa)
    n1 = expansion_product(mx, n_m, dwa, n_dwa, t1)
    t2 = np.empty(2 * n_l * n_dwc)
    n2 = expansion_product(lx, n_l, dwc, n_dwc, t2)
    t3 = np.empty(2 * n_l * n_m)
    n3 = expansion_product(lx, n_l, mx, n_m, t3)
    s = np.empty(n1 + n2)
    ns = compress_expansion(s, expansion_sum(t1, n1, t2, n2, s), s)
    f = np.empty(ns + n3)
    nf = expansion_diff(s, ns, t3, n3, f)
    return expansion_sign(f, nf)


@njit(cache=True)
def collinear_power_test(ax, ay, aw, bx, by, bw, cx, cy, cw):
    """Exact sign of where weighted site b's lifted point lies against the chord of a's and c's,
    for collinear sites a < b < c along their line (the caller's promise; not checked):
    +1 above (b is hidden between a and c), 0 on it (hidden too: a line cell), -1 below
    (b keeps a cell between them). Float filter, then expansion arithmetic; exact for
    coordinates in [2**-100, 2**100) and weights in [2**-200, 2**200) in magnitude."""
    bax = bx - ax
    bay = by - ay
    cax = cx - ax
    cay = cy - ay
    cbx = cx - bx
    cby = cy - by
    dwa = aw - bw
    dwc = cw - bw
    l1 = bax * cax
    l2 = bay * cay
    m1 = cbx * cax
    m2 = cby * cay
    el = l1 + l2
    em = m1 + m2
    f = (em * dwa + el * dwc) - el * em
    labs = abs(l1) + abs(l2)
    mabs = abs(m1) + abs(m2)
    permanent = mabs * abs(dwa) + labs * abs(dwc) + labs * mabs
    if abs(f) > COLLINEAR_POWER_ERRBOUND * permanent:
        return (f > 0.0) - (f < 0.0)
    return _collinear_power_exact(ax, ay, aw, bx, by, bw, cx, cy, cw)


@njit(cache=True)
def _lower_chain(xs, ys, ws, order, out):
    """Monotone chain over ``order`` (sorted along the line): the lower hull of the lifted
    points, popping the middle site while it is on or above the chord; writes the kept
    sites to ``out`` and returns how many."""
    k = 0
    for i in order:
        while k >= 2:
            a = out[k - 2]
            b = out[k - 1]
            if collinear_power_test(xs[a], ys[a], ws[a], xs[b], ys[b], ws[b], xs[i], ys[i], ws[i]) < 0:
                break
            k -= 1
        out[k] = i
        k += 1
    return k
