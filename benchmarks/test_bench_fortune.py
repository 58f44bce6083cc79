"""Fortune's sweep against scipy.spatial.Voronoi on the same ``uniform`` sites, n = 10^4 .. 10^6.

    .venv/bin/python -m pytest benchmarks/test_bench_fortune.py --benchmark-only

Both builds are timed in one run (grouped by n, so the table shows them side by side); the
fortune benchmark also stores ``ratio_vs_scipy`` (target <= 0.2 at n = 10^6), the counters
and ``us_per_site_per_log2n`` (should stay flat within 2x over the sizes) in ``extra_info``.
"""

from __future__ import annotations

import math

import pytest
from scipy.spatial import Voronoi

SIZES = (10_000, 100_000, 1_000_000)


@pytest.mark.parametrize("n", SIZES)
def test_fortune(benchmark, sites_of, build_benchmark, scipy_ratio, n):
    sites = sites_of("uniform", n)
    benchmark.group = f"fortune vs scipy, uniform n={n}"
    diagram = build_benchmark(benchmark, "fortune", sites, rounds=3 if n >= 1_000_000 else None)
    stats = getattr(getattr(benchmark, "stats", None), "stats", None)
    if stats is not None:
        benchmark.extra_info["us_per_site_per_log2n"] = stats.median / n / math.log2(n) * 1e6
    scipy_ratio(benchmark, sites, rounds=3 if n >= 1_000_000 else 5)
    assert diagram.n_vertices > n             # about 2n - 2 - h vertices for points in general position


@pytest.mark.parametrize("n", SIZES)
def test_scipy_voronoi(benchmark, sites_of, n):
    sites = sites_of("uniform", n)
    centred = sites - sites.mean(axis=0)          # what the qhull adapter hands to Qhull
    benchmark.group = f"fortune vs scipy, uniform n={n}"
    vor = benchmark.pedantic(Voronoi, args=(centred,), rounds=3 if n >= 1_000_000 else 5, iterations=1)
    assert vor.vertices.shape[0] > n
