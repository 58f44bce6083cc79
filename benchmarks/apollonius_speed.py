"""``fortune`` for disks against CGAL's ``Apollonius_graph_2`` (``cgal-cpp``) and the ordinary sweep.

    .venv/bin/python benchmarks/apollonius_speed.py                          # n = 1e3, 1e4
    .venv/bin/python benchmarks/apollonius_speed.py --sizes 1000 10000 30000 --rounds 3 --radii integer
    .venv/bin/python benchmarks/apollonius_speed.py --sizes 10000 100000 1000000    # issue 26's goals

In one process, on the same prepared disks (``uniform`` centres, radii of ``--radii``), the
builds alternate ``--rounds`` times and medians are compared (issue 26's goals):

* ``disks``: ``fortune``'s compiled sweep for disks (``impls.fortune.build_disks``; compiled or
  loaded from numba's cache before the first timed build);
* ``cgal``: ``cgal-cpp`` on the same disks, its own time line (the insertion alone,
  ``time_library_s``) and its whole build (process, protocol, and vorobench computing each
  vertex exactly from its faces); goal: ``disks`` faster than the insertion at 10^5;
* ``ordinary``: ``impls.fortune.build`` of the centres; goal: ``disks`` within 3x at 10^6.

Each size where CGAL runs (up to ``--cgal-up-to``) is also judged once: the two diagrams of disks
must agree exactly (``compare_disks``) and have the same hidden disks. With three sizes or more, the exponent of a least-squares fit
of log time against log n is printed (goal: at most 1.15). Needs the cgal-cpp toolchain
(``python3 dev.py setup --references``); without it, ``cgal`` is left out.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import datasets_gen
import impls
from impls.fortune import build as ordinary_build, build_disks
from vorobench.core.prepare import prepare_disks
from vorobench.judge.disk_judging import compare_disks

TARGET_CGAL = 1.0
TARGET_ORDINARY = 3.0


def _wall(fn) -> float:
    t0 = time.perf_counter_ns()
    fn()
    return (time.perf_counter_ns() - t0) / 1e9


def measure(n: int, family: str, rounds: int, with_cgal: bool) -> dict:
    points = datasets_gen.generate("uniform", n, seed=0)
    sites, radii, _ = prepare_disks(points, datasets_gen.radii(family, points, seed=0))
    ordinary_build(sites)                                      # numba cache loaded, untimed
    build_disks(sites[:50], radii[:50])
    cgal = impls.get("cgal-cpp") if with_cgal else None
    runs: dict = {"disks": [], "cgal_library": [], "cgal_whole": [], "ordinary": []}
    verdict = ""
    for k in range(rounds):
        holder: dict = {}
        runs["disks"].append(_wall(lambda: holder.update(disks=build_disks(sites, radii))))
        if cgal is not None:
            timings: dict = {}
            runs["cgal_whole"].append(_wall(lambda: holder.update(cgal=cgal.run(sites, radii=radii, timings=timings))))
            runs["cgal_library"].append(float(timings.get("library", float("nan"))))
            if k == 0:
                comp = compare_disks(holder["disks"], holder["cgal"])
                same_hidden = holder["disks"].hidden.tolist() == holder["cgal"].hidden.tolist()
                verdict = f"{comp.verdict.value}{'' if same_hidden else ', hidden sets DIFFER'}"
        runs["ordinary"].append(_wall(lambda: ordinary_build(sites)))
    med = {key: float(np.median(v)) if v else float("nan") for key, v in runs.items()}
    return {"n": int(sites.shape[0]), "med": med, "verdict": verdict}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", type=int, default=[1_000, 10_000])
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--radii", default="random", choices=sorted(datasets_gen.RADIUS_FAMILIES))
    parser.add_argument("--cgal-up-to", type=int, default=100_000, metavar="N",
                        help="time cgal-cpp at sizes up to N only (its whole build takes minutes at 10^5; default %(default)s)")
    args = parser.parse_args()
    with_cgal = "cgal-cpp" in impls.apollonius()
    print(f"uniform centres, {args.radii} radii, {args.rounds} rounds alternated; medians in seconds"
          + ("" if with_cgal else " (cgal-cpp's toolchain is not here: left out)"))
    print(f"{'n':>8} {'disks':>9} {'cgal ins':>9} {'cgal all':>9} {'ordinary':>9} {'disks/ins':>10} "
          f"{'disks/ord':>10}  agreement")
    rows = []
    for n in args.sizes:
        r = measure(n, args.radii, args.rounds, with_cgal and n <= args.cgal_up_to)
        m = r["med"]
        rows.append(r)
        print(f"{r['n']:>8} {m['disks']:>9.3f} {m['cgal_library']:>9.3f} {m['cgal_whole']:>9.3f} {m['ordinary']:>9.3f} "
              f"{m['disks'] / m['cgal_library']:>9.2f}x {m['disks'] / m['ordinary']:>9.1f}x  {r['verdict']}", flush=True)
    if len(rows) >= 3:
        slope = np.polyfit(np.log([r["n"] for r in rows]), np.log([r["med"]["disks"] for r in rows]), 1)[0]
        print(f"fitted exponent of the sweep for disks: {slope:.2f} (goal <= 1.15)")
    print(f"goals: disks/ins < {TARGET_CGAL} at 10^5; disks/ord <= {TARGET_ORDINARY} at 10^6")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
