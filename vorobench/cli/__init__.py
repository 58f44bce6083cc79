"""The vorobench command line: build, check, time and compare Voronoi diagram constructions."""

from __future__ import annotations

import argparse
import importlib
import importlib.util
import numbers
import os
import sys
import time
from pathlib import Path
from typing import Optional, Sequence

from rich.console import Console
from rich.markup import escape
from rich.table import Table

import datasets_gen
import impls
from vorobench.cli.args import (
    OneLineParser,
    bounds,
    non_negative_float,
    non_negative_int,
    plain_help,
    positive_float,
    size,
    sizes,
)

# The parser imports every command module, so each one imports the harness (numba, pandas,
# matplotlib: about 1.5 s) inside the functions that run a command, and only the light
# registry here: `vorobench --help` starts in 0.2 s instead of 1.7 s (measured).

__all__ = ["main", "parse_list", "parse_sizes"]


def parse_list(text: str) -> list[str]:
    """Comma-separated names; empty items dropped, repeats collapsed (first place kept)."""
    return list(dict.fromkeys(t.strip() for t in text.split(",") if t.strip()))


def parse_sizes(text: str) -> list[int]:
    """Comma-separated sizes; accepts 1e4, 10k, 1M (see :func:`vorobench.cli.args.sizes`)."""
    return sizes(text)


def _console():
    console = Console()
    # Piped output has no terminal width: give tables room instead of rich's 80 columns.
    return console if console.is_terminal else Console(width=160)


def cmd_impls(args: argparse.Namespace) -> int:
    """Table of the implementations that can run here, those of ``--plugin`` included, as they
    declare themselves in a sandbox (no implementation is imported in this process)."""
    from vorobench.judge.pinning import PluginError, declare_in_sandbox
    from vorobench.judge.wire import clean_text

    available, declared, failed = declare_in_sandbox(None, tuple(args.plugin))
    if "*" in failed:
        raise PluginError(failed["*"].split("\n")[0])
    table = Table(title="implementations")
    for col in ("name", "kind", "exact", "weights", "disks", "complexity", "from", "description"):
        table.add_column(col)
    for name in available:
        d = declared.get(name)
        if d is None:        # an outside plugin that fails to load is listed, not fatal
            table.add_row(escape(name), "?", "?", "?", "?", "?", "?",
                          f"[red]failed to load: {escape(failed.get(name, ''))}[/red]")
            continue
        table.add_row(*(escape(clean_text(x, 200)) for x in (d.name, d.kind, "yes" if d.exact else "no",
                                                            "yes" if d.weighted else "no",
                                                            "yes" if d.apollonius else "no", d.complexity, d.origin,
                                                            d.description)))
    _console().print(table)
    return 0


def cmd_datasets(args: argparse.Namespace) -> int:
    """Table of the dataset families."""
    table = Table(title="datasets")
    for col in ("name", "family", "exact n", "description"):
        table.add_column(col)
    for name in datasets_gen.available():
        ds = datasets_gen.DATASETS[name]
        exact = "yes" if ds.exact_n else f"no: {ds.note}" if ds.note else "no"
        table.add_row(name, ds.family, exact, ds.description)
    _console().print(table)
    weights = Table(title="weight families (--weights FAMILY on bench, validate, fuzz: power diagrams)")
    for col in ("name", "description"):
        weights.add_column(col)
    for name, text in datasets_gen.WEIGHT_FAMILIES.items():
        weights.add_row(name, text)
    _console().print(weights)
    radii = Table(title="radius families (--radii FAMILY on bench, validate, fuzz: disks as sites, docs/apollonius.md; "
                        "impls.build(name, centres, radii=r) with an implementation that takes disks)")
    for col in ("name", "description"):
        radii.add_column(col)
    for name, text in datasets_gen.RADIUS_FAMILIES.items():
        radii.add_row(name, text)
    _console().print(radii)
    return 0


def load_points(dataset: Optional[str], n: int, seed: int, points_file: Optional[str]):
    """Points from a named dataset or from a file, with the label to show for them."""
    if points_file:
        return datasets_gen.load(points_file), Path(points_file).name
    return datasets_gen.generate(dataset, n, seed=seed), f"{dataset} n={n} seed={seed}"


def _build_in_sandbox(name: str, sites):
    """Runs in the sandbox: ({"unsupported", "seconds", "stats"}, the diagram's arrays)."""
    from vorobench.core.diagram import Diagram
    from vorobench.judge.engine import diagram_arrays

    impl = impls.get(name)
    reason = impl.unsupported_reason(sites)
    if reason:
        return {"unsupported": reason}, None
    stats: dict = {}
    t0 = time.perf_counter_ns()
    diagram = impl.run(sites, stats, check_supports=False, wrap_build_errors=True)
    seconds = (time.perf_counter_ns() - t0) / 1e9
    if type(diagram) is not Diagram:
        raise TypeError(f"build returned {type(diagram).__name__}, not a Diagram")
    counters = {str(k): (int(v) if isinstance(v, numbers.Integral) else float(v))
                for k, v in stats.items() if isinstance(v, numbers.Real)}
    return {"unsupported": "", "seconds": seconds, "stats": counters}, diagram_arrays(diagram)


def cmd_build(args: argparse.Namespace) -> int:
    """Build one diagram in an isolated worker, print its counts, optionally plot and save it."""
    from vorobench.core.prepare import prepare
    from vorobench.judge.sandbox import Sandbox

    if args.box is not None and not args.plot:
        raise ValueError("--box frames the picture: give --plot FILE too")
    if args.plot:
        from vorobench.judge.plotting import check_picture_path

        check_picture_path(args.plot)          # before the build, not after it
    from vorobench.judge.pinning import resolve_declarations
    from vorobench.judge.engine import diagram_schema

    points, label = load_points(args.dataset, args.n, args.seed, args.points)
    sites, _ = prepare(points)
    declared = resolve_declarations([args.impl], tuple(args.plugin))[args.impl]   # names the available ones
    box = Sandbox(args.impl, plugins=(declared.plugin,) if declared.plugin else (), memory_limit_mb=args.memory_limit,
                  expected=declared)
    try:
        outcome = box.call(_build_in_sandbox, args.impl, sites, timeout=args.timeout,
                           schema=diagram_schema(sites.shape[0]))
    finally:
        box.close()
    if not outcome.ok:
        print(f"vorobench build: {args.impl} failed on {label}: {outcome.kind}: {outcome.message}", file=sys.stderr)
        return 1
    data, arrays = outcome.value
    if not (isinstance(data, dict) and isinstance(data.get("stats", {}), dict)
            and type(data.get("seconds", 0.0)) in (int, float)):
        print(f"vorobench build: {args.impl} answered no build record on {label}", file=sys.stderr)
        return 1
    if data.get("unsupported"):
        raise ValueError(f"{args.impl} does not support {label}: {data['unsupported']}")
    from vorobench.judge.engine import diagram_from_arrays

    diagram = diagram_from_arrays(arrays)
    if not (diagram.sites.shape == sites.shape and (diagram.sites == sites).all()):
        print(f"vorobench build: {args.impl} returned the diagram of other sites than {label}", file=sys.stderr)
        return 1
    stats, elapsed = data.get("stats", {}), data.get("seconds", 0.0)
    diagram.validate()
    c = diagram.counts()
    print(f"{args.impl} on {label}: {points.shape[0]} points, {c['n']} distinct sites")
    print(f"V = {c['V']}  E = {c['E']}  H = {c['H']}  ({elapsed:.4f} s, structure valid)")
    if stats:
        print("stats: " + ", ".join(f"{k}={v}" for k, v in stats.items()))
    if args.save:
        diagram.save(args.save)
        print(f"saved {args.save}")
    if args.plot:
        from vorobench.judge.plotting import save_plot

        save_plot(diagram, args.plot, title=f"{args.impl}: {label}", box=args.box)
        print(f"wrote {args.plot}")
    return 0


# Commands that live in their own modules register here: name -> (module, help).
_EXTRA_COMMANDS: dict[str, tuple[str, str]] = {
    "validate": ("vorobench.cli.validate", "cross-validate implementations against a reference"),
    "bench": ("vorobench.cli.bench", "time implementations on datasets (worker per case)"),
    "report": ("vorobench.cli.report", "figures + Markdown/HTML report from a results file"),
    "compare": ("vorobench.cli.compare", "compare two result files and flag regressions"),
    "history": ("vorobench.cli.history", "list the runs of a run store"),
    "trend": ("vorobench.cli.trend", "HTML page of build times and counters across a run store's runs, change points marked"),
    "continuous": ("vorobench.cli.continuous", "benchmark two git revisions in their own worktrees and compare them"),
    "demo": ("vorobench.cli.demo", "the main job: default benchmark + cross-validation + report"),
    "fuzz": ("vorobench.cli.fuzz", "seeded campaign of small random/degenerate cases, cross-validated on an executor"),
}


def _add_dataset_args(p: argparse.ArgumentParser, default: str = "uniform") -> None:
    p.add_argument("--dataset", default=default, help=f"dataset name (default {default}); see `vorobench datasets`")
    p.add_argument("--n", type=size, default=1000, help="number of points (default 1000)")
    p.add_argument("--seed", type=non_negative_int, default=0, help="dataset seed (default 0)")
    p.add_argument("--points", help="read points from a .npy/.csv/.txt file instead of a dataset")


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(prog="vorobench", description=__doc__)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineParser)
    p = sub.add_parser("impls", help="list implementations",
                       description="List every implementation this installation can run (its own, the outside "
                                   "libraries that are installed, entry points and --plugin ones): whether its "
                                   "decisions are exact, whether it takes weights, its declared complexity, where "
                                   "it comes from.")
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE",
                   help="also list these implementations: a module or .py file defining IMPLEMENTATIONS, "
                        "or a program's manifest (impl.toml); repeatable")
    p.set_defaults(func=cmd_impls)
    sub.add_parser("datasets", help="list dataset families",
                   description="List the dataset families (random and degenerate) that --datasets and "
                               "--generators name, with how many rows each gives for n, and the weight families "
                               "of --weights.").set_defaults(func=cmd_datasets)
    p = sub.add_parser("build", help="build one diagram, print counts, plot/save it")
    p.add_argument("--impl", default=impls.DEFAULT_REFERENCE,
                   help=f"implementation name (default {impls.DEFAULT_REFERENCE})")
    _add_dataset_args(p)
    p.add_argument("--plot", help="write a picture (PNG/SVG/PDF) of the diagram")
    p.add_argument("--box", type=bounds, default=None, metavar="XMIN,YMIN,XMAX,YMAX",
                   help="what --plot shows (default: the sites with a margin); "
                        "write --box=-1,-1,1,1 when it starts with a minus")
    p.add_argument("--save", help="save the diagram as .npz")
    p.add_argument("--timeout", type=positive_float, default=None,
                   help="seconds the build may take, warm-up aside (default: no limit)")
    p.add_argument("--memory-limit", type=non_negative_float, default=None, metavar="MB",
                   help="address space the build may add (MemoryError instead of the OOM killer)")
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE",
                   help="extra implementations: a module or .py file defining IMPLEMENTATIONS, or a "
                        "program's manifest (impl.toml; docs/executables.md); repeatable")
    p.set_defaults(func=cmd_build)
    for name, (module, help_text) in _EXTRA_COMMANDS.items():
        if importlib.util.find_spec(module) is None:
            continue
        mod = importlib.import_module(module)
        p = sub.add_parser(name, help=help_text, description=plain_help(mod.__doc__),
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        mod.add_arguments(p)
        p.set_defaults(func=mod.run)
    return parser


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    from vorobench.judge.isolation import Terminated, install_termination_handler

    install_termination_handler()
    try:
        return int(args.func(args) or 0)
    except (ValueError, KeyError, FileNotFoundError, FileExistsError, NotADirectoryError, IsADirectoryError,
            PermissionError, OverflowError) as exc:
        msg = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"vorobench {args.command}: error: {_one_line(msg)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader of our output went away (`vorobench history S | head`): not an error of ours.
        # Point stdout at nothing, so that flushing it at exit does not fail again.

        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    except Terminated as exc:
        print(f"{exc}: workers stopped, finished results kept", file=sys.stderr)
        return 143


def _one_line(message: object) -> str:
    lines = [line.strip() for line in str(message).splitlines() if line.strip()]
    return "; ".join(lines)[:500] if lines else type(message).__name__
