"""Change points of a series of runs: steps in build time, changes of exact counters.

A series is one case (implementation, dataset, n, seed) on one machine, its runs in date order.

**Time steps** (:func:`time_steps`). Each run gives the repeats of the case's build time. The
detection is binary segmentation of the log of each run's median time (a step in log time is
a ratio, whatever the size of the case):

1. Within a segment of runs, the candidate split is the run that minimises the summed squared
   error of the log medians about the mean of each side.
2. The split is accepted only if the one timing rule
   (:func:`vorobench.harness.timing_rule.decide`, the rule of ``compare``) says "slower" or
   "faster" for all repeats of the segment's runs after the split against all before it: the
   ratio of their medians beyond ``1 + threshold`` (or below its inverse), its bootstrap
   interval clear of 1, a one-sided Mann-Whitney U test with ``p < alpha``, and the ratio
   outside the run-to-run noise measured between the two runs around the split (``noise``).
3. An accepted split segments both of its sides the same way; a rejected one ends its segment.
4. Finally each change point is checked again between its neighbours (the runs from the
   previous change point to the next one), and the weakest one that fails rule 2 there is
   dropped, until all pass. So every change point reported satisfies rule 2 with the medians,
   ratio and p-value reported with it, and a pair of runs gets the same answer here as from
   ``compare``.

The threshold keeps differences too small to matter out (the repeats of many runs pooled make
a rank test call a 3 % drift significant); the rank test keeps out steps the repeats cannot
support (one repeat a side, or repeats scattered over both levels). The p-value is taken
after the best split was chosen, so it is optimistic; it is a guard, not a calibrated error
rate. A run at a new level is a change point as soon as its repeats show it, the last run
included.

**Counter changes** (:func:`counter_steps`). Counters (``stat_*``) are machine-independent
integers, equal for equal code on equal input, so every run whose value differs from the
previous run that has one is a change point; no threshold, no test.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable, Optional, Sequence

import numpy as np

from vorobench.harness.timing_rule import TimingDecision, decide

__all__ = ["TimeStep", "CounterStep", "time_steps", "counter_steps"]


@dataclass(frozen=True)
class TimeStep:
    """A step in build time before run ``index`` of the series (``index`` is the first run at the new level)."""

    index: int
    before: float            # median of the repeats from the previous change point up to the step
    after: float             # median of the repeats from the step up to the next change point
    ratio: float             # after / before
    p_value: float           # one-sided Mann-Whitney U in the step's direction, repeats before vs after
    first: int               # first run of the segment before
    end: int                 # one past the last run of the segment after


@dataclass(frozen=True)
class CounterStep:
    """A counter's value changed at run ``index``, from its value at run ``previous_index``."""

    index: int
    previous_index: int
    before: Any
    after: Any


def _test(samples: Sequence[np.ndarray], lo: int, split: int, hi: int, threshold: float, alpha: float,
          noise: Callable[[int], Optional[float]]) -> TimingDecision:
    """The one timing rule for runs [lo, split) against [split, hi)."""
    return decide(np.concatenate(samples[lo:split]), np.concatenate(samples[split:hi]), threshold, alpha,
                  noise=noise(split), noise_source="the spread of all cases' ratios between these runs")


def _best_split(logs: np.ndarray, lo: int, hi: int) -> int:
    """The split in (lo, hi) minimising the squared error of ``logs`` about each side's mean."""
    x = logs[lo:hi]
    s1 = np.concatenate([[0.0], np.cumsum(x)])
    s2 = np.concatenate([[0.0], np.cumsum(x * x)])
    m = x.size
    k = np.arange(1, m)
    left = s2[k] - s1[k] ** 2 / k
    right = (s2[m] - s2[k]) - (s1[m] - s1[k]) ** 2 / (m - k)
    return lo + 1 + int(np.argmin(left + right))


def time_steps(samples: Sequence[Sequence[float]], threshold: float = 0.10, alpha: float = 0.05,
               noise: Optional[Callable[[int], Optional[float]]] = None) -> list[TimeStep]:
    """The steps in a series of runs' build times (see the module docstring for the rule).

    ``samples[i]`` holds the repeats (seconds, > 0) of run ``i``, runs in date order.
    ``noise(i)``: the run-to-run noise (log-ratio half-width) between runs i - 1 and i, or None.
    Returns the steps in run order; ``[]`` for fewer than two runs. ValueError if a run has no
    repeat.
    """
    runs = [np.asarray(s, dtype=float).ravel() for s in samples]
    for i, r in enumerate(runs):
        if r.size == 0 or not np.all(np.isfinite(r)):
            raise ValueError(f"run {i} of the series has no repeats (or a time that is not a number)")
    if len(runs) < 2:
        return []
    noise = noise or (lambda i: None)
    logs = np.log(np.maximum([np.median(r) for r in runs], 1e-300))

    found: list[int] = []
    pending = [(0, len(runs))]
    while pending:
        lo, hi = pending.pop()
        if hi - lo < 2:
            continue
        split = _best_split(logs, lo, hi)
        if _test(runs, lo, split, hi, threshold, alpha, noise).is_change:
            found.append(split)
            pending += [(lo, split), (split, hi)]
    found.sort()

    while True:
        bounds = [0, *found, len(runs)]
        checked = [(i, _test(runs, bounds[i], bounds[i + 1], bounds[i + 2], threshold, alpha, noise))
                   for i in range(len(found))]
        failing = [(i, d) for i, d in checked if not d.is_change]
        if not failing:
            break
        weakest = max(failing, key=lambda c: (c[1].p_value if c[1].p_value is not None else 1.0,
                                              -abs(math.log(c[1].ratio)) if 0 < c[1].ratio < math.inf else 0.0))
        del found[weakest[0]]
    return [TimeStep(index=found[i], before=d.base_median, after=d.new_median, ratio=d.ratio,
                     p_value=d.p_value if d.p_value is not None else 1.0, first=bounds[i], end=bounds[i + 2])
            for i, d in checked]


def counter_steps(values: Sequence[Optional[Any]]) -> list[CounterStep]:
    """Every run whose counter value differs from the previous run that has one (None: no value)."""
    out: list[CounterStep] = []
    previous: Optional[int] = None
    for i, value in enumerate(values):
        if value is None:
            continue
        if previous is not None and value != values[previous]:
            out.append(CounterStep(index=i, previous_index=previous, before=values[previous], after=value))
        previous = i
    return out
