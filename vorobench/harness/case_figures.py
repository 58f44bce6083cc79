"""Pictures of a run's smallest weighted case and smallest case of disks, for the report: the
run's own points with their weights or radii, generated again from their seeds and drawn with
their hidden sites marked."""

from __future__ import annotations

from pathlib import Path
from typing import Callable, Optional

import pandas as pd

import datasets_gen
import impls
from vorobench.harness.site_attributes import RADII, WEIGHTS, SiteAttribute

__all__ = ["plot_power_case", "plot_disk_case", "MAX_DRAWN_SITES", "MAX_DRAWN_DISKS"]

#: Larger cases are not drawn: their cells would be too small to see.
MAX_DRAWN_SITES = 2000
#: Disks are built again by a sweep in rationals and drawn along sampled curves: fewer of them.
MAX_DRAWN_DISKS = 500


def _smallest_case(df: pd.DataFrame, column: str, largest: int) -> Optional[tuple[str, str, int, int]]:
    """(dataset, family, n, seed) of the smallest case whose ``column`` (``weights`` or
    ``radii``) names a family, of at most ``largest`` sites, that can be generated here."""
    if column not in df.columns:
        return None
    rows = df[df[column].fillna("").astype(str) != ""]
    rows = rows[(rows["n"] <= largest) & rows["dataset"].isin(datasets_gen.available())]
    if rows.empty:
        return None
    first = rows.sort_values(["n", "dataset", "seed"]).iloc[0]
    return str(first["dataset"]), str(first[column]), int(first["n"]), int(first["seed"])


def _draw_case(df: pd.DataFrame, path: Path, reference: str, attribute: SiteAttribute, largest: int,
               able: list[str], describe: Callable[[object], str]) -> Optional[tuple[Path, str]]:
    """Build the smallest case with ``attribute`` again (by ``reference`` if it is ``able``,
    else the first that is), draw it into ``path``; (path, caption) or None."""
    column = attribute.name
    case = _smallest_case(df, column, largest)
    if case is None or not able:
        return None
    builder = reference if reference in able else able[0]
    dataset, family, n, seed = case
    try:
        points = datasets_gen.generate(dataset, n, seed=seed)
        diagram = impls.build(builder, points, **{column: attribute.draw(family, points, seed)})
    except Exception:  # a case that cannot be built again here is simply not drawn
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 7))
    caption = f"{dataset}, n = {n}, seed {seed}, {family} {column}, built by {builder}: {describe(diagram)}"
    diagram.plot(ax=ax, title=caption)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)
    return path, caption


def plot_power_case(df: pd.DataFrame, path: Path, reference: str) -> Optional[tuple[Path, str]]:
    """Draw the smallest weighted case of ``df`` (built by ``reference`` if it takes weights,
    else by the first weighted implementation) into ``path``; returns (path, caption), or
    None when the run has no weighted case that can be generated again here."""
    return _draw_case(df, path, reference, WEIGHTS, MAX_DRAWN_SITES, impls.weighted(),
                      lambda d: f"{d.hidden.size} of {d.n_sites} sites hidden")


def plot_disk_case(df: pd.DataFrame, path: Path, reference: str) -> Optional[tuple[Path, str]]:
    """Draw the smallest case of disks of ``df`` (its ``radii`` column names the radius family;
    built by ``reference`` if it takes disks, else by the first implementation that does) into
    ``path``; (path, caption), or None when the run has no such case drawable here."""
    return _draw_case(df, path, reference, RADII, MAX_DRAWN_DISKS, impls.apollonius(),
                      lambda d: f"{d.hidden.size} of {d.n_sites} disks hidden")
