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
from numpy.typing import NDArray

from impls.base import Implementation
from impls.external.clock import BuildClock
from impls.external.screen import flattest_triangle, triangulation
from vorobench.core.builder import collinear_diagram
from vorobench.core.delaunay_dual import voronoi_dcel
from vorobench.core.ghosts import ghost_layout
from vorobench.core.diagram import Diagram
from vorobench.core.read_only import read_only
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
    vertices, origin, twin, nxt, site, merged = voronoi_dcel(read_only(sites), ids, tri, opp, ntri, counters)
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
