"""Which disks are hidden in the Apollonius diagram: those inside another disk (touching
included), decided exactly, without building the diagram.

Under the distance |x - p_i| - r_i a disk inside another is never strictly closer to any
point than the bigger one, so its cell has no interior; a disk inside no other has a cell
(docs/apollonius.md). Identical disks hide each other: the one with the smallest index stays
visible, as ``prepare`` keeps the first of duplicated points.

Disk i is hidden when some disk j has r_j - |p_i - p_j| >= r_i. The centres go into a
balanced k-d tree (median splits, so clustered centres cost what spread ones do) whose nodes
keep the box of their centres and their largest radius; the search for disk i enters a node
only when that radius minus the box's distance could reach r_i, and stops at the first disk
that covers i. Each pair is decided by a float test with an error bound and, where it cannot
tell, by the exact sign of (r_j - r_i)^2 - |p_i - p_j|^2 in expansion arithmetic. Both need
the input scaled by a power of two into the exact range (docs/dcel.md), where no square
overflows or underflows; an input no power of two brings there is refused.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit
from numpy.typing import NDArray

from vorobench.core.predicates.expansion import diff_product_expansion, expansion_diff, expansion_sign
from vorobench.core.scaling import (
    EXACT_EXPONENT_SPAN,
    EXACT_MIN_EXPONENT,
    RANGE_TEXT,
    OutsideExactRange,
    magnitude_range,
)

__all__ = ["hidden_disks"]

#: A float decision of |p_i - p_j| + r_i <= r_j is trusted when the margin g^2 - d^2
#: (g = r_j - r_i, d the distance of the centres) exceeds this many units of roundoff of
#: g^2 + d^2: each of g, dx, dy is rounded once and squared, and the sums add two more.
_FILTER_ULPS = 16.0 * 2.0**-53

#: Relative slack on a node's pruning test (its radius minus its box's distance against r_i),
#: of the magnitudes in that test: far above their few roundings, far below a node's size.
_PRUNE_SLACK = 2.0**-45

#: Centres per leaf of the k-d tree
_LEAF = 8


def hidden_disks(centres: NDArray[np.float64], radii: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Boolean mask of the disks (``centres`` (n, 2), ``radii`` (n,), finite, >= 0) that lie
    inside another disk, touching included; of identical disks all but the first.

    Raises ``ValueError`` on a bad shape, a non-finite value or a negative radius, and
    :class:`~vorobench.core.scaling.OutsideExactRange` when the nonzero magnitudes of the
    centres and radii together span more than the exact range."""
    centres = np.asarray(centres, dtype=np.float64)
    radii = np.asarray(radii, dtype=np.float64)
    if centres.ndim != 2 or centres.shape[1] != 2:
        raise ValueError(f"centres must have shape (n, 2), got {centres.shape}")
    if radii.shape != (centres.shape[0],):
        raise ValueError(f"radii must have shape ({centres.shape[0]},), got {radii.shape}")
    if not (np.isfinite(centres).all() and np.isfinite(radii).all()):
        raise ValueError("centres and radii must be finite")
    if (radii < 0).any():
        raise ValueError(f"radii must be >= 0; disk {int(np.argmax(radii < 0))} has {radii[radii < 0][0]!r}")
    n = centres.shape[0]
    if n < 2:
        return np.zeros(n, dtype=bool)
    centres, radii = _scaled(centres, radii)
    order, disks, boxes, reach, children = _kd_tree(centres, radii)
    return _search(disks, order, boxes, reach, children)


def _scaled(centres: NDArray[np.float64],
            radii: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centres and radii times one power of two that puts the largest magnitude in [0.5, 1)
    (raised if the smallest nonzero one needs it): containment does not change, and every
    square and product of differences below is then exact in expansions."""
    hi, lo = magnitude_range(np.concatenate([centres.ravel(), radii]))
    if hi == 0:
        return np.ascontiguousarray(centres), np.ascontiguousarray(radii)
    top, bottom = math.frexp(hi)[1], math.frexp(lo)[1]
    if top - bottom > EXACT_EXPONENT_SPAN:
        raise OutsideExactRange(f"hidden_disks: centres and radii span more than {RANGE_TEXT}: magnitudes from "
                                f"{lo:.6g} to {hi:.6g}")
    k = max(-top, EXACT_MIN_EXPONENT - bottom)
    return np.ascontiguousarray(np.ldexp(centres, k)), np.ascontiguousarray(np.ldexp(radii, k))


def _kd_tree(centres: NDArray[np.float64], radii: NDArray[np.float64]):
    """A balanced k-d tree over the centres: (order, disks, boxes, reach, children). ``disks``
    are the rows (x, y, r) in tree order, disk ``order[t]`` at row t: the build and the search
    read them in sequence, not scattered (at 10^6 disks in random order that was most of their
    time). Node v holds rows ``start:end`` (``children[v] = (left, right, start, end)``, left =
    -1 for a leaf), the box of their centres ``boxes[v] = (xmin, ymin, xmax, ymax)`` and their
    largest radius ``reach[v]``. Node 0 is the root; each split is at the median of the box's
    longer side."""
    n = centres.shape[0]
    capacity = 4 * (n // _LEAF + 1) + 1
    order = np.arange(n)
    disks = np.empty((n, 3))
    disks[:, :2] = centres
    disks[:, 2] = radii
    boxes = np.empty((capacity, 4))
    reach = np.empty(capacity)
    children = np.full((capacity, 4), -1, dtype=np.int64)
    count = _build(disks, order, boxes, reach, children)
    return order, disks, boxes[:count], reach[:count], children[:count]


@njit(cache=True)
def _build(disks, order, boxes, reach, children):
    # the nodes of _kd_tree, depth first with an explicit stack; returns their number
    n = disks.shape[0]
    stack = np.empty((children.shape[0], 3), dtype=np.int64)
    stack[0, 0], stack[0, 1], stack[0, 2] = 0, 0, n
    depth = 1
    count = 1
    while depth > 0:
        depth -= 1
        v, start, end = stack[depth, 0], stack[depth, 1], stack[depth, 2]
        xmin = ymin = np.inf
        xmax = ymax = -np.inf
        big = 0.0
        for t in range(start, end):
            xmin = min(xmin, disks[t, 0])
            xmax = max(xmax, disks[t, 0])
            ymin = min(ymin, disks[t, 1])
            ymax = max(ymax, disks[t, 1])
            big = max(big, disks[t, 2])
        boxes[v, 0], boxes[v, 1], boxes[v, 2], boxes[v, 3] = xmin, ymin, xmax, ymax
        reach[v] = big
        children[v, 2], children[v, 3] = start, end
        if end - start <= _LEAF:
            continue
        axis = 0 if xmax - xmin >= ymax - ymin else 1
        middle = start + (end - start) // 2
        _select(disks, order, start, end, middle, axis)
        left, right = count, count + 1
        count += 2
        children[v, 0], children[v, 1] = left, right
        stack[depth, 0], stack[depth, 1], stack[depth, 2] = left, start, middle
        stack[depth + 1, 0], stack[depth + 1, 1], stack[depth + 1, 2] = right, middle, end
        depth += 2
    return count


@njit(cache=True, inline='always')
def _swap_rows(disks, order, i, j):
    for c in range(3):
        disks[i, c], disks[j, c] = disks[j, c], disks[i, c]
    order[i], order[j] = order[j], order[i]


@njit(cache=True)
def _select(disks, order, start, end, k, axis):
    # rows start:end rearranged so that row k holds the centre of rank k - start along the
    # axis, none after it smaller and none before it larger (Hoare's quickselect)
    lo, hi = start, end - 1
    while lo < hi:
        pivot = disks[(lo + hi) // 2, axis]
        i, j = lo, hi
        while i <= j:
            while disks[i, axis] < pivot:
                i += 1
            while disks[j, axis] > pivot:
                j -= 1
            if i <= j:
                _swap_rows(disks, order, i, j)
                i += 1
                j -= 1
        if k <= j:
            hi = j
        elif k >= i:
            lo = i
        else:
            return


@njit(cache=True)
def _covers(cx, cy, r, px, py, ri):
    """Whether the disk (cx, cy, r) contains the disk (px, py, ri), r >= ri, exactly: the sign
    of (r - ri)^2 - (px - cx)^2 - (py - cy)^2, a float filter first, expansions where it
    cannot tell (exact for inputs in the exact range)."""
    g = r - ri
    dx = px - cx
    dy = py - cy
    d2 = dx * dx + dy * dy
    margin = g * g - d2
    bound = _FILTER_ULPS * (g * g + d2)
    if margin > bound:
        return True
    if margin < -bound:
        return False
    h = np.empty(24)
    g2 = np.empty(8)
    x2 = np.empty(8)
    y2 = np.empty(8)
    ng = diff_product_expansion(r, ri, r, ri, g2)
    nx = diff_product_expansion(px, cx, px, cx, x2)
    ny = diff_product_expansion(py, cy, py, cy, y2)
    t = np.empty(16)
    nt = expansion_diff(g2, ng, x2, nx, t)
    nh = expansion_diff(t, nt, y2, ny, h)
    return expansion_sign(h, nh) >= 0


@njit(cache=True, inline='always')
def _gap(boxes, v, px, py):
    # how far p lies outside node v's box, in the L1 norm (to pick the nearer child)
    return max(boxes[v, 0] - px, px - boxes[v, 2], 0.0) + max(boxes[v, 1] - py, py - boxes[v, 3], 0.0)


@njit(cache=True)
def _search(disks, order, boxes, reach, children):
    """The mask of hidden disks: each disk, taken in tree order (so that consecutive searches
    walk the same nodes), searches the tree depth first, nearest child first, and stops at the
    first disk that covers it."""
    n = disks.shape[0]
    hidden = np.zeros(n, dtype=np.bool_)
    stack = np.empty(2 * children.shape[0] + 2, dtype=np.int64)
    for s in range(n):
        i = order[s]
        px = disks[s, 0]
        py = disks[s, 1]
        ri = disks[s, 2]
        depth = 1
        stack[0] = 0
        while depth > 0 and not hidden[i]:
            depth -= 1
            v = stack[depth]
            # distance from p_i to the node's box, against the largest radius in it
            bx = max(boxes[v, 0] - px, px - boxes[v, 2], 0.0)
            by = max(boxes[v, 1] - py, py - boxes[v, 3], 0.0)
            dist = math.sqrt(bx * bx + by * by)
            slack = _PRUNE_SLACK * (reach[v] + dist + ri + abs(px) + abs(py))
            if reach[v] - dist < ri - slack:
                continue
            left = children[v, 0]
            if left >= 0:
                right = children[v, 1]
                # the child whose box is nearer p_i goes on top of the stack
                near, far = (left, right) if _gap(boxes, left, px, py) <= _gap(boxes, right, px, py) else (right, left)
                stack[depth] = far
                stack[depth + 1] = near
                depth += 2
                continue
            for t in range(children[v, 2], children[v, 3]):
                j = order[t]
                rj = disks[t, 2]
                if j == i or rj < ri:
                    continue
                if rj == ri and disks[t, 0] == px and disks[t, 1] == py:
                    if j < i:                       # identical disks: the later one is hidden
                        hidden[i] = True
                        break
                    continue
                if _covers(disks[t, 0], disks[t, 1], rj, px, py, ri):
                    hidden[i] = True
                    break
    return hidden
