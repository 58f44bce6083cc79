"""A validation summary as the files CI systems read: JUnit XML and a Markdown digest.

One JUnit test case per (dataset, n, seed, implementation[, exact peer]) row of
``summary.json``: a failing verdict is a ``<failure>`` with the verdict's message, an
``unsupported`` row is ``<skipped>``. The Markdown digest (for ``$GITHUB_STEP_SUMMARY`` or a
pull-request comment) says whether the gate passed and lists every failure. Text from the
results is escaped: XML by the serializer, Markdown by :mod:`vorobench.markdown_text`.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

from vorobench.markdown_text import cell as _cell

__all__ = ["write_junit", "write_markdown"]


def _case_name(row: dict[str, Any]) -> str:
    seed = "" if row.get("seed") is None else f" seed={row['seed']}"
    peer = f" vs {row['exact_peer']}" if row.get("exact_peer") else ""
    return f"{row['impl']}{peer} on {row['dataset']} n={row['n']}{seed}"


def write_junit(summary: dict[str, Any], path: str | Path) -> Path:
    """``summary`` (validate's) as a JUnit XML file; returns its path."""
    rows = summary.get("results", [])
    failed = [r for r in rows if not r["passed"]]
    skipped = [r for r in rows if r["passed"] and r["verdict"] == "unsupported"]
    suite = ET.Element("testsuite", name="vorobench validate", tests=str(len(rows)), failures=str(len(failed)),
                       skipped=str(len(skipped)), errors="0",
                       time=f"{sum(float(r.get('seconds') or 0.0) for r in rows):.3f}")
    for row in rows:
        case = ET.SubElement(suite, "testcase", classname=f"vorobench.{row['impl']}", name=_case_name(row),
                             time=f"{float(row.get('seconds') or 0.0):.3f}")
        if not row["passed"]:
            failure = ET.SubElement(case, "failure", type=str(row["verdict"]), message=str(row["message"])[:500])
            failure.text = str(row["message"])
        elif row["verdict"] == "unsupported":
            ET.SubElement(case, "skipped", message=str(row["message"])[:500])
    for name in summary.get("never_judged", []):
        case = ET.SubElement(suite, "testcase", classname=f"vorobench.{name}", name=f"{name} judged at all")
        ET.SubElement(case, "failure", type="never_judged", message=f"{name} declared every case unsupported")
        suite.set("tests", str(int(suite.get("tests")) + 1))
        suite.set("failures", str(int(suite.get("failures")) + 1))
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    root = ET.Element("testsuites", name="vorobench")
    root.append(suite)
    ET.ElementTree(root).write(path, encoding="utf-8", xml_declaration=True)
    return path


def write_markdown(summary: dict[str, Any], path: str | Path) -> Path:
    """``summary`` (validate's) as a short Markdown digest; returns its path."""
    rows = summary.get("results", [])
    failed = [r for r in rows if not r["passed"]]
    verdict = "passed" if summary.get("passed") else "FAILED"
    lines = [f"## vorobench validate: {verdict}", "",
             f"{summary.get('judged', 0)} of {summary.get('cases', 0)} cases judged against "
             f"`{_cell(summary.get('reference', '?'))}`; {len(rows)} verdicts, {len(failed)} failing, "
             f"{summary.get('lost', 0)} cases lost.", ""]
    if summary.get("never_judged"):
        lines += [f"Never judged (unsupported on every case): {_cell(', '.join(summary['never_judged']))}", ""]
    if failed:
        lines += ["| implementation | case | verdict | message |", "|---|---|---|---|"]
        lines += [f"| {_cell(r['impl'])} | {_cell(_case_name(r))} | {_cell(r['verdict'])} | {_cell(r['message'])[:300]} |"
                  for r in failed]
        lines.append("")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines))
    return path
