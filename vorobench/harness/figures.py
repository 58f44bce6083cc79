"""The report's matplotlib figures (Agg): one panel per dataset, one line per implementation.

Every figure takes the summary tables of :mod:`vorobench.harness.analysis` and a path, writes a PNG
and returns its path, or writes nothing and returns None when there is nothing to draw (no
figure is ever a placeholder). Colours and markers are fixed per implementation across figures,
and the verdict colours (:data:`VERDICT_COLOURS`) are shared with the interactive page.
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path
from typing import Optional, Sequence

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
from matplotlib.ticker import FixedLocator, FuncFormatter, LogLocator, NullFormatter, NullLocator  # noqa: E402

from vorobench.judge.outcomes import Verdict  # noqa: E402

__all__ = ["impl_styles", "plot_metric_panels", "plot_time", "plot_time_per_nlogn", "plot_ratio",
           "plot_memory", "plot_correctness", "VERDICT_COLOURS", "verdict_colour", "verdict_label",
           "text_colour", "has_data", "MEMORY_RESOLUTION_MB"]

_MARKERS = "osD^vP*Xh<>"

#: Colour of each verdict, one per :class:`vorobench.judge.outcomes.Verdict` in its order (best first).
#: Okabe-Ito's colour-blind-safe palette for the first eleven, three of Paul Tol's for the rest,
#: chosen so that every pair stays apart (CIELAB distance above 10) also under simulated
#: protanopia, deuteranopia and tritanopia. Passes are blues and green, "said nothing" greys,
#: failures warm or dark; every cell also names its verdict, so colour is never the only cue.
VERDICT_COLOURS: dict[str, str] = {
    Verdict.EXACT: "#009E73",             # bluish green
    Verdict.WITHIN_TOLERANCE: "#56B4E9",  # sky blue
    Verdict.CERTIFIED: "#0072B2",         # blue
    Verdict.NO_REFERENCE: "#BFD8EE",      # pale blue
    Verdict.UNSUPPORTED: "#BBBBBB",       # grey
    Verdict.SKIPPED: "#E8E8E8",           # light grey
    Verdict.DIFFERS: "#E69F00",           # orange
    Verdict.NOT_CERTIFIED: "#D55E00",     # vermillion
    Verdict.CHECK_ERROR: "#F0E442",       # yellow
    Verdict.WRONG_SITES: "#CC79A7",       # reddish purple
    Verdict.INVALID_OUTPUT: "#762A83",    # dark purple (ColorBrewer PRGn)
    Verdict.MUTATED_INPUT: "#882255",     # wine (Tol)
    Verdict.OOM: "#332288",               # indigo (Tol)
    Verdict.TIMEOUT: "#6F4E37",           # brown
    Verdict.CRASHED: "#000000",           # black
}
assert list(VERDICT_COLOURS) == [v.value for v in Verdict], "one colour per verdict, in the schema's order"

#: Colour of a verdict this version does not know.
UNKNOWN_VERDICT_COLOUR = "#FFFFFF"


def verdict_colour(verdict: object) -> str:
    return VERDICT_COLOURS.get(str(verdict), UNKNOWN_VERDICT_COLOUR)


def verdict_label(verdict: object) -> str:
    """How a verdict reads in a legend: "within tolerance"; "skipped" reads "not checked"."""
    return "not checked" if str(verdict) == Verdict.SKIPPED else str(verdict).replace("_", " ")


def text_colour(background: str) -> str:
    """Black or white, whichever reads better on ``background`` (relative luminance)."""
    r, g, b, _ = to_rgba(background)
    lin = [c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4 for c in (r, g, b)]
    return "black" if 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2] > 0.18 else "white"


def impl_styles(impls: Sequence[str]) -> dict[str, dict]:
    """A stable colour and marker for each implementation (sorted order)."""
    cmap = plt.get_cmap("tab10")
    return {name: {"color": cmap(i % 10), "marker": _MARKERS[i % len(_MARKERS)]}
            for i, name in enumerate(sorted(impls))}


def _size_label(n: float, _pos=None) -> str:
    """1000 -> 1k, 30000 -> 30k, 1024 -> 1.02k: short tick labels for sizes."""
    if n >= 1e6:
        return f"{n / 1e6:.3g}M"
    if n >= 1e3:
        return f"{n / 1e3:.3g}k"
    return f"{n:.3g}"


def _value_label(v: float, _pos=None) -> str:
    return f"{v:g}"


def _label_size_axis(ax, sizes: Sequence[float]) -> None:
    """Ticks at the sizes actually measured (when few), labelled 1k, 10k, ... instead of 10^3."""
    sizes = sorted(set(float(s) for s in sizes))
    if 0 < len(sizes) <= 8:
        ax.xaxis.set_major_locator(FixedLocator(sizes))
        ax.xaxis.set_minor_locator(NullLocator())
    else:
        ax.xaxis.set_minor_formatter(NullFormatter())
    ax.xaxis.set_major_formatter(FuncFormatter(_size_label))


def _label_log_values(ax) -> None:
    """Plain numbers on a log y axis; intermediate labels (2, 5) only when it spans little."""
    ax.yaxis.set_major_formatter(FuncFormatter(_value_label))
    lo, hi = ax.get_ylim()
    if lo > 0 and hi / lo < 100:
        ax.yaxis.set_minor_locator(LogLocator(base=10, subs=(2.0, 5.0)))
        ax.yaxis.set_minor_formatter(FuncFormatter(_value_label))
    else:
        ax.yaxis.set_minor_formatter(NullFormatter())


def _grid(n_panels: int, title: str):
    ncols = min(3, max(1, n_panels))
    nrows = math.ceil(n_panels / ncols)
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.6 * ncols, 3.6 * nrows + 0.8),
                             squeeze=False, layout="constrained")
    # Wrapped to the figure's width (about 11 characters per inch at this size): a one-panel
    # figure is narrow, and a long title would be clipped at both sides.
    fig.suptitle(textwrap.fill(title, width=max(30, int(4.6 * ncols * 11))), fontsize=13)
    for ax in axes.flat[n_panels:]:
        ax.set_visible(False)
    return fig, axes.flat


def _finish(fig, axes, path: Path, handles, labels) -> Path:
    if handles:
        fig.legend(handles, labels, loc="outside lower center", ncol=min(len(labels), 6), fontsize=10,
                   frameon=False)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def _drawable(values: pd.Series, positive: bool) -> pd.Series:
    v = pd.to_numeric(values, errors="coerce")
    ok = v.notna() & np.isfinite(v.astype(float))
    return ok & (v > 0) if positive else ok


def has_data(table: pd.DataFrame, column: str, positive: bool = True) -> bool:
    """Does ``table`` hold a value of ``column`` a figure can draw (finite; positive on a log axis)?"""
    return column in table.columns and bool(_drawable(table[column], positive).any())


def plot_metric_panels(table: pd.DataFrame, column: str, path: Path, title: str, ylabel: str,
                       styles: dict, logy: bool = True, hline: Optional[float] = None,
                       band: Optional[tuple[str, str]] = None, positive_only: bool = False,
                       order: Optional[Sequence[str]] = None) -> Optional[Path]:
    """One panel per dataset (in ``order``): ``column`` against n (log x) for every implementation.
    None, and no file, when no dataset has a value to draw."""
    drawable = table if table.empty else table[_drawable(table[column], positive_only or logy)]
    present = set(drawable["dataset"]) if not drawable.empty else set()
    datasets = [d for d in (order or sorted(present)) if d in present]
    datasets += sorted(present - set(datasets))
    if not datasets:
        return None
    table = drawable
    fig, axes = _grid(len(datasets), title)
    handles: dict[str, object] = {}
    for ax, dataset in zip(axes, datasets):
        part = table[table["dataset"] == dataset]
        for impl, g in part.groupby("impl", sort=True):
            g = g.sort_values("n_sites")
            if positive_only:
                g = g[g[column] > 0]
            if g.empty:
                continue
            style = styles[impl]
            (line,) = ax.plot(g["n_sites"], g[column], label=impl, color=style["color"],
                              marker=style["marker"], markersize=5, linewidth=1.6)
            if band:
                ax.fill_between(g["n_sites"], g[band[0]], g[band[1]], color=style["color"], alpha=0.15,
                                linewidth=0)
            handles.setdefault(impl, line)
        if hline is not None:
            ax.axhline(hline, color="0.3", linestyle="--", linewidth=1)
        ax.set_xscale("log")
        _label_size_axis(ax, part["n_sites"])
        if logy:
            ax.set_yscale("log")
            _label_log_values(ax)
        ax.set_title(dataset, fontsize=11)
        ax.set_xlabel("n (distinct sites)")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="major", alpha=0.35)
        ax.grid(True, which="minor", alpha=0.12)
    names = sorted(handles)
    return _finish(fig, axes, path, [handles[k] for k in names], names)


def plot_time(sizes: pd.DataFrame, path: Path, styles: dict,
              order: Optional[Sequence[str]] = None) -> Optional[Path]:
    """Median build time against n, log-log, with a band from the fastest to the slowest repeat."""
    band = ("time_min_s", "time_max_s") if {"time_min_s", "time_max_s"} <= set(sizes.columns) else None
    return plot_metric_panels(sizes, "time_s", path, "Build time vs n (median; band = fastest to slowest repeat)",
                              "time (s)", styles, band=band, order=order)


def plot_time_per_nlogn(sizes: pd.DataFrame, path: Path, styles: dict,
                        order: Optional[Sequence[str]] = None) -> Optional[Path]:
    """Time divided by n log2 n: flat for an O(n log n) method, rising for anything worse."""
    return plot_metric_panels(sizes, "ns_per_nlogn", path, "Time / (n log2 n): flat = O(n log n)",
                              "ns per n·log2(n)", styles, order=order)


def plot_ratio(ratios: pd.DataFrame, reference: str, path: Path, styles: dict,
               order: Optional[Sequence[str]] = None) -> Optional[Path]:
    """Time relative to the reference: 1 = as fast, below = faster."""
    return plot_metric_panels(ratios, "ratio", path,
                              f"Speed relative to {reference}: time / time({reference}), below 1 = faster",
                              f"time / time({reference})", styles, hline=1.0, order=order)


#: A build's memory rise below this is allocator and page noise, not its own need: such
#: points are not drawn (the report says how many were left out).
MEMORY_RESOLUTION_MB = 1.0


def plot_memory(sizes: pd.DataFrame, path: Path, styles: dict,
                order: Optional[Sequence[str]] = None) -> Optional[Path]:
    """Peak memory of the build itself (rise of the worker's resident peak during the build)."""
    measurable = sizes[sizes["mem_mb"] >= MEMORY_RESOLUTION_MB] if not sizes.empty else sizes
    return plot_metric_panels(measurable, "mem_mb", path,
                              f"Peak memory of the build (rise above the worker's resident size; below "
                              f"{MEMORY_RESOLUTION_MB:g} MiB not measurable, not drawn)",
                              "peak memory (MiB)", styles, positive_only=True, order=order)


def plot_correctness(matrix: pd.DataFrame, path: Path, order: Optional[Sequence[str]] = None) -> Optional[Path]:
    """Implementation x dataset grid coloured by the worst verdict, with good/checked counts;
    None, and no file, when the matrix is empty."""
    if matrix.empty:
        return None
    impls = sorted(matrix["impl"].unique())
    present = set(matrix["dataset"])
    datasets = [d for d in (order or sorted(present)) if d in present]
    datasets += sorted(present - set(datasets))
    fig, ax = plt.subplots(figsize=(1.25 * max(3, len(datasets)) + 2.4, 0.62 * max(2, len(impls)) + 2.2),
                           layout="constrained")
    rgba = np.ones((len(impls), len(datasets), 4))
    seen = {(r["impl"], r["dataset"]) for _, r in matrix.iterrows()}
    for i, impl in enumerate(impls):
        for j, dataset in enumerate(datasets):
            if (impl, dataset) not in seen:
                ax.text(j, i, "not run", ha="center", va="center", fontsize=8, color="0.5")
    for _, r in matrix.iterrows():
        i, j = impls.index(r["impl"]), datasets.index(r["dataset"])
        colour = verdict_colour(r["worst"])
        rgba[i, j] = to_rgba(colour)
        counts = f"{r['good']}/{r['checked']} good" if r["checked"] else f"{r['cases']} case(s)"
        ax.text(j, i, f"{verdict_label(r['worst'])}\n{counts}", ha="center", va="center", fontsize=8,
                color=text_colour(colour))
    ax.imshow(rgba, aspect="auto")
    ax.set_xticks(range(len(datasets)), datasets, rotation=30, ha="right")
    ax.set_yticks(range(len(impls)), impls)
    ax.set_xticks(np.arange(-0.5, len(datasets), 1), minor=True)
    ax.set_yticks(np.arange(-0.5, len(impls), 1), minor=True)
    ax.grid(which="minor", color="white", linewidth=2)
    ax.tick_params(which="minor", length=0)
    ax.set_xlabel("dataset")
    ax.set_ylabel("implementation")
    ax.set_title("Correctness: worst verdict over sizes and seeds\n(k/m good = passed the cross-validation, of checked)",
                 fontsize=11)
    worst = set(matrix["worst"].astype(str))
    shown = [v for v in VERDICT_COLOURS if v in worst] + sorted(worst - set(VERDICT_COLOURS))
    ax.legend(handles=[Patch(facecolor=verdict_colour(v), edgecolor="0.5", label=verdict_label(v)) for v in shown],
              loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, frameon=False)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
