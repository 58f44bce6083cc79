"""`validate --junit/--markdown`: files a CI system reads, listing every verdict."""

import json
import xml.etree.ElementTree as ET
from pathlib import Path

from vorobench.cli import main
from vorobench.harness.ci_outputs import write_markdown

DOUBLES = str(Path(__file__).resolve().parents[1] / "support" / "doubles.py")


def test_junit_and_markdown_list_every_case(tmp_path):
    junit, md = tmp_path / "j.xml", tmp_path / "m.md"
    code = main(["validate", "--plugin", DOUBLES, "--impls", "fortune,wrong", "--datasets", "uniform,grid",
                 "--sizes", "10,30", "--no-shrink", "--out", str(tmp_path / "v"), "--junit", str(junit),
                 "--markdown", str(md)])
    assert code == 1
    summary = json.loads((tmp_path / "v" / "summary.json").read_text())
    suite = ET.parse(junit).getroot().find("testsuite")
    cases = suite.findall("testcase")
    assert len(cases) == len(summary["results"]) == int(suite.get("tests"))
    failing = [c for c in cases if c.find("failure") is not None]
    assert len(failing) == int(suite.get("failures")) == sum(not r["passed"] for r in summary["results"]) == 4
    assert {c.get("classname") for c in failing} == {"vorobench.wrong"}
    assert all(c.find("failure").get("type") == "not_certified" for c in failing)
    names = {c.get("name") for c in cases}
    assert "fortune on grid n=30 seed=0" in names and "wrong on uniform n=10 seed=0" in names
    text = md.read_text()
    assert "## vorobench validate: FAILED" in text
    assert text.count("| wrong |") == 4 and "not\\_certified" in text


def test_a_passing_run_says_so(tmp_path):
    md = tmp_path / "m.md"
    assert main(["validate", "--impls", "qhull", "--datasets", "uniform", "--sizes", "10", "--out",
                 str(tmp_path / "v"), "--markdown", str(md), "--junit", str(tmp_path / "j.xml")]) == 0
    assert md.read_text().startswith("## vorobench validate: passed")
    assert ET.parse(tmp_path / "j.xml").getroot().find("testsuite").get("failures") == "0"


def test_markdown_shows_hostile_text_as_text(tmp_path):
    row = {"impl": "x|<script>alert(1)</script>", "exact_peer": None, "dataset": "d", "n": 3, "seed": 0,
           "verdict": "crashed", "passed": False, "message": "line one\n| injected | row |"}
    text = write_markdown({"passed": False, "results": [row], "cases": 1, "judged": 1}, tmp_path / "m.md").read_text()
    assert "<script>" not in text and "\n| injected" not in text
    assert sum(line.startswith("| ") for line in text.splitlines()) == 2     # header and one row
