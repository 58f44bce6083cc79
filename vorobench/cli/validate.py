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
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

import numpy as np
from rich.console import Console
from rich.markup import escape
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

import datasets_gen
from impls import DEFAULT_REFERENCE
from vorobench.cli import args as cli_args
from vorobench.cli.bench import weight_family
from vorobench.judge.defaults import DEFAULT_PROBES, DEFAULT_TIMEOUT

if TYPE_CHECKING:  # annotations only: the module itself is loaded when the command runs
    from vorobench.judge.declarations import Declaration
    from vorobench.judge.engine import CaseVerdict

# The harness and the judge are imported inside the functions that run the command, not here:
# the parser imports every command module (start-up time, measured in vorobench.cli).

__all__ = ["add_arguments", "run"]

_STYLE = {"exact": "green", "within_tolerance": "green", "certified": "green", "unsupported": "dim",
          "differs": "bold red", "not_certified": "bold red", "crashed": "bold red", "timeout": "bold red",
          "oom": "bold red", "mutated_input": "bold red"}
_SHORT = {"within_tolerance": "within tol", "not_certified": "NOT CERTIFIED", "differs": "DIFFERS",
          "crashed": "CRASHED", "timeout": "TIMEOUT", "oom": "OUT OF MEMORY", "mutated_input": "MUTATED INPUT"}


def add_arguments(p: argparse.ArgumentParser) -> None:

    p.add_argument("--impls", type=cli_args.names, default=["all"],
                   help="comma-separated implementations (default: all available)")
    p.add_argument("--datasets", type=cli_args.names, default=["all"], help="comma-separated datasets, or 'all' (default)")
    p.add_argument("--sizes", type=cli_args.sizes, default=[10, 100, 1000], help="comma-separated sizes (default 10,100,1000)")
    p.add_argument("--seeds", type=cli_args.seeds, default=[0], help="comma-separated dataset seeds (default 0)")
    p.add_argument("--reference", default=DEFAULT_REFERENCE, help=f"reference implementation (default {DEFAULT_REFERENCE})")
    p.add_argument("--points", help="validate the points of this file (.npy/.csv/.txt) instead of datasets")
    p.add_argument("--weights", type=_weights_option, default=None, metavar="FAMILY",
                   help="validate power diagrams: weights of this family (radii, equal, integer, hidden; see "
                        "`vorobench datasets`), or file:PATH (one per point of --points); implementations "
                        "without weights are reported unsupported")
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
                   help="import extra implementations (module or .py file defining IMPLEMENTATIONS); repeatable")
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


def _weights_of(args: argparse.Namespace, points: np.ndarray, seed: Optional[int]) -> Optional[np.ndarray]:
    """The weights of a case's points under ``--weights`` (None: ordinary diagrams)."""
    family = args.weights
    if family is None:
        return None
    if family.startswith("file:"):
        from vorobench.harness.weighted_witness import load_weights

        w = load_weights(family[len("file:"):])
        if w.shape[0] != points.shape[0]:
            raise ValueError(f"{family}: {w.shape[0]} weights for {points.shape[0]} points")
        return w
    return datasets_gen.weights(family, points, seed=seed or 0)


def _cases(args: argparse.Namespace) -> list[dict[str, Any]]:
    """(label, dataset, n, seed, points, weights) of every case (points and weights None: generated
    on the worker)."""
    if args.weights is not None and args.weights.startswith("file:") and not args.points:
        raise ValueError("--weights file:PATH gives the weights of --points FILE: give --points too")
    if args.points:
        pts = datasets_gen.load(args.points)
        return [dict(dataset=Path(args.points).name, n=int(pts.shape[0]), seed=None, points=pts,
                     weights=_weights_of(args, pts, None))]
    names = list(args.datasets)
    if not names or names == ["all"]:
        names = datasets_gen.available()
    unknown = [d for d in names if d not in datasets_gen.available() and not d.startswith(datasets_gen.FILE_PREFIX)]
    if unknown:
        raise ValueError(f"unknown dataset(s) {', '.join(unknown)}; see `vorobench datasets`")
    return [dict(dataset=d, n=n, seed=s, points=None, weights=None) for d in names for n in args.sizes
            for s in args.seeds]


def _declared(args: argparse.Namespace) -> dict[str, "Declaration"]:
    """The run's implementations, reference first, with what each declares: read once in a
    sandbox (plugins are loaded there, never in this process) and pinned for the run."""
    from vorobench.judge.pinning import resolve_declarations

    names = list(args.impls)
    every = not names or names == ["all"]
    declared = resolve_declarations(None if every else names + [args.reference], tuple(args.plugin),
                                    timeout=args.warmup_timeout)
    if args.reference not in declared:
        declared.update(resolve_declarations([args.reference], tuple(args.plugin), timeout=args.warmup_timeout))
    if args.weights is not None and not declared[args.reference].weighted:
        weighted = [n for n, d in declared.items() if d.weighted]
        raise ValueError(f"the reference {args.reference} does not take weights, so it cannot judge weighted cases; "
                         f"choose one that does with --reference ({', '.join(weighted) or 'none here'})")
    # The reference is certified too: it always has a row, first.
    order = [args.reference] + [n for n in declared if n != args.reference and (every or n in names)]
    return {n: declared[n] for n in order}


def _judge_case(item: tuple) -> tuple[np.ndarray, list[tuple[str, CaseVerdict, Any]], Optional[np.ndarray]]:
    """One case on any worker, through the judging engine: (sites, [(impl, verdict, peer)], site
    weights or None). The points and weights of a named dataset are generated here."""
    from vorobench.judge.engine import shared_judge

    case, names, reference, options, family = item
    points, weights = case["points"], case["weights"]
    if points is None:
        points = datasets_gen.generate(case["dataset"], case["n"], seed=case["seed"])
        weights = datasets_gen.weights(family, points, seed=case["seed"]) if family else None
    judged = shared_judge(names, reference, **dict(options)).judge(points, weights=weights)
    return judged.sites, judged.rows, judged.weights


def _write_json(path: Path, data: dict) -> None:
    """Write ``data`` atomically: a reader never sees half a summary."""
    from vorobench.harness.atomic import replace_atomically

    replace_atomically(path, lambda f: json.dump(data, f, indent=1, default=_json_default))


def _worst(verdicts: list[str]) -> str:
    from vorobench.judge.engine import VERDICTS

    return max(verdicts, key=VERDICTS.index)


def _mark_unfinished(out: Path) -> Path:
    """Before anything else, the summary on disk says the run has not passed: a run killed at
    any point (even while starting) leaves no earlier green gate behind."""
    out.mkdir(parents=True, exist_ok=True)
    path = out / "summary.json"
    _write_json(path, dict(complete=False, passed=False, note="validation started and has not finished (or was killed)"))
    return path


def run(args: argparse.Namespace) -> int:
    from vorobench.harness.executors import parse_spec
    from vorobench.judge.engine import close_shared_judges, shared_judge
    from vorobench.judge.shrink import shrink_case, write_witness

    console = Console()
    parse_spec(args.executor)
    out = Path(args.out)
    path = _mark_unfinished(out)
    declared = _declared(args)
    names = list(declared)
    cases = _cases(args)
    reference = args.reference
    _write_json(path, dict(reference=reference, impls=names, cases=len(cases), complete=False, passed=False,
                           note="validation started and has not finished (or was killed)"))
    options = (("probes", args.probes), ("timeout", args.timeout), ("warmup_timeout", args.warmup_timeout),
               ("memory_limit_mb", args.memory_limit), ("plugins", tuple(args.plugin)),
               ("declarations", tuple(declared.items())))
    records: list[dict[str, Any]] = []
    failures: list[tuple[dict[str, Any], CaseVerdict, np.ndarray, Optional[np.ndarray]]] = []
    family = args.weights or ""
    unweighted = [n for n in names if family and not declared[n].weighted]
    if unweighted:
        console.print(f"[dim]weights {escape(family)}: {escape(', '.join(unweighted))} "
                      f"{'does' if len(unweighted) == 1 else 'do'} not take weights: unsupported[/]")
    lost_cases: list[tuple[str, str]] = []
    judged_count = 0
    try:
        with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                      console=console, transient=True) as progress:
            task = progress.add_task("validating", total=len(cases))
            items = [(case, names, reference, options, args.weights) for case in cases]
            if args.executor == "local" and args.workers == 1:
                judged_cases = ((item, _judge_case(item), "") for item in items)     # here, one at a time
            else:
                from vorobench.harness.executors import run_tasks

                # Off this machine a build may run without its sandbox: each case as a whole is bounded.
                limit = None if args.executor == "local" else len(names) * (args.timeout + args.warmup_timeout)
                judged_cases = ((r.item, r.value, r.lost or r.error)
                                for r in run_tasks(args.executor, args.workers, _judge_case, items, timeout=limit))
            for (case, *_), judged, lost in judged_cases:
                label = f"{case['dataset']} n={case['n']}" + (f" seed={case['seed']}" if case["seed"] is not None else "")
                label += f" weights={family}" if family else ""
                progress.update(task, description=f"validated {label}")
                progress.advance(task)
                if lost:                        # its worker died (twice): every implementation's row says so
                    lost_cases.append((label, lost))
                    records += [dict(dataset=case["dataset"], weights=family, n=case["n"], seed=case["seed"],
                                     exact_peer=None,
                                     impl=name, reference=reference, verdict="crashed", passed=False, certified=None,
                                     reference_certified=None, message=f"case lost: {lost}", blame="unknown",
                                     n_sites=0, seconds=0.0) for name in names]
                    continue
                judged_count += 1
                sites, checks, site_weights = judged
                for name, v, peer in checks:
                    records.append(dict(dataset=case["dataset"], weights=family, n=case["n"], seed=case["seed"],
                                        exact_peer=peer, **v.to_dict()))
                    if not v.passed:
                        failures.append((dict(case, impl=name, label=label, exact_peer=peer), v, sites, site_weights))
        # Witnesses, through a judge of this process (sandboxed like the cases were).
        witnesses = []
        shrink_judge = shared_judge(names, reference, **dict(options))
        for case, verdict, sites, site_weights in failures:
            name = case["impl"]
            stem = f"{name}-{case['dataset']}-n{case['n']}" + (f"-s{case['seed']}" if case["seed"] is not None else "")
            stem += f"-w{family.rpartition('/')[2]}" if family else ""
            stem = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in stem)
            peer = case["exact_peer"]
            if peer:
                stem += f"-vs-{peer}"
            # A hang or an exhausted memory costs its whole allowance per try: not shrunk.
            shrinkable = not args.no_shrink and verdict.verdict not in ("timeout", "oom")
            with console.status(f"shrinking {name} on {case['label']} ({sites.shape[0]} points)"):
                if site_weights is None:
                    small = sites if not shrinkable else shrink_case(
                        name, sites, verdict, reference=reference, exact_peer=peer, probes=min(args.probes, 2000),
                        time_budget=args.shrink_seconds, judge=shrink_judge)
                    w = write_witness(out / "witnesses", stem, name, small, reference=reference, exact_peer=peer,
                                      probes=min(args.probes, 2000), judge=shrink_judge,
                                      verdict=None if shrinkable else verdict)
                else:
                    from vorobench.harness.weighted_witness import shrink_weighted, write_weighted_witness

                    small, small_weights = (sites, site_weights) if not shrinkable else shrink_weighted(
                        name, sites, site_weights, verdict, reference=reference, exact_peer=peer,
                        probes=min(args.probes, 2000), time_budget=args.shrink_seconds, judge=shrink_judge)
                    w = write_weighted_witness(out / "witnesses", stem, name, small, small_weights,
                                               reference=reference, exact_peer=peer, probes=min(args.probes, 2000),
                                               judge=shrink_judge, verdict=None if shrinkable else verdict)
            witnesses.append(dict(impl=name, dataset=case["dataset"], weights=family, n=case["n"], seed=case["seed"],
                                  verdict=verdict.verdict, points=str(w.points), command=str(w.command),
                                  picture=str(w.picture) if w.picture else None, n_points=w.n_points,
                                  shrunk_verdict=w.verdict.verdict))
    finally:
        close_shared_judges()
    # The matrix: implementation x dataset (datasets as rows so that many fit on a terminal),
    # worst verdict over sizes and seeds.
    datasets = list(dict.fromkeys(r["dataset"] for r in records))
    table = Table(title=f"cross-validation against {reference} ({len(cases)} cases"
                        + (f"; power diagrams, {family} weights)" if family else ")"))
    table.add_column("dataset")
    for name in names:
        table.add_column(escape(name) + (" (ref)" if name == reference else ""))
    for d in datasets:
        row = [escape(str(d))]
        for name in names:
            vs = [r for r in records if r["impl"] == name and r["dataset"] == d]
            worst = _worst([r["verdict"] for r in vs])
            bad = sum(not r["passed"] for r in vs)
            text = _SHORT.get(worst, worst)
            if bad:
                text += f" {bad}/{len(vs)}"
                style = _STYLE.get(worst, "")
            elif any(r["blame"] == "reference" for r in vs):
                text, style = "ref wrong", "yellow"
            else:
                style = _STYLE.get(worst, "")
            row.append(f"[{style}]{text}[/]" if style else text)
        table.add_row(*row)
    console.print(table)
    notes = []
    float_impls = [n for n in names if not declared[n].exact]
    if float_impls:
        notes.append(f"{', '.join(float_impls)} {'is' if len(float_impls) == 1 else 'are'} floating point: "
                     f"'within tolerance' against {'it' if len(float_impls) == 1 else 'them'} is a pass, and "
                     f"{'its' if len(float_impls) == 1 else 'their'} certificates are judged within tolerance; "
                     f"exact implementations must agree with each other exactly.")
    pairs = [r for r in records if r["exact_peer"]]
    if pairs:
        bad_pairs = sum(not r["passed"] for r in pairs)
        notes.append(f"{len(pairs)} comparisons between exact implementations (against "
                     f"{', '.join(sorted({r['exact_peer'] for r in pairs}))}): "
                     + ("all exact." if not bad_pairs else f"{bad_pairs} NOT exact."))
    blamed = [r for r in records if r["blame"] == "reference"]
    if blamed:
        notes.append(f"{len(blamed)} difference(s) were the reference's failure (see the {reference} row).")
    for note in notes:
        console.print(f"[dim]note:[/] {note}")
    for case, verdict, *_ in failures:
        against = f" vs {case['exact_peer']}" if case["exact_peer"] else ""
        console.print(f"[red]FAIL[/] {escape(case['impl'])}{escape(against)} on {escape(case['label'])}: "
                      f"{verdict.verdict}: {escape(verdict.message[:400])}")
    for label, why in lost_cases:
        console.print(f"[red]LOST[/] {escape(label)}: {escape(why[:400])}")
    for w in witnesses:
        console.print(f"  witness: {w['n_points']} points -> {w['points']}  (picture: {w['picture']}; "
                      f"command in {w['command']})")
    # An implementation that declared every case unsupported was never judged: no pass. One that
    # does not take weights, on a weighted run, is declared so up front: it is not held against it.
    never_judged = sorted({r["impl"] for r in records if r["impl"] not in unweighted}
                          - {r["impl"] for r in records if r["verdict"] != "unsupported"})
    if unweighted:
        notes.append(f"{', '.join(unweighted)} {'does' if len(unweighted) == 1 else 'do'} not take weights: "
                     f"unsupported on every weighted case, and not part of the gate.")
    if never_judged:
        notes.append(f"{', '.join(never_judged)} declared every case unsupported: nothing of "
                     f"{'it' if len(never_judged) == 1 else 'them'} was judged, so the gate does not pass.")
        console.print(f"[red]NOT JUDGED[/] {escape(', '.join(never_judged))}: unsupported on every case")
    # The gate: every planned case judged, and every verdict a pass.
    ok = not failures and not lost_cases and judged_count == len(cases) and not never_judged
    failed_impls = sorted({case["exact_peer"] if verdict.blame == "reference" and case["exact_peer"] else case["impl"]
                           for case, verdict, *_ in failures})
    summary = dict(reference=reference, impls=names, datasets=datasets, weights=family or None,
                   unweighted=unweighted, cases=len(cases), judged=judged_count,
                   complete=judged_count == len(cases), passed=ok, failures=len(failures), lost=len(lost_cases),
                   failed_impls=failed_impls, never_judged=never_judged, timeout=args.timeout, notes=notes, witnesses=witnesses,
                   declarations={n: d.to_dict() for n, d in declared.items()}, results=records)
    _write_json(path, summary)
    from vorobench.harness.ci_outputs import write_junit, write_markdown

    if args.junit:
        console.print(f"JUnit XML: {write_junit(summary, args.junit)}")
    if args.markdown:
        console.print(f"Markdown digest: {write_markdown(summary, args.markdown)}")
    console.print(f"{'[green]all passed[/]' if ok else f'[red]{len(failures)} failure(s)[/]'}: "
                  f"{len(records)} results written to {path}")
    return 0 if ok else 1


def _json_default(x: Any) -> Any:
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)
