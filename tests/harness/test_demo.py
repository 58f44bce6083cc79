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
