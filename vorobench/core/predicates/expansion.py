"""Floating-point expansion arithmetic (Shewchuk): the error-free transformations, expansions
as (array, length) in the caller's buffers, the same on array slices drawn from one scratch
pool per evaluation (the sweep's and the constructions' style), and double-double values with
certified error bounds. Every exact predicate is built from these."""

from __future__ import annotations

import math

import numpy as np
from llvmlite import binding as llvm_binding
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

__all__ = ["EPSILON", "SPLITTER", "ORIENT2D_EXPANSION_MAX", "INCIRCLE_EXPANSION_MAX", "two_sum", "fast_two_sum", "two_diff", "split", "two_product", "grow_expansion", "expansion_sum", "expansion_diff", "scale_expansion", "expansion_product", "expansion_negate", "compress_expansion", "expansion_sign", "estimate", "float_expansion", "diff_expansion", "product_expansion", "det2_expansion", "diff_product_expansion"]


#: Half an ulp of 1.0: the unit roundoff of float64.
EPSILON = 2.0**-53


#: Veltkamp splitter 2**ceil(53/2) + 1 used by :func:`split`.
SPLITTER = 2.0**27 + 1.0


#: Capacity needed for the output of :func:`orient2d_expansion`.
ORIENT2D_EXPANSION_MAX = 12


#: Capacity needed for the output of :func:`incircle_expansion`.
INCIRCLE_EXPANSION_MAX = 384


_UNDECIDED = 2  # internal: returned by the float filters when they cannot decide


_F64 = types.float64


_I64 = types.int64


_COUNTERS = types.int64[:]


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


@intrinsic
def fused_multiply_add(typingctx, a, b, c):
    """``a * b + c`` rounded once (LLVM's ``llvm.fma``; numba has no ``math.fma`` before
    Python 3.13). Exact fused arithmetic on every CPU: one instruction where the CPU has FMA,
    a library call where it has not."""
    sig = types.float64(a, b, c)

    def codegen(context, builder, signature, args):
        values = [context.cast(builder, v, t, types.float64) for v, t in zip(args, signature.args)]
        double = ir.DoubleType()
        fma = cgutils.get_or_insert_function(builder.module, ir.FunctionType(double, [double] * 3), "llvm.fma.f64")
        return builder.call(fma, values)

    return sig, codegen


def _host_has_fma() -> bool:
    """Whether this machine's CPU has fused multiply-add. Either way of :func:`two_product`
    is exact, so the choice only costs speed: on a host without it ``llvm.fma`` is a library
    call; compiled for another target (``NUMBA_CPU_NAME``), the fused form stays exact too.
    numba's cache keys carry the CPU's features, so a cache never mixes the two."""
    features = llvm_binding.get_host_cpu_features()
    return bool(features.get("fma", False))


#: :func:`two_product` takes the error from one fused multiply-add (2 operations instead of
#: the split's 17) where the CPU has the instruction.
HAS_FMA = _host_has_fma()


@njit(cache=True)
def _two_product_split(a, b):
    # Dekker/Veltkamp: exact unless a*b overflows, |a| or |b| >= 2**996, or the error is
    # below the subnormal range
    x = a * b
    ahi, alo = split(a)
    bhi, blo = split(b)
    err1 = x - ahi * bhi
    err2 = err1 - alo * bhi
    err3 = err2 - ahi * blo
    return x, alo * blo - err3


@njit(cache=True)
def _two_product_fused(a, b):
    # the rounding error of a*b is itself a float (barring underflow), and fma(a, b, -x)
    # computes it with one rounding, so exactly
    x = a * b
    return x, fused_multiply_add(a, b, -x)


@njit(cache=True)
def two_product(a, b):
    """Return ``(x, y)`` with ``x = fl(a * b)`` and ``x + y == a * b`` exactly.

    Exact unless ``a*b`` overflows or the rounding error is below the subnormal range
    (i.e. needs ``ulp(a) * ulp(b) >= 2**-1074``). One fused multiply-add where the CPU has it
    (:data:`HAS_FMA`, a constant when numba compiles this), else Dekker's split.
    """
    if HAS_FMA:
        return _two_product_fused(a, b)
    return _two_product_split(a, b)


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


@njit(cache=True, inline='always')
def _ddv_mul(ah, al, ea, bh, bl, eb):
    # product of two double-double values with error bounds, its bound propagated
    ph, pl = _dd_mul(ah, al, bh, bl)
    return ph, pl, abs(ah) * eb + abs(bh) * ea + ea * eb + 8.0 * _U2 * abs(ph)


@njit(cache=True, inline='always')
def _ddv_add(ah, al, ea, bh, bl, eb):
    sh, sl = _dd_add(ah, al, bh, bl)
    return sh, sl, ea + eb + 4.0 * _U2 * (abs(ah) + abs(bh))
