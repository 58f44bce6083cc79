"""Verdicts as the files CI systems read: JUnit XML and a Markdown digest, for validate and compare.

validate: one JUnit test case per (dataset, n, seed, implementation[, exact peer]) row of
``summary.json``: a failing verdict is a ``<failure>`` with the verdict's message, an
``unsupported`` row is ``<skipped>``. The Markdown digest (for ``$GITHUB_STEP_SUMMARY`` or a
pull-request comment) says whether the gate passed and lists every failure. compare: one test
case per case of BASE or NEW (a flag is a ``<failure>``, an inconclusive timing ``<skipped>``)
plus one for the combined timing verdict, and a ``<skipped>`` one saying so when NEW did not
check correctness. Text from the results is escaped: XML by the serializer, Markdown by
:mod:`vorobench.harness.markdown_text`; characters no reader takes (control characters, lone
surrogates) become visible escapes (:func:`printable`), and a Markdown table cell that a
spreadsheet would run as a formula is quoted.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

from vorobench.harness.markdown_text import cell as _cell
from vorobench.judge.outcomes import CertificateLevel, Verdict
from vorobench.judge.wire import escaped

__all__ = ["write_junit", "write_markdown", "write_compare_junit", "write_compare_markdown", "printable",
           "formula_safe"]

# A cell starting with one of these is a formula to a spreadsheet the table is pasted into.
_FORMULA_START = ("=", "+", "-", "@", "\t", "\r")


def printable(value: object) -> str:
    """``value`` as text any file, XML parser or terminal takes (the wire's own rule,
    :func:`vorobench.judge.wire.escaped`): each unsafe character shown as its escape."""
    return escaped(value)


def formula_safe(text: str) -> str:
    """``text`` with a leading quote when a spreadsheet would read it as a formula (``=HYPERLINK(``)."""
    return "'" + text if text.startswith(_FORMULA_START) else text


def _md(value: object) -> str:
    """A value from the results as Markdown inline text."""
    return _cell(printable(value))


def _md_cell(value: object) -> str:
    """A value from the results as a Markdown table cell, safe to paste into a spreadsheet."""
    return _cell(formula_safe(printable(value)))


def _case_name(row: dict[str, Any]) -> str:
    """A validate record as one case: its dataset named with its weight or radius family, if any."""
    from vorobench.harness.results import dataset_label  # pandas: only when a file is written

    seed = "" if row.get("seed") is None else f" seed={row['seed']}"
    peer = f" vs {row['exact_peer']}" if row.get("exact_peer") else ""
    dataset = dataset_label(str(row["dataset"]), str(row.get("weights") or ""), str(row.get("radii") or ""))
    return f"{row['impl']}{peer} on {dataset} n={row['n']}{seed}"


def write_junit(summary: dict[str, Any], path: str | Path) -> Path:
    """``summary`` (validate's) as a JUnit XML file; returns its path."""
    rows = summary.get("results", [])
    failed = [r for r in rows if not r["passed"]]
    skipped = [r for r in rows if r["passed"] and r["verdict"] == Verdict.UNSUPPORTED]
    suite = ET.Element("testsuite", name="vorobench validate", tests=str(len(rows)), failures=str(len(failed)),
                       skipped=str(len(skipped)), errors="0",
                       time=f"{sum(float(r.get('seconds') or 0.0) for r in rows):.3f}")
    for row in rows:
        case = ET.SubElement(suite, "testcase", classname=f"vorobench.{row['impl']}", name=_case_name(row),
                             time=f"{float(row.get('seconds') or 0.0):.3f}")
        properties = ET.SubElement(case, "properties")
        for key in ("verdict", "certificate_level", "reference_certificate_level"):
            if row.get(key):
                ET.SubElement(properties, "property", name=key.replace("_level", ""), value=str(row[key]))
        if not row["passed"]:
            failure = ET.SubElement(case, "failure", type=str(row["verdict"]), message=str(row["message"])[:500])
            failure.text = str(row["message"])
        elif row["verdict"] == Verdict.UNSUPPORTED:
            ET.SubElement(case, "skipped", message=str(row["message"])[:500])
    for name in summary.get("never_judged", []):
        case = ET.SubElement(suite, "testcase", classname=f"vorobench.{name}", name=f"{name} judged at all")
        ET.SubElement(case, "failure", type="never_judged", message=f"{name} declared every case unsupported")
        suite.set("tests", str(int(suite.get("tests")) + 1))
        suite.set("failures", str(int(suite.get("failures")) + 1))
    if summary.get("nothing_judged"):
        names = ", ".join(summary["nothing_judged"])
        case = ET.SubElement(suite, "testcase", classname="vorobench.gate", name="anything judged at all")
        ET.SubElement(case, "failure", type="nothing_judged",
                      message=f"nothing of {names} was judged: unsupported on every case")
        suite.set("tests", str(int(suite.get("tests")) + 1))
        suite.set("failures", str(int(suite.get("failures")) + 1))
    return _write_suite(suite, path)


def _write_suite(suite: ET.Element, path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    root = ET.Element("testsuites", name="vorobench")
    root.append(suite)
    _make_printable(root)
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)
    return path


def _make_printable(root: ET.Element) -> None:
    """Every text and attribute under ``root`` through :func:`printable`: the serializer escapes
    markup but writes forbidden characters as they are, which no XML parser then reads."""
    for element in root.iter():
        element.attrib = {key: printable(value) for key, value in element.attrib.items()}
        if element.text is not None:
            element.text = printable(element.text)
        if element.tail is not None:
            element.tail = printable(element.tail)


def certificate_counts(rows: list[dict[str, Any]]) -> dict[str, int]:
    """How many judged diagrams reached each certificate level, in the levels' order (each
    implementation's own diagram once per row; the reference's on its own row)."""
    found = [str(r.get("certificate_level") or "") for r in rows]
    return {level.value: found.count(level.value) for level in CertificateLevel if level.value in found}


def write_markdown(summary: dict[str, Any], path: str | Path) -> Path:
    """``summary`` (validate's) as a short Markdown digest; returns its path."""
    rows = summary.get("results", [])
    failed = [r for r in rows if not r["passed"]]
    verdict = "passed" if summary.get("passed") else "FAILED"
    lines = [f"## vorobench validate: {verdict}", "",
             f"{summary.get('judged', 0)} of {summary.get('cases', 0)} cases judged against "
             f"`{_md(summary.get('reference', '?'))}`; {len(rows)} verdicts, {len(failed)} failing, "
             f"{summary.get('lost', 0)} cases lost.", ""]
    levels = certificate_counts(rows)
    if levels:
        lines += ["Certificates: " + ", ".join(f"{count} {level.replace('_', ' ')}" for level, count in levels.items())
                  + " (`certified`: exact topology; `certified within tolerance`: differs from the exact diagram "
                  "only at near-degenerate configurations, the standard for floating-point libraries).", ""]
    if summary.get("never_judged"):
        lines += [f"Never judged (unsupported on every case): {_md(', '.join(summary['never_judged']))}", ""]
    if summary.get("nothing_judged"):
        lines += [f"Nothing judged: {_md(', '.join(summary['nothing_judged']))} unsupported on every case, so the "
                  f"gate does not pass.", ""]
    if failed:
        lines += ["| implementation | case | verdict | certificate | message |", "|---|---|---|---|---|"]
        lines += [f"| {_md_cell(r['impl'])} | {_md_cell(_case_name(r))} | {_md_cell(r['verdict'])} | "
                  f"{_md_cell(r.get('certificate_level') or '-')} | {_md_cell(r['message'])[:300]} |" for r in failed]
        lines.append("")
    return _write_text(lines, path)


def _write_text(lines: list[str], path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    # printable() again: any text a caller did not pass through it still cannot break the file.
    path.write_text(printable("\n".join(lines) + "\n"), encoding="utf-8")
    return path


def write_compare_junit(comparison, path: str | Path, base: str, new: str) -> Path:
    """A :class:`vorobench.harness.regress.RunComparison` as JUnit XML; returns its path."""
    changes = comparison.changes
    failures = sum(1 for c in changes if c.flagged) + bool(comparison.overall.flags)
    skipped = sum(1 for c in changes if c.change == "inconclusive" and not c.flagged)
    suite = ET.Element("testsuite", name=f"vorobench compare {new} vs {base}", tests=str(len(changes) + 1),
                       failures=str(failures), skipped=str(skipped), errors="0")
    for c in changes:
        case = ET.SubElement(suite, "testcase", classname=f"vorobench.{c.impl}", name=c.name,
                             time=f"{c.new_median_s or 0.0:.6f}")
        if c.flagged:
            message = "; ".join(c.flags)
            kind = "not_comparable" if c.why_not_comparable else "regression"
            ET.SubElement(case, "failure", type=kind, message=message[:500]).text = message
        elif c.change == "inconclusive":
            ET.SubElement(case, "skipped", message=f"timing inconclusive: {c.why_inconclusive}"[:500])
    overall = ET.SubElement(suite, "testcase", classname="vorobench.all", name="all cases together (geometric mean)")
    if comparison.overall.flags:
        message = "; ".join(comparison.overall.flags)
        ET.SubElement(overall, "failure", type="regression", message=message[:500]).text = message
    if comparison.unchecked:
        _add_unchecked_case(suite, comparison)
    return _write_suite(suite, path)


def _unchecked_text(comparison) -> str:
    """One sentence on the compared cases whose correctness NEW did not check."""
    return (f"correctness not checked in {len(comparison.unchecked)} of {len(comparison.compared)} compared "
            "case(s) of NEW (verdict skipped: bench --no-check?): judged on timings and counters only")


def _add_unchecked_case(suite: ET.Element, comparison) -> None:
    """A skipped test case saying NEW's correctness was not checked, so a CI page shows it."""
    case = ET.SubElement(suite, "testcase", classname="vorobench.all", name="correctness checked in NEW")
    ET.SubElement(case, "skipped", message=_unchecked_text(comparison))
    suite.set("tests", str(int(suite.get("tests")) + 1))
    suite.set("skipped", str(int(suite.get("skipped")) + 1))


def _ratio(c) -> str:
    if c.ratio is None:
        return "-"
    ci = f" ({c.ci_low:.2f}-{c.ci_high:.2f})" if c.ci_low is not None else ""
    return f"{c.ratio:.3f}{ci}"


def write_compare_markdown(comparison, path: str | Path, base: str, new: str, only_changes: bool = False) -> Path:
    """A :class:`vorobench.harness.regress.RunComparison` as a short Markdown digest; returns its path.
    ``only_changes``: the table lists only the notable cases (as the console's does)."""
    o = comparison.overall
    verdict = "no regression" if comparison.passed else "REGRESSION"
    if comparison.unchecked:
        verdict += " (correctness not checked)"
    lines = [f"## vorobench compare: {verdict}", "",
             f"`{_md(new)}` against `{_md(base)}`, threshold {comparison.threshold:.0%}, alpha "
             f"{comparison.alpha:g}: {len(comparison.compared)} case(s) compared, {len(comparison.flagged)} "
             f"flagged, {len(comparison.missing)} missing in NEW, {len(comparison.not_comparable)} not comparable, "
             f"{len(comparison.inconclusive)} inconclusive.", ""]
    if comparison.unchecked:
        lines += [f"**{_md(_unchecked_text(comparison))}**", ""]
    if o.geomean is not None:
        ci = f" (95% CI {o.ci_low:.3f}-{o.ci_high:.3f})" if o.ci_low is not None else ""
        lines += [f"All {o.cases} timed cases together: NEW / BASE = **{o.geomean:.3f}**{ci}, {o.change}.", ""]
    if comparison.noise is not None:
        lines += [f"Run-to-run noise band: x{math.exp(comparison.noise):.2f} either way (a single case's change "
                  "inside it is inconclusive).", ""]
    shown = [c for c in comparison.changes if c.notable or not only_changes]
    if only_changes:
        lines += [f"{len(comparison.changes) - len(shown)} unchanged case(s) left out (--only-changes).", ""]
    lines += ["| case | base | new | ratio (95% CI) | timing | verdict | flags |", "|---|---|---|---|---|---|---|"]
    for c in shown:
        verdict_cell = c.new_verdict if c.base_verdict == c.new_verdict else f"{c.base_verdict} -> {c.new_verdict}"
        lines.append(f"| {_md_cell(c.name)} | {_seconds(c.base_median_s)} | {_seconds(c.new_median_s)} | "
                     f"{_ratio(c)} | {_md_cell(c.change) if c.change else '-'} | "
                     f"{_md_cell(verdict_cell) if verdict_cell else '-'} | "
                     f"{_md_cell('; '.join(c.flags))[:300] or ''} |")
    return _write_text(lines, path)


def _seconds(x) -> str:
    if x is None:
        return "-"
    return f"{x * 1e3:.3g} ms" if x < 1 else f"{x:.3g} s"
