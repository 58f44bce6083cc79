"""Weighted ``fortune`` (the power-diagram sweep) against the ordinary sweep and CGAL.

    .venv/bin/python benchmarks/power_sweep_speed.py                          # n = 1e4, 1e5
    .venv/bin/python benchmarks/power_sweep_speed.py --sizes 10000 100000 1000000 --rounds 3
    .venv/bin/python benchmarks/power_sweep_speed.py --sizes 100000 --datasets grid,kuzmin,cocircular

In one process, after a warm-up (numba compile or cache load, timed and printed apart), the
builds alternate ``--rounds`` times on the same prepared sites and medians are compared:

* ``weighted``: ``impls.fortune.build_weighted`` (radii weights as in
  ``benchmarks/weighted_incremental.py``: radius up to half the mean spacing);
* ``ordinary``: ``impls.fortune.build`` of the same sites (issue 25's goal: weighted within 1.5x);
* ``cgal``: ``Regular_triangulation_2().insert`` of the same weighted points (goal: within 3x at
  2 x 10^5), with its count of hidden sites beside ours.

``--datasets`` adds the named families of ``datasets_gen`` with ``radii`` weights, each timed
against weighted uniform at the same n (goal: within 2x). With three sizes or more, the
exponent of a least-squares fit of log time against log n is printed (goal: at most 1.15).
"""

from __future__ import annotations

import argparse

import numpy as np

import datasets_gen
from impls.fortune import build, build_weighted, warmup
from vorobench.core.prepare import prepare_weighted
from weighted_incremental import _timed, cgal_insert, weighted_sites

TARGET_ORDINARY = 1.5
TARGET_CGAL = 3.0


def _family_sites(dataset: str, n: int) -> tuple[np.ndarray, np.ndarray]:
    if dataset == "uniform":
        return weighted_sites("radii", n)
    points = datasets_gen.generate(dataset, n, seed=0)
    sites, weights, _ = prepare_weighted(points, datasets_gen.weights("radii", points, seed=0))
    return sites, weights


def measure(sites: np.ndarray, weights: np.ndarray, rounds: int, with_cgal: bool) -> dict:
    stats: dict = {}
    build_weighted(sites, weights, stats)               # untimed: counts
    cgal = cgal_insert(sites, weights) if with_cgal else None
    runs: dict = {"weighted": [], "ordinary": [], "cgal": []}
    for _ in range(rounds):
        runs["weighted"].append(_timed(lambda: build_weighted(sites, weights))[0])
        runs["ordinary"].append(_timed(lambda: build(sites))[0])
        if cgal is not None:
            runs["cgal"].append(_timed(cgal)[0])
    med = {k: float(np.median(v)) if v else float("nan") for k, v in runs.items()}
    return {"n": sites.shape[0], "med": med, "stats": stats, "cgal_hidden": getattr(cgal, "hidden", -1)}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", type=int, default=[10_000, 100_000])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--datasets", default="", help="comma-separated datasets_gen families to time against uniform")
    parser.add_argument("--no-cgal", action="store_true", help="skip CGAL's Regular_triangulation_2")
    args = parser.parse_args()
    wall, _ = _timed(warmup)
    print(f"warm-up (numba compile or cache load, every fortune kernel): {wall:.2f} s")
    print(f"radii weights; medians of {args.rounds} alternating rounds; seconds")
    print(f"{'dataset':<12} {'n':>8} {'weighted':>9} {'ordinary':>9} {'w/ord':>6} {'cgal':>8} {'w/cgal':>7} "
          f"{'probes/n':>8} {'exact':>6} {'hidden':>7} {'cgal hid':>8} {'w/uniform':>9}")
    uniform_times = {}
    for dataset in ["uniform"] + [d for d in args.datasets.split(",") if d]:
        for n in args.sizes:
            sites, weights = _family_sites(dataset, n)
            r = measure(sites, weights, args.rounds, with_cgal=not args.no_cgal and dataset == "uniform")
            med, st = r["med"], r["stats"]
            if dataset == "uniform":
                uniform_times[n] = med["weighted"]
            against = med["weighted"] / uniform_times[n] if n in uniform_times else float("nan")
            print(f"{dataset:<12} {r['n']:>8} {med['weighted']:>9.3f} {med['ordinary']:>9.3f} "
                  f"{med['weighted'] / med['ordinary']:>6.2f} {med['cgal']:>8.3f} {med['weighted'] / med['cgal']:>7.2f} "
                  f"{st.get('probes', 0) / r['n']:>8.2f} {st.get('weighted_exact', 0):>6} {st['hidden_sites']:>7} "
                  f"{r['cgal_hidden']:>8} {against:>9.2f}", flush=True)
        if len(args.sizes) >= 3 and dataset == "uniform":
            slope = np.polyfit(np.log(args.sizes), np.log([uniform_times[n] for n in args.sizes]), 1)[0]
            print(f"fitted exponent of weighted uniform over n = {args.sizes[0]}..{args.sizes[-1]}: {slope:.3f}")
    print(f"goals: weighted / ordinary <= {TARGET_ORDINARY} at 10^6; weighted / cgal <= {TARGET_CGAL} at 2 x 10^5; "
          "each family within 2x of uniform; exponent <= 1.15")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
