"""The scipy-style views of a Diagram against scipy.spatial.Voronoi's own, and the way back:
Diagram.from_scipy and the builder's unoriented ridges."""

from __future__ import annotations

import dataclasses
import json
import pickle

import matplotlib
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial import KDTree, Voronoi, voronoi_plot_2d

import datasets_gen
import impls
from vorobench import Diagram, InvalidDiagramError, compare
from vorobench.core.builder import assemble
from vorobench.core.regions import Regions
from vorobench.core.hull import all_collinear

matplotlib.use("Agg")

#: Inputs Qhull decides the same way as the exact constructions: random, clustered, exactly
#: degenerate (a grid's cocircular squares, one big circle) and duplicated rows.
CASES = [("uniform", 300, 0), ("uniform", 200, 5), ("disk", 250, 1), ("clusters", 200, 2), ("grid", 225, 0),
         ("cocircular", 64, 0), ("duplicates", 240, 3)]


def _points(name: str, n: int, seed: int) -> np.ndarray:
    return datasets_gen.generate(name, n, seed=seed)


def _with_repeated_rows(points: np.ndarray, seed: int) -> np.ndarray:
    """``points`` with a few rows repeated at random places (13 rows, 10 distinct, and so on)."""
    rng = np.random.default_rng(seed)
    extra = points[rng.integers(0, len(points), size=max(3, len(points) // 5))]
    rows = np.concatenate([points, extra])
    return rows[rng.permutation(len(rows))]


def _vertex_map(ours: Diagram, vor: Voronoi) -> np.ndarray:
    """Index of scipy's vertex at each of our vertices; each must have exactly one partner."""
    scale = float(np.ptp(vor.points, axis=0).max())
    dist, idx = KDTree(vor.vertices).query(ours.vertices)
    assert dist.max(initial=0.0) <= 1e-9 * scale, "a vertex of ours has no scipy vertex at its place"
    assert len(set(idx.tolist())) == ours.n_vertices == len(vor.vertices)
    return np.append(idx, -1)                      # index -1 (infinity) maps to -1


def _site_of_row(d: Diagram, vor: Voronoi) -> np.ndarray:
    """Rows with equal coordinates share a site: the partition point_region must draw."""
    _, site = np.unique(vor.points, axis=0, return_inverse=True)
    return site.reshape(-1)


#: fortune may split a vertex of 4 cocircular sites into two joined by a zero-length ridge (the
#: DCEL contract allows either form); incremental merges them, as Qhull does.
VIEW_CASES = [("incremental", *case) for case in CASES] + [
    ("fortune", name, n, seed) for name, n, seed in CASES if name not in ("grid", "cocircular")]


@pytest.mark.parametrize("impl,name,n,seed", VIEW_CASES)
def test_views_match_scipy(impl, name, n, seed):
    rows = _with_repeated_rows(_points(name, n, seed), seed)
    d = impls.build(impl, rows)
    vor = Voronoi(rows)
    vmap = _vertex_map(d, vor)

    # points: the input rows, duplicates included; point_region: one entry per row
    assert np.array_equal(d.points, rows)
    assert d.point_region.shape == (len(rows),) == vor.point_region.shape
    same_site = _site_of_row(d, vor)
    assert np.array_equal(d.point_region, d.point_region[np.unique(same_site, return_index=True)[1]][same_site])
    assert len(set(d.point_region.tolist())) == len(set(same_site.tolist())) == d.n_sites

    # regions: each row's cell has scipy's vertices (and -1 when unbounded), once each
    for i in range(len(rows)):
        ours = d.regions[d.point_region[i]]
        theirs = vor.regions[vor.point_region[i]]
        assert sorted(vmap[ours].tolist()) == sorted(theirs), f"row {i}"

    # ridges: the same pairs of cells with the same two ends, -1 first
    rv = d.ridge_vertices
    assert not ((rv[:, 1] < 0) & (rv[:, 0] >= 0)).any(), "-1 must come first in an infinite ridge"
    e = d.edges()                                   # ridge_points name each site's first row
    assert np.array_equal(d.points[d.ridge_points[:, 0]], d.sites[d.site[e]])
    assert np.array_equal(d.points[d.ridge_points[:, 1]], d.sites[d.site[d.twin[e]]])
    assert (d.point_region[d.ridge_points] == d.site[np.stack([e, d.twin[e]], axis=1)]).all()
    ours = {frozenset(d.point_region[p].tolist()): tuple(vmap[v].tolist()) for p, v in zip(d.ridge_points, rv)}
    theirs = {frozenset(d.point_region[p].tolist()): tuple(v) for p, v in zip(vor.ridge_points, vor.ridge_vertices)
              if v[0] != v[1]}
    assert ours.keys() == theirs.keys()
    for key, ends in ours.items():
        assert sorted(ends) == sorted(theirs[key])
        if -1 in theirs[key]:
            assert ends[0] == -1 and theirs[key][0] == -1, "scipy and we both put -1 first"
    assert set(d.ridge_dict) == {tuple(p) for p in d.ridge_points.tolist()}


def test_regions_of_a_bounded_cell_run_counter_clockwise():
    d = impls.build("incremental", _points("uniform", 200, 4))
    for region in d.regions:
        if region and -1 not in region:
            x, y = d.vertices[region].T
            assert np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)) > 0


def test_voronoi_plot_2d_draws_our_diagram_as_scipy_draws_its_own():
    import matplotlib.pyplot as plt

    rows = _with_repeated_rows(_points("uniform", 200, 9), 9)
    figures = [voronoi_plot_2d(impls.build("fortune", rows)), voronoi_plot_2d(Voronoi(rows))]
    counts = [sorted(len(c.get_segments()) for c in fig.axes[0].collections) for fig in figures]
    for fig in figures:
        plt.close(fig)
    assert counts[0] == counts[1] and sum(counts[0]) > 500


def test_views_are_computed_once_and_cannot_be_changed():
    d = impls.build("incremental", _with_repeated_rows(_points("uniform", 100, 1), 1))
    for view in ("regions", "ridge_points", "ridge_vertices", "point_region", "ridge_dict"):
        assert getattr(d, view) is getattr(d, view), view
    for view in ("ridge_points", "ridge_vertices", "point_region", "points"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(d, view)[0] = 0
    with pytest.raises(dataclasses.FrozenInstanceError):
        d.sites = d.sites[:2]


def test_without_duplicates_the_points_are_the_sites():
    pts = _points("uniform", 50, 2)
    d = impls.build("incremental", pts)
    assert d.points is d.sites and np.array_equal(d.point_region, np.arange(50))


def test_input_rows_survive_save_and_load(tmp_path):
    rows = _with_repeated_rows(_points("uniform", 40, 3), 3)
    d = impls.build("incremental", rows)
    d.save(tmp_path / "d.npz")
    back = Diagram.load(tmp_path / "d.npz")
    assert np.array_equal(back.points, rows) and np.array_equal(back.point_region, d.point_region)


def test_with_input_refuses_rows_that_name_no_site():
    d = impls.build("incremental", _points("uniform", 10, 0))
    with pytest.raises(ValueError, match="outside"):
        d.with_input(np.zeros((3, 2)), [0, 1, 10])
    with pytest.raises(ValueError, match="go together"):
        Diagram(d.sites, d.vertices, d.origin, d.twin, d.next, d.site, input_points=d.sites)


# ------------------------------------------------------------------ from scipy
@pytest.mark.parametrize("name,n,seed", CASES + [("lattice_rotated", 196, 0), ("near_grid", 200, 1),
                                                  ("kuzmin", 300, 2), ("parabola", 200, 0)])
def test_from_scipy_agrees_with_incremental(name, n, seed):
    rows = _with_repeated_rows(_points(name, n, seed), seed)
    vor = Voronoi(rows)
    d = Diagram.from_scipy(vor).validate()
    assert np.array_equal(d.points, rows) and d.npoints == len(rows)
    assert KDTree(vor.vertices).query(d.vertices)[0].max(initial=0.0) == 0.0     # scipy's own vertices
    verdict = compare(d, impls.build("incremental", rows), labels=("scipy", "incremental")).verdict
    assert verdict in ("exact", "within_tolerance"), verdict


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.integers(-6, 6), st.integers(-6, 6)), min_size=4, max_size=40))
def test_from_scipy_on_small_integer_inputs(cells):
    rows = np.array(cells, dtype=np.float64)
    sites = np.unique(rows, axis=0)
    if len(sites) < 3 or all_collinear(sites):
        return                                      # Qhull refuses flat input
    d = Diagram.from_scipy(Voronoi(rows)).validate()
    verdict = compare(d, impls.build("incremental", rows)).verdict
    assert verdict in ("exact", "within_tolerance"), verdict


def test_from_scipy_refuses_what_is_not_a_nearest_site_voronoi():
    pts = _points("uniform", 30, 0)
    with pytest.raises(ValueError, match="furthest_site"):
        Diagram.from_scipy(Voronoi(pts, furthest_site=True))
    with pytest.raises(ValueError, match=r"got object without \.points"):
        Diagram.from_scipy(object())


# ------------------------------------------------------------------ unoriented ridges
@pytest.mark.parametrize("name,n", [("uniform", 300), ("grid", 256), ("cocircular", 48), ("collinear", 20),
                                    ("near_grid", 200)])
def test_assemble_orients_ridges_given_in_any_order(name, n):
    d = impls.build("incremental", _points(name, n, 0))
    e = d.edges()
    pairs = np.stack([d.site[e], d.site[d.twin[e]]], axis=1)
    ends = np.stack([d.origin[e], d.origin[d.twin[e]]], axis=1)
    rng = np.random.default_rng(0)
    ends = np.where(rng.random(len(e))[:, None] < 0.5, ends, ends[:, ::-1])
    pairs = np.where(rng.random(len(e))[:, None] < 0.5, pairs, pairs[:, ::-1])
    rebuilt = assemble(d.sites, d.vertices, pairs, ends, oriented=False)
    assert compare(rebuilt, d).verdict == "exact"


def test_scipy_ridges_need_the_unoriented_builder():
    vor = Voronoi(_points("uniform", 200, 6))
    with pytest.raises(InvalidDiagramError, match="oriented=False"):
        assemble(vor.points, vor.vertices, vor.ridge_points, vor.ridge_vertices)
    d = assemble(vor.points, vor.vertices, vor.ridge_points, vor.ridge_vertices, oriented=False).validate()
    assert compare(d, impls.build("incremental", vor.points)).equal


def test_assemble_names_ids_out_of_range():
    sites = np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]])
    with pytest.raises(InvalidDiagramError, match="site 3"):
        assemble(sites, [[1.0, 1.0]], [[0, 1], [1, 3], [2, 0]], [[-1, 0], [-1, 0], [-1, 0]])
    with pytest.raises(InvalidDiagramError, match="vertex 4"):
        assemble(sites, [[1.0, 1.0]], [[0, 1], [1, 2], [2, 0]], [[-1, 4], [-1, 0], [-1, 0]], oriented=False)
    with pytest.raises(ValueError, match="integer ids"):
        assemble(sites, [[1.0, 1.0]], [[0.5, 1], [1, 2], [2, 0]], [[-1, 0], [-1, 0], [-1, 0]])


def test_the_arrays_of_a_diagram_cannot_be_written_through_it():
    d = impls.build("incremental", _points("uniform", 50, 0))
    regions = d.regions
    for name in ("sites", "vertices", "origin", "twin", "next", "site"):
        with pytest.raises(ValueError, match="read-only"):
            getattr(d, name)[0] = 0
    assert d.regions is regions


def test_changing_a_region_handed_out_changes_no_cached_region():
    d = impls.build("incremental", _points("uniform", 50, 0))
    before = d.regions.tolist()
    d.regions[0].append(99)
    for region in d.regions:
        region.clear()
    d.regions.tolist()[1].append(7)
    d.regions[2:4][0].append(5)
    assert d.regions == before and d.regions.tolist() == before
    assert json.loads(json.dumps(d.regions.tolist())) == before


@pytest.mark.parametrize("protocol", range(pickle.HIGHEST_PROTOCOL + 1))
def test_a_diagram_whose_regions_were_read_pickles_with_every_protocol(protocol):
    d = impls.build("incremental", _points("uniform", 30, 0))
    regions = d.regions.tolist()
    back = pickle.loads(pickle.dumps(d, protocol=protocol))
    assert back.regions == regions and pickle.loads(pickle.dumps(d.regions, protocol=protocol)) == regions


def test_regions_refuse_arrays_of_the_wrong_shape_or_type():
    with pytest.raises(ValueError, match="1-D integer"):
        Regions(np.array([[1, 2]]), [0, 2])
    with pytest.raises(ValueError, match="offsets must be integers"):
        Regions(np.array([1, 2]), [0.0, 2.5])
    with pytest.raises(ValueError, match="offsets must rise"):
        Regions(np.array([1, 2]), [0, 3])


def test_regions_index_like_a_list_and_name_what_they_cannot_take():
    d = impls.build("incremental", _points("uniform", 20, 3))
    as_list = d.regions.tolist()
    assert len(d.regions) == len(as_list) == d.n_sites
    assert d.regions[-1] == as_list[-1] and d.regions[np.int64(2)] == as_list[2]
    assert d.regions[1:7:2] == as_list[1:7:2]
    assert d.regions != as_list[:-1] and d.regions != [[]] * len(as_list)
    with pytest.raises(IndexError, match="out of range"):
        d.regions[len(as_list)]
    with pytest.raises(TypeError, match="integers or slices"):
        d.regions["0"]
