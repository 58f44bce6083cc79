"""Time implementations on datasets, one worker process per case; results go to a tidy CSV.

Each (implementation, dataset, n, seed) runs in a fresh process: a crash, a hang past
--timeout or running out of memory is recorded as that case's status and the run goes on.
Every finished case is appended to --out at once; --resume skips cases already there.
With --weights FAMILY every case times the power diagram of its points with weights of that
family (see `vorobench datasets`), and an implementation that does not take weights is
recorded as unsupported. With --radii FAMILY every case times the diagram of the disks centred
at its points with radii of that family (docs/apollonius.md), judged by the certificate and
comparison of disks, and an implementation that does not take disks is recorded as
unsupported. A case has weights or radii, never both; either one names its dataset in the
results ("uniform (radii weights)", "uniform (random radii)"), so it is never mixed with the
ordinary case.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Optional, Sequence

from rich.console import Console

import datasets_gen
import impls
from vorobench.cli import args as cli_args

if TYPE_CHECKING:  # annotations only: the harness is imported when a command runs
    from vorobench.harness.runner import RunConfig
    from vorobench.harness.site_attributes import SiteAttribute

# The parser imports every command module, so each one imports the harness (numba, pandas,
# matplotlib: about 1.5 s) inside the functions that run a command, and only the light
# registry here: `vorobench --help` starts in 0.2 s instead of 1.7 s (measured).

__all__ = ["add_arguments", "run", "execute", "weight_family"]

DEFAULT_SIZES = "1000,10000,100000"


def _family(text: str, families: dict, what: str) -> str:
    name = text.strip()
    if name not in families:
        raise argparse.ArgumentTypeError(f"unknown {what} family {text!r}; available: "
                                         f"{', '.join(families)} (see `vorobench datasets`)")
    return name


def weight_family(text: str) -> str:
    """A ``--weights`` value: the name of a weight family of ``datasets_gen``."""
    return _family(text, datasets_gen.WEIGHT_FAMILIES, "weight")


def radius_family(text: str) -> str:
    """A ``--radii`` value: the name of a radius family of ``datasets_gen`` (disks as sites)."""
    return _family(text, datasets_gen.RADIUS_FAMILIES, "radius")


#: The option parser of each site attribute's family, by the attribute's name (``--weights``, ``--radii``).
_FAMILY_OPTIONS = {"weights": weight_family, "radii": radius_family}


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--impls", type=cli_args.names, default=None,
                   help="comma-separated implementations (default: all available)")
    p.add_argument("--datasets", type=cli_args.names, default=["uniform"],
                   help="comma-separated datasets (default uniform); see `vorobench datasets`")
    p.add_argument("--sizes", type=cli_args.sizes, default=cli_args.sizes(DEFAULT_SIZES),
                   help=f"comma-separated sizes, 1e4/10k accepted (default {DEFAULT_SIZES})")
    p.add_argument("--seeds", type=cli_args.seeds, default=[0], help="comma-separated dataset seeds (default 0)")
    p.add_argument("--weights", type=weight_family, default=None, metavar="FAMILY",
                   help="time power diagrams: every site weighted by this family (radii, equal, integer, hidden; "
                        "see `vorobench datasets`); implementations without weights are recorded as unsupported")
    p.add_argument("--radii", type=radius_family, default=None, metavar="FAMILY",
                   help="time diagrams of disks (docs/apollonius.md): every point the centre of a disk with a radius "
                        "of this family (random, separate, equal, nested, tangent, integer, huge, last_bit; see "
                        "`vorobench datasets`); implementations without disks are recorded as unsupported; not "
                        "with --weights")
    p.add_argument("--repeat", type=cli_args.positive_int, default=5,
                   help="timed builds per case, at least (default 5: the fewest with which `compare`'s rank test "
                        "can show a change at alpha 0.05 on one case)")
    p.add_argument("--min-time", type=cli_args.non_negative_float, default=0.25, metavar="S",
                   help="repeat builds shorter than this until S seconds are timed (at most 25 builds; default "
                        "0.25: short cases get the repeats that tell their noise from a change)")
    p.add_argument("--timeout", type=cli_args.positive_float, default=60.0,
                   help="seconds allowed for each timed build and for the check (default 60)")
    p.add_argument("--warmup-timeout", type=cli_args.positive_float, default=300.0,
                   help="seconds allowed for the warm-up, JIT compilation included (default 300)")
    p.add_argument("--budget", type=cli_args.positive_float, default=None,
                   help="skip a case whose build time, extrapolated from smaller n, exceeds this many seconds")
    p.add_argument("--memory-limit", type=cli_args.positive_float, default=None, metavar="MB",
                   help="address space a worker may add after start-up (MemoryError instead of the OOM killer)")
    p.add_argument("--out", default=None,
                   help="results CSV (default results/bench-<date>.csv); metadata goes to <stem>.meta.json")
    p.add_argument("--resume", action="store_true", help="skip cases already in --out and append the rest")
    p.add_argument("--overwrite", action="store_true", help="replace an existing --out")
    p.add_argument("--reference", default=impls.DEFAULT_REFERENCE,
                   help=f"reference implementation for the check (default {impls.DEFAULT_REFERENCE})")
    p.add_argument("--no-check", action="store_true", help="skip certification and comparison with the reference")
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE",
                   help="extra implementations: a module or .py file defining IMPLEMENTATIONS, or a "
                        "program's manifest (impl.toml; docs/executables.md); repeatable")
    p.add_argument("--start-method", choices=("forkserver", "spawn"), default=None,
                   help="how workers start: forked from a server with the libraries imported (default "
                        "where available), or a fresh interpreter per case (spawn, ~2 s slower per case)")
    p.add_argument("--executor", default="local",
                   help="where cases run: 'local' (default; worker processes here) or dask://HOST:PORT "
                        "(a running Dask scheduler; run one single-threaded worker per host for fair timings)")
    p.add_argument("--workers", type=cli_args.positive_int, default=1,
                   help="local cases run at once (default 1: concurrent cases disturb each other's timings)")
    p.add_argument("--parquet", action="store_true", help="also write <stem>.parquet at the end")
    p.add_argument("--store", default=None, metavar="DIR",
                   help="also file the run in this run store when it ends (see `vorobench history`)")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no line per case")


def default_out(now: Optional[_dt.datetime] = None) -> Path:
    now = now or _dt.datetime.now()
    return Path("results") / f"bench-{now:%Y%m%d-%H%M%S}.csv"


def _validate_names(declared: dict, datasets: Sequence[str], reference: Optional[str],
                    weights: Optional[str] = None, radii: Optional[str] = None,
                    config: Optional[RunConfig] = None) -> None:
    """Refuse unknown datasets and families, weights with radii, and a reference that cannot
    build the run's cases (weighted, or of disks), naming the implementations here that can."""
    from vorobench.harness.site_attributes import attribute_of

    for name in datasets:
        if name not in datasets_gen.available() and not name.startswith("file:"):
            raise ValueError(f"unknown dataset {name!r}; available: {', '.join(datasets_gen.available())}")
    attribute, family = attribute_of(weights or "", radii or "")
    if attribute is None:
        return
    _FAMILY_OPTIONS[attribute.name](family)
    if reference and not attribute.takes(declared[reference]):
        takers = _takers(attribute, declared, config)
        raise ValueError(f"the reference {reference} {attribute.refusal}, so it cannot check {attribute.cases}; "
                         f"choose one that does with --reference ({', '.join(takers) or 'none here'}) "
                         f"or pass --no-check")


def _takers(attribute: SiteAttribute, declared: dict, config: Optional[RunConfig] = None) -> list[str]:
    """The implementations that take ``attribute`` (weights, disks): every one available here
    with the run's plugins (read in a sandbox, as the run's own are), or the run's alone when
    there is no ``config`` to read them with."""
    if config is not None:
        from vorobench.judge.pinning import resolve_declarations

        declared = resolve_declarations(None, tuple(config.plugins), timeout=config.warmup_timeout)
    return [name for name, d in declared.items() if attribute.takes(d)]


def pinned(impl_names: Optional[Sequence[str]], config) -> tuple[list[str], object]:
    """The run's implementation names and ``config`` with every declaration pinned, read once in
    a sandbox (plugins are loaded there, never in this process); unknown names are refused."""
    import dataclasses

    from vorobench.judge.pinning import resolve_declarations

    names = list(impl_names) if impl_names else None
    reference = [config.reference] if config.check and config.reference else []
    declared = resolve_declarations(names, tuple(config.plugins), timeout=config.warmup_timeout,
                                    also=tuple(reference))
    names = names or [n for n in declared]
    return names, dataclasses.replace(config, declarations=tuple(declared.items()))


def execute(impl_names: Optional[Sequence[str]], datasets: Sequence[str], sizes: Sequence[int],
            seeds: Sequence[int], out: Path, config, resume: bool = False, overwrite: bool = False,
            progress: bool = True, verbose: bool = True, console=None, executor: Optional[str] = None,
            workers: int = 1, weights: Optional[str] = None, radii: Optional[str] = None) -> tuple[int, list]:
    """Run a benchmark into ``out``; returns (exit code, outcomes). Shared by bench and demo.
    ``executor``/``workers``: see :func:`vorobench.harness.runner.run_cases`. ``weights``: a
    weight family of ``datasets_gen`` (power diagrams); ``radii``: a radius family (diagrams of
    disks); None for neither (ordinary diagrams), never both."""
    from vorobench.harness.site_attributes import attribute_of

    attribute_of(weights or "", radii or "")        # both: refused before anything is read or started
    impl_names, config = pinned(impl_names, config)
    return _execute(impl_names, datasets, sizes, seeds, out, config, resume, overwrite, progress,
                    verbose, console, executor, workers, weights, radii)


def _execute(impl_names, datasets, sizes, seeds, out: Path, config, resume: bool, overwrite: bool,
             progress: bool, verbose: bool, console, executor: Optional[str] = None,
             workers: int = 1, weights: Optional[str] = None, radii: Optional[str] = None) -> tuple[int, list]:
    from vorobench.harness import results, runner, sysinfo
    from vorobench.harness.repeat_check import SHIFTS_NOTE

    console = console or Console(stderr=True)
    declared = dict(config.declarations)
    _validate_names(declared, datasets, config.reference if config.check else None, weights, radii, config)
    # One run writes a results file at a time: a second one would rerun what the first has not
    # saved yet and interleave rows. Taken before reading (resume) or deleting (overwrite) it.
    with results.writer_lock(out):
        store = results.ResultsFile(out)
        if store.exists() and not (resume or overwrite):
            raise ValueError(f"{out} exists; pass --resume to continue it or --overwrite to replace it")
        if store.exists() and overwrite and not resume:
            out.unlink()
            results.metadata_path(out).unlink(missing_ok=True)
        previous = store.rows() if resume else []
        done = {results.case_key(r) for r in previous}
        cases = runner.plan_cases(impl_names, datasets, sizes, seeds,
                                  reference=config.reference if config.check else None, weights=weights or "",
                                  radii=radii or "")
        todo = [c for c in cases if c.key not in done]
        meta = sysinfo.run_metadata(impl_names, config.plugins)
        meta.update(run_id=config.run_id, argv=sys.argv[1:], impls=impl_names, datasets=list(datasets),
                    sizes=list(sizes), seeds=list(seeds), weights=weights or "", radii=radii or "",
                    repeat=config.repeat, min_time=config.min_time,
                    timeout=config.timeout,
                    reference=config.reference, check=config.check, start_method=config.start_method,
                    cases_planned=len(cases), executor=executor or "local", workers=workers,
                    cases_to_run=len(todo), declarations={n: d.to_dict() for n, d in declared.items()},
                    repeat_inputs=SHIFTS_NOTE)
        out.parent.mkdir(parents=True, exist_ok=True)
        results.append_run_metadata(out, meta)
        if resume and done:
            console.print(f"resuming {out}: {len(cases) - len(todo)} of {len(cases)} cases already done")
        _say_unsupported(console, impl_names, declared, weights, radii)
        try:
            outcomes = runner.run_cases(cases, config, store.append, done=done, previous_rows=previous,
                                        progress=progress, console=console, verbose=verbose,
                                        executor=executor, workers=workers)
        except KeyboardInterrupt:
            saved = len(store.done_keys())
            _finish_metadata(out, config.run_id, interrupted=True)
            console.print(f"[yellow]interrupted[/yellow]: {saved} cases are saved in {out}; "
                          "rerun with --resume to finish")
            return 130, []
        counts = runner.exit_status(outcomes)
        _finish_metadata(out, config.run_id, interrupted=False, statuses=counts)
        summary = ", ".join(f"{v} {k}" for k, v in sorted(counts.items())) or "nothing to run"
        console.print(f"{len(outcomes)} cases run ({summary}); results in {out}")
        return 0, outcomes


def _say_unsupported(console, impl_names: Sequence[str], declared: dict, weights: Optional[str],
                     radii: Optional[str]) -> None:
    """One line naming the run's implementations that do not take its weights or disks: their
    cases are recorded as unsupported, without a worker."""
    from vorobench.harness.site_attributes import attribute_of

    attribute, family = attribute_of(weights or "", radii or "")
    if attribute is None:
        return
    left_out = [name for name in impl_names if not attribute.takes(declared[name])]
    if left_out:
        verb = attribute.refusal if len(left_out) == 1 else attribute.refusal.replace("does not", "do not", 1)
        console.print(f"{attribute.name} {family}: {', '.join(left_out)} {verb}: unsupported")


def _finish_metadata(out: Path, run_id: str, **fields) -> None:
    from vorobench.harness import results, sysinfo

    finished = _dt.datetime.now().astimezone().isoformat(timespec="seconds")
    results.update_run_metadata(out, run_id, finished=finished, load_average_end=sysinfo.load_average(), **fields)


def config_from_args(args: argparse.Namespace):
    from vorobench.harness.runner import RunConfig
    from vorobench.judge.isolation import default_start_method

    if args.repeat < 1:
        raise ValueError("--repeat must be at least 1")
    if args.timeout <= 0:
        raise ValueError("--timeout must be positive")
    out = Path(args.out) if args.out else default_out()
    return RunConfig(repeat=args.repeat, min_time=args.min_time, timeout=args.timeout,
                     warmup_timeout=args.warmup_timeout,
                     reference=args.reference, check=not args.no_check, plugins=tuple(args.plugin),
                     memory_limit_mb=args.memory_limit, budget=args.budget,
                     start_method=args.start_method or default_start_method()), out


def run(args: argparse.Namespace) -> int:
    from vorobench.harness import results
    from vorobench.harness.executors import check_spec

    config, out = config_from_args(args)
    check_spec(args.executor)
    if args.workers < 1:
        raise ValueError("--workers must be at least 1")
    store = None
    if args.store:
        from vorobench.harness.store import Store

        store = Store(args.store)            # a file in its place is refused before the run
    code, _ = execute(args.impls, args.datasets, args.sizes, args.seeds, out, config,
                      resume=args.resume, overwrite=args.overwrite,
                      progress=not args.quiet, verbose=not args.quiet,
                      executor=args.executor, workers=args.workers, weights=args.weights, radii=args.radii)
    if args.parquet and out.exists():
        print(f"wrote {results.to_parquet(out)}")
    if store is not None:
        if code != 0:
            print(f"run not filed in {args.store}: it did not finish", file=sys.stderr)
        elif out.exists():
            filed = store.add_results(out)
            print(f"filed run {', '.join(filed) or '(already there)'} in {args.store}", file=sys.stderr)
    return code
