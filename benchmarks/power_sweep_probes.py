"""How local the weighted sweep's probes are: probes per site of the exact reference sweep.

    .venv/bin/python benchmarks/power_sweep_probes.py [--sizes 40,120,360] [--cases uniform:radii,...|all]
                                                     [--check] [--candidates]

For each case (dataset:weight family; ``all``: every dataset with every weight family) and
size, ``ProbingSweep`` (impls/fortune/power_reference.py) runs once and prints its probes per
site, the largest set of present sites a pending site kept, its hidden sites, and its run time
(Python and rationals: the time says nothing about a compiled sweep; the counts are machine
independent). ``--check`` compares each diagram with the half-plane oracle (``--candidates``:
the diagram of the candidates way, ``Sweep``, instead) and ends with the count that differ.
docs/power.md quotes the default run.
"""

from __future__ import annotations

import argparse
import time

import datasets_gen
import impls
from impls.fortune.power_reference import ProbingSweep, build_weighted
from vorobench.core.prepare import prepare_weighted
from vorobench.judge.comparison import Verdict, compare

DEFAULT_CASES = "uniform:radii,uniform:hidden,kuzmin:radii"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="40,120,360", help="comma-separated n (default 40,120,360)")
    parser.add_argument("--cases", default=DEFAULT_CASES, help=f"dataset:weights, comma-separated (default {DEFAULT_CASES})")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--check", action="store_true", help="compare each diagram with the half-plane oracle")
    parser.add_argument("--candidates", action="store_true", help="with --check: judge Sweep's diagram, not ProbingSweep's")
    args = parser.parse_args()
    cases = ([f"{d}:{f}" for d in datasets_gen.available() for f in datasets_gen.WEIGHT_FAMILIES]
             if args.cases == "all" else args.cases.split(","))
    differ = 0
    sizes = [int(v) for v in args.sizes.split(",")]
    print(f"{'case':<18} {'n':>5} {'probes/site':>12} {'max |S|':>8} {'hidden':>7} {'seconds':>8}" + ("  oracle" if args.check else ""))
    for case in cases:
        dataset, family = case.split(":")
        for n in sizes:
            points = datasets_gen.generate(dataset, n, seed=args.seed)
            sites, weights, _ = prepare_weighted(points, datasets_gen.weights(family, points, seed=args.seed))
            start = time.perf_counter()
            sweep = ProbingSweep(sites, weights)
            sweep.run()
            seconds = time.perf_counter() - start
            m = sites.shape[0]
            line = (f"{case:<18} {m:>5} {sweep.counts['probes'] / m:>12.2f} "
                    f"{max((len(v) for v in sweep.watch.values()), default=0):>8} {len(sweep.hidden):>7} {seconds:>8.1f}")
            if args.check:
                verdict = compare(build_weighted(sites, weights, probing=not args.candidates),
                                  impls.get("halfplane").build_weighted(sites, weights)).verdict
                differ += verdict != Verdict.EXACT
                line += f"  {'exact' if verdict == Verdict.EXACT else verdict.value}"
            print(line, flush=True)
    if args.check:
        print(f"{differ} of {len(cases) * len(sizes)} diagrams differ from the oracle")


if __name__ == "__main__":
    main()
