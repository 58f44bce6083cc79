"""The sweep line's predicates (Fortune's algorithm): which arc lies above a site (breakpoint
side), the tops of circle events and their exact order, and the keys that settle lattice ties
at once."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from vorobench.core.predicates.constructions import _circle_parts, _circle_parts_dd, _circle_parts_in_floats
from vorobench.core.predicates.expansion import (
    _DD_SAFETY,
    _U2,
    _UNDECIDED,
    EPSILON,
    _dd_add,
    _dd_div,
    _dd_mul,
    _dd_of,
    _dd_sqrt,
    _new_pool,
    _take,
    _xadd,
    _xd,
    _xmul,
    _xscale,
    _xscaled,
    _xsign,
    _xsub,
    two_product,
    two_sum,
)

__all__ = ["KEY_FOUND", "KEY_ABSENT", "KEY_NOT_SOUGHT", "UNDECIDED", "BREAKPOINT_ERRBOUND", "breakpoint_side_filter", "breakpoint_side_exact", "breakpoint_side", "circle_top_relative", "circle_top_to_y", "tops_order_filter", "circle_event_key", "circle_event_top", "tops_dd_order", "tops_key_order", "circle_event_vs_site_exact", "circle_events_order_exact"]


#: Returned by the ``*_filter`` functions of this section when the float evaluation cannot decide.
UNDECIDED = _UNDECIDED


#: Relative error bound of the float evaluation of the breakpoint polynomial (7 roundings
#: on the longest path, see :func:`breakpoint_side_filter`), rounded up.
BREAKPOINT_ERRBOUND = (8.0 + 64.0 * EPSILON) * EPSILON


#: Relative error (of the radius) above which :func:`circle_top_relative` gives no float
#: circumcentre: the sweep then computes it exactly (nearly collinear sites).
CENTRE_TRUST = 1e-12

# Safety factor applied to the running error bound of circle_top (covers the O(eps**2)
# terms dropped in its derivation and the rounding of the bound itself).
_CIRCLE_TOP_SAFETY = 2.0


@njit(cache=True)
def _midpoint_side(px, qx, sx):
    # sign of 2 sx - (px + qx), exact and without allocating: (px + qx) as the two-term
    # expansion (y, x), grown by -2 sx (exact in the supported range) in two error-free
    # sums; the sign of an expansion is that of its largest nonzero component
    x, y = two_sum(px, qx)
    q, low = two_sum(-2.0 * sx, y)
    q, mid = two_sum(q, x)
    top = q if q != 0.0 else (mid if mid != 0.0 else low)
    if top > 0.0:
        return -1
    if top < 0.0:
        return 1
    return 0


@njit(cache=True)
def _breakpoint_poly_exact(px, py, qx, qy, sx, sy):
    # exact sign of f = (sx-px)**2 (sy-qy) - (sx-qx)**2 (sy-py) + (sy-py)(sy-qy)(qy-py)
    w = _new_pool()
    dxp = _xd(sx, px, w)
    dxq = _xd(sx, qx, w)
    hp = _xd(sy, py, w)
    hq = _xd(sy, qy, w)
    dh = _xd(qy, py, w)
    t1 = _xmul(_xmul(dxp, dxp, w), hq, w)
    t2 = _xmul(_xmul(dxq, dxq, w), hp, w)
    t3 = _xmul(_xmul(hp, hq, w), dh, w)
    return _xsign(_xadd(_xsub(t1, t2, w), t3, w))


@njit(cache=True)
def _breakpoint_poly_filter(px, py, qx, qy, sx, sy):
    # float sign of the same f, or UNDECIDED.  Every factor is one rounded difference
    # (relative error <= eps), each product of three adds 2 roundings and each of the
    # two sums one more: |f - fl(f)| <= 7 eps * permanent + O(eps**2).
    dxp = sx - px
    dxq = sx - qx
    hp = sy - py
    hq = sy - qy
    dh = qy - py
    t1 = dxp * dxp * hq
    t2 = dxq * dxq * hp
    t3 = hp * hq * dh
    f = (t1 - t2) + t3
    permanent = abs(t1) + abs(t2) + abs(t3)
    bound = BREAKPOINT_ERRBOUND * permanent
    if f > bound:
        return 1
    if -f > bound:
        return -1
    if permanent == 0.0:
        return 0
    return _UNDECIDED


@njit(cache=True)
def _breakpoint_case(px, py, qx, qy, sx, sy):
    # The parts of the breakpoint test decided by plain comparisons of coordinates
    # (exact).  Returns -1 / 0 / +1 (s left of / on / right of the breakpoint), or 3 if
    # the sign of the breakpoint polynomial f decides it (s left iff f < 0, p higher).
    if py == qy:
        # equal heights: the parabolas are translates meeting once, at x = (px + qx) / 2
        # (also the vertical bisector of two sites on the first sweep position)
        return _midpoint_side(px, qx, sx)
    if py == sy:
        # p lies on the sweep line: its arc is the vertical ray x = px
        return -1 if sx < px else (1 if sx > px else 0)
    if qy == sy:
        return -1 if sx < qx else (1 if sx > qx else 0)
    if py < qy:
        # h_p > h_q: (p, q) is the left intersection; q_x lies between the two roots
        if sx >= qx:
            return 1
        return 3
    # h_p < h_q: (p, q) is the right intersection; p_x lies between the two roots
    if sx <= px:
        return -1
    return 3


@njit(cache=True)
def breakpoint_side_filter(px, py, qx, qy, sx, sy):
    """Float-filtered :func:`breakpoint_side`: the exact sign, or ``UNDECIDED`` (2). Allocates nothing
    unless p and q have equal y (then it is exact and cheap)."""
    c = _breakpoint_case(px, py, qx, qy, sx, sy)
    if c != 3:
        return c
    return _breakpoint_poly_filter(px, py, qx, qy, sx, sy)


@njit(cache=True, _nrt=True)
def breakpoint_side_exact(px, py, qx, qy, sx, sy):
    """:func:`breakpoint_side` evaluated in exact arithmetic only (no filter)."""
    c = _breakpoint_case(px, py, qx, qy, sx, sy)
    if c != 3:
        return c
    return _breakpoint_poly_exact(px, py, qx, qy, sx, sy)


@njit(cache=True)
def breakpoint_side(px, py, qx, qy, sx, sy):
    """Exact side of a new site s relative to the beach-line breakpoint of arcs p (left), q (right).

    Upward sweep at y = s_y, with p_y <= s_y and q_y <= s_y, p != q, and not both on the
    sweep line with equal x. Returns -1 if s_x is left of the breakpoint, +1 if right, 0 if
    s lies exactly below it (a circle event coincides with this site event). Sites on the
    sweep line (h = 0) have a vertical-ray arc, so the breakpoint is at their x.
    """
    s = breakpoint_side_filter(px, py, qx, qy, sx, sy)
    if s != _UNDECIDED:
        return s
    return _breakpoint_poly_exact(px, py, qx, qy, sx, sy)


@njit(cache=True)
def circle_top_relative(ax, ay, bx, by, cx, cy):
    """Float circumcircle of a, b, c relative to a: ``(q, err_q, vx, vy)``.

    ``q`` approximates y_top - a_y, where y_top is the top of the circle (the circle event's
    sweep position), with ``|q - exact| <= err_q`` (a running error bound, times a safety
    factor 2); ``err_q`` is ``inf`` when the float orientation cannot be trusted (nearly
    collinear). ``(vx, vy)`` is the circumcentre, computed relative to a (not exact), or NaN
    when its error bound exceeds :data:`CENTRE_TRUST` of the radius.
    """
    u = EPSILON
    bx_ = bx - ax
    by_ = by - ay
    cx_ = cx - ax
    cy_ = cy - ay
    t1 = bx_ * cy_
    t2 = by_ * cx_
    d = t1 - t2
    err_d = 4.1 * u * (abs(t1) + abs(t2))
    b2 = bx_ * bx_ + by_ * by_
    c2 = cx_ * cx_ + cy_ * cy_
    p1 = cy_ * b2
    p2 = by_ * c2
    nx = p1 - p2
    err_nx = 7.4 * u * (abs(p1) + abs(p2))
    q1 = bx_ * c2
    q2 = cx_ * b2
    ny = q1 - q2
    err_ny = 7.4 * u * (abs(q1) + abs(q2))
    e = 2.0 * d
    vx = ax + nx / e if e != 0.0 else np.inf
    vy = ay + ny / e if e != 0.0 else np.inf
    ae = abs(e)
    err_e = 2.0 * err_d
    if not ae > err_e:
        return np.inf, np.inf, np.nan, np.nan
    r = np.sqrt(nx * nx + ny * ny)
    err_r = err_nx + err_ny + 2.1 * u * r
    # m = |e| (y_top - a_y) = ny_s + r, with ny_s / |e| = c_y - a_y
    ny_s = ny if e > 0.0 else -ny
    if ny_s >= 0.0:
        m = ny_s + r
        err_m = err_ny + err_r + u * abs(m)
    else:
        # centre below a: the sum cancels (to nothing for the huge circles of nearly collinear
        # sites, whose top lies just above them), so take the equal nx^2 / (r - ny_s), in which
        # every term is a few ulps of its own size
        num = nx * nx
        err_num = err_nx * (2.0 * abs(nx) + err_nx) + u * num
        den = r - ny_s
        err_den = err_r + err_ny + u * den
        if not den > err_den:
            return np.inf, np.inf, np.nan, np.nan
        m = num / den
        # |num / den - exact| <= (m err_den + err_num) / (den - err_den), with m for num / den
        # (the 2 u m covers that and the division's rounding); no product of two degree-6
        # terms, which underflowed for differences below 2**-114 and dropped every error
        err_m = (m * err_den + err_num) / (den - err_den) + 2.0 * u * m
    q = m / ae
    # one division for the three bounds below: |t / e - exact| <= (err_t |e| + |t| err_e) / w,
    # w = |e| (|e| - err_e) (its rounding is far inside the safety factor)
    over_w = 1.0 / (ae * (ae - err_e))
    err_q = (abs(m) * err_e + ae * err_m) * over_w + u * abs(q)
    # the centre is a + (nx, ny) / e: trusted when both offsets are within CENTRE_TRUST of the
    # radius r / |e| (else NaN: nearly collinear sites, whose centre needs exact arithmetic);
    # adding a then rounds once, as any float centre must
    err_ox = (err_nx * ae + abs(nx) * err_e) * over_w + u * abs(nx) / ae
    err_oy = (err_ny * ae + abs(ny) * err_e) * over_w + u * abs(ny) / ae
    if not (_CIRCLE_TOP_SAFETY * max(err_ox, err_oy) <= CENTRE_TRUST * (r / ae)):
        vx = np.nan
        vy = np.nan
    return q, _CIRCLE_TOP_SAFETY * err_q, vx, vy


@njit(cache=True)
def circle_top(ax, ay, bx, by, cx, cy):
    """Float circumcircle of a, b, c: ``(y_top, err, vx, vy)``.

    ``y_top`` approximates the top of the circle, with ``|y_top - exact| <= err`` (safety
    factor 2 included; ``inf`` when nearly collinear); ``(vx, vy)`` is the circumcentre.
    Not exact; the comparisons below are.
    """
    q, err_q, vx, vy = circle_top_relative(ax, ay, bx, by, cx, cy)
    y, err = circle_top_to_y(ay, q, err_q)
    return y, err, vx, vy


@njit(cache=True)
def circle_top_to_y(ay, q, err_q):
    """``(y_top, err)`` from the relative top of :func:`circle_top_relative`: y_top = fl(ay + q)
    and its error bound (the rounding of the sum added, with the safety factor)."""
    y = ay + q
    return y, err_q + _CIRCLE_TOP_SAFETY * EPSILON * abs(y)


@njit(cache=True)
def tops_order_filter(ay, q, err_q, dy, r, err_r):
    """Float-filtered sign of (ay + q) - (dy + r) for two tops given relative to their own base
    heights (from :func:`circle_top_relative`; a site is ``r = err_r = 0``), or ``UNDECIDED``.

    Differences of the bases and of the offsets are taken separately, so large common
    coordinates (offsets of 1e9) do not swamp the bound.
    """
    u = EPSILON
    base = ay - dy
    rel = q - r
    d = base + rel
    bound = err_q + err_r + 2.0 * u * (abs(base) + abs(rel))
    if d > bound:
        return 1
    if -d > bound:
        return -1
    return _UNDECIDED


@njit(cache=True, _nrt=True)
def circle_event_vs_site_exact(ax, ay, bx, by, cx, cy, sy):
    """Exact sign of (top of the circumcircle of a, b, c) - sy; a, b, c must not be collinear."""
    w = _new_pool()
    e, nys, s, _ = _circle_parts(ax, ay, bx, by, cx, cy, 1.0, w)
    # y_top - sy = (nys + sqrt(s) - t) / e with t = e (sy - ay); sign(sqrt(s) - d), d = t - nys
    d = _xsub(_xmul(e, _xd(sy, ay, w), w), nys, w)
    if _xsign(d) < 0:
        return 1
    return _xsign(_xsub(s, _xmul(d, d, w), w))


@njit(cache=True)
def circle_event_vs_site(ax, ay, bx, by, cx, cy, sy):
    """Exact sign of (c_y + r) - sy for the circumcircle (centre c, radius r) of non-collinear a, b, c.

    +1: the circle event comes after a site at height sy (upward sweep), 0: at the same time.
    """
    y, err, vx, vy = circle_top(ax, ay, bx, by, cx, cy)
    d = y - sy
    if d > err:
        return 1
    if -d > err:
        return -1
    return circle_event_vs_site_exact(ax, ay, bx, by, cx, cy, sy)


@njit(cache=True)
def _sqrt_sum_sign(p, u, v, w):
    # exact sign of p + sqrt(u) - sqrt(v) for expansions p and u, v >= 0, by squaring with
    # case analysis
    sp = _xsign(p)
    suv = _xsign(_xsub(u, v, w))
    if sp == 0:
        return suv
    if suv == 0 or suv == sp:
        return sp
    p2 = _xmul(p, p, w)
    if sp > 0:
        # p > 0 > sqrt(u) - sqrt(v): compare (p + sqrt u)**2 = p**2 + u + 2 p sqrt(u) with v,
        # i.e. 2 p sqrt(u) (>= 0, = 0 iff u = 0) with -q, q = p**2 + u - v
        q = _xsub(_xadd(p2, u, w), v, w)
        sq = _xsign(q)
        if sq > 0:
            return 1
        if sq == 0:
            return _xsign(u)
        return _xsign(_xsub(_xscale(_xmul(p2, u, w), 4.0, w), _xmul(q, q, w), w))
    # p < 0 < sqrt(u) - sqrt(v): compare u with (|p| + sqrt v)**2 = p**2 + v + 2 |p| sqrt(v),
    # i.e. q = u - v - p**2 with 2 |p| sqrt(v) (>= 0, = 0 iff v = 0)
    q = _xsub(_xsub(u, v, w), p2, w)
    sq = _xsign(q)
    if sq < 0:
        return -1
    if sq == 0:
        return -_xsign(v)
    return _xsign(_xsub(_xmul(q, q, w), _xscale(_xmul(p2, v, w), 4.0, w), w))


@njit(cache=True, _nrt=True)
def circle_events_order_exact(ax, ay, bx, by, cx, cy, dx, dy, ex, ey, fx, fy):
    """Exact sign of y_top(a, b, c) - y_top(d, e, f) (tops of two circumcircles); no filter."""
    w = _new_pool()
    # y1 - y2 is homogeneous of degree 1 in the coordinate differences: scale them all by one
    # power of two so the largest is about 1, which keeps the degree-20 products of the last
    # squaring step inside the normal float range (exactness needs no underflow).
    big = max(abs(bx - ax), abs(by - ay), abs(cx - ax), abs(cy - ay),
              abs(ex - dx), abs(ey - dy), abs(fx - dx), abs(fy - dy), abs(ay - dy))
    scale = 1.0
    if big > 0.0:
        scale = math.ldexp(1.0, -math.frexp(big)[1])
    e1, n1, s1, _ = _circle_parts(ax, ay, bx, by, cx, cy, scale, w)
    e2, n2, s2, _ = _circle_parts(dx, dy, ex, ey, fx, fy, scale, w)
    # e2 e1 (y1 - y2) = p + e2 sqrt(s1) - e1 sqrt(s2)   (all times powers of scale)
    e12 = _xmul(e1, e2, w)
    p = _xadd(_xmul(e12, _xscaled(_xd(ay, dy, w), scale), w), _xsub(_xmul(e2, n1, w), _xmul(e1, n2, w), w), w)
    u = _xmul(_xmul(e2, e2, w), s1, w)
    v = _xmul(_xmul(e1, e1, w), s2, w)
    return _sqrt_sum_sign(p, u, v, w)


@njit(cache=True)
def _top_from_parts(ay, eh, el, ee, nh, nl, en, sh, sl, es):
    # (q, err_q, th, tl, terr): the relative top in floats and the top in double-double, from
    # e, nys, s given as double-double values with error bounds (see circle_event_key)
    r = math.sqrt(sh)
    q = (nh + r) / eh
    u = EPSILON
    err_q = _CIRCLE_TOP_SAFETY * (8.0 * u * (abs(nh) + r) / eh + 4.0 * u * abs(q)
                                  + (en + es / max(r, 1e-300) + abs(q) * ee) / max(eh - ee, 1e-300))
    if not (es < 0.5 * sh and ee < 0.5 * eh):
        return q, math.inf, q + ay, 0.0, math.inf
    rh, rl = _dd_sqrt(sh, sl)
    er = es / math.sqrt(sh - es) + 4.0 * _U2 * abs(rh)
    mh, ml = _dd_add(nh, nl, rh, rl)
    em = en + er + 4.0 * _U2 * (abs(nh) + abs(rh))
    qh, ql = _dd_div(mh, ml, eh, el)
    eq = (em + abs(qh) * ee) / (eh - ee) + 16.0 * _U2 * abs(qh)
    th, tl = _dd_add(ay, 0.0, qh, ql)
    return q, err_q, th, tl, _DD_SAFETY * (eq + 4.0 * _U2 * (abs(ay) + abs(qh)))


#: States of :func:`circle_event_top`: the exact key (cy, r2) was found; there is none; not
#: looked for (the double-double top came from double-double arithmetic, and only
#: :func:`circle_event_key`'s expansions can tell).
KEY_FOUND, KEY_ABSENT, KEY_NOT_SOUGHT = 1, 2, 3


@njit(cache=True, _nrt=True)
def circle_event_top(ax, ay, bx, by, cx, cy):
    """The cheap key of the circle event of non-collinear a, b, c, computed once per event:
    ``(state, cy, r2, q, err_q, th, tl, terr)`` as in :func:`circle_event_key`.

    On lattices with small differences every step is exact in plain floats, and the exact
    key is settled (``KEY_FOUND``/``KEY_ABSENT``). Otherwise the parts are evaluated in
    double-double with propagated error bounds (no expansion is formed) and the state is
    ``KEY_NOT_SOUGHT``: when two such tops cannot be told apart, call
    :func:`circle_event_key`. Nearly collinear triples go to :func:`circle_event_key` at
    once.
    """
    in_floats, ef, nf, sf = _circle_parts_in_floats(ax, ay, bx, by, cx, cy)
    if in_floats:
        ok, cyy, r2, q, err_q, th, tl, terr = _key_in_floats(ay, ef, nf, sf)
        return KEY_FOUND if ok else KEY_ABSENT, cyy, r2, q, err_q, th, tl, terr
    fine, eh, el, ee, nh, nl, en, sh, sl, es = _circle_parts_dd(ax, ay, bx, by, cx, cy)
    if not fine:
        ok, cyy, r2, q, err_q, th, tl, terr = circle_event_key(ax, ay, bx, by, cx, cy)
        return KEY_FOUND if ok else KEY_ABSENT, cyy, r2, q, err_q, th, tl, terr
    q, err_q, th, tl, terr = _top_from_parts(ay, eh, el, ee, nh, nl, en, sh, sl, es)
    return KEY_NOT_SOUGHT, 0.0, 0.0, q, err_q, th, tl, terr


@njit(cache=True, _nrt=True)
def circle_event_key(ax, ay, bx, by, cx, cy):
    """Everything the sweep needs to order the circle event of non-collinear a, b, c, from
    exact arithmetic, computed once per event:
    ``(ok, cy, r2, q, err_q, th, tl, terr)``.

    * ``q`` approximates y_top - a_y to a few ulps, with the bound ``err_q`` (tighter than
      :func:`circle_top_relative` when the float circumcircle is ill-conditioned, e.g.
      nearly collinear sites).
    * ``ok``: the centre's y and the squared radius are floats exactly (integer and dyadic
      lattices, cocircular lattice points: where ties abound); then the top is exactly
      ``cy + sqrt(r2)`` (see :func:`tops_key_order`).
    * ``th + tl`` is the top y_top itself in double-double, within the certified bound
      ``terr`` (about 1e-29 of its terms): two tops further apart than their bounds are
      ordered by :func:`tops_dd_order` without the degree-20 exact comparison.

    On lattices with small differences every step is exact in plain floats and no
    expansion is formed.
    """
    in_floats, ef, nf, sf = _circle_parts_in_floats(ax, ay, bx, by, cx, cy)
    if in_floats:
        return _key_in_floats(ay, ef, nf, sf)
    w = _new_pool()
    e, nys, s, _ = _circle_parts(ax, ay, bx, by, cx, cy, 1.0, w)
    eh, el, ee = _dd_of(e, w)
    nh, nl, en = _dd_of(nys, w)
    sh, sl, es = _dd_of(s, w)
    q, err_q, th, tl, terr = _top_from_parts(ay, eh, el, ee, nh, nl, en, sh, sl, es)
    # exact key: centre y = ay + nys / e and r2 = s / e**2 must be floats; the double-double
    # quotients round to them when they are, and exact tests confirm
    ch, cl = _dd_div(nh, nl, eh, el)
    c = ch + cl
    cyy, low = two_sum(ay, c)
    if low != 0.0:
        return False, 0.0, 0.0, q, err_q, th, tl, terr
    e2h, e2l = _dd_mul(eh, el, eh, el)
    r2h, r2l = _dd_div(sh, sl, e2h, e2l)
    r2 = r2h + r2l
    if _xsign(_xsub(_xscale(e, c, w), nys, w)) != 0:
        return False, 0.0, 0.0, q, err_q, th, tl, terr
    if _xsign(_xsub(_xscale(_xmul(e, e, w), r2, w), s, w)) != 0:
        return False, 0.0, 0.0, q, err_q, th, tl, terr
    return True, cyy, r2, q, err_q, th, tl, terr


@njit(cache=True)
def _key_in_floats(ay, ef, nf, sf):
    """:func:`circle_event_key` when the parts e, nys, s are floats exactly (``ef``, ``nf``,
    ``sf``: lattices with small differences). The quotients and their checks are
    error-free products, so no scratch pool is allocated: on a lattice every circle event
    comes here, 3 million times at 10^6 sites."""
    q, err_q, th, tl, terr = _top_from_parts(ay, ef, 0.0, 0.0, nf, 0.0, 0.0, sf, 0.0, 0.0)
    ch, cl = _dd_div(nf, 0.0, ef, 0.0)
    c = ch + cl
    cyy, low = two_sum(ay, c)
    if low != 0.0:
        return False, 0.0, 0.0, q, err_q, th, tl, terr
    e2h, e2l = _dd_mul(ef, 0.0, ef, 0.0)
    r2h, r2l = _dd_div(sf, 0.0, e2h, e2l)
    r2 = r2h + r2l
    # c * e == nys and r2 * e**2 == s, each product checked error-free
    pc, pce = two_product(c, ef)
    e2, e2e = two_product(ef, ef)
    pr, pre = two_product(r2, e2)
    keyed = pc == nf and pce == 0.0 and e2e == 0.0 and pr == sf and pre == 0.0
    if not keyed and pc == nf and pce == 0.0 and e2e != 0.0:
        w = _new_pool()                          # e**2 is no float: check with expansions
        e = w[1:2].copy()
        e[0] = ef
        s = w[1:2].copy()
        s[0] = sf
        keyed = _xsign(_xsub(_xscale(_xmul(e, e, w), r2, w), s, w)) == 0
    if not keyed:
        return False, 0.0, 0.0, q, err_q, th, tl, terr
    return True, cyy, r2, q, err_q, th, tl, terr


@njit(cache=True)
def circle_exact_key(ax, ay, bx, by, cx, cy):
    """``(ok, cy, r2, q, err_q)`` of :func:`circle_event_key`."""
    ok, cyy, r2, q, err_q, _, _, _ = circle_event_key(ax, ay, bx, by, cx, cy)
    return ok, cyy, r2, q, err_q


@njit(cache=True)
def tops_dd_order(h1, l1, e1, h2, l2, e2):
    """Sign of (h1 + l1) - (h2 + l2) for two double-double tops with error bounds e1, e2 (from
    :func:`circle_event_key`; a site at height y is ``(y, 0, 0)``), or ``UNDECIDED`` when the
    bounds overlap."""
    dh, dl = two_sum(h1, -h2)
    rest = (dl + l1) - l2
    d = dh + rest
    bound = e1 + e2 + 2.0 * EPSILON * (abs(dl) + abs(l1) + abs(l2) + abs(d))
    if d > bound:
        return 1
    if -d > bound:
        return -1
    return _UNDECIDED


@njit(cache=True, _nrt=True)
def tops_key_order(c1, r1, c2, r2):
    """Exact sign of (c1 + sqrt(r1)) - (c2 + sqrt(r2)) for floats r1, r2 >= 0: two circle tops
    from :func:`circle_exact_key`, or a site at height c2 with r2 = 0."""
    if c1 == c2 and r1 == r2:
        return 0
    w = _new_pool()
    p = _xd(c1, c2, w)
    u = _take(w, 1)
    u[0] = r1
    v = _take(w, 1)
    v[0] = r2
    return _sqrt_sum_sign(p, u, v, w)


@njit(cache=True)
def circle_events_order(ax, ay, bx, by, cx, cy, dx, dy, ex, ey, fx, fy):
    """Exact sign of (top of circle abc) - (top of circle def): which circle event comes first.

    -1: circle a, b, c reaches its top earlier (lower y), 0: both at the same sweep position.
    Both triples must be non-collinear.
    """
    y1, err1, vx1, vy1 = circle_top(ax, ay, bx, by, cx, cy)
    y2, err2, vx2, vy2 = circle_top(dx, dy, ex, ey, fx, fy)
    d = y1 - y2
    if d > err1 + err2:
        return 1
    if -d > err1 + err2:
        return -1
    return circle_events_order_exact(ax, ay, bx, by, cx, cy, dx, dy, ex, ey, fx, fy)
