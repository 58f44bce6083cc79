"""JUnit XML and Markdown digests stay well-formed and readable whatever text the results carry:
control characters XML 1.0 forbids, lone surrogates (undecodable bytes read with
``surrogateescape``) and the non-characters U+FFFE/U+FFFF, in names and messages.

Fault doubles: validate summaries and compare frames whose implementation, dataset and message
hold each forbidden character.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET

import pandas as pd
import pytest

from vorobench.harness import regress
from vorobench.harness.ci_outputs import (write_compare_junit, write_compare_markdown, write_junit,
                                          write_markdown)

#: One of each kind of character XML 1.0 forbids (and one of the C1 controls terminals obey).
FORBIDDEN = ["\x00", "\x08", "\x0b", "\x0c", "\x0e", "\x1b", "\x1f", "\udcff", "\ud800", "\ufffe", "\uffff"]

#: What no written file may hold: XML 1.0's forbidden characters, surrogates and C1 controls.
UNSHOWABLE = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff]")

FIELDS = ["impl", "dataset", "message"]


def _visible(ch: str) -> str:
    """The escape a reader sees in place of ``ch`` (``\\x1b``, ``\\udcff``)."""
    return ch.encode("unicode_escape").decode("ascii")


def _summary(field: str, ch: str) -> dict:
    """A failing validate summary whose ``field`` holds ``ch`` in the middle of a word."""
    row = {"impl": "impl", "exact_peer": None, "dataset": "uniform", "n": 3, "seed": 0, "verdict": "crashed",
           "passed": False, "message": "boom", "seconds": 0.5}
    row[field] = f"bad{ch}[31mtext"
    return {"passed": False, "results": [row], "cases": 1, "judged": 1, "reference": "qhull"}


def _all_text(root: ET.Element) -> str:
    return " ".join([*(e.text or "" for e in root.iter()), *(v for e in root.iter() for v in e.attrib.values())])


@pytest.mark.parametrize("field", FIELDS)
@pytest.mark.parametrize("ch", FORBIDDEN, ids=_visible)
def test_validate_junit_is_well_formed_and_shows_the_character(field, ch, tmp_path):
    path = write_junit(_summary(field, ch), tmp_path / "j.xml")
    root = ET.parse(path).getroot()                     # a ParseError when not well-formed
    text = _all_text(root)
    assert not UNSHOWABLE.search(text)
    assert f"bad{_visible(ch)}[31mtext" in text         # readable: the escape, not a hole


@pytest.mark.parametrize("field", FIELDS)
@pytest.mark.parametrize("ch", FORBIDDEN, ids=_visible)
def test_validate_markdown_is_utf8_one_row_and_shows_the_character(field, ch, tmp_path):
    path = write_markdown(_summary(field, ch), tmp_path / "m.md")
    text = path.read_bytes().decode("utf-8")            # written at all, and as UTF-8
    assert not UNSHOWABLE.search(text)
    assert f"bad{_visible(ch)}" in text.replace("\\\\", "\\")
    assert sum(line.startswith("| ") for line in text.splitlines()) == 2     # header and the one failure


def test_never_judged_names_are_escaped_too(tmp_path):
    summary = {"passed": False, "results": [], "never_judged": ["evil\x1b]0;title\x07"]}
    root = ET.parse(write_junit(summary, tmp_path / "j.xml")).getroot()
    assert "evil\\x1b]0;title\\x07" in _all_text(root)


def _hostile_frames(ch: str) -> tuple[pd.DataFrame, pd.DataFrame]:
    """BASE and NEW of one case whose names hold ``ch``; NEW lost its verdict, so it is flagged."""
    rows = [{"impl": f"im{ch}pl", "dataset": f"da{ch}ta", "n": 10, "seed": 0, "repeat": r, "status": "ok",
             "verdict": "exact", "time_s": 1.0} for r in range(3)]
    base = pd.DataFrame(rows)
    return base, base.assign(verdict="differs")


def _in_names(ch: str) -> str:
    """The character to put in case names: pandas (3, arrow strings) cannot group by a lone
    surrogate, so that one reaches compare only in a file name (sys.argv's surrogateescape)."""
    return "\x1b" if "\ud800" <= ch <= "\udfff" else ch


@pytest.mark.parametrize("ch", FORBIDDEN, ids=_visible)
def test_compare_junit_and_markdown_are_well_formed(ch, tmp_path):
    named = _in_names(ch)
    comparison = regress.compare_runs(*_hostile_frames(named))
    junit = write_compare_junit(comparison, tmp_path / "c.xml", f"base{ch}.csv", "new.csv")
    text = _all_text(ET.parse(junit).getroot())
    assert not UNSHOWABLE.search(text)
    assert f"im{_visible(named)}pl" in text and f"base{_visible(ch)}.csv" in text
    md = write_compare_markdown(comparison, tmp_path / "c.md", f"base{ch}.csv", "new.csv")
    md_text = md.read_bytes().decode("utf-8")
    assert not UNSHOWABLE.search(md_text)
    shown = md_text.replace("\\\\", "\\")                  # Markdown's escaped backslashes, as rendered
    assert f"im{_visible(named)}pl" in shown and f"base{_visible(ch)}.csv" in shown


@pytest.mark.parametrize("start", ["=", "+", "-", "@", "\t"], ids=repr)
def test_validate_markdown_quotes_a_cell_a_spreadsheet_would_run(start, tmp_path):
    summary = _summary("impl", "")
    summary["results"][0]["impl"] = f'{start}HYPERLINK("http://evil.example","x")'
    text = write_markdown(summary, tmp_path / "m.md").read_text()
    (row,) = [line for line in text.splitlines() if "HYPERLINK" in line]
    cells = row[len("| "):].split(" | ")
    assert cells[0].startswith("'") and cells[1].startswith("'")     # the implementation and the case
