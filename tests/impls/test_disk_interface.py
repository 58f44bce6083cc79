"""Disks through the common interface: ``impls.build(name, centres, radii=r)`` prepares them
(copies of a centre keep the largest radius), scales centres and radii by one power of two,
refuses what it cannot take, and keeps the caller's radii on the diagram."""

from __future__ import annotations

import numpy as np
import pytest

import impls
from impls.base import Implementation, InputMutated, UnsupportedInput
from impls.halfplane_disks import build as oracle


def test_halfplane_and_fortune_take_disks_and_qhull_says_it_does_not():
    assert {"halfplane", "fortune"} <= set(impls.apollonius()) and "qhull" not in impls.apollonius()
    with pytest.raises(UnsupportedInput, match="qhull does not take disks.*fortune, halfplane"):
        impls.build("qhull", [[0.0, 0.0], [1.0, 0.0]], radii=[0.5, 0.5])
    with pytest.raises(ValueError, match="one at a time"):
        impls.build("halfplane", [[0.0, 0.0], [1.0, 0.0]], radii=[0.5, 0.5], weights=[0.0, 0.0])


@pytest.mark.parametrize("radius", [-1.0, np.nan, np.inf])
def test_bad_radii_are_refused_naming_the_row(radius):
    with pytest.raises(ValueError, match="row 1"):
        impls.build("halfplane", [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], radii=[0.1, radius, 0.1])


def test_copies_of_a_centre_keep_the_largest_radius_and_rows_are_remembered():
    centres = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 0.0]]
    d = impls.build("halfplane", centres, radii=[0.1, 0.05, 0.1, 0.3])
    assert d.radii.tolist() == [0.1, 0.3, 0.1]
    assert d.point_region.shape == (4,) and d.point_region[1] == d.point_region[3]
    alone = oracle(np.array(centres[:3], dtype=float), np.array([0.1, 0.3, 0.1]))
    assert d.n_vertices == alone.n_vertices and np.array_equal(d.vertices, alone.vertices)


@pytest.mark.parametrize("scale", [2.0 ** -300, 2.0 ** 300])
def test_centres_and_radii_are_scaled_together(scale):
    rng = np.random.default_rng(2)
    centres, radii = rng.random((12, 2)), 0.2 * rng.random(12)
    unit = impls.build("halfplane", centres, radii=radii)
    far = impls.build("halfplane", centres * scale, radii=radii * scale)
    assert far.radii.tolist() == (radii * scale).tolist()
    assert np.array_equal(far.origin, unit.origin) and np.array_equal(far.next, unit.next)
    assert np.array_equal(far.vertices, unit.vertices * scale)          # powers of two: exact


def test_a_build_that_changes_its_radii_is_caught():
    def sneaky(centres, radii, stats):
        radii.setflags(write=True)
        radii[0] += 1.0
        return oracle(centres, radii)

    impl = Implementation(name="sneaky", description="", complexity="", build=lambda s, st: None,
                          build_apollonius=sneaky)
    with pytest.raises(InputMutated, match="radii"):
        impl.run(np.array([[0.0, 0.0], [1.0, 0.0]]), radii=np.array([0.1, 0.2]))
