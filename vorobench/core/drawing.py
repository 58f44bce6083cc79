"""Drawing a diagram with matplotlib: sites, edges clipped to a box, vertices (``Diagram.plot``).

The default box frames the sites (:func:`~vorobench.core.framing.site_box`), not the
vertices, which can lie arbitrarily far away when sites are nearly collinear.
"""

from __future__ import annotations

import math
from typing import Any, Optional, Protocol, Sequence

import numpy as np
from numpy.typing import NDArray

from vorobench.core.framing import HasSites, checked_box, site_box

# matplotlib is imported by the function that draws: importing the core must not load it
# (0.5 s, measured), and the caller may still have to choose its backend.

__all__ = ["Drawable", "edge_segments", "clip_segments", "draw"]


class Drawable(HasSites, Protocol):
    """What drawing reads of a ``Diagram`` (not imported here: its ``plot`` imports this module)."""

    @property
    def vertices(self) -> NDArray[np.float64]: ...
    @property
    def origin(self) -> NDArray[np.integer]: ...
    @property
    def twin(self) -> NDArray[np.integer]: ...
    @property
    def site(self) -> NDArray[np.integer]: ...
    def edges(self) -> NDArray[np.int64]: ...
    def half_edge_direction(self, h: NDArray[np.integer]) -> NDArray[np.float64]: ...


def edge_segments(diagram: Drawable, box: Sequence[float]) -> NDArray[np.float64]:
    """(E, 2, 2) segments of the edges in ``edges()`` order; an end at infinity is put far
    enough along its edge that the segment crosses all of ``box``."""
    d = diagram
    e = d.edges()
    if e.size == 0:
        return np.zeros((0, 2, 2))
    xmin, ymin, xmax, ymax = checked_box(box)
    centre = np.array([(xmin + xmax) / 2, (ymin + ymax) / 2])
    direction = d.half_edge_direction(e)
    direction = direction / np.linalg.norm(direction, axis=1)[:, None]
    start, end = d.origin[e], d.origin[d.twin[e]]
    a, b = d.sites[d.site[e]], d.sites[d.site[d.twin[e]]]
    mid = 0.5 * (a + b)
    weights = getattr(d, "weights", None)
    if weights is not None:
        # a power bisector passes the midpoint moved by (w_a - w_b) / (2 |b - a|^2) of b - a
        w = np.asarray(weights, dtype=np.float64)
        t = 0.5 * (w[d.site[e]] - w[d.site[d.twin[e]]]) / ((b - a) ** 2).sum(axis=1)
        mid = mid + t[:, None] * (b - a)
    has_vertices = d.vertices.shape[0] > 0
    vs = d.vertices[np.maximum(start, 0)] if has_vertices else mid
    ve = d.vertices[np.maximum(end, 0)] if has_vertices else mid
    # Each ray or line goes on from its finite point (a vertex, or the sites' midpoint for a
    # full line) by that point's distance to the box plus the box's diagonal: past the box,
    # even from a vertex far outside it.
    anchor = np.where((start >= 0)[:, None], vs, np.where((end >= 0)[:, None], ve, mid))
    reach = (np.hypot(*(anchor - centre).T) + np.hypot(xmax - xmin, ymax - ymin))[:, None]
    p0 = np.where((start >= 0)[:, None], vs, anchor - reach * direction)
    p1 = np.where((end >= 0)[:, None], ve, anchor + reach * direction)
    return np.stack([p0, p1], axis=1)


def clip_segments(segments: NDArray[np.float64], box: Sequence[float]
                  ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """``segments`` (m, 2, 2) cut to ``box`` (Liang-Barsky), and which of them meet the box.
    Rows that miss it are left as they were. Drawing only what is inside keeps coordinates
    of far-away vertices out of the renderer."""
    xmin, ymin, xmax, ymax = checked_box(box)
    p, q = segments[:, 0, :], segments[:, 1, :]
    delta = q - p
    t0, t1 = np.zeros(len(segments)), np.ones(len(segments))
    inside = np.ones(len(segments), dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        for axis, low, high in ((0, xmin, xmax), (1, ymin, ymax)):
            dx, px = delta[:, axis], p[:, axis]
            parallel = dx == 0
            inside &= ~(parallel & ((px < low) | (px > high)))
            ta, tb = (low - px) / dx, (high - px) / dx
            enter, leave = np.minimum(ta, tb), np.maximum(ta, tb)
            t0 = np.where(parallel, t0, np.maximum(t0, enter))
            t1 = np.where(parallel, t1, np.minimum(t1, leave))
    inside &= t0 <= t1
    clipped = segments.copy()
    clipped[inside, 0] = p[inside] + t0[inside, None] * delta[inside]
    clipped[inside, 1] = p[inside] + t1[inside, None] * delta[inside]
    return clipped, inside


def draw(diagram: Drawable, ax: Any = None, box: Optional[Sequence[float]] = None, *, title: str = "",
         highlight: Optional[Sequence[int]] = None, edge_color: str = "tab:blue", label: Optional[str] = None,
         show_sites: bool = True) -> Any:
    """Draw sites, edges and vertices of ``diagram`` inside ``box`` = (xmin, ymin, xmax, ymax)
    (default: around the sites) on ``ax`` (default: a new figure's); ``highlight`` lists
    half-edges to draw in red. Returns the axes."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    d = diagram
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 7))
    box = site_box(d) if box is None else checked_box(box)
    xmin, ymin, xmax, ymax = box
    radii = getattr(d, "radii", None)
    if radii is not None:
        return _draw_disks(d, ax, box, title=title, edge_color=edge_color, label=label, show_sites=show_sites)
    segments, shown = clip_segments(edge_segments(d, box), box)
    n_sites = d.sites.shape[0]
    small = n_sites <= 2000
    if shown.any():
        ax.add_collection(LineCollection(segments[shown], colors=edge_color, linewidths=0.9 if small else 0.3,
                                         label=label or "edges"))
    if highlight is not None and len(highlight):
        chosen = np.asarray(highlight, dtype=np.int64)
        row_of_edge = {int(h): k for k, h in enumerate(d.edges())}
        rows = [row_of_edge[h] for h in np.unique(np.minimum(chosen, d.twin[chosen])).tolist() if h in row_of_edge]
        rows = [k for k in rows if shown[k]]
        if rows:
            ax.add_collection(LineCollection(segments[rows], colors="red", linewidths=2.5, label="highlighted"))
    v = d.vertices
    in_box = (v[:, 0] >= xmin) & (v[:, 0] <= xmax) & (v[:, 1] >= ymin) & (v[:, 1] <= ymax)
    if in_box.any() and small:
        ax.plot(v[in_box, 0], v[in_box, 1], "o", ms=2.5, color="tab:orange", label="vertices")
    weights = getattr(d, "weights", None)
    hidden = np.zeros(n_sites, dtype=bool)
    if weights is not None and n_sites > 1:
        hidden[:] = True
        hidden[np.asarray(d.site, dtype=np.int64)] = False
        if small:
            # each weight w > 0 as the circle of radius sqrt(w): a cell is where a point's
            # tangent to that circle is the shortest
            w = np.asarray(weights, dtype=np.float64)
            ring = (w > 0) & ~hidden
            _circles(ax, d.sites[ring], np.sqrt(w[ring]), "weight w: circle of radius sqrt(w)")
    if show_sites and n_sites:
        shown_sites = d.sites[~hidden]
        ax.plot(shown_sites[:, 0], shown_sites[:, 1], ".", ms=4 if small else 1, color="black", label="sites")
        if hidden.any():
            ax.plot(d.sites[hidden, 0], d.sites[hidden, 1], "x", ms=5 if small else 2, color="tab:red",
                    label=f"hidden sites ({int(hidden.sum())})")
    return _framed(ax, box, title)


def _draw_disks(d: Any, ax: Any, box: Sequence[float], *, title: str, edge_color: str, label: Optional[str],
                show_sites: bool) -> Any:
    """A diagram of disks: its edges sampled along their branches (within a thousandth of the
    box's diagonal), the visible disks' circles, hidden disks marked."""
    from matplotlib.collections import LineCollection

    from vorobench.core.branch_curves import DEFAULT_CURVE_TOLERANCE, branch_polyline

    xmin, ymin, xmax, ymax = box
    tolerance = DEFAULT_CURVE_TOLERANCE * math.hypot(xmax - xmin, ymax - ymin)
    radii = np.asarray(d.radii, dtype=np.float64)
    pieces = []
    for h in d.edges():
        start, end = int(d.origin[h]), int(d.origin[d.twin[h]])
        line = branch_polyline(d.sites, radii, int(d.site[h]), int(d.site[d.twin[h]]),
                               None if start < 0 else d.vertices[start], None if end < 0 else d.vertices[end],
                               box, tolerance)
        pieces.append(np.stack([line[:-1], line[1:]], axis=1))
    if pieces:
        segments, shown = clip_segments(np.concatenate(pieces), box)
        if shown.any():
            ax.add_collection(LineCollection(segments[shown], colors=edge_color, linewidths=0.9,
                                             label=label or "edges (branches of hyperbolas)"))
    v = d.vertices
    in_box = (v[:, 0] >= xmin) & (v[:, 0] <= xmax) & (v[:, 1] >= ymin) & (v[:, 1] <= ymax)
    if in_box.any():
        ax.plot(v[in_box, 0], v[in_box, 1], "o", ms=2.5, color="tab:orange", label="vertices")
    n = d.sites.shape[0]
    hidden = np.zeros(n, dtype=bool)
    hidden[np.asarray(d.hidden, dtype=np.int64)] = n > 1
    ring = (radii > 0) & ~hidden
    _circles(ax, d.sites[ring], radii[ring], "disks")
    if show_sites and n:
        ax.plot(d.sites[~hidden, 0], d.sites[~hidden, 1], ".", ms=4, color="black", label="centres")
        if hidden.any():
            ax.plot(d.sites[hidden, 0], d.sites[hidden, 1], "x", ms=5, color="tab:red",
                    label=f"hidden disks ({int(hidden.sum())})")
    return _framed(ax, box, title)


def _circles(ax: Any, centres: NDArray[np.float64], radii: NDArray[np.float64], label: str) -> None:
    """Outlines of circles (disks, or the circles of power weights), in data units."""
    from matplotlib.collections import EllipseCollection

    if not len(radii):
        return
    size = 2 * np.asarray(radii, dtype=np.float64)
    ax.add_collection(EllipseCollection(size, size, np.zeros(size.size), units="xy", offsets=centres,
                                        offset_transform=ax.transData, facecolors="none",
                                        edgecolors="tab:gray", linewidths=0.6))
    ax.plot([], [], "o", mfc="none", mec="tab:gray", label=label)


def _framed(ax: Any, box: Sequence[float], title: str) -> Any:
    """The axes set to ``box`` at equal scale, titled, with a legend if anything was drawn."""
    xmin, ymin, xmax, ymax = box
    ax.set_xlim(xmin, xmax)
    ax.set_ylim(ymin, ymax)
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    if title:
        ax.set_title(title)
    if ax.get_legend_handles_labels()[0]:                  # nothing drawn, no empty legend
        ax.legend(loc="upper right", fontsize="small", framealpha=0.8)
    return ax
