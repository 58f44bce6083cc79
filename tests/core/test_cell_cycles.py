"""Each cell's half-edges in ``next`` order (vorobench/core/cell_cycles.py), with their origins
read along the walk: the same cycles, starts and first bad cell as a plain walk in Python."""

import numpy as np
import pytest

import datasets_gen
import impls
from vorobench.core.cell_cycles import cell_cycles


def _plain_walk(site, nxt, origin, n):
    """(order, offsets, bad) by the definition: cells walked in the order their starts lie in
    memory, each from its lowest half-edge from infinity (else its lowest half-edge)."""
    members = [[] for _ in range(n)]
    for h, c in enumerate(site.tolist()):
        members[c].append(h)
    start = {c: next((h for h in hs if origin[h] < 0), hs[0]) for c, hs in enumerate(members) if hs}
    offsets = np.concatenate([[0], np.cumsum([len(hs) for hs in members])])
    order = np.full(site.size, -1)
    for c in sorted(start, key=start.get):
        h, k = start[c], offsets[c]
        while True:
            if k >= offsets[c + 1] or site[h] != c:
                return order, offsets, c
            order[k], k, h = h, k + 1, nxt[h]
            if h == start[c]:
                break
        if k != offsets[c + 1]:
            return order, offsets, c
    return order, offsets, -1


@pytest.mark.parametrize("name", ["fortune", "incremental"])
@pytest.mark.parametrize("dataset", ["uniform", "grid"])
def test_the_cycles_are_those_of_a_plain_walk(name, dataset):
    d = impls.build(name, datasets_gen.generate(dataset, 3000, seed=1))
    order, origins, offsets, bad = cell_cycles(d.site, d.next, d.origin, d.n_sites)
    expected, expected_offsets, expected_bad = _plain_walk(d.site, d.next, d.origin, d.n_sites)
    assert bad == expected_bad == -1
    assert np.array_equal(offsets, expected_offsets)
    assert np.array_equal(order, expected)
    assert np.array_equal(origins, d.origin[expected])


@pytest.mark.parametrize("seed", range(6))
def test_the_bad_cell_is_the_first_a_plain_walk_finds(seed):
    # two cells spoilt far apart in memory: one's next leaves the cell, the other's skips a
    # half-edge (its cycle misses it); the walk names the one whose start comes first, as the
    # plain walk does
    d = impls.build("fortune", datasets_gen.generate("uniform", 3000, seed=seed))
    nxt = d.next.copy()
    rng = np.random.default_rng(seed)
    h1, h2 = int(rng.integers(0, d.n_half_edges // 4)), int(rng.integers(3 * d.n_half_edges // 4, d.n_half_edges))
    if rng.random() < 0.5:
        h1, h2 = h2, h1
    other = int(np.flatnonzero(d.site != d.site[h1])[0])
    nxt[h1] = other                                     # leaves its cell
    nxt[h2] = nxt[nxt[h2]]                              # skips one half-edge of its cell
    order, origins, offsets, bad = cell_cycles(d.site, nxt, d.origin, d.n_sites)
    expected_bad = _plain_walk(d.site, nxt, d.origin, d.n_sites)[2]
    assert bad >= 0 and bad == expected_bad


def test_cycles_that_swap_half_edges_between_cells_are_bad():
    # cells 0 = {0, 1} and 1 = {2, 3}, whose next pairs each half-edge with one of the other
    # cell: every cycle has its cell's length and returns to its start, yet leaves its cell
    site = np.array([0, 0, 1, 1], dtype=np.int32)
    nxt = np.array([2, 3, 0, 1], dtype=np.int32)
    origin = np.array([0, 1, 2, 3], dtype=np.int32)
    assert cell_cycles(site, nxt, origin, 2)[3] == _plain_walk(site, nxt, origin, 2)[2] == 0
