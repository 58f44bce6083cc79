"""Fortune's sweep vs scipy.spatial.Voronoi: time per site over n, peak memory, start-up.

    .venv/bin/python benchmarks/fortune_scaling.py                    # everything below
    .venv/bin/python benchmarks/fortune_scaling.py --sizes 1000000 --rounds 5 --skip-startup

1. Time: for each n the two builds alternate (``--rounds`` times each, so both see the same
   machine load) on the same prepared ``uniform`` sites; medians of wall-clock and of this
   process's CPU time (less sensitive to other jobs on a shared machine). Targets: ratio
   fortune / scipy <= 0.2 at n = 10^6; microseconds per site / log2(n) flat within 2x.
2. Peak memory of one build at the largest n, from ``/usr/bin/time -v`` around a fresh
   process (target < 1 GB), next to the same process without the build.
3. Start-up: a fresh process that imports the project and builds 1,000 points, with numba's
   on-disk cache warm (target < 2 s), and the cold (first ever) compile time, measured with
   an empty temporary NUMBA_CACHE_DIR.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.spatial import Voronoi

import datasets_gen
import impls
from vorobench.core.prepare import prepare

TARGET_RATIO = 0.2
TARGET_PEAK_MB = 1024
TARGET_STARTUP_S = 2.0

_BUILD_ONCE = """
import sys, numpy as np, datasets_gen, impls
from vorobench.core.prepare import prepare
n, build = int(sys.argv[1]), sys.argv[2] == "build"
sites, _ = prepare(datasets_gen.generate("uniform", n, seed=0))
impl = impls.get("fortune")
if build:
    impl.build(sites)
"""

_STARTUP = """
import time
t0 = time.perf_counter()
import numpy as np
import impls
impls.build("fortune", np.random.default_rng(0).random((1000, 2)))
print(time.perf_counter() - t0)
"""


def _timed(fn) -> tuple[float, float]:
    """(wall seconds, CPU seconds of this process) of one call."""
    w0, c0 = time.perf_counter_ns(), time.process_time_ns()
    fn()
    return (time.perf_counter_ns() - w0) / 1e9, (time.process_time_ns() - c0) / 1e9


def measure_time(n: int, rounds: int) -> dict:
    sites, _ = prepare(datasets_gen.generate("uniform", n, seed=0))
    impl = impls.get("fortune")
    stats: dict = {}
    impl.build(sites, stats)                          # untimed: counts, caches warm
    centred = sites - sites.mean(axis=0)              # what the qhull adapter gives Qhull
    ours, theirs = [], []
    for _ in range(rounds):
        ours.append(_timed(lambda: impl.build(sites)))
        theirs.append(_timed(lambda: Voronoi(centred)))
    ow, oc = np.median(ours, axis=0)
    sw, sc = np.median(theirs, axis=0)
    return dict(n=n, fortune_s=ow, fortune_cpu_s=oc, scipy_s=sw, scipy_cpu_s=sc, ratio=ow / sw,
                ratio_cpu=oc / sc, us_per_site=ow / n * 1e6, per_log=ow / n / math.log2(n) * 1e6,
                per_log_cpu=oc / n / math.log2(n) * 1e6, stats=stats)


def peak_rss_mb(n: int, build: bool) -> float:
    """Maximum resident set size (MB) of a fresh process preparing n sites (and building them)."""
    out = subprocess.run(["/usr/bin/time", "-v", sys.executable, "-c", _BUILD_ONCE, str(n),
                          "build" if build else "nobuild"], capture_output=True, text=True, check=True)
    kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", out.stderr).group(1))
    return kb / 1024


def startup_s(cache_dir: str | None = None) -> tuple[float, float, float]:
    """Seconds to import the project and build 1,000 points in a fresh process: (inside the
    process, wall clock of the whole process, its CPU time: user + system)."""
    env = dict(os.environ)
    if cache_dir is not None:
        env["NUMBA_CACHE_DIR"] = cache_dir
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", _STARTUP], capture_output=True, text=True, check=True, env=env)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return float(out.stdout.strip().splitlines()[-1]), wall, cpu


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--skip-memory", action="store_true")
    parser.add_argument("--skip-startup", action="store_true")
    args = parser.parse_args(argv)

    impl = impls.get("fortune")
    w0 = time.perf_counter()
    impl.warmup()
    print(f"warm-up (numba cache load or JIT compile): {time.perf_counter() - w0:.2f} s")
    print(f"load: {os.getloadavg()[0]:.2f} (1-minute average; {os.cpu_count()} CPUs)\n")

    print(f"{'n':>9} {'fortune s':>10} {'scipy s':>9} {'ratio':>6} {'ratio cpu':>9} "
          f"{'us/site':>8} {'us/site/log2n':>13} {'(cpu)':>7}  events/site")
    rows = []
    for n in args.sizes:
        r = measure_time(n, args.rounds)
        rows.append(r)
        st = r["stats"]
        print(f"{n:>9} {r['fortune_s']:>10.3f} {r['scipy_s']:>9.3f} {r['ratio']:>6.3f} {r['ratio_cpu']:>9.3f} "
              f"{r['us_per_site']:>8.3f} {r['per_log']:>13.4f} {r['per_log_cpu']:>7.4f}  "
              f"circle {st['circle_events'] / n:.2f}, false {st['false_alarms'] / n:.2f}, "
              f"breakpoint tests {st['breakpoint_tests'] / n:.1f}, max beach {st['max_beach_line']}", flush=True)
    if len(rows) >= 2:
        spread = max(r["per_log"] for r in rows) / min(r["per_log"] for r in rows)
        spread_cpu = max(r["per_log_cpu"] for r in rows) / min(r["per_log_cpu"] for r in rows)
        print(f"\nus/site/log2(n): max/min = {spread:.2f} wall, {spread_cpu:.2f} CPU (target <= 2)")
    big = rows[-1]
    verdict = "met" if big["ratio"] <= TARGET_RATIO else f"missed by {big['ratio'] / TARGET_RATIO:.2f}x"
    print(f"ratio at n = {big['n']}: {big['ratio']:.3f} wall, {big['ratio_cpu']:.3f} CPU "
          f"(target <= {TARGET_RATIO}: {verdict})")

    if not args.skip_memory:
        n = max(args.sizes)
        base, peak = peak_rss_mb(n, build=False), peak_rss_mb(n, build=True)
        print(f"\npeak RSS at n = {n}: {peak:.0f} MB with the build, {base:.0f} MB without "
              f"(target < {TARGET_PEAK_MB} MB: {'met' if peak < TARGET_PEAK_MB else 'missed'})")

    if not args.skip_startup:
        inside, wall, cpu = startup_s()
        print(f"\nstart-up, warm numba cache: {inside:.2f} s in-process, {wall:.2f} s whole process, "
              f"{cpu:.2f} s CPU (target < {TARGET_STARTUP_S} s: {'met' if wall < TARGET_STARTUP_S else 'missed'})")
        with tempfile.TemporaryDirectory() as cold:
            inside, wall, cpu = startup_s(cold)
        print(f"start-up, cold (empty numba cache, everything compiled): {inside:.1f} s in-process, "
              f"{wall:.1f} s whole process, {cpu:.1f} s CPU")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
