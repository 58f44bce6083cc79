"""Cells exported as shapely polygons and GeoJSON: they tile their box, whatever the input and
the implementation; the default box frames the sites; bad boxes are refused by name."""

import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

import datasets_gen
import impls
from vorobench.core.export import cell_rings, to_geojson, to_shapely
from vorobench.core.framing import checked_box, point_box, site_box

IMPLS = ("incremental", "fortune", "qhull")
#: (dataset, n): random, cocircular lattice, collinear, many duplicate rows, two sites
INPUTS = (("uniform", 200), ("grid", 100), ("collinear", 30), ("duplicates", 200), ("uniform", 2))


def shoelace(ring) -> float:
    """Signed area of a closed or open ring, relative to its first corner."""
    r = np.asarray(ring, dtype=np.float64)
    x, y = r[:, 0] - r[0, 0], r[:, 1] - r[0, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def box_area(box) -> float:
    return (box[2] - box[0]) * (box[3] - box[1])


@pytest.fixture(scope="module", params=[(impl, *case) for case in INPUTS for impl in IMPLS],
                ids=lambda p: f"{p[0]}-{p[1]}-{p[2]}")
def built(request):
    impl, dataset, n = request.param
    return impls.build(impl, datasets_gen.generate(dataset, n, seed=3))


# ---------------------------------------------------------------- GeoJSON, no shapely needed
def test_geojson_cells_tile_the_site_box(built):
    gj = to_geojson(built)
    box = site_box(built)
    assert gj["bbox"] == list(box)
    areas = [shoelace(f["geometry"]["coordinates"][0]) for f in gj["features"] if f["geometry"] is not None]
    assert all(a > 0 for a in areas)                       # exterior rings counter-clockwise
    assert math.fsum(areas) == pytest.approx(box_area(box), rel=1e-9)


def test_geojson_is_rfc7946_shaped_and_serialisable(built):
    gj = to_geojson(built)
    assert gj["type"] == "FeatureCollection"
    assert len(gj["features"]) == built.n_sites                # one per site, not per input row
    assert json.loads(json.dumps(gj, allow_nan=False)) == gj
    for i, feature in enumerate(gj["features"]):
        assert feature["type"] == "Feature" and feature["id"] == i
        props = feature["properties"]
        assert props["site"] == i and (props["x"], props["y"]) == tuple(built.sites[i])
        assert type(props["x"]) is float and type(props["y"]) is float
        geometry = feature["geometry"]
        assert geometry["type"] == "Polygon" and len(geometry["coordinates"]) == 1
        ring = geometry["coordinates"][0]
        assert ring[0] == ring[-1] and len(ring) >= 4             # closed, at least a triangle
        assert all(type(c) is float for point in ring for c in point)
        assert all(p != q for p, q in zip(ring, ring[1:]))        # no repeated corner


def test_each_sample_point_lies_in_the_cell_of_its_nearest_site(built):
    """The rings are the right cells, not just any tiling: a random point of the box is in
    (or on the edge of) the cell of the site nearest to it."""
    box = site_box(built)
    rings = cell_rings(built, box)
    rng = np.random.default_rng(0)
    samples = rng.uniform(box[:2], box[2:], size=(300, 2))
    _, nearest = cKDTree(built.sites).query(samples)
    for p, i in zip(samples, nearest):
        ring = rings[i]
        edges = np.roll(ring, -1, axis=0) - ring
        side = edges[:, 0] * (p[1] - ring[:, 1]) - edges[:, 1] * (p[0] - ring[:, 0])
        assert (side >= -1e-9 * box_area(box)).all(), f"{p} is outside the cell of its nearest site {i}"


def test_a_box_that_leaves_sites_out_gives_them_no_geometry():
    d = impls.build("fortune", datasets_gen.generate("uniform", 200, seed=5))
    box = (0.0, 0.0, 0.3, 0.2)
    gj = to_geojson(d, box)
    empty = [f["properties"]["site"] for f in gj["features"] if f["geometry"] is None]
    inside = np.flatnonzero((d.sites[:, 0] < 0.3) & (d.sites[:, 1] < 0.2))
    assert len(empty) > 100                                    # most cells miss this corner
    assert not set(inside.tolist()) & set(empty)               # a site in the box has its cell there
    areas = [shoelace(f["geometry"]["coordinates"][0]) for f in gj["features"] if f["geometry"] is not None]
    assert math.fsum(areas) == pytest.approx(box_area(box), rel=1e-9)
    # Nothing of an empty cell is in the box: no sample point of the box has its site nearest.
    rng = np.random.default_rng(1)
    _, nearest = cKDTree(d.sites).query(rng.uniform((0, 0), (0.3, 0.2), size=(2000, 2)))
    assert not set(nearest.tolist()) & set(empty)


def test_cells_far_from_the_origin_still_tile():
    """Sites near (1e9, 1e9): areas are taken relative to a corner, or every digit is lost;
    what is left is the rounding of coordinates to 1 ulp of 1e9 (1.2e-7)."""
    d = impls.build("fortune", datasets_gen.generate("huge_offset", 100, seed=3))
    box = site_box(d)
    rings = cell_rings(d, box)
    assert all(r is not None for r in rings)
    assert math.fsum(shoelace(r) for r in rings) == pytest.approx(box_area(box), rel=1e-6)


def test_a_box_of_only_one_cell():
    d = impls.build("incremental", [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]])
    gj = to_geojson(d, (-2.0, -2.0, 1.0, 1.0))                  # inside the cell of (0, 0)
    assert [f["geometry"] is None for f in gj["features"]] == [False, True, True]
    assert shoelace(gj["features"][0]["geometry"]["coordinates"][0]) == pytest.approx(9.0)


def test_no_sites_and_one_site():
    none = impls.build("fortune", np.zeros((0, 2)))
    assert to_geojson(none)["features"] == [] and cell_rings(none) == []
    one = impls.build("fortune", [[3.0, 4.0]])
    (feature,) = to_geojson(one)["features"]
    box = site_box(one)
    assert box[0] < 3.0 < box[2] and box[1] < 4.0 < box[3]
    assert shoelace(feature["geometry"]["coordinates"][0]) == pytest.approx(box_area(box))


def test_the_diagram_methods_are_these_functions():
    d = impls.build("fortune", datasets_gen.generate("uniform", 20, seed=0))
    assert d.to_geojson() == to_geojson(d)
    assert d.to_geojson((0, 0, 1, 1)) == to_geojson(d, (0, 0, 1, 1))


# ---------------------------------------------------------------- the boxes
def test_site_box_frames_the_sites_not_the_far_vertices():
    # Nearly collinear: the vertex lies about 1e6 below the sites.
    d = impls.build("fortune", [[0.0, 0.0], [1.0, 1e-6], [2.0, 0.0]])
    assert np.abs(d.vertices).max() > 1e5
    assert site_box(d) == pytest.approx((-0.2, -0.2, 2.2, 0.2 + 1e-6))


@pytest.mark.parametrize("points", [
    [[0.0, 5.0], [1.0, 5.0], [3.0, 5.0]],                     # horizontal line: zero height
    [[2.0, -1.0], [2.0, 7.0]],                                # vertical line: zero width
    [[0.0, 1e20], [1.0, 1e20]],                               # zero height where 1e-1 is below 1 ulp
    [[5.0, 5.0]],                                             # one point
    [[1e300, -1e300]],                                        # one point near the largest float
])
def test_point_box_opens_up_degenerate_point_sets(points):
    xmin, ymin, xmax, ymax = point_box(np.array(points))
    pts = np.array(points)
    assert xmin < pts[:, 0].min() <= pts[:, 0].max() < xmax
    assert ymin < pts[:, 1].min() <= pts[:, 1].max() < ymax


def test_point_box_margin_and_the_empty_box():
    assert point_box(np.zeros((0, 2))) == (-1.0, -1.0, 1.0, 1.0)
    assert point_box(np.array([[0.0, 0.0], [10.0, 4.0]]), margin=0.5) == (-5.0, -5.0, 15.0, 9.0)
    assert point_box(np.array([[0.0, 0.0]]), margin=0.1) == (-1.0, -1.0, 1.0, 1.0)
    with pytest.raises(ValueError, match="margin"):
        point_box(np.array([[0.0, 0.0]]), margin=-0.1)


@pytest.mark.parametrize("box, problem", [
    ((0, 0, 1), "four numbers"),
    ((0, 0, 1, 1, 2), "four numbers"),
    (("a", 0, 1, 1), "four numbers"),
    ((0, 0, float("nan"), 1), "finite"),
    ((0, -math.inf, 1, 1), "finite"),
    ((1, 0, 1, 1), "xmin < xmax"),
    ((2, 0, 1, 1), "xmin < xmax"),
    ((0, 1, 1, 1), "ymin < ymax"),
])
def test_a_bad_box_is_refused_by_name(box, problem):
    with pytest.raises(ValueError, match=problem):
        checked_box(box)
    d = impls.build("fortune", [[0.0, 0.0], [1.0, 0.0]])
    with pytest.raises(ValueError, match=problem):
        to_geojson(d, box)


def test_checked_box_gives_plain_floats():
    box = checked_box(np.array([0, 0, 2, 1], dtype=np.int32))
    assert box == (0.0, 0.0, 2.0, 1.0) and all(type(v) is float for v in box)
    with pytest.raises(ValueError, match="four numbers"):
        checked_box(None)


# ---------------------------------------------------------------- shapely
def test_shapely_cells_are_valid_disjoint_and_cover_the_box(built):
    shapely = pytest.importorskip("shapely")
    box = site_box(built)
    polygons = to_shapely(built)
    assert len(polygons) == built.n_sites and all(p.is_valid for p in polygons)
    frame = shapely.box(*box)
    # Neighbours share an edge up to rounding (a gap of 1e-16 between them is fine).
    near = 1e-9 * math.sqrt(frame.area)
    pairs = shapely.STRtree(polygons).query(polygons, predicate="dwithin", distance=near).T
    pairs = pairs[pairs[:, 0] < pairs[:, 1]]
    assert len(pairs) >= built.n_sites - 1
    overlap = sum(polygons[i].intersection(polygons[j]).area for i, j in pairs.tolist())
    assert overlap <= 1e-12 * frame.area
    union = shapely.union_all(polygons)
    assert union.symmetric_difference(frame).area <= 1e-9 * frame.area


def test_shapely_polygon_of_each_site_contains_it(built):
    shapely = pytest.importorskip("shapely")
    for i, polygon in enumerate(to_shapely(built)):
        assert polygon.covers(shapely.Point(built.sites[i]))


def test_shapely_gives_an_empty_polygon_for_a_cell_outside_the_box():
    shapely = pytest.importorskip("shapely")
    d = impls.build("qhull", [[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]])
    polygons = to_shapely(d, (-2.0, -2.0, 1.0, 1.0))
    assert [type(p) for p in polygons] == [shapely.Polygon] * 3
    assert [p.is_empty for p in polygons] == [False, True, True]
    assert polygons[0].area == pytest.approx(9.0)
    assert [p.is_empty for p in d.to_shapely((-2.0, -2.0, 1.0, 1.0))] == [False, True, True]


def test_without_shapely_the_error_says_what_to_install(monkeypatch):
    monkeypatch.setitem(sys.modules, "shapely", None)              # import shapely now fails
    d = impls.build("fortune", [[0.0, 0.0], [1.0, 0.0]])
    with pytest.raises(ImportError, match=r"pip install shapely.*vorobench\[peers\]"):
        to_shapely(d)


def test_the_documented_feature_is_what_to_geojson_gives():
    page = (Path(__file__).resolve().parents[2] / "docs" / "export.md").read_text()
    (shown,) = [line for line in page.splitlines() if line.startswith('{"type": "Feature"')]
    d = impls.build("fortune", [[0, 0], [2, 0], [1, 2]])
    assert json.dumps(d.to_geojson()["features"][0]) == shown
