"""`bench --radii`: cases of disks are timed by the implementations that take disks and recorded
as unsupported for the others; every repeat is judged, in the judge's process, as the diagram of
exactly the case's disks (the faults of ``tests/support/hostile/disk_bench_faults.py`` fail);
rows carry the radius family and stay apart from ordinary and weighted cases."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

from vorobench.cli import main
from vorobench.harness import results
from vorobench.harness.runner import Case, plan_cases

FAULTS = str(Path(__file__).resolve().parents[1] / "support" / "hostile" / "disk_bench_faults.py")
REFERENCE = "halfplane"
DOUBLES = ("centres_for_disks", "wrong_after_first", "radii_forger")


def _bench(out: Path, *extra: str) -> int:
    return main(["bench", "--plugin", FAULTS, "--datasets", "uniform", "--min-time", "0", "--quiet",
                 "--out", str(out), *extra])


def test_cases_of_disks_have_keys_of_their_own():
    plain, weighted = Case("fortune", "uniform", 10), Case("fortune", "uniform", 10, weights="radii")
    disks = Case("fortune", "uniform", 10, radii="random")
    assert len({plain.key, weighted.key, disks.key}) == 3
    assert len({plain.history_key, weighted.history_key, disks.history_key}) == 3
    assert disks.key[1] == "uniform (random radii)" and weighted.key[1] == "uniform (radii weights)"
    assert "radii=random" in str(disks) and "weights" not in str(disks)
    row = {"impl": "fortune", "dataset": "uniform", "weights": "", "radii": "random", "n": "10", "seed": "0"}
    assert results.case_key(row) == disks.key                     # a row read back names the same case


def test_a_case_has_weights_or_radii_never_both():
    with pytest.raises(ValueError, match="one at a time"):
        Case("fortune", "uniform", 10, weights="radii", radii="random")
    with pytest.raises(ValueError, match="one at a time"):
        plan_cases(["fortune"], ["uniform"], [10], [0], weights="radii", radii="random")
    planned = plan_cases(["fortune", "halfplane"], ["uniform"], [10, 20], [0], radii="tangent")
    assert len(planned) == 4 and {(c.radii, c.weights) for c in planned} == {("tangent", "")}


@pytest.fixture(scope="module")
def disk_run(tmp_path_factory) -> tuple[Path, pd.DataFrame]:
    """Random disks at n = 20 and 50: fortune and halfplane (the reference) take disks,
    incremental does not, and the three faulty constructions of disks."""
    out = tmp_path_factory.mktemp("disks") / "run.csv"
    names = ",".join(["fortune", "incremental", *DOUBLES, REFERENCE])
    assert _bench(out, "--impls", names, "--reference", REFERENCE, "--sizes", "20,50", "--repeat", "3",
                  "--radii", "random") == 0
    return out, pd.read_csv(out)


def _rows(df: pd.DataFrame, impl: str, n: int = 20) -> pd.DataFrame:
    return df[(df["impl"] == impl) & (df["n"] == n)].sort_values("repeat")


def test_implementations_with_disks_pass_and_the_others_are_unsupported(disk_run):
    _, df = disk_run
    for n in (20, 50):
        fortune, halfplane = _rows(df, "fortune", n), _rows(df, REFERENCE, n)
        assert len(fortune) == 3 and (fortune["status"] == "ok").all() and (fortune["time_s"] > 0).all()
        assert (fortune["verdict"] == "exact").all() and fortune["check_passed"].all(), fortune["verdict_detail"]
        assert (halfplane["verdict"] == "certified").all() and halfplane["check_passed"].all()
        assert (fortune["certificate"] == "certified").all()          # the exact certificate of disks
        plain = _rows(df, "incremental", n)
        assert len(plain) == 1
        row = plain.iloc[0]
        assert row["status"] == "unsupported" and row["verdict"] == "unsupported" and pd.isna(row["time_s"])
        assert "does not take disks" in row["error"]


def test_rows_carry_the_radius_family(disk_run):
    out, df = disk_run
    assert list(df.columns[:6]) == ["run_id", "impl", "dataset", "weights", "radii", "n"]
    assert (df["radii"] == "random").all() and df["weights"].isna().all()
    assert results.read_metadata(out)["runs"][-1]["radii"] == "random"
    assert {results.case_key(r)[1] for r in df.to_dict("records")} == {"uniform (random radii)"}


def test_the_centres_diagram_with_the_radii_attached_fails_every_repeat(disk_run):
    rows = _rows(disk_run[1], "centres_for_disks")
    assert len(rows) == 3 and (rows["verdict"] == "not_certified").all()
    assert not rows["check_passed"].any()


def test_a_diagram_sent_with_other_radii_is_wrong_sites(disk_run):
    rows = _rows(disk_run[1], "radii_forger")
    assert len(rows) == 3 and (rows["verdict"] == "wrong_sites").all()
    assert not rows["check_passed"].any()
    assert rows["verdict_detail"].str.contains("other radii").all()


def test_a_build_wrong_after_its_first_repeat_fails_on_the_later_ones(disk_run):
    rows = _rows(disk_run[1], "wrong_after_first")
    assert list(rows["verdict"]) == ["exact", "not_certified", "not_certified"], rows[["repeat", "verdict"]]
    assert list(rows["check_passed"]) == [True, False, False]
    assert rows["verdict_detail"].iloc[1].startswith("repeat 1 differs from repeat 0")


def test_a_resumed_ordinary_run_adds_its_own_cases(disk_run, tmp_path):
    # Same impl, dataset, n and seed: only the radius family tells the cases apart.
    out = tmp_path / "run.csv"
    out.write_bytes(disk_run[0].read_bytes())
    assert _bench(out, "--impls", "halfplane", "--sizes", "20", "--repeat", "1", "--resume", "--no-check") == 0
    df = results.load(out)
    mine = df[(df["impl"] == "halfplane") & (df["n"] == 20)]
    assert sorted(set(mine["radii"])) == ["", "random"]
    assert mine.loc[mine["radii"] == "", "status"].tolist() == ["ok"]


def test_the_report_names_the_datasets_of_disks(disk_run, tmp_path):
    from vorobench.harness.report import write_report

    report = write_report(disk_run[0], tmp_path / "report")
    assert "uniform (random radii)" in report.markdown.read_text()


def test_weights_with_radii_are_refused(tmp_path, capsys):
    code = _bench(tmp_path / "r.csv", "--impls", "halfplane", "--reference", "halfplane", "--sizes", "10",
                  "--weights", "equal", "--radii", "equal")
    assert code == 2 and "one at a time" in capsys.readouterr().err
    assert not (tmp_path / "r.csv").exists()


def test_a_reference_without_disks_is_refused_naming_those_with_them(tmp_path, capsys):
    code = _bench(tmp_path / "r.csv", "--impls", "incremental", "--reference", "incremental", "--sizes", "10",
                  "--radii", "random")
    err = capsys.readouterr().err
    assert code == 2 and "reference incremental does not take disks" in err
    takers = err.split("--reference (")[1].split(")")[0].split(", ")
    assert {"fortune", "halfplane"} <= set(takers) and "incremental" not in takers
    # without the check, any reference will do: the case is unsupported, not refused
    assert _bench(tmp_path / "r.csv", "--impls", "incremental", "--reference", "incremental", "--sizes", "10",
                  "--radii", "random", "--no-check") == 0
    assert results.load(tmp_path / "r.csv")["status"].tolist() == ["unsupported"]
