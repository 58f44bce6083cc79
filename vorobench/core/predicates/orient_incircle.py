"""``orient2d`` and ``incircle``: a float filter with Shewchuk's error bounds, an exact stage
without allocation where the differences are exact, then the full expansion; counted,
plain-float (not exact) and vectorised versions."""

from __future__ import annotations

import numpy as np
from numba import njit

from vorobench.core.predicates.expansion import (
    _COUNTERS,
    _F64,
    _I64,
    _UNDECIDED,
    EPSILON,
    INCIRCLE_EXPANSION_MAX,
    ORIENT2D_EXPANSION_MAX,
    det2_expansion,
    expansion_diff,
    expansion_sign,
    expansion_sum,
    grow_expansion,
    product_expansion,
    scale_expansion,
    two_diff,
    two_product,
    two_sum,
)

__all__ = ["CCW_ERRBOUND_A", "ICC_ERRBOUND_A", "ORIENT_CALLS", "ORIENT_EXACT", "INCIRCLE_CALLS", "INCIRCLE_EXACT", "orient2d_expansion", "incircle_expansion", "orient2d", "orient2d_counted", "orient2d_fast", "incircle", "incircle_counted", "incircle_fast", "orient2d_many", "incircle_many"]


#: Relative error bound of the orient2d float filter (Shewchuk's ccwerrboundA).
CCW_ERRBOUND_A = (3.0 + 16.0 * EPSILON) * EPSILON


#: Relative error bound of the incircle float filter (Shewchuk's iccerrboundA).
ICC_ERRBOUND_A = (10.0 + 96.0 * EPSILON) * EPSILON


#: Indices into the counters array of the ``*_counted`` predicates.
ORIENT_CALLS = 0


ORIENT_EXACT = 1


INCIRCLE_CALLS = 2


INCIRCLE_EXACT = 3


@njit(cache=True)
def orient2d_expansion(ax, ay, bx, by, cx, cy, h):
    """Exact value of the orient2d determinant as an expansion in ``h``; returns the length.

    ``h`` needs ORIENT2D_EXPANSION_MAX (12) entries.  Expanded in the original
    coordinates: ax*by - ax*cy + bx*cy - bx*ay + cx*ay - cx*by.  No allocation.
    """
    n = product_expansion(ax, by, h)
    x, y = two_product(ax, cy)
    n = grow_expansion(h, n, -y, h)
    n = grow_expansion(h, n, -x, h)
    x, y = two_product(bx, cy)
    n = grow_expansion(h, n, y, h)
    n = grow_expansion(h, n, x, h)
    x, y = two_product(bx, ay)
    n = grow_expansion(h, n, -y, h)
    n = grow_expansion(h, n, -x, h)
    x, y = two_product(cx, ay)
    n = grow_expansion(h, n, y, h)
    n = grow_expansion(h, n, x, h)
    x, y = two_product(cx, by)
    n = grow_expansion(h, n, -y, h)
    return grow_expansion(h, n, -x, h)


@njit(cache=True)
def _lifted(m, mlen, px, py, out, w):
    # out = (px**2 + py**2) * m, length <= 8 * mlen; w is scratch of >= 12 * mlen floats.
    t = w[: 2 * mlen]
    tt = w[2 * mlen : 6 * mlen]
    u = w[6 * mlen : 8 * mlen]
    uu = w[8 * mlen : 12 * mlen]
    tlen = scale_expansion(m, mlen, px, t)
    ttlen = scale_expansion(t, tlen, px, tt)
    ulen = scale_expansion(m, mlen, py, u)
    uulen = scale_expansion(u, ulen, py, uu)
    return expansion_sum(tt, ttlen, uu, uulen, out)


@njit(cache=True)
def _incircle_expansion_work(ax, ay, bx, by, cx, cy, dx, dy, h, w):
    # w: scratch of >= 1024 floats.
    # With pq := px*qy - qx*py, the 4x4 determinant with rows (x, y, x^2+y^2, 1) is
    #   |a|^2 (bc + cd - bd) - |b|^2 (ac + cd + da) + |c|^2 (ab + bd + da) - |d|^2 (ab + bc - ac)
    # (cofactor expansion along the lifted column).
    ab = w[0:4]
    bc = w[4:8]
    cd = w[8:12]
    da = w[12:16]
    ac = w[16:20]
    bd = w[20:24]
    s8 = w[24:32]
    m = w[32:44]
    la = w[44:140]
    lb = w[140:236]
    lc = w[236:332]
    ld = w[332:428]
    s1 = w[428:620]
    s2 = w[620:812]
    lw = w[812:1024]  # 12 * 12 = 144 needed by _lifted
    abn = det2_expansion(ax, by, bx, ay, ab)
    bcn = det2_expansion(bx, cy, cx, by, bc)
    cdn = det2_expansion(cx, dy, dx, cy, cd)
    dan = det2_expansion(dx, ay, ax, dy, da)
    acn = det2_expansion(ax, cy, cx, ay, ac)
    bdn = det2_expansion(bx, dy, dx, by, bd)

    n8 = expansion_sum(bc, bcn, cd, cdn, s8)
    mn = expansion_diff(s8, n8, bd, bdn, m)
    lan = _lifted(m, mn, ax, ay, la, lw)

    n8 = expansion_sum(ac, acn, cd, cdn, s8)
    mn = expansion_sum(s8, n8, da, dan, m)
    lbn = _lifted(m, mn, bx, by, lb, lw)

    n8 = expansion_sum(ab, abn, bd, bdn, s8)
    mn = expansion_sum(s8, n8, da, dan, m)
    lcn = _lifted(m, mn, cx, cy, lc, lw)

    n8 = expansion_sum(ab, abn, bc, bcn, s8)
    mn = expansion_diff(s8, n8, ac, acn, m)
    ldn = _lifted(m, mn, dx, dy, ld, lw)

    s1n = expansion_diff(la, lan, lb, lbn, s1)
    s2n = expansion_diff(lc, lcn, ld, ldn, s2)
    return expansion_sum(s1, s1n, s2, s2n, h)


@njit(cache=True)
def incircle_expansion(ax, ay, bx, by, cx, cy, dx, dy, h):
    """Exact value of the incircle determinant as an expansion in ``h``; returns the length.

    ``h`` needs INCIRCLE_EXPANSION_MAX (384) entries.  Expanded in the
    original coordinates (degree 4).  Allocates a scratch array.
    """
    w = np.empty(1024)
    return _incircle_expansion_work(ax, ay, bx, by, cx, cy, dx, dy, h, w)


@njit(cache=True)
def _sign(x):
    # branch-free sign of a float: -1, 0 or +1
    return (x > 0.0) - (x < 0.0)


@njit(cache=True)
def _orient2d_filter(ax, ay, bx, by, cx, cy):
    # Shewchuk's orient2d stage A: returns the sign if the float evaluation
    # provably has the right sign, else _UNDECIDED.  Allocates nothing.
    #
    # The common case is tested first with a single, well-predicted branch:
    # |det| > ccwerrboundA * (|detleft| + |detright|).  If detleft and detright
    # have the same sign (or one is 0) this is exactly Shewchuk's test (his
    # detsum is the same float); if they have opposite signs the sign of det
    # is certain anyway.  Only when the test fails do we look at the cases.
    detleft = (ax - cx) * (by - cy)
    detright = (ay - cy) * (bx - cx)
    det = detleft - detright
    errbound = CCW_ERRBOUND_A * (abs(detleft) + abs(detright))
    if abs(det) > errbound:
        return _sign(det)
    if detleft > 0.0:
        if detright <= 0.0:
            return 1
    elif detleft < 0.0:
        if detright >= 0.0:
            return -1
    else:
        # detleft == 0 exactly (a factor difference is exactly 0, because a
        # float difference rounds to 0 only if it is 0), so det = -detright
        # and detright has the sign of the exact product.
        return -_sign(detright)
    return _UNDECIDED


@njit(cache=True, inline='always')
def _two_two_diff_sign(a1, a0, b1, b0):
    # exact sign of (a1 + a0) - (b1 + b0) for two-component values (Shewchuk's Two_Two_Diff:
    # four nonoverlapping components; the sign is that of the largest nonzero one)
    i, x0 = two_diff(a0, b0)
    j, x1a = two_sum(a1, i)
    k, x1 = two_diff(x1a, b1)
    x3, x2 = two_sum(j, k)
    if x3 != 0.0:
        return _sign(x3)
    if x2 != 0.0:
        return _sign(x2)
    if x1 != 0.0:
        return _sign(x1)
    return _sign(x0)


@njit(cache=True, _nrt=True)
def _orient2d_exact(ax, ay, bx, by, cx, cy):
    # Stage B (no allocation): when the four differences are floats exactly (lattices, and
    # nearby points by Sterbenz's lemma), the determinant is a difference of two exact
    # two-component products. Otherwise the full expansion in the original coordinates.
    acx, t0 = two_diff(ax, cx)
    bcx, t1 = two_diff(bx, cx)
    acy, t2 = two_diff(ay, cy)
    bcy, t3 = two_diff(by, cy)
    if t0 == 0.0 and t1 == 0.0 and t2 == 0.0 and t3 == 0.0:
        l1, l0 = two_product(acx, bcy)
        r1, r0 = two_product(acy, bcx)
        return _two_two_diff_sign(l1, l0, r1, r0)
    h = np.empty(ORIENT2D_EXPANSION_MAX)
    n = orient2d_expansion(ax, ay, bx, by, cx, cy, h)
    return expansion_sign(h, n)


@njit(cache=True)
def _incircle_filter(ax, ay, bx, by, cx, cy, dx, dy):
    # Shewchuk's incircle stage A.  Allocates nothing.
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy

    bdxcdy = bdx * cdy
    cdxbdy = cdx * bdy
    alift = adx * adx + ady * ady

    cdxady = cdx * ady
    adxcdy = adx * cdy
    blift = bdx * bdx + bdy * bdy

    adxbdy = adx * bdy
    bdxady = bdx * ady
    clift = cdx * cdx + cdy * cdy

    det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady)
    permanent = (
        (abs(bdxcdy) + abs(cdxbdy)) * alift
        + (abs(cdxady) + abs(adxcdy)) * blift
        + (abs(adxbdy) + abs(bdxady)) * clift
    )
    errbound = ICC_ERRBOUND_A * permanent
    if abs(det) > errbound:
        return _sign(det)
    if permanent == 0.0:
        # every product is exactly 0 (no underflow in the supported range)
        return 0
    return _UNDECIDED


@njit(cache=True)
def _incircle_in_floats(ax, ay, bx, by, cx, cy, dx, dy):
    # the float evaluation of the determinant with every difference, product and sum checked
    # error-free: its sign when nothing rounded (small integer or dyadic lattices: every
    # cocircular quadruple of a grid), else _UNDECIDED. Allocates nothing.
    adx, t0 = two_diff(ax, dx)
    bdx, t1 = two_diff(bx, dx)
    cdx, t2 = two_diff(cx, dx)
    ady, t3 = two_diff(ay, dy)
    bdy, t4 = two_diff(by, dy)
    cdy, t5 = two_diff(cy, dy)
    if t0 != 0.0 or t1 != 0.0 or t2 != 0.0 or t3 != 0.0 or t4 != 0.0 or t5 != 0.0:
        return _UNDECIDED
    p0, r0 = two_product(bdx, cdy)
    p1, r1 = two_product(cdx, bdy)
    m0, r2 = two_diff(p0, p1)
    p2, r3 = two_product(cdx, ady)
    p3, r4 = two_product(adx, cdy)
    m1, r5 = two_diff(p2, p3)
    p4, r6 = two_product(adx, bdy)
    p5, r7 = two_product(bdx, ady)
    m2, r8 = two_diff(p4, p5)
    q0, r9 = two_product(adx, adx)
    q1, r10 = two_product(ady, ady)
    alift, r11 = two_sum(q0, q1)
    q2, r12 = two_product(bdx, bdx)
    q3, r13 = two_product(bdy, bdy)
    blift, r14 = two_sum(q2, q3)
    q4, r15 = two_product(cdx, cdx)
    q5, r16 = two_product(cdy, cdy)
    clift, r17 = two_sum(q4, q5)
    u0, r18 = two_product(alift, m0)
    u1, r19 = two_product(blift, m1)
    u2, r20 = two_product(clift, m2)
    v, r21 = two_sum(u0, u1)
    det, r22 = two_sum(v, u2)
    tails = (abs(r0) + abs(r1) + abs(r2) + abs(r3) + abs(r4) + abs(r5) + abs(r6) + abs(r7) + abs(r8)
             + abs(r9) + abs(r10) + abs(r11) + abs(r12) + abs(r13) + abs(r14) + abs(r15) + abs(r16)
             + abs(r17) + abs(r18) + abs(r19) + abs(r20) + abs(r21) + abs(r22))
    if tails == 0.0:
        return _sign(det)
    return _UNDECIDED


@njit(cache=True)
def _incircle_exact(ax, ay, bx, by, cx, cy, dx, dy):
    s = _incircle_in_floats(ax, ay, bx, by, cx, cy, dx, dy)
    if s != _UNDECIDED:
        return s
    buf = np.empty(1024 + INCIRCLE_EXPANSION_MAX)
    h = buf[:INCIRCLE_EXPANSION_MAX]
    w = buf[INCIRCLE_EXPANSION_MAX:]
    n = _incircle_expansion_work(ax, ay, bx, by, cx, cy, dx, dy, h, w)
    return expansion_sign(h, n)


_SIG6 = _I64(_F64, _F64, _F64, _F64, _F64, _F64)


_SIG8 = _I64(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64)


@njit(_SIG6, cache=True)
def orient2d(ax, ay, bx, by, cx, cy):
    """Exact orientation of (a, b, c): +1 counter-clockwise, -1 clockwise, 0 collinear.

    Sign of (ax-cx)*(by-cy) - (ay-cy)*(bx-cx), exact for coordinates that are 0
    or within [1e-100, 1e100] in magnitude.  Float filter first (no allocation),
    exact expansion arithmetic only when the filter cannot decide.
    """
    s = _orient2d_filter(ax, ay, bx, by, cx, cy)
    if s != _UNDECIDED:
        return s
    return _orient2d_exact(ax, ay, bx, by, cx, cy)


@njit(_I64(_F64, _F64, _F64, _F64, _F64, _F64, _COUNTERS), cache=True)
def orient2d_counted(ax, ay, bx, by, cx, cy, counters):
    """:func:`orient2d` that also does ``counters[ORIENT_CALLS] += 1`` and, when the exact stage runs, ``counters[ORIENT_EXACT] += 1``."""
    counters[ORIENT_CALLS] += 1
    s = _orient2d_filter(ax, ay, bx, by, cx, cy)
    if s != _UNDECIDED:
        return s
    counters[ORIENT_EXACT] += 1
    return _orient2d_exact(ax, ay, bx, by, cx, cy)


@njit(_F64(_F64, _F64, _F64, _F64, _F64, _F64), cache=True)
def orient2d_fast(ax, ay, bx, by, cx, cy):
    """NOT EXACT: plain float evaluation of the orient2d determinant (returns the float value).

    For measuring the cost of robustness only; its sign can be wrong (even
    inconsistent) for nearly collinear points.
    """
    return (ax - cx) * (by - cy) - (ay - cy) * (bx - cx)


@njit(_SIG8, cache=True)
def incircle(ax, ay, bx, by, cx, cy, dx, dy):
    """Exact incircle sign: for counter-clockwise a, b, c, +1 if d is strictly inside their circle, -1 outside, 0 cocircular.

    For clockwise a, b, c the sign is flipped.  It is the sign of the 3x3
    determinant with rows (px-dx, py-dy, (px-dx)**2 + (py-dy)**2), p = a, b, c;
    exact for coordinates that are 0 or within [1e-50, 1e50] in magnitude.
    """
    s = _incircle_filter(ax, ay, bx, by, cx, cy, dx, dy)
    if s != _UNDECIDED:
        return s
    return _incircle_exact(ax, ay, bx, by, cx, cy, dx, dy)


@njit(_I64(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _COUNTERS), cache=True)
def incircle_counted(ax, ay, bx, by, cx, cy, dx, dy, counters):
    """:func:`incircle` that also does ``counters[INCIRCLE_CALLS] += 1`` and, when the exact stage runs, ``counters[INCIRCLE_EXACT] += 1``."""
    counters[INCIRCLE_CALLS] += 1
    s = _incircle_filter(ax, ay, bx, by, cx, cy, dx, dy)
    if s != _UNDECIDED:
        return s
    counters[INCIRCLE_EXACT] += 1
    return _incircle_exact(ax, ay, bx, by, cx, cy, dx, dy)


@njit(_F64(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64), cache=True)
def incircle_fast(ax, ay, bx, by, cx, cy, dx, dy):
    """NOT EXACT: plain float evaluation of the incircle determinant (returns the float value).

    For measuring the cost of robustness only; its sign can be wrong for
    nearly cocircular points.
    """
    adx = ax - dx
    bdx = bx - dx
    cdx = cx - dx
    ady = ay - dy
    bdy = by - dy
    cdy = cy - dy
    alift = adx * adx + ady * ady
    blift = bdx * bdx + bdy * bdy
    clift = cdx * cdx + cdy * cdy
    return (
        alift * (bdx * cdy - cdx * bdy)
        + blift * (cdx * ady - adx * cdy)
        + clift * (adx * bdy - bdx * ady)
    )


@njit(cache=True)
def _orient2d_many_kernel(a, b, c, out, counters):
    sa = a.shape[0] > 1
    sb = b.shape[0] > 1
    sc = c.shape[0] > 1
    for i in range(out.shape[0]):
        ia = i if sa else 0
        ib = i if sb else 0
        ic = i if sc else 0
        out[i] = orient2d_counted(a[ia, 0], a[ia, 1], b[ib, 0], b[ib, 1], c[ic, 0], c[ic, 1], counters)


@njit(cache=True)
def _incircle_many_kernel(a, b, c, d, out, counters):
    sa = a.shape[0] > 1
    sb = b.shape[0] > 1
    sc = c.shape[0] > 1
    sd = d.shape[0] > 1
    for i in range(out.shape[0]):
        ia = i if sa else 0
        ib = i if sb else 0
        ic = i if sc else 0
        idd = i if sd else 0
        out[i] = incircle_counted(
            a[ia, 0], a[ia, 1], b[ib, 0], b[ib, 1], c[ic, 0], c[ic, 1], d[idd, 0], d[idd, 1], counters
        )


def _points(p, name):
    arr = np.ascontiguousarray(p, dtype=np.float64)
    if arr.ndim == 1:
        arr = arr.reshape(1, -1)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"{name} must have shape (k, 2) or (2,), got {np.shape(p)}")
    return arr


def _common_length(arrays):
    n = 1
    for arr in arrays:
        if arr.shape[0] != 1:
            if n != 1 and arr.shape[0] != n:
                raise ValueError("point arrays have incompatible lengths " + str([x.shape[0] for x in arrays]))
            n = arr.shape[0]
    if any(arr.shape[0] == 0 for arr in arrays):
        n = 0
    return n


def _counters(counters):
    if counters is None:
        return np.zeros(4, dtype=np.int64)
    if not isinstance(counters, np.ndarray) or counters.dtype != np.int64 or counters.ndim != 1 or counters.shape[0] < 4:
        raise ValueError("counters must be a 1-D int64 numpy array of length >= 4")
    return counters


def orient2d_many(a, b, c, counters=None):
    """Vectorised :func:`orient2d`: int8 array of exact signs for point rows a[i], b[i], c[i].

    Each argument is a (k, 2) float64 array or a single point of shape (2,)
    or (1, 2), which is broadcast.  If ``counters`` (int64 array, length >= 4)
    is given, calls and exact fallbacks are added to it as in
    :func:`orient2d_counted`.
    """
    pts = [_points(a, "a"), _points(b, "b"), _points(c, "c")]
    out = np.empty(_common_length(pts), dtype=np.int8)
    _orient2d_many_kernel(pts[0], pts[1], pts[2], out, _counters(counters))
    return out


def incircle_many(a, b, c, d, counters=None):
    """Vectorised :func:`incircle`: int8 array of exact signs for rows a[i], b[i], c[i], d[i].

    Broadcasting and ``counters`` as in :func:`orient2d_many`.
    """
    pts = [_points(a, "a"), _points(b, "b"), _points(c, "c"), _points(d, "d")]
    out = np.empty(_common_length(pts), dtype=np.int8)
    _incircle_many_kernel(pts[0], pts[1], pts[2], pts[3], out, _counters(counters))
    return out
