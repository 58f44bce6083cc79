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


def _third_sites(n: int, ridge_points: NDArray[np.int64], ridge_vertices: NDArray[np.int64],
                 V: int) -> NDArray[np.int64]:
    """For each finite ridge end, a site of that vertex other than the ridge's two sites."""
    p, q = ridge_points[:, 0], ridge_points[:, 1]
    # Incidences (vertex, site) from every finite ridge end, deduplicated and grouped by vertex.
    v_all = np.concatenate([ridge_vertices[:, 0], ridge_vertices[:, 0], ridge_vertices[:, 1], ridge_vertices[:, 1]])
    s_all = np.concatenate([p, q, p, q])
    keep = v_all >= 0
    inc = np.unique(v_all[keep] * n + s_all[keep])
    inc_v, inc_s = inc // n, inc % n
    start = np.searchsorted(inc_v, np.arange(V))
    count = np.searchsorted(inc_v, np.arange(V), side="right") - start
    if V and count.min() < 3:
        raise RuntimeError(f"Qhull vertex {int(np.argmin(count))} touches fewer than 3 sites")
    third = np.full(ridge_vertices.shape, -1, dtype=np.int64)
    for end in (0, 1):
        v = ridge_vertices[:, end]
        ok = v >= 0
        base = start[np.maximum(v, 0)]
        cand = [inc_s[np.minimum(base + k, inc_s.size - 1)] for k in range(3)]
        pick = np.where((cand[0] != p) & (cand[0] != q), cand[0],
                        np.where((cand[1] != p) & (cand[1] != q), cand[1], cand[2]))
        third[:, end] = np.where(ok, pick, -1)
    return third


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
    third = _third_sites(n, rp, rv, vertices.shape[0])
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
