"""Vertical slabs of sites, for the weighted sweep's first bounds (docs/power.md).

A pending site's first lower bound is only as good as the sites it watches. The beach line
offers only sites that have entered; below a dense cluster whose wavefronts are nearly flat,
those are far away. The site activated last in the same slab lies just below, about one
spacing away, and bounds the site's cell at once.
"""

from __future__ import annotations

import numpy as np
from numba import njit

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
    out = np.empty(n, dtype=np.int64)
    _count_at_most(np.ascontiguousarray(cuts, dtype=np.float64), np.ascontiguousarray(x, dtype=np.float64), out)
    return out


@njit(cache=True)
def _count_at_most(cuts, x, out):
    # out[j] = the number of cuts <= x[j] (numpy's searchsorted "right", which took 0.1 s at
    # 10**6 sites taken in y order: a mispredicted branch per step). A uniform grid of cells
    # over the cuts' range says between which two counts the answer lies; those are checked
    # (a rounding of the cell may be off by one) and the range searched.
    m = cuts.shape[0]
    if m == 0:
        out[:] = 0
        return
    low = cuts[0]
    cells = 4 * m
    width = (cuts[m - 1] - low) / cells
    below = np.empty(cells + 2, dtype=np.int64)   # below[g]: the cuts < the start of cell g
    c = 0
    for g in range(cells + 2):
        start = low + g * width
        while c < m and cuts[c] < start:
            c += 1
        below[g] = c
    for j in range(x.shape[0]):
        v = x[j]
        lo, hi = 0, m
        if width > 0 and v >= low:
            q = (v - low) / width
            # NaN (cuts and v both spanning more than the largest float) goes to the last
            # cell too, where the check below sends it to the full search
            g = int(q) if q < cells else cells
            lo, hi = below[g], below[g + 1]
            if (lo > 0 and cuts[lo - 1] > v) or (hi < m and cuts[hi] <= v):
                lo, hi = 0, m
        # the least k in [lo, hi] with cuts[k] > v (m if none)
        while lo < hi:
            mid = (lo + hi) >> 1
            if cuts[mid] <= v:
                lo = mid + 1
            else:
                hi = mid
        out[j] = lo
