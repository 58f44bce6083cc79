"""`vorobench report` treats the results as data: hostile strings in any column or in the metadata
come out as text in README.md and report.html, never as markup; damaged inputs are one line.

Fault doubles: a results file whose implementation, dataset, error, step, verdict detail and
metadata carry script tags, attribute breakouts, pipes, newlines and backtick fences; and
results or metadata files that are empty, garbage or not results at all.
"""

from __future__ import annotations

import json
import re
from html.parser import HTMLParser

import pytest
from markdown_it import MarkdownIt

from vorobench.cli import main
from vorobench.harness import results
from vorobench.harness.report import FIGURES

SCRIPT = "<script>alert(1)</script>"
FAILURE_HEADER = ["impl", "dataset", "n", "seed", "status", "verdict", "step", "error"]
BREAKOUT = '"><img src=x onerror=alert(1)>'
FENCE = "```\n</code></pre><script>alert(2)</script>"

#: Tags of the Markdown rendered by markdown-it.
MARKDOWN_TAGS = {"h1", "h2", "p", "ul", "li", "strong", "em", "code", "pre", "table", "thead", "tbody", "tr", "th",
                 "td", "img", "a"}
#: Tags the interactive page writes (vorobench.harness.report_html), the Markdown parts included.
OWN_TAGS = MARKDOWN_TAGS | {"html", "head", "meta", "title", "style", "script", "body", "h3", "div", "section", "nav",
                            "fieldset", "legend", "label", "input", "button", "span", "b", "i", "small", "details",
                            "summary", "br"}
#: The page's own scripts: plotly.js, the figures' JSON, the wiring.
OWN_SCRIPTS = [{}, {"type": "application/json", "id": "report-data"}, {}]


class _Tags(HTMLParser):
    """Every start tag with its attributes, and the text of every table cell by table and row."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.tags: list[tuple[str, dict]] = []
        self.tables: list[list[list[str]]] = []
        self._cell: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))
        if tag == "table":
            self.tables.append([])
        elif tag == "tr":
            self.tables[-1].append([])
        elif tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th") and self._cell is not None:
            self.tables[-1][-1].append("".join(self._cell))
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def _parse(html: str) -> _Tags:
    parser = _Tags()
    parser.feed(html)
    parser.close()
    return parser


def _assert_inert(html: str, markdown: bool = False) -> _Tags:
    """Only our own tags, no event handlers, only our scripts, and images only the report's figures."""
    page = _parse(html)
    allowed = MARKDOWN_TAGS if markdown else OWN_TAGS
    assert {t for t, _ in page.tags} <= allowed, {t for t, _ in page.tags} - allowed
    for tag, attrs in page.tags:
        assert not [a for a in attrs if a.startswith("on")], (tag, attrs)
        if tag == "img":
            assert attrs["src"] in FIGURES.values(), attrs
    assert [attrs for tag, attrs in page.tags if tag == "script"] == ([] if markdown else OWN_SCRIPTS)
    return page


def _payload(html: str) -> dict:
    """The page's figure data (JSON with <, > and & escaped, so it cannot end its script element)."""
    m = re.search(r'<script type="application/json" id="report-data">(.*?)</script>', html, re.S)
    assert m and not re.search(r"[<>&]", m.group(1))
    return json.loads(m.group(1))


def _hostile_results(path):
    rows = []
    for impl in (SCRIPT, "ref"):
        for dataset in (BREAKOUT, "uniform"):
            for n in (1000, 4000, 16000):
                for rep in range(2):
                    rows.append({"run_id": "r1", "impl": impl, "dataset": dataset, "n": n, "seed": 0,
                                 "repeat": rep, "status": "ok", "verdict": "exact", "n_sites": n,
                                 "time_s": 1e-7 * n * (2 if impl == "ref" else 1),
                                 "verdict_detail": SCRIPT + BREAKOUT, "host": BREAKOUT})
    rows.append({"run_id": "r1", "impl": SCRIPT, "dataset": BREAKOUT, "n": 64000, "seed": 0, "status": "crashed",
                 "verdict": "crashed", "phase": BREAKOUT, "error": f"{SCRIPT} | pipe\nsecond line",
                 "verdict_detail": SCRIPT})
    results.ResultsFile(path).append(rows)
    results.append_run_metadata(path, {
        "run_id": SCRIPT, "reference": "ref", "date": SCRIPT, "finished": BREAKOUT, "commit": BREAKOUT,
        "cpu": SCRIPT, "cores": 2, "hostname": BREAKOUT, "python": SCRIPT, "versions": {"numpy": SCRIPT},
        "repeat": 2, "timeout": SCRIPT, "check": True, "argv": ["bench", "--out", SCRIPT, FENCE, BREAKOUT]})


def test_hostile_strings_in_results_and_metadata_stay_text(tmp_path):
    path = tmp_path / "bench.csv"
    _hostile_results(path)
    out = tmp_path / "rep"
    assert main(["report", str(path), "-o", str(out), "--title", SCRIPT]) == 0
    html = (out / "report.html").read_text()
    page = _assert_inert(html)
    # the strings are there, as text
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in html
    assert "&lt;img src=x onerror=alert(1)&gt;" in html
    # what the figures show (names, hover text, labels) is escaped too: plotly reads it as HTML
    payload = _payload(html)
    shown = json.dumps({fid: {"data": f["data"], "layout": f["layout"]} for fid, f in payload["figures"].items()},
                       ensure_ascii=False)
    assert payload["figures"] and "<script>" not in shown and "<img" not in shown
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in shown
    # the failure table keeps its eight columns; the error is one cell with its pipe and both lines
    failures = [t for t in page.tables if t[0] == FAILURE_HEADER]
    assert len(failures) == 1 and all(len(row) == 8 for row in failures[0])
    assert failures[0][1][7] == f"{SCRIPT} | pipe second line"
    assert failures[0][1][:2] == [SCRIPT, BREAKOUT]
    # the Markdown is safe even for a renderer that lets raw HTML through
    md = (out / "README.md").read_text()
    _assert_inert(MarkdownIt("commonmark", {"html": True}).enable("table").render(md), markdown=True)


def test_markdown_cells_and_code_survive_pipes_newlines_and_backticks(tmp_path):
    path = tmp_path / "bench.csv"
    results.ResultsFile(path).append([
        {"run_id": "r", "impl": "a|b`c", "dataset": "x\ny", "n": 10, "seed": 0, "status": "error",
         "verdict": "error", "error": "one | two\r\nthree ``` four"}])
    out = tmp_path / "rep"
    assert main(["report", str(path), "-o", str(out)]) == 0
    page = _parse((out / "report.html").read_text())
    (failures,) = [t for t in page.tables if t[0] == FAILURE_HEADER]
    assert failures[1][:2] == ["a|b`c", "x y"] and failures[1][7] == "one | two three ``` four"


DAMAGED = {
    "empty": (b"", "is empty"),
    "header only": (b"run_id,impl,dataset,n,seed,status\r\n", "no result rows"),
    "binary garbage": (bytes(range(256)) * 4, "results"),
    "unrelated text": (b"hello world\nfoo bar\n", "not a results table"),
}


@pytest.mark.parametrize("kind", list(DAMAGED))
def test_a_file_that_is_no_results_is_one_line_and_exit_2(kind, tmp_path, capsys):
    content, problem = DAMAGED[kind]
    bad = tmp_path / "bad.csv"
    bad.write_bytes(content)
    assert main(["report", str(bad), "-o", str(tmp_path / "rep")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(bad) in err[0] and problem in err[0], err


@pytest.mark.parametrize("meta", [b"{not json", b"[1, 2]", b'{"runs": [1]}'])
def test_damaged_metadata_is_one_line_naming_it(meta, tmp_path, capsys):
    path = tmp_path / "bench.csv"
    results.ResultsFile(path).append([{"run_id": "r", "impl": "a", "dataset": "d", "n": 10, "seed": 0,
                                       "status": "ok", "time_s": 0.1}])
    results.metadata_path(path).write_bytes(meta)
    assert main(["report", str(path), "-o", str(tmp_path / "rep")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(results.metadata_path(path)) in err[0], err
