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

from vorobench.core.predicates.constructions import circumcentre_offsets_dd
from vorobench.core.predicates.expansion import (
    EPSILON,
    INCIRCLE_EXPANSION_MAX,
    ORIENT2D_EXPANSION_MAX,
    SPLITTER,
    compress_expansion,
    det2_expansion,
    diff_expansion,
    diff_product_expansion,
    estimate,
    expansion_diff,
    expansion_negate,
    expansion_product,
    expansion_sign,
    expansion_sum,
    fast_two_sum,
    float_expansion,
    grow_expansion,
    product_expansion,
    scale_expansion,
    split,
    two_diff,
    two_product,
    two_sum,
)
from vorobench.core.predicates.degeneracy import incircle_ulps, lift_extent, orient2d_ulps, power_test_ulps
from vorobench.core.predicates.orient_incircle import (
    CCW_ERRBOUND_A,
    ICC_ERRBOUND_A,
    INCIRCLE_CALLS,
    INCIRCLE_EXACT,
    ORIENT_CALLS,
    ORIENT_EXACT,
    incircle,
    incircle_counted,
    incircle_expansion,
    incircle_fast,
    incircle_many,
    orient2d,
    orient2d_counted,
    orient2d_expansion,
    orient2d_fast,
    orient2d_many,
)
from vorobench.core.predicates.power import (
    N_POWER_COUNTERS,
    POWER_BISECTOR_CALLS,
    POWER_BISECTOR_ERRBOUND_A,
    POWER_BISECTOR_EXACT,
    POWER_ERRBOUND_A,
    POWER_TEST_CALLS,
    POWER_TEST_EXACT,
    power_bisector_side,
    power_bisector_side_counted,
    power_bisector_side_fast,
    power_bisector_side_filter,
    power_bisector_side_many,
    power_test,
    power_test_counted,
    power_test_fast,
    power_test_filter,
    power_test_many,
)
from vorobench.core.predicates.sweep import (
    BREAKPOINT_ERRBOUND,
    KEY_ABSENT,
    KEY_FOUND,
    KEY_NOT_SOUGHT,
    UNDECIDED,
    breakpoint_side,
    breakpoint_side_exact,
    breakpoint_side_filter,
    circle_event_key,
    circle_event_top,
    circle_event_vs_site_exact,
    circle_events_order_exact,
    circle_top_relative,
    circle_top_to_y,
    tops_dd_order,
    tops_key_order,
    tops_order_filter,
)

__all__ = [
    "EPSILON",
    "incircle_ulps",
    "lift_extent",
    "orient2d_ulps",
    "power_test_ulps",
    "SPLITTER",
    "CCW_ERRBOUND_A",
    "ICC_ERRBOUND_A",
    "ORIENT_CALLS",
    "ORIENT_EXACT",
    "INCIRCLE_CALLS",
    "INCIRCLE_EXACT",
    "ORIENT2D_EXPANSION_MAX",
    "INCIRCLE_EXPANSION_MAX",
    "two_sum",
    "fast_two_sum",
    "two_diff",
    "split",
    "two_product",
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
    "orient2d",
    "orient2d_counted",
    "orient2d_fast",
    "incircle",
    "incircle_counted",
    "incircle_fast",
    "orient2d_many",
    "incircle_many",
    "UNDECIDED",
    "BREAKPOINT_ERRBOUND",
    "breakpoint_side_filter",
    "breakpoint_side_exact",
    "breakpoint_side",
    "circle_top_relative",
    "circle_top_to_y",
    "tops_order_filter",
    "circle_event_key",
    "circle_event_top",
    "KEY_FOUND",
    "KEY_ABSENT",
    "KEY_NOT_SOUGHT",
    "tops_dd_order",
    "circumcentre_offsets_dd",
    "tops_key_order",
    "circle_event_vs_site_exact",
    "circle_events_order_exact",
    "POWER_ERRBOUND_A",
    "POWER_BISECTOR_ERRBOUND_A",
    "POWER_TEST_CALLS",
    "POWER_TEST_EXACT",
    "POWER_BISECTOR_CALLS",
    "POWER_BISECTOR_EXACT",
    "N_POWER_COUNTERS",
    "power_test_filter",
    "power_test",
    "power_test_counted",
    "power_test_fast",
    "power_test_many",
    "power_bisector_side_filter",
    "power_bisector_side",
    "power_bisector_side_counted",
    "power_bisector_side_fast",
    "power_bisector_side_many",
]
