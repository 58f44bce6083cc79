"""A Diagram of disks: it carries its radii through copies and files, lets hidden disks go
without edges, refuses weights and radii together and polygons it cannot draw yet."""

from __future__ import annotations

import math

import numpy as np
import pytest

from impls import halfplane_disks
from vorobench.core.diagram import Diagram
from vorobench.core.errors import InvalidDiagramError


def _disks():
    centres = np.array([[-10.0, 0.0], [0.0, 0.0], [10.0, 0.0], [10.0, 0.5]])
    radii = np.array([9.5, 0.1, 9.5, 1.0])                    # the last one inside the third
    return halfplane_disks.build(centres, radii)


def test_radii_survive_copies_and_files(tmp_path):
    d = _disks().validate()
    assert d.is_apollonius and not d.is_power and d.hidden.tolist() == [3]
    again = d.with_input(d.sites, np.arange(d.n_sites))
    assert again.radii.tolist() == d.radii.tolist()
    d.save(tmp_path / "disks.npz")
    loaded = Diagram.load(tmp_path / "disks.npz").validate()
    assert loaded.radii.tolist() == d.radii.tolist() and loaded.hidden.tolist() == [3]
    assert not d.radii.flags.writeable


def test_an_ordinary_diagram_may_not_lose_a_cell_but_one_of_disks_may():
    d = _disks()
    plain = Diagram(d.sites, d.vertices, d.origin, d.twin, d.next, d.site)
    with pytest.raises(InvalidDiagramError, match="site 3 has no cell"):
        plain.validate()


def test_weights_and_radii_together_and_negative_radii_are_refused():
    d = _disks()
    with pytest.raises(ValueError, match="not both"):
        Diagram(d.sites, d.vertices, d.origin, d.twin, d.next, d.site, weights=np.zeros(4), radii=d.radii)
    bad = Diagram(d.sites, d.vertices, d.origin, d.twin, d.next, d.site, radii=d.radii * -1)
    with pytest.raises(InvalidDiagramError, match="radii must be >= 0"):
        bad.validate()


def _area(ring):
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) if len(ring) > 2 else 0.0


def _inside(point, ring) -> bool:
    """Even-odd rule."""
    x, y = point
    inside = False
    for (x0, y0), (x1, y1) in zip(ring, np.roll(ring, -1, axis=0)):
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def test_cells_of_disks_become_polygons_that_tile_the_box():
    """Edges sampled within a thousandth of the box's diagonal: the cells' polygons cover the
    box (their areas sum to its area, up to the sampling), each visible cell's polygon holds its
    centre (a visible disk's centre is in its own cell), and a hidden disk's is empty."""
    import datasets_gen

    centres = datasets_gen.generate("uniform", 40, seed=3)
    radii = datasets_gen.radii("random", centres, seed=3)
    d = halfplane_disks.build(centres, radii)
    box = (-0.1, -0.1, 1.1, 1.1)
    rings = d.polygons(box)
    assert len(rings) == 40
    tolerance = 1e-3 * math.hypot(1.2, 1.2)
    assert abs(sum(_area(r) for r in rings) - 1.44) < 0.02 * tolerance * 40
    hidden = set(d.hidden.tolist())
    for i, ring in enumerate(rings):
        if i in hidden:
            assert len(ring) == 0
        else:
            assert _area(ring) > 0 and _inside(centres[i], ring)
    assert np.array_equal(d.cell_polygon(5, box), rings[5])


@pytest.mark.parametrize("radii", [(1.0, 0.2), (0.2, 1.0), (0.5, 0.5)])
def test_two_disks_split_the_box_between_them(radii):
    """One branch, and each cell's gap at infinity a half-turn or more: closed around its centre
    beyond the box, not by a chord (which would cut the box)."""
    centres = np.array([[0.0, 0.0], [3.0, 0.0]])
    d = halfplane_disks.build(centres, np.array(radii))
    box = (-4.0, -4.0, 7.0, 4.0)
    first, second = d.polygons(box)
    assert abs(_area(first) + _area(second) - 88.0) < 0.05
    assert _inside(centres[0], first) and _inside(centres[1], second)
    # the branch crosses the x axis at (|d| - s) / 2 from the first centre
    crossing = (3.0 - (radii[1] - radii[0])) / 2
    assert abs(np.interp(0.0, *_right_edge_at_zero(first)) - crossing) < 0.02


def _right_edge_at_zero(ring):
    """(ys, xs) of the ring's points right of its centre's side, sorted by y, for interpolation."""
    right = ring[ring[:, 0] > 0.5]
    order = np.argsort(right[:, 1])
    return right[order, 1], right[order, 0]


def _branch_chords(ring, box):
    """Consecutive corners of a ring that are both strictly inside ``box``: chords of its curved
    edges (a corner on the box's side comes from the clipping)."""
    inside = [(box[0] < x < box[2]) and (box[1] < y < box[3]) for x, y in ring]
    return [(ring[k], ring[k + 1]) for k in range(len(ring) - 1) if inside[k] and inside[k + 1]]


@pytest.mark.parametrize("fraction", [1e-2, 1e-5])
def test_polygons_of_disks_keep_the_callers_tolerance(fraction):
    """Two disks share one branch; at the caller's tolerance (here much finer and much coarser
    than the default) no chord of either cell's polygon strays further from it, and a finer
    tolerance takes more corners."""
    from branch_distance import chord_stray

    centres, radii = np.array([[0.0, 0.0], [3.0, 1.0]]), np.array([2.0, 0.2])
    d = halfplane_disks.build(centres, radii)
    box = (-5.0, -5.0, 8.0, 6.0)
    tolerance = fraction * math.hypot(13.0, 11.0)
    for i in (0, 1):
        ring = d.cell_polygon(i, box, tolerance=tolerance)
        chords = _branch_chords(ring, box)
        assert len(chords) >= 2
        strays = [chord_stray(centres, radii, 0, 1, p, q, 1.0) for p, q in chords]
        assert max(s for s in strays if s is not None) <= tolerance * 1.01
    coarse, fine = (len(d.cell_polygon(0, box, tolerance=t)) for t in (tolerance, tolerance / 10))
    assert fine > coarse


def test_shapely_and_geojson_take_the_tolerance():
    shapely = pytest.importorskip("shapely")
    d = _disks()
    box = (-12.0, -12.0, 12.0, 12.0)
    default = d.to_shapely(box)
    fine = d.to_shapely(box, tolerance=1e-4)
    assert all(len(f.exterior.coords) >= len(c.exterior.coords) for f, c in zip(fine, default) if not c.is_empty)
    assert sum(len(f.exterior.coords) for f in fine) > sum(len(c.exterior.coords) for c in default if not c.is_empty)
    assert shapely.union_all(fine).area == pytest.approx(24.0 * 24.0, rel=1e-6)
    features = d.to_geojson(box, tolerance=1e-4)["features"]
    assert [len(f["geometry"]["coordinates"][0]) if f["geometry"] else 0 for f in features] == \
        [len(f.exterior.coords) if not f.is_empty else 0 for f in fine]


@pytest.mark.parametrize("tolerance", [0.0, -1e-3, float("nan"), float("inf"), 1e-12])
def test_a_tolerance_that_cannot_be_kept_is_refused(tolerance):
    box = (-12.0, -12.0, 12.0, 12.0)
    import impls

    for d in (_disks(), impls.build("fortune", np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]))):
        with pytest.raises(ValueError, match="tolerance"):
            d.cell_polygon(0, box, tolerance=tolerance)
        with pytest.raises(ValueError, match="tolerance"):
            d.to_geojson(box, tolerance=tolerance)
