"""Compare two benchmark runs case by case and as a whole; flag slowdowns, counter changes and lost correctness.

    vorobench compare BASE NEW [--threshold 0.10] [--junit FILE] [--markdown FILE]

BASE and NEW are results files (.csv or .parquet) or runs of a run store (``DIR@latest``,
``DIR@latest~1``, ``DIR@<run id>``, ``DIR@<commit>``; see :mod:`vorobench.harness.store`).

Timings gate statistically, per case (implementation, dataset, n, seed) and over all cases:

* **per case**: the ratio of median times NEW / BASE, a percentile bootstrap interval of it
  (``scipy.stats.bootstrap``) and a one-sided Mann-Whitney U test (``scipy.stats.mannwhitneyu``).
  A case is *slower* when the ratio exceeds 1 + threshold, its interval lies above 1 and the
  rank test gives p < alpha; *faster* likewise; *same* when its interval lies within
  1 ± threshold, which rules out a change of the threshold. Anything else is *inconclusive*:
  its repeats can tell neither (too few of them for the rank test to reach alpha, or too much
  noise), and the output says so, and what would decide it, instead of passing it silently.
  A change inside the measured run-to-run noise (the spread of all cases' ratios, from six
  cases on, or the case's own spread over earlier runs of a store) is inconclusive too.
  ``trend`` marks a step by the same rule (``vorobench.harness.timing_rule``), so the two
  give one answer for a pair of runs.
* **over all cases**: the geometric mean of the per-case ratios with a t interval of the mean
  log ratio (``scipy.stats.ttest_1samp``). A uniform slowdown too small for any one case's
  repeats is flagged here when the mean exceeds 1 + threshold and its interval lies above 1.

Counters (``stat_*``, machine-independent integers) gate exactly: any change is flagged.
So is a case that got a worse verdict or status, or that NEW lacks (a run that lost cases must
not pass for having fewer to compare), or that NEW no longer checks (``bench --no-check``)
while BASE did, or that cannot be compared (no usable timing on a side: missing, zero). A
NEW whose cases were not checked on either side passes on timings and counters alone, and
says so. Exit status 1 when anything is flagged, else 0; 2 when an input is not a results
table with at least one case, holds a case twice (run twice into one file), or an option
makes no sense (an output path that cannot be written is one, found before comparing).
"""

from __future__ import annotations

import argparse
import json
import math
import os
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Optional

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from vorobench.cli.args import fraction, non_negative_int, positive_float
from vorobench.judge.outcomes import Status, Verdict

if TYPE_CHECKING:  # annotations only: the module itself is loaded when the command runs
    from vorobench.harness.regress import CaseChange, RunComparison

# The harness and the judge are imported inside the functions that run the command, not here:
# the parser imports every command module (start-up time, measured in vorobench.cli).

__all__ = ["add_arguments", "run", "check_outputs"]


#: The options of ``compare`` besides its two inputs (``continuous`` passes them on).
OPTION_NAMES = ("threshold", "alpha", "seed", "measure", "relative_to", "only_changes", "json", "junit", "markdown")


def add_arguments(p, positional: bool = True) -> None:
    """``compare``'s arguments on ``p`` (a parser or an argument group); ``positional=False``
    leaves out BASE and NEW, for a command that makes them itself."""
    if positional:
        p.add_argument("base", help="baseline: a results file (.csv/.parquet) or a run store reference DIR@REF "
                                    "(REF: latest, latest~K, a run id or a commit)")
        p.add_argument("new", help="new results: a file or DIR@REF")
    p.add_argument("--threshold", type=positive_float, default=0.10,
                   help="flag slowdowns above this fraction, > 0 (default 0.10 = 10%%)")
    p.add_argument("--alpha", type=fraction, default=0.05,
                   help="significance level, between 0 and 1 (default 0.05)")
    p.add_argument("--seed", type=non_negative_int, default=0, help="bootstrap seed (default 0)")
    p.add_argument("--measure", choices=("auto", "cpu", "wall"), default="auto",
                   help="what a build's time is: cpu (the build's own CPU time, which a busy machine does not add "
                        "to), wall, or auto (default: cpu when both runs recorded it for every build, else wall)")
    p.add_argument("--relative-to", default=None, metavar="IMPL",
                   help="compare each build time divided by IMPL's median time on the same case of the same run "
                        "(e.g. qhull): the machine's speed cancels; IMPL must be timed in both runs")
    p.add_argument("--only-changes", action="store_true",
                   help="show only flagged, changed or inconclusive cases")
    p.add_argument("--json", default=None, help="also write every comparison to this JSON file")
    p.add_argument("--junit", default=None, metavar="FILE",
                   help="also write a JUnit XML file: one test case per compared case, plus the combined verdict")
    p.add_argument("--markdown", default=None, metavar="FILE",
                   help="also write a Markdown summary (for $GITHUB_STEP_SUMMARY or a pull-request comment)")


def _shown(text: object) -> str:
    """Text from the results or the command line as console markup that shows just its
    characters: control characters as escapes (rich's ``escape`` passes ESC on to the terminal),
    brackets escaped."""
    from vorobench.harness.ci_outputs import printable

    return escape(printable(text))


def _check_output(option: str, value: Optional[str]) -> None:
    """ValueError when ``option value`` names no file that can be written (a directory, a path
    under a file, a folder or file without write permission)."""
    if not value:
        return
    path = Path(value)
    if path.is_dir():
        raise ValueError(f"{option} {value}: is a directory; give a file name")
    folder = next(p for p in (path.parent, *path.parent.parents) if p.exists())
    if not folder.is_dir():
        raise ValueError(f"{option} {value}: {folder} is a file, not a folder")
    writable = os.access(path, os.W_OK) if path.exists() else os.access(folder, os.W_OK | os.X_OK)
    if not writable:
        raise ValueError(f"{option} {value}: not writable")


def check_outputs(args: argparse.Namespace) -> None:
    """Refuse, before anything is compared (or benchmarked), an output file that cannot be written."""
    for option in ("json", "junit", "markdown"):
        _check_output(f"--{option}", getattr(args, option, None))


def _fmt_s(x: Optional[float]) -> str:
    if x is None:
        return "-"
    return f"{x * 1e3:.3g} ms" if x < 1 else f"{x:.3g} s"


#: Lost cases listed by name; the rest are counted.
_MISSING_LISTED = 5


def _print_missing(console, missing: list[CaseChange]) -> None:

    console.print(f"[bold red]NEW lacks {len(missing)} case(s) that BASE has[/bold red]:")
    _print_some(console, [c.name for c in missing])


def _print_some(console, lines: list[str]) -> None:
    """The first :data:`_MISSING_LISTED` of ``lines``, indented, and how many more there are."""
    for line in lines[:_MISSING_LISTED]:
        console.print(f"  {_shown(line)}", highlight=False)
    if len(lines) > _MISSING_LISTED:
        console.print(f"  and {len(lines) - _MISSING_LISTED} more")


def _print_not_comparable(console, cases: list[CaseChange]) -> None:
    console.print(f"[bold red]{len(cases)} case(s) not comparable[/bold red] (this gate cannot judge them):")
    _print_some(console, [f"{c.name}: {c.why_not_comparable}" for c in cases])


def _print_unchecked(console, comparison: RunComparison) -> None:
    """Say loudly that NEW's correctness was not checked, and what the gate judged instead."""
    unchecked = comparison.unchecked
    lost = [c for c in unchecked if c.check_lost]
    console.print(f"[bold yellow]correctness not checked[/bold yellow] in {len(unchecked)} of "
                  f"{len(comparison.compared)} compared case(s) of NEW (verdict skipped: bench --no-check?)"
                  + (f"; {len(lost)} of them were checked in BASE (flagged)" if lost else
                     "; they are judged on timings and counters only"))


def _verdict_text(c: CaseChange) -> str:

    if c.base_status is None:
        return f"only in NEW ({c.new_status})"
    if c.new_status is None:
        return f"only in BASE ({c.base_status})"
    if c.base_verdict == c.new_verdict:
        return "not checked" if c.new_verdict == Verdict.SKIPPED and c.new_status == Status.OK else str(
            c.new_verdict or c.new_status)
    return f"{c.base_verdict} -> {c.new_verdict}"


def _overall_text(comparison: RunComparison) -> str:
    from vorobench.harness.regress import NOISE_MIN_CASES

    o = comparison.overall
    if o.geomean is None:
        return "no case timed on both sides"
    ci = f", 95% CI {o.ci_low:.3f}-{o.ci_high:.3f}" if o.ci_low is not None else ""
    band = (f"; run-to-run noise band x{math.exp(comparison.noise):.2f} either way" if comparison.noise is not None
            else f"; too few cases (< {NOISE_MIN_CASES}) to measure the run-to-run noise")
    return f"geometric mean ratio {o.geomean:.3f} over {o.cases} case(s){ci}: {o.change or 'n/a'}{band}"


def _print_table(console, comparison: RunComparison, title: str, only_changes: bool) -> None:

    table = Table(title=_shown(title))
    table.add_column("case", no_wrap=True)
    for col in ("base", "new", "ratio", "95% CI", "p"):
        table.add_column(col, justify="right", no_wrap=True)
    table.add_column("timing")
    table.add_column("verdict")
    table.add_column("flags", overflow="fold")
    shown = 0
    for c in comparison.changes:
        if only_changes and not c.notable:
            continue
        shown += 1
        colour = {"slower": "red", "faster": "green", "inconclusive": "yellow"}.get(c.change, "")
        ratio = f"{c.ratio:.3f}" if c.ratio is not None else "-"
        timing = f"[{colour}]{c.change}[/{colour}]" if colour else c.change
        ci = f"{c.ci_low:.2f}-{c.ci_high:.2f}" if c.ci_low is not None else "-"
        p = f"{c.p_value:.3g}" if c.p_value is not None else "-"
        flags = _shown("; ".join(c.flags))
        table.add_row(_shown(f"{c.impl} {c.dataset} n={c.n} s={c.seed}"), _fmt_s(c.base_median_s),
                      _fmt_s(c.new_median_s), ratio, ci, p, timing, _shown(_verdict_text(c)),
                      f"[bold red]{flags}[/bold red]" if flags else "")
    if shown:
        console.print(table)


def run(args: argparse.Namespace) -> int:
    from vorobench.harness.regress import (compare_runs, load_side, machine_warning, refuse_duplicates,
                                           store_history)

    check_outputs(args)
    base_df, base_meta = load_side(args.base)
    new_df, new_meta = load_side(args.new)
    refuse_duplicates(base_df, f"BASE {args.base}")
    refuse_duplicates(new_df, f"NEW {args.new}")
    from vorobench.harness.timing_rule import choose_measure, measured

    column = choose_measure(getattr(args, "measure", "auto"), base_df, new_df)
    base_df, new_df = measured(base_df, column), measured(new_df, column)
    relative = getattr(args, "relative_to", None)
    if relative:
        from vorobench.harness.regress import relative_to

        base_df, new_df = relative_to(base_df, relative, "BASE"), relative_to(new_df, relative, "NEW")
    history = store_history(args.base, base_meta, new_df)
    if history is not None:
        history = measured(history, column) if column == "time_s" or choose_measure("auto", history) == column \
            else None                        # earlier runs without CPU times measure no CPU noise
    if relative and history is not None:
        history = relative_to(history, relative, "the store's earlier runs")
    comparison = compare_runs(base_df, new_df, threshold=args.threshold, alpha=args.alpha, seed=args.seed,
                              history=history)
    console = Console()
    if not console.is_terminal:
        console = Console(width=max(console.width, 140))     # logs (CI) are wide, keep rows on one line
    warning = machine_warning(base_meta, new_meta)
    if warning:
        console.print(f"[yellow]warning[/yellow]: {_shown(warning)}")
    title = getattr(args, "title", None) or f"{args.new} vs {args.base}"
    console.print("build times compared: " + ("CPU time of each build (both runs recorded it; a busy machine does "
                                              "not add to it)" if column == "cpu_s" else "wall time"))
    if relative:
        console.print(f"times are relative to {_shown(relative)}: each build time over {_shown(relative)}'s median "
                      f"on the same case of the same run (base and new columns are these ratios, not seconds)")
    _print_table(console, comparison, f"{title} (threshold {args.threshold:.0%})",
                 args.only_changes)
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps({
            "passed": comparison.passed, "threshold": args.threshold, "alpha": args.alpha,
            "compared": len(comparison.compared), "not_comparable": len(comparison.not_comparable),
            "unchecked": len(comparison.unchecked),
            "overall": asdict(comparison.overall),
            "noise_band": None if comparison.noise is None else math.exp(comparison.noise),
            "cases": [asdict(c) | {"flagged": c.flagged} for c in comparison.changes]},
            indent=2, default=str) + "\n")
    if args.junit or args.markdown:
        from vorobench.harness import ci_outputs

        if args.junit:
            ci_outputs.write_compare_junit(comparison, args.junit, str(args.base), str(args.new))
        if args.markdown:
            ci_outputs.write_compare_markdown(comparison, args.markdown, str(args.base), str(args.new),
                                              only_changes=args.only_changes)
    compared, flagged, missing = comparison.compared, comparison.flagged, comparison.missing
    console.print(_shown(_overall_text(comparison)))
    inconclusive = comparison.inconclusive
    if inconclusive:
        console.print(f"[yellow]{len(inconclusive)} case(s) inconclusive[/yellow]: their timings cannot tell a "
                      f"{args.threshold:.0%} change from noise (e.g. {_shown(inconclusive[0].name)}: "
                      f"{_shown(inconclusive[0].why_inconclusive)}); more repeats (bench --repeat, --min-time) "
                      "or a quieter machine would decide them")
    if not compared:
        console.print(f"[bold red]no case in common[/bold red]: {_shown(args.new)} has none of the cases of "
                      f"{_shown(args.base)} that can be compared")
    for flag in comparison.overall.flags:
        console.print(f"[bold red]flagged[/bold red]: {_shown(flag)}")
    if flagged:
        console.print(f"[bold red]{len(flagged)} of {len(compared)} compared case(s) flagged[/bold red]")
    if comparison.not_comparable:
        _print_not_comparable(console, comparison.not_comparable)
    if missing:
        _print_missing(console, missing)
    if comparison.unchecked:
        _print_unchecked(console, comparison)
    if not comparison.passed:
        return 1
    faster = sum(1 for c in comparison.changes if c.change == "faster")
    console.print(f"[green]no regression[/green] in {len(compared)} compared case(s)"
                  + (f"; {faster} clearly faster" if faster else "")
                  + ("; [bold yellow]correctness not checked[/bold yellow]: timings and counters only"
                     if comparison.unchecked else ""))
    return 0
