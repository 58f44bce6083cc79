"""`vorobench compare` with power and honesty: a uniform slowdown too small for any one case's
repeats is caught over all cases, same-code runs pass, powerless cases are called inconclusive,
timings never gate as counters, and the verdicts reach CI as JUnit and Markdown."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import numpy as np
import pandas as pd
import pytest

from vorobench.cli import main
from vorobench.harness import regress

SIZES = (1000, 2000, 5000, 10000, 20000, 50000)
IMPLS = ("a", "b")


def _run(rng, factor=1.0, repeats=3, noise=0.15, extra=None, run_noise=0.0) -> pd.DataFrame:
    """12 cases whose repeats scatter by `noise` (log-normal) around a per-case time x factor;
    `run_noise` moves all repeats of a case together (the background of one run on a shared machine)."""
    rows = []
    for impl in IMPLS:
        for n in SIZES:
            base_time = 1e-6 * n * (2 if impl == "b" else 1) * np.exp(run_noise * rng.standard_normal())
            for i, t in enumerate(base_time * factor * np.exp(noise * rng.standard_normal(repeats))):
                row = {"run_id": "r", "impl": impl, "dataset": "uniform", "n": n, "seed": 0, "repeat": i,
                       "status": "ok", "verdict": "exact", "time_s": t, "stat_events": n // 10}
                row.update(extra(rng) if extra else {})
                rows.append(row)
    return pd.DataFrame(rows)


def _write(df: pd.DataFrame, path) -> str:
    df.to_csv(path, index=False)
    return str(path)


def test_a_uniform_25_percent_slowdown_is_caught_at_3_repeats(tmp_path, capsys):
    rng = np.random.default_rng(7)
    base, slow = _run(rng), _run(rng, factor=1.25)
    comparison = regress.compare_runs(base, slow)
    # no single case can show it with 3 noisy repeats, all of them together do
    assert not any(c.change == "slower" for c in comparison.changes)
    assert comparison.overall.change == "slower" and 1.1 < comparison.overall.geomean < 1.45
    assert comparison.overall.ci_low > 1.0
    code = main(["compare", _write(base, tmp_path / "base.csv"), _write(slow, tmp_path / "slow.csv")])
    out = capsys.readouterr().out
    assert code == 1 and "all 12 timed cases together" in out and "slower" in out


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_two_runs_of_the_same_code_raise_no_flag(tmp_path, capsys, seed):
    rng = np.random.default_rng(seed)
    base, same = _run(rng, repeats=5), _run(rng, repeats=5)
    code = main(["compare", _write(base, tmp_path / "a.csv"), _write(same, tmp_path / "b.csv")])
    assert code == 0, capsys.readouterr().out


def test_run_to_run_noise_that_the_repeats_do_not_show_raises_no_flag(tmp_path, capsys):
    # each case's repeats agree within 1 %, but a case moves by ~20 % from one run to the next
    rng = np.random.default_rng(11)
    base, same = _run(rng, repeats=9, noise=0.01, run_noise=0.2), _run(rng, repeats=9, noise=0.01, run_noise=0.2)
    comparison = regress.compare_runs(base, same)
    assert 0.3 < comparison.noise < 1.2 and comparison.passed
    assert any("noise band" in c.why_inconclusive for c in comparison.changes)
    # without the band, the repeats alone would have flagged cases
    raw = [c for c in comparison.changes if c.ratio > 1.1 and c.p_value is not None and c.p_value < 0.05]
    assert raw
    # a real slowdown far outside the band is still caught on its own
    slow = same.copy()
    slow.loc[(slow["impl"] == "a") & (slow["n"] == 2000), "time_s"] *= 4.0
    flagged = regress.compare_runs(base, slow).flagged
    assert [c.name for c in flagged] == ["a uniform n=2000 seed=0"]


def test_cases_whose_repeats_cannot_decide_are_inconclusive_not_passed(tmp_path, capsys):
    rng = np.random.default_rng(4)
    base, new = _run(rng, repeats=3), _run(rng, repeats=3)
    comparison = regress.compare_runs(base, new)
    assert all(c.change == "inconclusive" for c in comparison.changes)
    assert "cannot reach p < 0.05" in comparison.changes[0].why_inconclusive
    main(["compare", _write(base, tmp_path / "a.csv"), _write(new, tmp_path / "b.csv")])
    assert "12 case(s) inconclusive" in capsys.readouterr().out
    # with enough quiet repeats the same question has an answer
    rng = np.random.default_rng(4)
    quiet = regress.compare_runs(_run(rng, repeats=9, noise=0.01), _run(rng, repeats=9, noise=0.01))
    assert all(c.change == "same" for c in quiet.changes) and quiet.overall.change == "same"


def test_timings_of_library_parts_never_gate_as_counters():
    rng = np.random.default_rng(5)

    def parts(r):
        return {"time_library_s": float(r.random()), "time_convert_s": float(r.random())}

    comparison = regress.compare_runs(_run(rng, repeats=5, noise=0.01, extra=parts),
                                      _run(rng, repeats=5, noise=0.01, extra=parts))
    assert comparison.passed and not any(c.counters for c in comparison.changes)


def test_old_files_with_seconds_among_counters_do_not_raise_false_alarms(tmp_path):
    rng = np.random.default_rng(6)

    def legacy(r):
        return {"stat_library_s": float(r.random()), "stat_convert_s": float(r.random())}

    a = _write(_run(rng, repeats=5, noise=0.01, extra=legacy), tmp_path / "a.csv")
    b = _write(_run(rng, repeats=5, noise=0.01, extra=legacy), tmp_path / "b.csv")
    assert main(["compare", a, b]) == 0


def test_junit_and_markdown_list_every_case(tmp_path):
    rng = np.random.default_rng(8)
    base = _run(rng, repeats=5, noise=0.01)
    new = _run(rng, repeats=5, noise=0.01)
    new.loc[(new["impl"] == "a") & (new["n"] == 1000), "time_s"] *= 2.0          # one clear regression
    new.loc[(new["impl"] == "b") & (new["n"] == 5000), "stat_events"] += 1        # one counter change
    junit, md = tmp_path / "out" / "compare.xml", tmp_path / "out" / "compare.md"
    code = main(["compare", _write(base, tmp_path / "a.csv"), _write(new, tmp_path / "b.csv"),
                 "--junit", str(junit), "--markdown", str(md)])
    assert code == 1
    suite = ET.parse(junit).getroot().find("testsuite")
    cases = suite.findall("testcase")
    assert len(cases) == 13 and suite.get("tests") == "13"                      # 12 cases + all together
    failed = {c.get("name") for c in cases if c.find("failure") is not None}
    assert failed == {"a uniform n=1000 seed=0", "b uniform n=5000 seed=0"}
    assert suite.get("failures") == "2"
    text = md.read_text()
    assert text.startswith("## vorobench compare: REGRESSION")
    for impl in IMPLS:
        for n in SIZES:
            assert f"{impl} uniform n={n} seed=0" in text
    assert "counters changed: events 500 -\\> 501" in text          # Markdown-escaped arrow


def test_a_pytest_benchmark_file_is_refused_in_one_line(tmp_path, capsys):
    pb = tmp_path / "pb.json"
    pb.write_text(json.dumps({"machine_info": {}, "commit_info": {}, "benchmarks": [{"name": "x", "stats": {}}]}))
    base = _write(_run(np.random.default_rng(0)), tmp_path / "a.csv")
    assert main(["compare", str(pb), base]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "pytest-benchmark file" in err
    other = tmp_path / "other.json"
    other.write_text("[1, 2]")
    assert main(["compare", base, str(other)]) == 2
    assert "JSON file, not a vorobench results table" in capsys.readouterr().err


def test_a_case_that_varies_between_runs_is_judged_by_its_own_history():
    # case (a, n=50000) swings by ~40 % from run to run, the others by ~2 %: its 1.5x in NEW is
    # noise that the earlier runs show, while the same 1.5x on a steady case is a regression
    rng = np.random.default_rng(12)

    def run(run_id, swing, steady_factor=1.0):
        df = _run(rng, repeats=7, noise=0.01, run_noise=0.02).assign(run_id=run_id)
        swinging = (df["impl"] == "a") & (df["n"] == 50000)
        df.loc[swinging, "time_s"] *= swing
        df.loc[(df["impl"] == "b") & (df["n"] == 1000), "time_s"] *= steady_factor
        return df

    history = pd.concat([run(f"h{i}", s) for i, s in enumerate([1.0, 1.45, 0.7, 1.2])])
    base, new = run("base", 1.0), run("new", 1.5, steady_factor=1.5)
    without = {c.name for c in regress.compare_runs(base, new).flagged}
    assert without == {"a uniform n=50000 seed=0", "b uniform n=1000 seed=0"}
    comparison = regress.compare_runs(base, new, history=history)
    assert {c.name for c in comparison.flagged} == {"b uniform n=1000 seed=0"}
    swinging = next(c for c in comparison.changes if c.name == "a uniform n=50000 seed=0")
    assert swinging.change == "inconclusive" and "over 4 earlier runs" in swinging.why_inconclusive
