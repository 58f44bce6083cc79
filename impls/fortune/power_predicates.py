"""The weighted sweep's predicates, compiled: float and interval filters, then the exact stage.

Each decision of :mod:`impls.fortune.power_reference` (the specification) is evaluated here
in interval arithmetic (:mod:`vorobench.core.predicates.interval`) on the points and times of
*specs* (see :mod:`impls.fortune.power_exact`); the breakpoint test and the power centre of
three sites, the most frequent, are first evaluated in floats with error bounds derived by
hand (``_gap_float``, ``_apex_float``, ``_centre_float``), and contact points and power gaps in
floats that carry their error bound (``_contact_float``, ``_power_gap_float``, with
:mod:`vorobench.core.predicates.running_error`). When the interval of the deciding
quantity holds 0, the same decision is taken in rationals by :mod:`impls.fortune.power_exact`,
called from numba's object mode. Signs known to be 0 by construction are not filtered: the power gap
of two sites at a point that defines them (their power centre, their contact point), and the
difference of two wavefronts at such a point, where only the branch is left to decide.

``G`` is the per-site table (x, y, s_lo, s_hi, w): coordinates, the shifted weight
s_i = max(w) - w_i as an interval, and the weight itself, from which differences of shifts
are taken (s_i - s_j = w_j - w_i, one rounding instead of two). ``counters`` counts filter
calls and exact decisions.

The float filters (``_gap_float``, ``_apex_float``, ``_power_gap_float``, ``_centre_float``,
``_contact_float``) are inlined by numba (``inline='always'``) into their one caller each: a
call passes the site table as a struct of about eight words, and inlining them took 7-9 % off
the sweep's time (A/B, 5x10^4 uniform and ``kuzmin``, medians of 30-40 alternating builds) for
about 9 s more of compilation. The rest, and the interval operations, are ordinary compiled
functions: numba's inlining of everything made the weighted sweep take 214 s to compile on a
fresh cache against about 100 s without it, for the same run time at the time.
"""

from __future__ import annotations

import math

from numba import njit, objmode

from impls.fortune import power_exact
from impls.fortune.power_exact import CENTRE, CONTACT, SITE
from vorobench.core.predicates import interval as iv
from vorobench.core.predicates import running_error as rerr
from vorobench.core.predicates import orient2d
from vorobench.core.predicates.expansion import EPSILON, _new_pool, _xadd, _xd, _xmul, _xsign, _xsub
from vorobench.core.predicates.interval import UNDECIDED
from vorobench.core.scaling import EXACT_MAX_EXPONENT, EXACT_MIN_EXPONENT, WEIGHT_MAX_EXPONENT, WEIGHT_MIN_EXPONENT

__all__ = ["SITE", "CENTRE", "CONTACT", "FILTERED", "EXACT", "spec_point", "time_order", "side",
           "power_gap", "same_centre", "farther", "tied", "keeps_middle", "line_inside"]

#: Indices into the counters array: weighted decisions filtered, and decided in rationals.
FILTERED = 0
EXACT = 1

_X, _Y, _SLO, _SHI, _W = 0, 1, 2, 3, 4


@njit(cache=True)
def _ds(G, a, b):
    # s_a - s_b = w_b - w_a
    return iv.sub(G[b, _W], G[b, _W], G[a, _W], G[a, _W])


@njit(cache=True)
def _delta(G, a, b):
    # the intervals of p_b - p_a: (x lo, x hi, y lo, y hi)
    xl, xh = iv.sub(G[b, _X], G[b, _X], G[a, _X], G[a, _X])
    yl, yh = iv.sub(G[b, _Y], G[b, _Y], G[a, _Y], G[a, _Y])
    return xl, xh, yl, yh


@njit(cache=True)
def _norm2(xl, xh, yl, yh):
    # the interval of x^2 + y^2
    t1l, t1h = iv.sqr(xl, xh)
    t2l, t2h = iv.sqr(yl, yh)
    return iv.add(t1l, t1h, t2l, t2h)


#: Relative slack on error bounds computed in floats: covers the few roundings of their own
#: nonnegative terms, far below it.
_BOUND_SLACK = 1.0 + 2.0 ** -40
#: Absolute slack for roundings that underflow (each errs by at most 2**-1075): added to each
#: bound, weighted by the factors such an error may be multiplied by afterwards. A normal
#: float, as :data:`running_error.TINY` says why.
_TINY = rerr.TINY


@njit(cache=True, inline='always')
def _centre_float(G, a, b, c):
    """The power centre of sites a, b, c and its time, in floats, with error bounds derived by
    hand (about three times cheaper than the intervals): (True, box) where they hold; (False,
    ...) when the sites are too near collinear for the float orientation D (or something
    overflowed), and the intervals take over.

    With b, c, s_b - s_a, s_c - s_a taken from p_a (one rounding each), r_b = |b|^2 + s_b - s_a
    and D = b_x c_y - b_y c_x have 5 and 4 roundings on their longest paths, N_x = r_b c_y - r_c b_y
    and N_y = b_x r_c - c_x r_b have 8: each errs by less than gamma_k (k + 0.01 EPSILON) times
    the same expression in absolute values, bounds taken with a unit more. The centre is
    p_a + N / (2 D), and |N/D - N'/D'| <= (e_N + |N/D| e_D) / (|D| - e_D) where |D| > e_D. Its
    time is v_y + sqrt(L), L = |v - p_a|^2 + s_a, and |sqrt(L) - sqrt(L')| is at most
    |L - L'| / sqrt(L) and at most sqrt(|L - L'|)."""
    u = EPSILON
    xa, ya = G[a, _X], G[a, _Y]
    bx, by, cx, cy = G[b, _X] - xa, G[b, _Y] - ya, G[c, _X] - xa, G[c, _Y] - ya
    db, dc = G[a, _W] - G[b, _W], G[a, _W] - G[c, _W]          # s_b - s_a, s_c - s_a
    bb, cc = bx * bx + by * by, cx * cx + cy * cy
    rb, rc = bb + db, cc + dc
    mb, mc = bb + abs(db), cc + abs(dc)
    d = bx * cy - by * cx
    ed = 5.0 * u * (abs(bx * cy) + abs(by * cx)) + _TINY
    if not abs(d) > 2.0 * ed:                   # near collinear, or NaN
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    nx, ny = rb * cy - rc * by, bx * rc - cx * rb
    enx = 9.0 * u * (mb * abs(cy) + mc * abs(by)) + _TINY * (1.0 + abs(cy) + abs(by))
    eny = 9.0 * u * (abs(bx) * mc + abs(cx) * mb) + _TINY * (1.0 + abs(bx) + abs(cx))
    ux, uy = nx / (2.0 * d), ny / (2.0 * d)
    den = 2.0 * (abs(d) - ed)
    # |N/D| <= 2 |u| (1 + 2 EPSILON): the quotient rounded once
    eux = (enx + 2.0 * (1.0 + 2.0 * u) * abs(ux) * ed) / den + 2.0 * u * abs(ux)
    euy = (eny + 2.0 * (1.0 + 2.0 * u) * abs(uy) * ed) / den + 2.0 * u * abs(uy)
    x, y = xa + ux, ya + uy
    ex = (eux + 3.0 * u * abs(x)) * _BOUND_SLACK + _TINY
    ey = (euy + 3.0 * u * abs(y)) * _BOUND_SLACK + _TINY
    s_hi = G[a, _SHI]
    ell = (ux * ux + uy * uy) + s_hi
    el = 4.0 * u * ell + eux * (2.0 * abs(ux) + eux) + euy * (2.0 * abs(uy) + euy) + (s_hi - G[a, _SLO]) + _TINY
    r = math.sqrt(ell)
    root_el = math.sqrt(el)
    er = min(el / r, root_el) if r > 0.0 else root_el
    t = y + r
    et = (ey + er + 2.0 * u * r + 3.0 * u * abs(t)) * _BOUND_SLACK + _TINY
    # an overflow, a NaN, or a shift interval given upside down (a negative bound): intervals
    if not (0.0 <= ex < math.inf and 0.0 <= ey < math.inf and 0.0 <= et < math.inf
            and abs(x) + abs(y) + abs(t) < math.inf):
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return True, x - ex, x + ex, y - ey, y + ey, t - et, t + et


@njit(cache=True, inline='always')
def _contact_float(G, i, k):
    """The contact point of site i with the lower site k and its time (see :func:`spec_point`)
    in floats with running error bounds (:mod:`vorobench.core.predicates.running_error`):
    (True, box), or (False, ...) where something overflowed or a divisor's error may reach it
    (differences near the underflow threshold), and the intervals take over."""
    nx, enx = rerr.sub(G[k, _X], 0.0, G[i, _X], 0.0)
    ny, eny = rerr.sub(G[k, _Y], 0.0, G[i, _Y], 0.0)
    sx, esx = rerr.sqr(nx, enx)
    sy, esy = rerr.sqr(ny, eny)
    nn, enn = rerr.add(sx, esx, sy, esy)
    ds, eds = rerr.sub(G[i, _W], 0.0, G[k, _W], 0.0)              # s_k - s_i
    q, eq = rerr.div(ds, eds, nn, enn)
    q, eq = rerr.half(q, eq)
    mx, emx = rerr.add(G[i, _X], 0.0, G[k, _X], 0.0)
    mx, emx = rerr.half(mx, emx)
    my, emy = rerr.add(G[i, _Y], 0.0, G[k, _Y], 0.0)
    my, emy = rerr.half(my, emy)
    p, ep = rerr.mul(nx, enx, q, eq)
    fx, efx = rerr.add(mx, emx, p, ep)
    p, ep = rerr.mul(ny, eny, q, eq)
    fy, efy = rerr.add(my, emy, p, ep)
    lam, elam = rerr.sub(q, eq, 0.5, 0.0)
    lam, elam = rerr.sqr(lam, elam)
    sk, esk = rerr.within(G[k, _SLO], G[k, _SHI])
    p, ep = rerr.div(sk, esk, nn, enn)
    h, eh = rerr.add(lam, elam, p, ep)
    h, eh = rerr.mul(h, eh, sy, esy)
    r, er = rerr.sqrt(h, eh)
    rat, erat = rerr.div(nx, enx, ny, eny)
    p, ep = rerr.mul(r, er, rat, erat)
    x, ex = rerr.add(fx, efx, p, ep)
    rat, erat = rerr.sqr(rat, erat)
    p, ep = rerr.mul(r, er, rat, erat)
    y, ey = rerr.sub(fy, efy, p, ep)
    t, et = rerr.add(fy, efy, r, er)
    okx, xl, xh = rerr.box(x, ex)
    oky, yl, yh = rerr.box(y, ey)
    okt, tl, th = rerr.box(t, et)
    return okx and oky and okt, xl, xh, yl, yh, tl, th


# Explicit signatures: the callers pass kinds and sites as constants, literals and array
# items, and each mix would otherwise be a compilation of its own (ten seconds each here).
# ``_nrt=False``: no reference counting of the array arguments, which costs two atomic
# instructions per array per call (see impls.fortune.power_sweep); these functions allocate
# nothing.
@njit("UniTuple(float64, 6)(float64[:, :], int64, int64, int64, int64)", cache=True, _nrt=False)
def spec_point(G, kind, a, b, c):
    """Intervals (xlo, xhi, ylo, yhi, tlo, thi) of the point and time of a spec."""
    if kind == SITE:
        x, y = G[a, _X], G[a, _Y]
        return x, x, y, y, y, y
    if kind == CENTRE:
        ok, xl, xh, yl, yh, tl, th = _centre_float(G, a, b, c)
        if ok:
            return xl, xh, yl, yh, tl, th
        # v = p_a + u with 2 u . (p_b - p_a) = |p_b - p_a|^2 + s_b - s_a (equal power with b), and
        # the same with c; the time is v_y + sqrt(|u|^2 + s_a)
        bxl, bxh = iv.sub(G[b, _X], G[b, _X], G[a, _X], G[a, _X])
        byl, byh = iv.sub(G[b, _Y], G[b, _Y], G[a, _Y], G[a, _Y])
        cxl, cxh = iv.sub(G[c, _X], G[c, _X], G[a, _X], G[a, _X])
        cyl, cyh = iv.sub(G[c, _Y], G[c, _Y], G[a, _Y], G[a, _Y])
        dbl, dbh = _ds(G, b, a)
        dcl, dch = _ds(G, c, a)
        t1l, t1h = iv.sqr(bxl, bxh)
        t2l, t2h = iv.sqr(byl, byh)
        rbl, rbh = iv.add(t1l, t1h, t2l, t2h)
        rbl, rbh = iv.add(rbl, rbh, dbl, dbh)
        t1l, t1h = iv.sqr(cxl, cxh)
        t2l, t2h = iv.sqr(cyl, cyh)
        rcl, rch = iv.add(t1l, t1h, t2l, t2h)
        rcl, rch = iv.add(rcl, rch, dcl, dch)
        t1l, t1h = iv.mul(bxl, bxh, cyl, cyh)
        t2l, t2h = iv.mul(byl, byh, cxl, cxh)
        dl, dh = iv.sub(t1l, t1h, t2l, t2h)
        dl, dh = iv.add(dl, dh, dl, dh)                  # 2 D
        t1l, t1h = iv.mul(rbl, rbh, cyl, cyh)
        t2l, t2h = iv.mul(rcl, rch, byl, byh)
        nl, nh = iv.sub(t1l, t1h, t2l, t2h)
        uxl, uxh = iv.div(nl, nh, dl, dh)
        t1l, t1h = iv.mul(bxl, bxh, rcl, rch)
        t2l, t2h = iv.mul(cxl, cxh, rbl, rbh)
        nl, nh = iv.sub(t1l, t1h, t2l, t2h)
        uyl, uyh = iv.div(nl, nh, dl, dh)
        xl, xh = iv.add(uxl, uxh, G[a, _X], G[a, _X])
        yl, yh = iv.add(uyl, uyh, G[a, _Y], G[a, _Y])
        t1l, t1h = iv.sqr(uxl, uxh)
        t2l, t2h = iv.sqr(uyl, uyh)
        ll, lh = iv.add(t1l, t1h, t2l, t2h)
        ll, lh = iv.add(ll, lh, G[a, _SLO], G[a, _SHI])
        rl, rh = iv.sqrt(ll, lh)
        tl, th = iv.add(yl, yh, rl, rh)
        return xl, xh, yl, yh, tl, th
    # CONTACT of a (= i) with the lower b (= k): on their bisector, with n = p_k - p_i, the foot
    # of p_k is f = (p_i + p_k) / 2 + n (s_k - s_i) / (2 |n|^2); with
    # h = (lam^2 + s_k / |n|^2) n_y^2, lam = (s_k - s_i) / (2 |n|^2) - 1/2, the contact is
    # c = f + sqrt(h) (n_x / n_y, -n_x^2 / n_y^2) at time f_y + sqrt(h)
    i, k = a, b
    ok, xl, xh, yl, yh, tl, th = _contact_float(G, i, k)
    if ok:
        return xl, xh, yl, yh, tl, th
    nxl, nxh = iv.sub(G[k, _X], G[k, _X], G[i, _X], G[i, _X])
    nyl, nyh = iv.sub(G[k, _Y], G[k, _Y], G[i, _Y], G[i, _Y])
    t1l, t1h = iv.sqr(nxl, nxh)
    t2l, t2h = iv.sqr(nyl, nyh)
    nnl, nnh = iv.add(t1l, t1h, t2l, t2h)
    dsl, dsh = _ds(G, k, i)
    ql, qh = iv.div(dsl, dsh, nnl, nnh)
    ql, qh = iv.half(ql, qh)                             # (s_k - s_i) / (2 |n|^2)
    mxl, mxh = iv.add(G[i, _X], G[i, _X], G[k, _X], G[k, _X])
    mxl, mxh = iv.half(mxl, mxh)
    myl, myh = iv.add(G[i, _Y], G[i, _Y], G[k, _Y], G[k, _Y])
    myl, myh = iv.half(myl, myh)
    t1l, t1h = iv.mul(nxl, nxh, ql, qh)
    fxl, fxh = iv.add(mxl, mxh, t1l, t1h)
    t1l, t1h = iv.mul(nyl, nyh, ql, qh)
    fyl, fyh = iv.add(myl, myh, t1l, t1h)
    laml, lamh = iv.sub(ql, qh, 0.5, 0.5)
    t1l, t1h = iv.sqr(laml, lamh)
    t2l, t2h = iv.div(G[k, _SLO], G[k, _SHI], nnl, nnh)
    hl, hh = iv.add(t1l, t1h, t2l, t2h)
    t1l, t1h = iv.sqr(nyl, nyh)
    hl, hh = iv.mul(hl, hh, t1l, t1h)
    rl, rh = iv.sqrt(hl, hh)
    ratl, rath = iv.div(nxl, nxh, nyl, nyh)
    t1l, t1h = iv.mul(rl, rh, ratl, rath)
    xl, xh = iv.add(fxl, fxh, t1l, t1h)
    t2l, t2h = iv.sqr(ratl, rath)
    t2l, t2h = iv.mul(rl, rh, t2l, t2h)
    yl, yh = iv.sub(fyl, fyh, t2l, t2h)
    tl, th = iv.add(fyl, fyh, rl, rh)
    return xl, xh, yl, yh, tl, th


@njit(cache=True)
def _defines(kind, a, b, c, s):
    # whether site s is one of those that define the spec's point
    if kind == CENTRE:
        return s == a or s == b or s == c
    if kind == CONTACT:
        return s == a or s == b
    return False


@njit(cache=True)
def _exact_time_order(k1, a1, b1, c1, k2, a2, b2, c2):
    with objmode(r='int64'):
        r = power_exact.time_order(k1, a1, b1, c1, k2, a2, b2, c2)
    return r


@njit(cache=True, _nrt=False)
def time_order(G, counters, k1, a1, b1, c1, lo1, hi1, k2, a2, b2, c2, lo2, hi2):
    """-1, 0 or 1 as the time of spec 1 (enclosed in [lo1, hi1]) is before, at or after that
    of spec 2."""
    counters[FILTERED] += 1
    if hi1 < lo2:
        return -1
    if hi2 < lo1:
        return 1
    if k1 == k2 and a1 == a2 and b1 == b2 and c1 == c2:
        return 0
    counters[EXACT] += 1
    return _exact_time_order(k1, a1, b1, c1, k2, a2, b2, c2)


@njit(cache=True)
def _exact_side(left, right, kind, a, b, c):
    with objmode(r='int64'):
        r = power_exact.side(left, right, kind, a, b, c)
    return r


#: Relative error bound of the float evaluation of the wavefront gap G in :func:`_gap_float`:
#: 8 roundings on the longest path (a leaf difference, two products, two sums, the last
#: product, the final sum), so the error is below gamma_8 < 8.01 EPSILON times the same
#: expression in absolute values; 12 EPSILON also covers the rounding of that magnitude.
SIDE_GAP_ERRBOUND = 12.0 * EPSILON
#: The same for the apex quantity of :func:`_apex_float` (4 roundings on its longest path).
SIDE_APEX_ERRBOUND = 6.0 * EPSILON
#: Relative slack on the spread terms (a few roundings of nonnegative terms, far below it).
_SPREAD_SLACK = 1.0 + 2.0 ** -40
#: Absolute slack for roundings that underflow (each errs by at most 2**-1075 and is then
#: multiplied by at most two of the factors it is weighted by below), where relative bounds fail.
_UNDERFLOW_SLACK = rerr.TINY


@njit(cache=True)
def _float_deltas(G, left, right, xl, tl):
    # the sites' coordinates, then A = t - y_l, B = t - y_r, x - x_l and x - x_r at (xl, tl)
    yl_, yr_, xl_, xr_ = G[left, _Y], G[right, _Y], G[left, _X], G[right, _X]
    return yl_, yr_, xl_, xr_, tl - yl_, tl - yr_, xl - xl_, xl - xr_


@njit(cache=True, inline='always')
def _gap_float(G, left, right, xl, xh, tl, th):
    """The sign of the wavefronts' difference G (see :func:`side`) at the point x in [xl, xh],
    at a time t in [tl, th], from one evaluation in floats at (xl, tl), or UNDECIDED.

    The error bound has three parts: the rounding error (SIDE_GAP_ERRBOUND times G with
    every term in absolute value, the shift s_r >= 0 taken at its upper end), the spread of G over
    the box, which is exact because G is quadratic in (x, t),
    |G(x, t) - G(xl, tl)| <= |G_t| dt + |G_x| dx + |dy| (dx^2 + dt^2) + 2 |x_l - x_r| dx dt
    with G_t = dy (A + B) + (x_l - x_r) (2 x - x_l - x_r) + s_r - s_l and
    G_x = 2 (B (x_l - x_r) - dy (x - x_r)), plus the width of s_r's interval times |dy|; and an
    absolute term for underflow. Overflow and NaN make the bound infinite or NaN: UNDECIDED."""
    yl_, yr_, xl_, xr_, a, b, dxl, dxr = _float_deltas(G, left, right, xl, tl)
    dy, dx = yl_ - yr_, xl_ - xr_
    sr = G[right, _SHI]
    ds = G[left, _W] - G[right, _W]                 # s_r - s_l
    value = dy * ((a * b - sr) - dxr * dxr) + b * (dx * (dxl + dxr) + ds)
    ady, adx, aa, ab, adxl, adxr, ads = abs(dy), abs(dx), abs(a), abs(b), abs(dxl), abs(dxr), abs(ds)
    magnitude = ady * ((aa * ab + sr) + adxr * adxr) + ab * (adx * (adxl + adxr) + ads)
    rx, rt = xh - xl, th - tl
    spread = ((ady * (aa + ab) + adx * (adxl + adxr) + ads) * rt + 2.0 * (ab * adx + ady * adxr) * rx
              + ady * (rx * rx + rt * rt) + 2.0 * adx * rx * rt + ady * (sr - G[right, _SLO]))
    bound = SIDE_GAP_ERRBOUND * magnitude + _SPREAD_SLACK * spread + \
        _UNDERFLOW_SLACK * (1.0 + ady + ab + adx + rx + rt)
    return rerr.sign_within(value, bound)


@njit(cache=True, inline='always')
def _apex_float(G, left, right, xl, xh, tl, th):
    """The sign of (x - x_l) B - (x - x_r) A (see :func:`side`) in floats at (xl, tl), or
    UNDECIDED: the quantity is affine in (x, t) (the x t terms cancel), so its spread over the
    box is exactly |y_l - y_r| dx + |x_l - x_r| dt."""
    yl_, yr_, xl_, xr_, a, b, dxl, dxr = _float_deltas(G, left, right, xl, tl)
    value = dxl * b - dxr * a
    spread = abs(yl_ - yr_) * (xh - xl) + abs(xl_ - xr_) * (th - tl)
    bound = SIDE_APEX_ERRBOUND * (abs(dxl) * abs(b) + abs(dxr) * abs(a)) + _SPREAD_SLACK * spread + \
        _UNDERFLOW_SLACK * (1.0 + abs(a) + abs(b))
    return rerr.sign_within(value, bound)


@njit(cache=True)
def _side_deltas(G, left, right, xl, xh, tl, th):
    # the intervals of A = t - y_l, B = t - y_r, x - x_l and x - x_r
    al, ah = iv.sub(tl, th, G[left, _Y], G[left, _Y])
    bl, bh = iv.sub(tl, th, G[right, _Y], G[right, _Y])
    dll, dlh = iv.sub(xl, xh, G[left, _X], G[left, _X])
    drl, drh = iv.sub(xl, xh, G[right, _X], G[right, _X])
    return al, ah, bl, bh, dll, dlh, drl, drh


@njit(cache=True)
def _gap_interval(G, left, right, xl, xh, tl, th):
    # the sign of G in interval arithmetic (tighter than _gap_float where the box is wide, and
    # exact zeros, as on lattices, stay exact), or UNDECIDED
    yl_, yr_ = G[left, _Y], G[right, _Y]
    al, ah, bl, bh, dll, dlh, drl, drh = _side_deltas(G, left, right, xl, xh, tl, th)
    # with A = B + (y_r - y_l): G = (y_l - y_r) (A B - s_r - (x - x_r)^2)
    #                              + B ((s_r - s_l) + (x_l - x_r) (2 x - x_l - x_r)),
    # which leaves t in one place per product (its interval is not counted twice)
    t1l, t1h = iv.mul(al, ah, bl, bh)
    t1l, t1h = iv.sub(t1l, t1h, G[right, _SLO], G[right, _SHI])
    t2l, t2h = iv.sqr(drl, drh)
    t1l, t1h = iv.sub(t1l, t1h, t2l, t2h)
    dyl, dyh = iv.sub(yl_, yl_, yr_, yr_)
    t1l, t1h = iv.mul(t1l, t1h, dyl, dyh)
    sxl, sxh = iv.add(dll, dlh, drl, drh)            # 2 x - x_l - x_r
    dxl_, dxh_ = iv.sub(G[left, _X], G[left, _X], G[right, _X], G[right, _X])
    t2l, t2h = iv.mul(dxl_, dxh_, sxl, sxh)
    dsl, dsh = _ds(G, right, left)
    t2l, t2h = iv.add(t2l, t2h, dsl, dsh)
    t2l, t2h = iv.mul(t2l, t2h, bl, bh)
    gl, gh = iv.add(t1l, t1h, t2l, t2h)
    return iv.sign(gl, gh)


@njit(cache=True)
def _apex_interval(G, left, right, xl, xh, tl, th):
    # the sign of (x - x_l) B - (x - x_r) A in interval arithmetic, or UNDECIDED
    al, ah, bl, bh, dll, dlh, drl, drh = _side_deltas(G, left, right, xl, xh, tl, th)
    t1l, t1h = iv.mul(dll, dlh, bl, bh)
    t2l, t2h = iv.mul(drl, drh, al, ah)
    nl, nh = iv.sub(t1l, t1h, t2l, t2h)
    return iv.sign(nl, nh)


@njit("int64(float64[:, :], int64[:], int64, int64, int64, int64, int64, int64, float64, float64, float64, float64)",
      cache=True, _nrt=False)
def side(G, counters, left, right, kind, a, b, c, xl, xh, tl, th):
    """Where the point of a spec (x in [xl, xh] at a time in [tl, th]) lies against the
    breakpoint (left, right): -1 left of it, 0 at it, 1 right of it.

    With A = t - y_l, B = t - y_r, the difference of the two wavefronts times 2 A B > 0 is
    G = A B (y_l - y_r) + A (s_r + (x - x_r)^2) - B (s_l + (x - x_l)^2), and the side of the
    apex of that difference is sign((x - x_l) B - (x - x_r) A) sign(y_l - y_r); the rule that
    combines them is ``power_reference.Sweep.side_of_breakpoint``. Each sign is taken from a
    float evaluation with an error bound first (about ten times cheaper), then in intervals."""
    counters[FILTERED] += 1
    yl_, yr_ = G[left, _Y], G[right, _Y]
    if _defines(kind, a, b, c, left) and _defines(kind, a, b, c, right):
        g = 0                                   # the point is on both wavefronts
    else:
        g = _gap_float(G, left, right, xl, xh, tl, th)
        if g == UNDECIDED:
            g = _gap_interval(G, left, right, xl, xh, tl, th)
    if g != UNDECIDED:
        if yl_ == yr_:
            return -g
        if g != 0 and yl_ > yr_ and g > 0:
            return -1
        if g != 0 and yl_ < yr_ and g < 0:
            return 1
        apex = _apex_float(G, left, right, xl, xh, tl, th)
        if apex == UNDECIDED:
            apex = _apex_interval(G, left, right, xl, xh, tl, th)
        if apex != UNDECIDED:
            apex = apex if yl_ > yr_ else -apex
            if yl_ > yr_:
                # the right crossing (g > 0 between the two): g < 0 or 0 left of the apex: left
                if apex < 0:
                    return -1
                return 0 if g == 0 else 1
            # the left crossing: g > 0 (with 0 excluded above: g < 0 returned) left of the apex
            if g > 0 and apex < 0:
                return -1
            if g == 0 and apex < 0:
                return 0
            return 1
    counters[EXACT] += 1
    return _exact_side(left, right, kind, a, b, c)


@njit(cache=True)
def _exact_power_gap(j, k, kind, a, b, c):
    with objmode(r='int64'):
        r = power_exact.power_gap(j, k, kind, a, b, c)
    return r


@njit(cache=True, inline='always')
def _power_gap_float(G, j, k, xl, xh, yl, yh):
    # the sign of l_j - l_k (see power_gap) in floats with running error bounds, the point
    # taken at its box's centre with half the box as its error, or UNDECIDED
    cx, ecx = rerr.within(xl, xh)
    cy, ecy = rerr.within(yl, yh)
    ux, eux = rerr.sub(G[j, _X], 0.0, G[k, _X], 0.0)
    uy, euy = rerr.sub(G[j, _Y], 0.0, G[k, _Y], 0.0)
    a, ea = rerr.sub(G[j, _X], 0.0, cx, ecx)
    b, eb = rerr.sub(G[k, _X], 0.0, cx, ecx)
    sx, esx = rerr.add(a, ea, b, eb)                   # (p_j - c)_x + (p_k - c)_x
    a, ea = rerr.sub(G[j, _Y], 0.0, cy, ecy)
    b, eb = rerr.sub(G[k, _Y], 0.0, cy, ecy)
    sy, esy = rerr.add(a, ea, b, eb)
    a, ea = rerr.mul(ux, eux, sx, esx)
    b, eb = rerr.mul(uy, euy, sy, esy)
    v, ev = rerr.add(a, ea, b, eb)
    d, ed = rerr.sub(G[k, _W], 0.0, G[j, _W], 0.0)     # s_j - s_k
    v, ev = rerr.add(v, ev, d, ed)
    return rerr.sign(v, ev)


@njit("int64(float64[:, :], int64[:], int64, int64, int64, int64, int64, int64, float64, float64, float64, float64)",
      cache=True, _nrt=False)
def power_gap(G, counters, j, k, kind, a, b, c, xl, xh, yl, yh):
    """The sign of l_j - l_k at the point of a spec, in the box [xl, xh] x [yl, yh]: positive
    where k has the smaller power. l_j - l_k = (p_j - p_k) . ((p_j - c) + (p_k - c)) + s_j - s_k
    is affine in c, so the box's interval is tight."""
    if j == k or (_defines(kind, a, b, c, j) and _defines(kind, a, b, c, k)):
        return 0
    counters[FILTERED] += 1
    s = _power_gap_float(G, j, k, xl, xh, yl, yh)
    if s != UNDECIDED:
        return s
    ux_l, ux_h = iv.sub(G[j, _X], G[j, _X], G[k, _X], G[k, _X])
    uy_l, uy_h = iv.sub(G[j, _Y], G[j, _Y], G[k, _Y], G[k, _Y])
    t1l, t1h = iv.sub(G[j, _X], G[j, _X], xl, xh)
    t2l, t2h = iv.sub(G[k, _X], G[k, _X], xl, xh)
    sxl, sxh = iv.add(t1l, t1h, t2l, t2h)
    t1l, t1h = iv.sub(G[j, _Y], G[j, _Y], yl, yh)
    t2l, t2h = iv.sub(G[k, _Y], G[k, _Y], yl, yh)
    syl, syh = iv.add(t1l, t1h, t2l, t2h)
    t1l, t1h = iv.mul(ux_l, ux_h, sxl, sxh)
    t2l, t2h = iv.mul(uy_l, uy_h, syl, syh)
    vl, vh = iv.add(t1l, t1h, t2l, t2h)
    dsl, dsh = _ds(G, j, k)
    vl, vh = iv.add(vl, vh, dsl, dsh)
    s = iv.sign(vl, vh)
    if s != UNDECIDED:
        return s
    counters[EXACT] += 1
    return _exact_power_gap(j, k, kind, a, b, c)


@njit(cache=True)
def _exact_same_centre(a1, b1, c1, a2, b2, c2):
    with objmode(r='int64'):
        r = power_exact.same_point(a1, b1, c1, a2, b2, c2)
    return r


@njit(cache=True, _nrt=False)
def same_centre(counters, a1, b1, c1, box1, a2, b2, c2, box2):
    """Whether the power centres of (a1, b1, c1) and (a2, b2, c2), enclosed in the boxes
    (xlo, xhi, ylo, yhi), are one point."""
    counters[FILTERED] += 1
    if box1[1] < box2[0] or box2[1] < box1[0] or box1[3] < box2[2] or box2[3] < box1[2]:
        return False
    counters[EXACT] += 1
    return _exact_same_centre(a1, b1, c1, a2, b2, c2) == 1


@njit(cache=True)
def _exact_farther(i1, p1, i2, p2):
    with objmode(r='int64'):
        r = power_exact.farther(i1, p1, i2, p2)
    return r


@njit(cache=True, _nrt=False)
def _far(G, i, p):
    if p < 0:
        return 0.0, 0.0
    xl, xh, yl, yh = _delta(G, p, i)
    return _norm2(xl, xh, yl, yh)


@njit(cache=True, _nrt=False)
def farther(G, counters, i1, p1, i2, p2):
    """The sign of |p_i1 - p_p1|^2 - |p_i2 - p_p2|^2 (a partner of -1 is at distance 0)."""
    if i1 == i2 and p1 == p2:
        return 0
    counters[FILTERED] += 1
    l1, h1 = _far(G, i1, p1)
    l2, h2 = _far(G, i2, p2)
    if h1 < l2:
        return -1
    if h2 < l1:
        return 1
    counters[EXACT] += 1
    return _exact_farther(i1, p1, i2, p2)


@njit(cache=True, _nrt=False)
def keeps_middle(G, counters, a, b, c):
    """On the lowest row (x_a < x_b < x_c), whether b's line 2 x_b X - x_b^2 - s_b is strictly
    above a's where a's and c's cross: the sign of
    -((x_b - x_a)((x_a^2 + s_a) - (x_c^2 + s_c)) - (x_a - x_c)((x_b^2 - x_a^2) + (s_b - s_a)))."""
    counters[FILTERED] += 1
    xa, xb, xc = G[a, _X], G[b, _X], G[c, _X]
    t1l, t1h = iv.sub(xb, xb, xa, xa)
    t2l, t2h = iv.sub(xa, xa, xc, xc)
    sl, sh = iv.add(xa, xa, xc, xc)
    t3l, t3h = iv.mul(t2l, t2h, sl, sh)                   # x_a^2 - x_c^2
    dsl, dsh = _ds(G, a, c)
    t3l, t3h = iv.add(t3l, t3h, dsl, dsh)
    p1l, p1h = iv.mul(t1l, t1h, t3l, t3h)
    sl, sh = iv.add(xb, xb, xa, xa)
    t4l, t4h = iv.mul(t1l, t1h, sl, sh)                   # x_b^2 - x_a^2
    dsl, dsh = _ds(G, b, a)
    t4l, t4h = iv.add(t4l, t4h, dsl, dsh)
    p2l, p2h = iv.mul(t2l, t2h, t4l, t4h)
    nl, nh = iv.sub(p1l, p1h, p2l, p2h)
    s = iv.sign(nl, nh)
    if s != UNDECIDED:
        return s < 0
    counters[EXACT] += 1
    with objmode(r='int64'):
        r = power_exact.keeps_middle(a, b, c)
    return r == 1


# where the compiled exact stages are exact (vorobench.core.scaling): nonzero coordinates with
# magnitudes in [2**-100, 2**100), weights in [2**-200, 2**200); ``Implementation.run`` scales
# every input into it, a direct call may not
_XY_LOW, _XY_HIGH = 2.0 ** (EXACT_MIN_EXPONENT - 1), 2.0 ** EXACT_MAX_EXPONENT
_W_LOW, _W_HIGH = 2.0 ** (WEIGHT_MIN_EXPONENT - 1), 2.0 ** WEIGHT_MAX_EXPONENT


@njit(cache=True)
def _fits(v, low, high):
    a = abs(v)
    return a == 0.0 or (low <= a < high)


@njit(cache=True)
def _in_exact_range(G, a, b, c):
    """Whether sites a, b, c have coordinates and weights where expansions are exact (deeper
    under or over, products of differences lose bits: the rationals decide there)."""
    for s in (a, b, c):
        if not (_fits(G[s, _X], _XY_LOW, _XY_HIGH) and _fits(G[s, _Y], _XY_LOW, _XY_HIGH)
                and _fits(G[s, _W], _W_LOW, _W_HIGH)):
            return False
    return True


@njit(cache=True)
def _rational_tied(a, b, c):
    with objmode(r='int64'):
        r = power_exact.tied(a, b, c)
    return r


@njit(cache=True)
def _rational_line_inside(i, k, j):
    with objmode(r='int64'):
        r = power_exact.line_inside(i, k, j)
    return r


@njit(cache=True)
def _between(G, a, b, c):
    # for distinct collinear a, b, c: whether b lies strictly between a and c, from the signs
    # of coordinate differences (exact comparisons; on a line that is not vertical, x orders
    # the points, else y does)
    axis = _X if G[b, _X] != G[a, _X] else _Y
    return (G[b, axis] > G[a, axis]) == (G[c, axis] > G[b, axis])


@njit(cache=True, _nrt=True)
def _tied_exact(G, a, b, c):
    # the sign of D = u (q_c - q_b) - (q_b - q_a) v along one axis (see tied), in exact
    # expansions of the differences from p_a: D does not change when all three points move
    # together, as they are collinear (outside the exact range: 0 or 1 from the rationals)
    if not _in_exact_range(G, a, b, c):
        return 0 if _rational_tied(a, b, c) == 1 else 1
    w = _new_pool()
    axis = _X if G[b, _X] != G[a, _X] else _Y
    u = _xd(G[b, axis], G[a, axis], w)
    v = _xd(G[c, axis], G[b, axis], w)
    bx, by = _xd(G[b, _X], G[a, _X], w), _xd(G[b, _Y], G[a, _Y], w)
    cx, cy = _xd(G[c, _X], G[a, _X], w), _xd(G[c, _Y], G[a, _Y], w)
    bb = _xadd(_xmul(bx, bx, w), _xmul(by, by, w), w)
    cc = _xadd(_xmul(cx, cx, w), _xmul(cy, cy, w), w)
    uq = _xadd(bb, _xd(G[a, _W], G[b, _W], w), w)
    vq = _xadd(_xsub(cc, bb, w), _xd(G[b, _W], G[c, _W], w), w)
    return _xsign(_xsub(_xmul(u, vq, w), _xmul(uq, v, w), w))


@njit(cache=True, _nrt=False)
def _tied_filter(G, a, b, c):
    # the interval of D (see _tied_exact), from the same differences
    axis = _X if G[b, _X] != G[a, _X] else _Y
    ul, uh = iv.sub(G[b, axis], G[b, axis], G[a, axis], G[a, axis])
    vl, vh = iv.sub(G[c, axis], G[c, axis], G[b, axis], G[b, axis])
    bxl, bxh, byl, byh = _delta(G, a, b)
    bbl, bbh = _norm2(bxl, bxh, byl, byh)
    cxl, cxh, cyl, cyh = _delta(G, a, c)
    ccl, cch = _norm2(cxl, cxh, cyl, cyh)
    dl, dh = _ds(G, b, a)                                  # w_a - w_b
    uql, uqh = iv.add(bbl, bbh, dl, dh)
    dl, dh = _ds(G, c, b)                                  # w_b - w_c
    vql, vqh = iv.sub(ccl, cch, bbl, bbh)
    vql, vqh = iv.add(vql, vqh, dl, dh)
    t1l, t1h = iv.mul(ul, uh, vql, vqh)
    t2l, t2h = iv.mul(uql, uqh, vl, vh)
    return iv.sub(t1l, t1h, t2l, t2h)


@njit(cache=True, _nrt=False)
def tied(G, counters, a, b, c):
    """Collinear a, b, c with b strictly between a and c, and one bisector line for (a, b) and
    (b, c): the three have equal power all along it, so b's cell lies in the line.

    For collinear points, u = p_b - p_a and v = p_c - p_b are parallel, and the bisectors are one
    line where u (q_c - q_b) = (q_b - q_a) v along an axis where u is not 0 (q = x^2 + y^2 + s,
    s = max(w) - w): an interval filter, then exact expansions."""
    if orient2d(G[a, _X], G[a, _Y], G[b, _X], G[b, _Y], G[c, _X], G[c, _Y]) != 0 or not _between(G, a, b, c):
        return False
    counters[FILTERED] += 1
    dl, dh = _tied_filter(G, a, b, c)
    s = iv.sign(dl, dh)
    if s == UNDECIDED:
        counters[EXACT] += 1
        s = _tied_exact(G, a, b, c)
    return s == 0


@njit(cache=True, _nrt=True)
def _line_inside_exact(G, i, k, j):
    # the sign of E (see line_inside) in exact expansions of the differences from p_i (outside
    # the exact range: 1 or -1 from the rationals)
    if not _in_exact_range(G, i, k, j):
        return 1 if _rational_line_inside(i, k, j) == 1 else -1
    w = _new_pool()
    nx, ny = _xd(G[k, _X], G[i, _X], w), _xd(G[k, _Y], G[i, _Y], w)
    px, py = _xd(G[j, _X], G[i, _X], w), _xd(G[j, _Y], G[i, _Y], w)
    nn = _xadd(_xmul(nx, nx, w), _xmul(ny, ny, w), w)
    pp = _xadd(_xmul(px, px, w), _xmul(py, py, w), w)
    npj = _xadd(_xmul(nx, px, w), _xmul(ny, py, w), w)
    left = _xmul(nn, _xadd(pp, _xd(G[i, _W], G[j, _W], w), w), w)
    right = _xmul(_xadd(nn, _xd(G[i, _W], G[k, _W], w), w), npj, w)
    return _xsign(_xsub(left, right, w))


@njit(cache=True, _nrt=False)
def line_inside(G, counters, i, k, j):
    """Whether the bisector line of i and k lies where i has no more power than j (for j
    collinear with i and k the two bisector lines are parallel: all of it, or none).

    At the foot f = p_i + n (w_i - w_k + |n|^2) / (2 |n|^2) of the line (n = p_k - p_i,
    P = p_j - p_i), |n|^2 (l_j(f) - l_i(f)) = E = |n|^2 (|P|^2 + w_i - w_j) - (w_i - w_k + |n|^2) n.P:
    an interval filter, then exact expansions."""
    counters[FILTERED] += 1
    nxl, nxh, nyl, nyh = _delta(G, i, k)
    pxl, pxh, pyl, pyh = _delta(G, i, j)
    nnl, nnh = _norm2(nxl, nxh, nyl, nyh)
    ppl, pph = _norm2(pxl, pxh, pyl, pyh)
    dl, dh = _ds(G, j, i)                                  # w_i - w_j
    ppl, pph = iv.add(ppl, pph, dl, dh)
    leftl, lefth = iv.mul(nnl, nnh, ppl, pph)
    t1l, t1h = iv.mul(nxl, nxh, pxl, pxh)
    t2l, t2h = iv.mul(nyl, nyh, pyl, pyh)
    npl, nph = iv.add(t1l, t1h, t2l, t2h)
    dl, dh = _ds(G, k, i)                                  # w_i - w_k
    t1l, t1h = iv.add(nnl, nnh, dl, dh)
    rightl, righth = iv.mul(t1l, t1h, npl, nph)
    el, eh = iv.sub(leftl, lefth, rightl, righth)
    s = iv.sign(el, eh)
    if s == UNDECIDED:
        counters[EXACT] += 1
        s = _line_inside_exact(G, i, k, j)
    return s >= 0
