"""The ``cgal`` adapter: CGAL's Delaunay_triangulation_2 through the official bindings, dualised.

Skipped, with the reason, when the bindings are not installed (``pip install vorobench[peers]``).
``exact=True`` is checked against ``incremental``: same combinatorics and the very same vertex
coordinates on every kind of input, degenerate ones included; the file round trip the
conversion reads CGAL's triangulation through is checked on its own.
"""

from __future__ import annotations

import numpy as np
import pytest

import datasets_gen
import impls
from impls.base import UnsupportedInput
from vorobench.core.prepare import prepare
from vorobench.harness.sysinfo import library_versions
from vorobench.judge.certificate import certify
from vorobench.judge.comparison import compare
from vorobench.judge.engine import check_case

pytest.importorskip("CGAL", reason="adapter 'cgal' needs the optional library 'cgal' (pip install vorobench[peers])")

from impls.external import cgal  # noqa: E402  (imports CGAL)


def _sites(points) -> np.ndarray:
    return prepare(np.asarray(points, dtype=np.float64).reshape(-1, 2))[0]


def _assert_same_as_incremental(sites: np.ndarray, what: str = "") -> None:
    ours = impls.get("incremental").run(sites)
    d = impls.get("cgal").run(sites)
    cmp = compare(d, ours)
    assert cmp.equal and cmp.verdict == "exact", (what, str(cmp))
    key = np.lexsort(ours.vertices.T[::-1])
    assert np.array_equal(d.vertices[np.lexsort(d.vertices.T[::-1])], ours.vertices[key]), what


# ---------------------------------------------------------------- registry


def test_cgal_is_available_exact_and_external():
    assert "cgal" in impls.available()
    impl = impls.get("cgal")
    assert impl.name == "cgal" and impl.exact and impl.kind == "outside"
    assert impl.origin.startswith(f"CGAL {cgal.cgal_version()}")
    assert "cgal" in impls.of_kind("outside") and "cgal" not in impls.of_kind("own")


def test_cgal_is_absent_without_its_library(monkeypatch):
    monkeypatch.setitem(impls._BUILTIN, "cgal", ("impls.external.cgal:IMPLEMENTATION", "no_such_library_vorobench"))
    assert "cgal" not in impls.available()


def test_library_version_is_recorded():
    assert library_versions()["cgal"].startswith(cgal.cgal_version() + " (Python package cgal ")


# ---------------------------------------------------------------- agreement with incremental


@pytest.mark.parametrize("n", [0, 1, 2, 3])
def test_tiny_inputs_agree_exactly(n):
    for seed in range(3):
        _assert_same_as_incremental(_sites(np.random.default_rng(seed).random((n, 2))), f"n={n} seed={seed}")


@pytest.mark.parametrize("dataset", ["uniform", "grid", "cocircular", "cocircular_many", "collinear", "near_grid",
                                     "lattice_rotated", "huge_offset", "tiny_spacing", "clusters", "parabola"])
@pytest.mark.parametrize("n", [4, 10, 57, 300])
def test_families_agree_exactly_with_incremental(dataset, n):
    _assert_same_as_incremental(_sites(datasets_gen.generate(dataset, n, seed=3)), f"{dataset} n={n}")


def test_every_family_agrees_exactly_with_incremental():
    for dataset in datasets_gen.available():
        _assert_same_as_incremental(_sites(datasets_gen.generate(dataset, 150, seed=2)), dataset)


def test_small_random_sets_agree_exactly_and_certify():
    for seed in range(20):
        sites = _sites(np.random.default_rng(seed).random((4 + 3 * seed, 2)))
        _assert_same_as_incremental(sites, f"seed={seed}")
        assert certify(impls.get("cgal").run(sites)).ok


def test_magnitudes_the_run_scales_agree_exactly():
    unit = np.random.default_rng(7).random((40, 2))
    for k in (-1060, -400, 400, 1000):
        _assert_same_as_incremental(_sites(np.ldexp(unit, k)), f"2**{k}")


# ---------------------------------------------------------------- degenerate inputs


def test_collinear_sites_give_parallel_lines():
    stats: dict = {}
    sites = _sites([[3.0, 7.0], [0.0, 0.0], [6.0, 14.0], [-3.0, -7.0]])
    d = impls.get("cgal").run(sites, stats).validate()
    assert (d.n_vertices, d.n_edges) == (0, 3)
    pairs = {tuple(sorted(map(int, d.site[[h, d.twin[h]]]))) for h in range(d.n_half_edges)}
    assert pairs == {(1, 3), (0, 1), (0, 2)}
    assert stats["collinear"] == 1 and stats["cgal_faces"] == 0


def test_two_sites_give_one_full_line():
    d = impls.get("cgal").run(_sites([[0.0, 0.0], [2.0, 0.0]])).validate()
    assert (d.n_vertices, d.n_edges) == (0, 1) and np.all(d.origin == -1)


def test_cocircular_sites_are_one_vertex():
    stats: dict = {}
    # 12 integer points on x^2 + y^2 = 25: one vertex of degree 12, twelve rays
    circle = [(3, 4), (4, 3), (5, 0), (4, -3), (3, -4), (0, -5), (-3, -4), (-4, -3), (-5, 0), (-4, 3), (-3, 4), (0, 5)]
    d = impls.get("cgal").run(_sites(circle), stats).validate()
    assert d.n_vertices == 1 and np.array_equal(d.vertices, [[0.0, 0.0]])
    assert d.n_edges == 12
    assert stats["merged_triangles"] == 9 and stats["cgal_faces"] == 10
    _assert_same_as_incremental(_sites(circle))


def test_square_with_centre_keeps_four_vertices():
    d = impls.get("cgal").run(_sites([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0], [1.0, 1.0]])).validate()
    got = d.vertices[np.lexsort(d.vertices.T[::-1])]
    assert np.array_equal(got, [[0.0, 1.0], [1.0, 0.0], [1.0, 2.0], [2.0, 1.0]])


# ---------------------------------------------------------------- timings, counters, screening


def test_build_time_is_split_into_library_and_conversion_timings_not_counters():
    stats: dict = {}
    timings: dict = {}
    sites, _ = prepare(np.random.default_rng(1).random((300, 2)))
    impls.get("cgal").run(sites, stats, timings=timings)
    assert timings["library"] > 0 and timings["convert"] > 0
    assert all(isinstance(v, int) and not isinstance(v, bool) for v in stats.values()), stats
    assert not {"library_s", "convert_s"} & set(stats)
    # Euler on the sphere: 2 V - 4 triangles, V counting the infinite vertex
    assert stats["cgal_faces"] + stats["cgal_infinite_faces"] == 2 * (300 + 1) - 4


def test_supports_everything_in_range_and_refuses_what_no_scaling_fits():
    impl = impls.get("cgal")
    assert impl.unsupported_reason(_sites(np.random.default_rng(0).random((50, 2)))) is None
    assert impl.unsupported_reason(np.random.default_rng(0).random((50, 2)) * 1e300) is None
    mixed = np.array([[1.0, 0.0], [0.0, 1e-300], [1.0, 1.0], [0.5, 0.3]])
    reason = impl.unsupported_reason(mixed)
    assert reason and "exact range" in reason and "\n" not in reason
    with pytest.raises(ValueError):
        impls.build("cgal", mixed)
    assert issubclass(UnsupportedInput, ValueError)


def test_cross_validation_sees_it():
    for dataset in ("uniform", "grid", "cocircular", "collinear", "duplicates"):
        v = check_case("cgal", datasets_gen.generate(dataset, 120, seed=0), probes=500)
        assert v.passed, v.message


def test_the_public_point_constructor_gives_the_same_diagram(monkeypatch):
    sites = _sites(datasets_gen.generate("grid", 100, seed=0))
    fast = impls.get("cgal").run(sites)
    monkeypatch.setattr(cgal, "_MAKE_POINT", cgal.Point_2)
    slow = impls.get("cgal").run(sites)
    cmp = compare(fast, slow)
    assert cmp.equal and cmp.verdict == "exact"


def test_the_scratch_file_is_removed(monkeypatch, tmp_path):
    monkeypatch.setattr(cgal, "_scratch_dir", lambda size: str(tmp_path))
    impls.get("cgal").run(_sites(np.random.default_rng(2).random((100, 2))))
    assert list(tmp_path.iterdir()) == []


# ---------------------------------------------------------------- reading CGAL's file


def _parse(text: bytes, count: int):
    return cgal._read_doubles(np.frombuffer(text, dtype=np.uint8), 0, count, cgal._POW10_HI, cgal._POW10_LO,
                              cgal._POW10_MIN)


def test_17_digit_renderings_parse_back_bit_for_bit():
    rng = np.random.default_rng(3)
    x = np.concatenate([rng.random(20000), np.ldexp(rng.random(20000) + 1.0, rng.integers(-100, 100, 20000)),
                        rng.standard_normal(20000) * 10.0 ** rng.integers(-80, 80, 20000),
                        np.nextafter(np.ldexp(1.0, np.arange(-100, 100)), 0.0),
                        np.nextafter(10.0 ** np.arange(-30.0, 30.0), 0.0), 10.0 ** np.arange(-30.0, 30.0),
                        np.arange(-500.0, 500.0), [0.0, -0.0, 0.1, 1e-5, 123456789012345678.0]])
    text = ("\n".join(f"{v:.17g}" for v in x) + "\n").encode()
    y, end, ok = _parse(text, x.size)
    assert ok and end == len(text) - 1
    assert np.array_equal(x.view(np.uint64), y.view(np.uint64))


@pytest.mark.parametrize("token", [b"1e-300", b"5e300", b"inf", b"nan", b"1.2.3", b"1234567890123456789", b"-", b"1e"])
def test_tokens_outside_the_fast_parse_are_handed_back(token):
    assert not _parse(token + b" ", 1)[2]


#: CGAL's faces of one counter-clockwise triangle: the finite face (1, 2, 3) and a face with the
#: infinite vertex 0 across each of its edges; then each face's neighbours (k-th opposite vertex k).
_FACES = b"1 2 3 \n2 1 0 \n3 2 0 \n1 3 0 \n\n2 3 1 \n3 2 0 \n1 3 0 \n2 1 0 \n"


def test_read_triangulation_falls_back_to_numpy_for_extreme_coordinates():
    # the triangle (0, 0), (1e-300, 0), (0, 1e-300): outside the fast parse's range
    tiny = f"{1e-300:.17g}"
    text = (f"4 4 2\n0 0\n{tiny} 0\n0 {tiny}\n\n".encode() + _FACES)
    coords, faces, neighbours = cgal.read_triangulation(text)
    assert np.array_equal(coords, [[0.0, 0.0], [1e-300, 0.0], [0.0, 1e-300]])
    assert faces.shape == neighbours.shape == (4, 3)
    tri, opp = cgal.half_edges(faces, neighbours, 3)
    assert np.array_equal(opp[opp], np.arange(12))
    assert np.array_equal(tri[:3], [0, 1, 2])


def test_read_triangulation_refuses_truncated_or_foreign_text():
    good = b"4 4 2\n0 0\n1 0\n0 1\n\n" + _FACES
    cgal.read_triangulation(good)
    for bad in (good[:-8], good + b"7", b"3 1 1\n0 0\n1 0\n", b"hello\n"):
        with pytest.raises(ValueError):
            cgal.read_triangulation(bad)


def test_half_edges_refuse_neighbours_that_do_not_pair_up():
    faces = np.array([[1, 2, 3], [2, 1, 0], [3, 2, 0], [1, 3, 0]])
    neighbours = np.array([[2, 3, 1], [3, 2, 0], [1, 3, 0], [2, 1, 0]])
    cgal.half_edges(faces, neighbours, 3)
    with pytest.raises(ValueError):
        cgal.half_edges(faces, neighbours[[0, 2, 1, 3]], 3)


def test_cgal_file_round_trip_matches_every_site():
    from CGAL.CGAL_Triangulation_2 import Delaunay_triangulation_2

    sites = _sites(np.random.default_rng(5).standard_normal((500, 2)) * 1e7)
    dt = Delaunay_triangulation_2()
    dt.insert([cgal.Point_2(x, y) for x, y in sites.tolist()])
    coords, faces, neighbours = cgal.read_triangulation(cgal._file_text(dt, sites.shape[0]))
    ids, bad = cgal._match_sites(coords.view(np.uint64), sites.view(np.uint64))
    assert bad == -1 and np.array_equal(np.sort(ids), np.arange(sites.shape[0]))
    assert np.array_equal(coords, sites[ids])
    assert faces.shape[0] == dt.number_of_faces() + np.count_nonzero((faces == 0).any(axis=1))
