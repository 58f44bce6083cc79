"""Which cells touch which vertex: the vertex-site incidences of a DCEL, as CSR arrays."""

from __future__ import annotations

from typing import Optional

import numpy as np
from numpy.typing import NDArray

from vorobench.core.sorting import sorted_unique

__all__ = ["vertex_site_lists"]


def vertex_site_lists(site: NDArray[np.integer], origin: NDArray[np.integer], dest: Optional[NDArray[np.integer]],
                      V: int, n: int) -> tuple[NDArray[np.int64], NDArray[np.int64]]:
    """CSR ``(ptr, sites)``: the sorted, distinct sites whose cells touch each of V vertices.

    A half-edge h of cell ``site[h]`` touches its ``origin`` and ``dest`` (-1 = infinity,
    ignored). Pass ``dest`` when ``next`` may be broken, so that it cannot hide an incidence;
    with ``dest=None`` only origins are used, which suffices when ``origin[next] == dest``
    (each cell's boundary then leaves every vertex it touches). Vertex v's sites are
    ``sites[ptr[v]:ptr[v + 1]]``.
    """
    if dest is None:
        vs, ss = np.asarray(origin, np.int64), np.asarray(site, np.int64)
    else:
        vs = np.concatenate([np.asarray(origin, np.int64), np.asarray(dest, np.int64)])
        ss = np.concatenate([np.asarray(site, np.int64), np.asarray(site, np.int64)])
    keep = vs >= 0
    base = max(int(n), 1)
    code = sorted_unique(vs[keep] * base + ss[keep])
    ptr = np.zeros(V + 1, dtype=np.int64)
    np.cumsum(np.bincount(code // base, minlength=V), out=ptr[1:])
    return ptr, code % base
