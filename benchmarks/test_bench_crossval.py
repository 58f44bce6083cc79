"""compare + certify of two qhull diagrams vs. scipy's Voronoi building one (same run, same sites).

The cross-validation must cost less than the construction it checks: at n = 10^6 uniform
points, ``compare(a, b)`` + ``certify(a)`` + ``certify(b)`` must take less time than one
``scipy.spatial.Voronoi`` of the sites. Run with ``pytest benchmarks/test_bench_crossval.py
--benchmark-only -s``; the figures land in ``extra_info`` and are printed.
"""

from __future__ import annotations

import time

import pytest

import impls
from vorobench.judge.certificate import certify
from vorobench.judge.comparison import compare

SIZES = (100_000, 1_000_000)


def _seconds(fn):
    t0 = time.perf_counter_ns()
    out = fn()
    return out, (time.perf_counter_ns() - t0) / 1e9


@pytest.mark.parametrize("n", SIZES)
def test_compare_and_certify_cost_less_than_building(benchmark, sites_of, n):
    from scipy.spatial import Voronoi

    sites = sites_of("uniform", n)
    small = impls.build("qhull", sites_of("uniform", 64))      # compile the numba kernels, untimed
    certify(small)
    compare(small, small)
    _, scipy_before = _seconds(lambda: Voronoi(sites - sites.mean(axis=0)))
    a = impls.build("qhull", sites)
    b = impls.build("qhull", sites)
    timings: dict[str, float] = {}

    def check():
        comparison, timings["compare"] = _seconds(lambda: compare(a, b))
        cert_a, timings["certify_a"] = _seconds(lambda: certify(a))
        cert_b, timings["certify_b"] = _seconds(lambda: certify(b))
        return comparison, cert_a, cert_b

    comparison, cert_a, cert_b = benchmark.pedantic(check, rounds=1, iterations=1, warmup_rounds=0)
    # scipy once before and once after the checks: the machine is shared, its load drifts.
    _, scipy_after = _seconds(lambda: Voronoi(sites - sites.mean(axis=0)))
    scipy_s = 0.5 * (scipy_before + scipy_after)
    total = timings["compare"] + timings["certify_a"] + timings["certify_b"]
    benchmark.group = f"crossval uniform n={n}"
    benchmark.extra_info.update(n_sites=int(sites.shape[0]), scipy_voronoi_s=scipy_s, scipy_before_s=scipy_before,
                                scipy_after_s=scipy_after, total_s=total,
                                ratio_to_scipy=total / scipy_s, **{f"{k}_s": v for k, v in timings.items()})
    print(f"\nn={n}: scipy Voronoi {scipy_s:.2f} s ({scipy_before:.2f} before, {scipy_after:.2f} after); compare {timings['compare']:.2f} s + certify "
          f"{timings['certify_a']:.2f} s + {timings['certify_b']:.2f} s = {total:.2f} s "
          f"({total / scipy_s:.2f} x scipy)")
    per_check = {c.name: round(c.seconds, 3) for c in cert_a.checks}
    benchmark.extra_info["certify_checks_s"] = per_check
    print(f"  certify checks (a): {per_check}; compare + one certify (the cost per implementation in "
          f"`vorobench validate`, which certifies the reference once): "
          f"{(timings['compare'] + timings['certify_a']) / scipy_s:.2f} x scipy")
    assert comparison.verdict == "exact" and cert_a.ok and cert_b.ok
    assert total < scipy_s, f"cross-validation took {total:.2f} s, scipy's Voronoi {scipy_s:.2f} s"
