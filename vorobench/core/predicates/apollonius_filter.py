"""Float filters for the sweep of disks: the decisions of :mod:`.apollonius` in floats with a
running error bound (:mod:`.running_error`, about twice as fast as intervals here), compiled,
each answering UNDECIDED where its bound cannot tell, and the caller then asks the exact stage.

They follow the exact predicates step by step (same formulas, same branches), so a decided
answer is the exact one: every bound holds the exact value of the quantity the exact stage
computes from the same disks. Disks are given as floats (x, y, r), read exactly.
"""

from __future__ import annotations

from numba import njit

from vorobench.core.predicates import running_error as re
from vorobench.core.predicates.interval import UNDECIDED

__all__ = ["UNDECIDED", "NO_VERTEX", "VERTEX", "breakpoint_side", "vertex_box", "meets"]

#: :func:`vertex_box` statuses (besides UNDECIDED): no vertex for the ordered triple, or one.
NO_VERTEX = 0
VERTEX = 1


# The running-error operations are inlined by numba ('always'), which refuses calls spelled with
# *args; these plain kernels (inlined later by LLVM) take the filters' unpacked pairs.
@njit(cache=True)
def _add(a, ea, b, eb):
    return re.add(a, ea, b, eb)


@njit(cache=True)
def _sub(a, ea, b, eb):
    return re.sub(a, ea, b, eb)


@njit(cache=True)
def _mul(a, ea, b, eb):
    return re.mul(a, ea, b, eb)


@njit(cache=True)
def _sqr(a, ea):
    return re.sqr(a, ea)


@njit(cache=True)
def _div(a, ea, b, eb):
    return re.div(a, ea, b, eb)


@njit(cache=True)
def _half(a, ea):
    return re.half(a, ea)


@njit(cache=True)
def _sqrt(a, ea):
    return re.sqrt(a, ea)


@njit(cache=True)
def _sign(v, e):
    return re.sign(v, e)


@njit(cache=True)
def _box(v, e):
    return re.box(v, e)


@njit(cache=True)
def _within(lo, hi):
    return re.within(lo, hi)



@njit(cache=True)
def breakpoint_side(x, L, e_L, ax, ay, ar, bx, by, br):
    """Sign of x - (the breakpoint of left arc a, right arc b) when the sweep is at L, known
    within e_L (a site's time y - r); UNDECIDED when the filter cannot tell.

    As the exact stage (``apollonius_sweep.side``): with h_m = L + r_m - y_m, the heights of
    the parabolas' foci below their directrices, g(x) = 2 h_a h_b (y_a(x) - y_b(x)) =
    (alpha x + beta) x + gamma is positive where a is the higher arc; the breakpoint is the
    crossing where g goes from + to -, the smaller root when a's parabola is the wider
    (alpha > 0), else the larger."""
    lift_a = _sub(ar, 0.0, ay, 0.0)
    lift_b = _sub(br, 0.0, by, 0.0)
    ha = _add(L, e_L, *lift_a)
    hb = _add(L, e_L, *lift_b)
    if _sign(*ha) != 1 or _sign(*hb) != 1:
        return UNDECIDED                       # a spike (h = 0): the exact stage
    alpha = _sub(*lift_a, *lift_b)           # h_a - h_b, in which L cancels
    s_alpha = _sign(*alpha)
    if s_alpha == UNDECIDED:
        return UNDECIDED
    beta = _mul(2.0, 0.0, *_sub(*_mul(*hb, ax, 0.0), *_mul(*ha, bx, 0.0)))
    # (L + r_a + y_a) - (L + r_b + y_b), in which L cancels too
    rise = _sub(*_add(ar, 0.0, ay, 0.0), *_add(br, 0.0, by, 0.0))
    gamma = _add(*_sub(*_mul(*_mul(*ha, *hb), *rise), *_mul(*hb, *_sqr(ax, 0.0))),
                   *_mul(*ha, *_sqr(bx, 0.0)))
    g = _add(*_mul(*_add(*_mul(*alpha, x, 0.0), *beta), x, 0.0), *gamma)
    s_g = _sign(*g)
    if s_g == UNDECIDED:
        return UNDECIDED
    if s_alpha > 0 and s_g < 0:
        return 1
    if s_alpha < 0 and s_g > 0:
        return -1
    s_apex = _sign(*_add(*_mul(*alpha, 2.0 * x, 0.0), *beta))
    if s_apex == UNDECIDED:
        return UNDECIDED
    if s_alpha > 0:
        return -1 if s_apex < 0 else 1
    return -1 if s_apex > 0 else 1


@njit(cache=True)
def _turn(x1, e1, y1, f1, x2, e2, y2, f2):
    """Sign of (p1 - u) x (p2 - u), the offsets given: +1, -1 or UNDECIDED."""
    return _sign(*_sub(*_mul(x1, e1, y2, f2), *_mul(y1, f1, x2, e2)))


@njit(cache=True)
def _turns_positive(ux, eux, uy, euy, ajx, ajy, akx, aky):
    """How many of the three consecutive turns of the centres (0, a_j, a_k), seen from u, are
    counter-clockwise; -1 when a turn's sign is not decided (the exact stage then also looks
    at the dot product)."""
    ox, eox = _sub(0.0, 0.0, ux, eux)
    oy, eoy = _sub(0.0, 0.0, uy, euy)
    jx, ejx = _sub(*ajx, ux, eux)
    jy, ejy = _sub(*ajy, uy, euy)
    kx, ekx = _sub(*akx, ux, eux)
    ky, eky = _sub(*aky, uy, euy)
    positive = 0
    for s in (_turn(ox, eox, oy, eoy, jx, ejx, jy, ejy), _turn(jx, ejx, jy, ejy, kx, ekx, ky, eky),
              _turn(kx, ekx, ky, eky, ox, eox, oy, eoy)):
        if s == UNDECIDED:
            return -1
        if s > 0:
            positive += 1
    return positive


@njit(cache=True)
def vertex_box(ax, ay, ar, bx, by, br, cx, cy, cr):
    """The vertex of the diagram of disks a, b, c in that counter-clockwise order (exact stage:
    ``apollonius.vertex``), as (status, x_lo, x_hi, y_lo, y_hi, top_lo, top_hi): status
    NO_VERTEX, VERTEX with enclosures of its centre and of the top of its circle (y + R, the
    circle event's time), or UNDECIDED.

    The derivation is the exact stage's: relative to a's centre, the two planes
    a_m . u + s_m rho = (|a_m|^2 - s_m^2) / 2 meet in a line X0 + t d, which meets the cone
    u_x^2 + u_y^2 = rho^2 at the roots t of qa t^2 + qb t + qc; a root is the vertex when its
    circle touches the three disks from outside and their centres turn counter-clockwise
    around it."""
    undecided = (UNDECIDED, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    none = (NO_VERTEX, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    ajx = _sub(bx, 0.0, ax, 0.0)
    ajy = _sub(by, 0.0, ay, 0.0)
    sj = _sub(br, 0.0, ar, 0.0)
    akx = _sub(cx, 0.0, ax, 0.0)
    aky = _sub(cy, 0.0, ay, 0.0)
    sk = _sub(cr, 0.0, ar, 0.0)
    h1 = _half(*_sub(*_add(*_sqr(*ajx), *_sqr(*ajy)), *_sqr(*sj)))
    h2 = _half(*_sub(*_add(*_sqr(*akx), *_sqr(*aky)), *_sqr(*sk)))
    # d = n1 x n2 with n_m = (a_mx, a_my, s_m)
    d0 = _sub(*_mul(*ajy, *sk), *_mul(*sj, *aky))
    d1 = _sub(*_mul(*sj, *akx), *_mul(*ajx, *sk))
    d2 = _sub(*_mul(*ajx, *aky), *_mul(*ajy, *akx))
    sq0 = _sqr(*d0)
    sq1 = _sqr(*d1)
    sq2 = _sqr(*d2)
    dd = _add(*_add(*sq0, *sq1), *sq2)
    if _sign(*dd) != 1:
        return undecided
    n11 = _add(*_add(*_sqr(*ajx), *_sqr(*ajy)), *_sqr(*sj))
    n22 = _add(*_add(*_sqr(*akx), *_sqr(*aky)), *_sqr(*sk))
    n12 = _add(*_add(*_mul(*ajx, *akx), *_mul(*ajy, *aky)), *_mul(*sj, *sk))
    c1 = _div(*_sub(*_mul(*h1, *n22), *_mul(*h2, *n12)), *dd)
    c2 = _div(*_sub(*_mul(*h2, *n11), *_mul(*h1, *n12)), *dd)
    x0 = _add(*_mul(*c1, *ajx), *_mul(*c2, *akx))
    y0 = _add(*_mul(*c1, *ajy), *_mul(*c2, *aky))
    z0 = _add(*_mul(*c1, *sj), *_mul(*c2, *sk))
    qa = _sub(*_add(*sq0, *sq1), *sq2)
    if _sign(*qa) == UNDECIDED:
        return undecided                       # (qa = 0: one root, left to the exact stage)
    qb = _mul(2.0, 0.0, *_sub(*_add(*_mul(*x0, *d0), *_mul(*y0, *d1)), *_mul(*z0, *d2)))
    qc = _sub(*_add(*_sqr(*x0), *_sqr(*y0)), *_sqr(*z0))
    disc = _sub(*_sqr(*qb), *_mul(4.0, 0.0, *_mul(*qa, *qc)))
    s_disc = _sign(*disc)
    if s_disc == -1:
        return none
    if s_disc == UNDECIDED:
        return undecided                       # (a double root: the exact stage)
    root = _sqrt(*disc)
    two_qa = _mul(2.0, 0.0, *qa)
    found = 0
    out = none
    for plus in (True, False):
        # t = (-qb +- sqrt(disc)) / (2 qa)
        if plus:
            num = _sub(*root, *qb)
        else:
            num = _sub(-qb[0], qb[1], *root)
        t = _div(*num, *two_qa)
        ux = _add(*x0, *_mul(*t, *d0))
        uy = _add(*y0, *_mul(*t, *d1))
        rho = _add(*z0, *_mul(*t, *d2))
        # the circle touches each disk from outside: R + r_m = rho + s_m >= 0
        outside = 1
        for reach in (_sign(*rho), _sign(*_add(*rho, *sj)), _sign(*_add(*rho, *sk))):
            if reach == -1:
                outside = 0
                break
            if reach == UNDECIDED:
                outside = -1
        if outside == 0:
            continue
        if outside == -1:
            return undecided
        positive = _turns_positive(*ux, *uy, ajx, ajy, akx, aky)
        if positive < 0:
            return undecided
        if positive >= 2:
            found += 1
            ok_x, x_lo, x_hi = _box(*_add(*ux, ax, 0.0))
            y = _add(*uy, ay, 0.0)
            ok_y, y_lo, y_hi = _box(*y)
            ok_t, t_lo, t_hi = _box(*_add(*y, *_sub(*rho, ar, 0.0)))   # y + R, with R = rho - r_a
            if not (ok_x and ok_y and ok_t):
                return undecided
            out = (VERTEX, x_lo, x_hi, y_lo, y_hi, t_lo, t_hi)
    if found > 1:
        return undecided                       # (the exact stage reports it: it cannot happen)
    return out


@njit(cache=True)
def meets(ax, ay, ar, bx, by, br, x_lo, x_hi, top_lo, top_hi):
    """Whether the breakpoint of left arc a and right arc b is at a vertex whose x and circle
    top are enclosed as given, when the sweep reaches that top: 1, 0 or UNDECIDED (exact stage:
    ``apollonius_sweep.meets``). The vertex lies on both parabolas then; the breakpoint is the
    crossing where g goes from + to -: slope 2 alpha x + 2 (h_b a_x - h_a b_x) <= 0."""
    top = _within(top_lo, top_hi)
    lift_a = _sub(ar, 0.0, ay, 0.0)
    lift_b = _sub(br, 0.0, by, 0.0)
    ha = _add(*top, *lift_a)
    hb = _add(*top, *lift_b)
    if _sign(*ha) != 1 or _sign(*hb) != 1:
        return UNDECIDED                       # a spike (h = 0) meets every breakpoint: exact
    alpha = _sub(*lift_a, *lift_b)
    slope = _add(*_mul(*alpha, *_within(x_lo, x_hi)), *_sub(*_mul(*hb, ax, 0.0), *_mul(*ha, bx, 0.0)))
    s = _sign(*slope)
    if s == UNDECIDED:
        return UNDECIDED
    return 1 if s < 0 else 0
