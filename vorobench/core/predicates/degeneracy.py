"""How close a configuration of sites is to degenerate, in roundings of the data: the smallest
change of its sites that makes a predicate's determinant zero, to first order, in units of one
rounding of a coordinate (``EPSILON * extent``) and of a lifted coordinate x**2 + y**2 - w
(``EPSILON * lift_extent``).

A floating-point library decides a predicate from coordinates it holds to about one ulp of the
data's extent, and from lifted coordinates (the paraboloid x**2 + y**2 - w of a convex-hull or
regular-triangulation method such as Qhull's) it holds to about one ulp of theirs; its formulas
lose a few more. It can only decide wrongly where changing the input by a few such roundings
would change the answer. That is the rule by which the certifier and
the comparer forgive a floating-point library (``vorobench.core.tolerances.NEAR_DEGENERATE_ULPS``):
a topology that differs from the exact one only at configurations within that distance of a
degeneracy is honest rounding (backward stable); anywhere else it is wrong. It is decided per
configuration, is invariant under translation and scaling by a power of two, and is the same at
10 and at 10^6 sites.

Each function returns |det| / (EPSILON * (extent * G + lift_extent * G_w)), where det is the
determinant (in floats), G the l1 norm of its gradient over the coordinates and G_w over the
lifted coordinates. ``extent``: half the longer side of the sites' bounding box;
``lift_extent``: the largest lifted coordinate about the box's centre, ``2 extent**2`` plus the
largest weight's magnitude (:func:`lift_extent`). Zero when the float value is zero; infinite
when the determinant is nonzero and does not depend on the input.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from vorobench.core.predicates.expansion import EPSILON

__all__ = ["lift_extent", "orient2d_ulps", "incircle_ulps", "power_test_ulps"]


def lift_extent(extent: float, largest_weight: float = 0.0) -> float:
    """The lifted coordinates' extent for sites of ``extent`` and weights up to ``largest_weight``
    in magnitude: |x**2 + y**2 - w| about the bounding box's centre is at most this."""
    return 2.0 * extent * extent + abs(largest_weight)


@njit(cache=True)
def _ratio(det, rounding):
    if det == 0.0:
        return 0.0
    if rounding == 0.0:
        return np.inf
    return abs(det) / (EPSILON * rounding)


@njit(cache=True)
def orient2d_ulps(ax, ay, bx, by, cx, cy, extent):
    """How far a, b, c are from collinear, in roundings of a coordinate (about the distance of the
    worst-placed point from the line of the other two, over three)."""
    det = (ax - cx) * (by - cy) - (ay - cy) * (bx - cx)
    gradient = (abs(bx - cx) + abs(by - cy)) + (abs(cx - ax) + abs(cy - ay)) + (abs(ax - bx) + abs(ay - by))
    return _ratio(det, extent * gradient)


@njit(cache=True)
def _row_rounding(px, py, pw, jx, jy, jw, kx, ky, kw, lx, ly, lw, extent, lift_extent):
    """extent |d det / d p|_1 + lift_extent |d det / d lift_p| for the row p of the lifted determinant
    whose other rows are j, k, l: +-orient(j, k, l) * 2 (p - o), o the (power) centre of j, k, l,
    written without the division: 2 orient (p - l) - N, N the centre's numerator."""
    jx, jy, kx, ky, x, y = jx - lx, jy - ly, kx - lx, ky - ly, px - lx, py - ly
    jl, kl = jx * jx + jy * jy - (jw - lw), kx * kx + ky * ky - (kw - lw)
    orient = jx * ky - jy * kx
    gx = 2.0 * orient * x - (jl * ky - kl * jy)
    gy = 2.0 * orient * y - (kl * jx - jl * kx)
    return extent * (abs(gx) + abs(gy)) + lift_extent * abs(orient)


@njit(cache=True)
def _lifted_ulps(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw, extent, lift_extent):
    adx, ady, adw = ax - dx, ay - dy, aw - dw
    bdx, bdy, bdw = bx - dx, by - dy, bw - dw
    cdx, cdy, cdw = cx - dx, cy - dy, cw - dw
    alift = adx * adx + ady * ady - adw
    blift = bdx * bdx + bdy * bdy - bdw
    clift = cdx * cdx + cdy * cdy - cdw
    det = alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) + clift * (adx * bdy - bdx * ady)
    rounding = (_row_rounding(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw, extent, lift_extent)
                + _row_rounding(bx, by, bw, ax, ay, aw, cx, cy, cw, dx, dy, dw, extent, lift_extent)
                + _row_rounding(cx, cy, cw, ax, ay, aw, bx, by, bw, dx, dy, dw, extent, lift_extent)
                + _row_rounding(dx, dy, dw, ax, ay, aw, bx, by, bw, cx, cy, cw, extent, lift_extent))
    return _ratio(det, rounding)


@njit(cache=True)
def incircle_ulps(ax, ay, bx, by, cx, cy, dx, dy, extent, lift_extent):
    """How far a, b, c, d are from cocircular, in roundings of the data."""
    return _lifted_ulps(ax, ay, 0.0, bx, by, 0.0, cx, cy, 0.0, dx, dy, 0.0, extent, lift_extent)


@njit(cache=True)
def power_test_ulps(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw, extent, lift_extent):
    """How far four weighted sites are from having coplanar lifts, in roundings of the data."""
    return _lifted_ulps(ax, ay, aw, bx, by, bw, cx, cy, cw, dx, dy, dw, extent, lift_extent)
