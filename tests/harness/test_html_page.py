"""Both self-contained pages, ``report.html`` and the trend page, take names from the results as
text: a name that closes the script element, opens a comment in it, holds a terminal escape, a lone
surrogate (an undecodable byte read with surrogateescape) or a line separator comes out as inert,
readable text in a page that is valid UTF-8, with the page's own scripts and no other.

Fault doubles: results and a run store whose implementation and dataset names are such strings
(those a CSV file or SQLite can hold), and, for the lone surrogate no file or DataFrame can hold,
the pages' inputs given it directly (a title, a host, a store path from the command line, a name).
"""

from __future__ import annotations

import dataclasses
import json
import re
from html.parser import HTMLParser

import numpy as np
import pandas as pd
import pytest
from plotly.offline import get_plotlyjs

from vorobench.cli import main
from vorobench.harness import report, report_html, results, trend
from vorobench.harness.html_page import BASE_CSS, escape, page, script_json
from vorobench.harness.store import Store

SCRIPT = "</script><script>alert(1)</script>"
COMMENT = "<!--<script>alert(2)//"
TERMINAL = "evil\x1b[31m\x9b1m"
SURROGATE = "bad\udcffbyte"
SEPARATORS = "line\u2028para\u2029end"

#: The names a results file or a run store can hold (not the lone surrogate).
FILE_NAMES = [SCRIPT, COMMENT, TERMINAL, SEPARATORS]

#: What a valid page holds nowhere outside the inlined plotly.js: C0 controls but tab and line
#: breaks, DEL, C1 controls, lone surrogates, U+FFFE and U+FFFF.
UNSAFE = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff]")

#: How each name reads on the page (HTML text): markup escaped, unsafe characters as visible escapes.
SHOWN = {
    SCRIPT: "&lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt;",
    COMMENT: "&lt;!--&lt;script&gt;alert(2)//",
    TERMINAL: "evil\\x1b[31m\\x9b1m",
    SURROGATE: "bad\\udcffbyte",
    SEPARATORS: SEPARATORS,
}


class _Scripts(HTMLParser):
    """The attributes of every script element and every attribute name of any element."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.scripts: list[dict] = []
        self.attributes: set[str] = set()

    def handle_starttag(self, tag, attrs):
        self.attributes |= {name for name, _ in attrs}
        if tag == "script":
            self.scripts.append(dict(attrs))


def _assert_safe(page: str, data_id: str) -> dict:
    """The page is valid UTF-8, holds no unsafe character outside plotly.js, runs only its own three
    scripts (plotly.js, its JSON data, its wiring) and no event handler; returns the parsed data."""
    page.encode("utf-8")                                  # raises on a lone surrogate
    own = page.replace(get_plotlyjs(), "")
    assert not UNSAFE.findall(own), sorted(set(UNSAFE.findall(own)))
    parsed = _Scripts()
    parsed.feed(own)
    parsed.close()
    assert parsed.scripts == [{}, {"type": "application/json", "id": data_id}, {}]
    assert not [a for a in parsed.attributes if a.startswith("on")]
    m = re.search(f'<script type="application/json" id="{data_id}">(.*?)</script>', own, re.S)
    assert m and m.group(1).isascii() and not re.search(r"[<>&]", m.group(1))
    return json.loads(m.group(1))


def _strings(data) -> str:
    """Every string in JSON data, one a line."""
    if isinstance(data, dict):
        return "\n".join(_strings(v) for v in data.values())
    if isinstance(data, list):
        return "\n".join(_strings(v) for v in data)
    return data if isinstance(data, str) else ""


def _markup(page: str) -> str:
    """The page without its scripts: what a reader sees as text and attributes."""
    return re.sub(r"<script[^>]*>.*?</script>", "", page, flags=re.S)


def _assert_shown(page: str, names: list[str]) -> None:
    """Each name reads in the page's markup as :data:`SHOWN` says."""
    markup = _markup(page)
    assert [name for name in names if SHOWN[name] not in markup] == []


# ------------------------------------------------------------------------------ report.html


@pytest.fixture(scope="module")
def report_run(tmp_path_factory):
    """``vorobench report`` of results named by :data:`FILE_NAMES`: (the page, the PageInput it was drawn from)."""
    tmp = tmp_path_factory.mktemp("report")
    rows = []
    for impl in [*FILE_NAMES, "ref"]:
        for dataset in (SEPARATORS, COMMENT):
            for n in (1000, 4000, 16000):
                for rep in range(2):
                    rows.append({"run_id": "r1", "impl": impl, "dataset": dataset, "n": n, "seed": 0, "repeat": rep,
                                 "status": "ok", "verdict": "exact", "n_sites": n, "time_s": 1e-7 * n,
                                 "stat_events": n})
    rows.append({"run_id": "r1", "impl": TERMINAL, "dataset": SCRIPT, "n": 64000, "seed": 0, "status": "crashed",
                 "verdict": "crashed", "error": TERMINAL + SCRIPT})
    path = tmp / "bench.csv"
    results.ResultsFile(path).append(rows)
    results.append_run_metadata(path, {"run_id": "r1", "reference": "ref", "hostname": TERMINAL, "cpu": SCRIPT,
                                       "argv": ["bench", SCRIPT, TERMINAL, SEPARATORS]})
    inputs = []
    with pytest.MonkeyPatch.context() as mp, pytest.warns(UserWarning, match="Glyph"):   # matplotlib: no ESC glyph
        mp.setattr(report, "render", lambda page: inputs.append(page) or report_html.render(page))
        assert main(["report", str(path), "-o", str(tmp / "rep"), "--title", SCRIPT + TERMINAL]) == 0
    return (tmp / "rep" / "report.html").read_text(encoding="utf-8"), inputs[0]


def test_report_names_are_text_in_a_valid_page(report_run):
    page, _ = report_run
    data = _assert_safe(page, "report-data")
    _assert_shown(page, FILE_NAMES)
    # the figures' labels (HTML to plotly) are escaped and cleaned like the markup; the filter keys are data
    shown = _strings([[f["data"], f["layout"]] for f in data["figures"].values()])
    assert SHOWN[SCRIPT] in shown and SHOWN[TERMINAL] in shown and "<script" not in shown


def test_report_filters_match_the_figures_keys(report_run):
    """A filter box's value is the name as the figures' keys give it, so unchecking it hides that name."""
    page, _ = report_run
    data = _assert_safe(page, "report-data")
    values = set()

    class Boxes(HTMLParser):
        def handle_starttag(self, tag, attrs):
            a = dict(attrs)
            if tag == "input" and a.get("data-group") == "impl":
                values.add(a["value"])

    Boxes(convert_charrefs=True).feed(_markup(page))
    keyed = {k["impl"] for f in data["figures"].values() for k in f["keys"] if isinstance(k.get("impl"), str)}
    assert keyed and keyed <= values, keyed - values


def test_report_text_fields_with_a_lone_surrogate_still_make_a_valid_page(report_run):
    """A title from a folder name or metadata read from JSON can hold a lone surrogate."""
    _, inp = report_run
    hostile = dataclasses.replace(inp, title=SURROGATE, summary=SURROGATE + TERMINAL,
                                  run_rows=[("host", SURROGATE), (TERMINAL, SEPARATORS)],
                                  notes_md=[SURROGATE], skipped_md=SURROGATE, warmup_md=TERMINAL,
                                  command=f"bench {SURROGATE}\n{TERMINAL}", reference=SURROGATE)
    page = report_html.render(hostile)
    _assert_safe(page, "report-data")
    assert f"<title>vorobench report: {SHOWN[SURROGATE]}</title>" in page
    assert page.count(SHOWN[SURROGATE]) >= 6


# ------------------------------------------------------------------------------ the trend page


def _store(path) -> Store:
    """Three runs of cases named by :data:`FILE_NAMES`, a counter named :data:`TERMINAL` changing at the last."""
    store = Store(path)
    for k in range(3):
        run_id = f"run{k}"
        rows = [{"run_id": run_id, "impl": impl, "dataset": dataset, "n": 100, "seed": 0, "repeat": r,
                 "status": "ok", "verdict": "exact", "time_s": 0.01 * (1 + r / 100), f"stat_{TERMINAL}": 5 + (k == 2)}
                for impl, dataset in zip(FILE_NAMES, reversed(FILE_NAMES)) for r in range(3)]
        meta = {"run_id": run_id, "date": f"2026-01-0{k + 1}T00:00:00", "commit": f"{k:040x}", "dirty": False,
                "machine_id": SCRIPT, "hostname": TERMINAL, "cpu": SEPARATORS}
        assert store.add_run(pd.DataFrame(rows), meta)
    return store


@pytest.fixture(scope="module")
def trend_store(tmp_path_factory):
    return _store(tmp_path_factory.mktemp("trend") / "runs")


def test_trend_names_are_text_in_a_valid_page(trend_store, tmp_path):
    out = tmp_path / "t.html"
    assert main(["trend", str(trend_store.path), "-o", str(out)]) == 0
    page = out.read_text(encoding="utf-8")
    data = _assert_safe(page, "trend-figures")
    _assert_shown(page, FILE_NAMES)
    shown = _strings(data["figures"])
    assert SHOWN[TERMINAL] in shown and "<script" not in shown


def test_trend_page_with_a_lone_surrogate_in_names_and_store_path_is_valid(trend_store):
    """A store path from the command line (surrogateescape) or any name can hold a lone surrogate."""
    machines = trend.load(trend_store)
    machines[0].hostname = SURROGATE
    machines[0].series[0].impl = SURROGATE
    machines[0].series[1].dataset = SURROGATE + TERMINAL
    points = trend.detect(machines)
    page = trend.render(f"/tmp/{SURROGATE}/runs", machines, points, 0.10, 0.05)
    _assert_safe(page, "trend-figures")
    assert f"<title>vorobench trend: /tmp/{SHOWN[SURROGATE]}/runs</title>" in page
    assert page.count(SHOWN[SURROGATE]) >= 4


# ------------------------------------------------------------------------------ the shared helpers


def test_escape_makes_markup_and_unsafe_characters_text():
    for name, shown in SHOWN.items():
        assert escape(name) == shown
    assert escape("\"'&") == "&quot;&#x27;&amp;"
    assert escape("a\tb\r\nc") == "a\tb\r\nc"                 # white space is not unsafe


def test_script_json_reads_back_cleaned_and_cannot_end_its_element():
    data = {SCRIPT: [COMMENT, TERMINAL, SURROGATE, SEPARATORS], "n": 1, "x": 0.5, "none": None}
    text = script_json(data)
    assert text.isascii() and not re.search(r"[<>&]", text)
    assert json.loads(text) == {SCRIPT: [COMMENT, SHOWN[TERMINAL], SHOWN[SURROGATE], SEPARATORS],
                                "n": 1, "x": 0.5, "none": None}
    # what the browser's parser gives the script is the whole text
    content = []

    class Element(HTMLParser):
        def handle_data(self, data):
            content.append(data)

    Element().feed(f'<script type="application/json">{text}</script><p>after</p>')
    assert content == [text, "after"]


def test_script_json_converts_with_default_and_refuses_nan():
    values = np.array([TERMINAL])
    assert json.loads(script_json({"v": values}, default=lambda v: v.tolist())) == {"v": [SHOWN[TERMINAL]]}
    with pytest.raises(ValueError):
        script_json({"x": float("nan")})


def test_page_escapes_its_title_cleans_its_body_and_refuses_a_script_that_ends_early():
    doc = page(SCRIPT, "p { color: red; }", f"<p>{TERMINAL}</p>", data_id="d", data={"k": SCRIPT}, script="go();",
               libraries=["lib();"])
    assert f"<title>{SHOWN[SCRIPT]}</title>" in doc and f"<p>{SHOWN[TERMINAL]}</p>" in doc
    assert _assert_safe(doc, "d") == {"k": SCRIPT}
    assert doc.index(BASE_CSS) < doc.index("p { color: red; }") < doc.index("lib();") < doc.index("<body>")
    with pytest.raises(ValueError, match="</script"):
        page("t", "", "", data_id="d", data={}, script="x = '</SCRIPT>';")
