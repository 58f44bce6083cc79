"""GEOS's Voronoi diagram (``shapely.voronoi_polygons``) converted back into the vorobench DCEL.

CONTRACT
--------
Complexity: O(n log n) expected for GEOS (incremental Delaunay triangulation on a
quad-edge structure, sites inserted in sorted order, then one polygon per cell, clipped).
Conversion: O(n log n) (sorting of coordinates).
Input: prepared sites (distinct, finite float64), any n >= 0, within the limits below.
GEOS computes in floating point (``exact=False``): nearly cocircular sites may give
several vertices a rounding error apart, which ``compare`` contracts within tolerance.
Library part (``library_s``): ``shapely.voronoi_polygons(..., ordered=True, extend_to=box)``,
one polygon per site in input order, clipped to an envelope ``box``: the sites' bounding
box grown on every side by 2**e times its larger side. GEOS's default (e = 0) loses the
Voronoi vertices farther out, which nearly collinear hull sites put anywhere (~1e4 box
sizes for 1e5 uniform sites), while large envelopes make GEOS's clipping fail on exactly
degenerate inputs (grids, at e >= 14). So e is searched (``ENVELOPE_EXPONENTS``): a
result whose unbounded cells are not exactly the hull sites (exact test), or with an edge
cut at both ends although the sites are not collinear, lost vertices (larger e); a GEOS
failure asks for a smaller e. Discarded attempts are timed as ``discarded``.
Recovering the combinatorics (``convert_s``), one rule per kind of polygon vertex:
* A ring vertex strictly inside the envelope is a Voronoi vertex. GEOS computes each
  circumcentre once and shares it between the cells around it, so vertices are identified
  by their exact coordinates.
* A ring vertex on the envelope's boundary is where an edge was cut: it stands for infinity.
* A ring segment with both ends on the same side of the envelope is part of the envelope,
  not of the diagram: it is dropped. Every other segment is (part of) a Voronoi edge of
  the cell, oriented counter-clockwise (rings are reoriented if GEOS gives them clockwise).
* Its twin is the segment with the same two end points in the opposite order in another
  cell: both cells cut the same edge at the same point, which GEOS computes identically
  (checked: an unmatched segment raises an error naming it).
So rays become half-edges from or to infinity and the parallel lines of collinear sites
(segments from boundary to boundary) become lines, as the contract wants.
Limitations, all refused by ``supports`` (decided on the sites' own Delaunay
triangulation, :mod:`.screen`): a Voronoi vertex beyond the largest envelope (2**18 box
sizes: hull sites collinear to within ~1e-6) cannot be returned; Delaunay neighbours
cocircular to within ``MIN_INCIRCLE_MARGIN`` (but not exactly) make GEOS's cells stop
fitting together, its decisions being floating point; cells thinner than the float
resolution of the envelope's coordinates (two sites 1e-22 box sizes apart) make its
clipping fail. Exact degeneracies (grids, cocircular integer points) are fine.
"""

from __future__ import annotations

from typing import Optional

import numpy as np
import shapely
from numpy.typing import NDArray

from impls.base import Implementation
from impls.external.clock import BuildClock
from impls.external.screen import circumcentres, smallest_incircle_margin, triangulation
from vorobench.core.builder import assemble
from vorobench.core.diagram import Diagram
from vorobench.core.hull import all_collinear, convex_hull_boundary
from vorobench.core.scaling import exact_range_sites
from vorobench.core.sorting import argsort_keys, dense_rank

__all__ = ["build", "supports", "diagram_from_cells", "InconsistentCellsError", "ENVELOPE_EXPONENTS",
           "MIN_RELATIVE_SPACING", "MIN_INCIRCLE_MARGIN", "IMPLEMENTATION"]

#: Clip envelope search: the envelope is the sites' bounding box grown on every side by
#: 2**e times its larger side (e = 0 is GEOS's own default). Start at e = 17; if vertices
#: were lost, step up by 7 (but never above e = 18: GEOS's clipping fails from e = 20 on
#: nearly degenerate inputs that need it); if GEOS failed to clip (large envelopes break its
#: overlay on exactly degenerate inputs such as grids), step down by 7.
#: (start, step, largest exponent)
ENVELOPE_EXPONENTS = (17, 7, 18)

#: Delaunay neighbours this close to cocircular (but not exactly) are refused: GEOS's cells
#: stopped fitting together at 8e-15 (scale-free in-circle margin, see :mod:`.screen`).
MIN_INCIRCLE_MARGIN = 1e-12

#: Sites closer than this fraction of the bounding box are refused: their cells are too thin
#: to survive GEOS's clipping at the envelope's coordinates (seen failing at 1e-22).
MIN_RELATIVE_SPACING = 2.0**-40

_MAX_ATTEMPTS = 6
_MIN_GEOS = (3, 12, 0)        # ordered=True (cells in input order) needs GEOS 3.12 ...
_MIN_SHAPELY = (2, 1)         # ... and shapely 2.1


def _too_old() -> Optional[str]:
    """Why this shapely/GEOS cannot give cells in input order, or None."""
    shapely_version = tuple(int(part) for part in shapely.__version__.split(".")[:2] if part.isdigit())
    if shapely.geos_version < _MIN_GEOS or shapely_version < _MIN_SHAPELY:
        return (f"shapely {shapely.__version__} with GEOS {'.'.join(map(str, shapely.geos_version))}: "
                f"cells in input order need shapely >= 2.1 and GEOS >= 3.12")
    return None


class InconsistentCellsError(RuntimeError):
    """GEOS's cell polygons do not fit together (an edge of one cell is no other cell's edge)."""


def supports(sites: NDArray[np.float64]) -> Optional[str]:
    """None if GEOS can return the diagram, else why not: the library is too old; two sites
    are closer than ``MIN_RELATIVE_SPACING`` of the box (cells thinner than the envelope's
    float resolution break GEOS's clipping); or a Voronoi vertex lies outside the largest
    envelope tried (nearly collinear sites on the hull put vertices arbitrarily far away;
    GEOS triangulates inside a finite frame and clips its cells, so it cannot return them).
    Decided on the exact triangulation of the sites (:mod:`.screen`)."""
    old = _too_old()
    if old:
        return old
    sites, problem = exact_range_sites(sites)     # what run() will hand over, at any magnitude
    if problem:
        return problem
    n = sites.shape[0]
    if n <= 1:
        return None
    size = float(np.max(sites.max(axis=0) - sites.min(axis=0)))
    tr = triangulation(sites)
    if tr is None:              # collinear: neighbours along the line (lexicographic order)
        ordered = sites[np.lexsort((sites[:, 1], sites[:, 0]))]
        gaps = np.hypot(*np.diff(ordered, axis=0).T)
    else:                       # the nearest neighbours are joined by Delaunay edges
        t = tr.triangles
        gaps = np.hypot(*(sites[t] - sites[np.roll(t, 1, axis=1)]).reshape(-1, 2).T)
    closest = float(gaps.min())
    if closest < MIN_RELATIVE_SPACING * size:
        return (f"two sites are {closest / size:.3g} box sizes apart: GEOS cannot clip cells that "
                f"thin at the envelope's coordinates (below {MIN_RELATIVE_SPACING:.3g})")
    if tr is None:
        return None
    margin, quad = smallest_incircle_margin(tr, sites)
    if margin < MIN_INCIRCLE_MARGIN:
        return (f"sites {[int(i) for i in quad]} are cocircular to within {margin:.2g} (scale-free; "
                f"0: beyond float), below {MIN_INCIRCLE_MARGIN:g}: GEOS decides in floating point there "
                f"and its cells stop fitting")
    centres = circumcentres(sites, tr.triangles)
    box = _envelope(sites, 2.0**ENVELOPE_EXPONENTS[2])
    outside = np.any(centres < box[:2], axis=1) | np.any(centres > box[2:], axis=1)
    if outside.any():
        far = float(np.max(np.abs(centres[outside] - sites.mean(axis=0)))) / size
        return (f"{int(outside.sum())} Voronoi vertices lie outside the largest envelope "
                f"(2^{ENVELOPE_EXPONENTS[2]} box sizes; the farthest ~{far:.3g}): GEOS clips them away")
    return None


def _envelope(sites: NDArray[np.float64], growth: float) -> NDArray[np.float64]:
    """(xmin, ymin, xmax, ymax) of the clip envelope (n >= 2 distinct sites: a positive size)."""
    lo, hi = sites.min(axis=0), sites.max(axis=0)
    grow = growth * float(np.max(hi - lo))
    return np.concatenate([lo - grow, hi + grow])


def _rings(polygons: NDArray[np.object_]) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]:
    """Exterior rings without the closing repeat, counter-clockwise: (points, their cell, next point).

    ``next[k]`` is the index of the point after k on the same ring (cyclically).
    """
    kind, coords, (ring_offsets, polygon_offsets) = shapely.to_ragged_array(polygons)
    if kind != shapely.GeometryType.POLYGON or np.any(np.diff(polygon_offsets) != 1):
        raise InconsistentCellsError("geos: a cell is not a simple polygon")
    counts = np.diff(ring_offsets) - 1                       # drop each ring's closing point
    keep = np.ones(coords.shape[0], dtype=bool)
    keep[ring_offsets[1:] - 1] = False
    xy = coords[keep]
    cell = np.repeat(np.arange(counts.size, dtype=np.int64), counts)
    first = np.repeat(np.cumsum(counts) - counts, counts)
    nxt = np.arange(xy.shape[0], dtype=np.int64) + 1
    nxt[np.cumsum(counts)[counts > 0] - 1] = first[np.cumsum(counts)[counts > 0] - 1]
    # signed area of each ring (shoelace, relative to its first point for accuracy)
    rel = xy - xy[first]
    area = np.bincount(cell, weights=rel[:, 0] * rel[nxt, 1] - rel[:, 1] * rel[nxt, 0], minlength=counts.size)
    clockwise = area[cell] < 0
    if clockwise.any():        # reverse each clockwise ring in place
        pos = np.flatnonzero(clockwise)
        last = first[pos] + counts[cell[pos]] - 1
        xy[pos] = xy[first[pos] + last - pos]
    return xy, cell, nxt


def _sides(xy: NDArray[np.float64], box: NDArray[np.float64]) -> NDArray[np.uint8]:
    """Bit mask of the envelope sides each point lies on (0 = strictly inside)."""
    return ((xy[:, 0] == box[0]).astype(np.uint8) | (xy[:, 1] == box[1]) << 1
            | (xy[:, 0] == box[2]) << 2 | (xy[:, 1] == box[3]) << 3).astype(np.uint8)


def _point_ids(xy: NDArray[np.float64]) -> NDArray[np.int64]:
    """Dense ids of the distinct points (exact equality of both coordinates; -0.0 == 0.0)."""
    bits = np.ascontiguousarray(xy + 0.0).view(np.int64)      # + 0.0 turns -0.0 into 0.0
    rx, ry = dense_rank(bits[:, 0]), dense_rank(bits[:, 1])
    return dense_rank(rx * (int(ry.max(initial=0)) + 1) + ry)


def diagram_from_cells(sites: NDArray[np.float64], polygons: NDArray[np.object_],
                       box: NDArray[np.float64]) -> Diagram:
    """The DCEL of Voronoi cells given as polygons clipped to ``box`` (cell i = site i)."""
    n = sites.shape[0]
    if polygons.size != n:
        raise InconsistentCellsError(f"geos: {polygons.size} cells for {n} sites")
    xy, cell, nxt = _rings(polygons)
    side = _sides(xy, box)
    real = (side & side[nxt]) == 0               # not a piece of the envelope
    seg = np.flatnonzero(real)
    inside = side == 0
    point = _point_ids(xy)
    vid = dense_rank(point[inside])
    vertex = np.full(xy.shape[0], -1, dtype=np.int64)
    vertex[inside] = vid
    vertices = np.empty((int(vid.max(initial=-1)) + 1, 2))
    vertices[vid] = xy[inside]
    # pair segment p -> q of one cell with q -> p of another, by sorted (p, q) keys
    stride = int(point.max(initial=0)) + 1
    forward = point[seg] * stride + point[nxt[seg]]
    backward = point[nxt[seg]] * stride + point[seg]
    order_f, order_b = argsort_keys(forward), argsort_keys(backward)
    twin = np.empty(seg.size, dtype=np.int64)
    twin[order_b] = order_f                   # the k-th smallest of each list: the same key
    ok = forward[twin] == backward
    if not ok.all() or np.any(forward[order_f][1:] == forward[order_f][:-1]):
        k = int(np.flatnonzero(~ok)[0]) if not ok.all() else 0
        raise InconsistentCellsError(
            f"geos: the edge of cell {int(cell[seg[k]])} from {tuple(map(float, xy[seg[k]]))} to "
            f"{tuple(map(float, xy[nxt[seg[k]]]))} is not an edge of any other cell")
    first = np.flatnonzero(np.arange(seg.size) < twin)     # one segment per twin pair
    a, b = cell[seg[first]], cell[seg[twin[first]]]
    if np.any(a == b):
        raise InconsistentCellsError(f"geos: cell {int(a[a == b][0])} borders itself")
    edge_vertices = np.stack([vertex[seg[first]], vertex[nxt[seg[first]]]], axis=1)
    return assemble(sites, vertices, np.stack([a, b], axis=1), edge_vertices)


def _fits_hull(diagram: Diagram, hull: NDArray[np.int64], collinear: bool) -> bool:
    """Whether the unbounded cells are exactly the hull sites and, unless the sites are
    collinear, no edge is a full line (both ends cut off: a vertex was lost)."""
    dest = diagram.origin[diagram.twin]
    infinite = (diagram.origin < 0) | (dest < 0)
    if not collinear and np.any((diagram.origin < 0) & (dest < 0)):
        return False
    return np.array_equal(np.unique(diagram.site[infinite]), hull)


def _cells(points: shapely.Geometry, sites: NDArray[np.float64], growth: float, clock: BuildClock) -> Diagram:
    """GEOS's cells clipped to the envelope of this growth, as a DCEL (or an error saying why not)."""
    box = _envelope(sites, growth)
    with clock.library():
        try:
            collection = shapely.voronoi_polygons(points, extend_to=shapely.box(*box), ordered=True)
        except shapely.errors.GEOSException as exc:
            raise InconsistentCellsError(f"geos: GEOS failed: {exc}") from exc
    try:
        polygons = shapely.get_parts(collection)
        return diagram_from_cells(sites, polygons, box)
    except ValueError as exc:        # a clipped cell that is not a polygon; a DCEL that does not close
        raise InconsistentCellsError(f"geos: {exc}") from exc


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites`` through GEOS (shapely).

    Searches the clip envelope (see ``ENVELOPE_EXPONENTS``) until the cells fit together,
    the unbounded ones are exactly the sites on the convex-hull boundary (exact test) and
    no edge lost both its ends. If no envelope does, returns the diagram of the first
    envelope that converted (certification says what is wrong with it), or raises the first
    error. Only the attempt returned counts in the ``library``/``convert`` timings; the others are
    ``discarded``.
    """
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites)
    old = _too_old()
    if old:
        raise RuntimeError(f"geos: {old}")
    clock = BuildClock()
    points = shapely.multipoints(sites)
    hull = convex_hull_boundary(sites)
    collinear = all_collinear(sites)
    first: Optional[Diagram] = None
    first_error: Optional[Exception] = None
    diagram: Optional[Diagram] = None
    lo, hi = 0, ENVELOPE_EXPONENTS[2]
    exponent, tried = ENVELOPE_EXPONENTS[0], []
    while exponent not in tried and lo <= exponent <= hi and len(tried) < _MAX_ATTEMPTS:
        tried.append(exponent)
        since = clock.mark()
        try:
            candidate = _cells(points, sites, 2.0**exponent, clock)
        except InconsistentCellsError as exc:       # clipping failed: try a smaller envelope
            clock.discard(since)
            first_error = first_error or exc
            hi = exponent - 1
            exponent = max(lo, exponent - ENVELOPE_EXPONENTS[1])
            continue
        if _fits_hull(candidate, hull, collinear):
            diagram = candidate
            break
        clock.discard(since)                         # vertices lost: try a larger envelope
        first = first or candidate
        lo = exponent + 1
        exponent = min(hi, exponent + ENVELOPE_EXPONENTS[1])
    diagram = diagram or first
    if diagram is None:
        assert first_error is not None
        raise first_error
    clock.report()
    if stats is not None:
        stats.update(geos_vertices=diagram.n_vertices, envelope_attempts=len(tried),
                     envelope_log2_growth=tried[-1] if diagram is not first else -1)
    return diagram


def warmup() -> None:
    """Compile the numba kernels the adapter uses (DCEL builder, circumcentres, screening)."""
    sites = np.random.default_rng(0).random((40, 2))
    supports(sites)
    build(sites)


IMPLEMENTATION = Implementation(
    name="geos",
    description="GEOS Voronoi cells via shapely.voronoi_polygons (floating point), clipped cells turned back into the DCEL",
    complexity="O(n log n)",
    build=build,
    exact=False,
    origin=f"GEOS {'.'.join(map(str, shapely.geos_version))} (C++), Python package shapely",
    supports=supports,
    warmup=warmup,
    kind="outside",
)
