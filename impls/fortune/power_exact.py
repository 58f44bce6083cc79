"""The exact stage of the compiled weighted sweep: the reference's rational arithmetic, by index.

The compiled sweep (:mod:`impls.fortune.power_sweep`) decides each predicate with an interval
filter; when the interval holds 0 it calls one of these functions (from numba's object mode)
with site indices and *specs* of the points and times involved, and the answer is computed in
the rationals of :mod:`impls.fortune.power_reference`, the sweep's specification. A spec
``(kind, a, b, c)`` names a point and its time without coordinates:

* kind 0 (``SITE``): x = x_a at time y_a (a site's activation);
* kind 1 (``CENTRE``): the power centre of a, b, c at the time its power is reached;
* kind 2 (``CONTACT``): c_ab, where the wavefront of a first touches that of the lower b.

The sites live here for the duration of one build (:func:`exact_context`), converted to
rationals on the first call only: random inputs rarely need any. The rationals are GMP's
(``gmpy2.mpq``) where gmpy2 is installed, which decides a lattice's ties about three times
faster than :class:`fractions.Fraction` (near_grid at 10^5: 3.5 s -> 1.4 s per build), and
Fraction otherwise; the reference's formulas are the same for both, and the tests hold them to
the same answers.
"""

from __future__ import annotations

from contextlib import contextmanager
from fractions import Fraction
from numbers import Rational
from typing import Iterator, Optional

import numpy as np
from numpy.typing import NDArray

from impls.fortune.power_reference import Sweep, Time

__all__ = ["SITE", "CENTRE", "CONTACT", "exact_context", "time_order", "side", "power_gap",
           "same_point", "farther", "tied", "keeps_middle", "line_inside"]

SITE, CENTRE, CONTACT = 0, 1, 2

try:
    from gmpy2 import mpq as _gmp_rational
except ImportError:                     # a dependency, but the answers do not depend on it
    _gmp_rational = None

#: The rational type of the exact stage (the exact value of a float: ``rational(float(v))``).
rational = _gmp_rational if _gmp_rational is not None else Fraction

_inputs: Optional[tuple[NDArray[np.float64], NDArray[np.float64]]] = None
_geometry: Optional[Sweep] = None


@contextmanager
def exact_context(sites: NDArray[np.float64], weights: NDArray[np.float64]) -> Iterator[None]:
    """Make ``sites`` and ``weights`` the input the exact stage answers about, for one build."""
    global _inputs, _geometry
    _inputs, _geometry = (sites, weights), None
    try:
        yield
    finally:
        _inputs, _geometry = None, None


class _Rationals:
    """x[i] as a rational, made when first asked for (a build that needs a few exact decisions
    converts a few sites, not all n)."""

    def __init__(self, value) -> None:
        self.value, self.made = value, {}

    def __getitem__(self, i: int) -> Rational:
        got = self.made.get(i)
        if got is None:
            got = self.made[i] = self.value(i)
        return got


def _sweep() -> Sweep:
    """The reference's geometry over the current input, with its per-site numbers lazy."""
    global _geometry
    if _geometry is None:
        if _inputs is None:
            raise RuntimeError("the weighted sweep's exact stage was called outside exact_context")
        sites, weights = _inputs
        q = rational
        top = q(float(weights.max()))
        g = Sweep.__new__(Sweep)
        g.n = sites.shape[0]
        g.x = _Rationals(lambda i: q(float(sites[i, 0])))
        g.y = _Rationals(lambda i: q(float(sites[i, 1])))
        g.s = _Rationals(lambda i: top - q(float(weights[i])))
        g.q = _Rationals(lambda i: g.x[i] ** 2 + g.y[i] ** 2 + g.s[i])
        g.spec_points = {}
        _geometry = g
    return _geometry


#: Specs whose exact point is kept for the rest of a build: a degenerate point is asked about
#: again and again (near_grid at 10^5: 12,558 exact points asked for, 1,678 of them distinct).
#: Dropped when full, so a build with millions of exact decisions stays within bounded memory.
_POINTS_KEPT = 1 << 16


def _point(kind: int, a: int, b: int, c: int) -> tuple[tuple, tuple, Time, Rational]:
    """(cx, cy, time, h) of a spec, as the reference writes them: c = c0 + c1 sqrt(h)."""
    g = _sweep()
    kept = g.spec_points
    key = (kind, a, b, c)
    got = kept.get(key)
    if got is None:
        if len(kept) >= _POINTS_KEPT:
            kept.clear()
        got = kept[key] = _new_point(g, kind, a, b, c)
    return got


def _new_point(g: Sweep, kind: int, a: int, b: int, c: int) -> tuple[tuple, tuple, Time, Rational]:
    zero = rational(0)
    if kind == SITE:
        return (g.x[a], zero), (g.y[a], zero), Time(g.y[a]), zero
    if kind == CENTRE:
        v = g.power_centre(a, b, c)
        if v is None:
            raise RuntimeError(f"the power centre of collinear sites {a}, {b}, {c} was asked for (a bug)")
        h = g.ell(a, *v)
        return (v[0], zero), (v[1], zero), Time(v[1], h), h
    found = g.arc_contact(a, b)
    if found is None:
        raise RuntimeError(f"the contact of site {a} with the higher site {b} was asked for (a bug)")
    t, cx, cy, h = found
    return cx, cy, t, h


def time_order(k1: int, a1: int, b1: int, c1: int, k2: int, a2: int, b2: int, c2: int) -> int:
    """-1, 0 or 1 as the time of the first spec is before, at or after the second's."""
    return _point(k1, a1, b1, c1)[2].compare(_point(k2, a2, b2, c2)[2])


def side(left: int, right: int, kind: int, a: int, b: int, c: int) -> int:
    """Where the point of a spec lies against the breakpoint (left, right) at its time."""
    cx, _, t, h = _point(kind, a, b, c)
    return _sweep().side_of_breakpoint(left, right, cx, t.a, h)


def power_gap(j: int, k: int, kind: int, a: int, b: int, c: int) -> int:
    """The sign of l_j - l_k at the point of a spec (positive: k has the smaller power)."""
    cx, cy, _, h = _point(kind, a, b, c)
    return _sweep().power_gap(j, k, cx, cy, h)


def same_point(a1: int, b1: int, c1: int, a2: int, b2: int, c2: int) -> int:
    """1 if the power centres of (a1, b1, c1) and (a2, b2, c2) are one point, else 0."""
    g = _sweep()
    return int(g.power_centre(a1, b1, c1) == g.power_centre(a2, b2, c2))


def farther(i1: int, p1: int, i2: int, p2: int) -> int:
    """The sign of |p_i1 - p_p1|^2 - |p_i2 - p_p2|^2 (a partner of -1 is at distance 0)."""
    g = _sweep()

    def far(i: int, p: int) -> Rational:
        return rational(0) if p < 0 else (g.x[i] - g.x[p]) ** 2 + (g.y[i] - g.y[p]) ** 2
    d = far(i1, p1) - far(i2, p2)
    return (d > 0) - (d < 0)


def tied(a: int, b: int, c: int) -> int:
    """1 if b's cell among collinear a, b, c lies in their common bisector line, else 0."""
    return int(_sweep().tied(a, b, c))


def keeps_middle(a: int, b: int, c: int) -> int:
    """1 if, on the lowest row, b's line is strictly on the upper envelope of a's and c's."""
    return int(_sweep()._keeps_middle(a, b, c))


def line_inside(i: int, k: int, j: int) -> int:
    """For j collinear with i and k: 1 if the bisector line of i and k lies where i has no more
    power than j, else 0 (the two bisector lines are parallel: all of it or none)."""
    g = _sweep()
    # a point of the bisector of i and k: the foot of p_k on it, f = p_k + lam (p_k - p_i)
    nx, ny = g.x[k] - g.x[i], g.y[k] - g.y[i]
    nn = nx * nx + ny * ny
    lam = (g.s[k] - g.s[i] - nn) / (2 * nn)
    fx, fy = g.x[k] + lam * nx, g.y[k] + lam * ny
    zero = rational(0)
    return int(g.power_gap(j, i, (fx, zero), (fy, zero), zero) >= 0)
