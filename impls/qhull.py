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

Weighted sites (power diagrams, :func:`build_weighted`): the regular triangulation is the
lower convex hull of the lifted points (x, y, x**2 + y**2 - w), through
``scipy.spatial.ConvexHull`` ("Qbb Qc"; scipy adds "Qt", so facets come triangulated).
* Frame: coordinates relative to the bounding box's centre, weights relative to the largest.
  Either only adds an affine function of the site to the lift, which keeps the lower hull.
* Lower facets are those whose outward normal points down, minus triangles of exactly
  collinear sites (vertical in the lift, whatever the rounded normal says). A site that is no
  vertex of a lower facet is hidden. That includes lifted points Qhull finds on a facet
  (within its rounding): their cells would be a point or a segment.
* When Qhull reports such coplanar points, it runs once more without the points strictly
  inside the hull (hidden by more than its rounding) and without vertices of upper facets
  only. A few very negative weights otherwise stretch the heights so much that the other
  sites' differences drown (sites 1e-9 apart with twenty weights of -1: 363 sites wrongly
  hidden without this).
* Each lower triangle gives a vertex: the
  :func:`~vorobench.core.circumcentre.power_centre` of its three sites, from the smallest id
  up. Each pair of lower triangles sharing an edge gives a ridge, and each boundary edge a
  ray. A coplanar lifted quadruple (cocircular sites with equal weights) gives two triangles
  with the same centre, joined by a zero-length ridge.
* Orientation is combinatorial. The triangles are turned counter-clockwise as one surface:
  neighbours run through their shared edge in opposite directions, and each patch turns the
  way most of its exact orient2d signs say. For the edge (a, b) of a counter-clockwise
  triangle T, a's half-edge then runs from the centre of the triangle across to T's centre.
  Cells close up even where Qhull's float surface
  folds over in the plane, e.g. a joggled sliver at the hull's boundary.
* Qhull failures, or a lower hull that is not one triangulated disc (cells that do not close,
  V - E + F != 1): Qhull runs again with joggled input ("QJ"), and ``stats["joggled"] = 1``
  says so. Before that, lifted points all on one plane (every site on one power circle,
  where Qhull cannot start) are recognised exactly (``power_test``) and built directly: the
  hull's corners around one vertex, every other site hidden (``stats["flat_lift"] = 1``).
* All-collinear sites go to :func:`~vorobench.core.builder.collinear_diagram` (exact). Three
  sites that are not collinear are one triangle.
Qhull decides in floating point: hidden sites and coplanar merges are float decisions.
Nearly degenerate weighted input (near-lattices with integer weights) can differ from an
exact construction. So can weights that dwarf the squared spacing (spacing 1e-9, weights 0
and 1): there the lift's heights cannot hold the differences in double precision.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
from numba import njit
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, Delaunay, QhullError, Voronoi

from impls.base import Implementation
from vorobench.core.builder import assemble, collinear_diagram, orient_ridges
from vorobench.core.circumcentre import power_centre
from vorobench.core.diagram import Diagram, InvalidDiagramError
from vorobench.core.hull import all_collinear, convex_hull_polygon
from vorobench.core.predicates import orient2d_many, power_test_many

__all__ = ["build", "build_weighted", "IMPLEMENTATION"]


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


def build_weighted(sites: NDArray[np.float64], weights: NDArray[np.float64],
                   stats: Optional[dict] = None) -> Diagram:
    """The power diagram of prepared ``sites`` with ``weights`` (power |x - p|^2 - w), dual to
    the lower convex hull of the lifted points through Qhull.

    When Qhull fails or its lower hull does not close up into cells, Qhull runs again with
    joggled input (``QJ``); ``stats["joggled"]`` records it. Lifted points all on one plane
    (every site on one power circle), where Qhull cannot start, are recognised exactly and
    built directly (``stats["flat_lift"]``).
    """
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites, weights)
    if all_collinear(sites):
        if stats is not None:
            stats.update(collinear=1)
        return collinear_diagram(sites, weights)
    joggled = flat = 0
    try:
        diagram = _build_from_lifted_hull(sites, weights, stats, "Qbb Qc")
    except (InvalidDiagramError, RuntimeError):
        if _lifted_coplanar(sites, weights):
            diagram, flat = _one_facet_diagram(sites, weights), 1
        else:
            diagram, joggled = _build_from_lifted_hull(sites, weights, stats, "Qbb Qc QJ"), 1
    if stats is not None:
        stats.update(joggled=joggled, flat_lift=flat)
    return diagram


def _lifted_coplanar(sites: NDArray[np.float64], weights: NDArray[np.float64]) -> bool:
    """Exact test: all lifted points (x, y, x^2 + y^2 - w) on one plane (sites not all collinear)."""
    turn = orient2d_many(sites[0], sites[1], sites[2:])
    c = 2 + int(np.flatnonzero(turn)[0])
    w = np.column_stack([sites, weights])
    return not power_test_many(w[0], w[1], w[c], w).any()


def _one_facet_diagram(sites: NDArray[np.float64], weights: NDArray[np.float64]) -> Diagram:
    """The power diagram when the lifted points lie on one plane: the lower hull is one facet,
    the convex polygon of the sites. Its corners keep a cell each, around one vertex; every
    other site lies on the facet (a tie everywhere it could win) and is hidden."""
    ring = convex_hull_polygon(sites)                   # counter-clockwise, with points on edges
    turn = orient2d_many(sites[np.roll(ring, 1)], sites[ring], sites[np.roll(ring, -1)])
    corners = ring[turn != 0]
    a, b, c = np.sort(corners)[:3]                      # the vertex from its three smallest sites
    vertex = power_centre(sites[a, 0], sites[a, 1], weights[a], sites[b, 0], sites[b, 1], weights[b],
                          sites[c, 0], sites[c, 1], weights[c])
    # edge (p, q) of the counter-clockwise polygon: the facet lies on its left, so p's
    # half-edge comes in from infinity to the vertex
    pairs = np.stack([corners, np.roll(corners, -1)], axis=1)
    ends = np.tile(np.array([-1, 0], dtype=np.int64), (corners.size, 1))
    return assemble(sites, np.array([vertex]), pairs, ends, weights=weights)


def _lower_hull(sites: NDArray[np.float64], weights: NDArray[np.float64], options: str
                ) -> tuple[NDArray[np.int64], NDArray[np.int64], int]:
    """(triangles, neighbours, facets) of the lower hull of the lifted sites: the lower facets'
    site ids, counter-clockwise in the plane (:func:`_clockwise`), and for each the lower facet
    across the edge opposite each corner (-1: none, a boundary edge), numbered among the
    lower facets; ``facets``: how many facets Qhull's whole hull has."""
    n = sites.shape[0]
    if n == 3:
        # Three sites that are not collinear (decided exactly before): one triangle, all on
        # the hull. Qhull needs four points to start a 3-D hull.
        ccw = orient2d_many(sites[:1], sites[1:2], sites[2:3])[0] > 0
        return (np.array([[0, 1, 2] if ccw else [0, 2, 1]], dtype=np.int64),
                np.full((1, 3), -1, dtype=np.int64), 1)
    ids = np.arange(n)
    hull = _lifted_hull(sites, weights, options)
    if hull.coplanar.shape[0] and "QJ" not in options:
        # Qhull put some lifted points within its rounding of a facet. The points strictly
        # inside the hull are above the lower hull (hidden) by more than that: run again
        # without them and without vertices of upper facets only, in the smaller range of
        # heights that is left (a few huge weights otherwise drown the rest's differences).
        down = hull.equations[:, 2] < 0.0
        coplanar = np.asarray(hull.coplanar, dtype=np.int64).reshape(-1, 3)
        keep = np.unique(np.concatenate([hull.simplices[down].ravel(), coplanar[down[coplanar[:, 1]], 0]]))
        if 4 <= keep.size < n and not all_collinear(sites[keep]):
            ids = keep
            hull = _lifted_hull(sites[ids], weights[ids], options)
    simplices = ids[np.asarray(hull.simplices, dtype=np.int64)]
    neighbours = np.asarray(hull.neighbors, dtype=np.int64)
    lower = np.flatnonzero(hull.equations[:, 2] < 0.0)          # outward normal pointing down
    turn = orient2d_many(sites[simplices[lower, 0]], sites[simplices[lower, 1]], sites[simplices[lower, 2]])
    # A triangle of collinear sites spans a vertical plane in the lift: never a lower facet,
    # whatever the rounded normal says (Qhull's triangulation of merged facets makes such slivers).
    lower, turn = lower[turn != 0], turn[turn != 0]
    new_id = np.full(simplices.shape[0] + 1, -1, dtype=np.int64)   # last entry: Qhull's -1
    new_id[lower] = np.arange(lower.size)
    triangles, across = simplices[lower], new_id[neighbours[lower]]
    # Counter-clockwise in the plane: swap two corners, and the neighbours opposite them.
    cw = _clockwise(triangles, across, turn)
    triangles[cw] = triangles[cw][:, [0, 2, 1]]
    across[cw] = across[cw][:, [0, 2, 1]]
    return triangles, across, int(simplices.shape[0])


def _lifted_hull(sites: NDArray[np.float64], weights: NDArray[np.float64], options: str) -> ConvexHull:
    """Qhull's convex hull of the lifted sites (x, y, x^2 + y^2 - w), in a frame that keeps the
    numbers small: coordinates relative to the bounding box's centre, weights relative to the
    largest (the lift then differs from the true one by an affine function of the site, the
    same for all: the same lower hull)."""
    centre = 0.5 * (sites.min(axis=0) + sites.max(axis=0))
    xy = sites - centre
    lifted = np.column_stack([xy, np.einsum("ij,ij->i", xy, xy) - (weights - weights.max())])
    try:
        return ConvexHull(lifted, qhull_options=options)
    except (QhullError, ValueError) as exc:
        raise RuntimeError(f"Qhull failed on {sites.shape[0]} lifted sites: {str(exc).splitlines()[0]}") from exc


@njit(cache=True)
def _clockwise(triangles, across, turn):
    """Which lower triangles to turn over so that all run counter-clockwise, decided for the
    surface, not triangle by triangle: neighbours must run through their shared edge in
    opposite directions (Qhull's facets come in either orientation), and each connected patch
    turns the way most of its triangles' exact orientations (``turn``, +-1) say. Exact and
    combinatorial agree unless Qhull's float surface folds over in the plane (a sliver, or
    joggled input): then the DCEL still closes up."""
    T = triangles.shape[0]
    rel = np.zeros(T, dtype=np.bool_)        # turned relative to the patch's first triangle
    patch = np.full(T, -1, dtype=np.int64)
    queue = np.empty(T, dtype=np.int64)
    out = np.zeros(T, dtype=np.bool_)
    for seed in range(T):
        if patch[seed] >= 0:
            continue
        patch[seed] = seed
        head, tail = 0, 1
        queue[0] = seed
        vote = 0
        while head < tail:
            t = queue[head]
            head += 1
            vote += -turn[t] if rel[t] else turn[t]
            for k in range(3):
                u = across[t, k]
                if u < 0 or patch[u] >= 0:
                    continue
                x = triangles[t, (k + 1) % 3]
                y = triangles[t, (k + 2) % 3]
                ix = 0
                iy = 0
                for j in range(3):
                    if triangles[u, j] == x:
                        ix = j
                    elif triangles[u, j] == y:
                        iy = j
                # t runs x -> y (as stored, turned if rel[t]); u must run y -> x once turned
                same = (iy - ix) % 3 == 1
                rel[u] = rel[t] != same
                patch[u] = seed
                queue[tail] = u
                tail += 1
        flip_patch = vote < 0
        for j in range(tail):
            t = queue[j]
            out[t] = rel[t] != flip_patch
    return out


@njit(cache=True)
def _power_centres(sites, weights, triangles):
    """Power centre of each triangle, from its site ids in increasing order (the rule that
    makes every construction compute a vertex the same way)."""
    out = np.empty((triangles.shape[0], 2))
    for t in range(triangles.shape[0]):
        a, b, c = triangles[t, 0], triangles[t, 1], triangles[t, 2]
        if a > b:
            a, b = b, a
        if b > c:
            b, c = c, b
        if a > b:
            a, b = b, a
        out[t, 0], out[t, 1] = power_centre(sites[a, 0], sites[a, 1], weights[a], sites[b, 0], sites[b, 1],
                                            weights[b], sites[c, 0], sites[c, 1], weights[c])
    return out


def _build_from_lifted_hull(sites: NDArray[np.float64], weights: NDArray[np.float64],
                            stats: Optional[dict], options: str) -> Diagram:
    """Run Qhull on the lifted sites with ``options`` and dualise the lower hull into the DCEL.

    Every edge is oriented combinatorially, as in the joggled Delaunay path: with triangle T
    counter-clockwise, its edge (a, b) opposite a corner has T on its left, so a's half-edge
    (direction perp(b - a), towards T) runs from the power centre of the triangle T' across
    to T's (from infinity on a boundary edge).
    """
    triangles, neighbours, facets = _lower_hull(sites, weights, options)
    T = triangles.shape[0]
    if T == 0:
        raise InvalidDiagramError(f"Qhull found no lower facet among {facets}")
    vertices = _power_centres(np.ascontiguousarray(sites), np.ascontiguousarray(weights), triangles)
    tid = np.arange(T)
    pairs, ends = [], []
    for k in range(3):
        a, b = triangles[:, (k + 1) % 3], triangles[:, (k + 2) % 3]   # edge opposite corner k
        across = neighbours[:, k]
        once = (across < 0) | (tid < across)     # a ray (boundary edge), or a ridge seen once
        pairs.append(np.stack([a[once], b[once]], axis=1))
        ends.append(np.stack([across[once], tid[once]], axis=1))
    diagram = assemble(sites, vertices, np.concatenate(pairs), np.concatenate(ends), weights=weights)
    if diagram.n_vertices - diagram.n_edges + diagram.n_visible != 1:
        # cells that close one by one, around a hole or a second patch: not one lower hull
        raise InvalidDiagramError(f"Qhull's lower hull is not one triangulated disc (V - E + F = "
                                  f"{diagram.n_vertices - diagram.n_edges + diagram.n_visible})")
    if stats is not None:
        stats.update(qhull_facets=facets, lower_facets=int(T), hidden=int(diagram.hidden.size))
    return diagram


IMPLEMENTATION = Implementation(
    name="qhull",
    description="scipy.spatial.Voronoi (Qhull, floating point) converted to the DCEL; "
                "power diagrams from the lower hull of the lifted sites (scipy.spatial.ConvexHull)",
    complexity="O(n log n)",
    build=build,
    exact=False,
    origin="scipy/Qhull",
    kind="own",
    build_weighted=build_weighted,
)
