"""Does the weighted ``fortune`` agree exactly with an exact oracle on every dataset and weight family?

    .venv/bin/python benchmarks/power_sweep_agreement.py                          # incremental
    .venv/bin/python benchmarks/power_sweep_agreement.py --oracle cgal --sizes 2,3,10,120,1000

Builds each case (every ``datasets_gen`` family x every weight family x each size, seed 0)
with ``impls.fortune.build_weighted`` and with the oracle, in this process, and prints each
case whose ``compare`` verdict is not ``exact``, the slow ones (over 2 s, with the number of
decisions the sweep took in rationals), and the count of cases that differ. Exit status 1 if
any differs.
"""

from __future__ import annotations

import argparse
import time

import datasets_gen
import impls
from impls.fortune import build_weighted
from vorobench.core.prepare import prepare_weighted
from vorobench.judge.comparison import Verdict, compare


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="2,3,10,120,1000")
    parser.add_argument("--oracle", default="incremental", help="an exact implementation that takes weights")
    args = parser.parse_args()
    oracle = impls.get(args.oracle)
    sizes = [int(v) for v in args.sizes.split(",")]
    differ = total = 0
    start = time.perf_counter()
    for dataset in datasets_gen.available():
        for family in datasets_gen.WEIGHT_FAMILIES:
            for n in sizes:
                points = datasets_gen.generate(dataset, n, seed=0)
                sites, weights, _ = prepare_weighted(points, datasets_gen.weights(family, points, seed=0))
                stats: dict = {}
                total += 1
                try:
                    t = time.perf_counter()
                    d = build_weighted(sites, weights, stats)
                    seconds = time.perf_counter() - t
                    verdict = compare(d, oracle.build_weighted(sites, weights)).verdict
                    message = verdict.value
                except RuntimeError as error:
                    verdict, message, seconds = None, f"RuntimeError: {error}", 0.0
                if verdict != Verdict.EXACT:
                    differ += 1
                    print(f"DIFFERS {dataset} {family} n={n}: {message}", flush=True)
                elif seconds > 2:
                    print(f"slow {dataset} {family} n={n}: {seconds:.1f} s, "
                          f"{stats.get('weighted_exact', 0)} exact decisions", flush=True)
    print(f"{differ} of {total} cases differ from {args.oracle} ({time.perf_counter() - start:.0f} s)")
    return 1 if differ else 0


if __name__ == "__main__":
    raise SystemExit(main())
