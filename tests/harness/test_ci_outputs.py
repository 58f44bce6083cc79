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


def test_every_output_names_the_certificate_levels(tmp_path, capsys):
    """On near_grid Qhull rounds nearly cocircular sites (certified within tolerance) and fortune
    is exact (certified): summary rows, JUnit properties, the Markdown digest and the table say
    which, and Qhull's own row is a pass within tolerance, not "certified"."""
    junit, md = tmp_path / "j.xml", tmp_path / "m.md"
    code = main(["validate", "--impls", "fortune", "--datasets", "near_grid", "--sizes", "100", "--no-shrink",
                 "--out", str(tmp_path / "v"), "--junit", str(junit), "--markdown", str(md)])
    assert code == 0
    rows = {r["impl"]: r for r in json.loads((tmp_path / "v" / "summary.json").read_text())["results"]
            if not r.get("exact_peer")}
    assert rows["qhull"]["certificate_level"] == "certified_within_tolerance"
    assert rows["qhull"]["verdict"] == "within_tolerance" and rows["qhull"]["passed"]
    assert rows["fortune"]["certificate_level"] == "certified"
    assert rows["fortune"]["reference_certificate_level"] == "certified_within_tolerance"
    properties = {(c.get("classname"), p.get("name")): p.get("value")
                  for c in ET.parse(junit).getroot().iter("testcase") for p in c.iter("property")}
    assert properties[("vorobench.qhull", "certificate")] == "certified_within_tolerance"
    assert properties[("vorobench.fortune", "certificate")] == "certified"
    assert "1 certified, 1 certified within tolerance" in md.read_text()
    out = capsys.readouterr().out
    assert "fortune 1 certified" in out and "qhull 1 certified within tolerance" in out
