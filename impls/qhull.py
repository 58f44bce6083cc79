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
* Nearly collinear hull sites: Qhull may merge them into one non-convex facet whose ridges
  cannot be closed into cells; then Qhull runs again with joggled input ("QJ", its own
  documented remedy), and ``stats["joggled"] = 1`` says so.
* Large offsets: sites are translated so that their bounding box is centred at the origin
  before Qhull runs, and vertices translated back. Without this, 2,000 uniform points offset
  by 1e6 give 62 vertices instead of about 3,980, silently (advice of scipy's maintainers).
Orientation: each ridge is oriented combinatorially by the builder's
:func:`~vorobench.core.builder.orient_ridges` (a vertex's third site lies right of p->q
exactly when the vertex is where p's half-edge starts), so tiny ridges cannot be flipped by
rounding.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import Delaunay, QhullError, Voronoi

from impls.base import Implementation
from vorobench.core.builder import assemble, collinear_diagram, orient_ridges
from vorobench.core.diagram import Diagram, InvalidDiagramError
from vorobench.core.hull import all_collinear
from vorobench.core.predicates import orient2d_many

__all__ = ["build", "IMPLEMENTATION"]


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites`` through Qhull.

    When Qhull's merged output does not close up into cells (nearly collinear hull sites
    merged into one non-convex facet), Qhull runs again with its joggle option (``QJ``),
    which gives simplicial output; ``stats["joggled"]`` records it.
    """
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites)
    if all_collinear(sites):
        if stats is not None:
            stats.update(collinear=1)
        return collinear_diagram(sites)
    try:
        diagram = _build_from_qhull(sites, stats, "Qbb Qc Qz")
        joggled = 0
    except (InvalidDiagramError, RuntimeError):
        diagram = _build_from_joggled_delaunay(sites)
        joggled = 1
    if stats is not None:
        stats.update(joggled=joggled)
    return diagram


def _circumcentres(a: NDArray[np.float64], b: NDArray[np.float64], c: NDArray[np.float64]) -> NDArray[np.float64]:
    """Circumcentres of triangles (a, b, c), computed relative to a to limit cancellation."""
    ab, ac = b - a, c - a
    d = 2.0 * (ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0])
    ab2, ac2 = (ab ** 2).sum(axis=1), (ac ** 2).sum(axis=1)
    ux = (ac[:, 1] * ab2 - ab[:, 1] * ac2) / d
    uy = (ab[:, 0] * ac2 - ac[:, 0] * ab2) / d
    return a + np.stack([ux, uy], axis=1)


def _build_from_joggled_delaunay(sites: NDArray[np.float64]) -> Diagram:
    """Dual of Qhull's joggled (simplicial) Delaunay triangulation.

    scipy orients 2-D simplices counter-clockwise and gives each one's neighbours, so the
    orientation of every Voronoi edge is combinatorial: the edge between a and b (triangle T
    on the left of a->b, T' across) runs from T's neighbour T' to T; a hull edge comes from
    infinity. Vertices are the circumcentres of the original (not joggled) sites.
    """
    centre = 0.5 * (sites.min(axis=0) + sites.max(axis=0))
    if sites.shape[0] == 3:
        # Three sites that are not collinear (decided exactly before) are one triangle; Qhull
        # cannot start its lifted hull from three nearly collinear points, joggled or not.
        ccw = orient2d_many(sites[:1], sites[1:2], sites[2:3])[0] > 0
        simplices = np.array([[0, 1, 2] if ccw else [0, 2, 1]], dtype=np.int64)
        neighbours = np.full((1, 3), -1, dtype=np.int64)
    else:
        tri = Delaunay(sites - centre, qhull_options="Qbb Qc QJ")
        simplices = np.asarray(tri.simplices, dtype=np.int64)
        neighbours = np.asarray(tri.neighbors, dtype=np.int64)
    T = simplices.shape[0]
    tid = np.arange(T)
    vertices = _circumcentres(sites[simplices[:, 0]], sites[simplices[:, 1]], sites[simplices[:, 2]])
    pairs, ends = [], []
    for k in range(3):
        a, b = simplices[:, (k + 1) % 3], simplices[:, (k + 2) % 3]   # edge opposite corner k
        across = neighbours[:, k]
        once = (across < 0) | (tid < across)
        pairs.append(np.stack([a[once], b[once]], axis=1))
        ends.append(np.stack([across[once], tid[once]], axis=1))
    return assemble(sites, vertices, np.concatenate(pairs), np.concatenate(ends))


def _build_from_qhull(sites: NDArray[np.float64], stats: Optional[dict], options: str) -> Diagram:
    """Run Qhull with ``options`` and convert its ridges to the DCEL."""
    n = sites.shape[0]
    centre = 0.5 * (sites.min(axis=0) + sites.max(axis=0))
    try:
        vor = Voronoi(sites - centre, qhull_options=options)
    except QhullError as exc:  # pragma: no cover - Qhull's own failures are reported as such
        raise RuntimeError(f"Qhull failed on {n} sites: {str(exc).splitlines()[0]}") from exc
    vertices = vor.vertices + centre
    rp = np.asarray(vor.ridge_points, dtype=np.int64).reshape(-1, 2)
    rv = np.asarray(vor.ridge_vertices, dtype=np.int64).reshape(-1, 2)
    keep = rv[:, 0] != rv[:, 1]                    # a ridge collapsed to one vertex is no edge
    rp, rv = rp[keep], rv[keep]
    ends = orient_ridges(sites, vertices, rp, rv)
    if stats is not None:
        stats.update(qhull_vertices=int(vertices.shape[0]), qhull_ridges=int(rp.shape[0]))
    return assemble(sites, vertices, rp, ends)


IMPLEMENTATION = Implementation(
    name="qhull",
    description="scipy.spatial.Voronoi (Qhull, floating point) converted to the DCEL",
    complexity="O(n log n)",
    build=build,
    exact=False,
    origin="scipy/Qhull",
    kind="own",
)
