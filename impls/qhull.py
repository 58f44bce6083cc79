"""Qhull's Voronoi diagram (``scipy.spatial.Voronoi``) converted to the vorobench DCEL.

CONTRACT
--------
Complexity: O(n log n) expected (Qhull's Quickhull on the lifted points) plus O(n log n)
for the conversion (sorting).
Input: prepared sites (distinct, finite float64), any n >= 0.
Degenerate cases:
* n = 0, 1: no edges. All sites collinear (n = 2 included): Qhull refuses a flat input, so
  the n - 1 parallel bisector lines are built directly.
* Cocircular sites: Qhull merges them ("Qz", joggle off), giving one vertex of degree >= 4;
  it also merges *nearly* cocircular sites, since its decisions are floating point. That is
  why this implementation is marked not exact: against exact constructions it is expected to
  agree within tolerance.
* Large offsets: sites are translated so that their bounding box is centred at the origin
  before Qhull runs, and vertices translated back. Without this, 2,000 uniform points offset
  by 1e6 give 62 vertices instead of about 3,980, silently (advice of scipy's maintainers).
Orientation: each ridge is oriented combinatorially, not from float coordinates: a vertex's
third site r (other than the ridge's sites p, q) lies right of p->q exactly when the vertex
is where p's half-edge starts (exact orient2d), so tiny ridges cannot be flipped by rounding.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import QhullError, Voronoi

from impls.base import Implementation
from vorobench.dcel import assemble, collinear_diagram
from vorobench.diagram import Diagram
from vorobench.predicates import orient2d_many

__all__ = ["build", "IMPLEMENTATION"]


def _all_collinear(sites: NDArray[np.float64]) -> bool:
    """Exact test: every site lies on the line through the first two."""
    if sites.shape[0] <= 2:
        return True
    signs = orient2d_many(sites[0], sites[1], sites[2:])
    return not np.any(signs)


def _third_sites(ridge_points: NDArray[np.int64], ridge_vertices: NDArray[np.int64]) -> NDArray[np.int64]:
    """For each finite ridge end, a site of that vertex other than the ridge's two sites.

    Any other ridge meeting at the same vertex separates a different pair of the vertex's
    sites, so one of its two sites is the third site we need.
    """
    E = ridge_points.shape[0]
    v = ridge_vertices.reshape(-1)                     # incidence k = 2 * ridge + end
    finite = np.flatnonzero(v >= 0)
    order = finite[np.argsort(v[finite], kind="stable")]
    sorted_v = v[order]
    # Pair each incidence with its neighbour in vertex order (the previous one for the last).
    partner = np.empty_like(order)
    partner[:-1] = order[1:]
    partner[-1:] = order[-2:-1] if order.size > 1 else order[-1:]
    last = np.ones(order.size, dtype=bool)
    last[:-1] = sorted_v[1:] != sorted_v[:-1]
    partner[last] = np.concatenate([order[:1], order[:-1]])[last]
    if np.any(v[partner] != sorted_v):
        bad = int(sorted_v[np.flatnonzero(v[partner] != sorted_v)[0]])
        raise RuntimeError(f"Qhull vertex {bad} lies on a single ridge")
    ridge, other = order // 2, partner // 2
    p, q = ridge_points[ridge, 0], ridge_points[ridge, 1]
    r0, r1 = ridge_points[other, 0], ridge_points[other, 1]
    third = np.full(2 * E, -1, dtype=np.int64)
    third[order] = np.where((r0 != p) & (r0 != q), r0, r1)
    return third.reshape(E, 2)


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites`` through Qhull."""
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites)
    if _all_collinear(sites):
        if stats is not None:
            stats.update(collinear=1)
        return collinear_diagram(sites)
    centre = 0.5 * (sites.min(axis=0) + sites.max(axis=0))
    try:
        vor = Voronoi(sites - centre)
    except QhullError as exc:  # pragma: no cover - Qhull's own failures are reported as such
        raise RuntimeError(f"Qhull failed on {n} sites: {str(exc).splitlines()[0]}") from exc
    vertices = vor.vertices + centre
    rp = np.asarray(vor.ridge_points, dtype=np.int64).reshape(-1, 2)
    rv = np.asarray(vor.ridge_vertices, dtype=np.int64).reshape(-1, 2)
    keep = rv[:, 0] != rv[:, 1]                    # a ridge collapsed to one vertex is no edge
    rp, rv = rp[keep], rv[keep]
    third = _third_sites(rp, rv)
    p, q = rp[:, 0], rp[:, 1]
    side = np.zeros(rv.shape, dtype=np.int8)       # orient2d(p, q, third site of each end)
    for end in (0, 1):
        ok = rv[:, end] >= 0
        side[ok, end] = orient2d_many(sites[p[ok]], sites[q[ok]], sites[third[ok, end]])
    # p's half-edge runs in direction perp(q - p), to the left of p->q: it starts at the vertex
    # whose third site is on the right (negative) and ends at the one whose third site is on the left.
    end0_is_start = np.where(rv[:, 0] >= 0, side[:, 0] < 0, side[:, 1] > 0)
    if np.any((rv >= 0) & (side == 0)):
        raise RuntimeError("Qhull returned a vertex collinear with one of its ridges")
    start = np.where(end0_is_start, rv[:, 0], rv[:, 1])
    end = np.where(end0_is_start, rv[:, 1], rv[:, 0])
    if stats is not None:
        stats.update(qhull_vertices=int(vertices.shape[0]), qhull_ridges=int(rp.shape[0]))
    return assemble(sites, vertices, rp, np.stack([start, end], axis=1))


IMPLEMENTATION = Implementation(
    name="qhull",
    description="scipy.spatial.Voronoi (Qhull, floating point) converted to the DCEL",
    complexity="O(n log n)",
    build=build,
    exact=False,
    origin="scipy/Qhull",
)
