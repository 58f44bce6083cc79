"""Weighted incremental (regular triangulation + power diagram) vs CGAL's Regular_triangulation_2.

    .venv/bin/python benchmarks/weighted_incremental.py                     # n = 2e4, 2e5
    .venv/bin/python benchmarks/weighted_incremental.py --sizes 200000 --rounds 7 --weights many_hidden

In one process, after warming up (the numba compile or cache load is timed and printed
apart), the builds alternate ``--rounds`` times each on the same prepared sites and the medians
are compared, wall clock and CPU time of this process:

* ``cgal``: ``Regular_triangulation_2().insert(list)`` alone (its spatial sort and insertion;
  the Python list of ``Weighted_point_2`` is made beforehand, untimed);
* ``ours tri``: the regular triangulation alone (insertion order + insertion with flips);
* ``ours build``: the whole power diagram (triangulation, dual, DCEL);
* ``equal``: the weighted build with all weights equal, against ``unweighted``, the ordinary
  build of the same sites (goal: within ~1.3x).

Issue 16's target: the weighted build at most 3x CGAL's insertion at n = 2 x 10^5.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from impls.incremental import build, build_weighted, regular, warmup
from vorobench.core.prepare import prepare_weighted

TARGET_RATIO = 3.0


def _timed(fn) -> tuple[float, float]:
    """(wall seconds, CPU seconds of this process) of one call."""
    w0, c0 = time.perf_counter_ns(), time.process_time_ns()
    fn()
    return (time.perf_counter_ns() - w0) / 1e9, (time.process_time_ns() - c0) / 1e9


def weighted_sites(family: str, n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Prepared uniform sites in the unit square with weights from random radii: ``radii``
    (radius up to half the mean spacing, few hidden), ``many_hidden`` (90% tiny among larger)."""
    rng = np.random.default_rng(seed)
    points = rng.random((n, 2))
    spacing = 1.0 / np.sqrt(n)
    if family == "radii":
        radii = rng.random(n) * 0.5 * spacing
    elif family == "many_hidden":
        radii = np.where(rng.random(n) < 0.9, 0.05, 1.5) * rng.random(n) * spacing
    else:
        raise ValueError(f"unknown weight family {family!r}")
    sites, weights, _ = prepare_weighted(points, radii ** 2)
    return sites, weights


def cgal_insert(sites: np.ndarray, weights: np.ndarray):
    """A function timing nothing but CGAL's insertion of the weighted points (None without CGAL)."""
    try:
        from CGAL.CGAL_Kernel import Point_2, Weighted_point_2
        from CGAL.CGAL_Triangulation_2 import Regular_triangulation_2
    except ImportError:
        return None
    points = [Weighted_point_2(Point_2(float(x), float(y)), float(w)) for (x, y), w in zip(sites, weights)]

    def insert():
        rt = Regular_triangulation_2()
        rt.insert(points)
        insert.hidden = rt.number_of_hidden_vertices()
    return insert


def measure(family: str, n: int, rounds: int) -> dict:
    sites, weights = weighted_sites(family, n)
    equal = np.full(sites.shape[0], 0.25 / n)
    stats: dict = {}
    build_weighted(sites, weights, stats)                # untimed: counts, caches warm
    cgal = cgal_insert(sites, weights)
    runs = {"cgal": [], "tri": [], "build": [], "equal": [], "unweighted": []}
    for _ in range(rounds):
        if cgal is not None:
            runs["cgal"].append(_timed(cgal))
        runs["tri"].append(_timed(lambda: regular(sites, weights)))
        runs["build"].append(_timed(lambda: build_weighted(sites, weights)))
        runs["equal"].append(_timed(lambda: build_weighted(sites, equal)))
        runs["unweighted"].append(_timed(lambda: build(sites)))
    med = {k: np.median(v, axis=0) if v else (np.nan, np.nan) for k, v in runs.items()}
    m = sites.shape[0]
    return {"n": m, "med": med, "hidden": stats["hidden"], "cgal_hidden": getattr(cgal, "hidden", -1),
            "flips_per_site": stats["flips"] / m, "power_per_site": stats["power_test_calls"] / m,
            "removals": stats["flips_3_1"] + stats["flips_4_2"],
            "exact": stats["power_test_exact"] + stats["orient2d_exact"]}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", type=int, default=[20_000, 200_000])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--weights", default="radii", choices=["radii", "many_hidden"])
    args = parser.parse_args()
    wall, cpu = _timed(warmup)
    print(f"warm-up (numba compile or cache load, all incremental kernels): {wall:.2f} s wall, {cpu:.2f} s CPU")
    print(f"weights: {args.weights}; medians of {args.rounds} alternating rounds; seconds (CPU seconds)")
    print(f"{'n':>7} {'cgal':>15} {'ours tri':>15} {'ours build':>15} {'build/cgal':>10} {'tri/cgal':>8} "
          f"{'equal':>15} {'unweighted':>15} {'eq/unw':>6}  {'hidden':>6} {'cgal hid':>8} {'flips/n':>7} "
          f"{'power/n':>7} {'removed':>7} {'exact':>5}")
    ratio_at_largest = None
    for n in args.sizes:
        r = measure(args.weights, n, args.rounds)
        med = r["med"]

        def cell(k):
            return f"{med[k][0]:.3f} ({med[k][1]:.3f})"
        build_ratio = med["build"][0] / med["cgal"][0]
        tri_ratio = med["tri"][0] / med["cgal"][0]
        print(f"{r['n']:>7} {cell('cgal'):>15} {cell('tri'):>15} {cell('build'):>15} {build_ratio:>10.2f} "
              f"{tri_ratio:>8.2f} {cell('equal'):>15} {cell('unweighted'):>15} "
              f"{med['equal'][0] / med['unweighted'][0]:>6.2f}  {r['hidden']:>6} {r['cgal_hidden']:>8} "
              f"{r['flips_per_site']:>7.2f} {r['power_per_site']:>7.2f} {r['removals']:>7} {r['exact']:>5}", flush=True)
        ratio_at_largest = build_ratio
    if ratio_at_largest is not None and np.isfinite(ratio_at_largest):
        print(f"weighted build / CGAL insertion at n = {args.sizes[-1]}: {ratio_at_largest:.2f} "
              f"(target <= {TARGET_RATIO})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
