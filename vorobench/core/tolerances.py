"""Every floating-point tolerance of the project, named in one place.

Combinatorial decisions (orientation, cocircularity) are exact and need no tolerance; the
numbers here only judge float coordinates (Voronoi vertices are rounded circumcentres).
Lengths are judged relative to a *local scale*: the larger of the sites' bounding-box size
and the radius of the vertex's empty circle (far-away vertices of nearly collinear sites
carry proportionally larger rounding errors), plus a few ulps of the coordinates' magnitude
(sites around 1e9 with unit spacing cannot be resolved better than ulp(1e9) ~ 1.2e-7).
One number is not a length: NEAR_DEGENERATE_ULPS, the rule by which a floating-point library's
topology may differ from the exact one, counted in roundings of the data.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "VERTEX_MATCH_REL_TOL",
    "EQUIDISTANCE_REL_TOL",
    "PROBE_REL_TOL",
    "NEAR_DEGENERATE_REL_TOL",
    "NEAR_DEGENERATE_ULPS",
    "COINCIDENCE_FILTER_REL_TOL",
    "COINCIDENCE_FILTER_ULPS",
    "ROUNDOFF_ULPS",
    "RIDGE_DIRECTION_REL_TOL",
    "data_scale",
    "length_tolerance",
    "allowed_error",
    "circumcentre_tolerance",
]

#: compare(): matched vertices may differ by this fraction of their local scale.
VERTEX_MATCH_REL_TOL = 1e-7

#: certify(): a vertex's distances to its own sites may differ, and another site may be
#: closer than them, by this fraction of the local scale.
EQUIDISTANCE_REL_TOL = 1e-8

#: certify(): a probe point may lie outside its nearest site's cell by this fraction of the
#: local scale (probes on a cell boundary belong to both cells).
PROBE_REL_TOL = 1e-9

#: certify() of a floating-point library (Qhull): a decision that is wrong only for sites
#: within this fraction of the data scale of being collinear or cocircular (a wrong side, a
#: merged vertex whose sites are equidistant only to this fraction of the scale) is a
#: near-degenerate error, tolerated in the ``within_tolerance`` verdict (never for exact
#: code). Qhull's precision is relative to the bounding box, not to the local spacing.
NEAR_DEGENERATE_REL_TOL = 1e-8

#: certify() and compare() of a floating-point library: its topology may differ from the exact
#: diagram only at configurations that moving the sites (and weights) by at most this many
#: roundings of the data's extent (EPSILON * half the bounding box's longer side; of the largest
#: weight) makes degenerate: four sites cocircular, three collinear
#: (:mod:`vorobench.core.predicates.degeneracy`). Qhull's rounding measured on near_grid and
#: weighted tiny_spacing at 10^2..10^5 sites stays below 450 (benchmarks/degeneracy_margins.py).
NEAR_DEGENERATE_ULPS = 4096.0

#: qhull adapter: a finite ridge whose end vertices are further apart than this fraction of
#: their magnitude is oriented by its float direction; shorter ones combinatorially.
RIDGE_DIRECTION_REL_TOL = 1e-9

#: compare(): before deciding exactly whether an edge's two end vertices coincide, vertices
#: farther apart than COINCIDENCE_FILTER_REL_TOL of their local scale plus
#: COINCIDENCE_FILTER_ULPS ulps of (magnitude + R^2 / distance of the edge's sites) -- far
#: beyond any rounding of one circumcentre, and 100x what certify() accepts -- are distinct.
COINCIDENCE_FILTER_REL_TOL = 1e-6
COINCIDENCE_FILTER_ULPS = 1e4

#: Absolute slack, in units of float64 epsilon times the coordinates' magnitude.
ROUNDOFF_ULPS = 64.0

_EPS = float(np.finfo(np.float64).eps)


def data_scale(sites: NDArray[np.float64]) -> float:
    """Size of the sites' bounding box (its longer side); 1.0 when it is empty or a point."""
    if sites.shape[0] < 2:
        return 1.0
    span = float(np.max(sites.max(axis=0) - sites.min(axis=0)))
    return span if span > 0 else 1.0


def length_tolerance(rel_tol: float, local_scale: ArrayLike, magnitude: ArrayLike) -> NDArray[np.float64]:
    """Allowed length error: ``rel_tol * local_scale`` plus ROUNDOFF_ULPS ulps of ``magnitude``."""
    return rel_tol * np.asarray(local_scale, dtype=np.float64) + \
        ROUNDOFF_ULPS * _EPS * np.asarray(magnitude, dtype=np.float64)


@njit(cache=True)
def allowed_error(rel_tol: float, local_scale: float, magnitude: float) -> float:
    """Scalar, numba-callable :func:`length_tolerance`, for kernels."""
    return rel_tol * local_scale + ROUNDOFF_ULPS * _EPS * magnitude


def circumcentre_tolerance(rel_tol: float, local_scale: ArrayLike, radius: ArrayLike, shortest: ArrayLike,
                           magnitude: ArrayLike) -> NDArray[np.float64]:
    """Allowed error of a Voronoi vertex computed in floating point.

    The circumcentre of sites at distance ``shortest`` on a circle of ``radius`` R divides by
    a cross product that loses about eps R / shortest of relative accuracy, so the centre is
    off by up to ~eps R^2 / shortest: nearly collinear sites give vertices far away whose
    coordinates no float computation pins down. That term is added to ``length_tolerance``.
    """
    radius = np.asarray(radius, dtype=np.float64)
    conditioning = radius * radius / np.maximum(np.asarray(shortest, dtype=np.float64), 1e-300)
    return length_tolerance(rel_tol, local_scale, np.asarray(magnitude, dtype=np.float64) + conditioning)
