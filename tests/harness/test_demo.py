"""`vorobench demo`: benchmark + cross-validation + report in one folder (tiny sizes here)."""

from __future__ import annotations

import pandas as pd

from vorobench.cli import main
from vorobench.harness.demo import demo_sizes, own_implementations


def test_own_implementations_leave_out_adapters_and_plugins():
    import impls

    own = own_implementations()
    assert "qhull" in own
    for name in own:
        assert impls.get(name).build.__module__.startswith("impls.")
        assert not impls.get(name).build.__module__.startswith("impls.external")


def test_sizes_grow_when_qhull_is_alone():
    assert max(demo_sizes(1)) > max(demo_sizes(4))


def test_demo_writes_results_and_report(tmp_path, capsys):
    out = tmp_path / "demo"
    code = main(["demo", "--impls", "qhull", "--datasets", "grid", "--sizes", "40,90", "--repeat", "1",
                 "--min-time", "0", "--out", str(out), "--quiet"])
    assert code == 0
    df = pd.read_csv(out / "results.csv")
    assert sorted(set(zip(df["dataset"], df["n"]))) == [("grid", 40), ("grid", 90)]
    assert sorted(set(df["n_sites"])) == [49, 100]                 # grids round n up to a square
    assert (df["status"] == "ok").all() and (df["verdict"] == "certified").all()
    assert (out / "README.md").exists() and (out / "report.html").exists()
    assert not (out / ".reference").exists()           # the cached reference diagrams are cleaned up
    assert str(out / "README.md") in capsys.readouterr().out


def test_demo_adds_installed_outside_references():
    import impls
    from vorobench.harness.demo import DEMO_REFERENCES, demo_implementations

    names = demo_implementations()
    assert names[: len(own_implementations())] == own_implementations()
    expected = [n for n in DEMO_REFERENCES if n in impls.available()]
    assert names[len(own_implementations()):] == expected


def test_demo_shows_the_sizes_it_runs_and_every_case_it_does_not(tmp_path, capsys):
    """cocircular stops at 6,144 points: n=7000 runs 6144 and n=8000 is the same set; a case
    the budget skips is listed with its reason."""
    code = main(["demo", "--impls", "halfplane,qhull", "--datasets", "cocircular,uniform", "--sizes", "60,7000,8000",
                 "--repeat", "1", "--min-time", "0", "--budget", "0.0001", "--out", str(tmp_path / "d"),
                 "--quiet"])
    assert code == 0
    err = " ".join(capsys.readouterr().err.split())          # the console wraps long lines
    assert "cocircular: n=7000 runs 6144 points; not run: n=8000 (the same 6144 points as n=7000)" in err
    assert "halfplane on uniform n=7000: skipped: extrapolated build time" in err
    assert "case(s) not run" in err


def test_the_default_demo_is_the_quick_matrix_and_full_the_big_one():
    from vorobench.harness.demo import DEMO_DATASETS, FULL_DATASETS

    assert set(DEMO_DATASETS) < set(FULL_DATASETS)
    assert max(demo_sizes(4)) < max(demo_sizes(4, full=True))
