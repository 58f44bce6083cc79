"""The main job: benchmark and cross-validate every own implementation, then write a report.

    python3 dev.py demo                   # = vorobench demo
    vorobench demo --out reports/NAME     # results.csv, figures, README.md, report.html there

Runs each own implementation, and the outside references that are installed (Triangle, CGAL,
Boost.Polygon, GEOS: so every report shows where ours stand against C and C++ code), on a
representative set of datasets (random, clustered, exactly degenerate, numerically hostile)
at sizes over a decade, with certification and comparison against Qhull for every case, in a
worker process per case. Sized to finish within 3 minutes on a 2-core machine (after set-up):
a build whose time, extrapolated from the smaller sizes with the declared complexity, would
exceed the budget is skipped, so quadratic methods stop early instead of stalling the run.
It says which sizes a dataset cannot give (cocircular has at most 6,144 points) and lists
every case it did not run, with the reason. --full runs the big matrix.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import time
from pathlib import Path

from rich.console import Console

import impls
from vorobench.cli import args as cli_args
from vorobench.cli.bench import execute
from vorobench.harness.demo import DEMO_DATASETS, FULL_DATASETS, demo_implementations, demo_sizes, size_notes

# The harness and the judge are imported inside the functions that run the command, not here:
# the parser imports every command module (start-up time, measured in vorobench.cli).

__all__ = ["add_arguments", "run"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", default=None, help="report folder (default reports/<today's date>)")
    p.add_argument("--impls", type=cli_args.names, default=None,
                   help="implementations (default: all own ones + installed references)")
    p.add_argument("--datasets", type=cli_args.names, default=None,
                   help=f"datasets (default {', '.join(DEMO_DATASETS)})")
    p.add_argument("--sizes", type=cli_args.sizes, default=None,
                   help="sizes (default 1k,3k,10k; up to 100k when only qhull is available)")
    p.add_argument("--repeat", type=cli_args.positive_int, default=None,
                   help="timed builds per case, at least (default 3; 5 with --full)")
    p.add_argument("--min-time", type=cli_args.non_negative_float, default=None,
                   help="repeat short builds until this many seconds are timed (default 0.1; 0.3 with --full)")
    p.add_argument("--full", action="store_true",
                   help=f"the big matrix: datasets {', '.join(FULL_DATASETS)}, sizes up to 30k (300k for qhull "
                        f"alone), 5 repeats; about a quarter of an hour on 2 cores")
    p.add_argument("--budget", type=cli_args.positive_float, default=2.0,
                   help="skip builds extrapolated to take longer than this many seconds (default 2)")
    p.add_argument("--timeout", type=cli_args.positive_float, default=60.0,
                   help="seconds per build and per check (default 60)")
    p.add_argument("--plugin", action="append", default=[], metavar="MODULE",
                   help="extra implementations: a module or .py file defining IMPLEMENTATIONS, or a "
                        "program's manifest (impl.toml; docs/executables.md); repeatable")
    p.add_argument("--resume", action="store_true", help="continue an interrupted demo in the same folder")
    p.add_argument("--title", default=None, help="report title")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no line per case")


def run(args: argparse.Namespace) -> int:
    from vorobench.harness.report import write_report
    from vorobench.harness.runner import RunConfig

    console = Console(stderr=True)
    names = args.impls or demo_implementations()
    if not names:
        raise ValueError("no implementation available")
    datasets = args.datasets or list(FULL_DATASETS if args.full else DEMO_DATASETS)
    sizes = args.sizes or list(demo_sizes(len(names), full=args.full))
    repeat = args.repeat or (5 if args.full else 3)
    min_time = args.min_time if args.min_time is not None else (0.3 if args.full else 0.1)
    out = Path(args.out) if args.out else Path("reports") / f"{_dt.date.today():%Y-%m-%d}"
    results_csv = out / "results.csv"
    config = RunConfig(repeat=repeat, min_time=min_time, timeout=args.timeout,
                       reference=impls.DEFAULT_REFERENCE, check=True, plugins=tuple(args.plugin), budget=args.budget)
    console.print(f"vorobench demo: {', '.join(names)} on {len(datasets)} datasets x sizes "
                  f"{', '.join(map(str, sizes))}, {repeat} repeats, certified and compared with qhull")
    for note in size_notes(datasets, sizes):
        console.print(f"  sizes: {note}")
    started = time.perf_counter()
    code, _ = execute(names, datasets, sizes, [0], results_csv, config, resume=args.resume,
                      overwrite=not args.resume, progress=not args.quiet, verbose=not args.quiet,
                      console=console)
    if code != 0:
        return code
    # The report reads the declared complexities from the run's metadata: no plugin is imported here.
    from vorobench.harness.demo import skipped_notes
    from vorobench.harness.results import ResultsFile

    skipped = skipped_notes(ResultsFile(results_csv).rows())
    if skipped:
        console.print(f"{len(skipped)} case(s) not run:")
        for note in skipped:
            console.print(f"  {note}")
    rep = write_report(results_csv, out, title=args.title or f"demo {out.name}", reference=impls.DEFAULT_REFERENCE)
    minutes = (time.perf_counter() - started) / 60
    print(f"Report ({minutes:.1f} min): {rep.markdown} (figures next to it; single-file HTML: {rep.html})")
    return 0
