"""Shewchuk's Triangle (the ``triangle`` package): its Delaunay triangulation, Voronoi as the dual.

CONTRACT
--------
Complexity: O(n log n) for Triangle's divide and conquer (default) and its Fortune sweep
(switch ``F``); O(n^(4/3)) expected for its incremental insertion (switch ``i``: each point
is located by Mucke, Saias and Zhu's jump and walk from a random sample of triangles).
The conversion is O(n).
Input: prepared sites (distinct, finite float64), any n >= 0. Triangle refuses fewer than
three vertices and returns no triangle for collinear ones: both give the n - 1 parallel
bisector lines (:func:`vorobench.core.builder.collinear_diagram`).
Library part: ``triangle.triangulate(..., "n" + switch)`` gives CCW triangles and, for each
corner, the triangle across the opposite edge (-1 on the hull). That call is ``library_s``.
Conversion (``convert_s``): the hull is closed with ghost triangles (one per hull edge,
using an infinite vertex n) so that the triangulation has the layout of our own
incremental implementation, and its dual is taken by the same routine,
:func:`vorobench.core.delaunay_dual.voronoi_dcel`: circumcentres from the three smallest site
ids on each empty circle, hull edges become rays, and neighbours whose four sites are
exactly cocircular (exact ``incircle == 0``) are merged into one vertex of degree >= 4.
Exactness: Triangle decides every orientation and in-circle test with Shewchuk's adaptive
exact predicates (the ``X`` switch, which would turn them off, is never used). For divide
and conquer and incremental insertion the triangulation is therefore a Delaunay
triangulation of the exact input; the only freedom left, how cocircular groups are split
into triangles, is removed by the exact merging, and the float vertex coordinates are
computed by our routine, by the same rule as the other exact implementations. So the
diagram is determined by the input alone and must agree bit for bit with any other exact
build: ``exact=True``, a claim the cross-validation tests check on every family.
The sweep (``F``) is *not* exact in that sense, though its orientation and in-circle
tests are: on nearly degenerate input (``near_grid``, ``huge_offset``) it returns
triangulations with edges that fail the exact in-circle test, drops sites, or leaves a
hull that is not a closed cycle (witnesses ``tests/impls/witnesses/triangle_sweep_*.txt``,
4 to 9 sites). Two decisions of its sweep are plain floating point in triangle.c: where a
new site falls on the front (``rightofhyperbola``) and when a circle event fires
(``circletop``); on nearly collinear sites they go wrong. It is marked
``exact=False``, and ``supports`` refuses nearly collinear inputs: those whose Delaunay
triangulation has a triangle flatter than ``SWEEP_MIN_FLATNESS`` (height over longest
side). Exact degeneracies (``grid``, ``cocircular``, ``collinear``) are fine and accepted.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
import triangle
from numba import njit
from numpy.typing import NDArray

from impls.base import Implementation
from impls.external.clock import BuildClock
from impls.external.screen import flattest_triangle, triangulation
from vorobench.core.builder import collinear_diagram
from vorobench.core.delaunay_dual import voronoi_dcel
from vorobench.core.diagram import Diagram
from vorobench.core.predicates import INCIRCLE_CALLS, INCIRCLE_EXACT
from vorobench.core.scaling import exact_range_sites

__all__ = ["build", "build_with", "ghost_layout", "sweep_supports", "SWEEP_MIN_FLATNESS", "SWITCHES",
           "DIVIDE_AND_CONQUER", "SWEEP", "INCREMENTAL", "IMPLEMENTATION"]

#: Triangle's sweep is refused inputs whose Delaunay triangulation has a triangle flatter than
#: this (height / longest side). It failed on triangles of flatness 1e-13 to 1e-16 (near_grid);
#: every other dataset family stays above 1e-6 up to n = 1e5.
SWEEP_MIN_FLATNESS = 1e-10

#: Registry name -> Triangle's switch selecting the algorithm ("" = divide and conquer).
SWITCHES = {"triangle": "", "triangle-sweep": "F", "triangle-incremental": "i"}


@njit(cache=True)
def _ghost_layout(tri3, neighbours, n):
    T = tri3.shape[0]
    hull = 0
    for t in range(T):
        for k in range(3):
            hull += neighbours[t, k] < 0
    tri = np.empty(3 * (T + hull), dtype=np.int64)
    opp = np.empty(3 * (T + hull), dtype=np.int64)
    ghost_from = np.full(n, -1, dtype=np.int64)     # ghost of the hull edge starting at a site
    ghost_to = np.full(n, -1, dtype=np.int64)       # ghost of the hull edge ending at a site
    g = T
    for t in range(T):
        for k in range(3):
            tri[3 * t + k] = tri3[t, k]
    for t in range(T):
        for k in range(3):
            e = 3 * t + k
            a = tri3[t, k]
            b = tri3[t, (k + 1) % 3]
            across = neighbours[t, (k + 2) % 3]      # Triangle: the triangle opposite corner k + 2
            if across >= 0:
                opp[e] = -1
                for j in range(3):
                    if tri3[across, j] == b:
                        opp[e] = 3 * across + j
                if opp[e] < 0:
                    raise RuntimeError("triangle: a triangle and its neighbour share no edge")
            else:                                     # hull edge a -> b: ghost (b, a, n) outside
                tri[3 * g] = b
                tri[3 * g + 1] = a
                tri[3 * g + 2] = n
                opp[e] = 3 * g
                opp[3 * g] = e
                if ghost_from[a] >= 0 or ghost_to[b] >= 0:
                    raise RuntimeError("triangle: the hull edges do not form one closed cycle")
                ghost_from[a] = g
                ghost_to[b] = g
                g += 1
    for g in range(T, T + hull):
        b = tri[3 * g]
        a = tri[3 * g + 1]
        before = ghost_to[a]                          # a -> n meets n -> a of the previous ghost
        after = ghost_from[b]                         # n -> b meets b -> n of the next ghost
        if before < 0 or after < 0:
            raise RuntimeError("triangle: the hull edges do not form one closed cycle")
        opp[3 * g + 1] = 3 * before + 2
        opp[3 * g + 2] = 3 * after + 1
    return tri, opp, T + hull


def ghost_layout(triangles: NDArray[np.integer], neighbours: NDArray[np.integer], n: int
                 ) -> tuple[NDArray[np.int64], NDArray[np.int64], int]:
    """Triangle's (triangles, neighbours) as flat corner/opposite arrays closed by ghosts.

    Half-edge ``e = 3 t + k`` runs from corner k of triangle t to corner k + 1; ``opp[e]`` is
    the half-edge running back in the triangle across (Triangle gives, per corner, the
    triangle across the *opposite* edge, hence the shift). Each hull edge a -> b gets a
    ghost triangle (b, a, n) on its outer side; consecutive ghosts share their edges to n.
    Returns (tri, opp, number of triangles including ghosts); raises if the hull edges do
    not form one closed cycle.
    """
    return _ghost_layout(np.ascontiguousarray(triangles, dtype=np.int64).reshape(-1, 3),
                         np.ascontiguousarray(neighbours, dtype=np.int64).reshape(-1, 3), int(n))


def build_with(sites: NDArray[np.float64], stats: Optional[dict], switch: str) -> Diagram:
    """The Voronoi diagram of prepared ``sites`` from Triangle run with algorithm ``switch``."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites)
    clock = BuildClock()
    out: dict = {}
    if n >= 3:
        with clock.library():
            out = triangle.triangulate({"vertices": np.array(sites)}, "n" + switch)  # Cython wants a writable buffer
    triangles = out.get("triangles")
    if triangles is None or len(triangles) == 0:
        diagram = collinear_diagram(sites)
        clock.report()
        if stats is not None:
            stats.update(collinear=1, triangles=0)
        return diagram
    tri, opp, ntri = ghost_layout(triangles, out["neighbors"], n)
    counters = np.zeros(4, dtype=np.int64)
    ids = np.arange(n, dtype=np.int64)           # Triangle keeps the input order: point v is site v
    vertices, origin, twin, nxt, site, merged = voronoi_dcel(sites, ids, tri, opp, ntri, counters)
    diagram = Diagram(sites, vertices, origin, twin, nxt, site)
    clock.report()
    if stats is not None:
        stats.update(triangles=int(len(triangles)), merged_triangles=int(merged),
                     dual_incircle_calls=int(counters[INCIRCLE_CALLS]),
                     dual_incircle_exact=int(counters[INCIRCLE_EXACT]))
    return diagram


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """Triangle's default divide and conquer (alternating cuts)."""
    return build_with(sites, stats, SWITCHES["triangle"])


def _build_sweep(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    return build_with(sites, stats, SWITCHES["triangle-sweep"])


def _build_incremental(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    return build_with(sites, stats, SWITCHES["triangle-incremental"])


def sweep_supports(sites: NDArray[np.float64]) -> Optional[str]:
    """None if the sweep can take the sites; refused: nearly collinear inputs, where a
    triangle of the sites' Delaunay triangulation is flatter than ``SWEEP_MIN_FLATNESS``
    (height over longest side). On such inputs Triangle's sweep drops sites or returns
    non-Delaunay triangulations (witnesses in ``tests/impls/witnesses/triangle_sweep_*``)."""
    sites, problem = exact_range_sites(sites)     # what run() will hand over, at any magnitude
    if problem:
        return problem
    if sites.shape[0] <= 3:
        return None
    tr = triangulation(sites)
    if tr is None:
        return None
    flatness, ids = flattest_triangle(tr, sites)
    if flatness < SWEEP_MIN_FLATNESS:
        return (f"nearly collinear sites {[int(i) for i in ids]} (a Delaunay triangle of flatness "
                f"{flatness:.2g} < {SWEEP_MIN_FLATNESS:g}), where Triangle's sweep fails")
    return None


def warmup() -> None:
    """Compile the dual's numba kernels (Triangle itself is C) on every code path."""
    rng = np.random.default_rng(0)
    for sites in (rng.random((40, 2)), np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [0.5, 0.5]])):
        sites.setflags(write=False)          # as Implementation.run passes them: one compiled version
        build(sites)


_ORIGIN = "Triangle (J. R. Shewchuk, C), Python package triangle"

DIVIDE_AND_CONQUER = Implementation(
    name="triangle",
    description="Shewchuk's Triangle, divide and conquer (exact predicates), Voronoi as the dual",
    complexity="O(n log n)",
    build=build,
    exact=True,
    origin=_ORIGIN,
    warmup=warmup,
    kind="outside",
)
SWEEP = Implementation(
    name="triangle-sweep",
    description="Shewchuk's Triangle, Fortune's sweep (switch F), Voronoi as the dual (not Delaunay on near-degenerate input)",
    complexity="O(n log n)",
    build=_build_sweep,
    exact=False,
    supports=sweep_supports,
    origin=_ORIGIN,
    warmup=warmup,
    kind="outside",
)
INCREMENTAL = Implementation(
    name="triangle-incremental",
    description="Shewchuk's Triangle, incremental insertion (switch i), Voronoi as the dual",
    complexity="O(n^(4/3)) expected",
    build=_build_incremental,
    exact=True,
    origin=_ORIGIN,
    warmup=warmup,
    kind="outside",
)
IMPLEMENTATION = DIVIDE_AND_CONQUER
