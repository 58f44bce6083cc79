"""Shared helpers for the pytest-benchmark suite (not part of the default test run).

    python3 dev.py bench                         # = pytest benchmarks --benchmark-only
    pytest benchmarks --benchmark-only --benchmark-autosave
    pytest benchmarks --benchmark-only --benchmark-compare --benchmark-compare-fail=median:10%

Fixtures for benchmark files: ``sites_of(dataset, n, seed=0)`` (prepared once per session,
outside every timed call), ``build_benchmark(benchmark, name, sites)`` (warms the implementation
up, JIT included, then times its build with ``benchmark.pedantic``), and
``scipy_ratio(benchmark, sites)`` (times scipy's Voronoi on the same sites in the same run and
stores the ratio in ``extra_info``: less machine-dependent than raw times).
"""

from __future__ import annotations

import functools
import time
from typing import Callable, Optional

import numpy as np
import pytest

import datasets_gen
import impls
from vorobench.prepare import prepare

@functools.lru_cache(maxsize=None)
def prepared_sites(dataset: str, n: int, seed: int = 0) -> np.ndarray:
    """Prepared sites of a dataset, generated once per session (shared: do not modify)."""
    sites, _ = prepare(datasets_gen.generate(dataset, n, seed=seed))
    return sites


@functools.lru_cache(maxsize=None)
def warmed(name: str):
    """The implementation, with its JIT code compiled and one small untimed build done."""
    impl = impls.get(name)
    if impl.warmup is not None:
        impl.warmup()
    impl.build(prepared_sites("uniform", 64), None)
    return impl


def rounds_for(n: int, budget_s: float = 3.0, per_site_s: float = 2e-6) -> int:
    """Rounds so that one benchmark takes about ``budget_s`` for an O(n log n) method: 3..50."""
    return int(min(50, max(3, budget_s / (per_site_s * max(n, 1)))))


def is_quadratic(name: str) -> bool:
    """Does the implementation declare quadratic (or worse) growth? Large sizes are skipped for it."""
    text = impls.get(name).complexity.replace(" ", "").lower()
    return any(tag in text for tag in ("n^2", "n²", "n**2", "n^3", "n³"))


def bench_build(benchmark, name: str, sites: np.ndarray, rounds: Optional[int] = None):
    """Time ``impls.get(name).build(sites)`` with pytest-benchmark; returns the last diagram.

    Each round gets the same prepared sites through ``setup`` (nothing generated in the timed
    call); the implementation's counters go to ``extra_info`` as ``stat_<name>``.
    """
    impl = warmed(name)
    stats: dict = {}
    diagram = impl.build(sites, stats)               # untimed: counters and a first result
    benchmark.extra_info.update({f"stat_{k}": v for k, v in stats.items() if isinstance(v, (int, float))})
    benchmark.extra_info["n_sites"] = int(sites.shape[0])
    result = benchmark.pedantic(impl.build, setup=lambda: ((sites, None), {}),
                                rounds=rounds or rounds_for(sites.shape[0]), iterations=1, warmup_rounds=0)
    return result if result is not None else diagram


def _median_seconds(fn: Callable[[], object], rounds: int) -> float:
    times = []
    for _ in range(rounds):
        t0 = time.perf_counter_ns()
        fn()
        times.append((time.perf_counter_ns() - t0) / 1e9)
    return float(np.median(times))


def ratio_to_scipy(benchmark, sites: np.ndarray, rounds: int = 5) -> Optional[float]:
    """Time scipy.spatial.Voronoi on the same sites now; store median(this) / median(scipy).

    The ratio lands in ``benchmark.extra_info["ratio_vs_scipy"]`` (None when the benchmark did
    not run, e.g. under --benchmark-disable).
    """
    from scipy.spatial import Voronoi

    stats = getattr(getattr(benchmark, "stats", None), "stats", None)
    if stats is None or sites.shape[0] < 3:
        return None
    centred = sites - sites.mean(axis=0)
    scipy_s = _median_seconds(lambda: Voronoi(centred), rounds)
    ratio = float(stats.median) / scipy_s
    benchmark.extra_info["scipy_median_s"] = scipy_s
    benchmark.extra_info["ratio_vs_scipy"] = ratio
    return ratio


@pytest.fixture(scope="session")
def sites_of() -> Callable[..., np.ndarray]:
    """``sites_of(dataset, n, seed=0)``: prepared sites, cached for the session."""
    return prepared_sites


@pytest.fixture(scope="session")
def build_benchmark() -> Callable:
    """``build_benchmark(benchmark, name, sites, rounds=None)``: see :func:`bench_build`."""
    return bench_build


@pytest.fixture(scope="session")
def scipy_ratio() -> Callable:
    """``scipy_ratio(benchmark, sites)``: see :func:`ratio_to_scipy`."""
    return ratio_to_scipy


@pytest.fixture(scope="session")
def quadratic() -> Callable[[str], bool]:
    """``quadratic(name)``: does the implementation declare O(n^2) or worse growth?"""
    return is_quadratic
