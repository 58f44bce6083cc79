"""Figures plus a Markdown report and a self-contained HTML page from a results file.

    vorobench report results/bench.csv -o reports/NAME

writes ``README.md`` (Markdown; GitHub shows it for the folder), ``report.html`` (an
interactive page in one file that works offline, with filters, hover details and every case's
repeats), the PNG figures (only those with data) and a copy of the results with their metadata.
Both pages open with the fits whose growth exceeds the declared complexity by more than 0.3 in
the exponent (the rule: vorobench.harness.analysis).

Everything taken from the results or their metadata (names, errors, host, command line) is
shown as text, never as markup, in both pages: a ``<script>`` in an error message stays text.
"""

from __future__ import annotations

import argparse
from pathlib import Path


# The harness and the judge are imported inside the functions that run the command, not here:
# the parser imports every command module (start-up time, measured in vorobench.cli).

__all__ = ["add_arguments", "run"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("results", help="results file from `vorobench bench` (.csv or .parquet)")
    p.add_argument("-o", "--out", default=None, help="report folder (default reports/<results stem>)")
    p.add_argument("--title", default=None, help="report title (default: the folder name)")
    p.add_argument("--reference", default=None,
                   help="implementation the speed ratios are relative to (default: the run's reference, else qhull)")
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE",
                   help="accepted for older scripts and ignored: the run's metadata records what each implementation declared")


def run(args: argparse.Namespace) -> int:
    from vorobench.harness.report import write_report

    results = Path(args.results)
    out = Path(args.out) if args.out else Path("reports") / results.stem
    # Declared complexities come from the run's metadata (pinned when it ran): no plugin is imported.
    rep = write_report(results, out, title=args.title, reference=args.reference)
    print(f"wrote {rep.markdown} and {rep.html} ({len(rep.figures)} figures)")
    return 0
