"""What may cross the wire for a diagram of n disks (``diagram_schema(n, disks=True)``) is honest:
two cells may share several edges, yet a diagram of n disks has at most 2n - 2 vertices and
3n - 3 edges (Euler with every vertex of degree 3 or more), and the schema allows twice that;
radii of the wrong length, or radii where no disks were asked for, are refused."""

from __future__ import annotations

import numpy as np
import pytest

import datasets_gen
from impls import halfplane_disks
from vorobench.judge import wire
from vorobench.judge.engine import diagram_arrays, diagram_schema


def _round_trip(d, schema) -> dict:
    return wire.decode(wire.encode("ok", None, diagram_arrays(d)), schema)[2]


def _lenses(k: int) -> tuple[np.ndarray, np.ndarray]:
    """k big disks in a row with a small one in each gap: neighbouring big disks share two edges,
    one above and one below the small disk's lens."""
    centres = np.array([[20.0 * i, 0.0] for i in range(k)] + [[20.0 * i + 10.0, 0.0] for i in range(k - 1)])
    return centres, np.array([9.5] * k + [0.1] * (k - 1))


def _edges_between(d, a: int, b: int) -> int:
    site, twin = np.asarray(d.site), np.asarray(d.twin)
    return int(np.sum((site == a) & (site[twin] == b)))


def _within_the_bound(d) -> None:
    n = d.sites.shape[0]
    counts = d.counts()
    assert counts["V"] <= 2 * n - 2 and counts["E"] <= 3 * n - 3, counts
    schema = diagram_schema(n, disks=True)
    # twice the bound fits: room for an honest layout (zero-length edges, unused rows)
    assert schema["vertices"].shape[0] >= 2 * (2 * n - 2) and schema["next"].shape[0] >= 2 * (6 * n - 6)
    arrays = _round_trip(d, schema)
    assert np.array_equal(arrays["radii"], d.radii) and np.array_equal(arrays["next"], d.next)


def test_cells_sharing_several_edges_stay_within_the_schema():
    d = halfplane_disks.build(*_lenses(6))
    assert all(_edges_between(d, i, i + 1) == 2 for i in range(5))       # several edges per pair
    _within_the_bound(d)


@pytest.mark.parametrize("family", ["random", "nested", "tangent", "integer", "huge"])
@pytest.mark.parametrize("layout", ["uniform", "grid"])
def test_every_radius_family_stays_within_the_schema(layout, family):
    points = datasets_gen.generate(layout, 60, seed=2)
    _within_the_bound(halfplane_disks.build(points, datasets_gen.radii(family, points, seed=2)))


def test_radii_of_another_length_or_without_disks_are_refused():
    d = halfplane_disks.build(*_lenses(3))
    n = d.sites.shape[0]
    with pytest.raises(wire.WireError, match="radii"):
        _round_trip(d, diagram_schema(n - 1, disks=True) | {"sites": diagram_schema(n)["sites"]})
    with pytest.raises(wire.WireError, match="unexpected array 'radii'"):
        _round_trip(d, diagram_schema(n))
