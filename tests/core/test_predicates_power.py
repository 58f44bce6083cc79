"""Power-diagram predicates (power test, power bisector side) against exact rational references.

References, written from the definitions and independent of the module:
* ``Fraction`` evaluation (``Fraction(float)`` is exact) of the 4x4 lifted determinant with rows
  (x, y, x**2 + y**2 - w, 1) and of |p-a|**2 - aw - (|p-b|**2 - bw), for fixtures and samples;
* Python-integer evaluation of the 3x3 form after scaling every coordinate of a batch by one
  2**s and every weight by 2**(2s) (both predicates then scale by a positive power of two),
  for the bulk. The two are cross-checked on samples of every category.
Exactly degenerate inputs are built with integer arithmetic: weights w_p = |p - u|**2 - R put
every weighted point p on the power circle (u, R) (lifted points on one plane); bw = |p-b|**2 -
|p-a|**2 + aw puts p on the power bisector of a and b.
"""

from __future__ import annotations

import itertools
import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from vorobench.core import predicates as P
from vorobench.core.scaling import WEIGHT_MAX_EXPONENT, WEIGHT_MIN_EXPONENT, OutsideExactRange, check_weight_range

RNG_SEED = 20250301
UNDECIDED = 2


# ---------------------------------------------------------------------------
# Exact references
# ---------------------------------------------------------------------------


def sgn(x):
    return (x > 0) - (x < 0)


def det3(r0, r1, r2):
    return (r0[0] * (r1[1] * r2[2] - r1[2] * r2[1])
            - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0])
            + r0[2] * (r1[0] * r2[1] - r1[1] * r2[0]))


def power_det3(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw):
    """3x3 determinant with rows (p-d, |p-d|^2 - (pw-dw)), p = a, b, c (works on object arrays)."""
    rows = []
    for px, py, pw in ((ax, ay, aw), (bx, by, bw), (cx, cy, cw)):
        u = px - dx
        v = py - dy
        rows.append((u, v, u * u + v * v - (pw - dw)))
    return det3(*rows)


def _perm_parity(p):
    p = list(p)
    parity = 1
    for i in range(len(p)):
        while p[i] != i:
            j = p[i]
            p[i], p[j] = p[j], p[i]
            parity = -parity
    return parity


def power_det4(*v):
    """Leibniz sum of the 4x4 determinant with rows (x, y, x^2 + y^2 - w, 1)."""
    rows = [(x, y, x * x + y * y - w, 1) for x, y, w in (v[0:3], v[3:6], v[6:9], v[9:12])]
    total = 0
    for perm in itertools.permutations(range(4)):
        term = _perm_parity(perm)
        for i, j in enumerate(perm):
            term = term * rows[i][j]
        total += term
    return total


def bisector_value(px, py, ax, ay, aw, bx, by, bw):
    return (px - ax) ** 2 + (py - ay) ** 2 - aw - ((px - bx) ** 2 + (py - by) ** 2 - bw)


def frac_power(*v):
    return sgn(power_det4(*(Fraction(float(x)) for x in v)))


def frac_bisector(*v):
    return sgn(bisector_value(*(Fraction(float(x)) for x in v)))


def _mant_exp(x):
    m, e = np.frexp(np.asarray(x, dtype=np.float64))
    mant = (m * 2.0**53).astype(np.int64)   # exact: |m| < 1 has 53 significant bits
    return mant, e.astype(np.int64) - 53


def scaled_ints(coords, weights):
    """Exact Python-int images of the float arrays: ``coords`` times 2**s, ``weights`` times 2**(2s), one s."""
    cm = [_mant_exp(c) for c in coords]
    wm = [_mant_exp(w) for w in weights]
    need = 0
    for mant, exp in cm:
        if (mant != 0).any():
            need = max(need, int(-exp[mant != 0].min()))
    for mant, exp in wm:
        if (mant != 0).any():
            need = max(need, (int(-exp[mant != 0].min()) + 1) // 2)

    def ints(mant, exp, factor):
        shift = np.where(mant != 0, exp + factor * need, 0)
        assert (shift >= 0).all()
        return mant.astype(object) << shift.astype(object)

    return [ints(m, e, 1) for m, e in cm], [ints(m, e, 2) for m, e in wm]


def obj_sign(x):
    return ((x > 0).astype(np.int8) - (x < 0).astype(np.int8)).astype(np.int8)


def ref_power_many(a, b, c, d):
    (ax, ay, bx, by, cx, cy, dx, dy), (aw, bw, cw, dw) = scaled_ints(
        [a[:, 0], a[:, 1], b[:, 0], b[:, 1], c[:, 0], c[:, 1], d[:, 0], d[:, 1]],
        [a[:, 2], b[:, 2], c[:, 2], d[:, 2]])
    return obj_sign(power_det3(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw))


def ref_bisector_many(p, a, b):
    (px, py, ax, ay, bx, by), (aw, bw) = scaled_ints(
        [p[:, 0], p[:, 1], a[:, 0], a[:, 1], b[:, 0], b[:, 1]], [a[:, 2], b[:, 2]])
    return obj_sign(bisector_value(px, py, ax, ay, aw, bx, by, bw))


# ---------------------------------------------------------------------------
# Case generators (seeded)
# ---------------------------------------------------------------------------


def nudge(rng, x, p=0.5):
    """Move each non-zero entry one ulp up or down with probability p (zeros stay: their neighbours are subnormal)."""
    x = np.array(x, dtype=np.float64)
    r = np.where(x == 0.0, 1.0, rng.random(x.shape))
    return np.where(r < p / 2, np.nextafter(x, np.inf), np.where(r < p, np.nextafter(x, -np.inf), x))


def weighted(xy, w):
    return np.column_stack([xy, w]).astype(np.float64)


def magnitudes(rng, k, lo, hi):
    """Random signs times U(0.1, 1) times 10**e, e uniform in [lo, hi] per row: nonzero, inside the range."""
    e = rng.integers(lo, hi + 1, k)
    return rng.choice([-1.0, 1.0], k) * rng.uniform(0.1, 1.0, k) * 10.0**e, e


def lattice_on_power_circle(rng, k, span=60, rspan=3000):
    """Four weighted integer points per row on one integer power circle (centre u, R): exactly coplanar lifts.

    Returns the int64 points (4, k, 2), weights (4, k) and the centres (k, 2).
    """
    pts = rng.integers(-span, span + 1, (4, k, 2))
    u = rng.integers(-span, span + 1, (k, 2))
    r = rng.integers(-rspan, rspan + 1, k)
    w = ((pts - u) ** 2).sum(axis=2) - r
    return pts, w, u


def power_cases():
    rng = np.random.default_rng(RNG_SEED)
    cases = {}
    k = 20000
    cases["uniform"] = [weighted(rng.uniform(-1, 1, (k, 2)), rng.uniform(-0.5, 0.5, k)) for _ in range(4)]
    cases["uniform_positive_weights"] = [weighted(rng.uniform(0, 1, (k, 2)), rng.uniform(0, 0.01, k))
                                         for _ in range(4)]
    wide = []
    for _ in range(4):
        x, e = magnitudes(rng, k, -24, 24)
        y = rng.choice([-1.0, 1.0], k) * rng.uniform(0.1, 1.0, k) * 10.0**e
        w, _ = magnitudes(rng, k, -48, 48)
        wide.append(weighted(np.column_stack([x, y]), w))
    cases["uniform_wide"] = wide

    k2 = 10000
    pts, w, _ = lattice_on_power_circle(rng, k2)
    lattice = [weighted(pts[j].astype(float), w[j].astype(float)) for j in range(4)]
    cases["lattice_coplanar"] = lattice
    # the same translated far away (the power circle moves along, the weights stay)
    offset = rng.choice([2.0**30 + 12345.0, 1e9, -7e8, 3.0 * 2**40], (k2, 1)) + rng.integers(-999, 1000, (k2, 2))
    far = [np.column_stack([p[:, :2] + offset, p[:, 2]]) for p in lattice]
    cases["lattice_coplanar_far"] = far
    # scaled: coordinates by 2**s, weights by 2**(2s) -- still exactly coplanar
    s = rng.integers(-85, 30, (k2, 1)).astype(float)
    cases["lattice_coplanar_scaled"] = [np.column_stack([p[:, :2] * 2.0**s, p[:, 2:] * 4.0**s]) for p in far]
    # one ulp off: coordinates (at 1e9 an ulp is 2**-23) or weights
    cases["lattice_far_nudged"] = [nudge(rng, p, 0.1) for p in far]
    cases["lattice_weights_nudged"] = [np.column_stack([p[:, :2], nudge(rng, p[:, 2], 0.4)]) for p in lattice]
    # weights rounded from a float power circle: near-coplanar, inexact differences
    xy = [rng.uniform(-1, 1, (k2, 2)) for _ in range(4)]
    u = rng.uniform(-1, 1, (k2, 2))
    r = rng.uniform(-1, 1, k2)
    cases["float_near_coplanar"] = [weighted(p, ((p - u) ** 2).sum(axis=1) - r) for p in xy]
    # the same with every row at its own magnitude 2**t (weights at 2**(2t)), far from the origin
    t = rng.integers(-80, 40, (k2, 1)).astype(float)
    shift = rng.choice([0.0, 1e6, -3e9], (k2, 1))
    near_wide = []
    for p in xy:
        q = (p + shift) * 2.0**t
        cu = (u + shift) * 2.0**t
        near_wide.append(weighted(q, ((q - cu) ** 2).sum(axis=1) - r * 4.0**t[:, 0]))
    cases["float_near_coplanar_wide"] = near_wide
    # each point at its own magnitude 10**[-6, 6] around a unit power circle: the coordinate
    # differences round (uniform samples share one grid, so the plain ones above do not)
    mixed = [rng.uniform(-1, 1, (k2, 2)) * 10.0 ** rng.integers(-6, 7, (k2, 1)) for _ in range(4)]
    u = rng.uniform(-1, 1, (k2, 2))
    r = rng.uniform(-1, 1, k2)
    cases["float_near_coplanar_mixed"] = [weighted(q, ((q - u) ** 2).sum(axis=1) - r) for q in mixed]
    # nearby points far out (exact differences by Sterbenz, inexact products)
    base = 1e9 + rng.uniform(-1, 1, (k2, 2)) * 1e3
    xy = [base + rng.uniform(-1, 1, (k2, 2)) for _ in range(4)]
    u = base + rng.uniform(-1, 1, (k2, 2))
    r = rng.uniform(0, 1, k2)
    cases["float_near_coplanar_far"] = [weighted(p, ((p - u) ** 2).sum(axis=1) - r) for p in xy]
    # equal weights on cocircular lattice points: the incircle degeneracy
    circle = lattice_circle(5**2 * 13**2)
    idx = np.argsort(rng.random((k2, len(circle))), axis=1)[:, :4]
    wq = rng.choice([0.0, 0.3, -5.5, 2.0**40, 1e-20], k2)
    off = rng.integers(-1000, 1000, (k2, 2)).astype(float)
    cases["equal_weights_cocircular"] = [weighted(circle[idx[:, j]] + off, wq) for j in range(4)]
    # rectangles x in {x1, x2}, y in {y1, y2} of wildly different magnitudes with weights f1, f2
    # per column (or per row): the lifts F(x) + G(y) are bilinear-separable, so the four lifted
    # corners are exactly coplanar while every difference and product of the evaluation rounds
    x1, x2, y1, y2 = (magnitudes(rng, k2, -20, 20)[0] for _ in range(4))
    f1, f2 = magnitudes(rng, k2, -40, 40)[0], magnitudes(rng, k2, -40, 40)[0]
    by_row = rng.random(k2) < 0.5
    corners = [np.column_stack([x, y, np.where(by_row, fy, fx)])
               for x, y, fx, fy in ((x1, y1, f1, f1), (x2, y1, f2, f1), (x2, y2, f2, f2), (x1, y2, f1, f2))]
    order = np.argsort(rng.random((k2, 4)), axis=1)
    stacked = np.stack(corners, axis=1)
    cases["rectangle_wide"] = [stacked[np.arange(k2), order[:, j]] for j in range(4)]
    return cases


def lattice_circle(r2):
    pts = []
    r = math.isqrt(r2)
    for x in range(-r, r + 1):
        y2 = r2 - x * x
        y = math.isqrt(y2)
        if y * y == y2:
            pts.append((x, y))
            if y:
                pts.append((x, -y))
    return np.array(pts, dtype=np.float64)


def bisector_cases():
    rng = np.random.default_rng(RNG_SEED + 1)
    cases = {}
    k = 20000
    cases["uniform"] = [rng.uniform(-1, 1, (k, 2)),
                        weighted(rng.uniform(-1, 1, (k, 2)), rng.uniform(-0.5, 0.5, k)),
                        weighted(rng.uniform(-1, 1, (k, 2)), rng.uniform(-0.5, 0.5, k))]
    x, e = magnitudes(rng, k, -24, 24)
    cols = []
    for _ in range(5):
        cols.append(rng.choice([-1.0, 1.0], k) * rng.uniform(0.1, 1.0, k) * 10.0**e)
    wa, _ = magnitudes(rng, k, -48, 48)
    wb, _ = magnitudes(rng, k, -48, 48)
    cases["uniform_wide"] = [np.column_stack([x, cols[0]]), weighted(np.column_stack(cols[1:3]), wa),
                             weighted(np.column_stack(cols[3:5]), wb)]
    # p exactly on the power bisector: integers, bw = |p-b|^2 - |p-a|^2 + aw
    k2 = 10000
    p = rng.integers(-1000, 1001, (k2, 2))
    a = rng.integers(-1000, 1001, (k2, 2))
    b = rng.integers(-1000, 1001, (k2, 2))
    aw = rng.integers(-10**6, 10**6 + 1, k2)
    bw = ((p - b) ** 2).sum(axis=1) - ((p - a) ** 2).sum(axis=1) + aw
    on = [p.astype(float), weighted(a, aw), weighted(b, bw)]
    cases["on_bisector"] = on
    offset = rng.choice([1e9, -2.0**33 + 7.0, 5e10], (k2, 1))
    far = [on[0] + offset, np.column_stack([on[1][:, :2] + offset, on[1][:, 2]]),
           np.column_stack([on[2][:, :2] + offset, on[2][:, 2]])]
    cases["on_bisector_far"] = far
    s = rng.integers(-85, 20, (k2, 1)).astype(float)
    cases["on_bisector_scaled"] = [far[0] * 2.0**s, np.column_stack([far[1][:, :2] * 2.0**s, far[1][:, 2:] * 4.0**s]),
                                   np.column_stack([far[2][:, :2] * 2.0**s, far[2][:, 2:] * 4.0**s])]
    cases["on_bisector_far_nudged"] = [nudge(rng, far[0], 0.5), far[1],
                                       np.column_stack([far[2][:, :2], nudge(rng, far[2][:, 2], 0.3)])]
    # bw rounded from float data: near the bisector, inexact differences
    p = rng.uniform(-1, 1, (k2, 2))
    a = rng.uniform(-1, 1, (k2, 2))
    b = rng.uniform(-1, 1, (k2, 2))
    aw = rng.uniform(-1, 1, k2)
    bw = ((p - b) ** 2).sum(axis=1) - ((p - a) ** 2).sum(axis=1) + aw
    cases["float_near_bisector"] = [p, weighted(a, aw), weighted(b, bw)]
    # each point at its own magnitude 10**[-6, 6]: coordinate and weight differences round
    p, a, b = (rng.uniform(-1, 1, (k2, 2)) * 10.0 ** rng.integers(-6, 7, (k2, 1)) for _ in range(3))
    aw = rng.uniform(-1, 1, k2) * 10.0 ** rng.integers(-6, 7, k2)
    bw = ((p - b) ** 2).sum(axis=1) - ((p - a) ** 2).sum(axis=1) + aw
    cases["float_near_bisector_mixed"] = [p, weighted(a, aw), weighted(b, bw)]
    base = -1e9 + rng.uniform(-1, 1, (k2, 2)) * 1e3
    p, a, b = (base + rng.uniform(-1, 1, (k2, 2)) for _ in range(3))
    aw = rng.uniform(0, 1, k2)
    bw = ((p - b) ** 2).sum(axis=1) - ((p - a) ** 2).sum(axis=1) + aw
    cases["float_near_bisector_far"] = [p, weighted(a, aw), weighted(b, bw)]
    # a = (-x, y, 4 px x), b = (x, y, 0): |p-a|^2 - |p-b|^2 = 4 px x, so p is exactly on the power
    # bisector; 26-bit px and x make the weight exact, magnitudes 2**[-60, 60] make every
    # difference and square of the evaluation round (axes swapped at random)
    k3 = 20000

    def wide(bits):
        m = rng.uniform(0.5, 1.0, k3)
        if bits < 53:
            m = np.round(m * 2.0**bits) / 2.0**bits
        return rng.choice([-1.0, 1.0], k3) * m * 2.0 ** rng.integers(-60, 61, k3)

    x, px, y, py = wide(26), wide(26), wide(53), wide(53)
    mirror = [np.column_stack([px, py]), np.column_stack([-x, y, 4 * px * x]), np.column_stack([x, y, np.zeros(k3)])]
    swap = rng.random(k3) < 0.5
    for arr in mirror:
        arr[swap, :2] = arr[swap, 1::-1]
    cases["mirror_wide"] = mirror
    return cases


POWER_CASES = power_cases()
BISECTOR_CASES = bisector_cases()

# exactly degenerate categories: every reference sign is 0
POWER_DEGENERATE = ("lattice_coplanar", "lattice_coplanar_far", "lattice_coplanar_scaled", "equal_weights_cocircular",
                    "rectangle_wide")
BISECTOR_DEGENERATE = ("on_bisector", "on_bisector_far", "on_bisector_scaled", "mirror_wide")

# Lower bounds on the share of calls reaching the exact stage (measured shares are about twice
# these, or ~1 for the degenerate ones): the adversarial categories must really exercise it.
# "uniform_wide" is hard by nature, as for orient2d: a huge point among tiny ones makes the
# minors cancel (incircle on the same points needs its exact stage even more often).
MIN_POWER_EXACT_SHARE = {
    "uniform_wide": 0.05,
    "lattice_coplanar": 0.95,
    "lattice_coplanar_far": 0.95,
    "lattice_coplanar_scaled": 0.95,
    "lattice_far_nudged": 0.2,
    "lattice_weights_nudged": 0.5,
    "float_near_coplanar": 0.5,
    "float_near_coplanar_wide": 0.5,
    "float_near_coplanar_far": 0.5,
    "float_near_coplanar_mixed": 0.5,
    "equal_weights_cocircular": 0.95,
    "rectangle_wide": 0.95,
}
MIN_BISECTOR_EXACT_SHARE = {
    "on_bisector": 0.95,
    "on_bisector_far": 0.95,
    "on_bisector_scaled": 0.95,
    "on_bisector_far_nudged": 0.12,   # at 1e9 most one-ulp moves of p are clear to the filter
    "float_near_bisector": 0.5,
    "float_near_bisector_far": 0.5,
    "float_near_bisector_mixed": 0.5,
    "mirror_wide": 0.95,
}


# ---------------------------------------------------------------------------
# Bulk comparisons
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(POWER_CASES))
def test_power_test_bulk(name):
    a, b, c, d = POWER_CASES[name]
    counters = np.zeros(P.N_POWER_COUNTERS, dtype=np.int64)
    got = P.power_test_many(a, b, c, d, counters=counters)
    want = ref_power_many(a, b, c, d)
    bad = np.flatnonzero(got != want)
    assert bad.size == 0, (f"{bad.size} mismatches, first at {bad[0]}: "
                           f"{a[bad[0]]}, {b[bad[0]]}, {c[bad[0]]}, {d[bad[0]]}")
    assert counters[P.POWER_TEST_CALLS] == len(a)
    assert counters[P.POWER_BISECTOR_CALLS] == 0 and counters[:4].sum() == 0
    share = counters[P.POWER_TEST_EXACT] / len(a)
    assert share >= MIN_POWER_EXACT_SHARE.get(name, 0.0), share
    if name in POWER_DEGENERATE:
        assert np.all(want == 0)
    if name in ("uniform", "uniform_positive_weights"):
        assert share < 0.01


@pytest.mark.parametrize("name", sorted(BISECTOR_CASES))
def test_power_bisector_side_bulk(name):
    p, a, b = BISECTOR_CASES[name]
    counters = np.zeros(P.N_POWER_COUNTERS, dtype=np.int64)
    got = P.power_bisector_side_many(p, a, b, counters=counters)
    want = ref_bisector_many(p, a, b)
    bad = np.flatnonzero(got != want)
    assert bad.size == 0, f"{bad.size} mismatches, first at {bad[0]}: {p[bad[0]]}, {a[bad[0]]}, {b[bad[0]]}"
    assert counters[P.POWER_BISECTOR_CALLS] == len(p)
    assert counters[P.POWER_TEST_CALLS] == 0
    share = counters[P.POWER_BISECTOR_EXACT] / len(p)
    assert share >= MIN_BISECTOR_EXACT_SHARE.get(name, 0.0), share
    if name in BISECTOR_DEGENERATE:
        assert np.all(want == 0)
    if name.startswith("uniform"):
        assert share < 0.01


def test_nudged_categories_have_every_sign():
    """The one-ulp perturbations really land on both sides (and some stay on)."""
    for name in ("lattice_far_nudged", "lattice_weights_nudged"):
        assert set(ref_power_many(*POWER_CASES[name])) == {-1, 0, 1}, name
    assert set(ref_bisector_many(*BISECTOR_CASES["on_bisector_far_nudged"])) == {-1, 0, 1}


def _sample(arrs, n, seed):
    rng = np.random.default_rng(seed)
    idx = rng.choice(len(arrs[0]), size=min(n, len(arrs[0])), replace=False)
    return [x[idx] for x in arrs]


def test_references_agree_with_fraction():
    """The scaled-integer references equal Fraction evaluation of the 4x4 form (sampled from every category)."""
    for i, arrs in enumerate(POWER_CASES.values()):
        a, b, c, d = _sample(arrs, 60, i)
        assert list(ref_power_many(a, b, c, d)) == [frac_power(*a[j], *b[j], *c[j], *d[j]) for j in range(len(a))]
    for i, arrs in enumerate(BISECTOR_CASES.values()):
        p, a, b = _sample(arrs, 100, 100 + i)
        assert list(ref_bisector_many(p, a, b)) == [frac_bisector(*p[j], *a[j], *b[j]) for j in range(len(p))]


def test_scalar_calls_match_fraction():
    for i, arrs in enumerate(POWER_CASES.values()):
        a, b, c, d = _sample(arrs, 40, 1000 + i)
        for j in range(len(a)):
            assert P.power_test(*a[j], *b[j], *c[j], *d[j]) == frac_power(*a[j], *b[j], *c[j], *d[j])
    for i, arrs in enumerate(BISECTOR_CASES.values()):
        p, a, b = _sample(arrs, 60, 2000 + i)
        for j in range(len(p)):
            assert P.power_bisector_side(*p[j], *a[j], *b[j]) == frac_bisector(*p[j], *a[j], *b[j])


# ---------------------------------------------------------------------------
# The filters: sound, and needed
# ---------------------------------------------------------------------------


@njit
def _power_filter_and_fast(a, b, c, d, filt, fast):
    for i in range(a.shape[0]):
        args = (a[i, 0], a[i, 1], a[i, 2], b[i, 0], b[i, 1], b[i, 2],
                c[i, 0], c[i, 1], c[i, 2], d[i, 0], d[i, 1], d[i, 2])
        filt[i] = P.power_test_filter(*args)
        v = P.power_test_fast(*args)
        fast[i] = (v > 0) - (v < 0)


@njit
def _bisector_filter_and_fast(p, a, b, filt, fast):
    for i in range(p.shape[0]):
        args = (p[i, 0], p[i, 1], a[i, 0], a[i, 1], a[i, 2], b[i, 0], b[i, 1], b[i, 2])
        filt[i] = P.power_bisector_side_filter(*args)
        v = P.power_bisector_side_fast(*args)
        fast[i] = (v > 0) - (v < 0)


def _filter_and_fast(kernel, arrs):
    n = len(arrs[0])
    filt = np.empty(n, dtype=np.int64)
    fast = np.empty(n, dtype=np.int64)
    kernel(*arrs, filt, fast)
    return filt, fast


def test_filters_never_decide_wrongly():
    """Wherever a filter decides, its sign is the exact one, in every category (adversarial ones included).

    Rounding errors of random inputs stay well below the worst-case bounds (at most ~2u of the
    power test's 11u times the permanent on "rectangle_wide", ~2.9u of the bisector's 5u on
    "mirror_wide"), so this catches bounds shrunk to about 1u (power) or 2u (bisector); the
    constants themselves are checked against their derivation below."""
    for name, arrs in POWER_CASES.items():
        filt, _ = _filter_and_fast(_power_filter_and_fast, arrs)
        want = ref_power_many(*arrs)
        decided = filt != UNDECIDED
        assert np.array_equal(filt[decided], want[decided]), name
    for name, arrs in BISECTOR_CASES.items():
        filt, _ = _filter_and_fast(_bisector_filter_and_fast, arrs)
        want = ref_bisector_many(*arrs)
        decided = filt != UNDECIDED
        assert np.array_equal(filt[decided], want[decided]), name


@pytest.mark.parametrize("name", ["uniform_wide", "lattice_far_nudged", "lattice_weights_nudged",
                                  "float_near_coplanar", "float_near_coplanar_wide", "float_near_coplanar_far",
                                  "float_near_coplanar_mixed", "rectangle_wide"])
def test_plain_floats_are_wrong_where_the_power_filter_abstains(name):
    """The float evaluation alone gets many of these signs wrong; the filter abstains on every one of
    them and the exact stage (its counter moves) gets them right."""
    arrs = POWER_CASES[name]
    filt, fast = _filter_and_fast(_power_filter_and_fast, arrs)
    want = ref_power_many(*arrs)
    wrong = fast != want
    assert wrong.sum() > 100, wrong.sum()
    assert np.all(filt[wrong] == UNDECIDED)
    counters = np.zeros(P.N_POWER_COUNTERS, dtype=np.int64)
    assert np.array_equal(P.power_test_many(*[x[wrong] for x in arrs], counters=counters), want[wrong])
    assert counters[P.POWER_TEST_EXACT] == wrong.sum()


@pytest.mark.parametrize("name", ["on_bisector_far_nudged", "float_near_bisector", "float_near_bisector_far",
                                  "float_near_bisector_mixed", "mirror_wide"])
def test_plain_floats_are_wrong_where_the_bisector_filter_abstains(name):
    arrs = BISECTOR_CASES[name]
    filt, fast = _filter_and_fast(_bisector_filter_and_fast, arrs)
    want = ref_bisector_many(*arrs)
    wrong = fast != want
    assert wrong.sum() > 100, wrong.sum()
    assert np.all(filt[wrong] == UNDECIDED)
    counters = np.zeros(P.N_POWER_COUNTERS, dtype=np.int64)
    assert np.array_equal(P.power_bisector_side_many(*[x[wrong] for x in arrs], counters=counters), want[wrong])
    assert counters[P.POWER_BISECTOR_EXACT] == wrong.sum()


def test_error_bound_constants_cover_their_derivation():
    """The chains of roundings derived in vorobench.core.predicates.power, evaluated exactly, stay
    under the constants (and above the first-order terms, 11u and 5u)."""
    u = Fraction(1, 2**53)

    def gamma(k):
        return k * u / (1 - k * u)

    per_term = u * (1 + u) ** 2 + (1 + u) * gamma(4) + (1 + gamma(3)) * gamma(5)
    first_sum = u * (1 + u) ** 3
    needed = (per_term + first_sum) * (1 + u) / (1 - u) ** 6
    assert 11 * u < needed <= Fraction(P.POWER_ERRBOUND_A)
    needed = gamma(5) * (1 + u) / (1 - u) ** 3
    assert 5 * u < needed <= Fraction(P.POWER_BISECTOR_ERRBOUND_A)


# ---------------------------------------------------------------------------
# Conventions, fixtures, limits
# ---------------------------------------------------------------------------


def test_power_test_conventions():
    # counter-clockwise a, b, c on the unit circle, zero weights: the power circle is the unit circle
    a, b, c = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (-1.0, 0.0, 0.0)
    assert P.orient2d(*a[:2], *b[:2], *c[:2]) == 1
    assert P.power_test(*a, *b, *c, 0.0, 0.0, 0.0) == 1       # inside: conflict
    assert P.power_test(*a, *b, *c, 2.0, 0.0, 0.0) == -1      # outside
    assert P.power_test(*a, *b, *c, 0.0, -1.0, 0.0) == 0      # on it
    # d = (2, 0): its power with respect to the unit circle is 4 - dw - 1
    assert P.power_test(*a, *b, *c, 2.0, 0.0, 3.0) == 0
    assert P.power_test(*a, *b, *c, 2.0, 0.0, 3.5) == 1       # big circle at d: conflict
    assert P.power_test(*a, *b, *c, 2.0, 0.0, 2.5) == -1
    # a point inside the circle with a negative weight is not in conflict
    assert P.power_test(*a, *b, *c, 0.0, 0.0, -1.5) == -1
    # clockwise a, b, c: every non-zero sign flips
    assert P.power_test(*c, *b, *a, 2.0, 0.0, 3.5) == -1
    assert P.power_test(*c, *b, *a, 2.0, 0.0, 3.0) == 0
    # raising a's weight lowers a's lift: d = origin is then not in conflict with the new circle
    assert P.power_test(1.0, 0.0, 5.0, *b, *c, 0.0, 0.0, 0.0) == -1
    assert isinstance(P.power_test(*a, *b, *c, 0.0, 0.0, 0.0), int)
    assert P.power_test(1, 0, 0, 0, 1, 0, -1, 0, 0, 0, 0, 0) == 1   # ints are converted to float64
    assert P.power_test_fast(*a, *b, *c, 0.0, 0.0, 0.0) > 0


def test_power_test_conflict_with_an_integer_power_circle():
    """d in conflict iff its power with respect to the power circle (u, R) of a, b, c is negative."""
    rng = np.random.default_rng(3)
    pts, w, u = lattice_on_power_circle(rng, 300)
    for j in range(300):
        a, b, c, d = (tuple(map(float, (*pts[i, j], w[i, j]))) for i in range(4))
        o = P.orient2d(*a[:2], *b[:2], *c[:2])
        assert P.power_test(*a, *b, *c, *d) == 0
        if o == 0:
            continue
        for delta in (1.0, 0.25, 1000.0):
            # larger dw: power of d w.r.t. (u, R) = |d-u|^2 - dw - R becomes -delta < 0
            assert P.power_test(*a, *b, *c, d[0], d[1], d[2] + delta) == o
            assert P.power_test(*a, *b, *c, d[0], d[1], d[2] - delta) == -o


def test_power_bisector_side_conventions():
    a, b = (0.0, 0.0, 0.0), (2.0, 0.0, 0.0)
    assert P.power_bisector_side(0.5, 7.0, *a, *b) == -1     # closer to a
    assert P.power_bisector_side(1.5, -7.0, *a, *b) == 1
    assert P.power_bisector_side(1.0, 123.0, *a, *b) == 0    # the perpendicular bisector x = 1
    # b's weight 4 moves the bisector to x = 0 (|p|^2 = |p-b|^2 - 4 there)
    b4 = (2.0, 0.0, 4.0)
    assert P.power_bisector_side(0.0, 3.0, *a, *b4) == 0
    assert P.power_bisector_side(0.5, 0.0, *a, *b4) == 1
    assert P.power_bisector_side(-0.5, 0.0, *a, *b4) == -1
    # coincident sites: the weights alone decide, everywhere
    assert P.power_bisector_side(5.0, 5.0, 1.0, 1.0, 2.0, 1.0, 1.0, 1.0) == -1
    assert P.power_bisector_side(5.0, 5.0, 1.0, 1.0, 2.0, 1.0, 1.0, 2.0) == 0
    assert P.power_bisector_side(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0) == 0
    assert P.power_bisector_side_fast(0.5, 7.0, *a, *b) < 0


def test_power_test_hard_fixture():
    """Integer weighted points far from the origin on one power circle, then d moved ulp by ulp."""
    a, b, c, d = ((1e9 + 3.0, 1e9 - 7.0), (1e9 + 11.0, 1e9 + 2.0), (1e9 - 5.0, 1e9 + 9.0), (1e9 + 1.0, 1e9 + 1.0))
    ux, uy, r = 1e9 + 2.0, 1e9 + 1.0, -40.0
    pts = [(x, y, (x - ux) ** 2 + (y - uy) ** 2 - r) for x, y in (a, b, c, d)]   # exact small integers
    assert P.power_test(*pts[0], *pts[1], *pts[2], *pts[3]) == 0 == frac_power(*pts[0], *pts[1], *pts[2], *pts[3])
    signs = set()
    counters = np.zeros(P.N_POWER_COUNTERS, dtype=np.int64)
    for i in range(-3, 4):
        for j in range(-3, 4):
            q = (pts[3][0] + i * 2.0**-23, pts[3][1] + j * 2.0**-23, pts[3][2])
            want = frac_power(*pts[0], *pts[1], *pts[2], *q)
            signs.add(want)
            assert P.power_test_counted(*pts[0], *pts[1], *pts[2], *q, counters) == want
            assert P.power_test(*pts[1], *pts[2], *pts[0], *q) == want
            assert P.power_test(*pts[1], *pts[0], *pts[2], *q) == -want
            # the same through the weight: one ulp of d's weight
            for wq in (np.nextafter(q[2], np.inf), np.nextafter(q[2], -np.inf)):
                assert P.power_test(*pts[0], *pts[1], *pts[2], q[0], q[1], float(wq)) == frac_power(
                    *pts[0], *pts[1], *pts[2], q[0], q[1], float(wq))
    assert signs == {-1, 0, 1}
    assert counters[P.POWER_TEST_EXACT] > 0


def test_power_bisector_exactly_on_and_one_ulp_off():
    rng = np.random.default_rng(11)
    for _ in range(200):
        p, a, b = (rng.integers(-10**6, 10**6, 2) for _ in range(3))
        aw = int(rng.integers(-10**9, 10**9))
        bw = int(((p - b) ** 2).sum() - ((p - a) ** 2).sum()) + aw
        args = [float(v) for v in (*p, *a, aw, *b, bw)]
        assert P.power_bisector_side(*args) == 0
        # along the bisector (p + t * perp(b - a), exact integers) it stays 0
        t = int(rng.integers(-50, 50))
        q = p + t * np.array([a[1] - b[1], b[0] - a[0]])
        assert P.power_bisector_side(float(q[0]), float(q[1]), *args[2:]) == 0
        for i in (0, 1, 4, 7):
            for direction in (np.inf, -np.inf):
                moved = list(args)
                moved[i] = float(np.nextafter(moved[i], direction))
                assert P.power_bisector_side(*moved) == frac_bisector(*moved)
                assert P.power_bisector_side(moved[0], moved[1], *moved[5:8], *moved[2:5]) == -frac_bisector(*moved)


@pytest.mark.parametrize("k", [-99, -60, -1, 0, 40, 85])
def test_exact_at_every_scale_of_the_range(k):
    """Degenerate lattices scaled to the ends of the range (coordinates near 2**-100 or 2**100, weights
    near 2**-200 or 2**200) stay degenerate, and ulp moves agree with Fraction."""
    rng = np.random.default_rng(100 + k)
    pts, w, _ = lattice_on_power_circle(rng, 40, span=7, rspan=20)
    s = 2.0**k
    for j in range(40):
        rows = [(float(pts[i, j, 0]) * s, float(pts[i, j, 1]) * s, float(w[i, j]) * s * s) for i in range(4)]
        flat = [v for r in rows for v in r]
        assert all(2.0**-100 <= abs(v) < 2.0**100 for r in rows for v in r[:2] if v != 0.0)
        assert all(2.0**-200 <= abs(r[2]) < 2.0**200 for r in rows if r[2] != 0.0)
        assert P.power_test(*flat) == 0
        for i in (0, 4, 9, 10, 11):
            if flat[i] != 0.0:
                moved = list(flat)
                moved[i] = float(np.nextafter(moved[i], np.inf))
                assert P.power_test(*moved) == frac_power(*moved)
        # p on the power bisector of a and b: every step below is exact (small integers times 2**k)
        p, a, b = rows[3][:2], rows[0], rows[1]
        bw = ((p[0] - b[0]) ** 2 + (p[1] - b[1]) ** 2) - ((p[0] - a[0]) ** 2 + (p[1] - a[1]) ** 2) + a[2]
        assert P.power_bisector_side(*p, *a, b[0], b[1], bw) == 0 == frac_bisector(*p, *a, b[0], b[1], bw)
        if bw != 0.0:
            bw = float(np.nextafter(bw, np.inf))
            assert P.power_bisector_side(*p, *a, b[0], b[1], bw) == frac_bisector(*p, *a, b[0], b[1], bw) == 1


def test_extreme_magnitudes():
    """Coordinates at 2**-100 and just below 2**100, weights at 2**-200 and just below 2**200."""
    top = float(np.nextafter(2.0**100, 0.0))
    wtop = float(np.nextafter(2.0**200, 0.0))
    for s, ws in ((2.0**-100, 2.0**-200), (top, wtop), (2.0**-100, wtop), (top, 2.0**-200)):
        sq = [(s, 0.0, ws), (0.0, s, ws), (-s, 0.0, ws), (0.0, -s, ws)]
        flat = [v for r in sq for v in r]
        assert P.power_test(*flat) == 0 == frac_power(*flat)
        for i in range(12):
            if flat[i] != 0.0:
                for direction in (np.inf, -np.inf):
                    moved = list(flat)
                    moved[i] = float(np.nextafter(moved[i], direction))
                    assert P.power_test(*moved) == frac_power(*moved)
        args = (0.0, s, s, 0.0, ws, -s, 0.0, ws)   # p on the perpendicular bisector of two equal-weight sites
        assert P.power_bisector_side(*args) == 0
        for i in range(8):
            if args[i] != 0.0:
                moved = list(args)
                moved[i] = float(np.nextafter(moved[i], 0.0))
                assert P.power_bisector_side(*moved) == frac_bisector(*moved)


def test_check_weight_range():
    sites = np.array([[0.0, 0.0], [1.0, 1.0], [0.5, 2.0], [3.0, 0.25]])
    check_weight_range(sites, [0.0, 2.0**-200, -3.0, float(np.nextafter(2.0**200, 0.0))])
    check_weight_range(sites, np.zeros(4))
    for bad in ([1.0, 2.0**200, 0, 0], [float(np.nextafter(2.0**-200, 0.0)), 0, 0, 0], [-2.0**201, 0, 0, 0]):
        with pytest.raises(OutsideExactRange):
            check_weight_range(sites, bad)
    assert (WEIGHT_MIN_EXPONENT, WEIGHT_MAX_EXPONENT) == (math.frexp(2.0**-200)[1], math.frexp(2.0**199)[1])


def test_counted_variants_and_layout():
    counters = np.zeros(P.N_POWER_COUNTERS + 1, dtype=np.int64)
    assert P.power_test_counted(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, counters) == 1
    assert P.power_test_counted(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0, counters) == 0
    assert P.power_bisector_side_counted(0.5, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, counters) == -1
    assert P.power_bisector_side_counted(1.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, counters) == 0
    assert (P.POWER_TEST_CALLS, P.POWER_TEST_EXACT, P.POWER_BISECTOR_CALLS, P.POWER_BISECTOR_EXACT) == (4, 5, 6, 7)
    assert list(counters) == [0, 0, 0, 0, 2, 1, 2, 1, 0]
    # one array counts all four predicates
    P.incircle_counted(1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, counters)
    assert counters[P.INCIRCLE_CALLS] == 1 and counters[P.POWER_TEST_CALLS] == 2


# ---------------------------------------------------------------------------
# Equal weights: incircle
# ---------------------------------------------------------------------------


def test_equal_weights_bulk_equals_incircle():
    for name in ("equal_weights_cocircular", "uniform"):
        a, b, c, d = POWER_CASES[name]
        same = [np.column_stack([x[:, :2], a[:, 2]]) for x in (a, b, c, d)]
        got = P.power_test_many(*same)
        assert np.array_equal(got, P.incircle_many(*(x[:, :2] for x in same)))
    a, b, c, d = POWER_CASES["lattice_far_nudged"]
    wq = np.full(len(a), 0.7)
    got = P.power_test_many(*(np.column_stack([x[:, :2], wq]) for x in (a, b, c, d)))
    assert np.array_equal(got, P.incircle_many(a[:, :2], b[:, :2], c[:, :2], d[:, :2]))
    assert set(got) == {-1, 0, 1}


coord = st.one_of(
    st.integers(-3, 3).map(float),
    st.sampled_from([-3.0, -2.0, -1.0, 1.0, 2.0, 3.0]).flatmap(
        lambda v: st.sampled_from([v, float(np.nextafter(v, np.inf)), float(np.nextafter(v, -np.inf))])),
    st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False, allow_subnormal=False).map(
        lambda x: x if abs(x) > 1e-20 else 0.0),
    st.integers(-3, 3).map(lambda v: 1e9 + v * 2.0**-23),
)
weight = st.one_of(
    st.integers(-20, 20).map(float),
    st.sampled_from([1.0, 2.0, 5.0, 8.0]).flatmap(
        lambda v: st.sampled_from([v, float(np.nextafter(v, np.inf)), float(np.nextafter(v, -np.inf))])),
    st.floats(-1e12, 1e12, allow_nan=False, allow_infinity=False, allow_subnormal=False).map(
        lambda x: x if abs(x) > 1e-40 else 0.0),
)
point = st.tuples(coord, coord)
wpoint = st.tuples(coord, coord, weight)


@settings(max_examples=300, deadline=None)
@given(point, point, point, point, weight)
def test_equal_weights_property(a, b, c, d, w):
    assert P.power_test(*a, w, *b, w, *c, w, *d, w) == P.incircle(*a, *b, *c, *d)


@settings(max_examples=250, deadline=None)
@given(wpoint, wpoint, wpoint, wpoint, st.permutations(range(4)))
def test_power_test_properties(a, b, c, d, perm):
    pts = [a, b, c, d]
    s = P.power_test(*a, *b, *c, *d)
    assert s == frac_power(*a, *b, *c, *d)
    # the lifted 4x4 determinant is alternating in the four weighted points
    q = [pts[i] for i in perm]
    assert P.power_test(*q[0], *q[1], *q[2], *q[3]) == _perm_parity(perm) * s
    # mirroring flips it
    assert P.power_test(*(v for p in pts for v in (-p[0], p[1], p[2]))) == -s
    # adding one constant to every weight does not move the lifted points off (or onto) a plane
    if all(float(p[2]).is_integer() for p in pts):
        assert P.power_test(*(v for p in pts for v in (p[0], p[1], p[2] + 7.0))) == s


@settings(max_examples=300, deadline=None)
@given(point, wpoint, wpoint)
def test_power_bisector_side_properties(p, a, b):
    s = P.power_bisector_side(*p, *a, *b)
    assert s == frac_bisector(*p, *a, *b)
    assert P.power_bisector_side(*p, *b, *a) == -s
    assert P.power_bisector_side(-p[0], p[1], -a[0], a[1], a[2], -b[0], b[1], b[2]) == s


# ---------------------------------------------------------------------------
# Vectorised API and nopython callers
# ---------------------------------------------------------------------------


def test_many_broadcasting_and_validation():
    rng = np.random.default_rng(5)
    a = weighted(rng.uniform(-1, 1, (50, 2)), rng.uniform(0, 1, 50))
    b = np.array([0.25, 0.5, 0.1])
    c = [[-0.5, 0.125, 0.0]]
    d = weighted(rng.uniform(-1, 1, (50, 2)), rng.uniform(0, 1, 50))
    got = P.power_test_many(a, b, c, d)
    assert got.dtype == np.int8 and got.shape == (50,)
    assert list(got) == [P.power_test(*x, *b, *c[0], *y) for x, y in zip(a, d)]
    p = rng.uniform(-1, 1, (50, 2))
    got = P.power_bisector_side_many(p, b, a)
    assert list(got) == [P.power_bisector_side(*q, *b, *x) for q, x in zip(p, a)]
    assert P.power_bisector_side_many(np.empty((0, 2)), b, c).shape == (0,)
    with pytest.raises(ValueError):
        P.power_test_many(a, a[:3], b, b)
    with pytest.raises(ValueError):
        P.power_test_many(a[:, :2], b, b, b)                     # weights missing
    with pytest.raises(ValueError):
        P.power_bisector_side_many(a, b, b)                      # p must be plain (x, y)
    with pytest.raises(ValueError):
        P.power_test_many(a, b, c, d, counters=np.zeros(4, dtype=np.int64))   # too short for 4..7


@njit
def _regular_triangle_user(pts, counters):
    # weighted points (rows x, y, w): conflicts with the power circle of the first three, and
    # which of the first two each point is closer to in power
    o = P.orient2d(pts[0, 0], pts[0, 1], pts[1, 0], pts[1, 1], pts[2, 0], pts[2, 1])
    conflicts = 0
    closer_to_first = 0
    for i in range(3, pts.shape[0]):
        s = P.power_test_counted(pts[0, 0], pts[0, 1], pts[0, 2], pts[1, 0], pts[1, 1], pts[1, 2],
                                 pts[2, 0], pts[2, 1], pts[2, 2], pts[i, 0], pts[i, 1], pts[i, 2], counters)
        if s * o > 0:
            conflicts += 1
        if P.power_bisector_side_counted(pts[i, 0], pts[i, 1], pts[0, 0], pts[0, 1], pts[0, 2],
                                         pts[1, 0], pts[1, 1], pts[1, 2], counters) < 0:
            closer_to_first += 1
    return conflicts, closer_to_first


def test_callable_from_njit():
    rng = np.random.default_rng(9)
    pts = weighted(rng.integers(0, 4, (200, 2)), rng.integers(0, 3, 200))
    counters = np.zeros(P.N_POWER_COUNTERS, dtype=np.int64)
    conflicts, closer = _regular_triangle_user(pts, counters)
    o = sgn((Fraction(pts[1, 0]) - Fraction(pts[0, 0])) * (Fraction(pts[2, 1]) - Fraction(pts[0, 1]))
            - (Fraction(pts[1, 1]) - Fraction(pts[0, 1])) * (Fraction(pts[2, 0]) - Fraction(pts[0, 0])))
    want_conflicts = sum(frac_power(*pts[0], *pts[1], *pts[2], *pts[i]) * o > 0 for i in range(3, len(pts)))
    want_closer = sum(frac_bisector(*pts[i, :2], *pts[0], *pts[1]) < 0 for i in range(3, len(pts)))
    assert (conflicts, closer) == (want_conflicts, want_closer)
    assert counters[P.POWER_TEST_CALLS] == counters[P.POWER_BISECTOR_CALLS] == len(pts) - 3
