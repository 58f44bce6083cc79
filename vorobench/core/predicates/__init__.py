"""Exact 2-D geometric predicates (orient2d, incircle) and expansion arithmetic, numba-compiled.

Sign conventions
----------------
``orient2d(ax, ay, bx, by, cx, cy)`` is the sign of

    | ax-cx  ay-cy |
    | bx-cx  by-cy |  = (ax-cx)*(by-cy) - (ay-cy)*(bx-cx)

(twice the signed area of triangle abc): +1 if a, b, c are in counter-clockwise
order, -1 if clockwise, 0 if collinear (including coincident points).

``incircle(ax, ay, bx, by, cx, cy, dx, dy)`` is the sign of the lifted determinant

    | ax-dx  ay-dy  (ax-dx)**2 + (ay-dy)**2 |
    | bx-dx  by-dy  (bx-dx)**2 + (by-dy)**2 |
    | cx-dx  cy-dy  (cx-dx)**2 + (cy-dy)**2 |

(equal to the 4x4 determinant with rows ``(px, py, px**2+py**2, 1)`` for
p = a, b, c, d).  When a, b, c are counter-clockwise it is +1 if d lies strictly
inside their circumcircle, -1 if strictly outside and 0 if the four points are
cocircular.  When a, b, c are clockwise every non-zero sign is flipped (+1 means
*outside*).  When a, b, c are collinear the result is the sign of a
degenerate "circle" (a line) test and rarely meaningful; it is still exact.
In general ``incircle(a, b, c, d) * orient2d(a, b, c)`` is +1 for "d inside".

Exactness guarantee and input range
-----------------------------------
Every result is the exact sign of the determinant evaluated in real
arithmetic on the given float64 values (the differences such as ``ax - cx`` are
*not* assumed to be exact: the exact stage expands the determinants in the
original coordinates with error-free transformations).  Exactness is
guaranteed for finite inputs as long as no intermediate product overflows or
underflows, which holds when every coordinate is 0 or has magnitude in

* orient2d: [1e-100, 1e100]  (sufficient: [2**-400, 2**400])
* incircle: [1e-50, 1e50]    (sufficient: [2**-180, 2**180])

e.g. coordinates around 1e9 differing by a single ulp (1.2e-7) are fine.
Outside those ranges the results may be wrong; NaN/inf inputs give
unspecified results.

The project's range lies inside the range of every predicate here (the
narrowest are the sweep's degree-6 circle tops; see "Expansions" below):
every nonzero coordinate of magnitude in [2**-100, 2**100). It is kept in
:mod:`vorobench.core.scaling` (free of numba, so that ``prepare`` can check it),
where it is derived; ``Implementation.run`` scales every input into it by a
power of two (exact), and ``prepare`` refuses inputs that no power of two fits
(magnitudes more than ~2**199 apart). One predicate is scale-free instead:
``circle_events_order_exact`` rescales its own differences, and its degree-20
squaring is exact when their significant bits span at most ~53 binary orders
(20 x 53 < 1074), which the range rule does not guarantee for coordinates of
very different binades; it is the last resort after every filter and exact key.

Evaluation strategy: a floating-point filter with Shewchuk's rigorous a-priori
error bounds decides almost all calls without allocating anything; if it cannot
decide, an exact evaluation with floating-point expansions (Shewchuk, "Adaptive
Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates",
1997) is run.  The expansion arithmetic building blocks are public so that
further exact predicates can be built on them (see ``two_sum`` ... ``estimate``).

Expansions
----------
An *expansion* is a float64 array ``e`` plus a length ``elen``; its value is
the exact (real) sum ``e[0] + ... + e[elen-1]``.  All functions here produce
(and expect) expansions whose components are *strongly nonoverlapping* and
sorted by increasing magnitude, with zero components eliminated (an expansion
of value 0 is ``[0.0]`` with length 1), so the sign of an expansion is the sign
of its last component.  Outputs are written into a caller-supplied array ``h``
(which must be large enough: see each function) and the new length is returned.
Unless a docstring says otherwise, ``h`` must not overlap the inputs.

Each expansion operation is exact provided nothing overflows and every
``two_product`` error term is representable (``ulp(a) * ulp(b) >= 2**-1074``);
for a polynomial of degree k in coordinates that are 0 or of magnitude in
[2**-m, 2**M], k * (m + 52) <= 1074 and k * M < ~1000 suffice.

The counting variants count calls and exact fallbacks into an int64 array,
indexed by ORIENT_CALLS, ORIENT_EXACT, INCIRCLE_CALLS, INCIRCLE_EXACT.

Compilation: the scalar predicates (``orient2d``, ``incircle``, their
``_counted`` and ``_fast`` siblings) have explicit float64 signatures, so they
are compiled (or loaded from numba's on-disk cache) when this module is
imported, and integer arguments are converted to float64.  The expansion
functions are compiled lazily for the array types they are called with.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, types

__all__ = [
    # constants
    "EPSILON",
    "SPLITTER",
    "CCW_ERRBOUND_A",
    "ICC_ERRBOUND_A",
    "ORIENT_CALLS",
    "ORIENT_EXACT",
    "INCIRCLE_CALLS",
    "INCIRCLE_EXACT",
    "ORIENT2D_EXPANSION_MAX",
    "INCIRCLE_EXPANSION_MAX",
    # error-free transformations
    "two_sum",
    "fast_two_sum",
    "two_diff",
    "split",
    "two_product",
    # expansion arithmetic
    "grow_expansion",
    "expansion_sum",
    "expansion_diff",
    "scale_expansion",
    "expansion_product",
    "expansion_negate",
    "compress_expansion",
    "expansion_sign",
    "estimate",
    "float_expansion",
    "diff_expansion",
    "product_expansion",
    "det2_expansion",
    "diff_product_expansion",
    "orient2d_expansion",
    "incircle_expansion",
    # predicates
    "orient2d",
    "orient2d_counted",
    "orient2d_fast",
    "incircle",
    "incircle_counted",
    "incircle_fast",
    "orient2d_many",
    "incircle_many",
]

# --------------------------------------------------------------------------
# Constants (Shewchuk's exactinit(), derived for IEEE-754 binary64 with
# round-to-nearest-even).
# --------------------------------------------------------------------------

#: Half an ulp of 1.0: the unit roundoff of float64.
EPSILON = 2.0**-53
#: Veltkamp splitter 2**ceil(53/2) + 1 used by :func:`split`.
SPLITTER = 2.0**27 + 1.0
#: Relative error bound of the orient2d float filter (Shewchuk's ccwerrboundA).
CCW_ERRBOUND_A = (3.0 + 16.0 * EPSILON) * EPSILON
#: Relative error bound of the incircle float filter (Shewchuk's iccerrboundA).
ICC_ERRBOUND_A = (10.0 + 96.0 * EPSILON) * EPSILON

#: Indices into the counters array of the ``*_counted`` predicates.
ORIENT_CALLS = 0
ORIENT_EXACT = 1
INCIRCLE_CALLS = 2
INCIRCLE_EXACT = 3

#: Capacity needed for the output of :func:`orient2d_expansion`.
ORIENT2D_EXPANSION_MAX = 12
#: Capacity needed for the output of :func:`incircle_expansion`.
INCIRCLE_EXPANSION_MAX = 384

_UNDECIDED = 2  # internal: returned by the float filters when they cannot decide

_F64 = types.float64
_I64 = types.int64
_COUNTERS = types.int64[:]


# --------------------------------------------------------------------------
# Error-free transformations
# --------------------------------------------------------------------------


@njit(cache=True)
def two_sum(a, b):
    """Return ``(x, y)`` with ``x = fl(a + b)`` and ``x + y == a + b`` exactly (Knuth)."""
    x = a + b
    bvirt = x - a
    avirt = x - bvirt
    bround = b - bvirt
    around = a - avirt
    return x, around + bround


@njit(cache=True)
def fast_two_sum(a, b):
    """Return ``(x, y)`` with ``x = fl(a + b)``, ``x + y == a + b``; requires ``|a| >= |b|`` (or a == 0)."""
    x = a + b
    bvirt = x - a
    return x, b - bvirt


@njit(cache=True)
def two_diff(a, b):
    """Return ``(x, y)`` with ``x = fl(a - b)`` and ``x + y == a - b`` exactly."""
    x = a - b
    bvirt = a - x
    avirt = x + bvirt
    bround = bvirt - b
    around = a - avirt
    return x, around + bround


@njit(cache=True)
def split(a):
    """Veltkamp split: return ``(hi, lo)`` with ``hi + lo == a``, each with at most 26 significant bits.

    Requires ``|a| < 2**996`` (no overflow of ``SPLITTER * a``).
    """
    c = SPLITTER * a
    abig = c - a
    ahi = c - abig
    return ahi, a - ahi


@njit(cache=True)
def two_product(a, b):
    """Return ``(x, y)`` with ``x = fl(a * b)`` and ``x + y == a * b`` exactly (Dekker/Veltkamp).

    Exact unless ``a*b`` overflows or the rounding error is below the subnormal
    range (i.e. needs ``ulp(a) * ulp(b) >= 2**-1074``).
    (``math.fma`` is not available in numba for Python < 3.13, hence the split.)
    """
    x = a * b
    ahi, alo = split(a)
    bhi, blo = split(b)
    err1 = x - ahi * bhi
    err2 = err1 - alo * bhi
    err3 = err2 - ahi * blo
    return x, alo * blo - err3


# --------------------------------------------------------------------------
# Expansion arithmetic
# --------------------------------------------------------------------------


@njit(cache=True)
def grow_expansion(e, elen, b, h):
    """``h = e + b`` (expansion plus a float), zero-eliminating; returns the length (<= elen + 1).

    ``h`` may be the same array as ``e`` (in-place growth is safe).
    """
    q = b
    hindex = 0
    for i in range(elen):
        q, hh = two_sum(q, e[i])
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
    if q != 0.0 or hindex == 0:
        h[hindex] = q
        hindex += 1
    return hindex


@njit(cache=True)
def _expansion_sum_signed(e, elen, f, flen, fsign, h):
    # Shewchuk's fast_expansion_sum_zeroelim on e + fsign*f (fsign = +-1, exact).
    # Two_Sum is used throughout (it equals Fast_Two_Sum wherever the latter's
    # precondition holds and is exact regardless), and reads never pass the end.
    eindex = 0
    findex = 0
    hindex = 0
    enow = e[0]
    fnow = fsign * f[0]
    if abs(enow) < abs(fnow):
        q = enow
        eindex = 1
        if eindex < elen:
            enow = e[eindex]
    else:
        q = fnow
        findex = 1
        if findex < flen:
            fnow = fsign * f[findex]
    while eindex < elen and findex < flen:
        if abs(enow) < abs(fnow):
            q, hh = two_sum(q, enow)
            eindex += 1
            if eindex < elen:
                enow = e[eindex]
        else:
            q, hh = two_sum(q, fnow)
            findex += 1
            if findex < flen:
                fnow = fsign * f[findex]
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
    while eindex < elen:
        q, hh = two_sum(q, e[eindex])
        eindex += 1
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
    while findex < flen:
        q, hh = two_sum(q, fsign * f[findex])
        findex += 1
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
    if q != 0.0 or hindex == 0:
        h[hindex] = q
        hindex += 1
    return hindex


@njit(cache=True)
def expansion_sum(e, elen, f, flen, h):
    """``h = e + f`` (fast_expansion_sum_zeroelim); returns the length (<= elen + flen).

    Inputs must be strongly nonoverlapping, increasing-magnitude expansions
    (all outputs of this module are); the output is too.
    """
    return _expansion_sum_signed(e, elen, f, flen, 1.0, h)


@njit(cache=True)
def expansion_diff(e, elen, f, flen, h):
    """``h = e - f``; returns the length (<= elen + flen).  Same rules as :func:`expansion_sum`."""
    return _expansion_sum_signed(e, elen, f, flen, -1.0, h)


@njit(cache=True)
def scale_expansion(e, elen, b, h):
    """``h = e * b`` for a float ``b`` (scale_expansion_zeroelim); returns the length (<= 2 * elen)."""
    q, hh = two_product(e[0], b)
    hindex = 0
    if hh != 0.0:
        h[hindex] = hh
        hindex += 1
    for i in range(1, elen):
        p1, p0 = two_product(e[i], b)
        s, hh = two_sum(q, p0)
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
        q, hh = two_sum(p1, s)
        if hh != 0.0:
            h[hindex] = hh
            hindex += 1
    if q != 0.0 or hindex == 0:
        h[hindex] = q
        hindex += 1
    return hindex


@njit(cache=True)
def _expansion_product_ordered(e, elen, f, flen, h):
    # h = e * f, iterating over the components of f (the shorter factor).
    cap = 2 * elen * flen
    t = np.empty(2 * elen)
    acc = np.empty(cap)
    nxt = np.empty(cap)
    alen = scale_expansion(e, elen, f[0], acc)
    for i in range(1, flen):
        tlen = scale_expansion(e, elen, f[i], t)
        alen = expansion_sum(acc, alen, t, tlen, nxt)
        acc, nxt = nxt, acc
    for i in range(alen):
        h[i] = acc[i]
    return alen


@njit(cache=True)
def expansion_product(e, elen, f, flen, h):
    """``h = e * f`` (product of two expansions); returns the length (<= 2 * elen * flen).

    Computed as the sum, over the components of the shorter factor, of the
    longer factor scaled by that component.  Allocates scratch arrays
    (O(elen * flen) floats); ``h`` may not overlap ``e`` or ``f``.
    """
    if flen > elen:
        return _expansion_product_ordered(f, flen, e, elen, h)
    return _expansion_product_ordered(e, elen, f, flen, h)


@njit(cache=True)
def expansion_negate(e, elen, h):
    """``h = -e``; returns elen.  ``h`` may be ``e``."""
    for i in range(elen):
        h[i] = -e[i]
    return elen


@njit(cache=True)
def compress_expansion(e, elen, h):
    """Shewchuk's compress: same value, usually far fewer components; returns the new length.

    The largest output component approximates the value to within an ulp.
    ``h`` may be ``e``.  Useful to keep repeated products short.
    """
    bottom = elen - 1
    q = e[bottom]
    for i in range(elen - 2, -1, -1):
        qnew, qq = two_sum(q, e[i])
        if qq != 0.0:
            h[bottom] = qnew
            bottom -= 1
            q = qq
        else:
            q = qnew
    top = 0
    for i in range(bottom + 1, elen):
        qnew, qq = two_sum(h[i], q)
        if qq != 0.0:
            h[top] = qq
            top += 1
        q = qnew
    h[top] = q
    return top + 1


@njit(cache=True)
def expansion_sign(e, elen):
    """Exact sign (-1, 0, +1) of the expansion's value: sign of its most significant non-zero component."""
    for i in range(elen - 1, -1, -1):
        if e[i] > 0.0:
            return 1
        if e[i] < 0.0:
            return -1
    return 0


@njit(cache=True)
def estimate(e, elen):
    """Float approximation of the expansion's value (sum of the components, smallest first)."""
    s = 0.0
    for i in range(elen):
        s += e[i]
    return s


@njit(cache=True)
def float_expansion(a, h):
    """Write the float ``a`` as a one-component expansion into ``h``; returns 1."""
    h[0] = a
    return 1


@njit(cache=True)
def diff_expansion(a, b, h):
    """Exact ``a - b`` of two floats as an expansion in ``h`` (<= 2 components); returns the length."""
    x, y = two_diff(a, b)
    if y != 0.0:
        h[0] = y
        h[1] = x
        return 2
    h[0] = x
    return 1


@njit(cache=True)
def product_expansion(a, b, h):
    """Exact ``a * b`` of two floats as an expansion in ``h`` (<= 2 components); returns the length."""
    x, y = two_product(a, b)
    if y != 0.0:
        h[0] = y
        h[1] = x
        return 2
    h[0] = x
    return 1


@njit(cache=True)
def det2_expansion(a, b, c, d, h):
    """Exact ``a*b - c*d`` as an expansion in ``h`` (<= 4 components); returns the length.  No allocation."""
    n = product_expansion(a, b, h)
    x, y = two_product(c, d)
    n = grow_expansion(h, n, -y, h)
    return grow_expansion(h, n, -x, h)


@njit(cache=True)
def diff_product_expansion(a, b, c, d, h):
    """Exact ``(a - b) * (c - d)`` as an expansion in ``h`` (<= 8 components); returns the length.

    Neither difference is assumed exact.  No allocation.
    """
    d1, t1 = two_diff(a, b)
    d2, t2 = two_diff(c, d)
    n = product_expansion(t1, t2, h)
    x, y = two_product(t1, d2)
    n = grow_expansion(h, n, y, h)
    n = grow_expansion(h, n, x, h)
    x, y = two_product(d1, t2)
    n = grow_expansion(h, n, y, h)
    n = grow_expansion(h, n, x, h)
    x, y = two_product(d1, d2)
    n = grow_expansion(h, n, y, h)
    return grow_expansion(h, n, x, h)


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


# --------------------------------------------------------------------------
# Predicates
# --------------------------------------------------------------------------


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


@njit(cache=True)
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


# --------------------------------------------------------------------------
# Vectorised versions
# --------------------------------------------------------------------------


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


# ==========================================================================
# Sweep-line predicates (Fortune's algorithm, impls/fortune)
# --------------------------------------------------------------------------
# The sweep line y = L moves upward; processed sites lie on or below it.  Site
# p's parabola (points equidistant from p and the sweep line) has height
# L - d_p**2 / (2 h_p) above abscissa x, where d_p = |(x, L) - p| and
# h_p = L - p_y, so at a site event (L = s_y) the arc above s belongs to the
# p minimising d_p**2 / h_p.  A circle event of consecutive arcs (a, b, c)
# happens when L reaches the top of their circumcircle, c_y + r.  Each
# predicate below has a float filter with an a-priori error bound and an exact
# fallback on expansions; the exact path allocates, the filters do not.
# ==========================================================================

__all__ += [
    "UNDECIDED",
    "BREAKPOINT_ERRBOUND",
    "breakpoint_side_filter",
    "breakpoint_side_exact",
    "breakpoint_side",
    "circle_top",
    "circle_top_relative",
    "circle_top_to_y",
    "tops_order_filter",
    "circle_exact_key",
    "circle_event_key",
    "circle_event_top",
    "KEY_FOUND",
    "KEY_ABSENT",
    "KEY_NOT_SOUGHT",
    "tops_dd_order",
    "circumcentre_accurate",
    "circumcentre_offsets_dd",
    "tops_key_order",
    "circle_event_vs_site_exact",
    "circle_event_vs_site",
    "circle_events_order_exact",
    "circle_events_order",
]

#: Returned by the ``*_filter`` functions of this section when the float evaluation cannot decide.
UNDECIDED = _UNDECIDED
#: Relative error bound of the float evaluation of the breakpoint polynomial (7 roundings
#: on the longest path, see :func:`breakpoint_side_filter`), rounded up.
BREAKPOINT_ERRBOUND = (8.0 + 64.0 * EPSILON) * EPSILON
# Safety factor applied to the running error bound of circle_top (covers the O(eps**2)
# terms dropped in its derivation and the rounding of the bound itself).
_CIRCLE_TOP_SAFETY = 2.0


#: Floats in the scratch pool of one exact evaluation (16 KiB: one allocation per exact
#: predicate call instead of one per arithmetic step; larger needs fall back to allocation).
_POOL_SIZE = 2048


@njit(cache=True)
def _new_pool():
    # w[0] holds the cursor (the next free index, as a float: exact below 2**53)
    w = np.empty(_POOL_SIZE)
    w[0] = 1.0
    return w


@njit(cache=True)
def _take(w, k):
    # k floats of scratch: from the pool while it lasts, else freshly allocated
    c = int(w[0])
    if c + k <= w.shape[0]:
        w[0] = c + k
        return w[c:c + k]
    return np.empty(k)


@njit(cache=True)
def _xd(a, b, w):
    # exact a - b of two floats as a (<= 2 component) expansion array
    h = _take(w, 2)
    n = diff_expansion(a, b, h)
    return h[:n]


@njit(cache=True)
def _xmul(e, f, w):
    # exact product of two expansion arrays, compressed: the longer one scaled by each
    # component of the shorter, accumulated
    if e.shape[0] < f.shape[0]:
        e, f = f, e
    m = e.shape[0]
    acc = _take(w, 2 * m * f.shape[0])
    nxt = _take(w, 2 * m * f.shape[0])
    t = _take(w, 2 * m)
    alen = scale_expansion(e, m, f[0], acc)
    for i in range(1, f.shape[0]):
        tlen = scale_expansion(e, m, f[i], t)
        alen = expansion_sum(acc, alen, t, tlen, nxt)
        acc, nxt = nxt, acc
    alen = compress_expansion(acc, alen, acc)
    return acc[:alen]


@njit(cache=True)
def _xadd(e, f, w):
    h = _take(w, e.shape[0] + f.shape[0])
    n = expansion_sum(e, e.shape[0], f, f.shape[0], h)
    n = compress_expansion(h, n, h)
    return h[:n]


@njit(cache=True)
def _xsub(e, f, w):
    h = _take(w, e.shape[0] + f.shape[0])
    n = expansion_diff(e, e.shape[0], f, f.shape[0], h)
    n = compress_expansion(h, n, h)
    return h[:n]


@njit(cache=True)
def _xscale(e, b, w):
    h = _take(w, 2 * e.shape[0])
    n = scale_expansion(e, e.shape[0], b, h)
    n = compress_expansion(h, n, h)
    return h[:n]


@njit(cache=True)
def _xscaled(e, scale):
    # e times a power of two, in place (exact while no component leaves the normal range)
    for i in range(e.shape[0]):
        e[i] *= scale
    return e


@njit(cache=True)
def _xsign(e):
    return expansion_sign(e, e.shape[0])


@njit(cache=True)
def _xneg(e, w):
    h = _take(w, e.shape[0])
    expansion_negate(e, e.shape[0], h)
    return h


# ---------------------------------------------------------------- breakpoints


@njit(cache=True)
def _midpoint_side(px, qx, sx):
    # sign of 2 sx - (px + qx), exact: (px + qx) as a two-term expansion, minus 2 sx
    # (2 sx is exact in the supported range).
    x, y = two_sum(px, qx)
    h = np.empty(3)
    if y != 0.0:
        h[0] = y
        h[1] = x
        n = 2
    else:
        h[0] = x
        n = 1
    m = np.empty(4)
    k = grow_expansion(h, n, -2.0 * sx, m)
    return -expansion_sign(m, k)


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


@njit(cache=True)
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


# ---------------------------------------------------------------- circle events


@njit(cache=True)
def circle_top_relative(ax, ay, bx, by, cx, cy):
    """Float circumcircle of a, b, c relative to a: ``(q, err_q, vx, vy)``.

    ``q`` approximates y_top - a_y, where y_top is the top of the circle (the circle event's
    sweep position), with ``|q - exact| <= err_q`` (a running error bound, times a safety
    factor 2); ``err_q`` is ``inf`` when the float orientation cannot be trusted (nearly
    collinear). ``(vx, vy)`` is the circumcentre, computed relative to a (not exact).
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
        return np.inf, np.inf, vx, vy
    r = np.sqrt(nx * nx + ny * ny)
    err_r = err_nx + err_ny + 2.1 * u * r
    m = (ny if e > 0.0 else -ny) + r
    err_m = err_ny + err_r + u * abs(m)
    q = m / ae
    err_q = (abs(m) * err_e + ae * err_m) / (ae * (ae - err_e)) + u * abs(q)
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
def circumcentre_accurate(ax, ay, bx, by, cx, cy):
    """Circumcentre of non-collinear a, b, c to a few ulps, from exact expansions (the float
    formula of :func:`circle_top_relative` loses everything when a, b, c are nearly collinear)."""
    w = _new_pool()
    e, nys, s, nxs = _circle_parts(ax, ay, bx, by, cx, cy, 1.0, w)
    ee = estimate(e, e.shape[0])
    return ax + estimate(nxs, nxs.shape[0]) / ee, ay + estimate(nys, nys.shape[0]) / ee


@njit(cache=True)
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


@njit(cache=True)
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


# --- double-double values with a certified error bound ------------------------------
# A value is (hi, lo) with hi = fl(hi + lo), plus an absolute error bound err >= |true - (hi + lo)|.
# Each operation below adds its own rounding (relative bounds in units of u**2, u = 2**-53,
# rounded up from the published bounds of the double-word algorithms: Joldes, Muller,
# Popescu, "Tight and rigorous error bounds for basic building blocks of double-word
# arithmetic", 2017) to the propagated error of its inputs; _DD_SAFETY covers the
# rounding of the bounds themselves.

_U2 = EPSILON * EPSILON
_DD_SAFETY = 4.0


@njit(cache=True, inline='always')
def _dd_add(ah, al, bh, bl):
    # (a + b) to ~3 u**2 relative to |a + b|
    sh, sl = two_sum(ah, bh)
    th, tl = two_sum(al, bl)
    vh, vl = fast_two_sum(sh, sl + th)
    return fast_two_sum(vh, tl + vl)


@njit(cache=True, inline='always')
def _dd_mul(ah, al, bh, bl):
    # (a * b) to ~7 u**2 relative (no fma: the cross terms are plain products)
    ph, pl = two_product(ah, bh)
    return fast_two_sum(ph, pl + (ah * bl + al * bh))


@njit(cache=True, inline='always')
def _dd_div(ah, al, bh, bl):
    # (a / b) by two corrections of the float quotient, to ~16 u**2 relative
    q1 = ah / bh
    ph, pl = _dd_mul(bh, bl, q1, 0.0)
    rh, rl = _dd_add(ah, al, -ph, -pl)
    q2 = rh / bh
    ph, pl = _dd_mul(bh, bl, q2, 0.0)
    rh, rl = _dd_add(rh, rl, -ph, -pl)
    qh, ql = fast_two_sum(q1, q2)
    return _dd_add(qh, ql, rh / bh, 0.0)


@njit(cache=True, inline='always')
def _dd_sqrt(ah, al):
    # sqrt(a) for a > 0 by one Newton step from the float root, to ~4 u**2 relative
    x = math.sqrt(ah)
    ph, pl = two_product(x, x)
    return fast_two_sum(x, (((ah - ph) - pl) + al) / (2.0 * x))


@njit(cache=True)
def _dd_of(e, w):
    # an expansion as (hi, lo, err): hi + lo is its value to within err (measured: the exact
    # remainder e - hi - lo is formed and bounded by twice its estimate)
    n = e.shape[0]
    hi = estimate(e, n)
    r = _take(w, n + 2)
    m = grow_expansion(e, n, -hi, r)
    lo = estimate(r, m)
    m = grow_expansion(r, m, -lo, r)
    return hi, lo, 2.0 * abs(estimate(r, m))


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
def _ddv_mul(ah, al, ea, bh, bl, eb):
    # product of two double-double values with error bounds, its bound propagated
    ph, pl = _dd_mul(ah, al, bh, bl)
    return ph, pl, abs(ah) * eb + abs(bh) * ea + ea * eb + 8.0 * _U2 * abs(ph)


@njit(cache=True, inline='always')
def _ddv_add(ah, al, ea, bh, bl, eb):
    sh, sl = _dd_add(ah, al, bh, bl)
    return sh, sl, ea + eb + 4.0 * _U2 * (abs(ah) + abs(bh))


@njit(cache=True)
def _circle_parts_dd(ax, ay, bx, by, cx, cy):
    # (ok, e, nys, s) of _circle_parts in double-double, each as (hi, lo, err) with a
    # propagated absolute error bound; ok False when the sign of the orientation is not
    # certain (nearly collinear: the expansions are needed)
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
    limit = 2.0 ** -70 / _DD_SAFETY
    if not (de < limit * abs(dh) and nxe <= limit * abs(nxh) and nye <= limit * abs(nyh)
            and math.isfinite(dh + nxh + nyh)):
        return False, 0.0, 0.0
    # the centre is a + (nx, ny) / (2 d)
    uxh, uxl = _dd_div(nxh, nxl, 2.0 * dh, 2.0 * dl)
    uyh, uyl = _dd_div(nyh, nyl, 2.0 * dh, 2.0 * dl)
    return True, uxh + uxl, uyh + uyl


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


@njit(cache=True)
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
        ok, cyy, r2, q, err_q, th, tl, terr = circle_event_key(ax, ay, bx, by, cx, cy)
        return KEY_FOUND if ok else KEY_ABSENT, cyy, r2, q, err_q, th, tl, terr
    fine, eh, el, ee, nh, nl, en, sh, sl, es = _circle_parts_dd(ax, ay, bx, by, cx, cy)
    if not fine:
        ok, cyy, r2, q, err_q, th, tl, terr = circle_event_key(ax, ay, bx, by, cx, cy)
        return KEY_FOUND if ok else KEY_ABSENT, cyy, r2, q, err_q, th, tl, terr
    q, err_q, th, tl, terr = _top_from_parts(ay, eh, el, ee, nh, nl, en, sh, sl, es)
    return KEY_NOT_SOUGHT, 0.0, 0.0, q, err_q, th, tl, terr


@njit(cache=True)
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
    w = _new_pool()
    if in_floats:
        eh, el, ee, nh, nl, en, sh, sl, es = ef, 0.0, 0.0, nf, 0.0, 0.0, sf, 0.0, 0.0
        e = nys = s = w[:0]
    else:
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
    if in_floats:
        # c * e == nys and r2 * e**2 == s, each product checked error-free
        pc, pce = two_product(c, ef)
        e2, e2e = two_product(ef, ef)
        pr, pre = two_product(r2, e2)
        keyed = pc == nf and pce == 0.0 and e2e == 0.0 and pr == sf and pre == 0.0
        if not keyed and pc == nf and pce == 0.0 and e2e != 0.0:
            e = w[1:2].copy()                    # e**2 is no float: check with expansions
            e[0] = ef
            s = w[1:2].copy()
            s[0] = sf
            keyed = _xsign(_xsub(_xscale(_xmul(e, e, w), r2, w), s, w)) == 0
        if not keyed:
            return False, 0.0, 0.0, q, err_q, th, tl, terr
        return True, cyy, r2, q, err_q, th, tl, terr
    if _xsign(_xsub(_xscale(e, c, w), nys, w)) != 0:
        return False, 0.0, 0.0, q, err_q, th, tl, terr
    if _xsign(_xsub(_xscale(_xmul(e, e, w), r2, w), s, w)) != 0:
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


@njit(cache=True)
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
