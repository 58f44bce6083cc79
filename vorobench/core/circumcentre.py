"""Circumcentres of site triples, computed the same way wherever a Voronoi vertex is made.

A Voronoi vertex is identified by the sites on its empty circle; its coordinates are always
computed from the three smallest site indices among them, in increasing order, so that two
exact constructions that find the same vertex produce bit-identical coordinates.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from vorobench.core.predicates import (
    ORIENT2D_EXPANSION_MAX,
    circumcentre_offsets_dd,
    diff_expansion,
    estimate,
    expansion_diff,
    expansion_product,
    expansion_sum,
    orient2d_expansion,
)

__all__ = ["circumcentre", "circumcentre_fast", "power_centre", "CANCELLATION_THRESHOLD"]

#: When a determinant or numerator keeps less than this fraction of the size of its terms,
#: cancellation has eaten too many digits: it is recomputed exactly (expansion arithmetic).
CANCELLATION_THRESHOLD = 1e-4


@njit(cache=True)
def _square_sum(x, xlen, y, ylen):
    """Exact x**2 + y**2 of two expansions."""
    xx = np.empty(2 * xlen * xlen)
    yy = np.empty(2 * ylen * ylen)
    out = np.empty(2 * xlen * xlen + 2 * ylen * ylen)
    n1 = expansion_product(x, xlen, x, xlen, xx)
    n2 = expansion_product(y, ylen, y, ylen, yy)
    return out, expansion_sum(xx, n1, yy, n2, out)


@njit(cache=True)
def _cross_numerator(p, plen, s, slen, q, qlen, t, tlen):
    """Float nearest to the exact p * s - q * t of four expansions."""
    ps = np.empty(2 * plen * slen)
    qt = np.empty(2 * qlen * tlen)
    out = np.empty(2 * plen * slen + 2 * qlen * tlen)
    n1 = expansion_product(p, plen, s, slen, ps)
    n2 = expansion_product(q, qlen, t, tlen, qt)
    return estimate(out, expansion_diff(ps, n1, qt, n2, out))


@njit(cache=True, _nrt=True)
def _exact_offsets(ax, ay, bx, by, cx, cy):
    """Centre minus a, from exact numerators and denominator (rounded once at the end): the
    power centre's with no weights."""
    return _exact_power_offsets(ax, ay, 0.0, bx, by, 0.0, cx, cy, 0.0)


@njit(cache=True, inline='always')
def circumcentre_fast(ax: float, ay: float, bx: float, by: float, cx: float, cy: float):
    """(ok, x, y): :func:`circumcentre`'s float formula, ok False where cancellation leaves it
    to the careful paths. Its bits do not depend on the order of b and c: swapping them swaps
    the two products of the determinant and of each numerator, which negates all three exactly,
    and the quotient with them."""
    bx_ = bx - ax
    by_ = by - ay
    cx_ = cx - ax
    cy_ = cy - ay
    b2 = bx_ * bx_ + by_ * by_
    c2 = cx_ * cx_ + cy_ * cy_
    d1 = bx_ * cy_
    d2 = by_ * cx_
    x1 = cy_ * b2
    x2 = by_ * c2
    y1 = bx_ * c2
    y2 = cx_ * b2
    det = d1 - d2
    num_x = x1 - x2
    num_y = y1 - y2
    if (abs(det) <= CANCELLATION_THRESHOLD * (abs(d1) + abs(d2))
            or abs(num_x) <= CANCELLATION_THRESHOLD * (abs(x1) + abs(x2))
            or abs(num_y) <= CANCELLATION_THRESHOLD * (abs(y1) + abs(y2))):
        return False, 0.0, 0.0
    inv = 0.5 / det
    return True, ax + num_x * inv, ay + num_y * inv


@njit(cache=True)
def circumcentre(ax: float, ay: float, bx: float, by: float, cx: float, cy: float):
    """Centre (x, y) of the circle through a, b, c (not collinear).

    Computed relative to ``a``, which keeps large common offsets (1e9) out of the products;
    if the determinant or either numerator is dominated by cancellation (nearly collinear
    triples, whose centres lie far away; slivers), they are recomputed in double-double with
    certified error bounds (no allocation), or exactly from the original coordinates when
    even those bounds are too wide, and the quotient is rounded once.
    """
    ok, x, y = circumcentre_fast(ax, ay, bx, by, cx, cy)
    if ok:
        return x, y
    ok, ux, uy = circumcentre_offsets_dd(ax, ay, bx, by, cx, cy)
    if not ok:
        ux, uy = _exact_offsets(ax, ay, bx, by, cx, cy)
    return ax + ux, ay + uy


@njit(cache=True)
def _exact_power_offsets(ax, ay, aw, bx, by, bw, cx, cy, cw):
    """Power centre minus a, from exact numerators and denominator (rounded once at the end):
    |B|^2 and |C|^2 of the circumcentre become |B|^2 - (w_b - w_a) and |C|^2 - (w_c - w_a)."""
    ebx = np.empty(2)
    eby = np.empty(2)
    ecx = np.empty(2)
    ecy = np.empty(2)
    ewb = np.empty(2)
    ewc = np.empty(2)
    nbx = diff_expansion(bx, ax, ebx)
    nby = diff_expansion(by, ay, eby)
    ncx = diff_expansion(cx, ax, ecx)
    ncy = diff_expansion(cy, ay, ecy)
    nwb = diff_expansion(bw, aw, ewb)
    nwc = diff_expansion(cw, aw, ewc)
    sb, nsb = _square_sum(ebx, nbx, eby, nby)
    sc, nsc = _square_sum(ecx, ncx, ecy, ncy)
    b2 = np.empty(nsb + nwb)
    nb2 = expansion_diff(sb, nsb, ewb, nwb, b2)
    c2 = np.empty(nsc + nwc)
    nc2 = expansion_diff(sc, nsc, ewc, nwc, c2)
    num_x = _cross_numerator(ecy, ncy, b2, nb2, eby, nby, c2, nc2)
    num_y = _cross_numerator(ebx, nbx, c2, nc2, ecx, ncx, b2, nb2)
    h = np.empty(ORIENT2D_EXPANSION_MAX)
    det = estimate(h, orient2d_expansion(ax, ay, bx, by, cx, cy, h))
    return num_x / (2.0 * det), num_y / (2.0 * det)


@njit(cache=True)
def power_centre(ax: float, ay: float, aw: float, bx: float, by: float, bw: float, cx: float, cy: float,
                 cw: float):
    """The point (x, y) of equal power |x - p|^2 - w with respect to a, b and c (not collinear):
    a vertex of the power diagram.

    The same arithmetic as :func:`circumcentre` with the squared lengths |b - a|^2, |c - a|^2
    lowered by the weight differences, so equal weights give the circumcentre bit for bit
    (the differences are exactly 0); under cancellation the quotient's parts are computed
    exactly and rounded once.
    """
    if aw == bw and aw == cw:
        return circumcentre(ax, ay, bx, by, cx, cy)
    bx_ = bx - ax
    by_ = by - ay
    cx_ = cx - ax
    cy_ = cy - ay
    b2 = bx_ * bx_ + by_ * by_ - (bw - aw)
    c2 = cx_ * cx_ + cy_ * cy_ - (cw - aw)
    d1 = bx_ * cy_
    d2 = by_ * cx_
    x1 = cy_ * b2
    x2 = by_ * c2
    y1 = bx_ * c2
    y2 = cx_ * b2
    det = d1 - d2
    num_x = x1 - x2
    num_y = y1 - y2
    scale_b = bx_ * bx_ + by_ * by_ + abs(bw - aw)
    scale_c = cx_ * cx_ + cy_ * cy_ + abs(cw - aw)
    if (abs(det) <= CANCELLATION_THRESHOLD * (abs(d1) + abs(d2))
            or abs(num_x) <= CANCELLATION_THRESHOLD * (abs(cy_) * scale_b + abs(by_) * scale_c)
            or abs(num_y) <= CANCELLATION_THRESHOLD * (abs(bx_) * scale_c + abs(cx_) * scale_b)
            or abs(b2) <= CANCELLATION_THRESHOLD * scale_b or abs(c2) <= CANCELLATION_THRESHOLD * scale_c):
        ux, uy = _exact_power_offsets(ax, ay, aw, bx, by, bw, cx, cy, cw)
        return ax + ux, ay + uy
    inv = 0.5 / det
    return ax + num_x * inv, ay + num_y * inv
