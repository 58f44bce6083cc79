"""The exact stage of the compiled sweep of disks (:mod:`impls.fortune.disk_sweep`): each
decision its float filter left open, in rationals, by the predicates of the sweep written for
correctness (:mod:`impls.fortune.apollonius_sweep`, :mod:`vorobench.core.predicates.apollonius`).

The compiled sweep calls these from object mode with indices into the disks of one build,
which :func:`exact_context` holds in event order (as the weighted sweep's exact stage holds its
sites: :mod:`impls.fortune.power_exact`); a disk becomes rationals when first asked for. An
event is named by ``(kind, i, a, b, c)``: kind SITE_KIND with site i (its time y_i - r_i), or
CIRCLE_KIND with the ordered triple (a, b, c) (its time the top of their Apollonius circle).
"""

from __future__ import annotations

import functools
from contextlib import contextmanager
from typing import Iterator, Optional

import numpy as np

from impls.fortune.apollonius_sweep import meets, side
from vorobench.core.predicates.apollonius import ApolloniusVertex, QuadraticNumber, compare, rational, vertex

__all__ = ["SITE_KIND", "CIRCLE_KIND", "exact_context", "breakpoint_side", "circle_event", "compare_events", "same_point",
           "vertex_floats"]

SITE_KIND = 0
CIRCLE_KIND = 1

_ZERO = rational(0)


_disks: Optional[tuple[np.ndarray, np.ndarray, np.ndarray]] = None


@contextmanager
def exact_context(xs: np.ndarray, ys: np.ndarray, rs: np.ndarray) -> Iterator[None]:
    """Make the disks (x, y, r) in event order the input the exact stage answers about, for one
    build."""
    global _disks
    _disks = (xs, ys, rs)
    try:
        yield
    finally:
        _disks = None
        _vertex.cache_clear()


def _disk(i: int) -> tuple:
    xs, ys, rs = _disks
    return rational(float(xs[i])), rational(float(ys[i])), rational(float(rs[i]))


@functools.lru_cache(maxsize=1 << 14)
def _vertex(a: tuple, b: tuple, c: tuple) -> Optional[ApolloniusVertex]:
    """The vertex of disks a, b, c (as exact tuples) in that order; cached, since an event's
    exact time is asked for again by each comparison the filters leave open."""
    return vertex((a, b, c), 0, 1, 2)


def _triple_vertex(a: int, b: int, c: int) -> ApolloniusVertex:
    v = _vertex(_disk(a), _disk(b), _disk(c))
    if v is None:
        raise RuntimeError(f"disk sweep: the circle event of disks {a}, {b}, {c} has no vertex")
    return v


def _time(kind: int, i: int, a: int, b: int, c: int) -> QuadraticNumber:
    """An event's exact time."""
    if kind == SITE_KIND:
        x, y, r = _disk(i)
        return QuadraticNumber(y - r, _ZERO, _ZERO)
    v = _triple_vertex(a, b, c)
    return v.y + v.radius


def breakpoint_side(s: int, a: int, b: int) -> int:
    """Sign of x_s - (the breakpoint of left arc a and right arc b) at site s's time."""
    disks = {m: _disk(m) for m in (s, a, b)}
    x, y, r = disks[s]
    return side(disks, y - r, x, a, b)


def circle_event(a: int, b: int, c: int, kind: int, i: int, ea: int, eb: int, ec: int
                 ) -> tuple[bool, float, float, float]:
    """Whether arc b between a and c has a circle event not before the sweep's present event
    (kind, i, ea, eb, ec), and its vertex and time as floats (each to about an ulp)."""
    v = _vertex(_disk(a), _disk(b), _disk(c))
    if v is None:
        return False, 0.0, 0.0, 0.0
    top = v.y + v.radius
    if compare(top, _time(kind, i, ea, eb, ec)) < 0:
        return False, 0.0, 0.0, 0.0
    disks = {0: _disk(a), 1: _disk(b), 2: _disk(c)}
    if not (meets(disks, 0, 1, v, top) and meets(disks, 1, 2, v, top)):
        return False, 0.0, 0.0, 0.0
    return True, float(v.x), float(v.y), float(top)


def compare_events(kind1: int, i1: int, a1: int, b1: int, c1: int,
                   kind2: int, i2: int, a2: int, b2: int, c2: int) -> int:
    """The exact sign of time(event 1) - time(event 2)."""
    return compare(_time(kind1, i1, a1, b1, c1), _time(kind2, i2, a2, b2, c2))


def same_point(a1: int, b1: int, c1: int, a2: int, b2: int, c2: int) -> bool:
    """Whether the vertices of two triples are one point."""
    v = _triple_vertex(a1, b1, c1)
    w = _triple_vertex(a2, b2, c2)
    return compare(v.x, w.x) == 0 and compare(v.y, w.y) == 0


def vertex_floats(a: int, b: int, c: int) -> tuple[float, float]:
    """A triple's vertex as floats, each to about an ulp."""
    v = _triple_vertex(a, b, c)
    return float(v.x), float(v.y)
