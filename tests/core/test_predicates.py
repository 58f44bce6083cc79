"""Tests for vorobench.core.predicates: exact signs checked against rational arithmetic.

Two independent exact references are used, both written from the definitions:
* ``Fraction`` evaluation (``Fraction(float)`` is exact), for fixtures and
  samples;
* Python-integer evaluation after scaling all floats of a batch by a common
  power of two (a positive scale does not change the sign), for the bulk.
The two references are cross-checked against each other.
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

RNG_SEED = 20240611


# ---------------------------------------------------------------------------
# Exact references (from the definitions, independent of the module)
# ---------------------------------------------------------------------------


def det3(r0, r1, r2):
    return (
        r0[0] * (r1[1] * r2[2] - r1[2] * r2[1])
        - r0[1] * (r1[0] * r2[2] - r1[2] * r2[0])
        + r0[2] * (r1[0] * r2[1] - r1[1] * r2[0])
    )


def orient_det(ax, ay, bx, by, cx, cy):
    """| a-c ; b-c | (2x2), positive for counter-clockwise a, b, c."""
    return (ax - cx) * (by - cy) - (ay - cy) * (bx - cx)


def incircle_det(ax, ay, bx, by, cx, cy, dx, dy):
    """3x3 determinant with rows (p-d, |p-d|^2), p = a, b, c."""
    rows = []
    for px, py in ((ax, ay), (bx, by), (cx, cy)):
        u = px - dx
        v = py - dy
        rows.append((u, v, u * u + v * v))
    return det3(*rows)


def sgn(x):
    return (x > 0) - (x < 0)


def frac_orient(*coords):
    return sgn(orient_det(*map(Fraction, map(float, coords))))


def frac_incircle(*coords):
    return sgn(incircle_det(*map(Fraction, map(float, coords))))


def scaled_ints(*arrays):
    """Exact images of float arrays as object arrays of Python ints, all scaled by one common 2**s."""
    flat = np.concatenate([np.ravel(np.asarray(a, dtype=np.float64)) for a in arrays])
    assert np.all(np.isfinite(flat))
    m, e = np.frexp(flat)
    mant = (m * 2.0**53).astype(np.int64)  # exact: |m| < 1 has 53 significant bits
    assert np.array_equal(np.ldexp(mant.astype(np.float64), e - 53), flat)
    exp = e.astype(np.int64) - 53
    nz = mant != 0
    emin = exp[nz].min() if nz.any() else 0
    shift = np.where(nz, exp - emin, 0)
    ints = mant.astype(object) << shift.astype(object)
    out = []
    pos = 0
    for a in arrays:
        a = np.asarray(a)
        out.append(ints[pos : pos + a.size].reshape(a.shape))
        pos += a.size
    return out


def obj_sign(x):
    return ((x > 0).astype(np.int8) - (x < 0).astype(np.int8)).astype(np.int8)


def ref_orient_many(a, b, c):
    A, B, C = scaled_ints(a, b, c)
    return obj_sign(orient_det(A[:, 0], A[:, 1], B[:, 0], B[:, 1], C[:, 0], C[:, 1]))


def ref_incircle_many(a, b, c, d):
    A, B, C, D = scaled_ints(a, b, c, d)
    return obj_sign(incircle_det(A[:, 0], A[:, 1], B[:, 0], B[:, 1], C[:, 0], C[:, 1], D[:, 0], D[:, 1]))


# ---------------------------------------------------------------------------
# Case generators (all seeded)
# ---------------------------------------------------------------------------


def nudge(rng, x, p=0.5):
    """Move each non-zero entry one ulp up or down with probability p (direction random).

    Zeros are left alone: their neighbours are subnormal, outside the supported range.
    """
    x = np.array(x, dtype=np.float64)
    r = np.where(x == 0.0, 1.0, rng.random(x.shape))
    up = np.nextafter(x, np.inf)
    down = np.nextafter(x, -np.inf)
    return np.where(r < p / 2, up, np.where(r < p, down, x))


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


R2 = 5**2 * 13**2 * 17**2  # 1105^2: many lattice points
CIRCLE = lattice_circle(R2)


def pick_distinct(rng, n_pts, k, m):
    """k rows of m distinct indices into range(n_pts)."""
    return np.argsort(rng.random((k, n_pts)), axis=1)[:, :m]


def orient_cases():
    rng = np.random.default_rng(RNG_SEED)
    cases = {}
    k = 15000
    cases["uniform"] = [rng.uniform(-1, 1, (k, 2)) for _ in range(3)]
    cases["uniform_wide"] = [rng.uniform(-1e3, 1e3, (k, 2)) * 10.0 ** rng.integers(-30, 30, (k, 1)) for _ in range(3)]
    cases["grid_nudged"] = [nudge(rng, rng.integers(0, 5, (k, 2)).astype(float)) for _ in range(3)]
    # exactly collinear integer points with a large offset, then the same nudged
    k2 = 10000
    origin = 1e9 + rng.integers(-1000, 1000, (k2, 2)).astype(float)
    direction = rng.integers(-7, 8, (k2, 2)).astype(float)
    pts = [origin + rng.integers(-50, 51, (k2, 1)) * direction for _ in range(3)]
    cases["collinear_offset"] = pts
    cases["collinear_offset_nudged"] = [nudge(rng, p, 0.3) for p in pts]
    # points on y = x, y = 2x, y = -x with x of wildly different magnitudes:
    # the differences are not exact, the determinant is exactly zero
    xs = [rng.uniform(-1, 1, k2) * 10.0 ** rng.integers(-20, 20, k2) for _ in range(3)]
    slope = rng.choice([1.0, 2.0, -1.0, 0.5], k2)
    diag = [np.column_stack([x, slope * x]) for x in xs]
    cases["diagonal"] = diag
    cases["diagonal_nudged"] = [nudge(rng, p, 0.2) for p in diag]
    # ulp-spaced lattice around 1e9 (ulp(1e9) = 2**-23)
    u = 2.0**-23
    cases["ulp_lattice_1e9"] = [1e9 + rng.integers(-3, 4, (k2, 2)) * u for _ in range(3)]
    # 1e-9 spacing around 1 (rounded to the float grid), and 1e-9 jitter around 1e9
    cases["spacing_1e-9"] = [1.0 + rng.integers(-5, 6, (k2, 2)) * 1e-9 for _ in range(3)]
    cases["jitter_1e9"] = [1e9 + rng.uniform(-1, 1, (k2, 2)) * 1e-9 * 1e3 for _ in range(3)]
    return cases


def incircle_cases():
    rng = np.random.default_rng(RNG_SEED + 1)
    cases = {}
    k = 12000
    cases["uniform"] = [rng.uniform(-1, 1, (k, 2)) for _ in range(4)]
    cases["grid_nudged"] = [nudge(rng, rng.integers(0, 5, (k, 2)).astype(float), 0.3) for _ in range(4)]
    cases["grid_exact"] = [rng.integers(0, 4, (k, 2)).astype(float) for _ in range(4)]
    # four distinct lattice points on x^2 + y^2 = 1105^2, translated
    k2 = 10000
    idx = pick_distinct(rng, len(CIRCLE), k2, 4)
    offset = rng.choice([0.0, 2.0**30 + 12345.0, 1e9, -7e8], (k2, 1)) * np.ones((1, 2))
    offset += rng.integers(-1000, 1000, (k2, 2))
    cyc = [CIRCLE[idx[:, j]] + offset for j in range(4)]
    cases["cocircular_lattice"] = cyc
    cases["cocircular_lattice_nudged"] = [nudge(rng, p, 0.15) for p in cyc]
    # scaled by a power of two into tiny coordinates (still exactly cocircular)
    scale = 2.0 ** rng.integers(-60, -20, (k2, 1))
    cases["cocircular_lattice_scaled"] = [p * scale for p in cyc]
    # rectangles x in {x1, x2}, y in {y1, y2} of wildly different magnitudes:
    # cocircular, with inexact coordinate differences
    def mag(n):
        return rng.uniform(-1, 1, n) * 10.0 ** rng.integers(-25, 25, n)

    x1, x2, y1, y2 = mag(k2), mag(k2), mag(k2), mag(k2)
    corners = [np.column_stack(v) for v in ((x1, y1), (x2, y1), (x2, y2), (x1, y2))]
    order = pick_distinct(rng, 4, k2, 4)
    stacked = np.stack(corners, axis=1)  # (k2, 4, 2)
    rect = [stacked[np.arange(k2), order[:, j]] for j in range(4)]
    cases["rectangle_wide"] = rect
    cases["rectangle_wide_nudged"] = [nudge(rng, p, 0.1) for p in rect]
    # ulp lattice around 1e9
    u = 2.0**-23
    cases["ulp_lattice_1e9"] = [1e9 + rng.integers(-2, 3, (k2, 2)) * u for _ in range(4)]
    cases["spacing_1e-9"] = [1.0 + rng.integers(-3, 4, (k2, 2)) * 1e-9 for _ in range(4)]
    return cases


ORIENT_CASES = orient_cases()
INCIRCLE_CASES = incircle_cases()

# Lower bounds on the share of calls that reach the exact stage (measured
# values are roughly twice these; exactly degenerate inputs nearly always do,
# except when a product is exactly zero, which the filter decides itself).
MIN_ORIENT_EXACT_SHARE = {
    "uniform_wide": 0.05,  # huge c with tiny a, b: cancellation in the pivoted differences
    "grid_nudged": 0.02,
    "collinear_offset": 0.5,
    "collinear_offset_nudged": 0.05,
    "diagonal": 0.95,
    "diagonal_nudged": 0.9,
    "ulp_lattice_1e9": 0.015,
    "spacing_1e-9": 0.004,
    "jitter_1e9": 0.004,
}
MIN_INCIRCLE_EXACT_SHARE = {
    "grid_nudged": 0.07,
    "grid_exact": 0.1,
    "cocircular_lattice": 0.95,
    "cocircular_lattice_nudged": 0.2,
    "cocircular_lattice_scaled": 0.95,
    "rectangle_wide": 0.95,
    "rectangle_wide_nudged": 0.9,
    "ulp_lattice_1e9": 0.07,
    "spacing_1e-9": 0.03,
}


# ---------------------------------------------------------------------------
# Bulk comparisons
# ---------------------------------------------------------------------------


def test_total_case_count():
    n = sum(len(v[0]) for v in ORIENT_CASES.values()) + sum(len(v[0]) for v in INCIRCLE_CASES.values())
    assert n >= 100_000


@pytest.mark.parametrize("name", sorted(ORIENT_CASES))
def test_orient2d_bulk(name):
    a, b, c = ORIENT_CASES[name]
    counters = np.zeros(4, dtype=np.int64)
    got = P.orient2d_many(a, b, c, counters=counters)
    want = ref_orient_many(a, b, c)
    bad = np.flatnonzero(got != want)
    assert bad.size == 0, f"{bad.size} mismatches, first at {bad[0]}: {a[bad[0]]}, {b[bad[0]]}, {c[bad[0]]}"
    assert counters[P.ORIENT_CALLS] == len(a)
    assert counters[P.INCIRCLE_CALLS] == 0
    exact_share = counters[P.ORIENT_EXACT] / len(a)
    # the degenerate categories must really exercise the exact stage
    assert exact_share >= MIN_ORIENT_EXACT_SHARE.get(name, 0.0), exact_share
    if name in ("collinear_offset", "diagonal"):
        assert np.all(want == 0)
    if name == "uniform":
        assert exact_share < 0.01


@pytest.mark.parametrize("name", sorted(INCIRCLE_CASES))
def test_incircle_bulk(name):
    a, b, c, d = INCIRCLE_CASES[name]
    counters = np.zeros(4, dtype=np.int64)
    got = P.incircle_many(a, b, c, d, counters=counters)
    want = ref_incircle_many(a, b, c, d)
    bad = np.flatnonzero(got != want)
    assert bad.size == 0, f"{bad.size} mismatches, first at {bad[0]}: {a[bad[0]]}, {b[bad[0]]}, {c[bad[0]]}, {d[bad[0]]}"
    assert counters[P.INCIRCLE_CALLS] == len(a)
    assert counters[P.ORIENT_CALLS] == 0
    exact_share = counters[P.INCIRCLE_EXACT] / len(a)
    assert exact_share >= MIN_INCIRCLE_EXACT_SHARE.get(name, 0.0), exact_share
    if name in ("cocircular_lattice", "cocircular_lattice_scaled", "rectangle_wide"):
        assert np.all(want == 0)
    if name == "uniform":
        assert exact_share < 0.01


def _sample_rows(arrs, n, seed):
    rng = np.random.default_rng(seed)
    idx = rng.choice(len(arrs[0]), size=min(n, len(arrs[0])), replace=False)
    return [p[idx] for p in arrs]


def test_references_agree_with_fraction():
    """The scaled-integer bulk reference equals direct Fraction evaluation (sampled)."""
    for i, arrs in enumerate(ORIENT_CASES.values()):
        a, b, c = _sample_rows(arrs, 150, i)
        fast = ref_orient_many(a, b, c)
        slow = [frac_orient(*a[j], *b[j], *c[j]) for j in range(len(a))]
        assert list(fast) == slow
    for i, arrs in enumerate(INCIRCLE_CASES.values()):
        a, b, c, d = _sample_rows(arrs, 100, 100 + i)
        fast = ref_incircle_many(a, b, c, d)
        slow = [frac_incircle(*a[j], *b[j], *c[j], *d[j]) for j in range(len(a))]
        assert list(fast) == slow


def test_scalar_matches_fraction_sample():
    """Scalar (dispatcher) calls from Python agree with Fraction on a sample of every category."""
    for i, arrs in enumerate(ORIENT_CASES.values()):
        a, b, c = _sample_rows(arrs, 100, 1000 + i)
        for j in range(len(a)):
            assert P.orient2d(*a[j], *b[j], *c[j]) == frac_orient(*a[j], *b[j], *c[j])
    for i, arrs in enumerate(INCIRCLE_CASES.values()):
        a, b, c, d = _sample_rows(arrs, 60, 2000 + i)
        for j in range(len(a)):
            assert P.incircle(*a[j], *b[j], *c[j], *d[j]) == frac_incircle(*a[j], *b[j], *c[j], *d[j])


# ---------------------------------------------------------------------------
# Conventions and fixtures
# ---------------------------------------------------------------------------


def test_orient2d_conventions():
    assert P.orient2d(0.0, 0.0, 1.0, 0.0, 0.0, 1.0) == 1
    assert P.orient2d(0.0, 0.0, 0.0, 1.0, 1.0, 0.0) == -1
    assert P.orient2d(0.0, 0.0, 1.0, 1.0, 2.0, 2.0) == 0
    assert P.orient2d(0.0, 0.0, 0.0, 0.0, 0.0, 0.0) == 0
    assert P.orient2d(0, 0, 1, 0, 0, 1) == 1  # ints are converted to float64
    assert isinstance(P.orient2d(0.0, 0.0, 1.0, 0.0, 0.0, 1.0), int)
    assert P.orient2d_fast(0.0, 0.0, 1.0, 0.0, 0.0, 1.0) == 1.0


def test_incircle_conventions():
    # counter-clockwise triangle on the unit circle
    a, b, c = (1.0, 0.0), (0.0, 1.0), (-1.0, 0.0)
    assert P.orient2d(*a, *b, *c) == 1
    assert P.incircle(*a, *b, *c, 0.0, 0.0) == 1  # inside
    assert P.incircle(*a, *b, *c, 0.5, -0.5) == 1
    assert P.incircle(*a, *b, *c, 2.0, 0.0) == -1  # outside
    assert P.incircle(*a, *b, *c, 0.0, -1.0) == 0  # on the circle
    assert P.incircle(*a, *b, *c, 0.6, -0.8) == frac_incircle(*a, *b, *c, 0.6, -0.8)
    # clockwise triangle: sign flips
    assert P.incircle(*c, *b, *a, 0.0, 0.0) == -1
    assert P.incircle(*c, *b, *a, 2.0, 0.0) == 1
    assert P.incircle(*c, *b, *a, 0.0, -1.0) == 0
    assert P.incircle_fast(*a, *b, *c, 0.0, 0.0) > 0


def test_counted_variants():
    counters = np.zeros(6, dtype=np.int64)
    assert P.orient2d_counted(0.0, 0.0, 1.0, 0.0, 0.0, 1.0, counters) == 1
    assert P.orient2d_counted(0.0, 0.0, 1.0, 1.0, 3.0, 3.0, counters) == 0
    assert P.incircle_counted(1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, counters) == 1
    assert P.incircle_counted(1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0, -1.0, counters) == 0
    assert (P.ORIENT_CALLS, P.ORIENT_EXACT, P.INCIRCLE_CALLS, P.INCIRCLE_EXACT) == (0, 1, 2, 3)
    assert list(counters) == [2, 1, 2, 1, 0, 0]


def test_kettner_classroom_example():
    """Kettner et al., "Classroom examples of robustness problems": orient(p, q, r) near the line y = x."""
    q = (12.0, 12.0)
    r = (24.0, 24.0)
    n = 48
    xs = [0.5]
    for _ in range(n - 1):
        xs.append(float(np.nextafter(xs[-1], np.inf)))
    got_fast_wrong = 0
    seen = set()
    counters = np.zeros(4, dtype=np.int64)
    for px, py in itertools.product(xs, xs):
        want = frac_orient(px, py, *q, *r)
        assert P.orient2d_counted(px, py, *q, *r, counters) == want
        assert P.orient2d(*q, *r, px, py) == want  # cyclic rotation
        assert P.orient2d(*r, *q, px, py) == -want
        got_fast_wrong += sgn(P.orient2d_fast(px, py, *q, *r)) != want
        seen.add(want)
    assert seen == {-1, 0, 1}
    assert counters[P.ORIENT_EXACT] > 0
    # the second example of the paper
    p0 = (0.50000000000002531, 0.5000000000000171)
    q2 = (17.300000000000001, 17.300000000000001)
    r2 = (24.00000000000005, 24.0000000000000517765)
    x, y = p0
    for i in range(16):
        yy = y
        for j in range(16):
            assert P.orient2d(x, yy, *q2, *r2) == frac_orient(x, yy, *q2, *r2)
            yy = float(np.nextafter(yy, np.inf))
        x = float(np.nextafter(x, np.inf))
    # the non-robust sibling really gets many of these wrong (over 1000 of 2304)
    assert got_fast_wrong > 100


def test_incircle_hard_fixture():
    # a cocircular lattice quadruple at a 1e9 offset, then ulp-perturbed d in a 7x7 grid
    pts = CIRCLE[[0, len(CIRCLE) // 3, len(CIRCLE) // 2, len(CIRCLE) - 5]] + 1e9
    a, b, c, d = (tuple(map(float, p)) for p in pts)
    assert P.incircle(*a, *b, *c, *d) == 0 == frac_incircle(*a, *b, *c, *d)
    signs = set()
    for i in range(-3, 4):
        for j in range(-3, 4):
            dx = d[0] + i * 2.0**-23
            dy = d[1] + j * 2.0**-23
            want = frac_incircle(*a, *b, *c, dx, dy)
            signs.add(want)
            assert P.incircle(*a, *b, *c, dx, dy) == want
            assert P.incircle(*b, *c, *a, dx, dy) == want
            assert P.incircle(*b, *a, *c, dx, dy) == -want
    assert signs == {-1, 0, 1}


def test_extreme_range():
    # coordinates at the documented limits
    for s in (1e-100, 1e-60, 1.0, 1e60, 1e100):
        assert P.orient2d(0.0, 0.0, s, s, 3 * s, 3 * s) == 0
        x = float(np.nextafter(3 * s, np.inf))
        assert P.orient2d(0.0, 0.0, s, s, x, 3 * s) == frac_orient(0.0, 0.0, s, s, x, 3 * s) == -1
    for s in (1e-50, 1e-20, 1e20, 1e50):
        sq = [(s, 0.0), (0.0, s), (-s, 0.0), (0.0, -s)]
        coords = [v for p in sq for v in p]
        assert P.incircle(*coords) == 0
        coords[-1] = float(np.nextafter(-s, 0.0))
        assert P.incircle(*coords) == frac_incircle(*coords) == 1


# ---------------------------------------------------------------------------
# Vectorised API
# ---------------------------------------------------------------------------


def test_many_broadcasting_and_validation():
    rng = np.random.default_rng(5)
    a = rng.uniform(-1, 1, (50, 2))
    b = np.array([0.25, 0.5])
    c = [[-0.5, 0.125]]
    got = P.orient2d_many(a, b, c)
    assert got.dtype == np.int8 and got.shape == (50,)
    assert list(got) == [P.orient2d(*p, *b, *c[0]) for p in a]
    d = rng.uniform(-1, 1, (50, 2))
    got = P.incircle_many(a, b, c, d)
    assert list(got) == [P.incircle(*p, *b, *c[0], *q) for p, q in zip(a, d)]
    assert P.orient2d_many(np.empty((0, 2)), b, c).shape == (0,)
    with pytest.raises(ValueError):
        P.orient2d_many(a, a[:3], b)
    with pytest.raises(ValueError):
        P.orient2d_many(np.zeros((4, 3)), b, b)
    with pytest.raises(ValueError):
        P.orient2d_many(a, b, c, counters=np.zeros(4, dtype=np.int32))


# ---------------------------------------------------------------------------
# Calling from nopython code
# ---------------------------------------------------------------------------


@njit
def _njit_user(pts, counters):
    # counts ccw triples and points strictly inside the circle of the first three points
    n = pts.shape[0]
    ccw = 0
    inside = 0
    for i in range(n - 2):
        s = P.orient2d(pts[i, 0], pts[i, 1], pts[i + 1, 0], pts[i + 1, 1], pts[i + 2, 0], pts[i + 2, 1])
        if s > 0:
            ccw += 1
        P.orient2d_counted(pts[i, 0], pts[i, 1], pts[i + 1, 0], pts[i + 1, 1], pts[i + 2, 0], pts[i + 2, 1], counters)
    for i in range(3, n):
        o = P.orient2d(pts[0, 0], pts[0, 1], pts[1, 0], pts[1, 1], pts[2, 0], pts[2, 1])
        s = P.incircle(pts[0, 0], pts[0, 1], pts[1, 0], pts[1, 1], pts[2, 0], pts[2, 1], pts[i, 0], pts[i, 1])
        P.incircle_counted(pts[0, 0], pts[0, 1], pts[1, 0], pts[1, 1], pts[2, 0], pts[2, 1], pts[i, 0], pts[i, 1], counters)
        if s * o > 0:
            inside += 1
    return ccw, inside


def test_callable_from_njit():
    rng = np.random.default_rng(9)
    pts = rng.integers(0, 4, (200, 2)).astype(np.float64)
    counters = np.zeros(4, dtype=np.int64)
    ccw, inside = _njit_user(pts, counters)
    exp_ccw = sum(frac_orient(*pts[i], *pts[i + 1], *pts[i + 2]) > 0 for i in range(len(pts) - 2))
    o = frac_orient(*pts[0], *pts[1], *pts[2])
    exp_inside = sum(frac_incircle(*pts[0], *pts[1], *pts[2], *pts[i]) * o > 0 for i in range(3, len(pts)))
    assert (ccw, inside) == (exp_ccw, exp_inside)
    assert counters[P.ORIENT_CALLS] == len(pts) - 2
    assert counters[P.INCIRCLE_CALLS] == len(pts) - 3


# ---------------------------------------------------------------------------
# Expansion arithmetic building blocks
# ---------------------------------------------------------------------------


def exp_value(h, n):
    return sum((Fraction(float(v)) for v in h[:n]), Fraction(0))


def check_expansion(h, n):
    """Zero-eliminated, increasing magnitudes, nonoverlapping (|e_i| below the lowest set bit of e_{i+1})."""
    comps = [float(v) for v in h[:n]]
    assert n >= 1
    if n == 1:
        return
    assert all(v != 0.0 for v in comps)
    for lo, hi in zip(comps, comps[1:]):
        assert abs(lo) < abs(hi)
        # nonoverlapping: lo is smaller than the lowest set bit of hi
        m, e = math.frexp(hi)
        mant = int(m * 2**53)
        low_bit = (mant & -mant) * 2.0 ** (e - 53)
        assert abs(lo) < low_bit


finite = st.floats(-1e30, 1e30, allow_nan=False, allow_infinity=False, allow_subnormal=False).map(
    lambda x: x if abs(x) > 1e-30 else 0.0
)


def build_expansion(values):
    h = np.zeros(len(values) + 1)
    n = P.float_expansion(float(values[0]), h)
    for v in values[1:]:
        n = P.grow_expansion(h, n, float(v), h)
    return h, n


@settings(max_examples=150, deadline=None)
@given(finite, finite)
def test_error_free_transformations(a, b):
    x, y = P.two_sum(a, b)
    assert Fraction(x) + Fraction(y) == Fraction(a) + Fraction(b) and x == a + b
    x, y = P.two_diff(a, b)
    assert Fraction(x) + Fraction(y) == Fraction(a) - Fraction(b) and x == a - b
    x, y = P.two_product(a, b)
    assert Fraction(x) + Fraction(y) == Fraction(a) * Fraction(b) and x == a * b
    hi, lo = P.split(a)
    assert hi + lo == a
    if abs(a) >= abs(b):
        x, y = P.fast_two_sum(a, b)
        assert Fraction(x) + Fraction(y) == Fraction(a) + Fraction(b)


@settings(max_examples=120, deadline=None)
@given(st.lists(finite, min_size=1, max_size=7), st.lists(finite, min_size=1, max_size=5), finite)
def test_expansion_arithmetic(xs, ys, s):
    e, elen = build_expansion(xs)
    f, flen = build_expansion(ys)
    check_expansion(e, elen)
    ev, fv = exp_value(e, elen), exp_value(f, flen)
    assert ev == sum(map(Fraction, xs), Fraction(0))
    assert P.expansion_sign(e, elen) == sgn(ev)
    assert P.estimate(e, elen) == pytest.approx(float(ev), rel=1e-15, abs=1e-300)

    h = np.empty(elen + flen)
    n = P.expansion_sum(e, elen, f, flen, h)
    assert exp_value(h, n) == ev + fv
    check_expansion(h, n)
    n = P.expansion_diff(e, elen, f, flen, h)
    assert exp_value(h, n) == ev - fv
    check_expansion(h, n)

    h = np.empty(2 * elen)
    n = P.scale_expansion(e, elen, s, h)
    assert exp_value(h, n) == ev * Fraction(s)
    check_expansion(h, n)

    h = np.empty(2 * elen * flen)
    n = P.expansion_product(e, elen, f, flen, h)
    assert exp_value(h, n) == ev * fv
    check_expansion(h, n)
    assert P.expansion_sign(h, n) == sgn(ev * fv)
    n2 = P.compress_expansion(h, n, h)
    assert n2 <= n
    assert exp_value(h, n2) == ev * fv

    g = np.empty(elen)
    assert P.expansion_negate(e, elen, g) == elen
    assert exp_value(g, elen) == -ev


@settings(max_examples=150, deadline=None)
@given(finite, finite, finite, finite)
def test_small_expansion_helpers(a, b, c, d):
    F = Fraction
    h = np.empty(8)
    n = P.diff_expansion(a, b, h)
    assert n <= 2 and exp_value(h, n) == F(a) - F(b)
    n = P.product_expansion(a, b, h)
    assert n <= 2 and exp_value(h, n) == F(a) * F(b)
    n = P.det2_expansion(a, b, c, d, h)
    assert n <= 4 and exp_value(h, n) == F(a) * F(b) - F(c) * F(d)
    check_expansion(h, n)
    n = P.diff_product_expansion(a, b, c, d, h)
    assert n <= 8 and exp_value(h, n) == (F(a) - F(b)) * (F(c) - F(d))
    check_expansion(h, n)


# ---------------------------------------------------------------------------
# Hypothesis properties of the predicates
# ---------------------------------------------------------------------------

coord = st.one_of(
    st.integers(-3, 3).map(float),
    # one-ulp neighbours of small integers (not of 0: those are subnormal, out of range)
    st.sampled_from([-3.0, -2.0, -1.0, 1.0, 2.0, 3.0]).flatmap(
        lambda v: st.sampled_from([v, float(np.nextafter(v, np.inf)), float(np.nextafter(v, -np.inf))])
    ),
    st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False, allow_subnormal=False).map(lambda x: x if abs(x) > 1e-40 else 0.0),
    st.integers(-3, 3).map(lambda v: 1e9 + v * 2.0**-23),
)
point = st.tuples(coord, coord)


@settings(max_examples=300, deadline=None)
@given(point, point, point)
def test_orient2d_properties(a, b, c):
    s = P.orient2d(*a, *b, *c)
    assert s == frac_orient(*a, *b, *c)
    assert P.orient2d(*b, *c, *a) == s
    assert P.orient2d(*c, *a, *b) == s
    assert P.orient2d(*b, *a, *c) == -s
    assert P.orient2d(*a, *c, *b) == -s
    # point reflection keeps orientation, mirroring flips it, power-of-two scaling keeps it
    assert P.orient2d(-a[0], -a[1], -b[0], -b[1], -c[0], -c[1]) == s
    assert P.orient2d(-a[0], a[1], -b[0], b[1], -c[0], c[1]) == -s
    assert P.orient2d(a[0] * 0.125, a[1] * 0.125, b[0] * 0.125, b[1] * 0.125, c[0] * 0.125, c[1] * 0.125) == s


def _perm_parity(p):
    p = list(p)
    parity = 1
    for i in range(len(p)):
        while p[i] != i:
            j = p[i]
            p[i], p[j] = p[j], p[i]
            parity = -parity
    return parity


@settings(max_examples=200, deadline=None)
@given(point, point, point, point, st.permutations(range(4)))
def test_incircle_properties(a, b, c, d, perm):
    pts = [a, b, c, d]
    s = P.incircle(*a, *b, *c, *d)
    assert s == frac_incircle(*a, *b, *c, *d)
    # even permutations of a, b, c keep the sign, odd ones flip it
    assert P.incircle(*b, *c, *a, *d) == s
    assert P.incircle(*c, *a, *b, *d) == s
    assert P.incircle(*b, *a, *c, *d) == -s
    # more generally: the 4x4 lifted determinant is alternating in all four points
    q = [pts[i] for i in perm]
    assert P.incircle(*q[0], *q[1], *q[2], *q[3]) == _perm_parity(perm) * s
    assert P.incircle(-a[0], a[1], -b[0], b[1], -c[0], c[1], -d[0], d[1]) == -s
    # "d inside the circle" is independent of the orientation of a, b, c
    o = P.orient2d(*a, *b, *c)
    assert P.incircle(*b, *a, *c, *d) * P.orient2d(*b, *a, *c) == s * o


def test_fused_multiply_add_rounds_once():
    from vorobench.core.predicates.expansion import fused_multiply_add
    from numba import njit

    @njit
    def fma(a, b, c):
        return fused_multiply_add(a, b, c)

    # (1 + 2^-52)(1 - 2^-52) - 1 = -2^-104 exactly; a product rounded first gives 0
    assert fma(1.0 + 2.0 ** -52, 1.0 - 2.0 ** -52, -1.0) == -(2.0 ** -104)
    assert fma(3, 2.0, 1.0) == 7.0                  # integer arguments are converted


@settings(max_examples=300, deadline=None)
@given(finite, finite)
def test_two_product_fused_and_split_agree(a, b):
    # two_product takes whichever the CPU allows (HAS_FMA); both must give the exact error
    # (finite's magnitudes, 1e-30 to 1e30, keep every error above the subnormal range)
    from vorobench.core.predicates.expansion import _two_product_fused, _two_product_split
    for x, y in (_two_product_fused(a, b), _two_product_split(a, b)):
        assert x == a * b and Fraction(x) + Fraction(y) == Fraction(a) * Fraction(b)
