"""Exact predicates for disks as sites (Apollonius diagrams), in rational arithmetic.

A disk is (x, y, r), r >= 0; the distance from a point v to it is |v - p| - r
(docs/apollonius.md). The vertex of three disks i, j, k is the centre v of a circle of
radius R with |v - p_m| - r_m = R for m = i, j, k (R may be negative where the disks
overlap); it is a vertex of the diagram for the ordered triple (i, j, k) when the centres
p_i, p_j, p_k lie counter-clockwise around v, each in the direction of its own cell.

Derivation (translated so that p_i is the origin: u = v - p_i, a_m = p_m - p_i,
s_m = r_m - r_i, rho = R + r_i = |u|): subtracting |u|^2 = rho^2 from
|u - a_m|^2 = (rho + s_m)^2 leaves two planes in (u_x, u_y, rho),

    a_m . u + s_m rho = (|a_m|^2 - s_m^2) / 2        (m = j, k),

whose common line X0 + t d (d = n_j x n_k, X0 a rational point of it) meets the cone
u_x^2 + u_y^2 = rho^2 where t solves a quadratic with rational coefficients. So every
coordinate of a vertex is a + b sqrt(D) with rationals a, b and one D per triple, and each
sign below is decided exactly by :class:`QuadraticNumber` (squaring once). A root is a vertex
when rho + s_m = R + r_m >= 0 for all three disks (the circle touches each from outside) and
the centres turn counter-clockwise around it.

This is the exact stage, written for clarity: Python rationals (``gmpy2.mpq`` where installed,
``fractions.Fraction`` otherwise), used by the oracle and by tests. Float filters in front of
it come with the constructions that need speed.
"""

from __future__ import annotations

import decimal
import functools
import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Optional, Sequence

try:  # GMP's rationals, several times faster; the answers are the same
    from gmpy2 import mpq as rational
except ImportError:  # pragma: no cover - gmpy2 is a dependency
    rational = Fraction

__all__ = ["Disk", "QuadraticNumber", "ApolloniusVertex", "hidden_by", "vertex", "conflict", "compare", "branch_order",
           "apex", "asymptote", "turn", "direction_key", "rational"]

#: A disk as the caller gives it: (x, y, r), floats or rationals
Disk = Sequence[float]


@dataclass(frozen=True)
class QuadraticNumber:
    """The real number a + b sqrt(d), with rationals a, b and d >= 0."""

    a: object
    b: object
    d: object

    def _same_field(self, other: "QuadraticNumber") -> None:
        if other.d != self.d and self.b != 0 and other.b != 0:
            raise ValueError("numbers of different quadratic fields")

    def __add__(self, other: "QuadraticNumber") -> "QuadraticNumber":
        self._same_field(other)
        return QuadraticNumber(self.a + other.a, self.b + other.b, self.d if self.b != 0 else other.d)

    def __sub__(self, other: "QuadraticNumber") -> "QuadraticNumber":
        self._same_field(other)
        return QuadraticNumber(self.a - other.a, self.b - other.b, self.d if self.b != 0 else other.d)

    def __mul__(self, other: "QuadraticNumber") -> "QuadraticNumber":
        self._same_field(other)
        d = self.d if self.b != 0 else other.d
        return QuadraticNumber(self.a * other.a + self.b * other.b * d, self.a * other.b + self.b * other.a, d)

    def scaled(self, c) -> "QuadraticNumber":
        """This number times the rational c."""
        return QuadraticNumber(self.a * c, self.b * c, self.d)

    def sign(self) -> int:
        """The exact sign: of a + b sqrt(d), from the signs of a and b and, where they differ,
        a^2 against b^2 d."""
        sa = (self.a > 0) - (self.a < 0)
        sb = (self.b > 0) - (self.b < 0) if self.d != 0 else 0
        if sb == 0 or sa == sb:
            return sa if sa != 0 else sb
        if sa == 0:
            return sb
        # a and b sqrt(d) of opposite signs: the one of larger magnitude wins
        diff = self.a * self.a - self.b * self.b * self.d
        return sa * ((diff > 0) - (diff < 0))

    def __float__(self) -> float:
        """The value to an ulp: evaluated in 60-digit decimals with an exponent range no input
        leaves (d grows like the sixth power of the coordinates, so it leaves the double
        range long before they do), as a + b sqrt(d) where the two terms have one sign, else
        as (a^2 - b^2 d) / (a - b sqrt(d)), whose numerator is exact: nothing cancels."""
        with decimal.localcontext(_DECIMALS):
            a = _decimal(self.a)
            if self.b == 0 or self.d == 0:
                return float(a)
            root = _decimal(self.b) * _decimal(self.d).sqrt()
            if (self.a >= 0) == (self.b > 0):
                return float(a + root)
            return float(_decimal(self.a * self.a - self.b * self.b * self.d) / (a - root))


#: Decimal arithmetic for :meth:`QuadraticNumber.__float__`: 60 digits, and exponents far beyond
#: any product of the predicates' inputs
_DECIMALS = decimal.Context(prec=60, Emax=10**9, Emin=-10**9)


def _decimal(q) -> decimal.Decimal:
    """A rational as a Decimal of the current context (one rounding)."""
    q = Fraction(int(q.numerator), int(q.denominator))
    return decimal.Decimal(q.numerator) / decimal.Decimal(q.denominator)


def _q(value) -> QuadraticNumber:
    return QuadraticNumber(rational(value), rational(0), rational(0))


@dataclass(frozen=True)
class ApolloniusVertex:
    """The vertex of the ordered triple ``sites``: centre (x, y) and radius R (the common
    distance |v - p_m| - r_m), each exact as a + b sqrt(d)."""

    sites: tuple[int, int, int]
    x: QuadraticNumber
    y: QuadraticNumber
    radius: QuadraticNumber
    #: a double root: the bisector branches of the three disks touch here without crossing
    double: bool = False

    def as_floats(self) -> tuple[float, float, float]:
        """(x, y, R) each to a few ulps (see :meth:`QuadraticNumber.__float__`)."""
        return float(self.x), float(self.y), float(self.radius)


def _rational(value):
    """A float, an int or a numpy scalar of either, as an exact rational."""
    if hasattr(value, "item"):           # numpy scalars: gmpy2 takes Python numbers only
        value = value.item()
    return rational(value)


def _disk(disk: Disk) -> tuple:
    x, y, r = (_rational(v) for v in disk)
    if r < 0:
        raise ValueError(f"a disk's radius must be >= 0, got {float(r)!r}")
    return x, y, r


def hidden_by(small: Disk, big: Disk) -> bool:
    """Whether disk ``small`` lies inside disk ``big`` (|p_s - p_b| + r_s <= r_b, touching
    included): then no point is closer to it, and its cell is empty (or has no interior)."""
    sx, sy, sr = _disk(small)
    bx, by, br = _disk(big)
    gap = br - sr
    return gap >= 0 and gap * gap >= (sx - bx) ** 2 + (sy - by) ** 2


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def _turn(u_x: QuadraticNumber, u_y: QuadraticNumber, a, b) -> tuple[int, int]:
    """Signs of (a - u) x (b - u) and (a - u) . (b - u): whether centre b is counter-clockwise
    of centre a as seen from u, and whether the two lie on one side (a, b rational points
    relative to p_i)."""
    ax, ay = _q(a[0]) - u_x, _q(a[1]) - u_y
    bx, by = _q(b[0]) - u_x, _q(b[1]) - u_y
    return (ax * by - ay * bx).sign(), (ax * bx + ay * by).sign()


def _counter_clockwise(u_x: QuadraticNumber, u_y: QuadraticNumber, centres) -> bool:
    """Whether the directions from u to the three centres (relative to p_i) turn counter-
    clockwise: at least two of the three consecutive turns positive (in clockwise order at
    most one is). Two centres may lie in opposite directions (the centre of a right
    triangle's circle is on its hypotenuse); two in one direction cannot both have a cell
    at u (the nearer disk lies inside the farther one), and are refused."""
    positive = 0
    for m in range(3):
        cross, dot = _turn(u_x, u_y, centres[m], centres[(m + 1) % 3])
        if cross == 0 and dot >= 0:
            return False
        positive += cross > 0
    return positive >= 2


#: The unit roundoff of doubles, for the float filters' error bounds.
_EPS = 2.0 ** -53


#: The float filters trust magnitudes in [2^-300, 2^300] only: their products and error bounds
#: then neither overflow nor underflow (a rational that rounds to zero or infinity is no guide).
_TRUSTED = (2.0 ** -300, 2.0 ** 300)


def _float(q) -> Optional[float]:
    """A rational as a float, or None outside the trusted magnitudes (0 stays 0)."""
    if q == 0:
        return 0.0
    try:
        value = float(q)
    except OverflowError:
        return None
    return value if _TRUSTED[0] <= abs(value) <= _TRUSTED[1] else None


def _approx(q: QuadraticNumber) -> tuple[float, float]:
    """q in floats and a bound on its error (inf where the floats are not trusted)."""
    a = _float(q.a)
    if a is None:
        return 0.0, math.inf
    if q.b == 0 or q.d == 0:
        return a, _EPS * abs(a)
    b, d = _float(q.b), _float(q.d)
    if b is None or d is None:
        return 0.0, math.inf
    root = b * math.sqrt(d)
    return a + root, 8 * _EPS * (abs(a) + abs(root))


def _float_sign(value: float, err: float) -> Optional[int]:
    """The sign of a float known within ``err``, or None when the error could flip it."""
    if value > err:
        return 1
    if value < -err:
        return -1
    return None


def _difference(value: float, err: float, centre) -> tuple[float, float]:
    """centre - value, and its error bound (the rational centre rounds once)."""
    c = _float(centre)
    if c is None or err == math.inf:
        return 0.0, math.inf
    d = c - value
    return d, err + _EPS * (abs(c) + abs(d))


def _counter_clockwise_in_floats(ux: tuple[float, float], uy: tuple[float, float], centres) -> Optional[bool]:
    """:func:`_counter_clockwise` from floats with error bounds, or None where they cannot tell."""
    offsets = [(_difference(*ux, cx), _difference(*uy, cy)) for cx, cy in centres]
    positive = 0
    for m in range(3):
        ((ax, eax), (ay, eay)), ((bx, ebx), (by, eby)) = offsets[m], offsets[(m + 1) % 3]
        bound_cross = (abs(ax) * eby + abs(by) * eax + eax * eby + abs(ay) * ebx + abs(bx) * eay + eay * ebx
                       + 4 * _EPS * (abs(ax * by) + abs(ay * bx)) + 2.0 ** -900)     # (and underflow)
        cross = _float_sign(ax * by - ay * bx, 2 * bound_cross)
        if cross is None:                      # (a zero turn needs the exact test's look at the dot product)
            return None
        positive += cross > 0
    return positive >= 2


def _touches_from_outside(rho: QuadraticNumber, sj, sk) -> bool:
    """R + r_m >= 0 for the three disks, with R + r_i = rho: a float filter, then exact."""
    value, err = _approx(rho)
    for s in (0, sj, sk):
        shift = _float(s)
        sign = None if shift is None else _float_sign(value + shift, 2 * (err + _EPS * (abs(shift) + abs(value + shift))))
        if sign is None:
            sign = (rho + _q(s)).sign()
        if sign < 0:
            return False
    return True


def vertex(disks: Sequence[Disk], i: int, j: int, k: int) -> Optional[ApolloniusVertex]:
    """The vertex of the diagram of disks i, j, k in that counter-clockwise order, exactly, or
    None if there is none (no circle touches the three from outside with their centres
    counter-clockwise around it; the centres' planes parallel: the triple has no single vertex)."""
    px, py, pr = _disk(disks[i])
    rel = []
    for m in (j, k):
        x, y, r = _disk(disks[m])
        rel.append((x - px, y - py, r - pr))
    (ajx, ajy, sj), (akx, aky, sk) = rel
    # the planes n_m . X = h_m in X = (u_x, u_y, rho)
    n1, n2 = (ajx, ajy, sj), (akx, aky, sk)
    h1 = (ajx * ajx + ajy * ajy - sj * sj) / 2
    h2 = (akx * akx + aky * aky - sk * sk) / 2
    d = (n1[1] * n2[2] - n1[2] * n2[1], n1[2] * n2[0] - n1[0] * n2[2], n1[0] * n2[1] - n1[1] * n2[0])
    dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2]
    if dd == 0:
        return None
    # the point of the line nearest the origin: a combination of n1 and n2
    n11 = sum(c * c for c in n1)
    n22 = sum(c * c for c in n2)
    n12 = sum(a * b for a, b in zip(n1, n2))
    c1 = (h1 * n22 - h2 * n12) / dd
    c2 = (h2 * n11 - h1 * n12) / dd
    x0 = tuple(c1 * a + c2 * b for a, b in zip(n1, n2))
    # X0 + t d on the cone u_x^2 + u_y^2 - rho^2 = 0
    qa = d[0] * d[0] + d[1] * d[1] - d[2] * d[2]
    qb = 2 * (x0[0] * d[0] + x0[1] * d[1] - x0[2] * d[2])
    qc = x0[0] * x0[0] + x0[1] * x0[1] - x0[2] * x0[2]
    zero = rational(0)
    if qa == 0:
        if qb == 0:
            return None
        roots = [QuadraticNumber(-qc / qb, zero, zero)]
    else:
        disc = qb * qb - 4 * qa * qc
        if disc < 0:
            return None
        half = 1 / (2 * qa)
        roots = [QuadraticNumber(-qb * half, sign * half, disc) for sign in (1, -1)] if disc > 0 else \
            [QuadraticNumber(-qb * half, zero, zero)]
    centres = ((zero, zero), (ajx, ajy), (akx, aky))
    found = []
    for t in roots:
        ux, uy, rho = (_q(x0[c]) + t.scaled(d[c]) for c in range(3))
        # the circle touches each disk from outside: R + r_m = rho + s_m >= 0
        if not _touches_from_outside(rho, sj, sk):
            continue
        turning = _counter_clockwise_in_floats(_approx(ux), _approx(uy), centres)
        if turning is None:
            turning = _counter_clockwise(ux, uy, centres)
        if turning:
            found.append((ux, uy, rho))
    if not found:
        return None
    if len(found) > 1:
        # two circles with the centres counter-clockwise around both cannot both bound cells
        # of three disks; it would be a bug in the derivation, not an input to round away
        raise ArithmeticError(f"disks {i}, {j}, {k}: two Apollonius circles qualify")
    ux, uy, rho = found[0]
    double = qa != 0 and len(roots) == 1
    return ApolloniusVertex((i, j, k), ux + _q(px), uy + _q(py), rho - _q(pr), double)


def conflict(disks: Sequence[Disk], v: ApolloniusVertex, m: int) -> int:
    """Sign of (distance from v's centre to disk m) - R, exactly: -1 when disk m is strictly
    closer than v's three disks (v is not a vertex of a diagram with m: a conflict), 0 when it
    touches v's circle too (a vertex of degree four or more), +1 when it is farther."""
    x, y, r = _disk(disks[m])
    reach = v.radius + _q(r)                  # R + r_m: the distance |v - p_m| would have at a tie
    if reach.sign() < 0:
        return 1
    dx, dy = v.x - _q(x), v.y - _q(y)
    return (dx * dx + dy * dy - reach * reach).sign()


def compare(x: QuadraticNumber, y: QuadraticNumber) -> int:
    """The exact sign of x - y, for numbers of any two quadratic fields (two vertices of
    different triples): -1, 0 or +1."""
    bx = x.b if x.d != 0 else 0                       # a root of 0 is no root
    by = y.b if y.d != 0 else 0
    a = x.a - y.a
    if by == 0:
        return QuadraticNumber(a, bx, x.d).sign()
    if bx == 0:
        return QuadraticNumber(a, -by, y.d).sign()
    if x.d == y.d:
        return QuadraticNumber(a, bx - by, x.d).sign()
    # a + bx sqrt(dx) - by sqrt(dy): the sign of the first part against that of the second
    first = QuadraticNumber(a, bx, x.d)
    s1 = first.sign()
    s2 = -1 if by > 0 else 1
    if s1 == 0 or s1 == s2:
        return s2 if s1 == 0 else s1
    # opposite signs: the larger magnitude wins, and (a + bx sqrt(dx))^2 - by^2 dy is again
    # one number of the first field
    gap = QuadraticNumber(a * a + bx * bx * x.d - by * by * y.d, 2 * a * bx, x.d).sign()
    return s1 if gap > 0 else s2 if gap < 0 else 0


def branch_order(disks: Sequence[Disk], i: int, j: int, u: ApolloniusVertex, w: ApolloniusVertex) -> int:
    """The order of two points u, w of the bisector branch of disks i and j, along the
    direction in which cell i lies on the left: -1 if u comes first, 0 if they are one point,
    +1 if w comes first. Points of one branch are in order of their coordinate along
    perp(p_j - p_i): a branch is a graph over the perpendicular of its focal axis
    (docs/apollonius.md, "The DCEL of disks")."""
    xi, yi, _ = _disk(disks[i])
    xj, yj, _ = _disk(disks[j])
    px, py = -(yj - yi), xj - xi                      # perp(p_j - p_i), rational
    position_u = u.x.scaled(px) + u.y.scaled(py)
    position_w = w.x.scaled(px) + w.y.scaled(py)
    return compare(position_u, position_w)


def apex(disks: Sequence[Disk], i: int, j: int) -> ApolloniusVertex:
    """The point of the bisector branch of i and j on the segment between their centres (its
    vertex, nearest both centres), as a point of the branch with the common distance R; its
    ``sites`` are (i, j, -1). Neither disk may lie inside the other (then there is no branch).

    With a = p_j - p_i and s = r_j - r_i it is p_i + a (|a| - s) / (2 |a|), where the distance
    to i, t - r_i, equals |a| - t - r_j: every coordinate is in the field of sqrt(|a|^2)."""
    xi, yi, ri = _disk(disks[i])
    xj, yj, rj = _disk(disks[j])
    ax, ay, s = xj - xi, yj - yi, rj - ri
    norm2 = ax * ax + ay * ay
    if s * s >= norm2:
        raise ValueError(f"disks {i} and {j}: one lies inside the other, they have no bisector branch")
    half = rational(1) / 2
    # p_i + a / 2 - a s / (2 |a|), with 1 / |a| = sqrt(|a|^2) / |a|^2
    x = QuadraticNumber(xi + ax * half, -ax * s * half / norm2, norm2)
    y = QuadraticNumber(yi + ay * half, -ay * s * half / norm2, norm2)
    radius = QuadraticNumber(-s * half - ri, half, norm2)
    return ApolloniusVertex((i, j, -1), x, y, radius)


def asymptote(disks: Sequence[Disk], i: int, j: int, end: int) -> tuple[QuadraticNumber, QuadraticNumber]:
    """The direction (not normalised) in which the bisector branch of i and j runs out to
    infinity: ``end`` +1 for the end reached going with cell i on the left, -1 for the other.

    Seen from p_i the branch spans the directions u with u . a + s > 0 (a = p_j - p_i, s =
    r_j - r_i: along them disk j ends up closer); its ends are the two unit u with u . a = -s:
    (-s a + end sqrt(|a|^2 - s^2) perp(a)) / |a|^2, scaled here by |a|^2."""
    xi, yi, ri = _disk(disks[i])
    xj, yj, rj = _disk(disks[j])
    ax, ay, s = xj - xi, yj - yi, rj - ri
    root = ax * ax + ay * ay - s * s
    if root <= 0:
        raise ValueError(f"disks {i} and {j}: one lies inside the other, they have no bisector branch")
    return QuadraticNumber(-s * ax, -end * ay, root), QuadraticNumber(-s * ay, end * ax, root)


def _sign_across_fields(x: QuadraticNumber, y: QuadraticNumber, d) -> int:
    """The sign of x + y sqrt(d), x and y of one field, d a rational >= 0."""
    sx, sy = x.sign(), y.sign() if d != 0 else 0
    if sy == 0 or sx == sy:
        return sx if sx != 0 else sy
    if sx == 0:
        return sy
    # opposite signs: the larger magnitude wins
    return sx * (x * x - (y * y).scaled(d)).sign()


def turn(u: tuple[QuadraticNumber, QuadraticNumber], w: tuple[QuadraticNumber, QuadraticNumber]) -> tuple[int, int]:
    """Signs of u x w and u . w for two vectors whose coordinates may lie in two different
    quadratic fields (asymptotes of two branches): whether w is counter-clockwise of u, and
    whether the two point to one side."""
    (ux, uy), (wx, wy) = u, w
    fields = {q.d for q in (wx, wy) if q.b != 0 and q.d != 0}
    if len(fields) > 1:
        raise ValueError("a vector's two coordinates lie in different fields")
    if not fields or all(q.b == 0 or q.d == 0 or q.d in fields for q in (ux, uy)):
        return (ux * wy - uy * wx).sign(), (ux * wx + uy * wy).sign()
    (d,) = fields

    def combination(p: QuadraticNumber, r: QuadraticNumber, q: QuadraticNumber, t: QuadraticNumber) -> int:
        # p r + q t with r, t in the field of sqrt(d): (p r.a + q t.a) + (p r.b + q t.b) sqrt(d)
        return _sign_across_fields(p.scaled(r.a) + q.scaled(t.a), p.scaled(r.b) + q.scaled(t.b), d)

    minus_wx = QuadraticNumber(-wx.a, -wx.b, wx.d)
    return combination(ux, wy, uy, minus_wx), combination(ux, wx, uy, wy)


def _half_turn(w: tuple[QuadraticNumber, QuadraticNumber]) -> int:
    """0 for directions in [0, pi) from the positive x axis, 1 for [pi, 2 pi)."""
    sy, sx = w[1].sign(), w[0].sign()
    return 0 if sy > 0 or (sy == 0 and sx > 0) else 1


def _by_angle(w1: tuple[QuadraticNumber, QuadraticNumber], w2: tuple[QuadraticNumber, QuadraticNumber]) -> int:
    h1, h2 = _half_turn(w1), _half_turn(w2)
    if h1 != h2:
        return h1 - h2
    cross, _ = turn(w1, w2)
    return -cross


#: A sort key of directions (vectors of quadratic numbers, of any fields) by their angle from
#: the positive x axis, counter-clockwise, exactly: the order of a cell's rays to infinity.
direction_key = functools.cmp_to_key(_by_angle)
