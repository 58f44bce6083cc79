"""Cases of disks (``radii`` column) are cases of their own in compare, in ratios to the reference
and in CI outputs; files written before the column read as cases of points."""

from __future__ import annotations

import pandas as pd

from vorobench.harness import regress, results
from vorobench.harness.ci_outputs import write_markdown


def _rows(weights: str, radii: str, time_s: float, impl: str = "qhull") -> list[dict]:
    return [{"run_id": "r", "impl": impl, "dataset": "uniform", "weights": weights, "radii": radii, "n": 100,
             "seed": 0, "repeat": i, "status": "ok", "verdict": "certified", "time_s": time_s} for i in range(5)]


def test_compare_never_matches_a_case_of_disks_with_an_ordinary_or_weighted_one():
    base = results.normalise(pd.DataFrame(_rows("", "", 0.01) + _rows("radii", "", 0.01)))
    new = results.normalise(pd.DataFrame(_rows("", "random", 0.01)))
    changes = regress.compare_frames(base, new)
    assert sorted(c.name for c in changes) == ["qhull uniform (radii weights) n=100 seed=0",
                                               "qhull uniform (random radii) n=100 seed=0",
                                               "qhull uniform n=100 seed=0"]
    missing = sorted(c.dataset for c in changes if "missing in NEW" in c.flags)
    assert missing == ["uniform", "uniform (radii weights)"]


def test_files_without_the_radii_column_read_as_points(tmp_path):
    old = tmp_path / "old.csv"
    pd.DataFrame(_rows("", "", 0.01)).drop(columns=["radii"]).to_csv(old, index=False)
    df = results.load_checked(old)
    assert (df["radii"] == "").all()
    assert results.case_key(df.iloc[0].to_dict()) == ("qhull", "uniform", 100, 0)
    assert set(results.with_families_in_dataset(df)["dataset"]) == {"uniform"}
    # the same rows from a file written with the column are the same cases, unchanged
    new = results.normalise(pd.DataFrame(_rows("", "", 0.01)))
    changes = regress.compare_frames(df, new)
    assert len(changes) == 1 and not changes[0].flags


def test_ratios_to_the_reference_pair_a_case_of_disks_with_its_own_reference_time():
    # points: the reference 1 s, qhull 2 s; disks: the reference 10 s, qhull 10 s
    df = results.normalise(pd.DataFrame(_rows("", "", 1.0, "ref") + _rows("", "", 2.0)
                                        + _rows("", "random", 10.0, "ref") + _rows("", "random", 10.0)))
    ratios = regress.relative_to(df, "ref").groupby("radii")["time_s"].median()
    assert ratios.to_dict() == {"": 2.0, "random": 1.0}


def test_ci_outputs_name_the_radius_family(tmp_path):
    summary = {"results": [{"impl": "fortune", "exact_peer": None, "dataset": "uniform", "weights": "",
                            "radii": "random", "n": 12, "seed": 0, "verdict": "differs", "passed": False,
                            "message": "x"}],
               "reference": "halfplane", "passed": False, "cases": 1, "judged": 1}
    text = write_markdown(summary, tmp_path / "s.md").read_text()
    assert "uniform (random radii) n=12" in text
