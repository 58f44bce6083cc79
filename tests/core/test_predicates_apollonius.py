"""The exact Apollonius predicates: a vertex touches its three disks exactly, equal radii give
the circumcentre and the incircle test, ties are found where they were built, hidden disks."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobench.core.predicates import incircle, orient2d
from vorobench.core.predicates.apollonius import QuadraticNumber, conflict, hidden_by, vertex


def _circumcentre(a, b, c):
    """The circumcentre of three points, in Fractions (textbook formula)."""
    (ax, ay), (bx, by), (cx, cy) = ((Fraction(x), Fraction(y)) for x, y in (a, b, c))
    d = 2 * (ax * (by - cy) + bx * (cy - ay) + cx * (ay - by))
    ux = ((ax * ax + ay * ay) * (by - cy) + (bx * bx + by * by) * (cy - ay) + (cx * cx + cy * cy) * (ay - by)) / d
    uy = ((ax * ax + ay * ay) * (cx - bx) + (bx * bx + by * by) * (ax - cx) + (cx * cx + cy * cy) * (bx - ax)) / d
    return ux, uy


def _value(q: QuadraticNumber) -> Fraction:
    """A QuadraticNumber known to be rational."""
    assert q.b == 0 or q.d == 0 or _is_square(q.d)
    root = _sqrt_rational(q.d) if q.b != 0 else 0
    return Fraction(q.a) + Fraction(q.b) * root


def _is_square(d) -> bool:
    d = Fraction(d)
    return _isqrt_exact(d.numerator) is not None and _isqrt_exact(d.denominator) is not None


def _isqrt_exact(n: int):
    import math
    r = math.isqrt(n)
    return r if r * r == n else None


def _sqrt_rational(d) -> Fraction:
    d = Fraction(d)
    return Fraction(_isqrt_exact(d.numerator), _isqrt_exact(d.denominator))


_SMALL = st.integers(-6, 6)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(_SMALL, _SMALL), min_size=4, max_size=4, unique=True), st.integers(0, 5))
def test_equal_radii_give_the_circumcentre_and_the_incircle_test(points, radius):
    disks = [(x, y, radius) for x, y in points]
    a, b, c, d = points
    o = orient2d(*a, *b, *c)
    v, reverse = vertex(disks, 0, 1, 2), vertex(disks, 0, 2, 1)
    if o == 0:
        assert v is None and reverse is None
        return
    if o < 0:
        v, reverse = reverse, v
    assert reverse is None                      # one vertex per triangle, for its ccw order
    assert v is not None
    ux, uy = _circumcentre(a, b, c)
    assert (_value(v.x), _value(v.y)) == (ux, uy)
    # the common distance is the circumradius minus the radius
    assert (v.radius + QuadraticNumber(radius, 0, 0)).sign() > 0
    # disk d closer than the circle (-1) exactly when point d is inside it
    assert conflict(disks, v, 3) == -incircle(*a, *b, *c, *d) * o


_COORD = st.integers(-40, 40).map(lambda k: k / 4)
_RADIUS = st.integers(0, 40).map(lambda k: k / 8)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(_COORD, _COORD, _RADIUS), min_size=3, max_size=3))
def test_a_vertex_touches_its_three_disks_exactly(disks):
    for order in ((0, 1, 2), (0, 2, 1)):
        v = vertex(disks, *order)
        if v is None:
            continue
        assert [conflict(disks, v, m) for m in range(3)] == [0, 0, 0]
        # and in floats: |v - p_m| - r_m is R for each
        x, y, radius = v.as_floats()
        for px, py, r in disks:
            assert abs(np.hypot(x - px, y - py) - r - radius) <= 1e-9 * (1 + abs(radius) + abs(x) + abs(y))


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(_COORD, _COORD, _RADIUS), min_size=3, max_size=3), st.integers(1, 16))
def test_growing_every_radius_moves_no_vertex(disks, grow):
    # |x - p| - (r + c) = (|x - p| - r) - c: the same diagram, every R smaller by c
    grown = [(x, y, r + grow / 8) for x, y, r in disks]
    for order in ((0, 1, 2), (0, 2, 1)):
        v, w = vertex(disks, *order), vertex(grown, *order)
        assert (v is None) == (w is None)
        if v is not None:
            assert (v.x - w.x).sign() == 0 and (v.y - w.y).sign() == 0
            assert (v.radius - w.radius - QuadraticNumber(Fraction(grow, 8), 0, 0)).sign() == 0


def test_a_disk_touching_the_circle_is_a_tie_and_a_last_bit_decides():
    # the circle of centre (0, 0) and R = 5 touches (12, 5) r 8, (-3, 4) r 0 and (0, -10) r 5;
    # (6, 8) r 5 touches it too; a radius one ulp larger reaches inside, one smaller does not
    five = 5.0
    disks = [(12, 5, 8), (-3, 4, 0), (0, -10, 5), (6, 8, five), (6, 8, np.nextafter(five, 9)),
             (6, 8, np.nextafter(five, 0))]
    v = vertex(disks, 0, 1, 2)
    assert v is not None and v.as_floats() == pytest.approx((0, 0, 5))
    assert [conflict(disks, v, m) for m in (3, 4, 5)] == [0, -1, 1]


def test_overlapping_disks_have_a_vertex_inside_them_with_a_negative_radius():
    disks = [(0, 0, 3), (4, 0, 3), (2, 3, 3)]
    v = vertex(disks, 0, 1, 2)
    assert v is not None and float(v.radius) < 0
    assert [conflict(disks, v, m) for m in range(3)] == [0, 0, 0]


def test_collinear_centres_with_different_radii_still_have_vertices():
    # a small disk between two big ones: circles above and below the line. Seen from below,
    # left, right and middle turn counter-clockwise; seen from above, left, middle and right
    disks = [(-4, 0, 2), (0, 0, 0.5), (4, 0, 2)]
    above, below = vertex(disks, 0, 1, 2), vertex(disks, 0, 2, 1)
    assert above is not None and below is not None
    assert float(above.y) > 0 > float(below.y)
    for v in (above, below):
        assert [conflict(disks, v, m) for m in range(3)] == [0, 0, 0]


def test_hidden_by_means_inside_touching_included():
    assert hidden_by((1, 0, 1), (0, 0, 3))          # well inside
    assert hidden_by((2, 0, 1), (0, 0, 3))          # touching from inside: no interior left
    assert not hidden_by((2.5, 0, 1), (0, 0, 3))    # overlapping, partly outside
    assert not hidden_by((0, 0, 3), (1, 0, 1))      # the big one is not inside the small
    assert hidden_by((0, 0, 1), (0, 0, 1))          # a copy: each hides the other
    with pytest.raises(ValueError, match="radius must be >= 0"):
        hidden_by((0, 0, -1), (0, 0, 1))


def test_quadratic_numbers_decide_their_sign_exactly():
    two = QuadraticNumber(Fraction(0), Fraction(1), Fraction(2))       # sqrt 2
    close = Fraction(14142135623730951, 10 ** 16)                       # just above sqrt 2
    assert (two - QuadraticNumber(close, 0, 0)).sign() == -1
    assert (QuadraticNumber(close - Fraction(1, 10 ** 16), 0, 0) - two).sign() == -1
    assert (two * two - QuadraticNumber(2, 0, 0)).sign() == 0
    assert float(QuadraticNumber(Fraction(10 ** 8), Fraction(-1), Fraction(10 ** 16 - 1))) == pytest.approx(5e-9)


@pytest.mark.parametrize("scale", [2.0 ** -200, 2.0 ** -60, 2.0 ** 60, 2.0 ** 200])
def test_vertices_in_floats_scale_with_the_disks_far_outside_the_double_range_of_their_parts(scale):
    # the discriminant grows like the sixth power of the coordinates: 2**1200 at 2**200
    disks = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.5)]
    unit = vertex(disks, 0, 1, 2).as_floats()
    scaled = vertex([tuple(scale * c for c in d) for d in disks], 0, 1, 2).as_floats()
    assert scaled == pytest.approx(tuple(scale * c for c in unit), rel=1e-15)


def test_numpy_integers_and_float32_are_taken_as_the_numbers_they_hold():
    rows = [[0, 0, 0], [4, 0, 0], [0, 4, 1]]
    expected = vertex(rows, 0, 1, 2).as_floats()
    for dtype in (np.int64, np.int32, np.float32, np.float64):
        assert vertex(np.array(rows, dtype=dtype), 0, 1, 2).as_floats() == expected
    assert hidden_by(np.array([1, 0, 1], dtype=np.int64), np.array([0, 0, 3], dtype=np.int32))


def _decimal_value(q: QuadraticNumber):
    from decimal import Decimal, localcontext
    with localcontext() as ctx:
        ctx.prec = 80
        a, b, d = (Fraction(int(v.numerator), int(v.denominator)) for v in (q.a, q.b, q.d))
        dec = lambda f: Decimal(f.numerator) / Decimal(f.denominator)
        return dec(a) + dec(b) * dec(d).sqrt()


_small = st.fractions(min_value=-20, max_value=20, max_denominator=8)


@settings(max_examples=300, deadline=None)
@given(_small, _small, st.integers(0, 30), _small, _small, st.integers(0, 30))
def test_compare_across_quadratic_fields(a1, b1, d1, a2, b2, d2):
    from decimal import Decimal, localcontext
    from vorobench.core.predicates.apollonius import compare, rational
    x = QuadraticNumber(rational(a1), rational(b1), rational(d1))
    y = QuadraticNumber(rational(a2), rational(b2), rational(d2))
    with localcontext() as ctx:
        ctx.prec = 80
        gap = _decimal_value(x) - _decimal_value(y)
    want = 0 if abs(gap) < Decimal(10) ** -60 else (1 if gap > 0 else -1)
    assert compare(x, y) == want and compare(y, x) == -want


def test_compare_finds_ties_written_in_different_fields():
    from vorobench.core.predicates.apollonius import compare, rational
    q = lambda a, b, d: QuadraticNumber(rational(a), rational(b), rational(d))
    assert compare(q(0, 1, 8), q(0, 2, 2)) == 0                 # sqrt(8) = 2 sqrt(2)
    assert compare(q(1, 3, 12), q(1, 2, 27)) == 0               # 3 sqrt(12) = 2 sqrt(27)
    assert compare(q(5, 0, 3), q(2, 1, 9)) == 0                 # 5 = 2 + sqrt(9)
    assert compare(q(0, 1, 2), q(rational(99, 70), 0, 0)) == -1     # 140/99 < sqrt(2) < 99/70
    assert compare(q(0, 1, 2), q(rational(140, 99), 0, 0)) == 1
    assert compare(q(1, 1, 2), q(0, 1, 3)) == 1 and compare(q(0, 1, 3), q(1, 1, 2)) == -1


def _vertex_on_branch(disks, i, j, k):
    """The vertex of disks i, j, k on the bisector branch of i and j, in whichever turn exists."""
    return vertex(disks, i, j, k) or vertex(disks, i, k, j)


@pytest.mark.parametrize("radii", [(1.0, 1.0), (1.0, 0.0), (0.0, 1.5)])
def test_branch_order_runs_with_cell_i_on_the_left(radii):
    # i at the origin, j at (4, 0): perp(p_j - p_i) points up, and cell i (left of the
    # upward direction) is the side of i; a third disk far below gives a vertex before one
    # from a third disk far above, whatever the radii bend the branch to
    from vorobench.core.predicates.apollonius import branch_order
    disks = [(0.0, 0.0, radii[0]), (4.0, 0.0, radii[1]), (2.0, -9.0, 0.5), (2.0, 9.0, 0.25)]
    below, above = _vertex_on_branch(disks, 0, 1, 2), _vertex_on_branch(disks, 0, 1, 3)
    assert below is not None and above is not None
    assert branch_order(disks, 0, 1, below, above) == -1
    assert branch_order(disks, 0, 1, above, below) == 1
    assert branch_order(disks, 1, 0, below, above) == 1           # cell j on the left: downwards
    assert branch_order(disks, 0, 1, below, below) == 0


def test_branch_order_agrees_with_the_floats_of_random_vertices():
    from vorobench.core.predicates.apollonius import branch_order
    rng = np.random.default_rng(11)
    checked = 0
    for _ in range(40):
        disks = [tuple(v) for v in np.column_stack([rng.random((6, 2)) * 10, rng.random(6)])]
        points = [v for k in range(2, 6) if (v := _vertex_on_branch(disks, 0, 1, k)) is not None]
        (xi, yi, _), (xj, yj, _) = disks[0], disks[1]
        for u in points:
            for w in points:
                ux, uy, _ = u.as_floats()
                wx, wy, _ = w.as_floats()
                gap = -(yj - yi) * (ux - wx) + (xj - xi) * (uy - wy)
                if abs(gap) > 1e-9 * (1 + abs(ux) + abs(uy) + abs(wx) + abs(wy)):
                    assert branch_order(disks, 0, 1, u, w) == (1 if gap > 0 else -1)
                    checked += 1
    assert checked > 50


def test_apex_asymptotes_and_turns_of_branches():
    """The apex lies on its branch (its two disks tie there exactly, on the segment between the
    centres); each asymptote u satisfies u . a = -s |u| exactly (|u| = |a|^2); ``turn`` agrees with
    floats on vectors of two different fields."""
    import math
    from vorobench.core.predicates.apollonius import apex, asymptote, turn

    rng = np.random.default_rng(11)
    for _ in range(200):
        disks = [tuple(row) for row in np.column_stack([rng.random((4, 2)), 0.3 * rng.random(4)])]
        (xi, yi, ri), (xj, yj, rj) = (tuple(Fraction(v) for v in disks[m]) for m in (0, 1))
        ax, ay, s = xj - xi, yj - yi, rj - ri
        if s * s >= ax * ax + ay * ay:
            with pytest.raises(ValueError):
                apex(disks, 0, 1)
            continue
        top = apex(disks, 0, 1)
        assert conflict(disks, top, 0) == 0 and conflict(disks, top, 1) == 0
        x, y, _ = top.as_floats()
        assert abs((x - float(xi)) * float(ay) - (y - float(yi)) * float(ax)) < 1e-12   # on the segment
        for end in (1, -1):
            ux, uy = asymptote(disks, 0, 1, end)
            dot = ux.scaled(ax) + uy.scaled(ay)
            assert dot.b == 0 and dot.a == -s * (ax * ax + ay * ay)
            assert (ux.scaled(-ay) + uy.scaled(ax)).sign() == end          # the end ahead runs along perp(a)
        try:
            u, w = asymptote(disks, 0, 1, 1), asymptote(disks, 2, 3, -1)
        except ValueError:
            continue
        fu, fw = [float(c) for c in u], [float(c) for c in w]
        cross, dot = fu[0] * fw[1] - fu[1] * fw[0], fu[0] * fw[0] + fu[1] * fw[1]
        assert turn(u, w) == (int(math.copysign(1, cross)), int(math.copysign(1, dot)))

