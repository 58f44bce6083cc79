"""The diagram of disks from its dual, the Apollonius graph: what an executable's faces become
(docs/apollonius.md, docs/executables.md).

The graph comes as its faces, infinite ones included (-1: the vertex at infinity), each with its
three vertices counter-clockwise and the faces across its three edges (the one opposite each
vertex in turn). Faces are needed with their neighbours: a graph of disks may join two sites by
several edges, and a site to infinity by several (a cell with several gaps at infinity), so
which face lies across which edge cannot be read from the vertices alone.

Duality, from the orientation of the vertex predicate (``vertex(i, j, k)``: cell i turns from
its edge with j to its edge with k there): in a face (x, y, z) counter-clockwise, the vertex of
the face ends cell x's half-edge with y and starts cell x's half-edge with z. So a graph edge
x -> y of face f, with g across it, is cell x's half-edge from g's vertex to f's, and its twin
is cell y's from f's to g's; a vertex of an infinite face is infinity. After the half-edge of
cell x that ends at face (x, y, z), the cell goes on along its edge with z; if z is the vertex
at infinity, along its edge with y' in the face across the edge (x, infinity): (x, infinity, y').

Every finite face's vertex is computed exactly (``vertex``): a face with no Apollonius circle in
its orientation is refused. Neighbouring faces with one exact point (four or more disks on one
circle: the graph triangulates the polygon of their sites) are one vertex, and the edges
between them, of length zero, are dropped. Fewer than three visible disks give no faces, and
the diagram is built here: none, or the one branch between two disks.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vorobench.core.diagram import Diagram
from vorobench.core.errors import InvalidDiagramError
from vorobench.core.hidden_disks import hidden_disks
from vorobench.core.predicates.apollonius import compare, rational, vertex
from vorobench.core.union_find import find

__all__ = ["diagram_from_apollonius_faces", "NotAnApolloniusGraph"]


class NotAnApolloniusGraph(ValueError):
    """Faces that are not the Apollonius graph of the disks (the message says how)."""


def _two_disks(centres: NDArray[np.float64], radii: NDArray[np.float64]) -> Diagram:
    """No faces: the diagram of at most two visible disks (one branch between two)."""
    visible = np.flatnonzero(~hidden_disks(centres, radii))
    if visible.size <= 1:
        return Diagram.empty(centres, radii=radii)
    if visible.size > 2:
        raise NotAnApolloniusGraph(f"no faces for {visible.size} visible disks")
    a, b = (int(v) for v in visible)
    minus = np.array([-1, -1], dtype=np.int64)
    return Diagram(centres, np.zeros((0, 2)), minus, np.array([1, 0]), np.array([0, 1]), np.array([a, b]),
                   radii=radii)


def _checked(faces: ArrayLike, n: int) -> NDArray[np.int64]:
    faces = np.asarray(faces, dtype=np.int64).reshape(-1, 6)
    F = faces.shape[0]
    corners, across = faces[:, :3], faces[:, 3:]
    if corners.size and (corners.min() < -1 or corners.max() >= n):
        raise NotAnApolloniusGraph(f"a face names a site outside -1..{n - 1}")
    if across.size and (across.min() < 0 or across.max() >= F):
        raise NotAnApolloniusGraph(f"a face names a neighbour outside 0..{F - 1}")
    for f in range(F):
        v = corners[f].tolist()
        if len(set(v)) != 3:
            raise NotAnApolloniusGraph(f"face {f} ({v}) repeats a vertex")
        for i in range(3):
            g = int(across[f, i])
            edge = (v[(i + 1) % 3], v[(i + 2) % 3])
            back = [j for j in range(3) if across[g, j] == f and
                    (corners[g, (j + 1) % 3], corners[g, (j + 2) % 3]) == (edge[1], edge[0])]
            if g == f or not back:
                raise NotAnApolloniusGraph(f"face {f}'s neighbour across {edge} is face {g}, which does not "
                                           f"have face {f} across that edge reversed")
    return faces


def diagram_from_apollonius_faces(centres: ArrayLike, radii: ArrayLike, faces: ArrayLike) -> Diagram:
    """The diagram of the disks from the faces of their Apollonius graph ((F, 6): three
    vertices counter-clockwise, -1 at infinity, then the faces opposite each); raises
    :class:`NotAnApolloniusGraph` (a ``ValueError``) for faces that do not fit together, a
    finite face with no Apollonius circle in its orientation, or cells that do not close.
    Whether the faces are the graph *of these disks* (its empty circles, its hidden disks) is
    not decided here: that is the certificate's question (``certify_disks``)."""
    centres = np.ascontiguousarray(centres, dtype=np.float64).reshape(-1, 2)
    radii = np.ascontiguousarray(radii, dtype=np.float64).reshape(-1)
    n = centres.shape[0]
    faces = _checked(faces, n)
    if faces.shape[0] == 0:
        return _two_disks(centres, radii)
    corners, across = faces[:, :3], faces[:, 3:]
    disks = [(rational(float(x)), rational(float(y)), rational(float(r))) for (x, y), r in zip(centres, radii)]
    F = faces.shape[0]
    points = [None] * F
    for f in range(F):
        if (corners[f] >= 0).all():
            points[f] = vertex(disks, *(int(v) for v in corners[f]))
            if points[f] is None:
                raise NotAnApolloniusGraph(f"face {f} ({corners[f].tolist()}): no Apollonius circle touches "
                                           f"these disks in this order")
    # half-edges: for the edge opposite corner i of face f, x -> y, cell x's half-edge ends at
    # f (ending[f, i]) and cell y's starts at f (starting[f, i]); made once per graph edge
    ending = np.full((F, 3), -1, dtype=np.int64)
    starting = np.full((F, 3), -1, dtype=np.int64)
    site, start_face = [], []
    for f in range(F):
        for i in range(3):
            x, y = int(corners[f, (i + 1) % 3]), int(corners[f, (i + 2) % 3])
            if x < 0 or y < 0 or ending[f, i] >= 0:
                continue
            g = int(across[f, i])
            j = next(j for j in range(3) if across[g, j] == f and corners[g, (j + 1) % 3] == y
                     and corners[g, (j + 2) % 3] == x)
            hx, hy = len(site), len(site) + 1
            site += [x, y]
            start_face += [g, f]
            ending[f, i], starting[f, i] = hx, hy
            ending[g, j], starting[g, j] = hy, hx
    H = len(site)
    nxt = np.full(H, -1, dtype=np.int64)
    for f in range(F):
        for i in range(3):
            h = ending[f, i]
            if h < 0:
                continue
            z = corners[f, i]
            if z >= 0:
                nxt[h] = starting[f, (i + 2) % 3]
                continue
            # past infinity: the face across (infinity, x), where x's next edge starts at infinity
            x = corners[f, (i + 1) % 3]
            g = int(across[f, (i + 2) % 3])
            q = int(np.flatnonzero(corners[g] == -1)[0])
            if corners[g, (q + 2) % 3] != x:
                raise NotAnApolloniusGraph(f"around site {int(x)}, face {g} does not follow face {f} at infinity")
            nxt[h] = starting[g, q]
    if (nxt < 0).any():
        raise NotAnApolloniusGraph("a cell does not close")
    # one vertex per exact point: neighbouring finite faces at one point merge, their edge drops
    parent = np.arange(F)
    dropped = np.zeros(H, dtype=bool)
    for f in range(F):
        for i in range(3):
            g = int(across[f, i])
            h = ending[f, i]
            if h < 0 or points[f] is None or points[g] is None:
                continue
            if compare(points[f].x, points[g].x) == 0 and compare(points[f].y, points[g].y) == 0:
                dropped[h] = True
                ru, rv = find(parent, f), find(parent, g)
                if ru != rv:
                    parent[max(ru, rv)] = min(ru, rv)
    vertex_of = np.full(F, -1, dtype=np.int64)
    vertices = []
    for f in range(F):
        if points[f] is not None and find(parent, f) == f:
            vertex_of[f] = len(vertices)
            vertices.append((float(points[f].x), float(points[f].y)))
    kept = np.flatnonzero(~dropped)
    new_id = np.full(H, -1, dtype=np.int64)
    new_id[kept] = np.arange(kept.size)
    twin = np.arange(H) ^ 1
    origin, next_kept = [], []
    for h in kept:
        f = start_face[h]
        origin.append(-1 if points[f] is None else int(vertex_of[find(parent, f)]))
        k, steps = nxt[h], 0
        while dropped[k]:                          # through a merged vertex: skip the zero-length edges
            k, steps = nxt[k], steps + 1
            if steps > H:
                raise NotAnApolloniusGraph("a cell is made of zero-length edges only")
        next_kept.append(new_id[k])
    try:
        d = Diagram(centres, np.array(vertices, dtype=np.float64).reshape(-1, 2), np.array(origin, dtype=np.int64),
                    new_id[twin[kept]], np.array(next_kept, dtype=np.int64), np.array(site, dtype=np.int64)[kept],
                    radii=radii)
        return d.validate()
    except InvalidDiagramError as exc:
        raise NotAnApolloniusGraph(str(exc)) from None
