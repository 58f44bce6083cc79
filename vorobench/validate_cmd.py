"""Cross-validate implementations against a reference on every dataset; shrink failures to witnesses.

Every case is built by each implementation (an exception is recorded as a crash), each diagram
is certified, and each is compared with the reference, which is certified too. Prints a matrix
implementation x dataset, writes ``summary.json`` and, for every failure, a small witness
(``.npy``, the command that reproduces it, a PNG) under ``--out``. Exit status 1 if anything
is wrong.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np

from vorobench.certify import DEFAULT_PROBES
from vorobench.crossval import DEFAULT_REFERENCE, VERDICTS, CaseVerdict, agree_exactly, build_and_certify, check_case

__all__ = ["add_arguments", "run"]

_STYLE = {"exact": "green", "within_tolerance": "green", "certified": "green", "unsupported": "dim",
          "differs": "bold red", "not_certified": "bold red", "crashed": "bold red"}
_SHORT = {"within_tolerance": "within tol", "not_certified": "NOT CERTIFIED", "differs": "DIFFERS",
          "crashed": "CRASHED"}


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--impls", default="all", help="comma-separated implementations (default: all available)")
    p.add_argument("--datasets", default="all", help="comma-separated datasets, or 'all' (default)")
    p.add_argument("--sizes", default="10,100,1000", help="comma-separated sizes (default 10,100,1000)")
    p.add_argument("--seeds", default="0", help="comma-separated dataset seeds (default 0)")
    p.add_argument("--reference", default=DEFAULT_REFERENCE, help=f"reference implementation (default {DEFAULT_REFERENCE})")
    p.add_argument("--points", help="validate the points of this file (.npy/.csv/.txt) instead of datasets")
    p.add_argument("--out", default="reports/validate", help="directory for summary.json and witnesses "
                                                             "(default reports/validate)")
    p.add_argument("--probes", type=int, default=DEFAULT_PROBES, help=f"random probes per certificate "
                                                                      f"(default {DEFAULT_PROBES})")
    p.add_argument("--no-shrink", action="store_true", help="save failing point sets as they are, unshrunk")
    p.add_argument("--shrink-seconds", type=float, default=120.0, help="time budget per witness (default 120)")
    p.add_argument("--executor", default="local", help="where cases are judged: 'local' (default) or dask://HOST:PORT")
    p.add_argument("--workers", type=int, default=1,
                   help="local worker processes (default 1: every case in this process)")


def _cases(args: argparse.Namespace) -> list[dict[str, Any]]:
    """(label, dataset, n, seed, points) of every case."""
    import datasets_gen

    from vorobench.cli import parse_list, parse_sizes

    if args.points:
        pts = datasets_gen.load(args.points)
        return [dict(dataset=Path(args.points).name, n=int(pts.shape[0]), seed=None, points=pts)]
    names = parse_list(args.datasets)
    if not names or names == ["all"]:
        names = datasets_gen.available()
    unknown = [d for d in names if d not in datasets_gen.available() and not d.startswith(datasets_gen.FILE_PREFIX)]
    if unknown:
        raise ValueError(f"unknown dataset(s) {', '.join(unknown)}; see `vorobench datasets`")
    sizes = parse_sizes(args.sizes)
    seeds = [int(s) for s in parse_list(args.seeds)]
    return [dict(dataset=d, n=n, seed=s, points=None) for d in names for n in sizes for s in seeds]


def _impl_names(args: argparse.Namespace) -> list[str]:
    import impls

    from vorobench.cli import parse_list

    names = parse_list(args.impls)
    if not names or names == ["all"]:
        names = impls.available()
    for name in names + [args.reference]:
        impls.get(name)  # KeyError naming the available ones
    # The reference is certified too: it always has a row, first.
    return [args.reference] + [n for n in names if n != args.reference]


def _judge_case(item: tuple) -> tuple[np.ndarray, list[tuple[str, CaseVerdict, Any]]]:
    """One case on any worker: the reference and every implementation judged against it, and
    each exact implementation against the first exact one: (sites, [(impl, verdict, peer)])."""
    import datasets_gen

    from vorobench.prepare import prepare

    case, names, reference, probes = item
    points = case["points"] if case["points"] is not None else \
        datasets_gen.generate(case["dataset"], case["n"], seed=case["seed"])
    sites, _ = prepare(points)
    ref_res = build_and_certify(reference, sites, probes=probes)
    anchor = None                       # the first exact implementation: the others must match it exactly
    judged: list[tuple[str, CaseVerdict, Any]] = []
    for name in names:
        verdict = check_case(name, sites, reference=reference, reference_result=ref_res, probes=probes)
        judged.append((name, verdict, None))
        res = verdict.result
        if res is not None and res.exact and res.diagram is not None and name != reference:
            if anchor is None:
                anchor = res
            else:
                judged.append((name, agree_exactly(anchor, res), anchor.impl))
    return sites, judged


def _worst(verdicts: list[str]) -> str:
    return max(verdicts, key=VERDICTS.index)


def run(args: argparse.Namespace) -> int:
    import impls
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
    from rich.table import Table

    from vorobench.shrink import shrink_case, write_witness

    console = Console()
    names = _impl_names(args)
    cases = _cases(args)
    reference = args.reference
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    records: list[dict[str, Any]] = []
    failures: list[tuple[dict[str, Any], CaseVerdict, np.ndarray]] = []
    lost_cases: list[tuple[str, str]] = []
    with Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=console, transient=True) as progress:
        task = progress.add_task("validating", total=len(cases))
        items = [(case, names, reference, args.probes) for case in cases]
        if args.executor == "local" and args.workers == 1:
            judged_cases = ((item, _judge_case(item), "") for item in items)     # here, one at a time
        else:
            from vorobench.executors import run_tasks

            judged_cases = ((r.item, r.value, r.lost or r.error)
                            for r in run_tasks(args.executor, args.workers, _judge_case, items))
        for (case, *_), judged, lost in judged_cases:
            label = f"{case['dataset']} n={case['n']}" + (f" seed={case['seed']}" if case["seed"] is not None else "")
            progress.update(task, description=f"validated {label}")
            progress.advance(task)
            if lost:                            # its worker died (twice): every implementation's row says so
                lost_cases.append((label, lost))
                records += [dict(dataset=case["dataset"], n=case["n"], seed=case["seed"], exact_peer=None, impl=name,
                                 reference=reference, verdict="crashed", passed=False, certified=None,
                                 reference_certified=None, message=f"case lost: {lost}", blame="unknown",
                                 n_sites=0, seconds=0.0) for name in names]
                continue
            sites, checks = judged
            for name, v, peer in checks:
                records.append(dict(dataset=case["dataset"], n=case["n"], seed=case["seed"], exact_peer=peer,
                                    **v.to_dict()))
                if not v.passed:
                    failures.append((dict(case, impl=name, label=label, exact_peer=peer), v, sites))
    # Witnesses.
    witnesses = []
    for case, verdict, sites in failures:
        name = case["impl"]
        stem = f"{name}-{case['dataset']}-n{case['n']}" + (f"-s{case['seed']}" if case["seed"] is not None else "")
        stem = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in stem)
        peer = case["exact_peer"]
        if peer:
            stem += f"-vs-{peer}"
        with console.status(f"shrinking {name} on {case['label']} ({sites.shape[0]} points)"):
            small = sites if args.no_shrink else shrink_case(name, sites, verdict, reference=reference,
                                                            exact_peer=peer, probes=min(args.probes, 2000),
                                                            time_budget=args.shrink_seconds)
            w = write_witness(out / "witnesses", stem, name, small, reference=reference, exact_peer=peer,
                              probes=min(args.probes, 2000))
        witnesses.append(dict(impl=name, dataset=case["dataset"], n=case["n"], seed=case["seed"],
                              verdict=verdict.verdict, points=str(w.points), command=str(w.command),
                              picture=str(w.picture) if w.picture else None, n_points=w.n_points,
                              shrunk_verdict=w.verdict.verdict))
    # The matrix: implementation x dataset (datasets as rows so that many fit on a terminal),
    # worst verdict over sizes and seeds.
    datasets = list(dict.fromkeys(r["dataset"] for r in records))
    table = Table(title=f"cross-validation against {reference} ({len(cases)} cases)")
    table.add_column("dataset")
    for name in names:
        table.add_column(name + (" (ref)" if name == reference else ""))
    for d in datasets:
        row = [d]
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
    float_impls = [n for n in names if not impls.get(n).exact]
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
    for case, verdict, _ in failures:
        against = f" vs {case['exact_peer']}" if case["exact_peer"] else ""
        console.print(f"[red]FAIL[/] {case['impl']}{against} on {case['label']}: {verdict.verdict}: "
                      f"{verdict.message[:400]}")
    for label, why in lost_cases:
        console.print(f"[red]LOST[/] {label}: {why[:400]}")
    for w in witnesses:
        console.print(f"  witness: {w['n_points']} points -> {w['points']}  (picture: {w['picture']}; "
                      f"command in {w['command']})")
    summary = dict(reference=reference, impls=names, datasets=datasets, cases=len(cases),
                   passed=not failures and not lost_cases, failures=len(failures), lost=len(lost_cases), notes=notes,
                   witnesses=witnesses, results=records)
    path = out / "summary.json"
    path.write_text(json.dumps(summary, indent=1, default=_json_default))
    ok = not failures and not lost_cases
    console.print(f"{'[green]all passed[/]' if ok else f'[red]{len(failures)} failure(s)[/]'}: "
                  f"{len(records)} results written to {path}")
    return 0 if ok else 1


def _json_default(x: Any) -> Any:
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, np.ndarray):
        return x.tolist()
    return str(x)
