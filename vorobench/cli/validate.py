"""Cross-validate implementations against a reference on every dataset; shrink failures to witnesses.

Every case is built by each implementation (an exception is recorded as a crash), each diagram
is certified, and each is compared with the reference, which is certified too. Prints a matrix
implementation x dataset, writes ``summary.json`` and, for every failure, a small witness
(``.npy``, the command that reproduces it, a PNG) under ``--out``. Exit status 1 if anything
is wrong.

With ``--weights FAMILY`` every case is the power diagram of its points with weights of that
family (``--weights file:PATH`` reads them, one per point, for ``--points``). The reference
must take weights; an implementation that does not is ``unsupported`` on every case and is
left out of the gate (it says so), and a witness keeps its weights (``NAME.weights.npy``).

With ``--radii FAMILY`` every case is the diagram of disks centred at its points with radii of
that family (docs/apollonius.md; ``--radii file:PATH`` reads one radius per point of
``--points``), judged by the certificate and comparison of disks
(:mod:`vorobench.judge.disk_judging`). The reference must take disks; a witness is shrunk with
its radii kept row for row (``NAME.radii.npy``).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Optional

import numpy as np
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

import datasets_gen
from impls import DEFAULT_REFERENCE
from vorobench.cli import args as cli_args
from vorobench.cli.bench import radius_family, weight_family
from vorobench.judge.defaults import DEFAULT_PROBES, DEFAULT_TIMEOUT
from vorobench.judge.outcomes import Verdict

if TYPE_CHECKING:  # annotations only: the module itself is loaded when the command runs
    from vorobench.judge.declarations import Declaration
    from vorobench.harness.validation import ValidationCase

# The harness and the judge are imported inside the functions that run the command, not here:
# the parser imports every command module (start-up time, measured in vorobench.cli).

__all__ = ["add_arguments", "run"]

_STYLE = {Verdict.EXACT: "green", Verdict.WITHIN_TOLERANCE: "green", Verdict.CERTIFIED: "green",
          Verdict.UNSUPPORTED: "dim", Verdict.DIFFERS: "bold red", Verdict.NOT_CERTIFIED: "bold red",
          Verdict.CRASHED: "bold red", Verdict.TIMEOUT: "bold red", Verdict.OOM: "bold red",
          Verdict.MUTATED_INPUT: "bold red"}
_SHORT = {Verdict.WITHIN_TOLERANCE: "within tol", Verdict.NOT_CERTIFIED: "NOT CERTIFIED", Verdict.DIFFERS: "DIFFERS",
          Verdict.CRASHED: "CRASHED", Verdict.TIMEOUT: "TIMEOUT", Verdict.OOM: "OUT OF MEMORY",
          Verdict.MUTATED_INPUT: "MUTATED INPUT"}


def add_arguments(p: argparse.ArgumentParser) -> None:

    p.add_argument("--impls", type=cli_args.names, default=["all"],
                   help="comma-separated implementations (default: all available)")
    p.add_argument("--datasets", type=cli_args.names, default=["all"],
                   help="comma-separated datasets, or 'all' (default); '-name' leaves one out ('all,-near_grid')")
    p.add_argument("--sizes", type=cli_args.sizes, default=[10, 100, 1000], help="comma-separated sizes (default 10,100,1000)")
    p.add_argument("--seeds", type=cli_args.seeds, default=[0], help="comma-separated dataset seeds (default 0)")
    p.add_argument("--reference", default=DEFAULT_REFERENCE, help=f"reference implementation (default {DEFAULT_REFERENCE})")
    p.add_argument("--points", help="validate the points of this file (.npy/.csv/.txt) instead of datasets")
    p.add_argument("--weights", type=_weights_option, default=None, metavar="FAMILY",
                   help="validate power diagrams: weights of this family (radii, equal, integer, hidden; see "
                        "`vorobench datasets`), or file:PATH (one per point of --points); implementations "
                        "without weights are reported unsupported")
    p.add_argument("--radii", type=_radii_option, default=None, metavar="FAMILY",
                   help="validate diagrams of disks: radii of this family (random, separate, equal, nested, "
                        "tangent, integer, huge, last_bit; see `vorobench datasets`), or file:PATH (one per point "
                        "of --points); implementations without disks are reported unsupported")
    p.add_argument("--out", default="reports/validate", help="directory for summary.json and witnesses "
                                                             "(default reports/validate)")
    p.add_argument("--probes", type=cli_args.non_negative_int, default=DEFAULT_PROBES,
                   help=f"random probes per certificate (default {DEFAULT_PROBES})")
    p.add_argument("--timeout", type=cli_args.positive_float, default=DEFAULT_TIMEOUT,
                   help=f"seconds each implementation may take to build and certify one case "
                        f"(default {DEFAULT_TIMEOUT:g}; its warm-up has --warmup-timeout)")
    p.add_argument("--warmup-timeout", type=cli_args.positive_float, default=300.0,
                   help="seconds for starting an implementation's worker, JIT compilation included (default 300)")
    p.add_argument("--memory-limit", type=cli_args.positive_float, default=None, metavar="MB",
                   help="address space an implementation's worker may add (MemoryError instead of the OOM killer)")
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE",
                   help="extra implementations: a module or .py file defining IMPLEMENTATIONS, or a "
                        "program's manifest (impl.toml; docs/executables.md); repeatable")
    p.add_argument("--junit", metavar="FILE", help="also write the verdicts as JUnit XML (one test case per row)")
    p.add_argument("--markdown", metavar="FILE",
                   help="also write a Markdown digest (for $GITHUB_STEP_SUMMARY or a pull-request comment)")
    p.add_argument("--no-shrink", action="store_true", help="save failing point sets as they are, unshrunk")
    p.add_argument("--shrink-seconds", type=cli_args.non_negative_float, default=120.0,
                   help="time budget per witness (default 120)")
    p.add_argument("--executor", default="local", help="where cases are judged: 'local' (default) or dask://HOST:PORT")
    p.add_argument("--workers", type=cli_args.positive_int, default=1,
                   help="cases judged at once (default 1); every implementation runs in its own worker either way")


def _weights_option(text: str) -> str:
    """``--weights``: a weight family, or ``file:PATH`` of a weights file."""
    if text.startswith("file:") and len(text) > len("file:"):
        return text
    return weight_family(text)


def _radii_option(text: str) -> str:
    """``--radii``: a radius family, or ``file:PATH`` of a radii file."""
    if text.startswith("file:") and len(text) > len("file:"):
        return text
    return radius_family(text)


def _weights_of(args: argparse.Namespace, points: np.ndarray, seed: Optional[int]) -> Optional[np.ndarray]:
    """The weights of a case's points under ``--weights`` (None: ordinary diagrams)."""
    family = args.weights
    if family is None:
        return None
    if family.startswith("file:"):
        w = datasets_gen.load_weights(family[len("file:"):])
        if w.shape[0] != points.shape[0]:
            raise ValueError(f"{family}: {w.shape[0]} weights for {points.shape[0]} points")
        return w
    return datasets_gen.weights(family, points, seed=seed or 0)


def _cases(args: argparse.Namespace) -> list["ValidationCase"]:
    """Every case of the run: the points of ``--points``, or each dataset x size x seed."""
    from vorobench.harness.validation import ValidationCase

    if args.weights is not None and args.weights.startswith("file:") and not args.points:
        raise ValueError("--weights file:PATH gives the weights of --points FILE: give --points too")
    if args.radii is not None and args.radii.startswith("file:") and not args.points:
        raise ValueError("--radii file:PATH gives the radii of --points FILE: give --points too")
    if args.radii is not None and args.weights is not None:
        raise ValueError("--weights (power diagrams) and --radii (disks) go one at a time")
    family = args.weights or ""
    radii_family = "" if args.radii is None else args.radii.rpartition("/")[2] if args.radii.startswith("file:") \
        else args.radii
    if args.points:
        pts = datasets_gen.load(args.points)
        radii = None
        if args.radii is not None:
            radii = datasets_gen.load_weights(args.radii[len("file:"):]) if args.radii.startswith("file:") \
                else datasets_gen.radii(args.radii, pts, seed=0)
            if radii.shape[0] != pts.shape[0]:
                raise ValueError(f"{args.radii}: {radii.shape[0]} radii for {pts.shape[0]} points")
        return [ValidationCase(Path(args.points).name, int(pts.shape[0]), None, family, pts,
                               _weights_of(args, pts, None), radii_family, radii)]
    files = [d for d in args.datasets if d.startswith(datasets_gen.FILE_PREFIX)]
    names = cli_args.selection([d for d in args.datasets if d not in files], datasets_gen.available(), "dataset") \
        if len(files) < len(args.datasets) else []
    names += files
    return [ValidationCase(d, n, s, family, radii_family=radii_family)
            for d in names for n in args.sizes for s in args.seeds]


def _declared(args: argparse.Namespace) -> dict[str, "Declaration"]:
    """The run's implementations, reference first, with what each declares: read once in a
    sandbox (plugins are loaded there, never in this process) and pinned for the run."""
    from vorobench.judge.pinning import resolve_declarations

    names = list(args.impls)
    every = not names or names == ["all"]
    declared = resolve_declarations(None if every else names, tuple(args.plugin), timeout=args.warmup_timeout,
                                    also=(args.reference,))
    if args.weights is not None and not declared[args.reference].weighted:
        weighted = [n for n, d in declared.items() if d.weighted]
        raise ValueError(f"the reference {args.reference} does not take weights, so it cannot judge weighted cases; "
                         f"choose one that does with --reference ({', '.join(weighted) or 'none here'})")
    if args.radii is not None and not declared[args.reference].apollonius:
        takers = [n for n, d in declared.items() if d.apollonius]
        raise ValueError(f"the reference {args.reference} does not take disks, so it cannot judge cases of disks; "
                         f"choose one that does with --reference ({', '.join(takers) or 'none here'})")
    # The reference is certified too: it always has a row, first.
    order = [args.reference] + [n for n in declared if n != args.reference and (every or n in names)]
    return {n: declared[n] for n in order}


def run(args: argparse.Namespace) -> int:
    from vorobench.harness import validation
    from vorobench.harness.executors import check_spec
    from vorobench.judge.engine import close_shared_judges

    console = Console()
    check_spec(args.executor)
    _check_outputs(args)
    out = Path(args.out)
    path = validation.mark_unfinished(out)
    declared = _declared(args)
    names = list(declared)
    cases = _cases(args)
    reference = args.reference
    validation.mark_unfinished(out, reference=reference, impls=names, cases=len(cases))
    options = (("probes", args.probes), ("timeout", args.timeout), ("warmup_timeout", args.warmup_timeout),
               ("memory_limit_mb", args.memory_limit), ("plugins", tuple(args.plugin)),
               ("declarations", tuple(declared.items())))
    family = args.weights or ""
    unweighted = [n for n in names if family and not declared[n].weighted]
    if unweighted:
        console.print(f"[dim]weights {escape(family)}: {escape(', '.join(unweighted))} "
                      f"{'does' if len(unweighted) == 1 else 'do'} not take weights: unsupported[/]")
    radii_family = cases[0].radii_family if cases else ""
    no_disks = [n for n in names if radii_family and not declared[n].apollonius]
    if no_disks:
        console.print(f"[dim]radii {escape(radii_family)}: {escape(', '.join(no_disks))} "
                      f"{'does' if len(no_disks) == 1 else 'do'} not take disks: unsupported[/]")
    try:
        with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                      console=console, transient=True) as progress:
            task = progress.add_task("validating", total=len(cases))

            def on_case(case) -> None:
                progress.update(task, description=f"validated {case.label}")
                progress.advance(task)

            # Off this machine a build may run without its sandbox: each case as a whole is bounded.
            limit = None if args.executor == "local" else len(names) * (args.timeout + args.warmup_timeout)
            campaign = validation.run_campaign(cases, names, reference, options, executor=args.executor,
                                               workers=args.workers, case_limit=limit, on_case=on_case)
        validation.write_witnesses(
            campaign, out, names, reference, options, shrink=not args.no_shrink, probes=min(args.probes, 2000),
            seconds=args.shrink_seconds,
            on_witness=lambda f: console.status(f"shrinking {escape(f.impl)} on {escape(f.case.label)} "
                                                f"({f.sites.shape[0]} points)"))
    finally:
        close_shared_judges()
    summary = validation.summarise(campaign, len(cases), names, reference, declared, family, args.timeout,
                                   radii_family)
    _print_matrix(console, summary, names, reference, len(cases), family, radii_family)
    for note in summary["notes"]:
        console.print(f"[dim]note:[/] {escape(note)}")
    for failure in campaign.failures:
        against = f" vs {failure.exact_peer}" if failure.exact_peer else ""
        console.print(f"[red]FAIL[/] {escape(failure.impl)}{escape(against)} on {escape(failure.case.label)}: "
                      f"{failure.verdict.verdict}: {escape(failure.verdict.message[:400])}")
    for label, why in campaign.lost:
        console.print(f"[red]LOST[/] {escape(label)}: {escape(why[:400])}")
    for w in campaign.witnesses:
        console.print(f"  witness: {w['n_points']} points -> {escape(w['points'])}  (picture: {escape(str(w['picture']))}; "
                      f"command in {escape(w['command'])})")
    if summary["never_judged"]:
        console.print(f"[red]NOT JUDGED[/] {escape(', '.join(summary['never_judged']))}: unsupported on every case")
    if summary["nothing_judged"]:
        console.print(f"[red]NOTHING JUDGED[/] {escape(', '.join(summary['nothing_judged']))}: unsupported on every "
                      f"case, so the gate does not pass")
    validation.write_json(path, summary)
    from vorobench.harness.ci_outputs import write_junit, write_markdown

    if args.junit:
        console.print(f"JUnit XML: {write_junit(summary, args.junit)}")
    if args.markdown:
        console.print(f"Markdown digest: {write_markdown(summary, args.markdown)}")
    ok = summary["passed"]
    verdict = f"[red]{len(campaign.failures)} failure(s)[/]" if campaign.failures or not summary["nothing_judged"] \
        else "[red]nothing judged[/]"
    console.print(f"{'[green]all passed[/]' if ok else verdict}: "
                  f"{len(campaign.records)} results written to {escape(str(path))}")
    return 0 if ok else 1


def _check_outputs(args: argparse.Namespace) -> None:
    """Refuse an unusable ``--junit`` or ``--markdown`` path before anything runs."""
    for option, value in (("--junit", args.junit), ("--markdown", args.markdown)):
        if value is None:
            continue
        target = Path(value)
        if target.is_dir():
            raise ValueError(f"{option} {value}: is a directory, give a file name")
        if target.parent.exists() and not target.parent.is_dir():
            raise ValueError(f"{option} {value}: {target.parent} is not a directory")


def _print_matrix(console: Console, summary: dict, names: list[str], reference: str, cases: int, family: str,
                  radii_family: str = "") -> None:
    """Implementation x dataset (datasets as rows so that many fit on a terminal), the worst
    verdict over sizes and seeds."""
    from vorobench.harness.validation import worst

    records = summary["results"]
    table = Table(title=f"cross-validation against {escape(reference)} ({cases} cases"
                        + (f"; power diagrams, {escape(family)} weights)" if family else
                           f"; disks, {escape(radii_family)} radii)" if radii_family else ")"))
    table.add_column("dataset")
    for name in names:
        table.add_column(escape(name) + (" (ref)" if name == reference else ""))
    for d in summary["datasets"]:
        row = [escape(str(d))]
        for name in names:
            vs = [r for r in records if r["impl"] == name and r["dataset"] == d]
            if not vs:
                row.append("")
                continue
            worst_verdict = worst([r["verdict"] for r in vs])
            bad = sum(not r["passed"] for r in vs)
            text = _SHORT.get(worst_verdict, str(worst_verdict))
            if bad:
                text += f" {bad}/{len(vs)}"
                style = _STYLE.get(worst_verdict, "")
            elif any(r["blame"] == "reference" for r in vs):
                text, style = "ref wrong", "yellow"
            else:
                style = _STYLE.get(worst_verdict, "")
            row.append(f"[{style}]{text}[/]" if style else text)
        table.add_row(*row)
    console.print(table)
    from vorobench.harness.ci_outputs import certificate_counts

    levels = []
    for name in names:
        counts = certificate_counts([r for r in records if r["impl"] == name])
        if counts:
            levels.append(f"{escape(name)} " + ", ".join(f"{c} {k.replace('_', ' ')}" for k, c in counts.items()))
    if levels:
        console.print("certificates: " + "; ".join(levels))
