"""Speed targets of the two other constructions (pytest-benchmark; not part of the default run).

* ``incremental`` at n = 10^6 on ``uniform`` and ``sorted``: at most 0.15 x the time of
  scipy.spatial.Voronoi on the same sites, measured in the same run.
* ``halfplane`` at n = 20,000 ``uniform``: under 60 s.

Tables with more sizes: ``benchmarks/incremental_scaling.py`` and ``benchmarks/halfplane_scaling.py``.
"""

from __future__ import annotations

import pytest

INCREMENTAL_N = 1_000_000
INCREMENTAL_MAX_RATIO = 0.15
HALFPLANE_N = 20_000
HALFPLANE_MAX_SECONDS = 60.0


@pytest.mark.parametrize("dataset", ["uniform", "sorted"])
def test_incremental_vs_scipy(benchmark, sites_of, build_benchmark, scipy_ratio, dataset):
    sites = sites_of(dataset, INCREMENTAL_N)
    benchmark.group = f"incremental {dataset} n={INCREMENTAL_N}"
    diagram = build_benchmark(benchmark, "incremental", sites, rounds=3)
    ratio = scipy_ratio(benchmark, sites, rounds=3)
    assert diagram.n_vertices - diagram.n_edges + diagram.n_sites == 1
    if ratio is not None:
        assert ratio <= INCREMENTAL_MAX_RATIO, f"incremental / scipy = {ratio:.3f}"


def test_halfplane_finishes_20000(benchmark, sites_of, build_benchmark):
    sites = sites_of("uniform", HALFPLANE_N)
    benchmark.group = f"halfplane uniform n={HALFPLANE_N}"
    diagram = build_benchmark(benchmark, "halfplane", sites, rounds=1)
    assert diagram.n_sites == HALFPLANE_N
    stats = getattr(getattr(benchmark, "stats", None), "stats", None)
    if stats is not None:
        assert stats.max < HALFPLANE_MAX_SECONDS
