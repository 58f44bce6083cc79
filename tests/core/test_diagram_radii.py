"""A Diagram of disks: it carries its radii through copies and files, lets hidden disks go
without edges, refuses weights and radii together and polygons it cannot draw yet."""

from __future__ import annotations

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


def test_polygons_of_curved_cells_are_refused_clearly():
    with pytest.raises(NotImplementedError, match="hyperbolas"):
        _disks().cell_polygon(1)
