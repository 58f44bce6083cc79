"""Exact predicates of power (Laguerre) diagrams and regular triangulations: the power test
(``incircle`` for weighted points) and the side of a power bisector, each a float filter with a
proven error bound, then exact expansion arithmetic; counted, plain-float and vectorised versions.

Weighted points and sign conventions
------------------------------------
A weighted point is (x, y, w); as in CGAL's ``Weighted_point_2``, the *power* of a point q with
respect to it is ``|q - (x, y)|**2 - w`` (w is a squared radius; any sign is allowed).

``power_test(a, b, c, d)`` (each point given as x, y, w) is the sign of the lifted determinant

    | ax-dx  ay-dy  (ax-dx)**2 + (ay-dy)**2 - (aw-dw) |
    | bx-dx  by-dy  (bx-dx)**2 + (by-dy)**2 - (bw-dw) |
    | cx-dx  cy-dy  (cx-dx)**2 + (cy-dy)**2 - (cw-dw) |

equal to the 4x4 determinant with rows ``(px, py, px**2 + py**2 - pw, 1)`` for p = a, b, c, d
(the lifted points of a regular triangulation). With equal weights the weight column vanishes
and it is exactly :func:`~vorobench.core.predicates.incircle`'s determinant. For a, b, c
counter-clockwise it is +1 when d is in conflict with the power circle of a, b, c (the circle
orthogonal to their three circles: d's power with respect to it is negative), i.e. when d's
lifted point lies strictly below the plane through the lifted a, b, c; -1 when above, 0 when
the four lifted points are coplanar. For clockwise a, b, c every non-zero sign flips; raising
dw by t adds t * (twice the signed area of abc) to the determinant.

``power_bisector_side(p, a, b)`` is the sign of ``pow_a(p) - pow_b(p)`` =
``|p-a|**2 - aw - (|p-b|**2 - bw)`` for a plain point p: -1 when p is strictly closer in power
to a (p lies in a's cell of the two-site power diagram), +1 when closer to b, 0 on the power
bisector (a line perpendicular to ab, or everything/nothing when a and b coincide).

Exactness guarantee and input range
-----------------------------------
Every result is the exact sign of the determinant (or difference) in real arithmetic on the
given float64 values, for finite inputs where every nonzero coordinate has magnitude in
[2**-100, 2**100) (the project's range, :mod:`vorobench.core.scaling`) and every nonzero
weight magnitude in [2**-200, 2**200): weights have the dimension of squared coordinates, so
this is the coordinate range squared (:func:`vorobench.core.scaling.check_weight_range` checks it; scaling the
coordinates by 2**k must scale the weights by 2**(2k), which keeps every sign here). In that
range no product of the evaluations underflows or overflows: the power test's exact stage
forms products of up to four coordinate differences (bits from 2**-608 to 2**408) and a weight
difference times two coordinate differences (down to 2**-556), the bisector test squares of
coordinate differences and weight differences; all far inside [2**-1074, 2**996). NaN/inf
inputs give unspecified results.

Evaluation
----------
Filter: the determinant evaluated in floats, with an a-priori bound on its rounding error
proportional to a "permanent" (the same expression on absolute values), derived below in
:data:`POWER_ERRBOUND_A` and :data:`POWER_BISECTOR_ERRBOUND_A`. Exact: the lifted coordinate
x**2 + y**2 - w is not representable in floats, so the exact stages work from the coordinate
and weight *differences*, which ``two_diff`` gives exactly as two components. When they are
single floats (nearby points, by Sterbenz's lemma; lattices) the power test first checks the
float evaluation for any rounding at all (small integer or dyadic lattices, the usual exactly
degenerate inputs, are decided there without allocating), then expands the products of the
float differences in one short buffer. Otherwise every difference is a two-component expansion
and the products are formed and compressed in a scratch pool (the slowest path: ~2.5x
incircle's exact stage, a few microseconds). The bisector test sums four exact squares, or
with inexact differences expands |p-a|**2 - |p-b|**2 in the original coordinates.

Counters: the ``*_counted`` variants add to an int64 array at POWER_TEST_CALLS,
POWER_TEST_EXACT, POWER_BISECTOR_CALLS, POWER_BISECTOR_EXACT (4..7, after the orient2d and
incircle block 0..3, so one array of length N_POWER_COUNTERS = 8 counts all four predicates).
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from vorobench.core.predicates.expansion import (
    _COUNTERS,
    _F64,
    _I64,
    _UNDECIDED,
    EPSILON,
    _new_pool,
    _xadd,
    _xd,
    _xmul,
    _xsign,
    _xsub,
    det2_expansion,
    diff_expansion,
    expansion_sign,
    expansion_sum,
    grow_expansion,
    product_expansion,
    scale_expansion,
    two_diff,
    two_product,
    two_sum,
)
from vorobench.core.predicates.orient_incircle import _common_length, _sign

__all__ = ["POWER_ERRBOUND_A", "POWER_BISECTOR_ERRBOUND_A", "POWER_TEST_CALLS", "POWER_TEST_EXACT",
           "POWER_BISECTOR_CALLS", "POWER_BISECTOR_EXACT", "N_POWER_COUNTERS", 
           "power_test_filter", "power_test",
           "power_test_counted", "power_test_fast", "power_test_many", "power_bisector_side_filter",
           "power_bisector_side", "power_bisector_side_counted", "power_bisector_side_fast",
           "power_bisector_side_many"]


#: Relative error bound of the power-test filter: the float determinant is within
#: POWER_ERRBOUND_A * permanent of the exact one (``u`` = EPSILON, gamma_k = k u / (1 - k u)).
#: Per row p (differences X, Y, W exact; adx, ady, adw their floats, relative error <= u):
#: S = fl(adx**2 + ady**2) is within gamma_4 S of X**2 + Y**2, so the lift fl(S - adw) is within
#: gamma_5 Lambda of X**2 + Y**2 - W, where Lambda = S + |adw| (and |lift| <= (1+u) Lambda);
#: the minor fl(P1 - P2) of the two products P1, P2 is within gamma_4 mu, mu = |P1| + |P2|;
#: their rounded product is within [u(1+u)**2 + (1+u) gamma_4 + (1+gamma_3) gamma_5] Lambda mu,
#: and the first of the two final sums adds u(1+u)**3 Lambda mu (the last one keeps the sign).
#: That is 11u + ~65u**2 times permanent = sum Lambda mu; computing the permanent and the bound
#: in floats (6 roundings) and |det| vs the unrounded sum (1 more) raise it to 11u + ~142u**2:
#: 160u**2 covers it (tests/core/test_predicates_power.py evaluates the chain with fractions).
POWER_ERRBOUND_A = (11.0 + 160.0 * EPSILON) * EPSILON

#: Relative error bound of the bisector filter: each squared distance fl(pax**2 + pay**2) is
#: within gamma_4 of the exact one, their difference adds u (sa + sb), the weight difference
#: gamma_1 |dw|, the last subtraction keeps the sign: gamma_5 (sa + sb + |dw|), and 3 more
#: roundings for the permanent and the bound: 5u + ~45u**2, covered by 64u**2.
POWER_BISECTOR_ERRBOUND_A = (5.0 + 64.0 * EPSILON) * EPSILON


#: Indices into the counters array of the ``*_counted`` power predicates (after the orient2d /
#: incircle block 0..3); arrays given to them need N_POWER_COUNTERS entries.
POWER_TEST_CALLS = 4
POWER_TEST_EXACT = 5
POWER_BISECTOR_CALLS = 6
POWER_BISECTOR_EXACT = 7
N_POWER_COUNTERS = 8


@njit(cache=True)
def power_test_filter(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw):
    """Float-filtered :func:`power_test`: the exact sign, or ``UNDECIDED`` (2). Allocates nothing."""
    adx = ax - dx
    ady = ay - dy
    adw = aw - dw
    bdx = bx - dx
    bdy = by - dy
    bdw = bw - dw
    cdx = cx - dx
    cdy = cy - dy
    cdw = cw - dw
    # squared distances to d, then the lifts relative to d's (may cancel: hence |adw| in Lambda)
    alen = adx * adx + ady * ady
    blen = bdx * bdx + bdy * bdy
    clen = cdx * cdx + cdy * cdy
    alift = alen - adw
    blift = blen - bdw
    clift = clen - cdw
    # the 2x2 minors (orientations of the other two points seen from d)
    bdxcdy = bdx * cdy
    cdxbdy = cdx * bdy
    cdxady = cdx * ady
    adxcdy = adx * cdy
    adxbdy = adx * bdy
    bdxady = bdx * ady
    det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady)
    permanent = ((alen + abs(adw)) * (abs(bdxcdy) + abs(cdxbdy))
                 + (blen + abs(bdw)) * (abs(cdxady) + abs(adxcdy))
                 + (clen + abs(cdw)) * (abs(adxbdy) + abs(bdxady)))
    errbound = POWER_ERRBOUND_A * permanent
    if abs(det) > errbound:
        return _sign(det)
    if permanent == 0.0:
        # in every row the lift is exactly 0 (its differences are) or both minor products are
        # (a float difference is 0 only when exact; nothing underflows in the range)
        return 0
    return _UNDECIDED


@njit(cache=True)
def _power_in_floats(adx, ady, adw, bdx, bdy, bdw, cdx, cdy, cdw):
    # The filter's evaluation on exact (float) differences with every product and sum checked
    # error-free: its sign when nothing rounded (small integer or dyadic lattices with such
    # weights, the usual exactly degenerate inputs), else UNDECIDED. Allocates nothing.
    err = 0.0
    s, e = two_product(adx, adx)
    err += abs(e)
    t, e = two_product(ady, ady)
    err += abs(e)
    s, e = two_sum(s, t)
    err += abs(e)
    alift, e = two_diff(s, adw)
    err += abs(e)
    s, e = two_product(bdx, bdx)
    err += abs(e)
    t, e = two_product(bdy, bdy)
    err += abs(e)
    s, e = two_sum(s, t)
    err += abs(e)
    blift, e = two_diff(s, bdw)
    err += abs(e)
    s, e = two_product(cdx, cdx)
    err += abs(e)
    t, e = two_product(cdy, cdy)
    err += abs(e)
    s, e = two_sum(s, t)
    err += abs(e)
    clift, e = two_diff(s, cdw)
    err += abs(e)
    s, e = two_product(bdx, cdy)
    err += abs(e)
    t, e = two_product(cdx, bdy)
    err += abs(e)
    ma, e = two_diff(s, t)
    err += abs(e)
    s, e = two_product(cdx, ady)
    err += abs(e)
    t, e = two_product(adx, cdy)
    err += abs(e)
    mb, e = two_diff(s, t)
    err += abs(e)
    s, e = two_product(adx, bdy)
    err += abs(e)
    t, e = two_product(bdx, ady)
    err += abs(e)
    mc, e = two_diff(s, t)
    err += abs(e)
    ta, e = two_product(alift, ma)
    err += abs(e)
    tb, e = two_product(blift, mb)
    err += abs(e)
    tc, e = two_product(clift, mc)
    err += abs(e)
    s, e = two_sum(ta, tb)
    err += abs(e)
    # the last sum may round: rounding keeps the sign of s + tc
    if err == 0.0:
        return _sign(s + tc)
    return _UNDECIDED


@njit(cache=True)
def _lift_times_minor(dx, dy, dw1, dw0, p, q, r, t, w, out):
    # out = (dx**2 + dy**2 - (dw1 + dw0)) * (p*q - r*t) exactly, for floats; returns the length
    # (<= 48). The lift has <= 6 components, the minor <= 4; the product is the lift scaled by
    # each component of the minor, accumulated. w: scratch of >= 120 floats.
    lift = w[0:6]
    n = product_expansion(dx, dx, lift)
    hi, lo = two_product(dy, dy)
    n = grow_expansion(lift, n, lo, lift)
    n = grow_expansion(lift, n, hi, lift)
    n = grow_expansion(lift, n, -dw0, lift)
    n = grow_expansion(lift, n, -dw1, lift)
    minor = w[6:10]
    m = det2_expansion(p, q, r, t, minor)
    part = w[10:22]
    acc = w[22:70]
    nxt = w[70:118]
    alen = scale_expansion(lift, n, minor[0], acc)
    for i in range(1, m):
        plen = scale_expansion(lift, n, minor[i], part)
        alen = expansion_sum(acc, alen, part, plen, nxt)
        acc, nxt = nxt, acc
    for i in range(alen):
        out[i] = acc[i]
    return alen


@njit(cache=True)
def _power_from_float_differences(adx, ady, adw1, adw0, bdx, bdy, bdw1, bdw0, cdx, cdy, cdw1, cdw0):
    # exact sign of the 3x3 determinant when its six coordinate differences are floats (the
    # weight differences are given as two components): three products of <= 48 components,
    # summed (<= 144), in one buffer
    buf = np.empty(504)
    w = buf[0:120]
    ta = buf[120:168]
    tb = buf[168:216]
    tc = buf[216:264]
    s = buf[264:360]
    h = buf[360:504]
    na = _lift_times_minor(adx, ady, adw1, adw0, bdx, cdy, cdx, bdy, w, ta)
    nb = _lift_times_minor(bdx, bdy, bdw1, bdw0, cdx, ady, adx, cdy, w, tb)
    nc = _lift_times_minor(cdx, cdy, cdw1, cdw0, adx, bdy, bdx, ady, w, tc)
    ns = expansion_sum(ta, na, tb, nb, s)
    nh = expansion_sum(s, ns, tc, nc, h)
    return expansion_sign(h, nh)


@njit(cache=True)
def _power_from_expansions(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw):
    # The general case: every difference an exact expansion of <= 2 components, all products
    # and sums exact and compressed, in one scratch pool.
    w = _new_pool()
    adx = _xd(ax, dx, w)
    ady = _xd(ay, dy, w)
    bdx = _xd(bx, dx, w)
    bdy = _xd(by, dy, w)
    cdx = _xd(cx, dx, w)
    cdy = _xd(cy, dy, w)
    alift = _xsub(_xadd(_xmul(adx, adx, w), _xmul(ady, ady, w), w), _xd(aw, dw, w), w)
    blift = _xsub(_xadd(_xmul(bdx, bdx, w), _xmul(bdy, bdy, w), w), _xd(bw, dw, w), w)
    clift = _xsub(_xadd(_xmul(cdx, cdx, w), _xmul(cdy, cdy, w), w), _xd(cw, dw, w), w)
    ma = _xsub(_xmul(bdx, cdy, w), _xmul(cdx, bdy, w), w)
    mb = _xsub(_xmul(cdx, ady, w), _xmul(adx, cdy, w), w)
    mc = _xsub(_xmul(adx, bdy, w), _xmul(bdx, ady, w), w)
    det = _xadd(_xadd(_xmul(alift, ma, w), _xmul(blift, mb, w), w), _xmul(clift, mc, w), w)
    return _xsign(det)


@njit(cache=True)
def _power_test_exact(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw):
    # Exact sign of the 3x3 lifted determinant. When the six coordinate differences are floats
    # (nearby points by Sterbenz's lemma, lattices): first the float evaluation if the weight
    # differences are floats too and nothing in it rounds, else exact expansions of the float
    # differences (weight differences as two components); otherwise every difference as a
    # two-component expansion.
    adx, e0 = two_diff(ax, dx)
    ady, e1 = two_diff(ay, dy)
    adw, e2 = two_diff(aw, dw)
    bdx, e3 = two_diff(bx, dx)
    bdy, e4 = two_diff(by, dy)
    bdw, e5 = two_diff(bw, dw)
    cdx, e6 = two_diff(cx, dx)
    cdy, e7 = two_diff(cy, dy)
    cdw, e8 = two_diff(cw, dw)
    if e0 != 0.0 or e1 != 0.0 or e3 != 0.0 or e4 != 0.0 or e6 != 0.0 or e7 != 0.0:
        return _power_from_expansions(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw)
    if e2 == 0.0 and e5 == 0.0 and e8 == 0.0:
        s = _power_in_floats(adx, ady, adw, bdx, bdy, bdw, cdx, cdy, cdw)
        if s != _UNDECIDED:
            return s
    return _power_from_float_differences(adx, ady, adw, e2, bdx, bdy, bdw, e5, cdx, cdy, cdw, e8)


_SIG12 = _I64(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64)


_SIG8 = _I64(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64)


@njit(_SIG12, cache=True)
def power_test(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw):
    """Exact power test: for counter-clockwise a, b, c, +1 if the weighted point d is in conflict with
    their power circle (lifted d below their plane), -1 if not, 0 if the four lifts are coplanar.

    Flipped for clockwise a, b, c; equal to :func:`incircle` when all weights are equal. Exact for
    nonzero coordinates in [2**-100, 2**100) and weights in [2**-200, 2**200) in magnitude.
    """
    s = power_test_filter(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw)
    if s != _UNDECIDED:
        return s
    return _power_test_exact(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw)


@njit(_I64(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _COUNTERS), cache=True)
def power_test_counted(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw, counters):
    """:func:`power_test` that also does ``counters[POWER_TEST_CALLS] += 1`` and, when the exact
    stage runs, ``counters[POWER_TEST_EXACT] += 1``."""
    counters[POWER_TEST_CALLS] += 1
    s = power_test_filter(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw)
    if s != _UNDECIDED:
        return s
    counters[POWER_TEST_EXACT] += 1
    return _power_test_exact(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw)


@njit(_F64(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64), cache=True)
def power_test_fast(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw):
    """NOT EXACT: plain float value of the power-test determinant (the filter's evaluation).

    For measuring the cost of robustness only; its sign can be wrong near coplanar lifts.
    """
    adx = ax - dx
    ady = ay - dy
    bdx = bx - dx
    bdy = by - dy
    cdx = cx - dx
    cdy = cy - dy
    alift = (adx * adx + ady * ady) - (aw - dw)
    blift = (bdx * bdx + bdy * bdy) - (bw - dw)
    clift = (cdx * cdx + cdy * cdy) - (cw - dw)
    return (alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy)
            + clift * (adx * bdy - bdx * ady))


@njit(cache=True)
def power_bisector_side_filter(px, py, ax, ay, aw, bx, by, bw):
    """Float-filtered :func:`power_bisector_side`: the exact sign, or ``UNDECIDED`` (2). Allocates nothing."""
    pax = px - ax
    pay = py - ay
    pbx = px - bx
    pby = py - by
    sa = pax * pax + pay * pay
    sb = pbx * pbx + pby * pby
    dw = aw - bw
    f = (sa - sb) - dw
    permanent = (sa + sb) + abs(dw)
    errbound = POWER_BISECTOR_ERRBOUND_A * permanent
    if abs(f) > errbound:
        return _sign(f)
    if permanent == 0.0:
        # p = a = b and aw = bw exactly
        return 0
    return _UNDECIDED


@njit(cache=True)
def _power_bisector_side_exact(px, py, ax, ay, aw, bx, by, bw):
    # exact |p-a|**2 - |p-b|**2 - (aw - bw) in one short buffer: with float differences of the
    # coordinates, four exact squares and the weight difference (<= 10 components); otherwise
    # expanded in the original coordinates, 2 p.(b - a) + |a|**2 - |b|**2 - aw + bw: eight exact
    # products (2 p is exact) and the weight difference (<= 18 components)
    pax, e0 = two_diff(px, ax)
    pay, e1 = two_diff(py, ay)
    pbx, e2 = two_diff(px, bx)
    pby, e3 = two_diff(py, by)
    h = np.empty(18)
    n = diff_expansion(bw, aw, h)
    if e0 == 0.0 and e1 == 0.0 and e2 == 0.0 and e3 == 0.0:
        for d, sign in ((pax, 1.0), (pay, 1.0), (pbx, -1.0), (pby, -1.0)):
            hi, lo = two_product(d, d)
            n = grow_expansion(h, n, sign * lo, h)
            n = grow_expansion(h, n, sign * hi, h)
        return expansion_sign(h, n)
    px2 = 2.0 * px
    py2 = 2.0 * py
    for f, g in ((px2, bx), (-px2, ax), (py2, by), (-py2, ay), (ax, ax), (ay, ay), (-bx, bx), (-by, by)):
        hi, lo = two_product(f, g)
        n = grow_expansion(h, n, lo, h)
        n = grow_expansion(h, n, hi, h)
    return expansion_sign(h, n)


@njit(_SIG8, cache=True)
def power_bisector_side(px, py, ax, ay, aw, bx, by, bw):
    """Exact sign of pow_a(p) - pow_b(p) = |p-a|**2 - aw - (|p-b|**2 - bw): -1 if p is strictly closer
    in power to a, +1 if to b, 0 on their power bisector. Range as for :func:`power_test`."""
    s = power_bisector_side_filter(px, py, ax, ay, aw, bx, by, bw)
    if s != _UNDECIDED:
        return s
    return _power_bisector_side_exact(px, py, ax, ay, aw, bx, by, bw)


@njit(_I64(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64, _COUNTERS), cache=True)
def power_bisector_side_counted(px, py, ax, ay, aw, bx, by, bw, counters):
    """:func:`power_bisector_side` that also does ``counters[POWER_BISECTOR_CALLS] += 1`` and, when
    the exact stage runs, ``counters[POWER_BISECTOR_EXACT] += 1``."""
    counters[POWER_BISECTOR_CALLS] += 1
    s = power_bisector_side_filter(px, py, ax, ay, aw, bx, by, bw)
    if s != _UNDECIDED:
        return s
    counters[POWER_BISECTOR_EXACT] += 1
    return _power_bisector_side_exact(px, py, ax, ay, aw, bx, by, bw)


@njit(_F64(_F64, _F64, _F64, _F64, _F64, _F64, _F64, _F64), cache=True)
def power_bisector_side_fast(px, py, ax, ay, aw, bx, by, bw):
    """NOT EXACT: plain float value of pow_a(p) - pow_b(p) (the filter's evaluation), for measurements only."""
    pax = px - ax
    pay = py - ay
    pbx = px - bx
    pby = py - by
    return ((pax * pax + pay * pay) - (pbx * pbx + pby * pby)) - (aw - bw)


@njit(cache=True)
def _power_test_many_kernel(a, b, c, d, out, counters):
    sa = a.shape[0] > 1
    sb = b.shape[0] > 1
    sc = c.shape[0] > 1
    sd = d.shape[0] > 1
    for i in range(out.shape[0]):
        ia = i if sa else 0
        ib = i if sb else 0
        ic = i if sc else 0
        idd = i if sd else 0
        out[i] = power_test_counted(a[ia, 0], a[ia, 1], a[ia, 2], b[ib, 0], b[ib, 1], b[ib, 2],
                                    c[ic, 0], c[ic, 1], c[ic, 2], d[idd, 0], d[idd, 1], d[idd, 2], counters)


@njit(cache=True)
def _power_bisector_side_many_kernel(p, a, b, out, counters):
    sp = p.shape[0] > 1
    sa = a.shape[0] > 1
    sb = b.shape[0] > 1
    for i in range(out.shape[0]):
        ip = i if sp else 0
        ia = i if sa else 0
        ib = i if sb else 0
        out[i] = power_bisector_side_counted(p[ip, 0], p[ip, 1], a[ia, 0], a[ia, 1], a[ia, 2],
                                             b[ib, 0], b[ib, 1], b[ib, 2], counters)


def _rows(p: ArrayLike, name: str, width: int) -> NDArray[np.float64]:
    arr = np.ascontiguousarray(p, dtype=np.float64)
    if arr.ndim == 1:
        arr = arr.reshape(1, -1)
    if arr.ndim != 2 or arr.shape[1] != width:
        what = "(x, y, w)" if width == 3 else "(x, y)"
        raise ValueError(f"{name} must have shape (k, {width}) or ({width},) of rows {what}, got {np.shape(p)}")
    return arr


def _power_counters(counters: Optional[NDArray[np.int64]]) -> NDArray[np.int64]:
    if counters is None:
        return np.zeros(N_POWER_COUNTERS, dtype=np.int64)
    if (not isinstance(counters, np.ndarray) or counters.dtype != np.int64 or counters.ndim != 1
            or counters.shape[0] < N_POWER_COUNTERS):
        raise ValueError(f"counters must be a 1-D int64 numpy array of length >= {N_POWER_COUNTERS}")
    return counters


def power_test_many(a: ArrayLike, b: ArrayLike, c: ArrayLike, d: ArrayLike,
                    counters: Optional[NDArray[np.int64]] = None) -> NDArray[np.int8]:
    """Vectorised :func:`power_test`: int8 array of exact signs for weighted rows a[i], b[i], c[i], d[i].

    Each argument is a (k, 3) float64 array of rows (x, y, w) or one weighted point of shape (3,)
    or (1, 3), which is broadcast. If ``counters`` (int64, length >= 8) is given, calls and exact
    fallbacks are added at POWER_TEST_CALLS and POWER_TEST_EXACT.
    """
    rows = [_rows(a, "a", 3), _rows(b, "b", 3), _rows(c, "c", 3), _rows(d, "d", 3)]
    out = np.empty(_common_length(rows), dtype=np.int8)
    _power_test_many_kernel(rows[0], rows[1], rows[2], rows[3], out, _power_counters(counters))
    return out


def power_bisector_side_many(p: ArrayLike, a: ArrayLike, b: ArrayLike,
                             counters: Optional[NDArray[np.int64]] = None) -> NDArray[np.int8]:
    """Vectorised :func:`power_bisector_side`: int8 signs for points p[i] ((k, 2) rows (x, y)) and
    weighted points a[i], b[i] ((k, 3) rows (x, y, w)); broadcasting and ``counters`` as in
    :func:`power_test_many` (at POWER_BISECTOR_CALLS and POWER_BISECTOR_EXACT).
    """
    rows = [_rows(p, "p", 2), _rows(a, "a", 3), _rows(b, "b", 3)]
    out = np.empty(_common_length(rows), dtype=np.int8)
    _power_bisector_side_many_kernel(rows[0], rows[1], rows[2], out, _power_counters(counters))
    return out
