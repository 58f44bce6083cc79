"""CGAL's ``Delaunay_triangulation_2`` (the official Python bindings, package ``cgal``), Voronoi as the dual;
its ``Regular_triangulation_2``, power diagrams as the dual (:func:`build_weighted`).

CONTRACT
--------
Complexity: O(n log n) expected for CGAL (the points are spatially sorted, Hilbert order
with random rounds, then each is located by a walk from the previous one and inserted by
edge flips); O(n) for the conversion.
Input: prepared sites (distinct, finite float64), any n >= 0. n = 0, 1: no edges (CGAL is
not called). n >= 2: CGAL triangulates; when it reports dimension < 2 (all sites on a line,
decided by its exact orientation test) the diagram is the n - 1 parallel bisector lines
(:func:`vorobench.core.builder.collinear_diagram`).
Library part (``library_s``): one ``Delaunay_triangulation_2().insert(points)`` call with
the list of all the points (CGAL sorts them spatially itself).
Conversion (``convert_s``): everything else.
* The list of points. The bindings' ``Point_2(x, y)`` makes the C++ point and then wraps it
  in a Python proxy class, and the wrapping is most of the cost (1.6 s for 10^6 points,
  0.15 s without): the points are made by the extension module's own constructor, the one
  ``Point_2`` calls (:func:`_point_maker`; ``Point_2`` itself if a binding lacks it).
  ``insert`` converts either kind to the same C++ points.
* Reading the triangulation back. The bindings expose no vertex info, and walking the faces
  through Python handles (a call per face, per corner, per handle hash) took 1.2 s for 10^5
  sites. CGAL's own writer (``write_to_file``, 17 significant digits: every double
  round-trips) puts the whole triangulation in a scratch file in one C++ call (about 2 s of
  the conversion's 3.2 s for 10^6 sites): the points in vertex order (vertex 0, the infinite
  vertex, is not written), then all faces, finite and infinite, as counter-clockwise vertex
  index triples, then their neighbours (neighbour i opposite vertex i). Numba parses it (the
  coordinates correctly rounded, see :func:`_read_doubles`); each vertex is matched to its
  site by the bits of its coordinates (a hash table; prepared sites are distinct), which
  also checks that CGAL kept every site, exactly.
* CGAL's infinite faces are ghost triangles: the faces and neighbours give the half-edge
  layout of our own incremental triangulation directly (``e = 3 t + k`` from corner k to
  k + 1, ``opp[e]`` its reverse), and its dual is taken by the same routine,
  :func:`vorobench.core.delaunay_dual.voronoi_dcel`: circumcentres from the three smallest site
  ids on each empty circle, hull edges become rays, and neighbours whose four sites are
  exactly cocircular (exact ``incircle == 0``) are merged into one vertex of degree >= 4.
Exactness: the bindings' kernel is ``Exact_predicates_inexact_constructions_kernel``:
orientation and in-circle tests are filtered and fall back to exact arithmetic, for every
finite double. The triangulation is therefore a Delaunay triangulation of the exact input;
the only freedom left, how cocircular groups are split into triangles, is removed by the
exact merging, and the vertex coordinates are computed by our routine, by the same rule as
the other exact implementations. So the diagram is determined by the input alone and must
agree bit for bit with any other exact build: ``exact=True``, as for Triangle's divide and
conquer, checked by the cross-validation tests on every family.
Range: CGAL takes every finite double exactly; the limit is our dual's exact predicates,
whose range ``Implementation.run`` scales every input into. ``supports`` refuses only what
no scaling brings there (the same inputs :func:`vorobench.prepare` refuses).
Stats: ``cgal_faces`` (finite faces), ``cgal_infinite_faces``, ``merged_triangles``, the dual's
in-circle tests (``dual_incircle_calls``, ``dual_incircle_exact``), ``collinear``.

POWER DIAGRAMS (``build_weighted``)
-----------------------------------
Convention: CGAL's ``Weighted_point_2`` weight is a squared radius and the power of x is
|x - p|^2 - w, the project's (checked on three sites against CGAL's ``weighted_circumcenter``).
Library part: one ``Regular_triangulation_2().insert(weighted points)`` (random shuffle,
spatial sort, then insertion by flips; a point whose lifted point (x, y, x^2 + y^2 - w) lies
above the lower hull is *hidden*: kept in a face's list, in no triangle).
Conversion: as above, through the same file writer (each point ``x y w``, hidden ones too,
in no face); the weights read back are checked against the given ones. The dual is the one
the weighted ``incremental`` uses, :func:`vorobench.core.delaunay_dual.power_dcel`, on the same
ghost-triangle layout as the ordinary path: one vertex per face of the lower hull of the lifted
points (neighbouring triangles with exact ``power_test == 0`` merged), at
:func:`vorobench.core.circumcentre.power_centre` of the three smallest site ids among the face's
corners; the orientation of each edge comes from the triangulation. CGAL keeps as vertices the
sites whose lifted point lies exactly on the lower hull without being a corner of it (inside a
face: a cell that is one point; on a crease between two faces or on the hull's side: a segment
or a ray); they have no area and are hidden there, as in
:func:`vorobench.core.builder.collinear_diagram`.
Collinear sites (CGAL's dimension < 2; a site off the line would be a corner of the hull,
never hidden): :func:`~vorobench.core.builder.collinear_diagram` with the weights.
Exactness: ``Regular_triangulation_2<Epick>`` in these bindings (SWIG_CGAL/Triangulation_2/
typedefs.h: ``typedef EPIC_Kernel CGAL_regular_traits``): its orientation and power tests are
Epick's filtered exact predicates. Everything else is decided by our exact predicates (the
merging, the collinear joins) and the vertices by the shared rule, so ``exact=True`` holds for
power diagrams too; the tests check it against a brute-force exact oracle.
Stats: ``cgal_faces``, ``cgal_infinite_faces``, ``cgal_hidden`` (CGAL's hidden vertices),
``degenerate_sites`` (kept by CGAL, hidden here), ``merged_triangles``, ``dual_power_test_calls``,
``dual_power_test_exact``, ``collinear``.
"""

from __future__ import annotations

import os
import tempfile
from fractions import Fraction
from typing import Callable, Optional

import numpy as np
from CGAL import CGAL_Kernel
from CGAL.CGAL_Kernel import Point_2, Weighted_point_2
from CGAL.CGAL_Triangulation_2 import CGAL_VERSION_NR, Delaunay_triangulation_2, Regular_triangulation_2
from numba import njit
from numpy.typing import NDArray

from impls.base import Implementation
from impls.external.clock import BuildClock
from vorobench.core.builder import collinear_diagram
from vorobench.core.delaunay_dual import power_dcel, voronoi_dcel
from vorobench.core.diagram import Diagram
from vorobench.core.read_only import read_only
from vorobench.core.predicates import (
    INCIRCLE_CALLS,
    INCIRCLE_EXACT,
    N_POWER_COUNTERS,
    POWER_TEST_CALLS,
    POWER_TEST_EXACT,
)
from vorobench.core.scaling import exact_range_sites

__all__ = ["build", "build_weighted", "supports", "read_triangulation", "read_regular_triangulation", "half_edges",
           "cgal_version", "DIGITS", "IMPLEMENTATION"]

#: Significant digits of CGAL's file output: 17 make every double round-trip.
DIGITS = 17

#: Scratch file bytes per site (coordinates, faces, neighbours: ~130 at 10^6 sites), to pick
#: a scratch directory with room for it.
_FILE_BYTES_PER_SITE = 200

#: Decimal exponents of the correctly rounded parse: 10^k as a double-double for these k.
_POW10_MIN, _POW10_MAX = -300, 300


def cgal_version() -> str:
    """The CGAL release the bindings were compiled against (``CGAL_VERSION_NR`` = 1MMmmbiiii)."""
    nr = int(CGAL_VERSION_NR)
    return f"{nr // 10**7 % 100}.{nr // 10**5 % 100}.{nr // 10**4 % 10}"


def _point_maker() -> Callable[[float, float], object]:
    """The fastest maker of the points ``insert`` takes: the extension module's
    ``new_Point_2`` (what ``Point_2.__init__`` calls before wrapping the result in a proxy),
    if these bindings have it and a triangulation built from its points has them; else
    ``Point_2``."""
    make = getattr(getattr(CGAL_Kernel, "_CGAL_Kernel", None), "new_Point_2", None)
    if make is None:
        return Point_2
    try:
        dt = Delaunay_triangulation_2()
        dt.insert([make(0.0, 0.0), make(1.0, 0.0), make(0.0, 0.5)])
        got = sorted((v.point().x(), v.point().y()) for v in dt.finite_vertices())
    except Exception:       # a binding that wraps differently: the documented constructor
        return Point_2
    return make if got == [(0.0, 0.0), (0.0, 0.5), (1.0, 0.0)] else Point_2


_MAKE_POINT = _point_maker()


def _powers_of_ten() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """10^k = hi + lo for k in [_POW10_MIN, _POW10_MAX]: hi the correctly rounded double, lo the
    correctly rounded remainder (relative error < 2^-106; exact in rationals, once)."""
    ks = range(_POW10_MIN, _POW10_MAX + 1)
    hi = np.empty(len(ks))
    lo = np.empty(len(ks))
    for i, k in enumerate(ks):
        exact = Fraction(10) ** k
        hi[i] = float(exact)
        lo[i] = float(exact - Fraction(hi[i]))
    return hi, lo


_POW10_HI, _POW10_LO = _powers_of_ten()


# ---------------------------------------------------------------- parsing CGAL's file


@njit(cache=True)
def _skip_tokens(buf, pos, count):
    """The position after ``count`` whitespace-separated tokens from ``buf[pos:]`` (-1: fewer)."""
    size = buf.shape[0]
    for _ in range(count):
        while pos < size and buf[pos] <= 32:
            pos += 1
        if pos == size:
            return -1
        while pos < size and buf[pos] > 32:
            pos += 1
    return pos


@njit(cache=True)
def _read_ints(buf, pos, count):
    """``count`` whitespace-separated non-negative integers from ``buf[pos:]``: (values, end);
    end = -1 if the text ends first or a token is not an integer."""
    out = np.empty(count, dtype=np.int64)
    size = buf.shape[0]
    for i in range(count):
        while pos < size and buf[pos] <= 32:
            pos += 1
        if pos == size:
            return out, -1
        value = 0
        start = pos
        while pos < size and buf[pos] > 32:
            digit = np.int64(buf[pos]) - 48
            if digit < 0 or digit > 9 or pos - start > 17:
                return out, -1
            value = value * 10 + digit
            pos += 1
        out[i] = value
    return out, pos


@njit(cache=True)
def _split(a):
    """Veltkamp's split: a = hi + lo exactly, each with at most 26 significant bits."""
    c = 134217729.0 * a            # 2^27 + 1
    hi = c - (c - a)
    return hi, a - hi


@njit(cache=True)
def _two_product(a, b):
    """(p, e) with p = fl(a b) and a b = p + e exactly (Dekker)."""
    p = a * b
    ah, al = _split(a)
    bh, bl = _split(b)
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
    return p, e


@njit(cache=True)
def _read_doubles(buf, pos, count, pow_hi, pow_lo, pow_min):
    """``count`` decimal numbers from ``buf[pos:]``, correctly rounded: (values, end, ok).

    A token ``[-]digits[.digits][e[+-]digits]`` with at most 18 significant digits is
    m 10^k, m < 10^18 an integer; m = mh + ml exactly and 10^k = ph + pl to 2^-106 (a table
    computed in rationals), so mh ph (an exact product: p + e) + (e + mh pl + ml ph) is the
    value to a few 2^-104 of itself, then rounded once. That is the correctly rounded double
    unless the value lies that close to a midpoint between doubles; a double's 17-digit
    rendering (what CGAL writes) lies within 5e-17 of it (relative) and its midpoints at
    least 2^-54 = 5.55e-17 away, so the rendering is 5e-18 from every midpoint and always
    comes back exactly. ``ok`` is False (the caller parses another way) for anything else:
    more digits, other tokens, results outside ~[2^-900, 2^900] (the double-doubles would lose
    bits), truncated text.
    """
    out = np.empty(count, dtype=np.float64)
    size = buf.shape[0]
    for i in range(count):
        while pos < size and buf[pos] <= 32:
            pos += 1
        if pos == size:
            return out, -1, False
        negative = buf[pos] == 45          # '-'
        if negative:
            pos += 1
        m = np.int64(0)
        digits = 0
        shift = 0                          # decimal places after the point
        seen_point = False
        any_digit = False
        while pos < size and buf[pos] > 32:
            c = np.int64(buf[pos])
            if 48 <= c <= 57:
                any_digit = True
                if m > 0 or c > 48:
                    digits += 1
                    if digits > 18:
                        return out, pos, False
                m = m * 10 + (c - 48)
                if seen_point:
                    shift += 1
            elif c == 46 and not seen_point:           # '.'
                seen_point = True
            else:
                break
            pos += 1
        if not any_digit:
            return out, pos, False
        exponent = 0
        if pos < size and (buf[pos] == 101 or buf[pos] == 69):    # 'e', 'E'
            pos += 1
            sign = 1
            if pos < size and (buf[pos] == 45 or buf[pos] == 43):
                sign = -1 if buf[pos] == 45 else 1
                pos += 1
            start = pos
            while pos < size and 48 <= buf[pos] <= 57 and pos - start < 5:
                exponent = exponent * 10 + (np.int64(buf[pos]) - 48)
                pos += 1
            if pos == start:
                return out, pos, False
            exponent *= sign
        if pos < size and buf[pos] > 32:
            return out, pos, False
        if m == 0:
            out[i] = -0.0 if negative else 0.0
            continue
        k = exponent - shift - pow_min
        if k < 0 or k >= pow_hi.shape[0]:
            return out, pos, False
        mh = np.float64(m)
        ml = np.float64(m - np.int64(mh))          # |ml| <= 2^6: exact
        p, e = _two_product(mh, pow_hi[k])
        value = p + (e + (mh * pow_lo[k] + ml * pow_hi[k]))
        magnitude = abs(value)
        if not (magnitude > 1.2e-271 and magnitude < 8.5e270):     # ~[2^-900, 2^900]
            return out, pos, False
        out[i] = -value if negative else value
    return out, pos, True


@njit(cache=True)
def _hash(x, y):
    h = x * np.uint64(0x9E3779B97F4A7C15)
    h ^= y
    h ^= h >> np.uint64(29)
    return h * np.uint64(0xD6E8FEB86659FD93)


@njit(cache=True)
def _match_sites(point_bits, site_bits):
    """For each point (rows of two uint64 bit patterns), the site with the same bits: an
    open-addressing table of the sites, probed linearly. Returns (site of each point, first
    point matching no site or a site already taken, or -1)."""
    n = site_bits.shape[0]
    bits = 1
    while (1 << bits) < 2 * n:
        bits += 1
    size = 1 << bits
    down = np.uint64(64 - bits)
    mask = size - 1
    table = np.full(size, -1, dtype=np.int64)
    for s in range(n):
        slot = np.int64(_hash(site_bits[s, 0], site_bits[s, 1]) >> down)
        while table[slot] >= 0:
            slot = (slot + 1) & mask
        table[slot] = s
    site_of = np.empty(point_bits.shape[0], dtype=np.int64)
    taken = np.zeros(n, dtype=np.bool_)
    for i in range(point_bits.shape[0]):
        x, y = point_bits[i, 0], point_bits[i, 1]
        slot = np.int64(_hash(x, y) >> down)
        while True:
            s = table[slot]
            if s < 0:
                return site_of, i
            if site_bits[s, 0] == x and site_bits[s, 1] == y:
                break
            slot = (slot + 1) & mask
        if taken[s]:
            return site_of, i
        taken[s] = True
        site_of[i] = s
    return site_of, np.int64(-1)


@njit(cache=True)
def _half_edges(faces, neighbours, n_points):
    """(tri, opp) from CGAL's faces (file vertex ids: 0 infinite, v >= 1 point v - 1) and
    neighbours (neighbour k opposite vertex k); point ids in ``tri``, the infinite vertex as
    ``n_points``. Returns an empty ``opp`` if the faces are not a closed, consistently
    oriented triangulation (a neighbour that does not hold the shared edge reversed)."""
    m = faces.shape[0]
    tri = np.empty(3 * m, dtype=np.int64)
    opp = np.empty(3 * m, dtype=np.int64)
    for t in range(m):
        for k in range(3):
            v = faces[t, k]
            if v < 0 or v > n_points:
                return tri, opp[:0]
            tri[3 * t + k] = n_points if v == 0 else v - 1
    for t in range(m):
        for k in range(3):
            a = tri[3 * t + k]
            b = tri[3 * t + (k + 1) % 3]
            u = neighbours[t, (k + 2) % 3]      # the face across edge a -> b (opposite corner k + 2)
            if u < 0 or u >= m:
                return tri, opp[:0]
            back = -1
            for j in range(3):
                if tri[3 * u + j] == b and tri[3 * u + (j + 1) % 3] == a:
                    back = 3 * u + j
            if back < 0:
                return tri, opp[:0]
            opp[3 * t + k] = back
    return tri, opp


def half_edges(faces: NDArray[np.integer], neighbours: NDArray[np.integer], n_points: int
               ) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """CGAL's faces and neighbours (file numbering, vertex 0 infinite) as the flat corner and
    opposite-half-edge arrays of our triangulations (``e = 3 t + k`` runs from corner k to
    k + 1; the infinite vertex is ``n_points``); ValueError if they do not pair up."""
    tri, opp = _half_edges(np.ascontiguousarray(faces, dtype=np.int64).reshape(-1, 3),
                           np.ascontiguousarray(neighbours, dtype=np.int64).reshape(-1, 3), int(n_points))
    if opp.size != tri.size:
        raise ValueError("cgal: the faces do not form a closed, consistently oriented triangulation")
    return tri, opp


def _scratch_dir(size: int) -> Optional[str]:
    """/dev/shm (memory) when it has room for ``size`` bytes twice over, else the default."""
    try:
        st = os.statvfs("/dev/shm")
        if os.access("/dev/shm", os.W_OK) and st.f_bavail * st.f_frsize > 2 * size:
            return "/dev/shm"
    except (OSError, AttributeError):
        pass
    return None


def _file_text(dt: Delaunay_triangulation_2 | Regular_triangulation_2, n: int) -> bytes:
    """CGAL's file output of the triangulation (``DIGITS`` significant digits), read back."""
    fd, path = tempfile.mkstemp(prefix="vorobench-cgal-", suffix=".txt",
                                dir=_scratch_dir(_FILE_BYTES_PER_SITE * n + 4096))
    os.close(fd)
    try:
        dt.write_to_file(path, DIGITS)
        with open(path, "rb") as fh:
            return fh.read()
    finally:
        os.unlink(path)


def _read_file(text: bytes, columns: int, dimensions: tuple[int, ...]
               ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], int]:
    """(points (n, ``columns``), faces (m, d + 1), neighbours (m, d + 1), d) from CGAL's file
    output of a triangulation of dimension d in ``dimensions``; ValueError otherwise."""
    end = text.find(b"\n")
    head = text[:end].split() if end >= 0 else []
    if len(head) != 3 or not all(h.isdigit() for h in head):
        raise ValueError(f"cgal: unexpected file header {text[:60]!r}")
    n_vertices, m, dim = map(int, head)
    if dim not in dimensions or n_vertices < dim + 2:
        raise ValueError(f"cgal: the file holds a triangulation of dimension {dim} with {n_vertices} vertices")
    n = n_vertices - 1
    corners = dim + 1
    buf = np.frombuffer(text, dtype=np.uint8)
    coords, pos, ok = _read_doubles(buf, end + 1, columns * n, _POW10_HI, _POW10_LO, _POW10_MIN)
    if not ok:                 # outside the fast parse's limits: numpy parses these tokens
        pos = _skip_tokens(buf, end + 1, columns * n)
        if pos < 0:
            raise ValueError(f"cgal: the file ends before the coordinates of its {n} points")
        try:
            coords = np.array(text[end + 1:pos].split(), dtype=np.float64)
        except ValueError as exc:
            raise ValueError(f"cgal: unreadable point coordinates ({exc})") from None
    faces, pos = _read_ints(buf, pos, corners * m)
    if pos >= 0:
        neighbours, pos = _read_ints(buf, pos, corners * m)
    if pos < 0 or text[pos:].strip():
        raise ValueError(f"cgal: the file does not hold {n} points and twice {m} index tuples")
    return coords.reshape(n, columns), faces.reshape(m, corners), neighbours.reshape(m, corners), dim


def read_triangulation(text: bytes) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64]]:
    """(points (n, 2) in vertex order, faces (m, 3), neighbours (m, 3)) from CGAL's file output
    of a 2-dimensional triangulation: a line ``vertices faces dimension`` (vertices counting
    the infinite one), the points' coordinates, the faces' vertex ids (0: the infinite
    vertex, v: point v - 1), the faces' neighbours. ValueError if the text is not that."""
    coords, faces, neighbours, _ = _read_file(text, 2, (2,))
    return coords, faces, neighbours


def read_regular_triangulation(text: bytes
                               ) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.int64], int]:
    """:func:`read_triangulation` for a ``Regular_triangulation_2`` of dimension 1 or 2: each
    point is ``x y w``, hidden vertices included (they are in no face); the faces (and
    neighbours) have dimension + 1 entries. Returns (points (n, 3), faces, neighbours, dimension)."""
    return _read_file(text, 3, (1, 2))


# ---------------------------------------------------------------- the build


def build(sites: NDArray[np.float64], stats: Optional[dict] = None) -> Diagram:
    """The Voronoi diagram of prepared ``sites``, dual to CGAL's Delaunay triangulation."""
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites)
    clock = BuildClock()
    points = list(map(_MAKE_POINT, sites[:, 0].tolist(), sites[:, 1].tolist()))
    dt = Delaunay_triangulation_2()
    with clock.library():
        dt.insert(points)
    del points
    kept = dt.number_of_vertices()
    if kept != n:
        raise RuntimeError(f"cgal: the triangulation holds {kept} of {n} distinct sites")
    if dt.dimension() < 2:
        del dt
        diagram = collinear_diagram(sites)
        clock.report()
        if stats is not None:
            stats.update(collinear=1, cgal_faces=0)
        return diagram
    text = _file_text(dt, n)
    del dt
    coords, faces, neighbours = read_triangulation(text)
    del text
    if coords.shape[0] != n:
        raise RuntimeError(f"cgal: the file holds {coords.shape[0]} of {n} sites")
    ids, bad = _match_sites(coords.view(np.uint64), sites.view(np.uint64))
    if bad >= 0:
        raise RuntimeError(f"cgal: vertex {int(bad)} at {tuple(map(float, coords[bad]))} is no site, "
                           f"or a site given twice")
    tri, opp = half_edges(faces, neighbours, n)
    counters = np.zeros(4, dtype=np.int64)
    # the points in CGAL's vertex order (spatially sorted: the dual's passes stay local)
    vertices, origin, twin, nxt, site, merged = voronoi_dcel(read_only(coords), ids, tri, opp, faces.shape[0],
                                                              counters)
    diagram = Diagram(sites, vertices, origin, twin, nxt, site)
    clock.report()
    if stats is not None:
        finite = int(np.count_nonzero((faces != 0).all(axis=1)))
        stats.update(cgal_faces=finite, cgal_infinite_faces=int(faces.shape[0]) - finite,
                     merged_triangles=int(merged), dual_incircle_calls=int(counters[INCIRCLE_CALLS]),
                     dual_incircle_exact=int(counters[INCIRCLE_EXACT]))
    return diagram


# ---------------------------------------------------------------- power diagrams


def _weighted_point_maker() -> Callable[[float, float, float], object]:
    """The fastest maker of the weighted points ``Regular_triangulation_2.insert`` takes:
    ``new_Weighted_point_2(new_Point_2(x, y), w)`` from the extension modules (no proxy objects,
    as for :func:`_point_maker`), if these bindings have them and a triangulation built from
    them holds the right points and weights; else the documented ``Weighted_point_2``."""
    def public(x: float, y: float, w: float) -> object:
        return Weighted_point_2(Point_2(x, y), w)

    raw = getattr(CGAL_Kernel, "_CGAL_Kernel", None)
    new_point = getattr(raw, "new_Point_2", None)
    new_weighted = getattr(raw, "new_Weighted_point_2", None)
    if new_point is None or new_weighted is None:
        return public

    def fast(x: float, y: float, w: float) -> object:
        return new_weighted(new_point(x, y), w)

    try:
        rt = Regular_triangulation_2()
        rt.insert([fast(0.0, 0.0, 0.25), fast(1.0, 0.0, 0.0), fast(0.0, 0.5, -0.5)])
        got = sorted((v.point().x(), v.point().y(), v.point().weight()) for v in rt.finite_vertices())
    except Exception:       # a binding that wraps differently: the documented constructor
        return public
    return fast if got == [(0.0, 0.0, 0.25), (0.0, 0.5, -0.5), (1.0, 0.0, 0.0)] else public


_MAKE_WEIGHTED_POINT = _weighted_point_maker()


def _weighted_points(sites: NDArray[np.float64], weights: NDArray[np.float64]) -> list:
    """CGAL weighted points for the sites, in site order."""
    make = _MAKE_WEIGHTED_POINT
    return list(map(make, sites[:, 0].tolist(), sites[:, 1].tolist(), weights.tolist()))


def build_weighted(sites: NDArray[np.float64], weights: NDArray[np.float64],
                   stats: Optional[dict] = None) -> Diagram:
    """The power diagram of prepared ``sites`` with ``weights`` (power |x - p|^2 - w, CGAL's
    ``Weighted_point_2``), dual to CGAL's ``Regular_triangulation_2``.

    Library part: one ``insert`` of the list of all weighted points. Conversion: the
    triangulation read back through CGAL's file writer (each point ``x y w``, hidden vertices
    included but in no face), every vertex matched to its site by its coordinates' bits and
    its weight checked, then :func:`~vorobench.core.delaunay_dual.power_dcel`. Hidden sites: CGAL's,
    plus the sites CGAL keeps whose cells have no area (lifted point exactly on a face or an
    edge of the lower hull, not a corner): one diagram per input, whatever the insertion order.
    Dimension < 2 (all sites collinear, decided exactly by CGAL):
    :func:`vorobench.core.builder.collinear_diagram` with the weights.
    """
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    weights = np.ascontiguousarray(weights, dtype=np.float64).reshape(-1)
    n = sites.shape[0]
    if n <= 1:
        return Diagram.empty(sites, weights)
    clock = BuildClock()
    points = _weighted_points(sites, weights)
    rt = Regular_triangulation_2()
    with clock.library():
        rt.insert(points)
    del points
    visible_count = rt.number_of_vertices()
    hidden_count = rt.number_of_hidden_vertices()
    if visible_count + hidden_count != n:
        raise RuntimeError(f"cgal: the regular triangulation holds {visible_count} visible and "
                           f"{hidden_count} hidden of {n} distinct sites")
    dimension = rt.dimension()
    if dimension < 2:
        # All sites collinear: a site off their line would be a corner of the sites' hull, and
        # corners are never hidden. The exact collinear power diagram; CGAL's hidden sites must
        # be hidden there too (it may also hide sites CGAL keeps with a cell of no area).
        del rt
        diagram = collinear_diagram(sites, weights)
        clock.report()
        if diagram.hidden.size < hidden_count:
            raise RuntimeError(f"cgal: {hidden_count} sites hidden by CGAL, {diagram.hidden.size} "
                               f"in the collinear power diagram")
        if stats is not None:
            stats.update(collinear=1, cgal_faces=0, cgal_hidden=hidden_count,
                         degenerate_sites=int(diagram.hidden.size) - hidden_count)
        return diagram
    text = _file_text(rt, n)
    del rt
    coords, faces, neighbours, dim = read_regular_triangulation(text)
    del text
    if coords.shape[0] != n or dim != 2:
        raise RuntimeError(f"cgal: the file holds {coords.shape[0]} of {n} sites, dimension {dim}")
    xy = np.ascontiguousarray(coords[:, :2])
    ids, bad = _match_sites(xy.view(np.uint64), sites.view(np.uint64))
    if bad >= 0:
        raise RuntimeError(f"cgal: vertex {int(bad)} at {tuple(map(float, coords[bad]))} is no site, "
                           f"or a site given twice")
    if not np.array_equal(coords[:, 2], weights[ids]):
        k = int(np.flatnonzero(coords[:, 2] != weights[ids])[0])
        raise RuntimeError(f"cgal: site {int(ids[k])} has weight {coords[k, 2]!r} in CGAL, {weights[ids[k]]!r} given")
    in_faces = np.zeros(n + 1, dtype=bool)
    in_faces[faces.reshape(-1)] = True
    if int(np.count_nonzero(in_faces[1:])) != visible_count:
        raise RuntimeError(f"cgal: {int(np.count_nonzero(in_faces[1:]))} sites in the file's faces, "
                           f"{visible_count} visible")
    tri, opp = half_edges(faces, neighbours, n)
    counters = np.zeros(N_POWER_COUNTERS, dtype=np.int64)
    # the points in CGAL's vertex order (spatially sorted: the passes stay local)
    lifts = read_only(np.ascontiguousarray(coords[:, 2]))
    vertices, origin, twin, nxt, site, merged, _ = power_dcel(read_only(xy), lifts, ids, tri, opp, faces.shape[0],
                                                              counters)
    diagram = Diagram(sites, vertices, origin, twin, nxt, site, weights=weights)
    clock.report()
    if stats is not None:
        finite = int(np.count_nonzero((faces != 0).all(axis=1)))
        stats.update(cgal_faces=finite, cgal_infinite_faces=int(faces.shape[0]) - finite,
                     cgal_hidden=hidden_count, degenerate_sites=int(diagram.hidden.size) - hidden_count,
                     merged_triangles=merged, dual_power_test_calls=int(counters[POWER_TEST_CALLS]),
                     dual_power_test_exact=int(counters[POWER_TEST_EXACT]), collinear=0)
    return diagram


def supports(sites: NDArray[np.float64]) -> Optional[str]:
    """None if the sites can be built, else why not. CGAL's kernel decides exactly for every
    finite double; the dual's predicates need the exact range, where ``run`` scales the sites:
    refused are only sites that no power of two brings there."""
    _, problem = exact_range_sites(sites)
    return problem


def warmup() -> None:
    """Compile the adapter's and the duals' numba kernels (CGAL itself is C++) on every path,
    ordinary and weighted, for read-only inputs as ``run`` hands them over (numba compiles
    those separately)."""
    rng = np.random.default_rng(0)
    cases = (rng.random((40, 2)),
             np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [2.0, 0.0], [0.5, 0.5]]),
             np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]]))
    for sites in cases:
        sites.setflags(write=False)
        build(sites)
    # weighted: random with hidden sites; a lattice whose centre's lifted point lies on a
    # face and whose edge midpoints lie on creases (merged faces); collinear
    lattice = np.array([[x, y] for x in range(3) for y in range(3)], dtype=np.float64)
    lattice_w = np.array([1.0 if (x + y) % 2 == 0 else 0.0 for x in range(3) for y in range(3)])
    weighted = ((rng.random((40, 2)), rng.random(40) * 0.05), (lattice, lattice_w),
                (cases[2].copy(), np.array([0.0, -3.0, 0.0])))
    for sites, weights in weighted:
        sites.setflags(write=False)
        weights.setflags(write=False)
        build_weighted(sites, weights)


IMPLEMENTATION = Implementation(
    name="cgal",
    description="CGAL's Delaunay_triangulation_2 (exact predicates, spatially sorted insertion), Voronoi as the dual; "
                "power diagrams as the dual of its Regular_triangulation_2",
    complexity="O(n log n) expected",
    build=build,
    exact=True,
    origin=f"CGAL {cgal_version()} (C++), Python package cgal",
    supports=supports,
    warmup=warmup,
    kind="outside",
    build_weighted=build_weighted,
)
