"""Read-only views: the same memory, no copy, and the original keeps its flags."""

from __future__ import annotations

import numpy as np
import pytest

from vorobench.core.read_only import read_only


def test_a_read_only_view_shares_memory_and_leaves_the_original_writable():
    a = np.arange(6.0).reshape(3, 2)
    v = read_only(a)
    assert np.shares_memory(a, v) and v.shape == a.shape and v.dtype == a.dtype
    assert not v.flags.writeable and a.flags.writeable
    with pytest.raises(ValueError):
        v[0, 0] = 1.0
    a[0, 0] = 7.0                        # a view: the change shows through
    assert v[0, 0] == 7.0
    assert not read_only(v).flags.writeable
