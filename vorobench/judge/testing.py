"""Test helpers: assert that two diagrams are the same Voronoi diagram, with a precise message."""

from __future__ import annotations

from vorobench.core.diagram import Diagram
from vorobench.judge.comparison import Comparison, compare
from vorobench.judge.outcomes import Verdict

__all__ = ["assert_diagrams_equal"]


def assert_diagrams_equal(a: Diagram, b: Diagram, exact: bool = False, **kwargs) -> Comparison:
    """Raise ``AssertionError`` with the comparison's report unless ``a`` and ``b`` compare equal.

    ``exact=True`` requires the ``exact`` verdict (after exact normalisation only); otherwise
    ``within_tolerance`` passes too. Keyword arguments go to :func:`vorobench.compare`.
    Returns the :class:`~vorobench.judge.comparison.Comparison` for further checks.
    """
    comparison = compare(a, b, **kwargs)
    if not comparison.equal or (exact and comparison.verdict != Verdict.EXACT):
        want = "exactly equal" if exact else "equal"
        raise AssertionError(f"diagrams are not {want}:\n{comparison}")
    return comparison
