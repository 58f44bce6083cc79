"""API contract of datasets_gen: names, shapes, determinism, actual_n and argument errors."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import datasets_gen as dg

NAMES = dg.available()
RANDOM = dg.available("random")
SIZES = [0, 1, 2, 3, 10, 100, 1000]

REQUIRED = {
    "random": {"uniform", "disk", "normal", "clusters", "kuzmin", "corners", "diagonal", "cross", "parabola"},
    "degenerate": {
        "grid",
        "lattice_rotated",
        "cocircular",
        "collinear",
        "duplicates",
        "near_grid",
        "huge_offset",
        "sorted",
    },
}


def test_required_families_registered() -> None:
    for family, names in REQUIRED.items():
        assert names <= set(dg.available(family))
    assert set(NAMES) == set(dg.DATASETS)
    assert NAMES == list(dg.DATASETS)
    assert set(dg.available("random")) | set(dg.available("degenerate")) == set(NAMES)


def test_registry_records_are_consistent() -> None:
    for name, d in dg.DATASETS.items():
        assert isinstance(d, dg.Dataset)
        assert d.name == name
        assert d.family in ("random", "degenerate")
        assert callable(d.generate)
        assert d.note and isinstance(d.exact_n, bool)
        desc = dg.describe(name)
        assert desc == d.description and desc.strip() and "\n" not in desc
        with pytest.raises(AttributeError):
            d.name = "other"  # type: ignore[misc]


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("n", SIZES)
def test_shape_dtype_finite_and_actual_n(name: str, n: int) -> None:
    pts = dg.generate(name, n, seed=11)
    assert isinstance(pts, np.ndarray)
    assert pts.dtype == np.float64
    assert pts.flags.c_contiguous
    assert pts.ndim == 2 and pts.shape[1] == 2
    assert pts.shape[0] == dg.actual_n(name, n)
    assert np.isfinite(pts).all()
    if dg.DATASETS[name].exact_n:
        assert pts.shape[0] == n
    else:
        assert (pts.shape[0] >= n) or (pts.shape[0] == dg.actual_n(name, n) < n)


@pytest.mark.parametrize("name", NAMES)
def test_deterministic_and_direct_generator_agrees(name: str) -> None:
    a = dg.generate(name, 200, seed=5)
    b = dg.generate(name, 200, seed=5)
    assert a.tobytes() == b.tobytes()
    direct = dg.DATASETS[name].generate(200, np.random.default_rng(5))
    assert direct.tobytes() == a.tobytes()
    assert dg.generate(name, 200).tobytes() == dg.generate(name, 200, seed=0).tobytes()


@pytest.mark.parametrize("name", RANDOM + ["duplicates", "huge_offset", "tiny_spacing", "sorted", "near_grid"])
def test_different_seeds_differ(name: str) -> None:
    assert not np.array_equal(dg.generate(name, 100, seed=1), dg.generate(name, 100, seed=2))


@pytest.mark.parametrize("name", ["grid", "lattice_rotated", "cocircular", "cocircular_many", "collinear"])
def test_seed_changes_order_or_choice_of_exact_sets(name: str) -> None:
    assert not np.array_equal(dg.generate(name, 100, seed=1), dg.generate(name, 100, seed=2))


def test_rounded_sizes() -> None:
    assert [dg.actual_n("grid", n) for n in (0, 1, 2, 4, 5, 10, 100, 101)] == [0, 1, 4, 4, 9, 16, 100, 121]
    for name in ("lattice_rotated", "near_grid"):
        assert dg.actual_n(name, 10) == 16
    assert dg.actual_n("cocircular", 10**6) == 6144
    assert dg.actual_n("cocircular", 5000) == 5000
    assert dg.actual_n("cocircular_many", 10**6) == 8192
    assert dg.actual_n("uniform", 12345) == 12345
    assert dg.generate("cocircular", 7000).shape == (6144, 2)
    assert dg.generate("cocircular_many", 9000).shape == (8192, 2)


# Golden digests (little-endian bytes of n=50, seed=7) pin the exact output so a
# change of platform or numpy stream is noticed.
GOLDEN: dict[str, str] = {
    "uniform": "a1c5fe9006668735",
    "disk": "252317a34e8633b0",
    "normal": "ca32d1cb5a00f2ad",
    "clusters": "0e9fce306b9dd63f",
    "kuzmin": "7b2169b689ec0fea",
    "corners": "27cf8aaf7b067163",
    "diagonal": "1bc3e6b89a1020a8",
    "cross": "8f6e8d88f721396f",
    "parabola": "bc2545fa9e65a402",
    "grid": "1101281e392e7960",
    "lattice_rotated": "f394b305407cb490",
    "near_grid": "56e81b8978471703",
    "cocircular": "e8c44ee01b10caba",
    "cocircular_many": "212cc9129513662e",
    "collinear": "07fad866f5736b78",
    "duplicates": "69b010b840b9346b",
    "huge_offset": "7bea022d3b263c46",
    "tiny_spacing": "344d4d1742857056",
    "sorted": "6ea4475b97284d49",
}


def _digest(name: str) -> str:
    return hashlib.sha256(dg.generate(name, 50, seed=7).astype("<f8").tobytes()).hexdigest()[:16]


def test_golden_digests_stable() -> None:
    got = {name: _digest(name) for name in NAMES}
    assert got == GOLDEN, {k: v for k, v in got.items() if GOLDEN.get(k) != v}




@pytest.mark.parametrize("bad", [-1, 1.5, 2.0, "10", None, True, np.float64(3.0)])
def test_bad_n_rejected(bad: object) -> None:
    with pytest.raises(ValueError, match="n must be a non-negative integer"):
        dg.generate("uniform", bad)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="n must be a non-negative integer"):
        dg.actual_n("grid", bad)  # type: ignore[arg-type]


def test_numpy_integer_n_and_seed_accepted() -> None:
    a = dg.generate("uniform", np.int64(5), seed=np.uint32(3))
    assert a.tobytes() == dg.generate("uniform", 5, seed=3).tobytes()


@pytest.mark.parametrize("bad", [-1, 0.5, "x", None])
def test_bad_seed_rejected(bad: object) -> None:
    with pytest.raises(ValueError, match="seed"):
        dg.generate("uniform", 3, seed=bad)  # type: ignore[arg-type]


def test_unknown_name_lists_available() -> None:
    for fn in (lambda: dg.generate("nope", 3), lambda: dg.describe("nope"), lambda: dg.actual_n("nope", 3)):
        with pytest.raises(ValueError) as info:
            fn()
        msg = str(info.value)
        assert "'nope'" in msg
        assert all(name in msg for name in NAMES)


def test_available_rejects_unknown_family() -> None:
    with pytest.raises(ValueError, match="family"):
        dg.available("weird")  # type: ignore[arg-type]


def test_public_api_exports() -> None:
    for sym in ("available", "generate", "describe", "actual_n", "load", "DATASETS", "Dataset"):
        assert sym in dg.__all__ and hasattr(dg, sym)
