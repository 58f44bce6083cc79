"""The interactive report page: one figure per view with data and none without, mismatches at the
top, distinct verdict colours, a run table without an empty header row, and one self-contained file."""

from __future__ import annotations

import itertools
import json
import math
import re
from html.parser import HTMLParser

import numpy as np
import pytest

from vorobench.cli import main
from vorobench.harness import figures, report, results
from vorobench.judge.outcomes import Verdict

SIZES = [1000, 4000, 16000, 64000]
DATASETS = ("uniform", "grid")
DECLARED = {"fast": "O(n log n)", "ref": "O(n log n)", "slow": "O(n log n)"}

LAWS = {"fast": lambda n: 5e-8 * n * math.log2(n), "ref": lambda n: 1e-7 * n * math.log2(n),
        "slow": lambda n: 1e-9 * n * n}


def _rows(impls=("fast", "ref", "slow"), mem=True, extra=None) -> list[dict]:
    rng = np.random.default_rng(11)
    rows = []
    for impl in impls:
        for dataset in DATASETS:
            for n in SIZES:
                for rep in range(4):
                    row = {"run_id": "r1", "impl": impl, "dataset": dataset, "n": n, "seed": 0, "repeat": rep,
                           "status": "ok", "verdict": "certified" if impl == "ref" else "exact",
                           "time_s": LAWS[impl](n) * (1 + 0.05 * abs(rng.standard_normal())),
                           "warmup_s": 0.1, "n_sites": n, "mem_mb": 1e-3 * n if mem else float("nan"),
                           "peak_rss_mb": 100.0, "stat_events": 3 * n}
                    row.update((extra or {}).get(impl, {}))
                    rows.append(row)
    return rows


def _write(tmp_path, rows, reference="ref", name="bench.csv"):
    path = tmp_path / name
    results.ResultsFile(path).append(rows)
    results.append_run_metadata(path, {"run_id": "r1", "reference": reference, "repeat": 4, "timeout": 60,
                                       "check": True, "hostname": "testhost", "cpu": "Test CPU", "cores": 2,
                                       "date": "2026-01-01T00:00:00", "commit": "abc"})
    return path


@pytest.fixture(autouse=True)
def declared(monkeypatch):
    """The synthetic implementations' declared complexities (they are not registered)."""
    monkeypatch.setattr(report, "_complexity", lambda name, recorded=None: DECLARED.get(name, "?"))


@pytest.fixture(scope="module")
def default(tmp_path_factory):
    """The report of :func:`_rows` (written once: matplotlib takes seconds): (folder, page, Markdown)."""
    tmp = tmp_path_factory.mktemp("default")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(report, "_complexity", lambda name, recorded=None: DECLARED.get(name, "?"))
        return _report(tmp, _write(tmp, _rows()))


def _report(tmp_path, path, *extra):
    out = tmp_path / "rep"
    assert main(["report", str(path), "-o", str(out), *extra]) == 0
    return out, (out / "report.html").read_text(), (out / "README.md").read_text()


def _payload(page: str) -> dict:
    m = re.search(r'<script type="application/json" id="report-data">(.*?)</script>', page, re.S)
    assert m, "no figure data in the page"
    return json.loads(m.group(1))


def _plot_ids(page: str) -> list[str]:
    return re.findall(r'<div class="plot" id="([^"]+)"', page)


class _Tables(HTMLParser):
    """Every table: its class, whether it has a thead, and its rows' cell texts."""

    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.tables: list[dict] = []
        self._cell = None

    def handle_starttag(self, tag, attrs):
        if tag == "table":
            self.tables.append({"class": dict(attrs).get("class", ""), "thead": False, "rows": []})
        elif tag == "thead" and self.tables:
            self.tables[-1]["thead"] = True
        elif tag == "tr" and self.tables:
            self.tables[-1]["rows"].append([])
        elif tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.tables[-1]["rows"][-1].append("".join(self._cell).strip())
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def _tables(page: str) -> list[dict]:
    parser = _Tables()
    parser.feed(page)
    return parser.tables


# ------------------------------------------------------------------------------ figures


def test_one_figure_per_dataset_and_view_with_data(default):
    out, page, md = default
    ids = _plot_ids(page)
    per_dataset = ["time", "spread", "nlogn", "ratio", "memory"]
    expected = {f"fig-{view}-{i}" for view in per_dataset for i in range(len(DATASETS))}
    expected |= {"fig-noise-0", "fig-growth-0"}
    assert set(ids) == expected and len(ids) == len(expected)
    payload = _payload(page)
    assert set(payload["figures"]) == expected
    for fid, fig in payload["figures"].items():
        assert fig["data"], fid
        assert any(len(t.get("y") or []) for t in fig["data"]), f"{fid} draws nothing"
    assert sorted(p.name for p in out.glob("*.png")) == ["correctness.png", "memory_vs_n.png", "speed_ratio.png",
                                                          "time_per_nlogn.png", "time_vs_n.png"]


def test_no_reference_timed_means_no_ratio_figure_and_no_placeholder(tmp_path):
    path = _write(tmp_path, _rows(impls=("fast", "slow")), reference="qhull")
    out, page, md = _report(tmp_path, path)
    assert not [i for i in _plot_ids(page) if i.startswith("fig-ratio")]
    assert 'id="ratio"' not in page and "Speed relative" not in page
    assert not (out / "speed_ratio.png").exists()
    assert "Speed relative" not in md and "speed_ratio.png" not in md
    assert "no successful" not in page.lower() and "no data" not in page.lower()


def test_a_stale_figure_of_an_earlier_report_is_removed(tmp_path):
    out = tmp_path / "rep"
    assert main(["report", str(_write(tmp_path, _rows())), "-o", str(out)]) == 0
    assert (out / "speed_ratio.png").exists()
    path = _write(tmp_path, _rows(impls=("fast", "slow")), reference="qhull", name="other.csv")
    assert main(["report", str(path), "-o", str(out)]) == 0
    assert not (out / "speed_ratio.png").exists()


def test_no_memory_measured_means_no_memory_figure(tmp_path):
    out, page, md = _report(tmp_path, _write(tmp_path, _rows(mem=False)))
    assert not [i for i in _plot_ids(page) if i.startswith("fig-memory")]
    assert 'id="memory"' not in page and not (out / "memory_vs_n.png").exists()
    assert "Peak memory" not in md


def test_a_dataset_where_nothing_ran_has_no_panel(tmp_path):
    rows = _rows() + [{"run_id": "r1", "impl": impl, "dataset": "cocircular", "n": 1000, "seed": 0,
                       "status": "timeout", "verdict": "timeout", "error": "no result"} for impl in LAWS]
    out, page, md = _report(tmp_path, _write(tmp_path, rows))
    panels = re.findall(r'<div class="panel" data-dataset="([^"]+)">', page)
    assert "cocircular" not in panels and {"uniform", "grid"} <= set(panels)
    # the failures are still listed, and the filters still offer the dataset
    assert 'value="cocircular"' in page and "3 case(s) failed" in page


def test_a_run_where_nothing_succeeded_draws_no_figure(tmp_path):
    path = _write(tmp_path, [{"run_id": "r", "impl": "x", "dataset": "uniform", "n": 10, "seed": 0,
                              "status": "timeout", "verdict": "timeout", "error": "no result"}])
    out, page, md = _report(tmp_path, path)
    assert _plot_ids(page) == [] and _payload(page)["figures"] == {}
    assert sorted(p.name for p in out.glob("*.png")) == ["correctness.png"]


def test_figure_data_are_plain_arrays_the_filters_can_cut(default):
    out, page, md = default
    payload = _payload(page)
    assert "bdata" not in json.dumps(payload)           # no typed arrays: the page filters points itself
    values = {}
    for group, value in re.findall(r'<input type="checkbox" data-group="(\w+)" value="([^"]+)"', page):
        values.setdefault(group, set()).add(value)
    assert values == {"impl": set(LAWS), "dataset": set(DATASETS), "n": {str(n) for n in SIZES}}
    for fid, fig in payload["figures"].items():
        assert len(fig["keys"]) == len(fig["data"]), fid
        for trace, key in zip(fig["data"], fig["keys"]):
            for group, value in key.items():
                points = value if isinstance(value, list) else [value]
                assert {str(v) for v in points} <= values[group], (fid, group)
                if isinstance(value, list):
                    assert len(value) == len(trace["y"]), fid


# ------------------------------------------------------------------------------ spread


def test_build_time_has_error_bars_from_fastest_to_slowest_repeat(tmp_path):
    rows = _rows()
    for r in rows:                                          # one slow repeat at fast/uniform/16k
        if (r["impl"], r["dataset"], r["n"], r["repeat"]) == ("fast", "uniform", 16000, 3):
            r["time_s"] *= 3
    out, page, md = _report(tmp_path, _write(tmp_path, rows))
    fig = _payload(page)["figures"]["fig-time-0"]
    (trace,) = [t for t, k in zip(fig["data"], fig["keys"]) if k["impl"] == "fast"]
    i = trace["x"].index(16000)
    times = [r["time_s"] for r in rows if (r["impl"], r["dataset"], r["n"]) == ("fast", "uniform", 16000)]
    assert trace["y"][i] == pytest.approx(np.median(times))
    assert trace["y"][i] + trace["error_y"]["array"][i] == pytest.approx(max(times))
    assert trace["y"][i] - trace["error_y"]["arrayminus"][i] == pytest.approx(min(times))
    # the distribution view has every repeat, relative to its case median
    spread = _payload(page)["figures"]["fig-spread-0"]
    (box,) = [t for t, k in zip(spread["data"], spread["keys"]) if k["impl"] == "fast"]
    assert box["type"] == "box" and len(box["y"]) == 4 * len(SIZES)
    assert max(box["y"]) == pytest.approx(max(times) / np.median(times), rel=1e-4)


def test_hover_names_the_case_spread_verdict_and_counters(default):
    out, page, md = default
    fig = _payload(page)["figures"]["fig-time-1"]
    trace = fig["data"][0]
    assert "fast" in trace["hovertemplate"] and "grid" in trace["hovertemplate"]
    detail = trace["customdata"][0][2]
    assert "fastest" in detail and "slowest" in detail and "verdict exact" in detail and "events 3,000" in detail


# ------------------------------------------------------------------------------ complexity


def test_a_complexity_mismatch_is_listed_at_the_top(default):
    out, page, md = default
    top = page.index('id="mismatches"')
    assert top < page.index('id="reading"') < page.index('id="time"')
    alert = page[top:page.index("</div>", top)]
    listed = re.findall(r"<tr><td><b>([^<]+)</b></td><td>([^<]+)</td><td><b>n\^(\d\.\d\d)</b>", alert)
    assert sorted((impl, dataset) for impl, dataset, _ in listed) == [("slow", "grid"), ("slow", "uniform")]
    assert all(abs(float(x) - 2) < 0.05 for _, _, x in listed)
    assert md.index("## Growth above the declared complexity") < md.index("## Reading")
    assert re.search(r"\| `slow` \| uniform \| \*\*n\^2\.0\d\*\* \|", md)
    # the reading names the mismatch instead of hiding it in a range
    (line,) = [x for x in md.splitlines() if x.startswith("* `slow` grows like")]
    assert "**above it on" in line and "uniform (n^2.0" in line


def test_no_mismatch_means_no_alert(tmp_path):
    out, page, md = _report(tmp_path, _write(tmp_path, _rows(impls=("fast", "ref"))))
    assert 'id="mismatches"' not in page and "Growth above" not in md


# ------------------------------------------------------------------------------ verdict colours

def _lab(hex_colour: str, matrix) -> np.ndarray:
    rgb = np.array([int(hex_colour[i:i + 2], 16) / 255 for i in (1, 3, 5)])
    lin = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    lin = np.clip(matrix @ lin, 0, 1)
    xyz = np.array([[0.4124, 0.3576, 0.1805], [0.2126, 0.7152, 0.0722], [0.0193, 0.1192, 0.9505]]) @ lin
    xyz = xyz / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > 0.008856, np.cbrt(xyz), 7.787 * xyz + 16 / 116)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


#: Machado, Oliveira and Fernandes (2009), severity 1, on linear RGB.
VISION = {
    "normal": np.eye(3),
    "protanopia": np.array([[0.152286, 1.052583, -0.204868], [0.114503, 0.786281, 0.099216],
                            [-0.003882, -0.048116, 1.051998]]),
    "deuteranopia": np.array([[0.367322, 0.860646, -0.227968], [0.280085, 0.672501, 0.047413],
                              [-0.011820, 0.042940, 0.968881]]),
    "tritanopia": np.array([[1.255528, -0.076749, -0.178779], [-0.078411, 0.930809, 0.147602],
                            [0.004733, 0.691367, 0.303900]]),
}


def test_every_verdict_has_its_own_colour_in_the_schemas_order():
    assert list(figures.VERDICT_COLOURS) == [v.value for v in Verdict]
    colours = [figures.verdict_colour(v.value) for v in Verdict]
    assert len({c.lower() for c in colours}) == len(colours)
    assert figures.verdict_colour("something new") not in colours


@pytest.mark.parametrize("vision", list(VISION))
def test_verdict_colours_stay_apart_for_colour_blind_readers(vision):
    labs = {v: _lab(c, VISION[vision]) for v, c in figures.VERDICT_COLOURS.items()}
    closest = min((float(np.linalg.norm(labs[a] - labs[b])), a, b) for a, b in itertools.combinations(labs, 2))
    assert closest[0] > 10, closest


def test_the_three_passing_verdicts_are_far_apart():
    """exact, within tolerance and certified were three greens 14-31 apart (CIELAB); now at least 20."""
    labs = [_lab(figures.VERDICT_COLOURS[v], VISION["normal"]) for v in ("exact", "within_tolerance", "certified")]
    assert min(float(np.linalg.norm(a - b)) for a, b in itertools.combinations(labs, 2)) > 20


def test_the_correctness_matrix_uses_the_verdict_colours_with_a_legend(tmp_path):
    rows = _rows()
    for r in rows:
        if r["impl"] == "slow" and r["dataset"] == "grid":
            r["verdict"] = "differs"
    out, page, md = _report(tmp_path, _write(tmp_path, rows))
    section = page[page.index('id="correctness"'):page.index('id="cases"')]
    for verdict in ("exact", "certified", "differs"):
        colour = figures.VERDICT_COLOURS[verdict]
        assert f"background:{colour}" in section
    legend = section[section.index('class="legend"'):section.index("</p>", section.index('class="legend"'))]
    for verdict in Verdict:                    # present ones first, the others listed too
        assert figures.verdict_label(verdict.value) in legend


def test_the_correctness_png_draws_every_verdict(tmp_path):
    import pandas as pd

    matrix = pd.DataFrame([{"impl": f"i{k}", "dataset": "d", "worst": v.value, "cases": 1, "checked": 1, "good": 0}
                           for k, v in enumerate(Verdict)])
    path = figures.plot_correctness(matrix, tmp_path / "c.png")
    assert path.exists() and path.stat().st_size > 10_000
    assert figures.plot_correctness(matrix.iloc[0:0], tmp_path / "none.png") is None
    assert not (tmp_path / "none.png").exists()


# ------------------------------------------------------------------------------ tables and page


def test_no_table_has_an_empty_header_row(default):
    out, page, md = default
    for table in _tables(page):
        for row in table["rows"]:
            assert any(cell for cell in row), table
    (run,) = [t for t in _tables(page) if t["class"] == "run"]
    assert not run["thead"] and [r[0] for r in run["rows"]][:3] == ["date", "commit", "machine"]
    assert all(len(r) == 2 and r[1] for r in run["rows"])
    assert not re.search(r"^\|(\s*\|)+\s*$", md, re.M)          # no Markdown row of empty cells


def test_the_page_is_self_contained_with_plotly_inlined_once(default):
    from plotly.offline import get_plotlyjs

    out, page, md = default
    tags = re.findall(r"<script\b[^>]*>", page)
    assert tags == ["<script>", '<script type="application/json" id="report-data">', "<script>"]
    assert not re.search(r"""<(script|link|img|iframe)[^>]+(src|href)=["']?(https?:)?//""", page, re.I)
    assert "<link" not in page
    js = get_plotlyjs()
    assert page.count(js[:200]) == 1
    assert len(page) < len(js) + 2_000_000


def test_the_drill_down_has_every_case_with_repeats_timings_and_counters(tmp_path):
    extra = {"ref": {"time_library_s": 0.001, "time_convert_s": 0.0005}}
    out, page, md = _report(tmp_path, _write(tmp_path, _rows(extra=extra)))
    payload = _payload(page)
    n_cases = len(LAWS) * len(DATASETS) * len(SIZES)
    assert len(payload["cases"]) == n_cases
    assert len(re.findall(r'<div class="case-detail" id="case-\d+" hidden>', page)) == n_cases
    rows = re.findall(r'<tr data-case="(\d+)"', page)
    assert sorted(map(int, rows)) == list(range(n_cases))
    ref = [i for i, c in enumerate(payload["cases"]) if dict(c["phases"])]
    assert ref and all(len(payload["cases"][i]["times"]) == 4 for i in ref)
    detail = page[page.index(f'id="case-{ref[0]}"'):]
    detail = detail[:detail.index('<div class="case-detail"', 10)]
    assert "time_library_s" in detail and "time_convert_s" in detail and "stat_events" in detail
    assert detail.count("<tr><td>") >= 4 + 1                   # four repeats and a counter
    # the page opens with the worst mismatch's largest case
    first = payload["cases"][payload["first_case"]]
    assert (first["repeats"], len(first["times"])) == ([0, 1, 2, 3], 4)


def test_legacy_duration_counters_show_as_timings(tmp_path):
    path = tmp_path / "old.csv"
    rows = _rows(impls=("fast", "ref"))
    header = sorted({k for r in rows for k in r} | {"stat_library_s"})
    with path.open("w") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            r = dict(r, stat_library_s=0.002 if r["impl"] == "ref" else "")
            f.write(",".join(str(r.get(k, "")) for k in header) + "\n")
    out, page, md = _report(tmp_path, path, "--reference", "ref")
    assert "time_library_s" in page and "stat_library_s" not in page


def test_memory_below_its_resolution_is_not_drawn_and_titles_wrap(tmp_path):
    """0.02 MiB is allocator noise, not a build's need: not drawn (no figure when nothing else
    is left); a long title of a one-panel figure is wrapped, not clipped."""
    import pandas as pd

    styles = figures.impl_styles(["a"])
    noise = pd.DataFrame({"impl": "a", "dataset": "uniform", "n": [1000, 3000], "n_sites": [1000, 3000],
                          "mem_mb": [0.02, 0.5]})
    assert figures.plot_memory(noise, tmp_path / "m.png", styles) is None
    real = noise.assign(mem_mb=[0.02, 12.0])
    assert figures.plot_memory(real, tmp_path / "m.png", styles) is not None
    fig, _ = figures._grid(1, "Peak memory of the build (rise above the worker's resident size; below 1 MiB "
                              "not measurable, not drawn)")
    try:
        assert "\n" in fig._suptitle.get_text()
    finally:
        figures.plt.close(fig)
