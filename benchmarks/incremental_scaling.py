"""Incremental construction vs scipy.spatial.Voronoi: time table over n, ratio in the same run.

    .venv/bin/python benchmarks/incremental_scaling.py                  # n = 1e4 .. 1e6
    .venv/bin/python benchmarks/incremental_scaling.py --sizes 1000000 --rounds 5

For each dataset and n, the two builds alternate (``--rounds`` times each, so both see the
same machine load) and the medians are compared, both in wall-clock time and in CPU time of
this process (less sensitive to other jobs on a shared machine). Target: ratio <= 0.15 at
n = 10^6 on ``uniform`` and ``sorted``. Also prints machine-independent counts per site.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.spatial import Voronoi

import datasets_gen
import impls
from vorobench.core.prepare import prepare

TARGET_RATIO = 0.15


def _timed(fn) -> tuple[float, float]:
    """(wall seconds, CPU seconds of this process) of one call."""
    w0, c0 = time.perf_counter_ns(), time.process_time_ns()
    fn()
    return (time.perf_counter_ns() - w0) / 1e9, (time.process_time_ns() - c0) / 1e9


def measure(dataset: str, n: int, rounds: int) -> dict:
    """Median wall and CPU times of the incremental build and of scipy on the same sites."""
    sites, _ = prepare(datasets_gen.generate(dataset, n, seed=0))
    impl = impls.get("incremental")
    stats: dict = {}
    impl.build(sites, stats)                          # untimed: counts, caches warm
    centred = sites - sites.mean(axis=0)              # what the qhull adapter gives Qhull
    ours, theirs = [], []
    for _ in range(rounds):
        ours.append(_timed(lambda: impl.build(sites, None)))
        theirs.append(_timed(lambda: Voronoi(centred)))
    ours_wall, ours_cpu = np.median(ours, axis=0)
    scipy_wall, scipy_cpu = np.median(theirs, axis=0)
    m = sites.shape[0]
    return {"dataset": dataset, "n": m, "ours_wall": ours_wall, "scipy_wall": scipy_wall,
            "ratio_wall": ours_wall / scipy_wall, "ours_cpu": ours_cpu, "scipy_cpu": scipy_cpu,
            "ratio_cpu": ours_cpu / scipy_cpu, "walk_per_site": stats["walk_steps"] / m,
            "incircle_per_site": stats["incircle_calls"] / m, "cavity_per_site": stats["cavity_triangles"] / m,
            "exact_fallbacks": stats["incircle_exact"] + stats["orient2d_exact"]}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--datasets", nargs="+", default=["uniform", "sorted"])
    parser.add_argument("--sizes", nargs="+", type=int, default=[10_000, 100_000, 1_000_000])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    impls.get("incremental").warmup()
    print(f"{'dataset':<9} {'n':>9} {'ours s':>8} {'scipy s':>8} {'ratio':>6} {'ours cpu':>9} "
          f"{'scipy cpu':>9} {'ratio':>6}  {'walk/n':>6} {'incirc/n':>8} {'cavity/n':>8} {'exact':>5}")
    worst = 0.0
    for dataset in args.datasets:
        for n in args.sizes:
            r = measure(dataset, n, args.rounds)
            print(f"{r['dataset']:<9} {r['n']:>9} {r['ours_wall']:>8.3f} {r['scipy_wall']:>8.3f} "
                  f"{r['ratio_wall']:>6.3f} {r['ours_cpu']:>9.3f} {r['scipy_cpu']:>9.3f} {r['ratio_cpu']:>6.3f}  "
                  f"{r['walk_per_site']:>6.2f} {r['incircle_per_site']:>8.2f} {r['cavity_per_site']:>8.2f} "
                  f"{r['exact_fallbacks']:>5}", flush=True)
            if n >= 1_000_000:
                worst = max(worst, r["ratio_wall"])
    if worst:
        print(f"worst wall-clock ratio at n >= 10^6: {worst:.3f} (target <= {TARGET_RATIO})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
