"""Edges of disks drawn as polylines: every sampled point is on its bisector branch, the ends are
the edge's vertices, no chord strays from the curve by more than the tolerance, and a diagram of
disks plots its curved edges, its disks and its hidden disks."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest

from impls import halfplane_disks
from branch_distance import chord_stray, gap
from vorobench.core.branch_curves import branch_polyline

matplotlib.use("Agg")

BOX = (-12.0, -12.0, 12.0, 12.0)


def test_points_lie_on_the_branch_and_the_ends_are_the_vertices():
    sites, radii = np.array([[-10.0, 0.0], [0.0, 0.0], [10.0, 0.0]]), np.array([9.5, 0.1, 9.5])
    d = halfplane_disks.build(sites, radii)
    for h in range(d.n_half_edges):
        a, b = int(d.site[h]), int(d.site[d.twin[h]])
        u, w = int(d.origin[h]), int(d.origin[d.twin[h]])
        line = branch_polyline(sites, radii, a, b, None if u < 0 else d.vertices[u], None if w < 0 else d.vertices[w],
                               BOX, 1e-3)
        assert all(abs(gap(sites, radii, a, b, p)) < 1e-9 * 20 for p in line)
        if u >= 0:
            assert np.array_equal(line[0], d.vertices[u])
        if w >= 0:
            assert np.array_equal(line[-1], d.vertices[w])
        if u < 0 or w < 0:                            # a ray runs out past the box
            far = line[0] if u < 0 else line[-1]
            assert not (BOX[0] <= far[0] <= BOX[2] and BOX[1] <= far[1] <= BOX[3])


@pytest.mark.parametrize("tolerance", [1e-1, 1e-3])
def test_no_chord_strays_beyond_the_tolerance(tolerance):
    sites, radii = np.array([[0.0, 0.0], [3.0, 1.0]]), np.array([2.0, 0.2])
    line = branch_polyline(sites, radii, 0, 1, None, None, BOX, tolerance)
    inside = [p for p in line if BOX[0] <= p[0] <= BOX[2] and BOX[1] <= p[1] <= BOX[3]]
    assert len(inside) >= 3
    # the curve between two consecutive samples, found by bisection on the bisector along the
    # chord's perpendicular, stays within the tolerance of the chord
    for p, q in zip(line[:-1], line[1:]):
        stray = chord_stray(sites, radii, 0, 1, p, q, 10 * tolerance + 1.0)
        assert stray is None or stray <= tolerance * 1.01 + 1e-12


def test_a_diagram_of_disks_plots_its_curves_disks_and_hidden_disks():
    import matplotlib.pyplot as plt
    from matplotlib.collections import EllipseCollection, LineCollection

    sites = np.array([[-10.0, 0.0], [0.0, 0.0], [10.0, 0.0], [10.0, 0.5]])
    d = halfplane_disks.build(sites, np.array([9.5, 0.1, 9.5, 1.0]))          # the last one hidden
    ax = d.plot(box=BOX)
    lines = [c for c in ax.collections if isinstance(c, LineCollection)]
    assert lines and len(lines[0].get_segments()) > 2 * d.n_edges          # curves, not one segment each
    assert any(isinstance(c, EllipseCollection) for c in ax.collections)
    labels = ax.get_legend_handles_labels()[1]
    assert "hidden disks (1)" in labels
    plt.close("all")
