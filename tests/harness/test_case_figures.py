"""The report draws the power diagram of its run's smallest weighted case and the diagram of its
smallest case of disks, and nothing when the run has none."""

from __future__ import annotations

import pandas as pd

import datasets_gen
import impls
from vorobench.harness.case_figures import MAX_DRAWN_DISKS, plot_disk_case, plot_power_case


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


def _disk_rows(radii: list[str], sizes: tuple[int, ...] = (300, 40, 60)) -> pd.DataFrame:
    return pd.DataFrame({"impl": "fortune", "dataset": ["uniform", "uniform", "grid"], "weights": "",
                         "radii": radii, "n": list(sizes), "seed": [1, 4, 0]})


def test_the_smallest_case_of_disks_is_drawn_with_its_hidden_count(tmp_path):
    drawn = plot_disk_case(_disk_rows(["random", "nested", ""]), tmp_path / "d.png", "qhull")
    assert drawn is not None
    path, caption = drawn
    assert path.stat().st_size > 10_000
    # the hidden set told by the oracle, not by the sweep that drew it
    points = datasets_gen.generate("uniform", 40, seed=4)
    d = impls.build("halfplane", points, radii=datasets_gen.radii("nested", points, seed=4))
    assert d.hidden.size > 0 and f"{d.hidden.size} of {d.n_sites} disks hidden" in caption
    assert caption.startswith("uniform, n = 40, seed 4, nested radii, built by fortune")


def test_no_case_of_disks_or_only_large_ones_no_picture(tmp_path):
    assert plot_disk_case(_disk_rows(["", "", ""]), tmp_path / "d.png", "qhull") is None
    assert plot_disk_case(_disk_rows(["", "", ""]).drop(columns="radii"), tmp_path / "d.png", "qhull") is None
    too_many = MAX_DRAWN_DISKS + 1
    assert plot_disk_case(_disk_rows(["random"] * 3, (too_many,) * 3), tmp_path / "d.png", "qhull") is None
    assert not (tmp_path / "d.png").exists()
