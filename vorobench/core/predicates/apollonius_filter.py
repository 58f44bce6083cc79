"""Float filters for the sweep of disks: the decisions of :mod:`.apollonius` in interval
arithmetic (:mod:`.interval`), compiled, each answering UNDECIDED where its enclosure cannot
tell, and the caller then asks the exact stage.

They follow the exact predicates step by step (same formulas, same branches), so a decided
answer is the exact one: every interval encloses the exact value of the quantity the exact
stage computes from the same disks. Disks are given as floats (x, y, r), read exactly.
"""

from __future__ import annotations

from numba import njit

from vorobench.core.predicates import interval as iv
from vorobench.core.predicates.interval import UNDECIDED

__all__ = ["UNDECIDED", "NO_VERTEX", "VERTEX", "breakpoint_side", "vertex_box", "meets"]

#: :func:`vertex_box` statuses (besides UNDECIDED): no vertex for the ordered triple, or one.
NO_VERTEX = 0
VERTEX = 1


@njit(cache=True)
def breakpoint_side(x, lo_L, hi_L, ax, ay, ar, bx, by, br):
    """Sign of x - (the breakpoint of left arc a, right arc b) when the sweep is at L, given by
    its enclosure [lo_L, hi_L] (a site's time y - r); UNDECIDED when the filter cannot tell.

    As the exact stage (``apollonius_sweep.side``): with h_m = L + r_m - y_m, the heights of
    the parabolas' foci below their directrices, g(x) = 2 h_a h_b (y_a(x) - y_b(x)) =
    (alpha x + beta) x + gamma is positive where a is the higher arc; the breakpoint is the
    crossing where g goes from + to -, the smaller root when a's parabola is the wider
    (alpha > 0), else the larger."""
    ha = iv.add(lo_L, hi_L, *iv.sub(ar, ar, ay, ay))
    hb = iv.add(lo_L, hi_L, *iv.sub(br, br, by, by))
    if iv.sign(*ha) != 1 or iv.sign(*hb) != 1:
        return UNDECIDED                       # a spike (h = 0): the exact stage
    # alpha = h_a - h_b, in which L cancels
    alpha = iv.sub(*iv.sub(ar, ar, ay, ay), *iv.sub(br, br, by, by))
    s_alpha = iv.sign(*alpha)
    if s_alpha == UNDECIDED:
        return UNDECIDED
    beta = iv.mul(2.0, 2.0, *iv.sub(*iv.mul(*hb, ax, ax), *iv.mul(*ha, bx, bx)))
    # (L + r_a + y_a) - (L + r_b + y_b), in which L cancels too
    rise = iv.sub(*iv.add(ar, ar, ay, ay), *iv.add(br, br, by, by))
    gamma = iv.add(*iv.sub(*iv.mul(*iv.mul(*ha, *hb), *rise), *iv.mul(*hb, *iv.sqr(ax, ax))),
                   *iv.mul(*ha, *iv.sqr(bx, bx)))
    g = iv.add(*iv.mul(*iv.add(*iv.mul(*alpha, x, x), *beta), x, x), *gamma)
    apex_side = iv.add(*iv.mul(*alpha, 2.0 * x, 2.0 * x), *beta)
    s_g = iv.sign(*g)
    if s_g == UNDECIDED:
        return UNDECIDED
    s_apex = iv.sign(*apex_side)
    if s_alpha > 0:
        if s_g < 0:
            return 1
        return UNDECIDED if s_apex == UNDECIDED else (-1 if s_apex < 0 else 1)
    if s_g > 0:
        return -1
    return UNDECIDED if s_apex == UNDECIDED else (-1 if s_apex > 0 else 1)


@njit(cache=True)
def _turns_positive(ux, uy, ajx, ajy, akx, aky):
    """How many of the three consecutive turns of the centres (0, a_j, a_k), seen from u, are
    counter-clockwise; -1 when a turn's sign is not decided (the exact stage then also looks
    at the dot product)."""
    cxs = ((0.0, 0.0), ajx, akx)
    cys = ((0.0, 0.0), ajy, aky)
    positive = 0
    for m in range(3):
        p = (m + 1) % 3
        dx1 = iv.sub(*cxs[m], *ux)
        dy1 = iv.sub(*cys[m], *uy)
        dx2 = iv.sub(*cxs[p], *ux)
        dy2 = iv.sub(*cys[p], *uy)
        s = iv.sign(*iv.sub(*iv.mul(*dx1, *dy2), *iv.mul(*dy1, *dx2)))
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
    ajx = iv.sub(bx, bx, ax, ax)
    ajy = iv.sub(by, by, ay, ay)
    sj = iv.sub(br, br, ar, ar)
    akx = iv.sub(cx, cx, ax, ax)
    aky = iv.sub(cy, cy, ay, ay)
    sk = iv.sub(cr, cr, ar, ar)
    h1 = iv.half(*iv.sub(*iv.add(*iv.sqr(*ajx), *iv.sqr(*ajy)), *iv.sqr(*sj)))
    h2 = iv.half(*iv.sub(*iv.add(*iv.sqr(*akx), *iv.sqr(*aky)), *iv.sqr(*sk)))
    # d = n1 x n2 with n_m = (a_mx, a_my, s_m)
    d0 = iv.sub(*iv.mul(*ajy, *sk), *iv.mul(*sj, *aky))
    d1 = iv.sub(*iv.mul(*sj, *akx), *iv.mul(*ajx, *sk))
    d2 = iv.sub(*iv.mul(*ajx, *aky), *iv.mul(*ajy, *akx))
    dd = iv.add(*iv.add(*iv.sqr(*d0), *iv.sqr(*d1)), *iv.sqr(*d2))
    if iv.sign(*dd) != 1:
        return undecided
    n11 = iv.add(*iv.add(*iv.sqr(*ajx), *iv.sqr(*ajy)), *iv.sqr(*sj))
    n22 = iv.add(*iv.add(*iv.sqr(*akx), *iv.sqr(*aky)), *iv.sqr(*sk))
    n12 = iv.add(*iv.add(*iv.mul(*ajx, *akx), *iv.mul(*ajy, *aky)), *iv.mul(*sj, *sk))
    c1 = iv.div(*iv.sub(*iv.mul(*h1, *n22), *iv.mul(*h2, *n12)), *dd)
    c2 = iv.div(*iv.sub(*iv.mul(*h2, *n11), *iv.mul(*h1, *n12)), *dd)
    x0 = iv.add(*iv.mul(*c1, *ajx), *iv.mul(*c2, *akx))
    y0 = iv.add(*iv.mul(*c1, *ajy), *iv.mul(*c2, *aky))
    z0 = iv.add(*iv.mul(*c1, *sj), *iv.mul(*c2, *sk))
    qa = iv.sub(*iv.add(*iv.sqr(*d0), *iv.sqr(*d1)), *iv.sqr(*d2))
    if iv.sign(*qa) == UNDECIDED:
        return undecided                       # (qa = 0: one root, left to the exact stage)
    qb = iv.mul(2.0, 2.0, *iv.sub(*iv.add(*iv.mul(*x0, *d0), *iv.mul(*y0, *d1)), *iv.mul(*z0, *d2)))
    qc = iv.sub(*iv.add(*iv.sqr(*x0), *iv.sqr(*y0)), *iv.sqr(*z0))
    disc = iv.sub(*iv.sqr(*qb), *iv.mul(4.0, 4.0, *iv.mul(*qa, *qc)))
    s_disc = iv.sign(*disc)
    if s_disc == -1:
        return none
    if s_disc == UNDECIDED:
        return undecided                       # (a double root: the exact stage)
    root = iv.sqrt(*disc)
    two_qa = iv.mul(2.0, 2.0, *qa)
    found = 0
    out = none
    minus_qb = (-qb[1], -qb[0])
    for plus in (True, False):
        # t = (-qb +- sqrt(disc)) / (2 qa)
        if plus:
            num = iv.add(*minus_qb, *root)
        else:
            num = iv.sub(*minus_qb, *root)
        t = iv.div(*num, *two_qa)
        ux = iv.add(*x0, *iv.mul(*t, *d0))
        uy = iv.add(*y0, *iv.mul(*t, *d1))
        rho = iv.add(*z0, *iv.mul(*t, *d2))
        # the circle touches each disk from outside: R + r_m = rho + s_m >= 0
        outside = 1
        for s in ((0.0, 0.0), sj, sk):
            reach = iv.sign(*iv.add(*rho, *s))
            if reach == -1:
                outside = 0
                break
            if reach == UNDECIDED:
                outside = -1
        if outside == 0:
            continue
        if outside == -1:
            return undecided
        positive = _turns_positive(ux, uy, ajx, ajy, akx, aky)
        if positive < 0:
            return undecided
        if positive >= 2:
            found += 1
            x = iv.add(*ux, ax, ax)
            y = iv.add(*uy, ay, ay)
            top = iv.add(*y, *iv.sub(*rho, ar, ar))          # y + R, with R = rho - r_a
            out = (VERTEX, x[0], x[1], y[0], y[1], top[0], top[1])
    if found > 1:
        return undecided                       # (the exact stage reports it: it cannot happen)
    return out


@njit(cache=True)
def meets(ax, ay, ar, bx, by, br, x_lo, x_hi, top_lo, top_hi):
    """Whether the breakpoint of left arc a and right arc b is at a vertex whose x and circle
    top are enclosed as given, when the sweep reaches that top: 1, 0 or UNDECIDED (exact stage:
    ``apollonius_sweep.meets``). The vertex lies on both parabolas then; the breakpoint is the
    crossing where g goes from + to -: slope 2 alpha x + 2 (h_b a_x - h_a b_x) <= 0."""
    ha = iv.add(top_lo, top_hi, *iv.sub(ar, ar, ay, ay))
    hb = iv.add(top_lo, top_hi, *iv.sub(br, br, by, by))
    if iv.sign(*ha) != 1 or iv.sign(*hb) != 1:
        return UNDECIDED                       # a spike (h = 0) meets every breakpoint: exact
    alpha = iv.sub(*iv.sub(ar, ar, ay, ay), *iv.sub(br, br, by, by))
    slope = iv.mul(2.0, 2.0, *iv.add(*iv.mul(*alpha, x_lo, x_hi),
                                     *iv.sub(*iv.mul(*hb, ax, ax), *iv.mul(*ha, bx, bx))))
    if slope[1] <= 0.0:
        return 1
    if slope[0] > 0.0:
        return 0
    return UNDECIDED
