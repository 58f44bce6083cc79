"""Pictures of diagrams for the judge and the command line: one diagram, or two overlaid.

The drawing itself (``draw``, ``edge_segments``) lives in :mod:`vorobench.core.drawing`, so
that ``Diagram.plot`` can use it; ``draw_diagram`` is its old name here.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Optional, Sequence

import numpy as np

from vorobench.core.diagram import Diagram
from vorobench.core.drawing import draw as draw_diagram
from vorobench.core.drawing import edge_segments
from vorobench.core.framing import Box, checked_box, point_box, site_box

# matplotlib is imported by the functions that draw: it must be told its backend (Agg) before
# pyplot loads, and it adds 0.5 s to the start of every command that might draw (measured).

__all__ = ["edge_segments", "draw_diagram", "save_plot", "witness_box", "draw_overlay", "save_overlay"]


def check_picture_path(path: str | Path, option: str = "--plot") -> None:
    """Refuse, before any work is done, a picture whose format (from the suffix) matplotlib
    cannot write (ValueError naming the formats it can)."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    formats = FigureCanvasAgg(Figure()).get_supported_filetypes()
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in formats:
        raise ValueError(f"{option} {path}: cannot write {'.' + suffix if suffix else 'a file without a suffix'}; "
                         f"give one of {', '.join('.' + f for f in sorted(formats))}")


def save_plot(d: Diagram, path: str | Path, title: str = "", box: Optional[Sequence[float]] = None) -> Path:
    """Draw ``d`` inside ``box`` (default: around the sites) and write the picture to ``path``
    (format from the suffix)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 7))
    try:
        draw_diagram(d, ax=ax, box=box, title=title)
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=120, bbox_inches="tight")
    finally:
        plt.close(fig)
    return path


def witness_box(diagrams: Sequence[Diagram], near: float = 0.5) -> Box:
    """The frame of an overlay: the sites, and the vertices within ``near`` times the sites'
    extent of them (where a wrong vertex would show), but not vertices far away, which nearly
    collinear sites have and which would shrink the sites to a dot."""
    if not diagrams:
        raise ValueError("witness_box needs at least one diagram")
    sites = diagrams[0].sites
    xmin, ymin, xmax, ymax = site_box(diagrams[0], margin=near)
    vertices = np.concatenate([np.asarray(d.vertices, dtype=np.float64).reshape(-1, 2) for d in diagrams])
    close = ((vertices[:, 0] >= xmin) & (vertices[:, 0] <= xmax)
             & (vertices[:, 1] >= ymin) & (vertices[:, 1] <= ymax))
    return point_box(np.concatenate([sites, vertices[close]]), margin=0.1)


def draw_overlay(first: Optional[Diagram], second: Optional[Diagram], ax: Any, *,
                 box: Optional[Sequence[float]] = None, labels: tuple[str, str] = ("a", "b"),
                 highlight_first: Optional[Sequence[int]] = None, highlight_second: Optional[Sequence[int]] = None,
                 mark_sites: Optional[Sequence[int]] = None, title: str = "") -> Any:
    """Draw two diagrams of the same sites on ``ax`` inside ``box`` (default
    :func:`witness_box`): ``first`` solid blue, ``second`` dashed orange, their differing
    half-edges in red and ``mark_sites`` circled. Either may be None (e.g. the implementation
    crashed). Returns the axes."""
    drawn = [d for d in (first, second) if d is not None]
    if not drawn:
        raise ValueError("draw_overlay needs at least one diagram")
    box = witness_box(drawn) if box is None else checked_box(box)
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
    if unique:
        ax.legend(unique.values(), unique.keys(), loc="best", fontsize="small", framealpha=0.8)
    return ax


def save_overlay(first: Optional[Diagram], second: Optional[Diagram], path: str | Path, *,
                 box: Optional[Sequence[float]] = None, labels: tuple[str, str] = ("a", "b"),
                 highlight_first: Optional[Sequence[int]] = None, highlight_second: Optional[Sequence[int]] = None,
                 mark_sites: Optional[Sequence[int]] = None, title: str = "") -> Path:
    """:func:`draw_overlay` on a new figure, written to ``path``."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 8))
    try:
        draw_overlay(first, second, ax, box=box, labels=labels, highlight_first=highlight_first,
                     highlight_second=highlight_second, mark_sites=mark_sites, title=title)
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=110, bbox_inches="tight")
    finally:
        plt.close(fig)
    return path
