"""Vertical slabs of sites, for the weighted sweep's first bounds (docs/power.md).

A pending site's first lower bound is only as good as the sites it watches. The beach line
offers only sites that have entered; below a dense cluster whose wavefronts are nearly flat,
those are far away. The site activated last in the same slab lies just below, about one
spacing away, and bounds the site's cell at once.
"""

from __future__ import annotations

import numpy as np

__all__ = ["slabs"]


def slabs(x: np.ndarray) -> np.ndarray:
    """Each site's slab: about sqrt(n) slabs of about sqrt(n) sites each, cut at quantiles of
    ``x`` (of a sample of at most 2**16 of the sites, which costs little at 10**6). Sites
    sorted by y within a slab are about one local spacing apart where they are dense, since a
    dense cluster gets narrow slabs."""
    n = x.shape[0]
    count = max(1, int(np.sqrt(n)))
    sample = x[::max(1, n // 65536)]
    cuts = np.quantile(sample, np.arange(1, count) / count)
    return np.searchsorted(cuts, x, side="right").astype(np.int64)
