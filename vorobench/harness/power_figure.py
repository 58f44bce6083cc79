"""The power diagram of a run's smallest weighted case, drawn with its hidden sites marked,
for the report: the run's own points and weights, generated again from their seeds."""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import pandas as pd

import datasets_gen
import impls

__all__ = ["plot_power_case", "MAX_DRAWN_SITES"]

#: Larger cases are not drawn: their cells would be too small to see.
MAX_DRAWN_SITES = 2000


def _smallest_weighted_case(df: pd.DataFrame) -> Optional[tuple[str, str, int, int]]:
    """(dataset, weight family, n, seed) of the smallest weighted case drawable here."""
    if "weights" not in df.columns:
        return None
    rows = df[df["weights"].fillna("").astype(str) != ""]
    rows = rows[(rows["n"] <= MAX_DRAWN_SITES) & rows["dataset"].isin(datasets_gen.available())]
    if rows.empty:
        return None
    first = rows.sort_values(["n", "dataset", "seed"]).iloc[0]
    return str(first["dataset"]), str(first["weights"]), int(first["n"]), int(first["seed"])


def plot_power_case(df: pd.DataFrame, path: Path, reference: str) -> Optional[tuple[Path, str]]:
    """Draw the smallest weighted case of ``df`` (built by ``reference`` if it takes weights,
    else by the first weighted implementation) into ``path``; returns (path, caption), or
    None when the run has no weighted case that can be generated again here."""
    case = _smallest_weighted_case(df)
    if case is None:
        return None
    names = impls.weighted()
    if not names:
        return None
    builder = reference if reference in names else names[0]
    dataset, family, n, seed = case
    try:
        points = datasets_gen.generate(dataset, n, seed=seed)
        weights = datasets_gen.weights(family, points, seed=seed)
        diagram = impls.build(builder, points, weights=weights)
    except Exception:  # a case that cannot be built again here is simply not drawn
        return None
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 7))
    caption = (f"{dataset}, n = {n}, seed {seed}, {family} weights, built by {builder}: "
               f"{diagram.hidden.size} of {diagram.n_sites} sites hidden")
    diagram.plot(ax=ax, title=caption)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)
    return path, caption
