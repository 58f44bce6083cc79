"""The weighted sweep's vertical slabs (impls/fortune/slabs.py): a site's slab is the number of
cuts at or left of it, as numpy's ``searchsorted(cuts, x, side="right")`` defines it, for any
cuts (repeated, clustered, a single one, none) and any finite x (on a cut, just beside one,
far outside the cuts' range)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from impls.fortune.slabs import _count_at_most, slabs

finite = st.floats(allow_nan=False, allow_infinity=False)
small = st.floats(-4, 4, allow_nan=False, allow_infinity=False)


def _counted(cuts, x):
    cuts, x = np.sort(np.asarray(cuts, dtype=np.float64)), np.asarray(x, dtype=np.float64)
    out = np.full(x.shape[0], -7, dtype=np.int64)
    _count_at_most(cuts, x, out)
    return out, np.searchsorted(cuts, x, side="right")


@settings(max_examples=300, deadline=None)
@given(st.lists(st.one_of(small, finite), max_size=40), st.lists(st.one_of(small, finite), min_size=1, max_size=60))
def test_the_count_of_cuts_is_numpys(cuts, x):
    got, expected = _counted(cuts, x)
    assert np.array_equal(got, expected)


def test_points_on_and_beside_repeated_cuts_are_counted_as_numpy_counts_them():
    rng = np.random.default_rng(5)
    cuts = np.sort(np.round(rng.standard_cauchy(500), 1))       # repeats, and a cluster near 0
    x = np.concatenate([cuts, np.nextafter(cuts, -np.inf), np.nextafter(cuts, np.inf), rng.standard_cauchy(5000),
                        [cuts[0] - 1e200, cuts[-1] + 1e200]])
    got, expected = _counted(cuts, x)
    assert np.array_equal(got, expected)


def test_cuts_and_points_spanning_more_than_the_largest_float():
    # the cuts' range and a point's distance from the first cut overflow to inf: the grid's
    # cell is NaN there, and the count must still be numpy's (this crashed once)
    got, expected = _counted([-1e308, 0.0, 1e308], [1e308, -1e308, 0.0, 5e307, -np.finfo(float).max])
    assert np.array_equal(got, expected)
    x = np.array([-1e308] * 4 + [1e308] * 5)
    cuts = np.quantile(x, np.arange(1, 3) / 3)                   # three slabs of nine sites
    assert np.array_equal(slabs(x), np.searchsorted(cuts, x, side="right"))


def test_slabs_cut_at_quantiles_of_a_sample():
    x = np.random.default_rng(6).random(10_000) ** 3            # denser near 0: narrower slabs there
    got = slabs(x)
    cuts = np.quantile(x[::1], np.arange(1, 100) / 100)
    assert np.array_equal(got, np.searchsorted(cuts, x, side="right"))
    assert np.bincount(got).max() <= 2 * 100                    # about sqrt(n) sites per slab
