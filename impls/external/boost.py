"""Boost.Polygon's Voronoi sweep (through ``pyvoronoi``) converted to the vorobench DCEL.

CONTRACT
--------
Complexity: O(n log n) (Fortune's sweep with a balanced beach line, ``std::map``).
Conversion: O(n) Python-level reading of pyvoronoi's edge objects (and vertex objects for
inputs on the grid), then the shared DCEL builder; this dominates the total for large n
(see ``convert_s``). Cell i is the i-th site in (x, y) order, the order of Boost's sweep
(checked on a sample of cells: reading every cell object would cost more than the sweep).
Input: Boost.Polygon's Voronoi builder takes 32-bit signed integer coordinates. The sites
are mapped to that grid by a similarity (which maps Voronoi diagrams onto Voronoi
diagrams): translate the bounding-box centre to the origin, multiply by the power of two
``2**e`` that brings the larger half-side just under 2**30, round to the nearest integer.
Vertices are mapped back with the inverse transform.
* Inputs whose coordinates are already on that grid (integer data such as ``grid``,
  ``lattice_rotated``, ``cocircular``, ``collinear``) go through exactly: stat
  ``rounded_sites`` is 0 and Boost's decisions are those for the true sites.
* Otherwise (random floats) Boost sees the sites moved by at most half a grid step
  (2**-31 of the bounding box); stat ``rounded_sites`` counts them.
* Inputs where rounding would merge distinct sites, or change any orientation or in-circle
  decision of the sites' Delaunay triangulation (exact test on both point sets, on a
  triangulation of the true sites by our incremental construction), are unsupported:
  ``supports`` says why and the runner skips them. Every other input has the same
  diagram combinatorics after rounding, so Boost's answer is the answer for the sites.
Vertices: for rounded inputs Boost's coordinates are those of the rounded sites, so they
are recomputed from the true sites (circumcentre of the vertex's three smallest site ids,
the rule of the exact implementations; stat ``vertices_from_sites``); inputs on the grid
keep Boost's own coordinates, mapped back.
Degenerate cases: n = 0, 1: no edges; collinear sites: Boost itself returns the parallel
lines (edges with both ends infinite); cocircular sites: Boost returns one vertex of
degree >= 4.
Exactness: Boost's predicates are exact for its integer input, but its finishing pass also
removes edges whose two vertices agree to within 128 ulps (nearly cocircular sites become
one vertex), and non-grid inputs are rounded: ``exact=False``.
Orientation: Boost's half-edges run counter-clockwise around their cell, as ours do, so a
twin pair's half-edge of cell a gives (a, b, start, end) directly.
"""

from __future__ import annotations

import math
from operator import attrgetter
from typing import Optional

import numpy as np
import pyvoronoi
from numpy.typing import NDArray

from impls.base import Implementation
from impls.external.clock import BuildClock
from impls.external.screen import changed_decisions, circumcentres, triangulation
from vorobench.core.builder import assemble
from vorobench.core.diagram import Diagram
from vorobench.core.predicates import orient2d_many
from vorobench.core.scaling import exact_range_sites

__all__ = ["build", "supports", "to_grid", "vertex_triples", "GRID_HALF_SPAN_BITS", "IMPLEMENTATION"]

#: The sites' larger half-side is scaled to just under 2**GRID_HALF_SPAN_BITS grid units,
#: inside Boost's 32-bit signed input range with a factor 2 to spare.
GRID_HALF_SPAN_BITS = 30

_CELL_SAMPLE = 64          # cells whose site is read back from pyvoronoi to check the order


def to_grid(sites: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64], float, NDArray[np.bool_]]:
    """The sites on Boost's integer grid: (integer-valued points, centre, scale, moved).

    ``points = rint((sites - centre) * scale)`` with ``scale`` a power of two; ``moved[i]``
    is True when site i is not exactly on the grid (its subtraction or its rounding was
    inexact; the subtraction is checked with the error-free TwoSum).
    """
    lo, hi = sites.min(axis=0), sites.max(axis=0)
    centre = 0.5 * lo + 0.5 * hi
    half = float(np.max(hi - lo)) / 2.0
    exponent = GRID_HALF_SPAN_BITS - (math.frexp(half)[1] if half > 0 else 0)
    scale = math.ldexp(1.0, exponent)             # half * scale < 2**30; exact products
    diff = sites - centre
    back = diff - sites                           # TwoSum(sites, -centre): the rounding error
    error = (sites - (diff - back)) + (-centre - back)
    scaled = diff * scale
    points = np.rint(scaled)
    moved = np.any((error != 0) | (points != scaled), axis=1)
    return points, centre, scale, moved


def _cell_sites(builder: "pyvoronoi.Pyvoronoi", points: NDArray[np.float64]) -> NDArray[np.int64]:
    """Site of each Boost cell. Boost numbers its cells in the order its sweep meets the
    sites, lexicographic (x, then y); reading every cell object from pyvoronoi costs more
    than the whole sweep, so the order is computed and checked on a sample of cells."""
    order = np.lexsort((points[:, 1], points[:, 0]))
    if builder.CountCells() != order.size:
        raise ValueError(f"boost: unsupported input: rounding to the grid merged "
                         f"{order.size - builder.CountCells()} sites (supports() refuses such inputs)")
    sample = np.unique(np.linspace(0, order.size - 1, num=min(order.size, _CELL_SAMPLE)).astype(np.int64))
    for i in sample.tolist():
        if builder.GetCell(i).site != order[i]:
            raise RuntimeError(f"boost: cell {i} belongs to site {builder.GetCell(i).site}, "
                               f"not to the {i}-th site in (x, y) order ({int(order[i])})")
    return order


def vertex_triples(n_vertices: int, start: NDArray[np.int64], cell_of: NDArray[np.int64]) -> NDArray[np.int64]:
    """The three smallest site ids of each vertex's cells, from (start vertex, cell site) per half-edge."""
    finite = start >= 0
    v, s = start[finite], cell_of[finite]
    order = np.lexsort((s, v))
    v, s = v[order], s[order]
    first = np.searchsorted(v, np.arange(n_vertices))
    if np.any(np.bincount(v, minlength=n_vertices) < 3):
        bad = int(np.flatnonzero(np.bincount(v, minlength=n_vertices) < 3)[0])
        raise RuntimeError(f"boost: vertex {bad} touches fewer than three cells")
    return np.stack([s[first], s[first + 1], s[first + 2]], axis=1)


def supports(sites: NDArray[np.float64]) -> Optional[str]:
    """None if Boost can take the sites, else why not.

    Sites already on the grid are always taken. Otherwise refused: inputs where rounding
    merges distinct sites, or where it changes any decision that makes the sites' Delaunay
    triangulation what it is (a triangle's orientation, a hull turn, an in-circle test;
    exact, see :func:`impls.external.screen.changed_decisions`): Boost would then return
    the diagram of different sites. This catches inputs degenerate at a finer scale than
    the grid (``near_grid``, ``parabola``, far-flung ``kuzmin``).
    """
    sites, problem = exact_range_sites(sites)     # what run() will hand over, at any magnitude
    if problem:
        return problem
    n = sites.shape[0]
    if n <= 1:
        return None
    points, _, scale, moved = to_grid(sites)
    if not math.isfinite(scale) or scale == 0.0:
        return "the bounding box is too small or too large for a power-of-two grid scale"
    if not moved.any():
        return None
    distinct = np.unique(points, axis=0).shape[0]
    if distinct < n:
        return f"rounding to Boost's 32-bit integer grid merges {n - distinct} of {n} sites"
    tr = triangulation(sites)
    if tr is None:   # collinear: they must stay collinear (the order along the line is kept)
        if np.any(orient2d_many(points[0], points[1], points[2:])):
            return "rounding to Boost's 32-bit integer grid makes collinear sites non-collinear"
        return None
    reason = changed_decisions(tr, sites, points)
    if reason:
        return f"rounding to Boost's 32-bit integer grid changes the diagram: {reason}"
    return None


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites`` through Boost.Polygon."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites)
    clock = BuildClock()
    points, centre, scale, moved = to_grid(sites)
    builder = pyvoronoi.Pyvoronoi(1)
    for point in points.astype(np.int64).tolist():
        builder.AddPoint(point)
    with clock.library():
        builder.Construct()
    cell_site = _cell_sites(builder, points)
    fields = attrgetter("start", "end", "cell", "twin")
    count = builder.CountEdges()
    edges = np.fromiter((x for e in builder.GetEdges() for x in fields(e)), dtype=np.int64,
                        count=4 * count).reshape(count, 4)
    half = np.flatnonzero(np.arange(edges.shape[0]) < edges[:, 3])   # one half-edge per twin pair
    edge_sites = np.stack([cell_site[edges[half, 2]], cell_site[edges[edges[half, 3], 2]]], axis=1)
    recompute = bool(moved.any())
    n_vertices = builder.CountVertices()
    if recompute:   # Boost's coordinates are those of the rounded sites: use the true sites'
        vertices = circumcentres(sites, vertex_triples(n_vertices, edges[:, 0], cell_site[edges[:, 2]]))
    else:
        vertices = np.array([(v.X, v.Y) for v in builder.GetVertices()], dtype=np.float64).reshape(-1, 2)
        vertices = vertices / scale + centre
    diagram = assemble(sites, vertices, edge_sites, edges[half, :2])
    clock.report()
    if stats is not None:
        stats.update(rounded_sites=int(moved.sum()), grid_scale_log2=int(math.frexp(scale)[1] - 1),
                     boost_vertices=int(n_vertices), boost_edges=int(half.size),
                     vertices_from_sites=int(recompute))
    return diagram


def warmup() -> None:
    """Compile the numba kernels the adapter uses (DCEL builder, circumcentres, screening)."""
    sites = np.random.default_rng(0).random((40, 2))
    supports(sites)
    build(sites)


IMPLEMENTATION = Implementation(
    name="boost",
    description="Boost.Polygon Voronoi sweep via pyvoronoi (32-bit integer input: sites scaled and rounded)",
    complexity="O(n log n)",
    build=build,
    exact=False,
    origin="Boost.Polygon voronoi (C++), Python package pyvoronoi",
    supports=supports,
    warmup=warmup,
    kind="outside",
)
