"""Drawing in the core (``Diagram.plot``): framed around the sites, edges from far-away vertices
still cross the picture, only what is inside the box goes to the renderer, and importing the
core does not load matplotlib."""

import subprocess
import sys

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import datasets_gen  # noqa: E402
import impls  # noqa: E402
from vorobench.core.drawing import clip_segments, draw, edge_segments  # noqa: E402
from vorobench.core.framing import site_box  # noqa: E402

#: Nearly collinear: one vertex, about 5e5 below the sites; the rays 0|1 and 1|2 come up from
#: it through the sites, the ray 0|2 goes down.
NEARLY_COLLINEAR = [[0.0, 0.0], [1.0, 1e-6], [2.0, 0.0]]


@pytest.fixture
def ax():
    fig, ax = plt.subplots()
    yield ax
    plt.close(fig)


def sites_share_of_width(ax, sites) -> float:
    """How much of the axes' width (in pixels) the sites spread over."""
    ax.figure.canvas.draw()
    x = ax.transData.transform(sites)[:, 0]
    return float((x.max() - x.min()) / ax.bbox.width)


def test_importing_the_core_does_not_load_matplotlib():
    code = ("import sys, vorobench.core.diagram, vorobench.core.drawing, vorobench.core.export; "
            "assert 'matplotlib' not in sys.modules, 'matplotlib loaded'")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_the_default_frame_is_the_sites_not_the_far_vertex(ax):
    d = impls.build("fortune", NEARLY_COLLINEAR)
    assert d.vertices[:, 1].min() < -1e5
    assert draw(d, ax=ax) is ax
    box = site_box(d)
    assert ax.get_xlim() == (box[0], box[2]) and ax.get_ylim() == (box[1], box[3])
    assert sites_share_of_width(ax, d.sites) > 0.8


def test_two_hundred_sites_spread_over_the_picture_not_a_blob(ax):
    d = impls.build("qhull", datasets_gen.generate("uniform", 200, seed=0))
    assert d.bounding_box()[2] - d.bounding_box()[0] > 5          # far vertices exist
    draw(d, ax=ax)
    assert sites_share_of_width(ax, d.sites) > 0.8


def test_rays_from_a_far_vertex_cross_the_box():
    d = impls.build("fortune", NEARLY_COLLINEAR)
    box = site_box(d)
    segments, shown = clip_segments(edge_segments(d, box), box)
    by_sites = {tuple(sorted((int(d.site[h]), int(d.site[d.twin[h]])))): k for k, h in enumerate(d.edges())}
    for pair, x in (((0, 1), 0.5), ((1, 2), 1.5)):
        k = by_sites[pair]
        assert shown[k], f"edge {pair} misses the picture"
        # It runs from the bottom of the box to the top, along the bisector.
        (x0, y0), (x1, y1) = segments[k]
        assert sorted([y0, y1]) == pytest.approx([box[1], box[3]])
        assert x0 == pytest.approx(x, abs=1e-6) and x1 == pytest.approx(x, abs=1e-6)
    assert not shown[by_sites[(0, 2)]]                             # goes down, away from the box


def test_only_the_part_inside_the_box_is_drawn(ax):
    d = impls.build("incremental", datasets_gen.generate("uniform", 100, seed=2))
    box = (0.2, 0.3, 0.6, 0.5)
    draw(d, ax=ax, box=box)
    (edges,) = [c for c in ax.collections if c.get_label() == "edges"]
    ends = np.concatenate(edges.get_segments())
    tol = 1e-12
    assert ((ends[:, 0] >= box[0] - tol) & (ends[:, 0] <= box[2] + tol)).all()
    assert ((ends[:, 1] >= box[1] - tol) & (ends[:, 1] <= box[3] + tol)).all()
    assert 10 < len(edges.get_segments()) < d.n_edges
    (vertices,) = [line for line in ax.lines if line.get_label() == "vertices"]
    x, y = vertices.get_data()
    assert ((x >= box[0]) & (x <= box[2]) & (y >= box[1]) & (y <= box[3])).all() and len(x) > 3
    assert ax.get_xlim() == (0.2, 0.6) and ax.get_ylim() == (0.3, 0.5)


def test_a_bad_box_is_refused(ax):
    d = impls.build("fortune", NEARLY_COLLINEAR)
    with pytest.raises(ValueError, match="xmin < xmax"):
        draw(d, ax=ax, box=(1, 0, 0, 1))


def test_highlighted_half_edges_are_drawn_in_red(ax):
    d = impls.build("fortune", NEARLY_COLLINEAR)
    h = int(np.flatnonzero(d.site == 1)[0])
    draw(d, ax=ax, highlight=[d.twin[h]])                         # either half of the edge will do
    (red,) = [c for c in ax.collections if c.get_label() == "highlighted"]
    (segment,) = red.get_segments()
    expected = edge_segments(d, site_box(d))[list(d.edges()).index(min(h, int(d.twin[h])))]
    assert np.allclose(segment, clip_segments(expected[None], site_box(d))[0][0])


@pytest.mark.parametrize("points", [np.zeros((0, 2)), [[1.0, 2.0]], [[0.0, 0.0], [1.0, 0.0]]])
def test_trivial_diagrams_draw(ax, points):
    d = impls.build("fortune", points)
    draw(d, ax=ax)
    ax.figure.canvas.draw()
    assert (ax.get_legend() is None) == (d.n_sites == 0)        # no empty legend


def test_the_diagram_method_draws_on_a_new_figure_by_default():
    d = impls.build("fortune", NEARLY_COLLINEAR)
    ax = d.plot(title="three sites")
    try:
        assert ax.get_title() == "three sites" and ax.get_xlim() == (site_box(d)[0], site_box(d)[2])
    finally:
        plt.close(ax.figure)


@pytest.mark.parametrize("segment, expected", [
    ([[-1.0, 0.5], [2.0, 0.5]], [[0.0, 0.5], [1.0, 0.5]]),       # crosses, horizontal
    ([[0.5, -1.0], [0.5, 2.0]], [[0.5, 0.0], [0.5, 1.0]]),       # crosses, vertical
    ([[-1.0, -1.0], [2.0, 2.0]], [[0.0, 0.0], [1.0, 1.0]]),      # the diagonal
    ([[0.2, 0.2], [0.3, 0.4]], [[0.2, 0.2], [0.3, 0.4]]),        # inside: unchanged
    ([[0.5, 0.5], [0.5, 0.5]], [[0.5, 0.5], [0.5, 0.5]]),        # a point inside
])
def test_clip_segments_cuts_to_the_box(segment, expected):
    clipped, shown = clip_segments(np.array([segment]), (0.0, 0.0, 1.0, 1.0))
    assert shown.tolist() == [True]
    assert np.allclose(clipped[0], expected)


@pytest.mark.parametrize("segment", [
    [[-1.0, 2.0], [2.0, 2.0]],                                   # parallel, above
    [[1.5, -1.0], [1.5, 2.0]],                                   # parallel, to the right
    [[1.5, 0.0], [3.0, 1.0]],                                    # entirely right
    [[-1.0, 0.5], [0.5, 2.0]],                                   # passes the corner outside
])
def test_clip_segments_drops_what_misses_the_box(segment):
    _, shown = clip_segments(np.array([segment]), (0.0, 0.0, 1.0, 1.0))
    assert shown.tolist() == [False]
