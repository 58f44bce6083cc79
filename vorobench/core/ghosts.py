"""Closing a triangulation's hull with ghost triangles: the layout the Delaunay duals read.

A triangulation given as CCW triangles and, per corner, the triangle across the opposite edge
(-1 on the hull) becomes flat corner/opposite arrays in which every half-edge has an opposite:
each hull edge a -> b gets a ghost triangle (b, a, n) with the infinite vertex n, and
consecutive ghosts share their edges to n (:mod:`vorobench.core.delaunay_dual` reads this).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import NDArray

__all__ = ["ghost_layout"]


@njit(cache=True)
def _ghost_layout(tri3, neighbours, n):
    T = tri3.shape[0]
    hull = 0
    for t in range(T):
        for k in range(3):
            hull += neighbours[t, k] < 0
    tri = np.empty(3 * (T + hull), dtype=np.int64)
    opp = np.empty(3 * (T + hull), dtype=np.int64)
    ghost_from = np.full(n, -1, dtype=np.int64)     # ghost of the hull edge starting at a site
    ghost_to = np.full(n, -1, dtype=np.int64)       # ghost of the hull edge ending at a site
    g = T
    for t in range(T):
        for k in range(3):
            tri[3 * t + k] = tri3[t, k]
    for t in range(T):
        for k in range(3):
            e = 3 * t + k
            a = tri3[t, k]
            b = tri3[t, (k + 1) % 3]
            across = neighbours[t, (k + 2) % 3]      # Triangle: the triangle opposite corner k + 2
            if across >= 0:
                opp[e] = -1
                for j in range(3):
                    if tri3[across, j] == b:
                        opp[e] = 3 * across + j
                if opp[e] < 0:
                    raise RuntimeError("a triangle and its neighbour share no edge")
            else:                                     # hull edge a -> b: ghost (b, a, n) outside
                tri[3 * g] = b
                tri[3 * g + 1] = a
                tri[3 * g + 2] = n
                opp[e] = 3 * g
                opp[3 * g] = e
                if ghost_from[a] >= 0 or ghost_to[b] >= 0:
                    raise RuntimeError("the hull edges do not form one closed cycle")
                ghost_from[a] = g
                ghost_to[b] = g
                g += 1
    for g in range(T, T + hull):
        b = tri[3 * g]
        a = tri[3 * g + 1]
        before = ghost_to[a]                          # a -> n meets n -> a of the previous ghost
        after = ghost_from[b]                         # n -> b meets b -> n of the next ghost
        if before < 0 or after < 0:
            raise RuntimeError("the hull edges do not form one closed cycle")
        opp[3 * g + 1] = 3 * before + 2
        opp[3 * g + 2] = 3 * after + 1
    return tri, opp, T + hull


def ghost_layout(triangles: NDArray[np.integer], neighbours: NDArray[np.integer], n: int
                 ) -> tuple[NDArray[np.int64], NDArray[np.int64], int]:
    """Triangle's (triangles, neighbours) as flat corner/opposite arrays closed by ghosts.

    Half-edge ``e = 3 t + k`` runs from corner k of triangle t to corner k + 1; ``opp[e]`` is
    the half-edge running back in the triangle across (Triangle gives, per corner, the
    triangle across the *opposite* edge, hence the shift). Each hull edge a -> b gets a
    ghost triangle (b, a, n) on its outer side; consecutive ghosts share their edges to n.
    Returns (tri, opp, number of triangles including ghosts); raises if the hull edges do
    not form one closed cycle.
    """
    return _ghost_layout(np.ascontiguousarray(triangles, dtype=np.int64).reshape(-1, 3),
                         np.ascontiguousarray(neighbours, dtype=np.int64).reshape(-1, 3), int(n))
