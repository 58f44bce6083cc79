"""The one rule that decides whether a case got slower, faster, stayed the same or cannot tell.

``compare`` (and ``continuous``, which ends in it) decides each case with :func:`decide`; ``trend``
keeps a change point only where :func:`decide` says slower or faster between its two sides. So
the two never disagree about a pair of runs.

The rule, on the repeats (seconds) of BASE and NEW:

* **slower**: the ratio of the medians NEW / BASE exceeds ``1 + threshold``, its percentile
  bootstrap 95 % interval lies above 1, and a one-sided Mann-Whitney U test of the repeats gives
  p < ``alpha``; **faster** the mirror image;
* **same**: the interval lies within ``1 / (1 + threshold)`` .. ``1 + threshold``;
* **inconclusive** otherwise, and also when a change lies within the measured run-to-run
  ``noise`` (a log-ratio half-width: the spread of all cases' ratios, or this case's spread
  over earlier runs), however clear its own repeats are. Each inconclusive decision says why
  and what would decide it.

The bootstrap is seeded, so the same repeats always get the same decision.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum
from typing import Optional, Sequence

import numpy as np
from scipy.stats import bootstrap, mannwhitneyu, median_abs_deviation

__all__ = ["Timing", "TimingDecision", "decide", "bootstrap_ratio_ci", "one_sided_p", "noise_half_width",
           "NOISE_MIN_CASES", "NOISE_Z", "MEASURES", "choose_measure", "measured"]

#: What a build's time is, as compare and trend judge it: ``cpu`` (the build process's own CPU
#: time, ``cpu_s``), ``wall`` (``time_s``), or ``auto``: CPU time when every timed row has it.
MEASURES = ("auto", "cpu", "wall")

#: Fewest cases timed on both sides from which the run-to-run noise is estimated.
NOISE_MIN_CASES = 6

#: A single case's change must exceed this many robust standard deviations of the run-to-run noise.
NOISE_Z = 3.0


class Timing(str, Enum):
    """How a case's build time changed."""

    SLOWER = "slower"
    FASTER = "faster"
    SAME = "same"
    INCONCLUSIVE = "inconclusive"

    def __str__(self) -> str:
        return self.value


@dataclass(frozen=True)
class TimingDecision:
    """The rule's answer for one case (or one step of a trend)."""

    change: Timing
    ratio: float                       # median(new) / median(base)
    base_median: float
    new_median: float
    ci_low: Optional[float] = None
    ci_high: Optional[float] = None
    p_value: Optional[float] = None    # one-sided, in the direction of the ratio
    why: str = ""                      # why inconclusive, and what would decide it

    @property
    def is_change(self) -> bool:
        return self.change in (Timing.SLOWER, Timing.FASTER)


#: What decides an inconclusive case, said the same way by every command.
MORE = "more repeats (bench --repeat, --min-time; continuous --rounds) or a quieter machine would decide it"


def bootstrap_ratio_ci(base: Sequence[float], new: Sequence[float], rng: np.random.Generator,
                       resamples: int = 2000, level: float = 0.95) -> tuple[float, float]:
    """Percentile bootstrap interval of median(new) / median(base), resampling each side."""
    def ratio(b, m, axis=-1):
        return np.median(m, axis=axis) / np.median(b, axis=axis)

    result = bootstrap((np.asarray(base, float), np.asarray(new, float)), ratio, vectorized=True,
                       method="percentile", n_resamples=resamples, confidence_level=level, rng=rng)
    return float(result.confidence_interval.low), float(result.confidence_interval.high)


def one_sided_p(base: Sequence[float], new: Sequence[float]) -> Optional[float]:
    """One-sided Mann-Whitney U p-value for "NEW is slower than BASE" (None below 2 samples each)."""
    if len(base) < 2 or len(new) < 2:
        return None
    return float(mannwhitneyu(new, base, alternative="greater").pvalue)


def _smallest_p(n1: int, n2: int) -> float:
    """The smallest p-value a one-sided rank test can give with these sample sizes."""
    return 1.0 / math.comb(n1 + n2, n1)


def decide(base: Sequence[float], new: Sequence[float], threshold: float, alpha: float,
           rng: Optional[np.random.Generator] = None, noise: Optional[float] = None,
           noise_source: str = "") -> TimingDecision:
    """Decide one case from its repeats (see the module docstring). ``rng`` seeds the bootstrap
    (default: seed 0); ``noise``: measured run-to-run noise, a log-ratio half-width."""
    base, new = np.asarray(base, float), np.asarray(new, float)
    b, m = float(np.median(base)), float(np.median(new))
    ratio = m / b
    if base.size < 2 or new.size < 2:
        return TimingDecision(Timing.INCONCLUSIVE, ratio, b, m,
                              why=f"one repeat: noise cannot be told from change; {MORE}")
    low, high = bootstrap_ratio_ci(base, new, rng if rng is not None else np.random.default_rng(0))
    slower = ratio >= 1
    p = one_sided_p(base, new) if slower else one_sided_p(new, base)
    testable = _smallest_p(base.size, new.size) < alpha
    significant = testable and p < alpha
    if slower and ratio > 1 + threshold and low > 1 and significant:
        change = Timing.SLOWER
    elif not slower and ratio < 1 / (1 + threshold) and high < 1 and significant:
        change = Timing.FASTER
    elif 1 / (1 + threshold) < low and high < 1 + threshold:
        change = Timing.SAME
    else:
        change = Timing.INCONCLUSIVE
    why = ""
    if change == Timing.INCONCLUSIVE:
        why = (f"{base.size} vs {new.size} repeats: the rank test cannot reach p < {alpha:g}; {MORE}"
               if not testable else
               f"95% CI {low:.2f}-{high:.2f} neither rules out nor shows a {threshold:.0%} change; {MORE}")
    elif change in (Timing.SLOWER, Timing.FASTER) and noise is not None and abs(math.log(ratio)) <= noise:
        change = Timing.INCONCLUSIVE
        why = (f"{ratio:.2f}x lies within the run-to-run noise band (x{math.exp(noise):.2f} either way"
               + (f", from {noise_source}" if noise_source else "") + f"); {MORE}")
    return TimingDecision(change, ratio, b, m, low, high, p, why)


def noise_half_width(ratios: Sequence[float]) -> Optional[float]:
    """Half-width, in log ratio, of the run-to-run noise band of two runs, from the ratios of
    all the cases timed in both; None with fewer than :data:`NOISE_MIN_CASES`.

    Repeats within one run share that run's background (other processes, frequency, cache
    state), so the rank test on one case's repeats sees only part of the noise: on a shared
    machine, a case of one run can be 1.5x slower than the same case of another run while each
    run's repeats agree closely. The spread of the per-case ratios over all cases measures the
    rest: its robust standard deviation (scaled median absolute deviation of the log ratios
    around their median, which a uniform change leaves alone) times :data:`NOISE_Z`.
    """
    logs = np.log([r for r in ratios if r is not None and r > 0 and math.isfinite(r)])
    if logs.size < NOISE_MIN_CASES:
        return None
    return float(NOISE_Z * median_abs_deviation(logs, scale="normal"))


def _has_cpu(df) -> bool:
    import pandas as pd

    if df is None or "cpu_s" not in df.columns:
        return False
    timed = pd.to_numeric(df["time_s"], errors="coerce") > 0
    cpu = pd.to_numeric(df.loc[timed, "cpu_s"], errors="coerce")
    return bool(timed.any()) and bool((cpu > 0).all())


def choose_measure(measure: str, *frames) -> str:
    """The column a comparison of ``frames`` judges: ``cpu_s`` when asked (ValueError if a
    frame lacks it) or, with ``auto``, when every frame records it for every timed build (a
    busy neighbour does not add to a build's own CPU time, while it does to its wall time);
    else ``time_s``."""
    if measure == "wall":
        return "time_s"
    has = all(_has_cpu(f) for f in frames)
    if measure == "cpu" and not has:
        raise ValueError("--measure cpu: a side has no CPU time for every build (results written before "
                         "vorobench recorded cpu_s); use --measure wall")
    return "cpu_s" if has else "time_s"


def measured(df, column: str):
    """``df`` with ``time_s`` replaced by ``column`` (a copy), so that every rule reads one column."""
    return df if column == "time_s" or df is None else df.assign(time_s=df[column])
