"""Regression compare of two benchmark runs: per-case timings with a rank test and a bootstrap interval, a combined geometric-mean verdict, exact counters and verdicts.

The command line is :mod:`vorobench.cli.compare`; its help text describes the behaviour."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional, Sequence

import numpy as np
import pandas as pd
from scipy.stats import ttest_1samp

from vorobench.harness import results, store
from vorobench.harness.timing_rule import NOISE_MIN_CASES, NOISE_Z, decide, noise_half_width
from vorobench.judge.outcomes import Status, counter_columns, status_rank, verdict_rank

__all__ = ["CaseChange", "Overall", "RunComparison", "compare_frames", "compare_runs",
           "compare_files", "load_side", "overall_change",
           "refuse_duplicates", "relative_to", "NOISE_MIN_CASES"]

KEY = ["impl", "dataset", "n", "seed"]


@dataclass
class CaseChange:
    """How one case changed between BASE and NEW, and why it is flagged (if it is)."""

    impl: str
    dataset: str
    n: int
    seed: int
    base_status: Optional[str] = None
    new_status: Optional[str] = None
    base_verdict: Optional[str] = None
    new_verdict: Optional[str] = None
    base_median_s: Optional[float] = None
    new_median_s: Optional[float] = None
    base_repeats: int = 0
    new_repeats: int = 0
    ratio: Optional[float] = None
    ci_low: Optional[float] = None
    ci_high: Optional[float] = None
    p_value: Optional[float] = None
    #: "slower", "faster", "same", "inconclusive", or "" (no timing on one side)
    change: str = ""
    why_inconclusive: str = ""
    #: Why the case, present on both sides, cannot be judged (no usable timing on a side); "" if it can.
    why_not_comparable: str = ""
    counters: dict[str, tuple] = field(default_factory=dict)
    flags: list[str] = field(default_factory=list)

    @property
    def flagged(self) -> bool:
        return bool(self.flags)

    @property
    def notable(self) -> bool:
        """Worth showing with ``--only-changes``: flagged, timed as a change or undecided, or in
        one run only."""
        return (self.flagged or self.change in ("slower", "faster", "inconclusive") or self.base_status is None
                or self.new_status is None)

    @property
    def name(self) -> str:
        return f"{self.impl} {self.dataset} n={self.n} seed={self.seed}"

    @property
    def unchecked(self) -> bool:
        """NEW built the case but did not check its correctness (``bench --no-check``)."""
        return _unchecked(self.new_status, self.new_verdict)

    @property
    def check_lost(self) -> bool:
        """BASE built and checked the case; NEW built it without checking it."""
        return self.base_status == Status.OK and verdict_rank(self.base_verdict) is not None and self.unchecked


@dataclass
class Overall:
    """The combined timing verdict: geometric mean of the per-case ratios, with its interval."""

    cases: int = 0
    geomean: Optional[float] = None
    ci_low: Optional[float] = None
    ci_high: Optional[float] = None
    change: str = ""                     # "slower", "faster", "same", "inconclusive", "" (no case)
    flags: list[str] = field(default_factory=list)


@dataclass
class RunComparison:
    """Every case of BASE and NEW, the combined verdict, and what sets the exit status."""

    changes: list[CaseChange]
    overall: Overall
    threshold: float
    alpha: float
    #: Run-to-run noise band (log ratio half-width, see :func:`noise_band`); None: too few cases.
    noise: Optional[float] = None

    @property
    def missing(self) -> list[CaseChange]:
        return [c for c in self.changes if c.new_status is None]

    @property
    def compared(self) -> list[CaseChange]:
        return [c for c in self.changes if c.base_status is not None and c.new_status is not None
                and not c.why_not_comparable]

    @property
    def not_comparable(self) -> list[CaseChange]:
        """Cases of both sides that cannot be judged: they fail the gate, and are not "compared"."""
        return [c for c in self.changes if c.why_not_comparable]

    @property
    def flagged(self) -> list[CaseChange]:
        return [c for c in self.changes if c.flagged and c.new_status is not None and not c.why_not_comparable]

    @property
    def inconclusive(self) -> list[CaseChange]:
        return [c for c in self.changes if c.change == "inconclusive"]

    @property
    def unchecked(self) -> list[CaseChange]:
        """Compared cases whose correctness NEW did not check: the gate vouches for their
        timings and counters only (flagged when BASE did check them)."""
        return [c for c in self.compared if c.unchecked]

    @property
    def passed(self) -> bool:
        return bool(self.compared) and not (self.flagged or self.missing or self.not_comparable
                                            or self.overall.flags)


def _timing(change: CaseChange, base: np.ndarray, new: np.ndarray, threshold: float, alpha: float, seed: int,
            noise: Optional[float] = None, noise_source: str = "") -> None:
    """Fill ``change``'s timing fields from the one rule (:func:`vorobench.harness.timing_rule.decide`)."""
    d = decide(base, new, threshold, alpha, np.random.default_rng(seed), noise, noise_source)
    change.base_median_s, change.new_median_s = d.base_median, d.new_median
    change.base_repeats, change.new_repeats = int(base.size), int(new.size)
    change.ratio, change.ci_low, change.ci_high, change.p_value = d.ratio, d.ci_low, d.ci_high, d.p_value
    change.change, change.why_inconclusive = d.change.value, d.why


def overall_change(changes: Sequence[CaseChange], threshold: float, level: float = 0.95) -> Overall:
    """Geometric mean of the per-case ratios and a t interval of the mean log ratio; flagged
    "slower" when the mean exceeds 1 + threshold and the interval lies above 1; inconclusive
    with fewer than NOISE_MIN_CASES cases."""
    logs = np.log([c.ratio for c in changes if c.ratio is not None and c.ratio > 0])
    out = Overall(cases=int(logs.size))
    if not logs.size:
        return out
    out.geomean = float(np.exp(logs.mean()))
    if logs.size < NOISE_MIN_CASES:
        # The cases of one run share its luck (its processes' cores and neighbours): with so few,
        # a uniform change cannot be told from a run that was slower throughout.
        out.change = "inconclusive"
        return out
    if np.ptp(logs) == 0:
        out.ci_low = out.ci_high = out.geomean
    else:
        interval = ttest_1samp(logs, 0.0).confidence_interval(confidence_level=level)
        out.ci_low, out.ci_high = float(np.exp(interval.low)), float(np.exp(interval.high))
    if out.geomean > 1 + threshold and out.ci_low > 1:
        out.change = "slower"
        out.flags.append(f"all {out.cases} timed cases together: {out.geomean:.2f}x slower "
                         f"(geometric mean, 95% CI {out.ci_low:.2f}-{out.ci_high:.2f})")
    elif out.geomean < 1 / (1 + threshold) and out.ci_high < 1:
        out.change = "faster"
    elif 1 / (1 + threshold) < out.ci_low and out.ci_high < 1 + threshold:
        out.change = "same"
    else:
        out.change = "inconclusive"
    return out


def _unchecked(status: Optional[str], verdict: Optional[str]) -> bool:
    """A built case with no verdict on its correctness ("skipped" or none at all)."""
    return status == Status.OK and verdict_rank(verdict) is None


def _usable_times(rows) -> np.ndarray:
    """The build times of ``rows`` that ran, as seconds a ratio can be taken of: a missing, zero,
    negative or infinite time says nothing about speed (and a zero one divides by zero).

    Rows of interleaved rounds (column ``round``, from ``continuous``) give one time per round,
    the median of its repeats: repeats of one process share its luck (the core it ran on, its
    neighbours), so the rounds, not the repeats, are the independent samples of the noise."""
    ok = rows[rows["status"] == Status.OK]
    times = pd.to_numeric(ok["time_s"], errors="coerce")
    usable = np.isfinite(times.to_numpy(float)) & (times.to_numpy(float) > 0)
    if "round" in ok.columns and ok["round"].notna().all() and ok.loc[usable, "round"].nunique() > 1:
        return times[usable].groupby(ok.loc[usable, "round"]).median().to_numpy(float)
    return times.to_numpy(float)[usable]


def _why_not_comparable(change: CaseChange, base_times: np.ndarray, new_times: np.ndarray) -> str:
    """Why a case both sides ran cannot be timed against itself; "" when it can (or need not)."""
    if change.new_status == Status.OK and not new_times.size:
        return "NEW has no usable timing (time_s missing, zero, negative or infinite)"
    if change.base_status == Status.OK and change.new_status == Status.OK and not base_times.size:
        return "BASE has no usable timing (time_s missing, zero, negative or infinite)"
    return ""


def _case_label(key: dict) -> str:
    """A case's key as compare names it (:attr:`CaseChange.name`)."""
    families = [key.get(c) if isinstance(key.get(c), str) else "" for c in results.SITE_ATTRIBUTES]
    dataset = results.dataset_label(str(key["dataset"]), *families)
    return f"{key['impl']} {dataset} n={int(float(key['n']))} seed={int(float(key['seed']))}"


def _cases_held_twice(df) -> list[dict]:
    """The cases of ``df`` (each as a dict of its key) that hold one repeat twice, or rows of
    more than one run: a case that was run twice into the same table."""
    key = [c for c in results.CASE_KEY if c in df.columns]
    twice: set[tuple] = set()
    if "repeat" in df.columns:
        numbered = df[df["repeat"].notna()]
        again = numbered.duplicated(key + ["repeat"])
        twice |= {tuple(k) for k in numbered.loc[again, key].itertuples(index=False)}
    if "run_id" in df.columns:
        runs = df[df["run_id"].notna()].groupby(key, dropna=False)["run_id"].nunique()
        twice |= {tuple(k) for k, count in runs.items() if count > 1}
    return [dict(zip(key, k)) for k in sorted(twice, key=str)]


def refuse_duplicates(df, side: str) -> None:
    """ValueError naming a case ``df`` holds twice (see :func:`_cases_held_twice`): pooling its
    two runs would judge it on both runs' repeats and hide that it was written twice."""
    twice = _cases_held_twice(df)
    if not twice:
        return
    more = f" (and {len(twice) - 1} more case(s) like it)" if len(twice) > 1 else ""
    raise ValueError(f"{side}: case {_case_label(twice[0])} is there twice (a repeat twice, or rows of two runs)"
                     f"{more}; keep one run of each case, a case run twice is not pooled")


def _counters(base_row, new_row, columns: list[str]) -> dict[str, tuple]:
    changed = {}
    for col in columns:
        a, b = base_row.get(col), new_row.get(col)
        a_missing = a is None or (isinstance(a, float) and math.isnan(a))
        b_missing = b is None or (isinstance(b, float) and math.isnan(b))
        if a_missing and b_missing:
            continue
        if a_missing != b_missing or a != b:
            changed[col[len("stat_"):]] = (None if a_missing else a, None if b_missing else b)
    return changed


def compare_frames(base_df, new_df, threshold: float = 0.10, alpha: float = 0.05,
                   seed: int = 0, history=None) -> list[CaseChange]:
    """Every case present in either table, with its flags. ``history``: earlier runs' rows
    (several ``run_id``) of the same machine, from which each case's own run-to-run noise is
    measured (:func:`case_noise`). A weighted case (``weights`` column) and a case of disks (``radii``)
    are datasets of their own (:func:`vorobench.harness.results.dataset_label`): never compared with the
    ordinary one."""
    timed: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    refuse_duplicates(base_df, "BASE")
    refuse_duplicates(new_df, "NEW")
    base_df, new_df = results.with_families_in_dataset(base_df), results.with_families_in_dataset(new_df)
    stat_cols = counter_columns(set(base_df.columns) | set(new_df.columns))
    base_groups = {k: g for k, g in base_df.groupby(KEY, sort=True)}
    new_groups = {k: g for k, g in new_df.groupby(KEY, sort=True)}
    changes = []
    for key in sorted(set(base_groups) | set(new_groups), key=lambda k: (k[0], k[1], int(k[2]), int(k[3]))):
        impl, dataset, n, s = key
        change = CaseChange(str(impl), str(dataset), int(n), int(s))
        b, m = base_groups.get(key), new_groups.get(key)
        if b is not None:
            change.base_status, change.base_verdict = _first(b, "status"), _first(b, "verdict")
        if m is not None:
            change.new_status, change.new_verdict = _first(m, "status"), _first(m, "verdict")
        if m is None:
            change.flags.append("missing in NEW")
        if b is None or m is None:
            changes.append(change)
            continue
        sb, sn = status_rank(change.base_status), status_rank(change.new_status)
        if sb == 0 and sn != 0:
            change.flags.append(f"status ok -> {change.new_status}")
        elif sb is not None and sn is not None and sn > sb:
            change.flags.append(f"status {change.base_status} -> {change.new_status}")
        rb, rn = verdict_rank(change.base_verdict), verdict_rank(change.new_verdict)
        if rb is not None and rn is not None and rn > rb:
            change.flags.append(f"verdict {change.base_verdict} -> {change.new_verdict}")
        if change.check_lost:
            change.flags.append(f"correctness not checked in NEW (BASE: {change.base_verdict})")
        tb, tn = _usable_times(b), _usable_times(m)
        change.why_not_comparable = _why_not_comparable(change, tb, tn)
        if change.why_not_comparable:
            change.flags.append(f"not comparable: {change.why_not_comparable}")
        elif tb.size and tn.size:
            timed[id(change)] = (tb, tn)
            change.ratio = float(np.median(tn) / np.median(tb))
        _compare_counters(change, b, m, stat_cols)
        changes.append(change)
    # The noise is measured before any case is decided: the spread of all cases' ratios, or a
    # case's own spread over earlier runs when that is wider.
    band = noise_band(changes)
    own = case_noise(history) if history is not None else {}
    for change in changes:
        if id(change) not in timed:
            continue
        key = (change.impl, change.dataset, change.n, change.seed)
        width, source = band, "the spread of all cases' ratios"
        if key in own and (width is None or NOISE_Z * own[key][0] > width):
            width, source = NOISE_Z * own[key][0], f"this case's spread over {own[key][1]} earlier runs"
        _timing(change, *timed[id(change)], threshold, alpha, seed, width, source)
        if change.change == "slower":
            change.flags.insert(0, f"{change.ratio:.2f}x slower (95% CI {change.ci_low:.2f}-{change.ci_high:.2f}, "
                                   f"p={change.p_value:.2g})")
    return changes


def _compare_counters(change: CaseChange, base_rows, new_rows, stat_cols: list[str]) -> None:
    """Flag ``change`` when a counter differs between the first rows that ran on each side."""
    ran_base, ran_new = base_rows[base_rows["status"] == Status.OK], new_rows[new_rows["status"] == Status.OK]
    if not stat_cols or ran_base.empty or ran_new.empty:
        return
    change.counters = _counters(ran_base.iloc[0].to_dict(), ran_new.iloc[0].to_dict(), stat_cols)
    if change.counters:
        change.flags.append("counters changed: " + ", ".join(
            f"{k} {_num(a)} -> {_num(c)}" for k, (a, c) in change.counters.items()))


#: Fewest earlier runs of a case from which its own run-to-run noise is measured.
HISTORY_MIN_RUNS = 3


def case_noise(history) -> dict[tuple, tuple[float, int]]:
    """Each case's own run-to-run noise from earlier runs: {(impl, dataset, n, seed): (standard
    deviation of the log of its per-run median times, runs)}, for cases with at least
    :data:`HISTORY_MIN_RUNS` runs. Some cases vary far more than others between runs (large
    memory-bound builds on a shared machine), which no single pair of runs can show."""
    if history is None or history.empty or "run_id" not in history.columns:
        return {}
    history = results.with_families_in_dataset(history)
    ok = history[(history["status"] == Status.OK) & history["time_s"].notna()]
    medians = ok.groupby(KEY + ["run_id"])["time_s"].median()
    out = {}
    for key, per_run in medians.groupby(level=[0, 1, 2, 3]):
        if per_run.size >= HISTORY_MIN_RUNS and (per_run > 0).all():
            out[(str(key[0]), str(key[1]), int(key[2]), int(key[3]))] = (float(np.log(per_run).std(ddof=1)),
                                                                         int(per_run.size))
    return out


def noise_band(changes: Sequence[CaseChange]) -> Optional[float]:
    """The run-to-run noise band of two runs, from all their cases' ratios
    (:func:`vorobench.harness.timing_rule.noise_half_width`); None with too few timed cases."""
    return noise_half_width([c.ratio for c in changes if c.ratio is not None])


def compare_runs(base_df, new_df, threshold: float = 0.10, alpha: float = 0.05, seed: int = 0,
                 history=None) -> RunComparison:
    """Per-case changes and the combined verdict over every case timed on both sides."""
    changes = compare_frames(base_df, new_df, threshold=threshold, alpha=alpha, seed=seed, history=history)
    timed = [c for c in changes if c.ratio is not None]
    return RunComparison(changes, overall_change(timed, threshold), threshold, alpha, noise_band(timed))


def _first(group, column: str) -> Optional[str]:
    if column not in group.columns:
        return None
    value = group[column].iloc[0]
    return None if not isinstance(value, str) else value


def _num(value) -> str:
    if value is None:
        return "none"
    if isinstance(value, float) and value.is_integer():
        return str(int(value))
    return f"{value:g}" if isinstance(value, float) else str(value)


def load_side(text: str | Path):
    """One side of a comparison: (results frame, metadata of its run or None) from a results
    file or a run store reference ``DIR@REF``. ValueError in one line for anything else."""
    if store.is_reference(str(text)):
        return store.load_reference(str(text))
    frame = results.load_checked(text)
    runs = results.read_metadata(text).get("runs", [])
    return frame, (runs[-1] if runs else None)


def relative_to(df, reference: str, side: str = "results"):
    """``df`` with each build time divided by the median time of ``reference`` on the same
    dataset, weights or radii, n and seed in the same run: a dimensionless ratio in which the machine's
    speed (and a change of it between runs) cancels. The reference's own rows and the cases it
    did not time are left out. ValueError when ``reference`` timed nothing in ``df``."""
    df = df.copy()
    for column in results.SITE_ATTRIBUTES:
        if column in df.columns:
            df[column] = df[column].fillna("").astype(str)
    # per run (a store's history holds several), per case with its weight or radius family
    key = [c for c in ("run_id", "dataset", *results.SITE_ATTRIBUTES, "n", "seed") if c in df.columns]
    times = pd.to_numeric(df["time_s"], errors="coerce")
    ran = df[(df["impl"] == reference) & (df["status"] == Status.OK) & np.isfinite(times) & (times > 0)]
    if ran.empty:
        raise ValueError(f"--relative-to {reference}: {side} has no timed case of {reference}")
    medians = ran.assign(time_s=pd.to_numeric(ran["time_s"])).groupby(key)["time_s"].median().rename("_reference_s")
    out = df[df["impl"] != reference].join(medians, on=key)
    out = out[out["_reference_s"].notna()].copy()
    out["time_s"] = pd.to_numeric(out["time_s"], errors="coerce") / out["_reference_s"]
    return out.drop(columns="_reference_s")


def compare_files(base: str | Path, new: str | Path, threshold: float = 0.10, alpha: float = 0.05,
                  seed: int = 0) -> list[CaseChange]:
    """:func:`compare_frames` on two results files or store references.

    Raises ValueError naming the file when one is empty, has no rows or is not a results table.
    """
    return compare_frames(load_side(base)[0], load_side(new)[0], threshold=threshold, alpha=alpha, seed=seed)


def store_history(base: str, base_meta: Optional[dict], new_df):
    """When BASE is a run of a store, the store's runs on BASE's machine, NEW's own run aside:
    they measure each case's run-to-run noise."""
    parsed = store.split_reference(str(base))
    if parsed is None or not base_meta or not base_meta.get("machine_id"):
        return None
    runs = store.Store(parsed[0]).runs(machine_id=base_meta["machine_id"])
    new_ids = set(new_df["run_id"].astype(str)) if "run_id" in new_df.columns else set()
    ids = [r for r in runs["run_id"] if r not in new_ids]
    return store.Store(parsed[0]).results(ids) if len(ids) >= HISTORY_MIN_RUNS else None


def machine_warning(base_meta: Optional[dict], new_meta: Optional[dict]) -> Optional[str]:
    def machine(meta):
        if not meta:
            return None
        return meta.get("machine_id") or (meta.get("hostname"), meta.get("cpu"))

    a, b = machine(base_meta), machine(new_meta)
    if a and b and a != b:
        def name(meta):
            return f"{meta.get('hostname')} ({meta.get('cpu')})"
        return (f"BASE ran on {name(base_meta)}, NEW on {name(new_meta)}: times are not comparable across "
                "machines; counters and verdicts are.")
    return None
