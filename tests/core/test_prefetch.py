"""vorobench.core.prefetch: the hint reaches the compiled code and changes no result, even for
indices outside the array (a prefetch never faults)."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit
from numba.core.errors import TypingError

from vorobench.core.prefetch import prefetch


@njit
def _sum_with_hints(values, rows, order, ahead):
    """Sum values[order] and rows[order, 1], asking for elements ``ahead`` reads early (and for
    indices past both ends of the arrays)."""
    total = 0.0
    n = order.size
    for i in range(n):
        prefetch(values, order[(i + ahead) % n])
        prefetch(rows, order[(i + ahead) % n])
        prefetch(values, values.size + 1000 * i)
        prefetch(rows, -1 - 1000 * i)
        total += values[order[i]] + rows[order[i], 1]
    return total


@njit
def _sum_plain(values, rows, order):
    total = 0.0
    for i in range(order.size):
        total += values[order[i]] + rows[order[i], 1]
    return total


def test_prefetch_changes_no_result():
    rng = np.random.default_rng(0)
    values = rng.random(10_000)
    rows = rng.random((10_000, 2))
    order = rng.permutation(10_000)
    expected = _sum_plain(values, rows, order)
    assert np.isclose(expected, values.sum() + rows[:, 1].sum(), rtol=1e-12)
    assert _sum_with_hints(values, rows, order, 7) == expected


def test_prefetch_is_compiled_as_the_llvm_hint():
    values = np.zeros(4)
    _sum_with_hints(values, np.zeros((4, 2)), np.arange(4), 1)
    (ir,) = _sum_with_hints.inspect_llvm().values()
    calls = [line for line in ir.splitlines() if "call" in line and "@llvm.prefetch" in line]
    assert len(calls) >= 4


def test_prefetch_refuses_what_it_cannot_address():
    @njit
    def bad(x):
        prefetch(x, 0)

    with pytest.raises(TypingError):
        bad(1.0)
