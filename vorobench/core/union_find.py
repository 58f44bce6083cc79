"""Union-find over integer ids (one parent array), for merging cocircular triangles and the
vertices of one empty circle into a single Voronoi vertex."""

from __future__ import annotations

from numba import njit

__all__ = ["find"]


@njit(cache=True)
def find(parent, x):
    """The root of x's set, compressing the path walked (parent[r] == r at a root)."""
    root = x
    while parent[root] != root:
        root = parent[root]
    while parent[x] != root:
        parent[x], x = root, parent[x]
    return root
