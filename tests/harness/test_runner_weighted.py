"""`bench --weights`: weighted cases are timed by the implementations that take weights, recorded
as unsupported for the others, carry their weight family in the results, and stay apart from
ordinary cases in resume, compare and report."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import pytest

import impls
from vorobench.cli import main
from vorobench.harness import regress, results
from vorobench.harness.runner import Case, plan_cases
from vorobench.harness.repeat_check import reference_result

DOUBLES = str(Path(__file__).resolve().parents[1] / "support" / "doubles.py")
WEIGHTED = "qhull"


def _bench(out: Path, *extra: str) -> int:
    return main(["bench", "--plugin", DOUBLES, "--datasets", "uniform", "--sizes", "40", "--repeat", "1",
                 "--min-time", "0", "--quiet", "--out", str(out), *extra])


#: A weighted implementation checked against the reference: CGAL's regular triangulation.
PEER = "cgal"


def _peer() -> list[str]:
    return [PEER] if PEER in impls.available() and impls.get(PEER).weighted else []


@pytest.fixture(scope="module")
def weighted_run(tmp_path_factory) -> tuple[Path, pd.DataFrame]:
    """A tiny weighted run: qhull (weighted, the reference), CGAL when installed, and `steady`,
    a test double without weights."""
    if not impls.get(WEIGHTED).weighted:
        pytest.skip(f"{WEIGHTED} does not take weights yet")
    out = tmp_path_factory.mktemp("weighted") / "run.csv"
    assert _bench(out, "--impls", ",".join(["steady", *_peer(), WEIGHTED]), "--weights", "radii") == 0
    return out, pd.read_csv(out)


def test_unweighted_implementation_is_unsupported_and_weighted_ones_ok(weighted_run):
    _, df = weighted_run
    steady = df[df["impl"] == "steady"]
    assert len(steady) == 1
    row = steady.iloc[0]
    assert row["status"] == "unsupported" and row["verdict"] == "unsupported"
    assert "does not take weights" in row["error"] and pd.isna(row["time_s"])
    qhull = df[df["impl"] == WEIGHTED].iloc[0]
    assert qhull["status"] == "ok" and qhull["time_s"] > 0 and qhull["verdict"] == "certified"
    for peer in _peer():          # judged against the reference's power diagram
        row = df[df["impl"] == peer].iloc[0]
        assert row["status"] == "ok" and bool(row["check_passed"]), row["verdict_detail"]
        assert row["verdict"] in ("exact", "within_tolerance")


def test_rows_carry_the_weight_family(weighted_run):
    out, df = weighted_run
    assert list(df.columns[:6]) == ["run_id", "impl", "dataset", "weights", "radii", "n"]
    assert (df["weights"] == "radii").all()
    assert results.read_metadata(out)["runs"][-1]["weights"] == "radii"


def test_an_ordinary_run_resumed_into_the_file_runs_its_own_cases(weighted_run, tmp_path):
    # Same impl, dataset, n and seed: only the weight family tells the cases apart.
    out = tmp_path / "run.csv"
    out.write_bytes(weighted_run[0].read_bytes())
    assert _bench(out, "--impls", "steady", "--resume", "--no-check") == 0
    df = results.load(out)
    steady = df[df["impl"] == "steady"]
    assert sorted(steady["weights"]) == ["", "radii"]
    assert steady.loc[steady["weights"] == "", "status"].tolist() == ["ok"]
    assert len({results.case_key(r) for r in steady.to_dict("records")}) == 2


def test_a_bench_refuses_a_reference_without_weights(tmp_path, capsys):
    code = _bench(tmp_path / "r.csv", "--impls", "steady", "--weights", "equal", "--reference", "steady")
    assert code == 2
    assert "reference steady does not take weights" in capsys.readouterr().err


def test_an_unknown_weight_family_is_one_line(tmp_path, capsys):
    with pytest.raises(SystemExit) as stop:
        _bench(tmp_path / "r.csv", "--weights", "heavy")
    assert stop.value.code == 2
    assert "unknown weight family 'heavy'; available: radii" in capsys.readouterr().err


def test_cases_and_reference_builds_keep_the_family_apart(tmp_path):
    plain, weighted = Case("qhull", "uniform", 10, 0), Case("qhull", "uniform", 10, 0, "radii")
    assert plain.key != weighted.key and plain.history_key != weighted.history_key
    assert "weights=radii" in str(weighted) and "weights" not in str(plain)
    assert {c.weights for c in plan_cases(["qhull"], ["uniform"], [10], [0], weights="hidden")} == {"hidden"}
    from vorobench.judge.engine import BuildResult

    built = []

    def build(tag):
        built.append(tag)
        return BuildResult("qhull", False, unsupported=tag)
    # the reference's builds are kept by case input, weight family included: no ordinary build serves a weighted case
    assert reference_result(("qhull", "uniform", 10, 0, ""), lambda: build("plain")).unsupported == "plain"
    assert reference_result(("qhull", "uniform", 10, 0, "radii"), lambda: build("radii")).unsupported == "radii"
    assert reference_result(("qhull", "uniform", 10, 0, ""), lambda: build("again")).unsupported == "plain"
    assert built == ["plain", "radii"]


def _rows(weights: str, time_s: float) -> list[dict]:
    return [{"run_id": "r", "impl": "qhull", "dataset": "uniform", "weights": weights, "n": 100, "seed": 0,
             "repeat": i, "status": "ok", "verdict": "certified", "time_s": time_s} for i in range(5)]


def test_compare_never_matches_a_weighted_case_with_an_ordinary_one():
    base = results.normalise(pd.DataFrame(_rows("", 0.01)))
    new = results.normalise(pd.DataFrame(_rows("radii", 0.01)))
    changes = regress.compare_frames(base, new)
    names = sorted(c.name for c in changes)
    assert names == ["qhull uniform (radii weights) n=100 seed=0", "qhull uniform n=100 seed=0"]
    missing = [c for c in changes if "missing in NEW" in c.flags]
    assert [c.dataset for c in missing] == ["uniform"]


def test_files_without_the_column_read_as_ordinary(tmp_path):
    old = tmp_path / "old.csv"
    frame = pd.DataFrame(_rows("", 0.01)).drop(columns=["weights"])
    frame.to_csv(old, index=False)
    df = results.load_checked(old)
    assert (df["weights"] == "").all()
    assert results.case_key(df.iloc[0].to_dict()) == ("qhull", "uniform", 100, 0)
    assert set(results.with_families_in_dataset(df)["dataset"]) == {"uniform"}
    # The same rows read back from a file written with the column compare as the same cases.
    new = results.normalise(pd.DataFrame(_rows("", 0.01)))
    assert all(not c.flags for c in regress.compare_frames(df, new))


def test_the_report_names_weighted_datasets(weighted_run, tmp_path):
    from vorobench.harness.report import write_report

    report = write_report(weighted_run[0], tmp_path / "report")
    text = report.markdown.read_text()
    assert "uniform (radii weights)" in text
