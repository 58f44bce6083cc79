"""Trends across the runs of a run store: every case's build time and counters, run after run,
with the change points marked at their commit.

    vorobench trend DIR -o trend.html [--json changes.json] [--machine PREFIX]
        [--impls a,b] [--datasets x,y] [--threshold 0.10] [--alpha 0.05]

DIR is a run store (``bench --store DIR``). The page (``-o``) is one self-contained HTML file
(plotly.js inlined once; it works offline). It opens with a table of every change point, then
has one figure per machine, implementation and dataset: the median build time of each case
(one line per n and seed) over the runs in date order, with the min-max of the repeats as
bars, and below it the counters that changed. The x axis names each run by vorobench's commit
(``+``: the tree was dirty); hovering a point gives the date, run id, commit, median, min-max
and repeats. ``--json FILE`` writes the change points for CI.

Machines are kept apart: each machine fingerprint has its own section and its own sequence of
runs, and no line joins runs of two machines (``--machine PREFIX`` keeps one).

Change points (rules in :mod:`vorobench.harness.changepoints`): a time step is a split of the series
of per-run medians found by binary segmentation of log time, kept only if the medians of the
repeats on its two sides differ by more than ``--threshold`` (default 10 %) and a two-sided
Mann-Whitney U test of those repeats gives p < ``--alpha`` (default 0.05). A counter
(``stat_*``, exact) changes wherever its value differs from the previous run's. A change
between two runs of the same clean commit (of vorobench and of the implementation's code, from
the same module) is marked ``same_code``: the machine changed, not the code.
The exit status is 0 whatever was found (``compare`` is the gate); 2 when DIR is not a run
store, holds no run, or the filters leave nothing.
"""

from __future__ import annotations

import argparse
import json

from vorobench.cli.args import fraction, names, positive_float

# The harness and the judge are imported inside the functions that run the command, not here:
# the parser imports every command module (start-up time, measured in vorobench.cli).

__all__ = ["add_arguments", "run"]


def add_arguments(p: argparse.ArgumentParser) -> None:
    # At least one of -o and --json is needed; argparse's usage would show both as optional.
    p.usage = ("vorobench trend STORE {-o HTML | --json FILE | both} [--machine PREFIX] [--impls IMPLS] "
               "[--datasets DATASETS] [--threshold THRESHOLD] [--alpha ALPHA] [--measure {auto,cpu,wall}]")
    p.add_argument("store", help="run store folder (filled by `vorobench bench --store DIR`)")
    p.add_argument("-o", "--out", default=None, metavar="HTML",
                   help="write the page here (self-contained HTML); this, --json or both is needed")
    p.add_argument("--json", default=None, metavar="FILE",
                   help="write the change points here as JSON (for CI); this, -o or both is needed")
    p.add_argument("--machine", default=None, metavar="PREFIX",
                   help="only the runs of the machine fingerprint starting with PREFIX")
    p.add_argument("--impls", type=names, default=None, help="only these implementations (comma-separated)")
    p.add_argument("--datasets", type=names, default=None, help="only these datasets (comma-separated)")
    p.add_argument("--threshold", type=positive_float, default=0.10,
                   help="smallest time step reported, as a fraction (default 0.10 = 10%%)")
    p.add_argument("--alpha", type=fraction, default=0.05,
                   help="significance level of the rank test of a time step (default 0.05)")
    p.add_argument("--measure", choices=("auto", "cpu", "wall"), default="auto",
                   help="what a build's time is: cpu, wall, or auto (default: cpu where every run of a machine "
                        "recorded it, else wall), as compare chooses")


def run(args: argparse.Namespace) -> int:
    from vorobench.harness.atomic import replace_atomically
    from vorobench.harness.store import Store
    from vorobench.harness.trend import detect, format_seconds, load, render, run_label, trend_json

    if not args.out and not args.json:
        raise ValueError("nothing to write: give -o HTML for the page and/or --json FILE for the change points")
    store = Store(args.store)
    machines = load(store, machine=args.machine, impls=args.impls, datasets=args.datasets, measure=args.measure)
    points = detect(machines, threshold=args.threshold, alpha=args.alpha)
    runs = sum(len(m.runs) for m in machines)
    series = sum(len(m.series) for m in machines)
    n_time = sum(p.kind == "time" for p in points)
    print(f"trend of {args.store}: {runs} runs on {len(machines)} machine(s), {series} series; "
          f"{n_time} time step(s), {len(points) - n_time} counter change(s)")
    shown = 0
    for p in points:
        if shown == 20:
            print(f"  and {len(points) - shown} more")
            break
        shown += 1
        where = f"{run_label(p.commit_before, p.dirty_before, p.run_id_before)} -> {run_label(p.commit, p.dirty, p.run_id)}"
        if p.kind == "time":
            print(f"  {p.machine_id} {p.case}: time {format_seconds(p.before)} -> {format_seconds(p.after)} ({p.ratio:.2f}x, "
                  f"p={p.p_value:.2g}) at {where}" + (" (same code)" if p.same_code else ""))
        else:
            print(f"  {p.machine_id} {p.case}: {p.counter} {p.before} -> {p.after} at {where}")
    if args.out:
        page = render(str(args.store), machines, points, args.threshold, args.alpha)
        replace_atomically(args.out, lambda f: f.write(page))
        print(f"wrote {args.out}")
    if args.json:
        doc = trend_json(str(args.store), machines, points, args.threshold, args.alpha)
        replace_atomically(args.json, lambda f: f.write(json.dumps(doc, indent=2, default=str) + "\n"))
        print(f"wrote {args.json}")
    return 0
