"""Exact parts of a circumcircle (its centre's numerators, denominator and squared radius as
expansions, in plain floats when every step is exact, or in double-double with bounds) and
the accurate circumcentres built on them."""

from __future__ import annotations

import math

from numba import njit

from vorobench.core.predicates.expansion import (
    _DD_SAFETY,
    EPSILON,
    _dd_div,
    _ddv_add,
    _ddv_mul,
    _xadd,
    _xd,
    _xmul,
    _xneg,
    _xscale,
    _xscaled,
    _xsign,
    _xsub,
    two_diff,
    two_product,
    two_sum,
)

__all__ = ["circumcentre_offsets_dd"]


@njit(cache=True)
def _circle_parts(ax, ay, bx, by, cx, cy, scale, w):
    # Exact expansions (e, nys, s, nxs) with y_top = a_y + (nys + sqrt(s)) / e, e > 0, and
    # centre a + (nxs, nys) / e: e = 2 |D|, D = orient of (b - a, c - a), nys = sign(D) * Ny,
    # nxs = sign(D) * Nx, s = Nx**2 + Ny**2,
    # all computed from the differences times ``scale`` (a power of two: exact).
    bx_ = _xscaled(_xd(bx, ax, w), scale)
    by_ = _xscaled(_xd(by, ay, w), scale)
    cx_ = _xscaled(_xd(cx, ax, w), scale)
    cy_ = _xscaled(_xd(cy, ay, w), scale)
    dd = _xsub(_xmul(bx_, cy_, w), _xmul(by_, cx_, w), w)
    b2 = _xadd(_xmul(bx_, bx_, w), _xmul(by_, by_, w), w)
    c2 = _xadd(_xmul(cx_, cx_, w), _xmul(cy_, cy_, w), w)
    nx = _xsub(_xmul(cy_, b2, w), _xmul(by_, c2, w), w)
    ny = _xsub(_xmul(bx_, c2, w), _xmul(cx_, b2, w), w)
    s = _xadd(_xmul(nx, nx, w), _xmul(ny, ny, w), w)
    if _xsign(dd) < 0:
        dd = _xneg(dd, w)
        ny = _xneg(ny, w)
        nx = _xneg(nx, w)
    e = _xscale(dd, 2.0, w)
    return e, ny, s, nx


@njit(cache=True)
def _circle_parts_in_floats(ax, ay, bx, by, cx, cy):
    # (ok, e, nys, s) of _circle_parts when every step is exact in plain floats (each
    # difference, product and sum checked error-free: small integer or dyadic lattices);
    # ok False means some step rounded and the expansions are needed
    bx_, t0 = two_diff(bx, ax)
    by_, t1 = two_diff(by, ay)
    cx_, t2 = two_diff(cx, ax)
    cy_, t3 = two_diff(cy, ay)
    p0, r0 = two_product(bx_, cy_)
    p1, r1 = two_product(by_, cx_)
    d, r2 = two_diff(p0, p1)
    if abs(t0) + abs(t1) + abs(t2) + abs(t3) + abs(r0) + abs(r1) + abs(r2) != 0.0:
        return False, 0.0, 0.0, 0.0     # off a lattice the orientation already rounds
    p2, r3 = two_product(bx_, bx_)
    p3, r4 = two_product(by_, by_)
    b2, r5 = two_sum(p2, p3)
    p4, r6 = two_product(cx_, cx_)
    p5, r7 = two_product(cy_, cy_)
    c2, r8 = two_sum(p4, p5)
    p6, r9 = two_product(cy_, b2)
    p7, r10 = two_product(by_, c2)
    nx, r11 = two_diff(p6, p7)
    p8, r12 = two_product(bx_, c2)
    p9, r13 = two_product(cx_, b2)
    ny, r14 = two_diff(p8, p9)
    p10, r15 = two_product(nx, nx)
    p11, r16 = two_product(ny, ny)
    s, r17 = two_sum(p10, p11)
    rounded = (abs(t0) + abs(t1) + abs(t2) + abs(t3) + abs(r0) + abs(r1) + abs(r2) + abs(r3) + abs(r4)
               + abs(r5) + abs(r6) + abs(r7) + abs(r8) + abs(r9) + abs(r10) + abs(r11) + abs(r12)
               + abs(r13) + abs(r14) + abs(r15) + abs(r16) + abs(r17))
    if rounded != 0.0 or not math.isfinite(s):
        return False, 0.0, 0.0, 0.0
    if d < 0.0:
        d, ny = -d, -ny
    return True, 2.0 * d, ny, s


@njit(cache=True, inline='always')
def _numerators_dd(ax, ay, bx, by, cx, cy):
    # D = orient of (b - a, c - a) and the centre's numerators Nx, Ny (centre = a + N / (2 D)),
    # each in double-double as (hi, lo, err) with its propagated absolute error bound
    bxh, bxl = two_diff(bx, ax)
    byh, byl = two_diff(by, ay)
    cxh, cxl = two_diff(cx, ax)
    cyh, cyl = two_diff(cy, ay)
    p0h, p0l, p0e = _ddv_mul(bxh, bxl, 0.0, cyh, cyl, 0.0)
    p1h, p1l, p1e = _ddv_mul(byh, byl, 0.0, cxh, cxl, 0.0)
    dh, dl, de = _ddv_add(p0h, p0l, p0e, -p1h, -p1l, p1e)
    p2h, p2l, p2e = _ddv_mul(bxh, bxl, 0.0, bxh, bxl, 0.0)
    p3h, p3l, p3e = _ddv_mul(byh, byl, 0.0, byh, byl, 0.0)
    b2h, b2l, b2e = _ddv_add(p2h, p2l, p2e, p3h, p3l, p3e)
    p4h, p4l, p4e = _ddv_mul(cxh, cxl, 0.0, cxh, cxl, 0.0)
    p5h, p5l, p5e = _ddv_mul(cyh, cyl, 0.0, cyh, cyl, 0.0)
    c2h, c2l, c2e = _ddv_add(p4h, p4l, p4e, p5h, p5l, p5e)
    p6h, p6l, p6e = _ddv_mul(cyh, cyl, 0.0, b2h, b2l, b2e)
    p7h, p7l, p7e = _ddv_mul(byh, byl, 0.0, c2h, c2l, c2e)
    nxh, nxl, nxe = _ddv_add(p6h, p6l, p6e, -p7h, -p7l, p7e)
    p8h, p8l, p8e = _ddv_mul(bxh, bxl, 0.0, c2h, c2l, c2e)
    p9h, p9l, p9e = _ddv_mul(cxh, cxl, 0.0, b2h, b2l, b2e)
    nyh, nyl, nye = _ddv_add(p8h, p8l, p8e, -p9h, -p9l, p9e)
    return dh, dl, de, nxh, nxl, nxe, nyh, nyl, nye


@njit(cache=True)
def _circle_parts_dd(ax, ay, bx, by, cx, cy):
    # (ok, e, nys, s) of _circle_parts in double-double, each as (hi, lo, err) with a
    # propagated absolute error bound; ok False when the sign of the orientation is not
    # certain (nearly collinear: the expansions are needed)
    dh, dl, de, nxh, nxl, nxe, nyh, nyl, nye = _numerators_dd(ax, ay, bx, by, cx, cy)
    q0h, q0l, q0e = _ddv_mul(nxh, nxl, nxe, nxh, nxl, nxe)
    q1h, q1l, q1e = _ddv_mul(nyh, nyl, nye, nyh, nyl, nye)
    sh, sl, se = _ddv_add(q0h, q0l, q0e, q1h, q1l, q1e)
    # the bounds above are first order in u**2 with rounded-up constants; the safety factor
    # covers their own rounding
    de *= _DD_SAFETY
    nye *= _DD_SAFETY
    se *= _DD_SAFETY
    if not (abs(dh) > de + 2.0 * EPSILON * abs(dl)) or not math.isfinite(sh + nyh + dh):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if dh < 0.0:
        dh, dl, nyh, nyl = -dh, -dl, -nyh, -nyl
    return True, 2.0 * dh, 2.0 * dl, 2.0 * de, nyh, nyl, nye, sh, sl, se


@njit(cache=True)
def circumcentre_offsets_dd(ax, ay, bx, by, cx, cy):
    """``(ok, ux, uy)``: the circumcentre of a, b, c minus a, to about an ulp, from numerators
    and determinant in double-double with propagated error bounds; ``ok`` is False when
    those bounds are not below 2**-70 of the values (then the caller needs expansions).
    Allocates nothing: the fast path for ill-conditioned (sliver) triangles."""
    dh, dl, de, nxh, nxl, nxe, nyh, nyl, nye = _numerators_dd(ax, ay, bx, by, cx, cy)
    limit = 2.0 ** -70 / _DD_SAFETY
    if not (de < limit * abs(dh) and nxe <= limit * abs(nxh) and nye <= limit * abs(nyh)
            and math.isfinite(dh + nxh + nyh)):
        return False, 0.0, 0.0
    # the centre is a + (nx, ny) / (2 d)
    uxh, uxl = _dd_div(nxh, nxl, 2.0 * dh, 2.0 * dl)
    uyh, uyl = _dd_div(nyh, nyl, 2.0 * dh, 2.0 * dl)
    return True, uxh + uxl, uyh + uyl
