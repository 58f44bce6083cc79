"""Adapters to outside Voronoi libraries, each behind the common :class:`~impls.base.Implementation`.

One module per library: :mod:`.triangle_lib` (Shewchuk's Triangle, three algorithms, with
:mod:`.triangle_sweep` and :mod:`.triangle_incremental` naming the two non-default ones for
the registry), :mod:`.cgal` (CGAL's ``Delaunay_triangulation_2`` through the official
bindings, package ``cgal``), :mod:`.boost` (Boost.Polygon's sweep through ``pyvoronoi``) and
:mod:`.geos` (GEOS through ``shapely.voronoi_polygons``). Each is importable only when its library is
installed (``pip install vorobench[peers]``); the registry lists it only then.

Every adapter times two parts of its build, ``library`` (wall time inside the library's own
call) and ``convert`` (everything else: input preparation and conversion of the output into
the DCEL), so a run can tell the library's speed from the cost of our adapter. They are
timings (results columns ``time_library_s``, ``time_convert_s``), never counters: ``stats``
holds only machine-independent integers.
"""

__all__: list[str] = []
