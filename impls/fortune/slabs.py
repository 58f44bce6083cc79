"""Vertical slabs of sites, for the weighted sweep's first bounds (docs/power.md).

A pending site's first lower bound is only as good as the sites it watches. The beach line
offers only sites that have entered; below a dense cluster whose wavefronts are nearly flat,
those are far away. The site activated last in the same slab lies just below, about one
spacing away, and bounds the site's cell at once.
"""

from __future__ import annotations

import numpy as np

__all__ = ["slabs", "OWN_DEPTH", "SIDE_DEPTH"]

#: Where the newest sites of its slab and of the two beside it move a site's first bound (it is
#: in a dense part), it also looks at this many sites activated before the newest in its own
#: slab, and in each beside it: in a dense cluster, where wavefronts are nearly flat and a site
#: enters at the lowest corner of its cell, they are the sites that close that corner (probes
#: per site at 10^6 on ``kuzmin`` 3.71 -> 1.82, on ``clusters`` 3.64 -> 2.09; uniform 1.09 -> 1.08)
OWN_DEPTH, SIDE_DEPTH = 2, 1


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
