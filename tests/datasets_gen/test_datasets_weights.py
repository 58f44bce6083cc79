"""Weight families for power diagrams: names, shapes, determinism, and what each family is for."""

from __future__ import annotations

import hashlib

import numpy as np
import pytest

import datasets_gen as dg
import impls
from datasets_gen.weight_families import HIDDEN_FRACTION, local_spacing

FAMILIES = list(dg.WEIGHT_FAMILIES)


def test_required_families_are_listed_with_descriptions() -> None:
    assert {"radii", "equal", "integer", "hidden"} <= set(FAMILIES)
    assert all(isinstance(text, str) and len(text) > 20 for text in dg.WEIGHT_FAMILIES.values())


@pytest.mark.parametrize("family", FAMILIES)
@pytest.mark.parametrize("n", [0, 1, 2, 3, 10, 200])
def test_shape_dtype_finite(family: str, n: int) -> None:
    points = dg.generate("uniform", n, seed=3)
    w = dg.weights(family, points, seed=3)
    assert w.dtype == np.float64 and w.shape == (n,) and w.flags.c_contiguous
    assert np.isfinite(w).all() and (w >= 0).all()


@pytest.mark.parametrize("family", FAMILIES)
def test_deterministic_by_seed(family: str) -> None:
    points = dg.generate("normal", 300, seed=1)
    first = dg.weights(family, points, seed=5)
    assert np.array_equal(first, dg.weights(family, points.copy(), seed=5))
    if family != "equal":
        assert not np.array_equal(first, dg.weights(family, points, seed=6))


# Little-endian bytes of the weights of uniform n=50 seed=7 (seed 7): a change of the streams
# or of a family's rule is noticed.
GOLDEN = {"radii": "b442f543fd3bbc79", "equal": "2a63edacb037cb71", "integer": "cbda7f387fafe694",
          "hidden": "10daed73bb0ea2e5"}


def test_golden_digests() -> None:
    points = dg.generate("uniform", 50, seed=7)
    got = {f: hashlib.sha256(dg.weights(f, points, seed=7).astype("<f8").tobytes()).hexdigest()[:16]
           for f in GOLDEN}
    assert got == GOLDEN


def test_weights_do_not_reuse_the_points_stream() -> None:
    # Uniform points of seed 0 are the first draws of default_rng(0): weights seeded the same
    # way would be a function of the x coordinates.
    points = dg.generate("uniform", 500, seed=0)
    w = dg.weights("radii", points, seed=0)
    assert abs(np.corrcoef(points[:, 0], w)[0, 1]) < 0.2
    assert not np.allclose(np.sqrt(w) / np.sqrt(w).max(), points[:, 0] / points[:, 0].max())


def test_equal_is_one_nonzero_constant() -> None:
    for dataset in ("uniform", "grid", "huge_offset", "collinear"):
        w = dg.weights("equal", dg.generate(dataset, 100, seed=2))
        assert w[0] > 0 and (w == w[0]).all()


def test_integer_weights_are_small_integers_and_0_or_1_on_the_unit_lattice() -> None:
    w = dg.weights("integer", dg.generate("grid", 400, seed=0), seed=4)
    assert set(np.unique(w)) == {0.0, 1.0}
    w = dg.weights("integer", dg.generate("lattice_rotated", 400, seed=0), seed=4)
    # The rotated lattice (spacing 5) fills about half its bounding box: s^2 is about 2 * 25.
    assert (w == np.round(w)).all() and w.max() <= 50 and len(np.unique(w)) > 5


def test_radii_stay_below_the_local_spacing() -> None:
    points = dg.generate("clusters", 400, seed=1)
    w = dg.weights("radii", points, seed=1)
    spacing = local_spacing(points)
    assert (np.sqrt(w) < spacing).all()
    # Dense clusters get small disks, their sparse edges large ones: the scale is local.
    assert spacing.max() > 5 * spacing.min()


def test_hidden_gives_most_sites_no_weight() -> None:
    w = dg.weights("hidden", dg.generate("uniform", 400, seed=0), seed=0)
    heavy = int((w > 0).sum())
    assert heavy == round(HIDDEN_FRACTION * 400)


def test_bad_arguments() -> None:
    points = dg.generate("uniform", 10)
    with pytest.raises(ValueError, match="unknown weight family 'nope'; available: radii"):
        dg.weights("nope", points)
    for seed in (-1, 1.5, True):
        with pytest.raises(ValueError, match="seed must be a non-negative integer"):
            dg.weights("radii", points, seed=seed)
    with pytest.raises(ValueError, match="finite"):
        dg.weights("radii", np.array([[0.0, np.nan], [1.0, 1.0]]))


def _weighted_qhull() -> None:
    if not impls.get("qhull").weighted:
        pytest.skip("qhull does not take weights yet")


def test_hidden_family_really_hides_most_sites() -> None:
    _weighted_qhull()
    points = dg.generate("uniform", 400, seed=0)
    d = impls.build("qhull", points, weights=dg.weights("hidden", points, seed=0))
    assert d.hidden.size > 400 // 2


def test_radii_hide_some_sites_and_equal_hides_none() -> None:
    _weighted_qhull()
    points = dg.generate("uniform", 400, seed=0)
    radii = impls.build("qhull", points, weights=dg.weights("radii", points, seed=0))
    assert 0 < radii.hidden.size < 400 // 4
    equal = impls.build("qhull", points, weights=dg.weights("equal", points, seed=0))
    assert equal.hidden.size == 0
