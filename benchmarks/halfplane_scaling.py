"""Half-plane oracle: build time over n on ``uniform`` and the fitted growth exponent.

    .venv/bin/python benchmarks/halfplane_scaling.py                     # n = 5000 .. 80000, ~1 min
    .venv/bin/python benchmarks/halfplane_scaling.py --sizes 1000 2000 4000 --rounds 5

Prints n, median wall and CPU seconds, clips (= n (n - 1), every ordered pair) and exact
vertex tests, then the least-squares slope of log(time) against log(n), over all sizes and
over the larger half (where the n^2 pair loop dominates the O(n) work per cell): about 2 for
an O(n^2) method. Target: n = 20,000 in under 60 s.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import datasets_gen
import impls
from vorobench.core.prepare import prepare
from vorobench.harness.analysis import loglog_fit

TARGET_N, TARGET_SECONDS = 20_000, 60.0


def fitted_exponent(sizes, seconds) -> float:
    """Slope of the least-squares line through (log n, log t)."""
    return loglog_fit(sizes, seconds)[0]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dataset", default="uniform")
    parser.add_argument("--sizes", nargs="+", type=int, default=[5000, 10_000, 20_000, 40_000, 80_000])
    parser.add_argument("--rounds", type=int, default=1)
    args = parser.parse_args()
    impl = impls.get("halfplane")
    impl.warmup()
    print(f"{'n':>7} {'wall s':>8} {'cpu s':>8} {'clips':>12} {'vertex tests':>13} {'prefiltered':>12}")
    sizes, walls, cpus = [], [], []
    for n in args.sizes:
        sites, _ = prepare(datasets_gen.generate(args.dataset, n, seed=0))
        stats: dict = {}
        runs = []
        for r in range(args.rounds):
            w0, c0 = time.perf_counter_ns(), time.process_time_ns()
            impl.build(sites, stats if r == 0 else None)
            runs.append(((time.perf_counter_ns() - w0) / 1e9, (time.process_time_ns() - c0) / 1e9))
        wall, cpu = np.median(runs, axis=0)
        sizes.append(n)
        walls.append(wall)
        cpus.append(cpu)
        print(f"{n:>7} {wall:>8.3f} {cpu:>8.3f} {stats['clips']:>12} {stats['vertex_tests']:>13} "
              f"{stats['prefiltered']:>12}", flush=True)
    if len(sizes) >= 2:
        print(f"fitted exponent (time ~ n^k), all sizes: wall k = {fitted_exponent(sizes, walls):.2f}, "
              f"cpu k = {fitted_exponent(sizes, cpus):.2f}")
    upper = len(sizes) // 2
    if len(sizes) - upper >= 2 and upper > 0:
        print(f"fitted exponent, n >= {sizes[upper]}: wall k = {fitted_exponent(sizes[upper:], walls[upper:]):.2f}, "
              f"cpu k = {fitted_exponent(sizes[upper:], cpus[upper:]):.2f}")
    if TARGET_N in sizes:
        t = walls[sizes.index(TARGET_N)]
        print(f"n = {TARGET_N}: {t:.1f} s wall (target < {TARGET_SECONDS:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
