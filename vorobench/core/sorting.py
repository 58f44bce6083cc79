"""Sort-based set operations on int64 keys, fast for millions of keys.

numpy >= 2.3 answers ``np.unique`` and ``np.isin`` on large int arrays with a hash table that
is an order of magnitude slower than sorting here (11 s vs 0.2 s for 12M keys), and
``np.argsort`` is several times slower than ``np.sort``. These helpers sort instead, and
pack (key, index) into one int64 when the bits allow, so that an argsort is a plain sort.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["argsort_keys", "sorted_unique", "dense_rank", "is_member"]


def argsort_keys(keys: NDArray[np.integer]) -> NDArray[np.int64]:
    """Stable argsort of integer keys (ties keep index order)."""
    keys = np.asarray(keys, dtype=np.int64)
    m = keys.size
    if m == 0:
        return np.zeros(0, np.int64)
    lo, hi = int(keys.min()), int(keys.max())
    index_bits = max(1, (m - 1).bit_length())
    key_bits = max(1, (hi - lo).bit_length())
    if key_bits + index_bits <= 63:
        packed = ((keys - lo) << index_bits) | np.arange(m, dtype=np.int64)
        packed.sort()
        return packed & ((1 << index_bits) - 1)
    return np.argsort(keys, kind="stable").astype(np.int64)


def sorted_unique(keys: NDArray[np.integer]) -> NDArray[np.int64]:
    """The distinct keys in increasing order."""
    s = np.sort(np.asarray(keys, dtype=np.int64))
    if s.size == 0:
        return s
    keep = np.empty(s.size, dtype=bool)
    keep[0] = True
    np.not_equal(s[1:], s[:-1], out=keep[1:])
    return s[keep]


def dense_rank(keys: NDArray[np.integer]) -> NDArray[np.int64]:
    """Rank of each key among the distinct keys (0, 1, ...): equal keys, equal ranks."""
    keys = np.asarray(keys, dtype=np.int64)
    if keys.size == 0:
        return np.zeros(0, np.int64)
    order = argsort_keys(keys)
    s = keys[order]
    step = np.empty(s.size, dtype=np.int64)
    step[0] = 0
    step[1:] = s[1:] != s[:-1]
    rank = np.empty(keys.size, dtype=np.int64)
    rank[order] = np.cumsum(step)
    return rank


def is_member(keys: NDArray[np.integer], pool: NDArray[np.integer]) -> NDArray[np.bool_]:
    """For each key, whether it occurs in ``pool``."""
    keys = np.asarray(keys, dtype=np.int64)
    pool = np.sort(np.asarray(pool, dtype=np.int64))
    if pool.size == 0 or keys.size == 0:
        return np.zeros(keys.size, dtype=bool)
    order = argsort_keys(keys)          # sorted needles make searchsorted cache-friendly
    ks = keys[order]
    pos = np.minimum(np.searchsorted(pool, ks), pool.size - 1)
    out = np.empty(keys.size, dtype=bool)
    out[order] = pool[pos] == ks
    return out
