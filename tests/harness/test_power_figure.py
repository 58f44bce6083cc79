"""The report draws the power diagram of its run's smallest weighted case, and nothing when
the run has none."""

from __future__ import annotations

import pandas as pd

import datasets_gen
import impls
from vorobench.harness.power_figure import plot_power_case


def _rows(weights: list[str]) -> pd.DataFrame:
    return pd.DataFrame({"impl": "qhull", "dataset": ["uniform", "uniform", "grid"], "weights": weights,
                         "n": [400, 120, 100], "seed": [1, 3, 0]})


def test_the_smallest_weighted_case_is_drawn_with_its_hidden_count(tmp_path):
    drawn = plot_power_case(_rows(["radii", "radii", ""]), tmp_path / "p.png", "qhull")
    assert drawn is not None
    path, caption = drawn
    assert path.stat().st_size > 10_000
    points = datasets_gen.generate("uniform", 120, seed=3)
    d = impls.build("qhull", points, weights=datasets_gen.weights("radii", points, seed=3))
    assert d.hidden.size > 0 and f"{d.hidden.size} of 120 sites hidden" in caption
    assert caption.startswith("uniform, n = 120, seed 3, radii weights")


def test_no_weighted_case_no_picture(tmp_path):
    assert plot_power_case(_rows(["", "", ""]), tmp_path / "p.png", "qhull") is None
    assert plot_power_case(_rows(["", "", ""]).drop(columns="weights"), tmp_path / "p.png", "qhull") is None
    assert not (tmp_path / "p.png").exists()
