"""Power-of-two scaling into the range where the predicates are exact, and back.

Why scaling is free
-------------------
Multiplying every coordinate by 2**k is exact (only the exponents change) as long as no
result leaves the float range, and it maps the Voronoi diagram onto the Voronoi diagram of
the scaled sites: every predicate keeps its sign, so the combinatorics are the same, and the
float arithmetic that places vertices (products, quotients, sums of coordinates) gives the
same significands, so the vertices scale back bit for bit. An input of any magnitude can
therefore be built where the predicates are exact, and its vertices scaled back.

The exact range (the rule)
--------------------------
:mod:`vorobench.core.predicates` is exact while no product underflows or overflows. A coordinate
of magnitude >= 2**-m (m + 52 bits below its leading one at most) and < 2**M makes a product
of k coordinates or their differences a multiple of 2**(-k (m + 52)) and smaller than about
2**(k (M + 1)); exact needs k (m + 52) <= 1074 (no bit below the smallest subnormal is lost)
and k (M + 1) well below 996 (where the product splitter overflows). The highest degree in
the coordinates is k = 6 (the sweep's squared circle radii N_x**2 + N_y**2 and their
comparisons; orient2d is degree 2, incircle and the breakpoint test 4 and 3), which allows
m <= 127 and M <= ~160; the range used, with room for the exactly computed circle tops
(ratios of such polynomials), is

    every nonzero coordinate of magnitude in [2**-100, 2**100)     (about [7.9e-31, 1.3e30]).

``EXACT_MIN_EXPONENT`` and ``EXACT_MAX_EXPONENT`` are its limits as :func:`math.frexp`
exponents (x = f 2**e, 0.5 <= |f| < 1): e in [-99, 100]. An input fits after one scaling iff
the frexp exponents of its largest and of its smallest nonzero magnitude differ by at most
``EXACT_EXPONENT_SPAN`` = 199, i.e. its nonzero magnitudes lie within a factor of about 2**199
(8e59) of each other, whatever their absolute size: 1e-300 and the subnormals (down to
2**-1074) are fine on their own, 1.0 together with 1e-300 is not (no float arithmetic can
weigh both in one exact decision). :func:`vorobench.prepare` refuses such inputs with
:class:`OutsideExactRange` (a ``ValueError``); zeros are always fine.

Where the sites are put (:func:`exact_shift`): inputs already inside the range are left as
they are (the hot path costs one pass for the two magnitudes). Others are scaled so that
their largest magnitude lies in [0.5, 1) -- the comfortable range for every library, where
an input and any power-of-two multiple of it are built identically -- unless that would push
the smallest nonzero magnitude below 2**-100; then just so far up that it does not.

Back: vertices are scaled by 2**-k. Far vertices of nearly collinear sites can leave the
float range then (sites near 1e300 whose vertex lies 1e8 times farther out); that diagram
has no float representation and is refused with :class:`OutsideExactRange` instead of
returning inf. Vertices that fall into the subnormal range are rounded once (to 2**-1074);
:mod:`vorobench.judge.certificate` and :mod:`vorobench.judge.comparison` allow for that rounding.

numpy only: a rule and its checks, no compiled kernels (``vorobench.core.prepare`` checks every input with it).
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["OutsideExactRange", "EXACT_MIN_EXPONENT", "EXACT_MAX_EXPONENT", "EXACT_EXPONENT_SPAN",
           "RANGE_TEXT", "magnitude_range", "check_exact_range", "exact_shift", "comfortable_shift",
           "scale_points", "scale_back_vertices", "smallest_normal", "exact_range_sites",
           "WEIGHT_MIN_EXPONENT", "WEIGHT_MAX_EXPONENT", "check_weight_range", "scale_weights"]

#: frexp exponents e (|x| in [2**(e-1), 2**e)) of nonzero coordinates where the predicates are
#: exact: |x| in [2**-100, 2**100).
EXACT_MIN_EXPONENT = -99
EXACT_MAX_EXPONENT = 100
#: Largest difference of frexp exponents that one power-of-two scaling fits into the range.
EXACT_EXPONENT_SPAN = EXACT_MAX_EXPONENT - EXACT_MIN_EXPONENT

#: frexp exponents of nonzero weights where the power predicates are exact, once the sites are
#: in the exact range and the weights scaled with them (by 2**(2k)): |w| in [2**-200, 2**200),
#: the range of squared coordinates (a weight is a squared length).
WEIGHT_MIN_EXPONENT = -199
WEIGHT_MAX_EXPONENT = 200

#: The rule in words, for error messages.
RANGE_TEXT = ("the exact range: nonzero coordinate magnitudes must fit in [2**-100, 2**100) "
              "after scaling by one power of two, i.e. lie within a factor of about 2**199 (8e59) "
              "of each other (any absolute size, subnormals included)")

_CHUNK = 1 << 16          # values per block: temporaries stay in cache and off the peak memory


class OutsideExactRange(ValueError):
    """The input (or its diagram) cannot be represented where the predicates are exact."""


def magnitude_range(values: ArrayLike) -> tuple[float, float]:
    """(largest |x|, smallest nonzero |x|) of finite values; (0.0, inf) if all are zero.

    One pass in blocks, without a full-size temporary (it runs before every build).
    """
    flat = np.asarray(values, dtype=np.float64).reshape(-1)
    hi, lo = 0.0, math.inf
    for start in range(0, flat.size, _CHUNK):
        a = np.abs(flat[start:start + _CHUNK])
        hi = max(hi, float(a.max()))
        lo = min(lo, float(np.min(a, where=a > 0, initial=math.inf)))
    return hi, lo


def _exponent(x: float) -> int:
    return math.frexp(x)[1]


def _row_of(points: NDArray[np.float64], magnitude: float) -> int:
    """The first row of (n, 2) ``points`` holding a coordinate of this magnitude (for messages)."""
    return int(np.flatnonzero((np.abs(points) == magnitude).any(axis=1))[0])


def check_exact_range(points: ArrayLike) -> tuple[float, float]:
    """(largest, smallest nonzero magnitude) of (n, 2) ``points``; :class:`OutsideExactRange`
    naming both (and their rows) when no power of two brings them into the exact range."""
    points = np.asarray(points, dtype=np.float64)
    hi, lo = magnitude_range(points)
    check_span(hi, lo, points)
    return hi, lo


def check_span(hi: float, lo: float, points: ArrayLike) -> None:
    """:class:`OutsideExactRange` naming the magnitudes ``hi`` and ``lo`` of ``points`` (and
    their rows) when no power of two brings both into the exact range."""
    if hi > 0 and _exponent(hi) - _exponent(lo) > EXACT_EXPONENT_SPAN:
        rows = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        raise OutsideExactRange(
            f"coordinates span more than {RANGE_TEXT}: magnitudes from {lo:.6g} (row {_row_of(rows, lo)}) "
            f"to {hi:.6g} (row {_row_of(rows, hi)}), a factor of 2**{_exponent(hi) - _exponent(lo)} in exponent")


def _placement(hi: float, lo: float) -> int:
    """k with hi 2**k in [0.5, 1), raised until lo 2**k >= 2**-100 (the span must fit)."""
    k = -_exponent(hi)
    if _exponent(lo) + k < EXACT_MIN_EXPONENT:
        k = EXACT_MIN_EXPONENT - _exponent(lo)
    return k


def exact_shift(points: ArrayLike) -> int:
    """The k such that ``points * 2**k`` lies in the exact range: 0 when it already does.

    Raises :class:`OutsideExactRange` when no k does (see the module docstring).
    """
    hi, lo = check_exact_range(points)
    if hi == 0 or (_exponent(hi) <= EXACT_MAX_EXPONENT and _exponent(lo) >= EXACT_MIN_EXPONENT):
        return 0
    return _placement(hi, lo)


def comfortable_shift(points: ArrayLike) -> tuple[int, Optional[str]]:
    """(k, problem) for judging a diagram at ``points * 2**k``: largest magnitude in [0.5, 1)
    unless the smallest needs more room (as :func:`exact_shift`, but always placed, so that
    tolerances and probes see the same numbers at every scale). ``problem`` says why the
    predicates cannot be exact for these points (their span), else None; never raises."""
    try:
        hi, lo = check_exact_range(points)
    except OutsideExactRange as exc:
        hi, _ = magnitude_range(points)
        return -_exponent(hi), str(exc)
    return (0 if hi == 0 else _placement(hi, lo)), None


def scale_points(points: NDArray[np.float64], k: int) -> NDArray[np.float64]:
    """``points * 2**k`` as a new C-contiguous float64 array (exact inside the float range)."""
    return np.ascontiguousarray(np.ldexp(np.asarray(points, dtype=np.float64), k))


def scale_back_vertices(vertices: NDArray[np.float64], k: int) -> NDArray[np.float64]:
    """``vertices * 2**-k``, the vertices of the unscaled input; :class:`OutsideExactRange`
    when a finite vertex leaves the float range (it has no float representation)."""
    vertices = np.asarray(vertices, dtype=np.float64).reshape(-1, 2)
    with np.errstate(over="ignore", under="ignore"):
        back = np.ldexp(vertices, -k)
    lost = np.isfinite(vertices).all(axis=1) & ~np.isfinite(back).all(axis=1)
    if lost.any():
        v = int(np.flatnonzero(lost)[0])
        raise OutsideExactRange(
            f"the diagram has no float representation: vertex {v} lies at ({vertices[v, 0]:.6g}, "
            f"{vertices[v, 1]:.6g}) x 2**{-k}, beyond the float range ({int(lost.sum())} such vertices; "
            f"nearly collinear sites put vertices far out; {RANGE_TEXT} holds for the sites, not for "
            f"their vertices)")
    return back


def smallest_normal(k: int) -> float:
    """The smallest normal float64 times 2**k: below it, coordinates scaled by 2**k were
    rounded to a multiple of 2**(k - 1074) (subnormals), an absolute error to allow for."""
    return math.ldexp(np.finfo(np.float64).smallest_normal, k)


def exact_range_sites(sites: NDArray[np.float64]) -> tuple[NDArray[np.float64], Optional[str]]:
    """(the sites as ``Implementation.run`` hands them to a build: scaled into the exact range,
    or unchanged when inside; why they cannot be, or None). For ``supports`` functions, which
    callers may ask about the unscaled sites: they must judge what the library will get."""
    try:
        shift = exact_shift(sites)
    except OutsideExactRange as exc:
        return sites, str(exc)
    return (scale_points(sites, shift) if shift else sites), None


def scale_weights(weights: NDArray[np.float64], k: int) -> NDArray[np.float64]:
    """``weights * 2**(2k)``: the weights of ``sites * 2**k`` (a weight is a squared length)."""
    return np.ascontiguousarray(np.ldexp(np.asarray(weights, dtype=np.float64), 2 * k))


def check_weight_range(sites: ArrayLike, weights: ArrayLike) -> None:
    """:class:`OutsideExactRange` naming the first weight whose magnitude, once the sites are
    placed in the exact range (:func:`exact_shift`) and the weights scaled with them, lies
    outside [2**-200, 2**200), where the power predicates are exact."""
    w = np.asarray(weights, dtype=np.float64).reshape(-1)
    hi, lo = magnitude_range(w)
    if hi == 0:
        return
    k = exact_shift(sites)
    if _exponent(hi) + 2 * k <= WEIGHT_MAX_EXPONENT and _exponent(lo) + 2 * k >= WEIGHT_MIN_EXPONENT:
        return
    bad = hi if _exponent(hi) + 2 * k > WEIGHT_MAX_EXPONENT else lo
    row = int(np.flatnonzero(np.abs(w) == bad)[0])
    raise OutsideExactRange(
        f"weight {bad:.6g} (site {row}) is outside the exact range of weights: nonzero weight magnitudes, "
        f"scaled by 2**{2 * k} with the sites (by 2**{k}), must lie in [2**-200, 2**200)")
