"""prepare(): clear errors on bad input, deduplication with an inverse map."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from vorobench import prepare


@pytest.mark.parametrize(
    "bad, words",
    [
        ([[1.0, np.nan]], ["finite", "row 0"]),
        ([[0.0, 0.0], [1.0, 2.0], [np.inf, 3.0]], ["finite", "row 2"]),
        ([1.0, 2.0, 3.0], ["shape (n, 2)", "(3,)"]),
        (np.zeros((4, 3)), ["shape (n, 2)", "(4, 3)"]),
        ([["a", "b"]], ["real numbers", "string"]),
        ("hello", ["string"]),
        (np.array([[1 + 2j, 0]]), ["complex"]),
        ([[1.0, 2.0], [3.0]], ["(n, 2)"]),
    ],
)
def test_bad_input_names_the_problem(bad, words):
    with pytest.raises(ValueError) as info:
        prepare(bad)
    for w in words:
        assert w in str(info.value)


def test_empty_input_is_allowed():
    sites, inverse = prepare(np.zeros((0, 2)))
    assert sites.shape == (0, 2) and inverse.shape == (0,)
    sites, _ = prepare([])
    assert sites.shape == (0, 2)


def test_duplicates_are_removed_in_order_of_first_appearance():
    pts = [[2, 2], [0, 0], [2, 2], [1, 1], [0, 0], [-0.0, 0.0]]
    sites, inverse = prepare(pts)
    assert sites.tolist() == [[2, 2], [0, 0], [1, 1]]
    assert inverse.tolist() == [0, 1, 0, 2, 1, 1]
    assert np.array_equal(sites[inverse], np.asarray(pts, dtype=float) + 0.0)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.5, 1e-300, 5e-324, 1e300, 3.0]),
                          st.sampled_from([0.0, -0.0, 2.0, -7.5, 1e-300, 5e-324, 1e300])), max_size=60))
def test_deduplication_matches_a_dictionary_of_first_appearances(rows):
    """Few distinct values, so that duplicates (and -0.0 against 0.0) abound."""
    first: dict = {}
    want = [first.setdefault((x + 0.0, y + 0.0), len(first)) for x, y in rows]
    try:
        sites, inverse = prepare(np.asarray(rows, dtype=float).reshape(-1, 2))
    except ValueError as exc:                      # 1e300 with 5e-324: beyond the exact range
        assert "span" in str(exc)
        return
    assert inverse.tolist() == want
    assert [tuple(r) for r in sites.tolist()] == list(first)


def test_output_is_contiguous_float64_and_integers_accepted():
    sites, inverse = prepare(np.arange(10, dtype=np.int32).reshape(5, 2))
    assert sites.dtype == np.float64 and sites.flags.c_contiguous
    assert inverse.tolist() == list(range(5))


# ------------------------------------------------------------------------------ exact range
def test_magnitudes_spanning_more_than_the_exact_range_are_refused():
    """Nonzero magnitudes must fit in [2**-100, 2**100) after one power-of-two scaling:
    their binary exponents (frexp) may differ by at most 199."""
    with pytest.raises(ValueError) as info:
        prepare([[1.0, 0.0], [0.0, 1e-300], [0.5, 0.5]])
    text = str(info.value)
    assert "exact range" in text and "2**-100" in text and "2**100" in text and "row 1" in text
    # the boundary: 2**-199 with 1.0 (exponents 1 and -198) fits, half of it does not
    sites, _ = prepare([[1.0, 0.0], [0.0, 2.0**-199]])
    assert sites.shape == (2, 2)
    with pytest.raises(ValueError, match="exact range"):
        prepare([[1.0, 0.0], [0.0, 2.0**-200]])


@pytest.mark.parametrize("k", [-1070, -1000, -300, 300, 1000, 1020])
def test_any_magnitude_alone_is_accepted_unchanged(k):
    pts = np.ldexp(np.array([[1.0, 3.0], [0.0, 2.0], [5.0, 0.0]]), k)
    sites, _ = prepare(pts)
    assert np.array_equal(sites, pts)
