"""Drawing a diagram with matplotlib: sites, edges clipped to a box, vertices."""

from __future__ import annotations

from pathlib import Path
from typing import Optional, Sequence

import numpy as np
from numpy.typing import NDArray

from vorobench.core.diagram import Diagram

# matplotlib is imported by the functions that draw: it must be told its backend (Agg) before
# pyplot loads, and it adds 0.5 s to the start of every command that might draw (measured).

__all__ = ["edge_segments", "draw_diagram", "save_plot", "save_overlay"]


def edge_segments(d: Diagram, box: tuple[float, float, float, float]) -> NDArray[np.float64]:
    """(E, 2, 2) segments of every edge; ends at infinity are pushed beyond ``box``."""
    e = d.edges()
    if e.size == 0:
        return np.zeros((0, 2, 2))
    xmin, ymin, xmax, ymax = box
    reach = 4.0 * float(np.hypot(xmax - xmin, ymax - ymin))
    direction = d.half_edge_direction(e)
    direction = direction / np.linalg.norm(direction, axis=1)[:, None]
    start, end = d.origin[e], d.origin[d.twin[e]]
    a, b = d.sites[d.site[e]], d.sites[d.site[d.twin[e]]]
    mid = 0.5 * (a + b)
    vs = d.vertices[np.maximum(start, 0)] if d.n_vertices else mid
    ve = d.vertices[np.maximum(end, 0)] if d.n_vertices else mid
    # A ray starting at infinity reaches vertex `end` along `direction`: it came from end - t*dir.
    p0 = np.where((start >= 0)[:, None], vs, np.where((end >= 0)[:, None], ve, mid) - reach * direction)
    p1 = np.where((end >= 0)[:, None], ve, np.where((start >= 0)[:, None], vs, mid) + reach * direction)
    return np.stack([p0, p1], axis=1)


def draw_diagram(d: Diagram, ax=None, box: Optional[tuple[float, float, float, float]] = None,
                 title: str = "", highlight: Optional[Sequence[int]] = None,
                 edge_color: str = "tab:blue", label: Optional[str] = None, show_sites: bool = True):
    """Draw ``d`` on a matplotlib axes; ``highlight`` lists half-edges to draw in red."""
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    if ax is None:
        _, ax = plt.subplots(figsize=(7, 7))
    box = box or d.bounding_box()
    segs = edge_segments(d, box)
    small = d.n_sites <= 2000
    if segs.size:
        ax.add_collection(LineCollection(segs, colors=edge_color, linewidths=0.9 if small else 0.3,
                                         label=label or "edges"))
    if highlight is not None and len(highlight):
        hl = np.unique(np.minimum(np.asarray(highlight), d.twin[np.asarray(highlight)]))
        lookup = {int(h): k for k, h in enumerate(d.edges())}
        rows = [lookup[int(h)] for h in hl if int(h) in lookup]
        if rows:
            ax.add_collection(LineCollection(segs[rows], colors="red", linewidths=2.5, label="highlighted"))
    if d.n_vertices and small:
        ax.plot(d.vertices[:, 0], d.vertices[:, 1], "o", ms=2.5, color="tab:orange", label="vertices")
    if show_sites and d.n_sites:
        ax.plot(d.sites[:, 0], d.sites[:, 1], ".", ms=4 if small else 1, color="black", label="sites")
    ax.set_xlim(box[0], box[2])
    ax.set_ylim(box[1], box[3])
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    if title:
        ax.set_title(title)
    ax.legend(loc="upper right", fontsize="small", framealpha=0.8)
    return ax


def save_plot(d: Diagram, path: str | Path, title: str = "") -> Path:
    """Draw ``d`` and write the picture to ``path`` (format from the suffix)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 7))
    draw_diagram(d, ax=ax, title=title)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return path


def save_overlay(first: Optional[Diagram], second: Optional[Diagram], path: str | Path, *,
                 labels: tuple[str, str] = ("a", "b"), highlight_first: Optional[Sequence[int]] = None,
                 highlight_second: Optional[Sequence[int]] = None, mark_sites: Optional[Sequence[int]] = None,
                 title: str = "") -> Path:
    """Draw two diagrams of the same sites on one axes (``first`` solid blue, ``second``
    dashed orange), their differing half-edges in red and ``mark_sites`` circled; write ``path``.
    Either diagram may be None (e.g. the implementation crashed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    drawn = [d for d in (first, second) if d is not None]
    if not drawn:
        raise ValueError("save_overlay needs at least one diagram")
    boxes = np.array([d.bounding_box() for d in drawn])
    # Far-away vertices (nearly collinear sites) would shrink the sites to a dot: frame the sites.
    site_box = drawn[0].bounding_box(margin=0.25) if drawn[0].n_sites else boxes[0]
    box = (max(boxes[:, 0].min(), site_box[0]), max(boxes[:, 1].min(), site_box[1]),
           min(boxes[:, 2].max(), site_box[2]), min(boxes[:, 3].max(), site_box[3]))
    fig, ax = plt.subplots(figsize=(8, 8))
    if first is not None:
        draw_diagram(first, ax=ax, box=box, highlight=highlight_first, edge_color="tab:blue", label=labels[0])
    if second is not None:
        before = len(ax.collections)
        draw_diagram(second, ax=ax, box=box, highlight=highlight_second, edge_color="tab:orange", label=labels[1],
                     show_sites=first is None)
        if len(ax.collections) > before:
            ax.collections[before].set_linestyle("--")     # the second diagram's edges
    sites = drawn[0].sites
    if mark_sites is not None and len(mark_sites):
        idx = np.asarray(mark_sites, dtype=np.int64)
        ax.plot(sites[idx, 0], sites[idx, 1], "o", ms=10, mfc="none", mec="red", label="offending sites")
    if sites.shape[0] <= 60:
        for i, (x, y) in enumerate(sites):
            ax.annotate(str(i), (x, y), textcoords="offset points", xytext=(3, 3), fontsize=7)
    ax.set_title(title)
    handles, names = ax.get_legend_handles_labels()
    unique = dict(zip(names, handles))                    # one entry per label
    ax.legend(unique.values(), unique.keys(), loc="best", fontsize="small", framealpha=0.8)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path
