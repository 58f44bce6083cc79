"""The float filters of the sweep of disks against the rational predicates they stand in front
of: wherever a filter decides, it decides as the exact stage does, on random disks and on disks
snapped to a coarse lattice (ties, touching circles, equal radii); and on random disks it
decides nearly always, or it would be no filter."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from impls.fortune.apollonius_sweep import meets, side
from vorobench.core.predicates import running_error
from vorobench.core.predicates.apollonius import rational, vertex
from vorobench.core.predicates.apollonius_filter import NO_VERTEX, UNDECIDED, VERTEX, breakpoint_side, meets as \
    meets_filter, vertex_box

_coordinate = st.one_of(st.floats(-4, 4, allow_nan=False), st.integers(-4, 4).map(float),
                        st.integers(-16, 16).map(lambda k: k / 8))
_radius = st.one_of(st.floats(0, 1, allow_nan=False), st.integers(0, 4).map(lambda k: k / 4))
_disk = st.tuples(_coordinate, _coordinate, _radius)


def _exact(disks):
    return [tuple(rational(v) for v in d) for d in disks]


@settings(max_examples=400, deadline=None)
@given(st.tuples(_disk, _disk, _disk))
def test_a_decided_vertex_is_the_exact_one(disks):
    status, x_lo, x_hi, y_lo, y_hi, t_lo, t_hi = vertex_box(*disks[0], *disks[1], *disks[2])
    if status == UNDECIDED:
        return
    exact = vertex(_exact(disks), 0, 1, 2)
    if status == NO_VERTEX:
        assert exact is None
        return
    assert status == VERTEX and exact is not None
    top = exact.y + exact.radius
    assert x_lo <= float(exact.x) <= x_hi and y_lo <= float(exact.y) <= y_hi and t_lo <= float(top) <= t_hi
    for a, b in ((0, 1), (1, 2)):
        decided = meets_filter(*disks[a], *disks[b], x_lo, x_hi, t_lo, t_hi)
        if decided != UNDECIDED:
            assert bool(decided) == meets(_exact(disks), a, b, exact, top)


@settings(max_examples=400, deadline=None)
@given(st.tuples(_disk, _disk, _disk))
def test_a_decided_breakpoint_side_is_the_exact_one(disks):
    exact = _exact(disks)
    now = exact[2][1] - exact[2][2]                # the time of site 2's event
    if any(now < d[1] - d[2] for d in exact[:2]):
        return                                     # arcs 0 and 1 must be on the beach line then
    L, e_L = running_error.sub(disks[2][1], 0.0, disks[2][2], 0.0)
    decided = breakpoint_side(disks[2][0], L, e_L, *disks[0], *disks[1])
    if decided != UNDECIDED:
        assert decided == side(exact, now, exact[2][0], 0, 1)


def test_random_disks_are_decided_by_the_filters():
    rng = np.random.default_rng(5)
    decided = 0
    for _ in range(500):
        d = rng.random((3, 3)) * [1, 1, 0.1]
        decided += vertex_box(*d[0], *d[1], *d[2])[0] != UNDECIDED
    assert decided >= 495
