"""Witness pictures: two diagrams overlaid, framed around the sites and the vertices near them,
not around vertices far away."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import impls  # noqa: E402
from vorobench.core.diagram import Diagram  # noqa: E402
from vorobench.judge.plotting import draw_overlay, save_overlay, save_plot, witness_box  # noqa: E402

#: Nearly collinear: the only vertex lies about 5e5 below the sites.
NEARLY_COLLINEAR = [[0.0, 0.0], [1.0, 1e-6], [2.0, 0.0], [3.0, 0.0]]


@pytest.fixture
def ax():
    fig, ax = plt.subplots()
    yield ax
    plt.close(fig)


def test_a_witness_with_a_far_vertex_shows_its_sites_spread_out(ax):
    own, ref = impls.build("fortune", NEARLY_COLLINEAR), impls.build("qhull", NEARLY_COLLINEAR)
    assert np.abs(own.vertices).max() > 1e5
    draw_overlay(ref, own, ax, labels=("qhull", "fortune"), highlight_second=[0])
    ax.figure.canvas.draw()
    x = ax.transData.transform(own.sites)[:, 0]
    assert (x.max() - x.min()) / ax.bbox.width > 0.7
    xmin, xmax = ax.get_xlim()
    ymin, ymax = ax.get_ylim()
    assert xmin < 0 and xmax > 3 and ymax - ymin < 2


def test_the_witness_frame_keeps_vertices_near_the_sites():
    # The circumcentre of this obtuse triangle, (1, -8/15), lies below the sites.
    d = impls.build("incremental", [[0.0, 0.0], [2.0, 0.0], [1.0, 0.6]])
    xmin, ymin, xmax, ymax = witness_box([d])
    assert ymin < -8 / 15 and ymax > 0.6 and xmin < 0 and xmax > 2
    far = impls.build("incremental", NEARLY_COLLINEAR)
    assert witness_box([far])[1] > -1


def test_a_moved_vertex_of_either_diagram_is_in_the_frame():
    good = impls.build("qhull", [[0.0, 0.0], [2.0, 0.0], [1.0, 2.0]])
    moved = Diagram(good.sites, good.vertices + [[0.0, 1.5]], good.origin, good.twin, good.next, good.site)
    assert witness_box([good, moved])[3] > moved.vertices[0, 1]


def test_save_overlay_writes_a_picture_in_the_given_box(tmp_path):
    d = impls.build("fortune", NEARLY_COLLINEAR)
    path = save_overlay(None, d, tmp_path / "w" / "overlay.png", box=(-1, -1, 4, 1), mark_sites=[1])
    assert path.stat().st_size > 1000
    with pytest.raises(ValueError, match="at least one diagram"):
        save_overlay(None, None, tmp_path / "none.png")
    with pytest.raises(ValueError, match="ymin < ymax"):
        save_overlay(d, None, tmp_path / "bad.png", box=(0, 1, 1, 0))


def test_save_plot_takes_a_box(tmp_path):
    d = impls.build("fortune", NEARLY_COLLINEAR)
    assert save_plot(d, tmp_path / "p.png", box=(0, -1, 1, 1)).stat().st_size > 1000
    with pytest.raises(ValueError, match="finite"):
        save_plot(d, tmp_path / "bad.png", box=(0, 0, float("inf"), 1))
