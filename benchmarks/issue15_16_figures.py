"""Figures of issues 15 and 16: the cost of the scipy-style views, and weighted against ordinary
builds of qhull and halfplane (best of 3, warm, one process).

    .venv/bin/python benchmarks/issue15_16_figures.py
"""

from __future__ import annotations

import time

import numpy as np

import datasets_gen
import impls


def _best_of(repeats: int, build) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        build()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    rng = np.random.default_rng(1)
    for n in (10**3, 10**4, 10**5, 10**6):
        d = impls.build("incremental", rng.random((n, 2)))
        t0 = time.perf_counter()
        d.regions
        t1 = time.perf_counter()
        for i in range(100):
            d.regions[d.point_region[i]]
        print(f"regions n={n}: first call {t1 - t0:.4f} s, then 100 lookups {time.perf_counter() - t1:.6f} s")
    for name, n in (("qhull", 10**5), ("halfplane", 10**4)):
        pts = datasets_gen.generate("uniform", n, seed=0)
        w = datasets_gen.weights("radii", pts, seed=0)
        impls.build(name, pts[:50])
        impls.build(name, pts[:50], weights=w[:50])          # compiled and warm before timing
        ordinary = _best_of(3, lambda: impls.build(name, pts))
        weighted = _best_of(3, lambda: impls.build(name, pts, weights=w))
        print(f"{name} n={n}: ordinary {ordinary:.3f} s, radii-weighted {weighted:.3f} s, "
              f"ratio {weighted / ordinary:.2f}")


if __name__ == "__main__":
    main()
