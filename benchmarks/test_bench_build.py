"""Build time of every own implementation on a few datasets and sizes (pytest-benchmark).

Grouped by dataset and size, so the table compares implementations side by side;
``extra_info`` carries the counters and the ratio to scipy's Voronoi measured in the same run.
"""

from __future__ import annotations

import pytest

from vorobench.harness.demo import own_implementations

DATASETS = ("uniform", "clusters", "grid")
SIZES = (1_000, 10_000, 100_000)
#: Quadratic methods stop here (10^5 would take minutes per round).
QUADRATIC_MAX_N = 10_000


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("dataset", DATASETS)
@pytest.mark.parametrize("name", own_implementations())
def test_build(benchmark, sites_of, build_benchmark, scipy_ratio, quadratic, name, dataset, n):
    if n > QUADRATIC_MAX_N and quadratic(name):
        pytest.skip(f"{name} is quadratic; sizes above {QUADRATIC_MAX_N} are left to `vorobench bench`")
    sites = sites_of(dataset, n)
    benchmark.group = f"build {dataset} n={n}"
    diagram = build_benchmark(benchmark, name, sites, label=dataset)
    scipy_ratio(benchmark, sites)
    assert diagram.n_sites == sites.shape[0]
    assert diagram.n_edges >= sites.shape[0] - 1   # a connected diagram of n >= 2 sites
