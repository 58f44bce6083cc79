"""Report: fitted exponents, ratios, verdict summaries, figures and the Markdown/HTML pages."""

from __future__ import annotations

import math
import re

import numpy as np
import pandas as pd
import pytest

from vorobench.cli import main
from vorobench.harness import analysis, results
from vorobench.judge import outcomes

SIZES = [1000, 4000, 16000, 64000]


def _synthetic_rows() -> list[dict]:
    """Three implementations with known growth: fast ~ n log n, ref ~ 2x fast, slow ~ n^2."""
    rng = np.random.default_rng(7)
    rows = []
    laws = {"fast": lambda n: 5e-8 * n * math.log2(n), "ref": lambda n: 1e-7 * n * math.log2(n),
            "slow": lambda n: 1e-9 * n * n}
    for impl, law in laws.items():
        for dataset in ("uniform", "grid"):
            for n in SIZES:
                verdict = "differs" if (impl == "slow" and dataset == "grid" and n == 4000) else "exact"
                for rep in range(3):
                    rows.append({"run_id": "r1", "impl": impl, "dataset": dataset, "n": n, "seed": 0,
                                 "repeat": rep, "status": "ok", "verdict": verdict,
                                 "time_s": law(n) * (1 + 0.01 * rng.standard_normal()),
                                 "warmup_s": 0.2, "n_sites": n, "mem_mb": 1e-4 * n, "peak_rss_mb": 200.0})
    rows.append({"run_id": "r1", "impl": "crashy", "dataset": "uniform", "n": 1000, "seed": 0,
                 "status": "crashed", "verdict": "crashed", "phase": "repeat 1/3",
                 "error": "worker killed by SIGSEGV"})
    return rows


@pytest.fixture()
def results_csv(tmp_path):
    path = tmp_path / "bench.csv"
    results.ResultsFile(path).append(_synthetic_rows())
    results.append_run_metadata(path, {"run_id": "r1", "reference": "ref", "repeat": 3, "timeout": 60,
                                       "check": True, "hostname": "testhost", "cpu": "Test CPU", "cores": 2})
    return path


def test_fit_recovers_a_power_law():
    sizes = pd.DataFrame({"impl": "x", "dataset": "d", "n": SIZES, "n_sites": SIZES,
                          "time_s": [3e-9 * n ** 1.5 for n in SIZES]})
    fit = analysis.fit_exponents(sizes).iloc[0]
    assert fit["exponent"] == pytest.approx(1.5, abs=1e-9)
    assert fit["r2"] == pytest.approx(1.0, abs=1e-12)
    assert (fit["n_min"], fit["n_max"], fit["points"]) == (1000, 64000, 4)


def test_two_sizes_give_no_r2_and_the_report_says_so():
    """Any line fits two points: R² would read 1.000 and say nothing, so it is not measured."""
    sizes = pd.DataFrame({"impl": "x", "dataset": "d", "n": [1000, 4000], "n_sites": [1000, 4000],
                          "time_s": [1e-3, 5e-3]})
    fit = analysis.fit_exponents(sizes).iloc[0]
    assert fit["points"] == 2 and fit["r2"] != fit["r2"]
    assert analysis.r2_text(fit["r2"]) == "R² n/a: two sizes" and analysis.r2_text(0.98765) == "R² 0.988"


def test_fit_leaves_out_small_sizes_dominated_by_overhead():
    ns = [10, 100] + SIZES
    sizes = pd.DataFrame({"impl": "x", "dataset": "d", "n": ns, "n_sites": ns,
                          "time_s": [0.05 + 0 * n if n < 1000 else 1e-6 * n for n in ns]})
    fit = analysis.fit_exponents(sizes).iloc[0]
    assert fit["n_min"] == 1000 and fit["exponent"] == pytest.approx(1.0)


def test_summaries_of_synthetic_results(results_csv):
    df = results.load(results_csv)
    sizes = analysis.size_table(df)
    exps = analysis.fit_exponents(sizes).set_index(["impl", "dataset"])
    assert exps.loc[("slow", "uniform"), "exponent"] == pytest.approx(2.0, abs=0.02)
    # n log2 n from 1000 to 64000 has a log-log slope of about 1.1
    assert 1.05 < exps.loc[("fast", "grid"), "exponent"] < 1.15
    ratios = analysis.speed_ratios(sizes, "ref")
    fast = ratios[ratios["impl"] == "fast"]["ratio"]
    assert fast.between(0.45, 0.55).all()
    matrix = analysis.correctness_matrix(analysis.case_table(df)).set_index(["impl", "dataset"])
    assert matrix.loc[("slow", "grid"), "worst"] == "differs"
    assert matrix.loc[("slow", "uniform"), "worst"] == "exact"
    assert matrix.loc[("crashy", "uniform"), "worst"] == "crashed"
    assert matrix.loc[("slow", "grid"), "good"] == 3


def test_verdict_ranking():
    assert analysis.worst_verdict(["exact", "within_tolerance", "exact"]) == "within_tolerance"
    assert analysis.worst_verdict(["exact", "crashed", "differs"]) == "crashed"
    assert analysis.worst_verdict(["skipped", "unsupported"]) == "skipped"
    assert outcomes.verdict_rank("not_certified") > outcomes.verdict_rank("differs")


def test_report_writes_figures_markdown_and_self_contained_html(results_csv, tmp_path):
    out = tmp_path / "rep"
    assert main(["report", str(results_csv), "-o", str(out), "--title", "synthetic"]) == 0
    pngs = sorted(p.name for p in out.glob("*.png"))
    assert pngs == ["correctness.png", "memory_vs_n.png", "speed_ratio.png", "time_per_nlogn.png",
                    "time_vs_n.png"]
    for p in out.glob("*.png"):
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and p.stat().st_size > 10_000
    md = (out / "README.md").read_text()
    for name in pngs:
        assert f"({name})" in md
    # the reading names the fastest implementation and the crash, the table shows the n^2 fit
    assert "`fast` on 2 dataset(s)" in md
    assert re.search(r"\| `slow` \| uniform \| 2\.0\d \|", md)
    assert "worker killed by SIGSEGV" in md and "crashy" in md
    assert "`fast` is 2x faster than `ref`" in md
    html = (out / "report.html").read_text()
    assert not re.search(r"<(img|script|iframe)\b[^>]*\bsrc=", html)   # figures are inline plotly, nothing linked
    assert html.count('<div class="plot"') >= 5 and "<table" in html
    assert 'id="failures"' in html and "worker killed by SIGSEGV" in html
    assert (out / "results.csv").exists() and (out / "results.meta.json").exists()


def test_report_of_a_run_where_nothing_succeeded(tmp_path):
    path = tmp_path / "bad.csv"
    results.ResultsFile(path).append([{"run_id": "r", "impl": "x", "dataset": "uniform", "n": 10, "seed": 0,
                                       "status": "timeout", "verdict": "timeout", "error": "no result"}])
    rep = tmp_path / "rep"
    assert main(["report", str(path), "-o", str(rep)]) == 0
    assert "1 case(s) failed" in (rep / "README.md").read_text()


def test_busy_machine_is_mentioned(results_csv, tmp_path):
    from vorobench.harness.report import busy_machine_note

    results.update_run_metadata(results_csv, "r1", load_average=[5.5, 5.0, 4.0], load_average_end=[3.0, 4.0, 4.0])
    note = busy_machine_note(results.read_metadata(results_csv))
    assert note is not None and "5.5 on 2 cores" in note
    results.update_run_metadata(results_csv, "r1", load_average=[0.5, 0.5, 0.5], load_average_end=[1.0, 1.0, 1.0])
    assert busy_machine_note(results.read_metadata(results_csv)) is None


def test_the_report_counts_certificate_levels_and_reads_older_results():
    import pandas as pd

    from vorobench.harness.report import certificate_tally

    cases = pd.DataFrame({"verdict": ["certified", "within_tolerance", "exact", "not_certified"],
                          "certificate": ["certified", "certified_within_tolerance", "certified", "not_certified"]})
    assert certificate_tally(cases) == "2 certified, 1 certified within tolerance, 1 not certified"
    older = cases.drop(columns="certificate")        # results written before the column existed
    assert certificate_tally(older) == "1 certified"


def test_a_run_with_disks_shows_its_smallest_case_of_disks(tmp_path):
    path = tmp_path / "disks.csv"
    rows = []
    for n, t in ((40, 0.2), (80, 0.5)):
        for rep in range(3):
            rows.append({"run_id": "r1", "impl": "fortune", "dataset": "uniform", "radii": "nested", "n": n,
                         "seed": 4, "repeat": rep, "status": "ok", "verdict": "exact", "time_s": t,
                         "warmup_s": 0.2, "n_sites": n, "mem_mb": 1.0, "peak_rss_mb": 200.0})
    results.ResultsFile(path).append(rows)
    results.append_run_metadata(path, {"run_id": "r1", "reference": "fortune", "repeat": 3, "timeout": 60,
                                       "check": True, "hostname": "testhost", "cpu": "Test CPU", "cores": 2})
    out = tmp_path / "rep"
    assert main(["report", str(path), "-o", str(out)]) == 0
    assert (out / "disks_diagram.png").stat().st_size > 10_000
    md = (out / "README.md").read_text()
    assert "## A diagram of disks of this run" in md and "(disks_diagram.png)" in md
    assert "uniform, n = 40, seed 4, nested radii, built by fortune" in md
