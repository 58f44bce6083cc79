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
from vorobench.core.prepare import prepare


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


#: Seconds of timed builds to aim for per benchmark, and the longest single build accepted.
TARGET_SECONDS = 3.0
MAX_BUILD_SECONDS = 20.0


def rounds_for(build_seconds: float, target_s: float = TARGET_SECONDS) -> int:
    """Rounds so that one benchmark takes about ``target_s``: between 3 and 50."""
    return int(min(50, max(3, target_s / max(build_seconds, 1e-9))))


def is_quadratic(name: str) -> bool:
    """Does the implementation declare quadratic (or worse) growth? Large sizes are skipped for it."""
    text = impls.get(name).complexity.replace(" ", "").lower()
    return any(tag in text for tag in ("n^2", "n²", "n**2", "n^3", "n³"))


#: (implementation, label) -> [(n, seconds of one build)], to skip hopeless larger sizes early.
_BUILD_TIMES: dict[tuple[str, str], list[tuple[int, float]]] = {}


def _predicted_seconds(name: str, label: Optional[str], n: int) -> Optional[float]:
    """One build's time at n, extrapolated from smaller sizes of the same label (None if unknown)."""
    seen = sorted(t for t in _BUILD_TIMES.get((name, label), []) if t[0] < n) if label else []
    if not seen:
        return None
    exponent = 2.0                       # cautious when only one size is known
    if len(seen) >= 2 and seen[-1][0] > seen[-2][0] and seen[-2][1] > 0:
        (n0, t0), (n1, t1) = seen[-2:]
        exponent = min(2.5, max(1.0, float(np.log(t1 / t0) / np.log(n1 / n0))))
    n_last, t_last = seen[-1]
    return t_last * (n / n_last) ** exponent


def bench_build(benchmark, name: str, sites: np.ndarray, rounds: Optional[int] = None,
                label: Optional[str] = None):
    """Time ``impls.get(name).build(sites)`` with pytest-benchmark; returns the last diagram.

    One untimed build first gives the counters (to ``extra_info`` as ``stat_<name>``) and the
    build time that sets the number of rounds; a build slower than ``MAX_BUILD_SECONDS`` (or
    predicted so from smaller sizes with the same ``label``, e.g. the dataset) is skipped:
    that is `vorobench bench`'s job, with its timeouts. Each round gets the same prepared
    sites through ``setup``: nothing is generated inside the timed call.
    """
    n = int(sites.shape[0])
    predicted = _predicted_seconds(name, label, n)
    if predicted is not None and predicted > MAX_BUILD_SECONDS:
        pytest.skip(f"{name}: one build of {n} sites would take about {predicted:.0f} s "
                    f"(> {MAX_BUILD_SECONDS:g} s, extrapolated); measure it with `vorobench bench`")
    impl = warmed(name)
    stats: dict = {}
    t0 = time.perf_counter_ns()
    diagram = impl.build(sites, stats)
    first_s = (time.perf_counter_ns() - t0) / 1e9
    if label:
        _BUILD_TIMES.setdefault((name, label), []).append((n, first_s))
    if first_s > MAX_BUILD_SECONDS:
        pytest.skip(f"{name}: one build of {sites.shape[0]} sites takes {first_s:.0f} s "
                    f"(> {MAX_BUILD_SECONDS:g} s); measure it with `vorobench bench`")
    benchmark.extra_info.update({f"stat_{k}": v for k, v in stats.items() if isinstance(v, (int, float))})
    benchmark.extra_info["n_sites"] = int(sites.shape[0])
    result = benchmark.pedantic(impl.build, setup=lambda: ((sites, None), {}),
                                rounds=rounds or rounds_for(first_s), iterations=1, warmup_rounds=0)
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
    """``build_benchmark(benchmark, name, sites, rounds=None, label=None)``: see :func:`bench_build`."""
    return bench_build


@pytest.fixture(scope="session")
def scipy_ratio() -> Callable:
    """``scipy_ratio(benchmark, sites)``: see :func:`ratio_to_scipy`."""
    return ratio_to_scipy


@pytest.fixture(scope="session")
def quadratic() -> Callable[[str], bool]:
    """``quadratic(name)``: does the implementation declare O(n^2) or worse growth?"""
    return is_quadratic
