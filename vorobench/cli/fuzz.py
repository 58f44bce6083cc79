"""Fuzz campaign: many small random and degenerate cases, cross-validated on an executor.

Case i of a campaign is (generator, n, seed), fixed by the campaign seed and i alone: the
generators are the named datasets (fresh seeds, small sizes) and ``int_box``, points of a
small integer box (duplicates and collinear triples everywhere) with lattice points of one
circle mixed in (cocircular subsets). Each case is built by every implementation, certified
and compared with the reference (:func:`vorobench.judge.engine.check_case`), exact
implementations also with each other, as a task on the executor (``local`` or
``dask://HOST:PORT``). Every checked case is appended to ``cases.jsonl`` in ``--out``, so a
rerun skips it; every failure is shrunk to a witness (:mod:`vorobench.judge.shrink`) under
``witnesses/``: the first few failures of each implementation and verdict are shrunk, the rest
(and timeouts, which would cost a timeout per step) are written as found. ``--budget`` is a
case count (``100000``) or a duration (``90s``, ``10m``, ``2h``); a duration covers the whole
run, shrinking and witnesses included. An implementation that times out is not built again in
that run. The log records digests of the implementations' code and of each plugin: after
either changes, a rerun moves the old log aside and starts afresh.
With ``--weights FAMILY`` every case is the power diagram of its points with weights of that
family; the reference must take weights, and the implementations that do not are
``unsupported`` (which passes). With ``--radii FAMILY`` every case is the diagram of disks
centred at its points with radii of that family (docs/apollonius.md), the same way.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from rich.console import Console

import datasets_gen
import impls
from vorobench.cli import args as cli_args
from vorobench.cli.bench import radius_family, weight_family
from vorobench.harness.campaign import INT_BOX, LOG_NAME, parse_budget

# The harness and the judge are imported inside the functions that run the command, not here:
# the parser imports every command module (start-up time, measured in vorobench.cli).

__all__ = ["add_arguments", "run"]


def add_arguments(p: argparse.ArgumentParser) -> None:

    p.add_argument("--impls", type=cli_args.names, default=None,
                   help="comma-separated implementations (default: all available)")
    p.add_argument("--generators", type=cli_args.names, default=None,
                   help=f"comma-separated dataset generators and/or {INT_BOX} (default: all datasets and {INT_BOX})")
    p.add_argument("--budget", type=parse_budget, default=parse_budget("1000"),
                   help="cases in the campaign (100000) or time for this run, shrinking and witnesses included "
                        "(90s, 10m, 2h); default 1000")
    p.add_argument("--min-n", type=cli_args.positive_int, default=3, help="smallest case size (default 3)")
    p.add_argument("--max-n", type=cli_args.size, default=40, help="largest case size (default 40)")
    p.add_argument("--seed", type=cli_args.non_negative_int, default=0,
                   help="campaign seed: fixes the sequence of cases (default 0)")
    p.add_argument("--reference", default=impls.DEFAULT_REFERENCE,
                   help=f"reference implementation (default {impls.DEFAULT_REFERENCE})")
    p.add_argument("--weights", type=weight_family, default=None, metavar="FAMILY",
                   help="fuzz power diagrams: weights of this family (radii, equal, integer, hidden; see "
                        "`vorobench datasets`); implementations without weights are reported unsupported")
    p.add_argument("--radii", type=radius_family, default=None, metavar="FAMILY",
                   help="fuzz diagrams of disks: radii of this family (see `vorobench datasets`); "
                        "implementations without disks are reported unsupported")
    p.add_argument("--probes", type=cli_args.non_negative_int, default=500,
                   help="random probes per certificate (default 500)")
    p.add_argument("--timeout", type=cli_args.positive_float, default=60.0,
                   help="seconds each implementation may take to build one case (default 60; less when a "
                        "duration budget is ending)")
    p.add_argument("--memory-limit", type=cli_args.positive_float, default=None, metavar="MB",
                   help="address space an implementation's worker may add (MemoryError instead of the OOM killer)")
    p.add_argument("--executor", default="local", help="'local' (process pool here) or dask://HOST:PORT")
    p.add_argument("--workers", type=cli_args.positive_int, default=1, help="local worker processes (default 1)")
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE",
                   help="extra implementations: a module or .py file defining IMPLEMENTATIONS, or a "
                        "program's manifest (impl.toml; docs/executables.md); repeatable")
    p.add_argument("--no-shrink", action="store_true", help="save failing cases unshrunk")
    p.add_argument("--shrink-seconds", type=cli_args.non_negative_float, default=30.0,
                   help="most time to shrink one witness (default 30; a duration budget may leave less)")
    p.add_argument("--out", default="reports/fuzz", help="campaign directory: cases.jsonl, witnesses/, summary.json "
                                                         "(default reports/fuzz; rerun to resume)")


def _declared(args: argparse.Namespace) -> dict:
    """The campaign's implementations and its reference with what each declares: read once in a
    sandbox (plugins are loaded there, never in this process) and pinned for the campaign."""
    from vorobench.judge.pinning import resolve_declarations

    names = list(args.impls) if args.impls else None
    declared = resolve_declarations(names, tuple(args.plugin), timeout=300.0, also=(args.reference,))
    if args.weights and not declared[args.reference].weighted:
        others = ", ".join(n for n, d in declared.items() if d.weighted) or "none here"
        raise ValueError(f"the reference {args.reference} does not take weights, so it cannot judge weighted "
                         f"cases; choose one that does with --reference ({others})")
    if args.radii and args.weights:
        raise ValueError("--weights (power diagrams) and --radii (disks) go one at a time")
    if args.radii and not declared[args.reference].apollonius:
        others = ", ".join(n for n, d in declared.items() if d.apollonius) or "none here"
        raise ValueError(f"the reference {args.reference} does not take disks, so it cannot judge cases of disks; "
                         f"choose one that does with --reference ({others})")
    return declared


def run(args: argparse.Namespace) -> int:
    from vorobench.harness.executors import check_spec
    from vorobench.harness.atomic import write_json
    from vorobench.harness.fuzz import run_campaign
    from vorobench.judge.engine import close_shared_judges

    console = Console()
    check_spec(args.executor)
    if not 1 <= args.min_n <= args.max_n:
        raise ValueError("--min-n and --max-n: need 1 <= min-n <= max-n")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    # Until this run ends, the summary says it did not pass: a killed run is no green gate.
    write_json(out / "summary.json", {"passed": False, "complete": False,
                                       "note": "fuzzing started and has not finished (or was killed)"})
    declared = _declared(args)
    names = list(dict.fromkeys(args.impls)) if args.impls else list(declared)
    unweighted = [n for n in names if args.weights and not declared[n].weighted]
    no_disks = [n for n in names if args.radii and not declared[n].apollonius]
    generators = list(args.generators) if args.generators else datasets_gen.available() + [INT_BOX]
    unknown = [g for g in generators if g != INT_BOX and g not in datasets_gen.available()]
    if unknown:
        raise ValueError(f"unknown generator(s) {', '.join(unknown)}; see `vorobench datasets` (or {INT_BOX})")
    where = (f"{args.workers} local worker{'s' if args.workers != 1 else ''}" if args.executor == "local"
             else f"the Dask cluster at {args.executor}")
    console.print(f"fuzzing {', '.join(names)} against {args.reference} with {where}; budget {args.budget}; "
                  f"log {out / LOG_NAME}"
                  + (f"; power diagrams, {args.weights} weights" if args.weights else "")
                  + (f"; disks, {args.radii} radii" if args.radii else ""))
    if no_disks:
        console.print(f"radii {args.radii}: {', '.join(no_disks)} {'does' if len(no_disks) == 1 else 'do'} "
                      f"not take disks: unsupported")
    if unweighted:
        console.print(f"weights {args.weights}: {', '.join(unweighted)} {'does' if len(unweighted) == 1 else 'do'} "
                      f"not take weights: unsupported")
    s = run_campaign(out, names, generators, args.budget, executor=args.executor, workers=args.workers,
                     reference=args.reference, min_n=args.min_n, max_n=args.max_n, campaign_seed=args.seed,
                     probes=args.probes, plugins=args.plugin, shrink=not args.no_shrink,
                     shrink_seconds=args.shrink_seconds, console=console, timeout=args.timeout,
                     memory_limit_mb=args.memory_limit, weights=args.weights or "",
                     declarations=tuple(declared.items()), radii=args.radii or "")
    # The gate covers the whole campaign: a failure logged by an earlier run still fails it.
    # A case the budget cut short was not judged: no green gate over it.
    bad = s.failed + s.failed_before + s.lost + s.errors + s.cut
    summary = {"passed": not bad, "complete": True, "checked": s.checked, "previously_checked": s.previously,
               "failed": s.failed, "failed_before": s.failed_before, "lost": s.lost,
               "errors": s.errors, "cut": s.cut, "not_built_again": s.hung, "unwitnessed": s.unwitnessed,
               "seconds": s.seconds,
               "cases_per_second": s.rate, "witnesses": s.witnesses,
               "executor": args.executor, "workers": args.workers, "impls": names, "generators": generators,
               "weights": args.weights, "unweighted": unweighted, "radii": args.radii, "no_disks": no_disks,
               "declarations": {n: d.to_dict() for n, d in declared.items()}}
    write_json(out / "summary.json", summary)
    close_shared_judges()
    for w in s.witnesses:
        console.print(f"  witness: {w['impl']} on {w['generator']} n={w['n']} seed={w['seed']}: "
                      f"{w['n_points']} points{'' if w['shrunk'] else ' (as found)'} -> {w['points']}")
    console.print(f"{s.checked} cases checked in {s.seconds:.1f} s ({s.rate:.2f} cases/s; "
                  f"{s.previously} done before); "
                  + ("[green]all passed[/]" if not bad else
                     f"[red]{s.failed} failed, {s.failed_before} failed in earlier runs, {s.lost} lost, "
                     f"{s.errors} errors, {s.cut} cut short by the budget[/]"))
    return 0 if not bad else 1
