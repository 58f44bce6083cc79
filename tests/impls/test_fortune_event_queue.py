"""The sweep's circle-event heap against a sorted list: pushes, pops and removals from the
middle in random order, with many equal tops (ties go to the older event)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from impls.fortune import event_queue as eq
from impls.fortune.sweep import N_COUNTERS


class Queue:
    """The heap with synthetic events: each has an exact key (CY = its top, R2 = 0), so equal
    float tops are decided by the exact-key tie rule and the order is (top, age)."""

    def __init__(self, capacity: int):
        self.ev_i, self.ev_f, self.heap, self.hkey, self.free = eq.new_queue(capacity)
        self.sites = np.zeros((1, 2))
        self.counters = np.zeros(N_COUNTERS, dtype=np.int64)
        self.size = 0
        self.seq = 0

    def push(self, row: int, top: float) -> None:
        self.ev_i[row, eq.SEQ] = self.seq
        self.seq += 1
        self.ev_i[row, eq.KEY] = eq.KEY_EXACT
        self.ev_f[row, eq.Y] = top
        self.ev_f[row, eq.ERR] = 0.0
        self.ev_f[row, eq.CY] = top
        self.ev_f[row, eq.R2] = 0.0
        self.size = eq.push(self.sites, self.ev_i, self.ev_f, self.heap, self.hkey, self.size, row, self.counters)

    def pop(self) -> int:
        row, self.size = eq.pop(self.sites, self.ev_i, self.ev_f, self.heap, self.hkey, self.size, self.counters)
        return int(row)

    def discard(self, row: int) -> None:
        self.size = eq.discard(self.sites, self.ev_i, self.ev_f, self.heap, self.hkey, self.size, row, self.counters)

    def check_positions(self) -> None:
        for k in range(self.size):
            assert self.ev_i[self.heap[k], eq.POS] == k


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(st.sampled_from(["push", "push", "pop", "discard"]), st.integers(0, 7),
                          st.integers(0, 10**6)), min_size=1, max_size=300))
def test_heap_pops_in_order_of_top_then_age(operations):
    q = Queue(400)
    live: dict[int, tuple[int, int]] = {}            # row -> (top, sequence number)
    next_row = 0
    for kind, top, pick in operations:
        if kind == "push":
            q.push(next_row, float(top))             # 8 distinct tops: ties are the rule
            live[next_row] = (top, q.seq - 1)
            next_row += 1
        elif kind == "pop" and live:
            want = min(live, key=live.__getitem__)
            assert q.pop() == want
            del live[want]
        elif kind == "discard" and live:
            row = sorted(live)[pick % len(live)]
            q.discard(row)
            assert q.ev_i[row, eq.POS] == -1
            del live[row]
        assert q.size == len(live)
        q.check_positions()
    order = sorted(live, key=live.__getitem__)
    assert [q.pop() for _ in order] == order


def test_heap_with_removals_near_the_root_keeps_its_order():
    # Fortune's sweep on a convex curve removes events near the root over and over while the
    # heap holds thousands; every removal refills a hole from the last slot
    rng = np.random.default_rng(5)
    q = Queue(5000)
    tops = rng.integers(0, 50, size=4000).astype(float)
    for row, top in enumerate(tops):
        q.push(row, top)
    alive = set(range(4000))
    for _ in range(1500):
        row = int(q.heap[rng.integers(0, min(q.size, 7))])  # one of the three top levels
        q.discard(row)
        alive.remove(row)
    q.check_positions()
    popped = [q.pop() for _ in range(q.size)]
    assert popped == sorted(alive, key=lambda r: (tops[r], r))
