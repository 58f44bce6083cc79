"""scipy.spatial.Delaunay (Qhull) as a vorobench implementation: the Voronoi diagram as the
dual of the Delaunay triangulation, put together by vorobench's shared builder.

Each triangle's circumcentre is a Voronoi vertex, and each Delaunay edge a Voronoi ridge: it
separates the edge's two sites and runs between the centres of the triangles on its two
sides (out to infinity on the hull). The ridges go to ``assemble`` unoriented; the builder
orients each one exactly. Qhull decides in floating point, hence ``exact=False``.

Registered by the entry point ``scipy-delaunay`` (group ``vorobench.impls``, in
pyproject.toml); ``--plugin vorobench_scipy_delaunay`` loads it without installing.
"""

from __future__ import annotations

import time
from typing import Optional

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import Delaunay

from vorobench.plugin import Diagram, Implementation, all_collinear, assemble, collinear_diagram, record_timing

__all__ = ["IMPLEMENTATION", "IMPLEMENTATIONS", "QHULL_OPTIONS", "build", "circumcentres", "delaunay_ridges"]

#: Qbb: scale the lifted coordinate; Qc: keep the sites Qhull leaves out (coplanar), so that a
#: dropped site is reported instead of losing its cell silently; Qz: add a point at infinity
#: (helps cocircular input); Qt: triangulated output.
QHULL_OPTIONS = "Qbb Qc Qz Qt"


def circumcentres(corners: NDArray[np.float64]) -> NDArray[np.float64]:
    """The circumcentres of triangles ``corners`` (m, 3, 2), computed relative to each first
    corner so that large coordinates cancel before the products."""
    b = corners[:, 1] - corners[:, 0]
    c = corners[:, 2] - corners[:, 0]
    d = 2.0 * (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0])
    b2 = (b * b).sum(axis=1)
    c2 = (c * c).sum(axis=1)
    x = (c[:, 1] * b2 - b[:, 1] * c2) / d
    y = (b[:, 0] * c2 - c[:, 0] * b2) / d
    return corners[:, 0] + np.stack([x, y], axis=1)


def delaunay_ridges(simplices: NDArray[np.int64],
                    neighbors: NDArray[np.int64]) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """Each Delaunay edge once, as a Voronoi ridge: (its two sites, the triangles on its two
    sides), -1 for the outside of a hull edge; neither pair is in any particular order."""
    m = simplices.shape[0]
    t = np.repeat(np.arange(m), 3)
    k = np.tile(np.arange(3), m)                 # edge k of triangle t is opposite its corner k
    a = simplices[t, (k + 1) % 3]
    b = simplices[t, (k + 2) % 3]
    across = neighbors[t, k]                     # the triangle on the other side, -1 outside
    once = (across < 0) | (t < across)           # an inner edge is seen from both of its triangles
    return np.stack([a, b], axis=1)[once], np.stack([t, across], axis=1)[once]


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites`` (see ``vorobench.plugin.BuildFunction``)."""
    if sites.shape[0] <= 1:
        return Diagram.empty(sites)
    if all_collinear(sites):                     # no triangle: n - 1 parallel lines
        return collinear_diagram(sites)
    started = time.perf_counter()
    # Centred first: Qhull's tolerances grow with the coordinates' magnitude, so sites far from
    # the origin (1e9 + unit square) would otherwise be merged. Only Qhull sees the shifted copy.
    tri = Delaunay(sites - (sites.min(axis=0) + sites.max(axis=0)) / 2, qhull_options=QHULL_OPTIONS)
    converting = time.perf_counter()
    record_timing("library", converting - started)
    if tri.coplanar.size:
        left_out = np.unique(tri.coplanar[:, 0])
        raise RuntimeError(f"Qhull left {left_out.size} of {sites.shape[0]} sites out of the triangulation "
                           f"(site {int(left_out[0])} first): they would have no cell")
    simplices = tri.simplices.astype(np.int64)
    vertices = circumcentres(sites[simplices])
    edge_sites, edge_vertices = delaunay_ridges(simplices, tri.neighbors.astype(np.int64))
    if stats is not None:
        stats["triangles"] = int(simplices.shape[0])
        stats["hull_edges"] = int((edge_vertices < 0).any(axis=1).sum())
    diagram = assemble(sites, vertices, edge_sites, edge_vertices, oriented=False)
    record_timing("convert", time.perf_counter() - converting)
    return diagram


IMPLEMENTATION = Implementation(
    name="scipy-delaunay",
    description="scipy.spatial.Delaunay (Qhull), dualised by vorobench's builder",
    complexity="O(n log n)",
    build=build,
    exact=False,                                 # Qhull decides in floating point
    origin="scipy.spatial.Delaunay (Qhull)",
    kind="plugin",
)

#: What ``--plugin vorobench_scipy_delaunay`` registers (the entry point names IMPLEMENTATION).
IMPLEMENTATIONS = [IMPLEMENTATION]
