"""Clipping by half-planes, one polygon and many at once: against shapely's own intersection,
and the bulk pass against the one-cell call, corner for corner."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import datasets_gen
import impls
from vorobench.core.clip import clean_rings, clip_convex, clip_groups, polygon_area

BOX = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 3.0], [0.0, 3.0]])
coordinate = st.floats(-5, 9, allow_nan=False, width=32)
line = st.tuples(coordinate, coordinate, coordinate, coordinate).filter(lambda v: abs(v[2]) + abs(v[3]) > 1e-3)


def _left_half_plane(shapely, ax, ay, dx, dy):
    """The left side of the directed line as a big shapely polygon (the oracle's half-plane)."""
    far = 1e4
    norm = np.hypot(dx, dy)
    ux, uy = dx / norm * far, dy / norm * far
    return shapely.Polygon([(ax - ux, ay - uy), (ax + ux, ay + uy), (ax + ux - uy, ay + uy + ux),
                            (ax - ux - uy, ay - uy + ux)])


@settings(max_examples=200, deadline=None)
@given(st.lists(line, min_size=1, max_size=6))
def test_a_box_clipped_by_lines_has_the_area_shapely_gives(lines):
    shapely = pytest.importorskip("shapely")  # the peers extra, which dev.py installs
    lines = np.array(lines, dtype=np.float64)
    clipped = clip_convex(BOX, lines[:, :2], lines[:, 2:])
    expected = shapely.Polygon(BOX)
    for ax, ay, dx, dy in lines:
        expected = expected.intersection(_left_half_plane(shapely, ax, ay, dx, dy))
    assert polygon_area(clipped) == pytest.approx(expected.area, abs=1e-9)


def test_many_lines_give_more_corners_than_the_start_had():
    """A regular 40-gon cut out of the box: the scratch space grows past the start's corners."""
    angles = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    centre, radius = np.array([2.0, 1.5]), 1.0
    anchor = centre + radius * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    direction = np.stack([-np.sin(angles), np.cos(angles)], axis=1)    # counter-clockwise tangents
    clipped = clip_convex(BOX, anchor, direction)
    assert clipped.shape == (40, 2)
    assert polygon_area(clipped) == pytest.approx(40 * np.tan(np.pi / 40), rel=1e-12)


def test_groups_without_lines_are_empty_or_the_start_as_asked():
    anchor, direction = np.array([[2.0, 0.0]]), np.array([[0.0, 1.0]])      # keep x <= 2
    offsets = np.array([0, 0, 1, 1])
    corners, bounds = clip_groups(BOX, anchor, direction, offsets)
    assert bounds.tolist() == [0, 0, 4, 4]
    assert polygon_area(corners[0:4]) == pytest.approx(6.0)
    corners, bounds = clip_groups(BOX, anchor, direction, offsets, empty_without_lines=False)
    assert bounds.tolist() == [0, 4, 8, 12] and np.array_equal(corners[:4], BOX)


def test_rings_lose_repeated_corners_turn_counter_clockwise_and_drop_what_has_no_area():
    square_cw = [[0, 0], [0, 1], [0, 1], [1, 1], [1, 0]]
    sliver = [[0, 0], [1, 1], [2, 2]]
    point = [[5, 5], [5, 5], [5, 5]]
    corners = np.array(square_cw + sliver + point, dtype=np.float64)
    rings, bounds = clean_rings(corners, np.array([0, 5, 8, 11]))
    assert bounds.tolist() == [0, 4, 4, 4]
    assert rings.tolist() == [[1, 0], [1, 1], [0, 1], [0, 0]]


@pytest.mark.parametrize("dataset", ["uniform", "grid", "collinear", "duplicates"])
@pytest.mark.parametrize("weights", [None, "radii"])
def test_all_cells_at_once_are_each_cell_alone(dataset, weights):
    sites = datasets_gen.generate(dataset, 150, seed=4)
    w = datasets_gen.weights(weights, sites, seed=4) if weights else None
    d = impls.build("incremental", sites, weights=w)
    box = d.bounding_box(0.05)
    corners, offsets = d.cell_polygons(box)
    for i in range(d.n_sites):
        assert np.array_equal(corners[offsets[i]:offsets[i + 1]], d.cell_polygon(i, box))
    areas = [polygon_area(p) for p in d.polygons(box)]
    assert sum(areas) == pytest.approx((box[2] - box[0]) * (box[3] - box[1]), rel=1e-9)


@pytest.mark.parametrize(("anchor", "direction", "offsets", "message"), [
    (np.array([0.5, 0.5]), np.array([1.0, 0.0]), [0, 1], "anchor must have shape"),
    (np.zeros((3, 2)), np.ones((2, 2)), [0, 3], "the same shape"),
    (np.zeros((2, 2)), np.ones((2, 2)), [0, 1], "rise from 0 to the number of lines"),
    (np.zeros((2, 2)), np.ones((2, 2)), [0, 2, 1, 2], "rise from 0"),
])
def test_shapes_that_do_not_fit_are_named_not_read_past(anchor, direction, offsets, message):
    with pytest.raises(ValueError, match=message):
        clip_groups(BOX, anchor, direction, np.array(offsets))
    with pytest.raises(ValueError, match="start must have shape"):
        clip_convex(np.zeros((2, 3)), np.zeros((1, 2)), np.ones((1, 2)))
