"""The geometric property each family promises, checked from its definition in exact arithmetic."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from scipy.spatial import ConvexHull

import datasets_gen as dg
from datasets_gen import degenerate as dgm
from datasets_gen.circles import CIRCLE_LADDER, lattice_points

SIZES = [0, 1, 2, 3, 4, 10, 100, 1000]
SEEDS = [0, 1, 17]


def int_rows(pts: np.ndarray) -> list[tuple[int, int]]:
    """Rows as exact Python ints, failing if any coordinate is not an integer."""
    assert np.array_equal(pts, np.floor(pts)), "non-integer coordinate"
    return [(int(x), int(y)) for x, y in pts.tolist()]


def frac_rows(pts: np.ndarray) -> list[tuple[Fraction, Fraction]]:
    """Rows as exact Fractions of the stored float64 values."""
    return [(Fraction(x), Fraction(y)) for x, y in pts.tolist()]


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("seed", SEEDS)
def test_grid_is_exact_integer_lattice(n: int, seed: int) -> None:
    pts = dg.generate("grid", n, seed)
    k = 0
    while k * k < n:
        k += 1
    assert sorted(int_rows(pts)) == [(i, j) for i in range(k) for j in range(k)]


@pytest.mark.parametrize("n", SIZES)
def test_lattice_rotated_is_integer_lattice_on_3_4_basis(n: int) -> None:
    pts = dg.generate("lattice_rotated", n, seed=3)
    k = math.isqrt(dg.actual_n("lattice_rotated", n))
    a, b = 3, 4
    seen = set()
    for x, y in int_rows(pts):
        # Invert x = a i - b j, y = b i + a j exactly: i = (a x + b y)/25, j = (a y - b x)/25.
        i, ri = divmod(a * x + b * y, a * a + b * b)
        j, rj = divmod(a * y - b * x, a * a + b * b)
        assert ri == rj == 0 and 0 <= i < k and 0 <= j < k
        seen.add((i, j))
    assert len(seen) == k * k == len(pts)


@pytest.mark.parametrize("n", SIZES)
def test_near_grid_is_within_1e12_of_lattice_and_not_exact(n: int) -> None:
    pts = dg.generate("near_grid", n, seed=4)
    rounded = np.rint(pts)
    assert np.abs(pts - rounded).max(initial=0.0) <= 1e-12
    assert sorted(int_rows(rounded)) == sorted(int_rows(dg.generate("grid", n, seed=4)))
    if n >= 4:
        assert not np.array_equal(pts, rounded)
        assert len({tuple(r) for r in pts.tolist()}) == len(pts)


@pytest.mark.parametrize("n", SIZES + [5000, 6144, 7000])
def test_cocircular_points_on_one_integer_circle(n: int) -> None:
    pts = dg.generate("cocircular", n, seed=9)
    rows = int_rows(pts)
    assert len(rows) == min(n, 6144) == len(set(rows))
    if not rows:
        return
    r2 = dgm.cocircular_circle(len(rows)).r2
    assert {x * x + y * y for x, y in rows} == {r2}
    assert max(max(abs(x), abs(y)) for x, y in rows) < 2**26
    # Claimed exactness in float64: the squared radius computed in floats equals R2 exactly.
    assert np.all(pts[:, 0] * pts[:, 0] + pts[:, 1] * pts[:, 1] == float(r2))
    assert float(r2) == r2


def test_cocircular_choice_depends_on_seed_and_small_n_uses_small_circle() -> None:
    assert dgm.cocircular_circle(3).r2 == 5
    assert {tuple(r) for r in dg.generate("cocircular", 8, 0).tolist()} == {
        (float(x), float(y)) for x, y in lattice_points(CIRCLE_LADDER[0])
    }
    a = {tuple(r) for r in dg.generate("cocircular", 50, 1).tolist()}
    b = {tuple(r) for r in dg.generate("cocircular", 50, 2).tolist()}
    assert a != b


def test_circle_ladder_counts_and_bounds() -> None:
    for circle in CIRCLE_LADDER:
        pts = lattice_points(circle)
        assert len(pts) == len(set(pts)) == circle.count
        assert all(x * x + y * y == circle.r2 for x, y in pts)
        assert circle.r2 < 2**53
    counts = [c.count for c in CIRCLE_LADDER]
    assert counts == sorted(counts) and counts[-1] == dgm.COCIRCULAR_MAX_N


@pytest.mark.parametrize("n", SIZES + [9000])
def test_cocircular_many_concentric_integer_circles(n: int) -> None:
    pts = dg.generate("cocircular_many", n, seed=2)
    rows = int_rows(pts)
    assert len(rows) == min(n, dgm.COCIRCULAR_MANY_MAX_N) == len(set(rows))
    if not rows:
        return
    radii = sorted({x * x + y * y for x, y in rows})
    base = radii[0]
    assert radii == [s * s * base for s in range(1, min(4, n) + 1)]
    assert max(max(abs(x), abs(y)) for x, y in rows) < 2**26
    per_circle = [sum(x * x + y * y == r for x, y in rows) for r in radii]
    assert max(per_circle) - min(per_circle) <= 1


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("seed", SEEDS)
def test_collinear_exact_cross_products_and_distinct(n: int, seed: int) -> None:
    rows = int_rows(dg.generate("collinear", n, seed))
    assert len(rows) == n == len(set(rows))
    if n < 2:
        return
    (x0, y0), (x1, y1) = rows[0], rows[1]
    for x, y in rows[2:]:
        assert (x1 - x0) * (y - y0) - (y1 - y0) * (x - x0) == 0
    # and on the documented line (-5, 11) + t (3, 7)
    assert all((x + 5) * 7 - (y - 11) * 3 == 0 for x, y in rows)


@pytest.mark.parametrize("n", SIZES)
def test_duplicates_has_exact_repeats(n: int) -> None:
    pts = dg.generate("duplicates", n, seed=6)
    assert len(pts) == n
    distinct = {tuple(r) for r in pts.tolist()}
    repeats = n - len(distinct)
    assert repeats == dgm.duplicate_count(n)
    if n >= 2:
        assert repeats >= 1
    if n >= 10:
        assert repeats == math.ceil(0.3 * n)
    assert ((pts >= 0) & (pts < 1)).all()


@pytest.mark.parametrize("n", [3, 4, 5, 10, 50, 300])
@pytest.mark.parametrize("seed", SEEDS)
def test_parabola_exact_and_in_convex_position(n: int, seed: int) -> None:
    pts = dg.generate("parabola", n, seed)
    rows = frac_rows(pts)
    assert all(y == x * x for x, y in rows)
    assert len({x for x, _ in rows}) == n
    assert all(-1 <= x <= 1 for x, _ in rows)
    hull = ConvexHull(pts)
    assert sorted(hull.vertices.tolist()) == list(range(n))


def test_parabola_exact_at_larger_n() -> None:
    pts = dg.generate("parabola", 5000, seed=1)
    assert np.array_equal(pts[:, 1], pts[:, 0] * pts[:, 0])
    assert len(np.unique(pts[:, 0])) == 5000
    assert all(Fraction(y) == Fraction(x) ** 2 for x, y in pts[:200].tolist())


@pytest.mark.parametrize("n", SIZES)
def test_sorted_nondecreasing_x(n: int) -> None:
    pts = dg.generate("sorted", n, seed=8)
    assert np.all(np.diff(pts[:, 0]) >= 0)
    assert ((pts >= 0) & (pts < 1)).all()


def test_offset_and_scale_families_ranges() -> None:
    huge = dg.generate("huge_offset", 1000, seed=1)
    assert ((huge >= 1e9) & (huge <= 1e9 + 1)).all()
    tiny = dg.generate("tiny_spacing", 1000, seed=1)
    assert ((tiny >= 0) & (tiny < 1e-9)).all()


def test_random_family_shapes() -> None:
    n = 4000
    assert ((dg.generate("uniform", n) >= 0) & (dg.generate("uniform", n) < 1)).all()
    d = dg.generate("disk", n)
    assert (np.hypot(d[:, 0], d[:, 1]) <= 1).all()
    c = dg.generate("corners", n)
    assert ((c >= 0) & (c <= 1)).all()
    # both coordinates within 0.1 (2 sigma) of the corner for ~0.954^2 of the points
    assert np.mean(np.max(np.minimum(c, 1 - c), axis=1) < 0.1) > 0.85
    diag = dg.generate("diagonal", n)
    assert np.abs(diag[:, 0] - diag[:, 1]).max() < 0.02
    x = dg.generate("cross", n)
    off = np.minimum(np.abs(x[:, 1] - x[:, 0]), np.abs(x[:, 1] - (1 - x[:, 0])))
    assert off.max() < 0.02
    k = dg.generate("kuzmin", n)
    r = np.hypot(k[:, 0], k[:, 1])
    # Kuzmin: median radius is sqrt(3) (M(r) = 1/2), and the tail is heavy.
    assert 1.5 < np.median(r) < 2.0 and r.max() > 50
    g = dg.generate("normal", n)
    assert abs(g.mean()) < 0.1 and 0.9 < g.std() < 1.1
    cl = dg.generate("clusters", n)
    assert np.isfinite(cl).all()
