"""Radius families for Apollonius diagrams and the ``x y r`` disk files: names, shapes,
determinism, and the property each family is for, checked exactly where it is claimed exact."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import datasets_gen as dg
from datasets_gen.radius_families import NESTING_FRACTION, nearest_distance
from datasets_gen.weight_families import local_spacing

FAMILIES = list(dg.RADIUS_FAMILIES)


def _pairs(points: np.ndarray, r: np.ndarray):
    """Every pair (i, j), i < j, with the exact squared distance of the centres and the radii
    as Fractions."""
    P = [(Fraction(x), Fraction(y)) for x, y in points]
    R = [Fraction(v) for v in r]
    for i in range(len(P)):
        for j in range(i + 1, len(P)):
            d2 = (P[i][0] - P[j][0]) ** 2 + (P[i][1] - P[j][1]) ** 2
            yield i, j, d2, R[i], R[j]


def _inside(d2: Fraction, r_big: Fraction, r_small: Fraction) -> bool:
    """Whether the disk of radius r_small lies inside the one of radius r_big (|c - c'| + r_small
    <= r_big), exactly."""
    return r_big >= r_small and (r_big - r_small) ** 2 >= d2


def test_every_family_is_listed_with_a_description() -> None:
    assert set(FAMILIES) == {"random", "separate", "equal", "nested", "tangent", "integer", "huge", "last_bit"}
    assert all(isinstance(text, str) and len(text) > 20 for text in dg.RADIUS_FAMILIES.values())


@pytest.mark.parametrize("family", FAMILIES)
@pytest.mark.parametrize("n", [0, 1, 2, 3, 10, 200])
def test_shape_dtype_finite_and_not_negative(family: str, n: int) -> None:
    points = dg.generate("uniform", n, seed=3)
    r = dg.radii(family, points, seed=3)
    assert r.dtype == np.float64 and r.shape == (n,) and r.flags.c_contiguous
    assert np.isfinite(r).all() and (r >= 0).all()


@pytest.mark.parametrize("family", FAMILIES)
def test_deterministic_by_seed_and_apart_from_the_weights(family: str) -> None:
    points = dg.generate("normal", 300, seed=1)
    first = dg.radii(family, points, seed=5)
    assert np.array_equal(first, dg.radii(family, points.copy(), seed=5))
    if family not in ("equal", "tangent"):          # these two draw nothing
        assert not np.array_equal(first, dg.radii(family, points, seed=6))
    if family == "random":
        # the same rule as the weight family radii (r below the local spacing), other numbers
        assert not np.allclose(first * first, dg.weights("radii", points, seed=5))


def test_bad_arguments_are_refused_with_the_reason() -> None:
    points = dg.generate("uniform", 5, seed=0)
    with pytest.raises(ValueError, match="unknown radius family 'wide'; available: random"):
        dg.radii("wide", points)
    with pytest.raises(ValueError, match="seed must be a non-negative integer"):
        dg.radii("random", points, seed=-1)
    with pytest.raises(ValueError, match="finite"):
        dg.radii("random", np.array([[0.0, np.nan]]))
    with pytest.raises(ValueError, match=r"shape \(n, 2\), got \(2, 3\)"):
        dg.radii("random", np.zeros((2, 3)))
    with pytest.raises(ValueError, match="beyond 1e.150 in magnitude"):
        dg.radii("separate", points * 1e160)


@pytest.mark.parametrize("dataset", ["uniform", "clusters", "grid", "duplicates"])
def test_separate_disks_at_different_centres_never_meet(dataset: str) -> None:
    points = dg.generate(dataset, 60, seed=4)
    r = dg.radii("separate", points, seed=4)
    for i, j, d2, ri, rj in _pairs(points, r):
        assert d2 == 0 or (ri + rj) ** 2 < d2, (i, j)


def test_copies_of_a_point_take_the_distance_to_the_nearest_other_place() -> None:
    # a copy is at distance 0 from its twin: the spacing must come from the next point, or
    # the disk spreads over its neighbours
    points = np.array([(0, 0), (0, 0), (0.01, 0), (1, 1), (1, 0), (0, 1)], dtype=float)
    assert np.array_equal(nearest_distance(points)[:3], [0.01, 0.01, 0.01])
    r = dg.radii("tangent", points)
    assert r[0] == r[1] == r[2] == 0.005


def test_equal_radii_are_one_value_and_last_bit_two_adjacent_floats() -> None:
    points = dg.generate("disk", 300, seed=2)
    assert np.unique(dg.radii("equal", points)).size == 1
    low, high = np.unique(dg.radii("last_bit", points, seed=2))
    assert np.nextafter(low, np.inf) == high


def test_nested_hides_the_small_disks_under_the_grown_ones() -> None:
    points = dg.generate("uniform", 120, seed=6)
    r = dg.radii("nested", points, seed=6)
    ratio = r / local_spacing(points)
    grown = np.flatnonzero(ratio >= 1.5)
    assert grown.size == round(NESTING_FRACTION * 120) and np.all((ratio < 0.25) | (ratio >= 1.5))
    hidden = {j if r[i] > r[j] else i for i, j, d2, ri, rj in _pairs(points, r)
              if _inside(d2, max(ri, rj), min(ri, rj)) and (i in grown or j in grown)}
    assert len(hidden) >= 10


def test_tangent_disks_on_a_lattice_touch_every_neighbour_exactly() -> None:
    points = dg.generate("grid", 49, seed=0)                 # the 7 x 7 integer lattice
    r = dg.radii("tangent", points)
    assert np.all(r == 0.5)
    touching = [(i, j) for i, j, d2, ri, rj in _pairs(points, r) if (ri + rj) ** 2 == d2]
    overlapping = [(i, j) for i, j, d2, ri, rj in _pairs(points, r) if (ri + rj) ** 2 > d2]
    assert len(touching) == 2 * 7 * 6 and not overlapping


@pytest.mark.parametrize("dataset", ["uniform", "duplicates"])
def test_tangent_disks_elsewhere_touch_their_nearest_neighbour_to_within_rounding(dataset: str) -> None:
    points = dg.generate(dataset, 200, seed=8)
    r = dg.radii("tangent", points)
    assert np.array_equal(r, 0.5 * nearest_distance(points))
    for i, j, d2, ri, rj in _pairs(points, r):
        gap = float(d2) ** 0.5 - float(ri + rj)
        assert d2 == 0 or gap > -1e-15, (i, j, gap)


def test_integer_radii_on_the_unit_lattice_put_point_disks_on_circles() -> None:
    points = dg.generate("grid", 100, seed=1)
    r = dg.radii("integer", points, seed=1)
    assert set(np.unique(r)) == {0.0, 1.0}
    on_circle = [(i, j) for i, j, d2, ri, rj in _pairs(points, r) if abs(ri - rj) == 1 and d2 == 1]
    assert on_circle


def test_huge_is_one_disk_of_a_quarter_diagonal() -> None:
    points = dg.generate("uniform", 500, seed=9)
    r = dg.radii("huge", points, seed=9)
    box = points.max(axis=0) - points.min(axis=0)
    assert np.count_nonzero(r > 10 * np.median(r)) == 1
    assert r.max() == 0.25 * np.hypot(*box)


# ---------------------------------------------------------------------------------------------
# x y r files
# ---------------------------------------------------------------------------------------------

def test_disk_files_read_in_text_and_npy(tmp_path) -> None:
    text = tmp_path / "disks.txt"
    text.write_text("# x y r\n0 0 1\n\n2.5, -1, 0.25   # a comment\n3\t4\t0\n")
    centres, r = dg.load_disks(text)
    assert np.array_equal(centres, [[0, 0], [2.5, -1], [3, 4]]) and np.array_equal(r, [1, 0.25, 0])
    npy = tmp_path / "disks.npy"
    np.save(npy, np.array([[1, 2, 3], [4, 5, 6]], dtype=np.int32))
    centres, r = dg.load_disks(npy)
    assert centres.dtype == np.float64 and np.array_equal(centres, [[1, 2], [4, 5]]) and np.array_equal(r, [3, 6])
    upper = tmp_path / "DISKS.NPY"                       # the suffix in capitals is .npy too
    with open(upper, "wb") as f:
        np.save(f, np.array([[1.0, 2.0, 3.0]]))
    assert np.array_equal(dg.load_disks(upper)[1], [3.0])
    empty = tmp_path / "none.txt"
    empty.write_text("# nothing\n")
    centres, r = dg.load_disks(empty)
    assert centres.shape == (0, 2) and r.shape == (0,)


@pytest.mark.parametrize("content, message", [
    ("0 0 1\n1 1\n", r"disks.txt:2: expected 3 numbers \(x y r\), found 2"),
    ("0 0 -1\n", r"disks.txt:1: negative radius -1.0"),
    ("0 0 1\n0 nan 1\n", r"disks.txt:2: non-finite value"),
    ("0 zero 1\n", r"disks.txt:1: non-numeric value 'zero' in column 2"),
    ("0 0 9007199254740993\n", r"disks.txt:1: integer 9007199254740993 has no exact float64 value"),
    ("1,,2\n", r"disks.txt:1: non-numeric value '' in column 2"),
    ("1, 2, 3, 4\n", r"disks.txt:1: expected 3 numbers \(x y r\), found 4"),
])
def test_bad_disk_files_name_the_file_and_line(tmp_path, content: str, message: str) -> None:
    path = tmp_path / "disks.txt"
    path.write_text(content)
    with pytest.raises(ValueError, match=message):
        dg.load_disks(path)


def test_bad_npy_disks_and_missing_files_are_refused(tmp_path) -> None:
    path = tmp_path / "disks.npy"
    np.save(path, np.zeros((3, 2)))
    with pytest.raises(ValueError, match=r"shape \(m, 3\)"):
        dg.load_disks(path)
    np.save(path, np.array([[0.0, 0.0, 1.0], [1.0, 1.0, -2.0]]))
    with pytest.raises(ValueError, match=r"row 1: negative radius"):
        dg.load_disks(path)
    with pytest.raises(ValueError, match="no such disk file"):
        dg.load_disks(tmp_path / "absent.txt")
