"""The complexity check: a fitted growth exponent against the implementation's declared complexity."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from vorobench.harness import analysis

SIZES = [1000, 3000, 10000, 30000]


@pytest.mark.parametrize("text, expected", [
    ("O(n log n)", (1.0, 1.0)),
    ("O(n log n) expected", (1.0, 1.0)),
    ("O(n^2)", (2.0, 0.0)),
    ("O(n^(4/3)) expected", (4 / 3, 0.0)),
    ("O(n)", (1.0, 0.0)),
    ("O(n^1.5)", (1.5, 0.0)),
    ("O(n log^2 n)", (1.0, 2.0)),
    ("O(n sqrt(n))", (1.5, 0.0)),
    ("O(n²)", (2.0, 0.0)),
    ("O(n * log(n))", (1.0, 1.0)),
])
def test_parse_complexity(text, expected):
    a, b = analysis.parse_complexity(text)
    assert (a, b) == pytest.approx(expected)


@pytest.mark.parametrize("text", ["?", "", None, "fast", "O(k n)", "O(n log log n)", "O(2^n)", float("nan")])
def test_parse_complexity_refuses_what_it_cannot_read(text):
    assert analysis.parse_complexity(text) is None


def test_declared_exponent_of_n_log_n_is_its_log_log_slope_over_the_range():
    # n log n from 1k to 30k: the chord slope of log(n ln n) against log n
    expected = 1 + math.log(math.log(30000) / math.log(1000)) / math.log(30)
    assert analysis.declared_exponent("O(n log n)", 1000, 30000) == pytest.approx(expected)
    assert 1.10 < expected < 1.13
    assert analysis.declared_exponent("O(n^2)", 1000, 30000) == pytest.approx(2.0)
    # one size: the local slope 1 + 1/ln n
    assert analysis.declared_exponent("O(n log n)", 1000, 1000) == pytest.approx(1 + 1 / math.log(1000))
    assert math.isnan(analysis.declared_exponent("?", 1000, 30000))


def _sizes(laws: dict) -> pd.DataFrame:
    rng = np.random.default_rng(3)
    rows = []
    for (impl, dataset), law in laws.items():
        for n in SIZES:
            rows.append({"impl": impl, "dataset": dataset, "n": n, "n_sites": n,
                         "time_s": law(n) * (1 + 0.02 * rng.standard_normal())})
    return pd.DataFrame(rows)


def test_an_n_squared_series_declared_n_log_n_is_a_mismatch_and_a_true_n_log_n_is_not():
    sizes = _sizes({("sweep", "uniform"): lambda n: 1e-7 * n * math.log2(n),
                    ("sweep", "cocircular"): lambda n: 1e-9 * n * n,
                    ("quad", "uniform"): lambda n: 1e-9 * n * n,
                    ("linear", "uniform"): lambda n: 1e-7 * n})
    declared = {"sweep": "O(n log n)", "quad": "O(n^2)", "linear": "O(n log n) expected"}
    check = analysis.complexity_check(analysis.fit_exponents(sizes), declared).set_index(["impl", "dataset"])
    assert bool(check.loc[("sweep", "cocircular"), "mismatch"]) is True
    assert check.loc[("sweep", "cocircular"), "excess"] == pytest.approx(2 - 1.12, abs=0.05)
    assert check.loc[("sweep", "cocircular"), "finding"] == "above"
    for case in [("sweep", "uniform"), ("quad", "uniform"), ("linear", "uniform")]:
        assert bool(check.loc[case, "mismatch"]) is False, case
    assert check.loc[("sweep", "uniform"), "finding"] == "as declared"
    assert check.loc[("linear", "uniform"), "finding"] == "as declared"     # 1.0 is within 0.3 of 1.12
    mismatches = analysis.complexity_mismatches(check.reset_index())
    assert list(zip(mismatches["impl"], mismatches["dataset"])) == [("sweep", "cocircular")]


def test_the_tolerance_is_the_boundary():
    sizes = _sizes({("x", "d"): lambda n: n ** 1.5})
    fit = analysis.fit_exponents(sizes)
    assert analysis.complexity_check(fit, {"x": "O(n^1.1)"}, tolerance=0.3)["mismatch"].item()
    assert not analysis.complexity_check(fit, {"x": "O(n^1.3)"}, tolerance=0.3)["mismatch"].item()
    assert analysis.complexity_check(fit, {"x": "O(n^2)"})["finding"].item() == "below"


def test_an_unknown_declaration_is_never_a_mismatch():
    sizes = _sizes({("x", "d"): lambda n: 1e-12 * n ** 3, ("y", "d"): lambda n: 1e-12 * n ** 3})
    check = analysis.complexity_check(analysis.fit_exponents(sizes), lambda name: "?" if name == "x" else None)
    assert not check["mismatch"].any()
    assert set(check["finding"]) == {"unknown"}
    assert analysis.complexity_mismatches(check).empty


def test_mismatches_are_sorted_worst_first():
    sizes = _sizes({("a", "d"): lambda n: 1e-12 * n ** 2.0, ("b", "d"): lambda n: 1e-12 * n ** 2.6})
    check = analysis.complexity_check(analysis.fit_exponents(sizes), {"a": "O(n)", "b": "O(n)"})
    assert list(analysis.complexity_mismatches(check)["impl"]) == ["b", "a"]


def test_empty_fits_give_an_empty_check():
    empty = analysis.fit_exponents(pd.DataFrame(columns=["impl", "dataset", "n", "n_sites", "time_s"]))
    check = analysis.complexity_check(empty, {})
    assert check.empty and "mismatch" in check.columns
