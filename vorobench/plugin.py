"""What a plugin author imports: the names needed to write a vorobench implementation.

A complete plugin, ``my_voronoi.py`` (scipy's Voronoi under another name)::

    import numpy as np
    from scipy.spatial import Voronoi

    from vorobench.plugin import Diagram, Implementation, all_collinear, assemble, collinear_diagram


    def build(sites, stats=None):
        if len(sites) <= 1:
            return Diagram.empty(sites)
        if all_collinear(sites):                  # no vertex at all: n - 1 parallel lines
            return collinear_diagram(sites)
        vor = Voronoi(sites)
        ends = np.asarray(vor.ridge_vertices, dtype=np.int64)
        if stats is not None:
            stats["ridges"] = len(ends)           # counters: machine-independent integers
        # Each ridge once: its two sites and its two vertex ids (-1 = infinity) in either
        # order; the builder orients them exactly and links the half-edges.
        return assemble(sites, vor.vertices, vor.ridge_points, ends, oriented=False)


    IMPLEMENTATIONS = [Implementation(
        name="my-voronoi", description="scipy.spatial.Voronoi, assembled by vorobench",
        complexity="O(n log n)", build=build, exact=False, origin="scipy (Qhull)")]

Then ``vorobench validate --plugin my_voronoi.py --impls my-voronoi`` judges it, and an
installed package lists it in the entry-point group ``vorobench.impls`` instead (a complete
one: ``examples/plugin/``). ``docs/implementations.md`` is the full guide.
"""

from __future__ import annotations

from impls.base import BuildFunction, Implementation, UnsupportedInput, record_timing
from vorobench.core.builder import assemble, collinear_diagram
from vorobench.core.diagram import Diagram
from vorobench.core.hull import all_collinear

__all__ = ["Implementation", "BuildFunction", "UnsupportedInput", "record_timing", "Diagram", "assemble",
           "collinear_diagram", "all_collinear"]
