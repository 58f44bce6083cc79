"""The array-based DCEL (half-edge structure) that every implementation returns.

Conventions (docs/dcel.md): half-edge h has cell ``site[h]`` on its left, runs along the
bisector of ``site[h]`` and ``site[twin[h]]`` in direction ``perp(b - a)``, starts at
``origin[h]`` (-1 = infinity), and ``next`` walks each cell counter-clockwise.

A diagram is immutable once made: the scipy-style views (``regions``, ``ridge_points``,
``ridge_vertices``, ...) are computed once, in linear time, and cached.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any, Optional

import numpy as np
from numpy.typing import NDArray

from vorobench.core.branch_curves import DEFAULT_CURVE_TOLERANCE, FINEST_CURVE_TOLERANCE
from vorobench.core.cell_cycles import cell_cycles
from vorobench.core.clip import clip_convex, clip_groups
from vorobench.core.errors import InvalidDiagramError
from vorobench.core.framing import site_box
from vorobench.core.regions import Regions

__all__ = ["Diagram", "InvalidDiagramError"]

_FIELDS = ("sites", "vertices", "origin", "twin", "next", "site")
_INPUT_FIELDS = ("input_points", "input_site", "weights", "radii")
_FORMAT_VERSION = 1


def _first(mask: NDArray[np.bool_]) -> int:
    return int(np.flatnonzero(mask)[0])


def _box_corners(box: tuple[float, float, float, float]) -> NDArray[np.float64]:
    """The corners of (xmin, ymin, xmax, ymax), counter-clockwise from the lower left."""
    xmin, ymin, xmax, ymax = box
    return np.array([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]], dtype=np.float64)


def _read_only(arr: NDArray) -> NDArray:
    arr.setflags(write=False)
    return arr


@dataclass(eq=False, frozen=True)
class Diagram:
    """A 2D Voronoi diagram as flat arrays: sites, vertices and four half-edge arrays.

    ``input_points`` and ``input_site`` optionally keep the caller's rows, duplicates
    included, and the site of each row (:func:`impls.build` and :meth:`from_scipy` fill them),
    so that ``points`` and ``point_region`` have one entry per input row, as in scipy.

    ``weights`` (one per site) makes it a power diagram: the power of x with respect to site
    i is |x - p_i|^2 - w_i, and a *hidden* site (its cell is empty) has no half-edge.
    ``radii`` (one per site) makes it the diagram of disks (docs/apollonius.md): the distance
    from x to disk i is |x - p_i| - r_i, each edge lies on the bisector branch of its two
    disks, two cells may share several edges, and a disk inside another is hidden.
    """

    sites: NDArray[np.float64]
    vertices: NDArray[np.float64]
    origin: NDArray[np.integer]
    twin: NDArray[np.integer]
    next: NDArray[np.integer]
    site: NDArray[np.integer]
    input_points: Optional[NDArray[np.float64]] = field(default=None, repr=False)
    input_site: Optional[NDArray[np.integer]] = field(default=None, repr=False)
    weights: Optional[NDArray[np.float64]] = field(default=None, repr=False)
    radii: Optional[NDArray[np.float64]] = field(default=None, repr=False)

    #: scipy's ``Voronoi.furthest_site``: these are nearest-site diagrams (read by
    #: ``scipy.spatial.voronoi_plot_2d``).
    furthest_site = False
    #: scipy's ``Voronoi.ndim``: the plane.
    ndim = 2

    def __post_init__(self) -> None:
        if (self.input_points is None) != (self.input_site is None):
            raise ValueError("input_points and input_site go together: give both or neither")
        if self.input_site is not None:
            rows = np.asarray(self.input_points).reshape(-1, 2).shape[0]
            if np.shape(self.input_site) != (rows,):
                raise ValueError(f"input_site has shape {np.shape(self.input_site)}, input_points has {rows} rows")
        if self.weights is not None and np.shape(self.weights) != (np.shape(self.sites)[0],):
            raise ValueError(f"weights has shape {np.shape(self.weights)}, there are {np.shape(self.sites)[0]} sites")
        if self.radii is not None and np.shape(self.radii) != (np.shape(self.sites)[0],):
            raise ValueError(f"radii has shape {np.shape(self.radii)}, there are {np.shape(self.sites)[0]} sites")
        if self.radii is not None and self.weights is not None:
            raise ValueError("a diagram has weights (power) or radii (disks), not both")
        # Immutable through the diagram: its arrays are read-only views (whoever built them keeps
        # their own, writeable), so the cached views can never go stale.
        for name in _FIELDS + _INPUT_FIELDS:
            value = getattr(self, name)
            if isinstance(value, np.ndarray) and value.flags.writeable:
                view = value.view()
                view.setflags(write=False)
                object.__setattr__(self, name, view)

    def with_input(self, points: NDArray[np.float64], inverse: NDArray[np.integer]) -> "Diagram":
        """The same diagram remembering the caller's rows ``points`` and the site ``inverse[i]``
        of each row (what :func:`vorobench.prepare` returned), duplicates included."""
        points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        inverse = np.asarray(inverse, dtype=np.int64).reshape(-1)
        if inverse.size and (inverse.min() < 0 or inverse.max() >= self.n_sites):
            raise ValueError(f"inverse names sites outside [0, {self.n_sites})")
        return Diagram(self.sites, self.vertices, self.origin, self.twin, self.next, self.site,
                       _read_only(points.copy()), _read_only(inverse.copy()), self.weights, self.radii)

    def with_weights(self, weights: Optional[NDArray[np.float64]]) -> "Diagram":
        """The same DCEL as a power diagram of these site ``weights`` (None: ordinary)."""
        if weights is not None:
            weights = _read_only(np.array(weights, dtype=np.float64).reshape(-1))
        return Diagram(self.sites, self.vertices, self.origin, self.twin, self.next, self.site,
                       self.input_points, self.input_site, weights, self.radii)

    @classmethod
    def from_scipy(cls, vor: Any) -> "Diagram":
        """The DCEL of a ``scipy.spatial.Voronoi`` (nearest-site, 2-D), its ridges oriented exactly.

        Duplicate input rows (which Qhull keeps as coplanar points) become one site, remembered
        per row in ``points`` / ``point_region``; ridges Qhull collapsed to a single vertex are
        dropped. Raises ``ValueError`` for anything but a 2-D nearest-site diagram and
        :class:`InvalidDiagramError` when its ridges do not close up into cells.
        """
        # Imported here: prepare compiles numba kernels, which an import of Diagram should not wait for.
        from vorobench.core.half_edges import link_edges
        from vorobench.core.prepare import prepare

        for name in ("points", "vertices", "ridge_points", "ridge_vertices"):
            if not hasattr(vor, name):
                raise ValueError(f"from_scipy needs a scipy.spatial.Voronoi, got {type(vor).__name__} without .{name}")
        if getattr(vor, "furthest_site", False):
            raise ValueError("from_scipy takes nearest-site diagrams; this one was built with furthest_site=True")
        points = np.asarray(vor.points, dtype=np.float64)
        if points.ndim != 2 or points.shape[1] != 2:
            raise ValueError(f"from_scipy takes 2-D diagrams; points have shape {points.shape}")
        sites, inverse = prepare(points)
        vertices = np.asarray(vor.vertices, dtype=np.float64).reshape(-1, 2)
        ridge_sites = inverse[np.asarray(vor.ridge_points, dtype=np.int64).reshape(-1, 2)]
        ridge_vertices = np.asarray(vor.ridge_vertices, dtype=np.int64).reshape(-1, 2)
        # a ridge collapsed to a point, or between two rows of one site (duplicates under "QJ")
        keep = (ridge_vertices[:, 0] != ridge_vertices[:, 1]) & (ridge_sites[:, 0] != ridge_sites[:, 1])
        if sites.shape[0] <= 1 or not keep.any():
            raise ValueError(f"from_scipy needs a diagram with ridges; this one has {sites.shape[0]} distinct points")
        arrays = link_edges(sites.shape[0], vertices, ridge_sites[keep], ridge_vertices[keep], sites=sites,
                            oriented=False, compact_vertices=True)
        return cls(sites, *arrays).with_input(points, inverse)

    # ------------------------------------------------------------------ construction
    @classmethod
    def empty(cls, sites: NDArray[np.float64], weights: Optional[NDArray[np.float64]] = None,
              radii: Optional[NDArray[np.float64]] = None) -> "Diagram":
        """The diagram with no edges (n = 0 or 1; or one visible site of a power diagram or of disks)."""
        none = np.zeros(0, dtype=np.int64)
        return cls(np.asarray(sites, dtype=np.float64).reshape(-1, 2), np.zeros((0, 2)),
                   none, none.copy(), none.copy(), none.copy(),
                   weights=None if weights is None else np.asarray(weights, dtype=np.float64).reshape(-1),
                   radii=None if radii is None else np.asarray(radii, dtype=np.float64).reshape(-1))

    # ------------------------------------------------------------------ sizes
    @property
    def n_sites(self) -> int:
        return int(self.sites.shape[0])

    @property
    def n_vertices(self) -> int:
        return int(self.vertices.shape[0])

    @property
    def n_half_edges(self) -> int:
        return int(self.origin.shape[0])

    @property
    def n_edges(self) -> int:
        return self.n_half_edges // 2

    @property
    def is_power(self) -> bool:
        """Whether this is a power diagram (it has site weights)."""
        return self.weights is not None

    @property
    def is_apollonius(self) -> bool:
        """Whether this is the diagram of disks (it has site radii)."""
        return self.radii is not None

    @cached_property
    def hidden(self) -> NDArray[np.int64]:
        """Sites with an empty cell (no half-edge): possible only in a power diagram or one of
        disks, and for every site of a diagram of one site or none; read-only."""
        if self.n_half_edges == 0:
            return _read_only(np.arange(self.n_sites if self.n_sites > 1 else 0, dtype=np.int64))
        has_cell = np.bincount(np.asarray(self.site, dtype=np.int64), minlength=self.n_sites) > 0
        return _read_only(np.flatnonzero(~has_cell).astype(np.int64))

    @property
    def n_visible(self) -> int:
        """Number of sites with a non-empty cell."""
        return self.n_sites - int(self.hidden.size)

    def counts(self) -> dict[str, int]:
        """Sizes as a dict: n (sites), V (vertices), E (edges), H (half-edges)."""
        return {"n": self.n_sites, "V": self.n_vertices, "E": self.n_edges, "H": self.n_half_edges}

    def __repr__(self) -> str:
        c = self.counts()
        return f"Diagram(n={c['n']}, V={c['V']}, E={c['E']}, H={c['H']})"

    # ------------------------------------------------------------------ derived views
    @property
    def destination(self) -> NDArray[np.integer]:
        """Vertex where each half-edge ends (-1 = infinity)."""
        return self.origin[self.twin]

    @property
    def prev(self) -> NDArray[np.int64]:
        """Inverse of ``next``: the half-edge before h along its cell."""
        prev = np.empty(self.n_half_edges, dtype=np.int64)
        prev[self.next] = np.arange(self.n_half_edges)
        return prev

    def edges(self) -> NDArray[np.int64]:
        """One half-edge per twin pair (the one with the smaller index)."""
        h = np.arange(self.n_half_edges)
        return h[h < self.twin]

    @cached_property
    def _cycles(self) -> tuple[NDArray[np.integer], NDArray[np.int64], NDArray[np.integer]]:
        """Every cell's half-edges in ``next`` order (:func:`cell_cycles`), walked once:
        ``(order, offsets, origins)``, ``origins`` being ``origin[order]``."""
        if self.n_half_edges and (self.site.min() < 0 or self.site.max() >= self.n_sites):
            raise InvalidDiagramError(f"site ids must lie in [0, {self.n_sites})")
        order, origins, offsets, bad = cell_cycles(self.site, self.next, self.origin, self.n_sites)
        if bad >= 0:
            raise InvalidDiagramError(f"cell {bad}: next does not walk once around the cell's half-edges")
        return _read_only(order), _read_only(offsets), _read_only(origins)

    def cell_half_edges(self, i: int) -> list[int]:
        """Half-edges of cell i in counter-clockwise order (starting after infinity if unbounded)."""
        order, offsets, _ = self._cycles
        return order[offsets[i]:offsets[i + 1]].tolist()

    # ------------------------------------------------------------------ scipy-style views
    @cached_property
    def _first_row(self) -> NDArray[np.int64]:
        """The first input row of each site (the site's own index without input rows)."""
        if self.input_site is None:
            return np.arange(self.n_sites, dtype=np.int64)
        rows = np.arange(self.input_site.size, dtype=np.int64)
        first = np.full(self.n_sites, -1, dtype=np.int64)
        first[self.input_site[::-1]] = rows[::-1]          # the last write of a site is its first row
        return first

    @property
    def points(self) -> NDArray[np.float64]:
        """scipy-style: the input rows, duplicates included (the sites when none were kept)."""
        return self.sites if self.input_points is None else self.input_points

    @property
    def npoints(self) -> int:
        """scipy-style: number of input rows."""
        return int(self.points.shape[0])

    @property
    def min_bound(self) -> NDArray[np.float64]:
        """scipy-style: the smallest coordinates of the input rows."""
        return self.points.min(axis=0) if self.npoints else np.full(2, np.nan)

    @property
    def max_bound(self) -> NDArray[np.float64]:
        """scipy-style: the largest coordinates of the input rows."""
        return self.points.max(axis=0) if self.npoints else np.full(2, np.nan)

    @cached_property
    def point_region(self) -> NDArray[np.int64]:
        """scipy-style: index into ``regions`` of each input row; duplicates share their cell
        (region i is the cell of site i)."""
        if self.input_site is None:
            return _read_only(np.arange(self.n_sites, dtype=np.int64))
        return _read_only(np.asarray(self.input_site, dtype=np.int64))

    @cached_property
    def regions(self) -> Regions:
        """scipy-style: the vertices of each cell counter-clockwise, -1 where it is unbounded
        (an unbounded cell's list starts at infinity); an empty list for a cell with no edge.
        A read-only sequence whose items are new lists (``.tolist()`` gives scipy's list of
        lists), so a caller cannot change the cached regions."""
        _, offsets, origins = self._cycles
        return Regions(origins, offsets, copy=False)  # read-only, like the cache it comes from

    @cached_property
    def ridge_points(self) -> NDArray[np.int64]:
        """scipy-style (E, 2) array: the input rows (first row of each site) on either side of
        each edge, in ``edges()`` order."""
        e = self.edges()
        pairs = np.stack([self.site[e], self.site[self.twin[e]]], axis=1).astype(np.int64)
        return _read_only(self._first_row[pairs])

    @cached_property
    def ridge_vertices(self) -> NDArray[np.int64]:
        """scipy-style (E, 2) array: the end vertices of each edge, -1 (infinity) first."""
        e = self.edges()
        ends = np.stack([self.origin[e], self.origin[self.twin[e]]], axis=1).astype(np.int64)
        ray = ends[:, 1] < 0
        ends[ray] = ends[ray, ::-1]
        return _read_only(ends)

    @cached_property
    def ridge_dict(self) -> dict[tuple[int, int], list[int]]:
        """scipy-style: ``{(p, q): [v, w]}`` for every ridge, keyed by its two input rows."""
        return {(p, q): [v, w] for (p, q), (v, w) in zip(self.ridge_points.tolist(), self.ridge_vertices.tolist())}

    def half_edge_direction(self, h: NDArray[np.integer] | int) -> NDArray[np.float64]:
        """Direction perp(b - a) of half-edges h (not normalised)."""
        a = self.sites[self.site[h]]
        b = self.sites[self.site[self.twin[h]]]
        d = b - a
        return np.stack([-d[..., 1], d[..., 0]], axis=-1)

    def bounding_box(self, margin: float = 0.1) -> tuple[float, float, float, float]:
        """(xmin, ymin, xmax, ymax) around sites and vertices, widened by ``margin`` of its size."""
        pts = np.concatenate([self.sites, self.vertices]) if self.n_vertices else self.sites
        if pts.shape[0] == 0:
            return (-1.0, -1.0, 1.0, 1.0)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        span = float(max(hi[0] - lo[0], hi[1] - lo[1]))
        pad = margin * span if span > 0 else max(1.0, float(np.abs(lo).max()) * 1e-9)
        return (float(lo[0] - pad), float(lo[1] - pad), float(hi[0] + pad), float(hi[1] + pad))

    def _cell_lines(self, hs: NDArray[np.int64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """(anchor, direction) of the line of each half-edge in ``hs``, its cell on the left.

        Each line goes through the half-edge's end nearer its two sites (a floating-point
        library may place a far-away vertex far off its line), or through their (power)
        bisector's point on the line between them when both ends are at infinity. An edge and
        its twin choose the same point, so neighbouring polygons share their corners exactly.
        """
        if self.radii is not None:
            raise NotImplementedError("cells of disks are bounded by branches of hyperbolas, not lines")
        direction = self.half_edge_direction(hs)
        a, b = self.sites[self.site[hs]], self.sites[self.site[self.twin[hs]]]
        anchor = 0.5 * (a + b)
        if self.weights is not None:
            # a power bisector passes the midpoint moved by (w_a - w_b) / (2 |b - a|^2) of b - a
            w = np.asarray(self.weights, dtype=np.float64)
            t = 0.5 * (w[self.site[hs]] - w[self.site[self.twin[hs]]]) / ((b - a) ** 2).sum(axis=1)
            anchor = anchor + t[:, None] * (b - a)
        if self.n_vertices:
            start, end = self.origin[hs], self.origin[self.twin[hs]]
            ps, pe = self.vertices[np.maximum(start, 0)], self.vertices[np.maximum(end, 0)]
            mid = 0.5 * (a + b)
            ds = np.where(start >= 0, ((ps - mid) ** 2).sum(axis=1), np.inf)
            de = np.where(end >= 0, ((pe - mid) ** 2).sum(axis=1), np.inf)
            # ties go to the vertex with the smaller id, the same choice from either side
            use_start = (ds < de) | ((ds == de) & (start <= end) & (start >= 0))
            anchor = np.where(use_start[:, None], ps, np.where((end >= 0)[:, None], pe, anchor))
        return anchor, direction

    def cell_polygon(self, i: int, box: tuple[float, float, float, float] | None = None, *,
                     tolerance: Optional[float] = None) -> NDArray[np.float64]:
        """Cell i clipped to ``box`` = (xmin, ymin, xmax, ymax), as a CCW (k, 2) polygon
        (default box: around the sites); empty for a hidden site. The cell is the intersection
        of the left half-planes of its half-edges' lines (see :meth:`cell_polygons`).
        ``tolerance``: how far the polygon may stray from a curved edge (a diagram of disks;
        default a thousandth of the box's diagonal); straight edges are exact."""
        if box is None:
            box = site_box(self)
        tolerance = _curve_tolerance(box, tolerance)
        if self.radii is not None and self.n_sites > 1:
            from vorobench.core.branch_curves import cell_polygon

            return cell_polygon(self, i, box, tolerance)
        poly = _box_corners(box)
        if self.n_sites == 1 and i == 0:
            return poly
        hs = np.asarray(self.cell_half_edges(i), dtype=np.int64)
        if hs.size == 0:
            return np.zeros((0, 2))
        anchor, direction = self._cell_lines(hs)
        return clip_convex(poly, anchor, direction)

    def cell_polygons(self, box: tuple[float, float, float, float] | None = None, *,
                      tolerance: Optional[float] = None) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
        """Every cell clipped to ``box`` in one pass: ``(corners, offsets)``, cell i being the CCW
        polygon ``corners[offsets[i]:offsets[i + 1]]``, the same as ``cell_polygon(i, box)``
        (``tolerance`` as there)."""
        if box is None:
            box = site_box(self)
        tolerance = _curve_tolerance(box, tolerance)
        if self.radii is not None and self.n_sites > 1:
            rings = [self.cell_polygon(i, box, tolerance=tolerance) for i in range(self.n_sites)]
            offsets = np.concatenate([[0], np.cumsum([len(r) for r in rings])]).astype(np.int64)
            return np.concatenate(rings).reshape(-1, 2), offsets
        order, offsets, _ = self._cycles
        anchor, direction = self._cell_lines(order)
        return clip_groups(_box_corners(box), anchor, direction, offsets, empty_without_lines=self.n_sites != 1)

    def polygons(self, box: tuple[float, float, float, float] | None = None, *,
                 tolerance: Optional[float] = None) -> list[NDArray[np.float64]]:
        """Every cell clipped to ``box`` (default: around the sites; ``tolerance`` as in
        :meth:`cell_polygon`)."""
        corners, offsets = self.cell_polygons(box, tolerance=tolerance)
        return np.split(corners, offsets[1:-1]) if self.n_sites else []

    # ------------------------------------------------------------------ export and drawing
    def to_shapely(self, box: Optional[tuple[float, float, float, float]] = None, *,
                   tolerance: Optional[float] = None) -> list:
        """One shapely ``Polygon`` per site, its cell clipped to ``box`` = (xmin, ymin, xmax, ymax)
        (default: around the sites); an empty polygon where the cell misses the box.
        ``tolerance``: how far a polygon may stray from a curved edge (:meth:`cell_polygon`)."""
        from vorobench.core.export import to_shapely  # shapely is optional; export imports this module

        return to_shapely(self, box, tolerance=tolerance)

    def to_geojson(self, box: Optional[tuple[float, float, float, float]] = None, *,
                   tolerance: Optional[float] = None) -> dict:
        """A JSON-serialisable GeoJSON ``FeatureCollection``: one ``Feature`` per site, its cell
        clipped to ``box`` (default: around the sites), ``null`` geometry where it misses the box
        (``tolerance`` as in :meth:`to_shapely`)."""
        from vorobench.core.export import to_geojson

        return to_geojson(self, box, tolerance=tolerance)

    def plot(self, ax: Any = None, box: Optional[tuple[float, float, float, float]] = None, **kwargs: Any) -> Any:
        """Draw sites, edges (clipped to ``box``, default around the sites) and vertices on a
        matplotlib axes (a new figure's when ``ax`` is None); returns the axes."""
        from vorobench.core.drawing import draw  # matplotlib loads only when drawing

        return draw(self, ax=ax, box=box, **kwargs)

    # ------------------------------------------------------------------ persistence
    def save(self, path: str | Path) -> None:
        """Write the diagram to a compressed ``.npz`` file (with its input rows, if it keeps them)."""
        kept = {f: getattr(self, f) for f in _INPUT_FIELDS if getattr(self, f) is not None}
        np.savez_compressed(path, format_version=_FORMAT_VERSION,
                            **{f: getattr(self, f) for f in _FIELDS}, **kept)

    @classmethod
    def load(cls, path: str | Path) -> "Diagram":
        """Read a diagram written by :meth:`save`."""
        with np.load(path, allow_pickle=False) as data:
            missing = [f for f in _FIELDS if f not in data]
            if missing:
                raise ValueError(f"{path}: not a vorobench diagram (missing {', '.join(missing)})")
            kept = {f: data[f] for f in _INPUT_FIELDS if f in data}
            return cls(**{f: data[f] for f in _FIELDS}, **kept)

    # ------------------------------------------------------------------ invariants
    def validate(self) -> "Diagram":
        """Check every structural invariant; raise :class:`InvalidDiagramError` naming the first
        broken one and the ids involved. Returns self so it can be chained."""
        s, v = self.sites, self.vertices
        if s.ndim != 2 or s.shape[1] != 2:
            raise InvalidDiagramError(f"sites must have shape (n, 2), got {s.shape}")
        if v.ndim != 2 or v.shape[1] != 2:
            raise InvalidDiagramError(f"vertices must have shape (V, 2), got {v.shape}")
        H = self.n_half_edges
        for name in ("twin", "next", "site"):
            arr = getattr(self, name)
            if arr.shape != (H,):
                raise InvalidDiagramError(f"{name} has shape {arr.shape}, origin has ({H},)")
            if arr.dtype.kind not in "iu":
                raise InvalidDiagramError(f"{name} must be an integer array, got {arr.dtype}")
        if self.origin.dtype.kind != "i":
            raise InvalidDiagramError(f"origin must be a signed integer array, got {self.origin.dtype}")
        if not np.isfinite(v).all():
            raise InvalidDiagramError(f"vertex {_first(~np.isfinite(v).all(axis=1))} is not finite")
        n, V = self.n_sites, self.n_vertices
        for name in ("weights", "radii"):
            w = getattr(self, name)
            if w is not None and (np.shape(w) != (n,) or not np.isfinite(w).all()):
                raise InvalidDiagramError(f"{name} must be {n} finite numbers, got shape {np.shape(w)}")
        if self.radii is not None and (np.asarray(self.radii) < 0).any():
            raise InvalidDiagramError(f"radii must be >= 0: disk {_first(np.asarray(self.radii) < 0)} is not")
        may_hide = self.weights is not None or self.radii is not None
        if n <= 1 or (may_hide and H == 0):
            if H or V:
                raise InvalidDiagramError(f"n = {n} must give no half-edges or vertices, got H={H}, V={V}")
            return self
        if H % 2:
            raise InvalidDiagramError(f"odd number of half-edges ({H})")
        for name, arr, lo, hi in (("origin", self.origin, -1, V), ("twin", self.twin, 0, H),
                                  ("next", self.next, 0, H), ("site", self.site, 0, n)):
            bad = (arr < lo) | (arr >= hi)
            if bad.any():
                h = _first(bad)
                raise InvalidDiagramError(f"{name}[{h}] = {int(arr[h])} is out of range [{lo}, {hi})")
        twin, nxt, site, origin = self.twin, self.next, self.site, self.origin
        h = np.arange(H)
        if (twin == h).any():
            raise InvalidDiagramError(f"half-edge {_first(twin == h)} is its own twin")
        bad = twin[twin] != h
        if bad.any():
            k = _first(bad)
            raise InvalidDiagramError(
                f"twin is not an involution: twin[{k}] = {int(twin[k])}, twin[{int(twin[k])}] = {int(twin[twin[k]])}")
        bad = site[twin] == site
        if bad.any():
            k = _first(bad)
            raise InvalidDiagramError(f"half-edge {k} and its twin {int(twin[k])} both bound cell {int(site[k])}")
        bad = site[nxt] != site
        if bad.any():
            k = _first(bad)
            raise InvalidDiagramError(
                f"next leaves the cell: half-edge {k} (cell {int(site[k])}) -> {int(nxt[k])} (cell {int(site[nxt[k]])})")
        indegree = np.bincount(nxt, minlength=H)
        if (indegree != 1).any():
            k = _first(indegree != 1)
            raise InvalidDiagramError(f"next is not a permutation: half-edge {k} follows {int(indegree[k])} half-edges")
        dest = origin[twin]
        bad = origin[nxt] != dest
        if bad.any():
            k = _first(bad)
            raise InvalidDiagramError(
                f"half-edge {k} ends at vertex {int(dest[k])} but next[{k}] = {int(nxt[k])} starts at vertex "
                f"{int(origin[nxt[k]])} (-1 = infinity)")
        has_cell = np.bincount(site, minlength=n) > 0
        if not has_cell.all() and not may_hide:
            raise InvalidDiagramError(f"site {_first(~has_cell)} has no cell (no half-edge bounds it)")
        visible = int(has_cell.sum())      # hidden sites (power, disks) have no cell
        cycles, labels = _cycle_labels(nxt)
        if cycles != visible:
            _, first_of_cycle = np.unique(labels, return_index=True)
            per_cell = np.bincount(site[first_of_cycle], minlength=n)
            k = _first((per_cell != 1) & has_cell)
            raise InvalidDiagramError(
                f"next must form one cycle per cell: {cycles} cycles for {visible} cells; cell {k} has "
                f"{int(per_cell[k])}")
        used = np.zeros(V, dtype=bool)
        used[origin[origin >= 0]] = True
        if not used.all():
            raise InvalidDiagramError(f"vertex {_first(~used)} is not the origin of any half-edge")
        return self


def _curve_tolerance(box: tuple[float, float, float, float], tolerance: Optional[float]) -> float:
    """How far the polygon of a cell of disks may stray from its curved edges: the caller's
    ``tolerance`` (checked), else a thousandth of the box's diagonal."""
    diagonal = math.hypot(box[2] - box[0], box[3] - box[1])
    if tolerance is None:
        return DEFAULT_CURVE_TOLERANCE * diagonal
    value = float(tolerance)
    if not math.isfinite(value) or value <= 0:
        raise ValueError(f"tolerance must be a positive finite distance, not {tolerance!r}")
    if value < FINEST_CURVE_TOLERANCE * diagonal:
        raise ValueError(f"tolerance {tolerance!r} is finer than curves can be sampled in floats: at least "
                         f"{FINEST_CURVE_TOLERANCE:g} of the box's diagonal ({FINEST_CURVE_TOLERANCE * diagonal:.3g})")
    return value


def _cycle_labels(perm: NDArray[np.integer]) -> tuple[int, NDArray[np.int32]]:
    """Number of cycles of a permutation and the cycle label of each element."""
    # Imported here, not at the top: scipy.sparse adds 0.25 s to every import of the core
    # (measured), and only validate() needs it.
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    m = perm.size
    graph = coo_matrix((np.ones(m, dtype=np.int8), (np.arange(m), perm)), shape=(m, m))
    count, labels = connected_components(graph, directed=True, connection="weak")
    return int(count), labels
