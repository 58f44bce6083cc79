"""A correct test program: scipy's Delaunay triangulation (Qhull), or, for weighted sites, the
regular triangulation as the lower hull of the lifted points (x, y, x^2 + y^2 - w)."""

import sys
import time

import numpy as np
from scipy.spatial import ConvexHull, Delaunay, QhullError

from sites_io import read_sites

sites, weights = read_sites()
start = time.perf_counter()
triangles = np.empty((0, 3), dtype=int)
try:
    if weights is None and len(sites) >= 3:
        triangles = Delaunay(sites).simplices
    elif weights is not None and len(sites) >= 3:
        lifted = np.column_stack([sites, (sites ** 2).sum(axis=1) - weights])
        hull = ConvexHull(lifted)
        triangles = hull.simplices[hull.equations[:, 2] < 0]        # facets facing down
except QhullError:                                                  # all collinear: no triangle
    pass
elapsed = time.perf_counter() - start
sys.stdout.write("".join(f"{a} {b} {c}\n" for a, b, c in triangles.tolist()) + f"time {elapsed!r}\n")
