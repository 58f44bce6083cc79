"""Float bounds on where the bisector branch of two disks can lie, seen from one centre: the
filters in front of the exact Apollonius predicates (docs/apollonius.md). Each answers
"disk j certainly cannot reach this part of cell i" with room for every rounding, or "maybe";
"maybe" costs an exact test, never a wrong answer.

Seen from p_i, the branch of i and j lies along direction u at t = (|a|^2 - s^2) / (2 (s + u . a))
(a = p_j - p_i, s = r_j - r_i), where s + u . a > 0: over the open arc of directions of
half-width acos(-s / |a|) about a's direction, nearest to p_i at its apex, (|a| - s) / 2.
"""

from __future__ import annotations

import math
from typing import Optional

import numpy as np
from numpy.typing import NDArray

from vorobench.core.predicates.apollonius import ApolloniusVertex

__all__ = ["ANGLE_PAD", "RADIUS_PAD", "DiskFloats", "arc_between", "apart", "nearest_reach", "tail_apart"]

#: Padding of the filters: angles (radians) and relative radii.
ANGLE_PAD = 1e-9
RADIUS_PAD = 1e-9


def arc_between(first: Optional[float], last: Optional[float]) -> Optional[tuple[float, float]]:
    """The counter-clockwise arc of directions from ``first`` to ``last`` as (centre, half-width)."""
    if first is None or last is None:
        return None
    width = (last - first) % (2 * math.pi)
    return first + width / 2, width / 2


def apart(arc: Optional[tuple[float, float]], centre: float, half: float) -> bool:
    """Whether two arcs of directions are disjoint with room to spare."""
    if arc is None:
        return False
    offset = abs((arc[0] - centre + math.pi) % (2 * math.pi) - math.pi)
    return offset > arc[1] + half + ANGLE_PAD


class DiskFloats:
    """Float images of the disks and of exact points, for the filters."""

    def __init__(self, centres: NDArray[np.float64], radii: NDArray[np.float64]) -> None:
        self.centres = centres
        self.radii = radii
        scale = float(np.abs(centres).max() + radii.max()) if centres.size else 1.0
        self.slack = 1e-12 * scale                  # absolute padding of distances
        self.near = 1e-6 * scale                    # closer than this to p_i, angles are not trusted
        self._points: dict[int, tuple[float, float]] = {}
        self._asymptotes: dict[tuple[int, int, int], Optional[float]] = {}

    def point(self, v: ApolloniusVertex) -> tuple[float, float]:
        if v.sites not in self._points:              # one point per ordered triple (or apex)
            self._points[v.sites] = (float(v.x), float(v.y))
        return self._points[v.sites]

    def distance(self, i: int, v: ApolloniusVertex) -> float:
        x, y = self.point(v)
        return math.hypot(x - self.centres[i][0], y - self.centres[i][1])

    def angle(self, i: int, v: ApolloniusVertex) -> Optional[float]:
        """The direction of v from p_i, None where v is too close to p_i for it to be trusted."""
        x, y = self.point(v)
        dx, dy = x - self.centres[i][0], y - self.centres[i][1]
        return math.atan2(dy, dx) if math.hypot(dx, dy) > self.near else None

    def norm_and_gap(self, i: int, j: int) -> tuple[float, float]:
        """|p_j - p_i| and r_j - r_i."""
        ax, ay = self.centres[j] - self.centres[i]
        return math.hypot(ax, ay), float(self.radii[j] - self.radii[i])

    def spread(self, i: int, j: int) -> tuple[float, Optional[float]]:
        """Direction of p_j from p_i and the half-width of the arc of directions j's branch
        spans (None when the disks nearly nest and the width is ill-conditioned)."""
        ax, ay = self.centres[j] - self.centres[i]
        s = float(self.radii[j] - self.radii[i])
        norm = math.hypot(ax, ay)
        if norm - abs(s) < 1e-6 * norm:
            return math.atan2(ay, ax), None
        return math.atan2(ay, ax), math.atan2(math.sqrt((norm - s) * (norm + s)), -s)

    def asymptote_angle(self, i: int, a: int, side: int) -> Optional[float]:
        key = (i, a, side)
        if key not in self._asymptotes:
            centre, half = self.spread(i, a)
            self._asymptotes[key] = None if half is None else centre + side * half
        return self._asymptotes[key]


def nearest_reach(arc: Optional[tuple[float, float]], centre: float, norm: float, s: float) -> float:
    """A lower bound on how far from p_i disk j's branch lies within an arc of directions: along
    u it lies at (|a|^2 - s^2) / (2 (s + u . a)) (a = p_j - p_i, s = r_j - r_i), nearest where u
    is closest to a's direction; inf where it never comes (s + u . a <= 0 on the whole arc)."""
    if arc is None:
        cosine = 1.0
    else:
        offset = abs((arc[0] - centre + math.pi) % (2 * math.pi) - math.pi)
        cosine = 1.0 if offset <= arc[1] else math.cos(offset - arc[1])
    reach = s + norm * min(1.0, cosine + ANGLE_PAD)
    if reach <= 0:
        return math.inf
    return (norm - s) * (norm + s) / (2 * reach)


def tail_apart(fl: DiskFloats, i: int, a: int, side: int, near: float, j: int) -> bool:
    """Whether disk j cannot reach the end of the branch of (i, a) that runs out to infinity on
    ``side`` (+1: with cell i on the left), beyond distance ``near`` from p_i. Only the part
    farther than j's nearest reach can be cut, and that part spans fewer directions: repeated,
    the arc shrinks towards the asymptote, which j reaches or not."""
    centre_a, half_a = fl.spread(i, a)
    centre_j, half_j = fl.spread(i, j)
    if half_a is None or half_j is None:
        return False
    norm_a, s_a = fl.norm_and_gap(i, a)
    norm_j, s_j = fl.norm_and_gap(i, j)
    offset = 0.0                                   # the arc: offsets from the apex's direction
    for _ in range(8):
        arc = arc_between(centre_a + side * offset if side > 0 else centre_a - half_a,
                   centre_a + half_a if side > 0 else centre_a - offset)
        reach = nearest_reach(arc, centre_j, norm_j, s_j)
        if reach == math.inf:
            return True
        if reach <= near * (1 + RADIUS_PAD) + fl.slack:
            return False
        # along the branch, the distance from p_i grows with the offset from the apex direction
        cosine = ((norm_a - s_a) * (norm_a + s_a) / (2 * reach) - s_a) / norm_a
        farther = math.acos(max(-1.0, min(1.0, cosine))) - ANGLE_PAD
        if farther <= offset * (1 + 1e-3):
            return False
        offset = farther
    return False
