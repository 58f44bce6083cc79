"""Compare two benchmark results case by case; flag slowdowns, counter changes and lost correctness.

    vorobench compare BASE NEW [--threshold 0.10]

Per case (implementation, dataset, n, seed): the ratio of median times NEW / BASE with a
bootstrap confidence interval, and a one-sided Mann-Whitney U test. A slowdown is flagged when
the ratio exceeds 1 + threshold *and* is statistically clear (the interval lies above 1 and,
when the repeats allow it, p < alpha). Any change of a ``stat_*`` counter is flagged (counters do
not depend on the machine, so they gate regressions without noise), as is any case that got a
worse verdict or stopped running, and any case of BASE that NEW lacks (a run that lost cases
must not pass for having fewer to compare). Exit status 1 when anything is flagged, else 0;
2 when a file is not a results table with at least one case, or an option makes no sense.
"""

from __future__ import annotations

import argparse
import json
import math
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

__all__ = ["add_arguments", "run", "CaseChange", "compare_frames", "compare_files", "bootstrap_ratio_ci",
           "slowdown_p_value"]

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
    ratio: Optional[float] = None
    ci_low: Optional[float] = None
    ci_high: Optional[float] = None
    p_value: Optional[float] = None
    change: str = ""                     # "slower", "faster", "same", "" (no timing on one side)
    counters: dict[str, tuple] = field(default_factory=dict)
    flags: list[str] = field(default_factory=list)

    @property
    def flagged(self) -> bool:
        return bool(self.flags)


def bootstrap_ratio_ci(base: Sequence[float], new: Sequence[float], rng: np.random.Generator,
                       resamples: int = 2000, level: float = 0.95) -> tuple[float, float]:
    """Percentile bootstrap interval of median(new) / median(base), resampling each side."""
    b, m = np.asarray(base, float), np.asarray(new, float)
    rb = np.median(b[rng.integers(0, b.size, size=(resamples, b.size))], axis=1)
    rn = np.median(m[rng.integers(0, m.size, size=(resamples, m.size))], axis=1)
    ratios = rn / rb
    tail = 50.0 * (1.0 - level)
    lo, hi = np.percentile(ratios, [tail, 100.0 - tail])
    return float(lo), float(hi)


def slowdown_p_value(base: Sequence[float], new: Sequence[float]) -> Optional[float]:
    """One-sided Mann-Whitney U p-value for "NEW is slower than BASE" (None below 2 samples each)."""
    from scipy.stats import mannwhitneyu

    if len(base) < 2 or len(new) < 2:
        return None
    return float(mannwhitneyu(new, base, alternative="greater").pvalue)


def _speedup_p_value(base: Sequence[float], new: Sequence[float]) -> Optional[float]:
    return slowdown_p_value(new, base)


def _smallest_p(n1: int, n2: int) -> float:
    """The smallest p-value a one-sided rank test can give with these sample sizes."""
    return 1.0 / math.comb(n1 + n2, n1)


def _timing(change: CaseChange, base: np.ndarray, new: np.ndarray, threshold: float, alpha: float,
            rng: np.random.Generator) -> None:
    change.base_median_s, change.new_median_s = float(np.median(base)), float(np.median(new))
    change.ratio = change.new_median_s / change.base_median_s
    if base.size >= 2 and new.size >= 2:
        change.ci_low, change.ci_high = bootstrap_ratio_ci(base, new, rng)
        testable = _smallest_p(base.size, new.size) < alpha
        p_slow = slowdown_p_value(base, new)
        p_fast = _speedup_p_value(base, new)
        clear_slow = change.ci_low > 1.0 and (not testable or p_slow < alpha)
        clear_fast = change.ci_high < 1.0 and (not testable or p_fast < alpha)
        change.p_value = p_slow if change.ratio >= 1 else p_fast
    else:                                # one repeat: nothing to test, the ratio has to do
        clear_slow = clear_fast = True
    if change.ratio > 1.0 + threshold and clear_slow:
        change.change = "slower"
        ci = f", 95% CI {change.ci_low:.2f}-{change.ci_high:.2f}" if change.ci_low is not None else " (1 repeat)"
        change.flags.append(f"{change.ratio:.2f}x slower{ci}")
    elif change.ratio < 1.0 / (1.0 + threshold) and clear_fast:
        change.change = "faster"
    else:
        change.change = "same"


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
                   seed: int = 0) -> list[CaseChange]:
    """Every case present in either table, with its flags."""
    from vorobench.analysis import verdict_rank

    rng = np.random.default_rng(seed)
    stat_cols = sorted({c for c in list(base_df.columns) + list(new_df.columns) if c.startswith("stat_")})
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
        if change.base_status == "ok" and change.new_status != "ok":
            change.flags.append(f"status ok -> {change.new_status}")
        rb, rn = verdict_rank(change.base_verdict), verdict_rank(change.new_verdict)
        if rb is not None and rn is not None and rn > rb:
            change.flags.append(f"verdict {change.base_verdict} -> {change.new_verdict}")
        tb = b.loc[b["status"] == "ok", "time_s"].dropna().to_numpy(float)
        tn = m.loc[m["status"] == "ok", "time_s"].dropna().to_numpy(float)
        if tb.size and tn.size:
            _timing(change, tb, tn, threshold, alpha, rng)
            if stat_cols:
                base_row = b[b["status"] == "ok"].iloc[0].to_dict()
                new_row = m[m["status"] == "ok"].iloc[0].to_dict()
                change.counters = _counters(base_row, new_row, stat_cols)
                if change.counters:
                    change.flags.append("counters changed: " + ", ".join(
                        f"{k} {_num(a)} -> {_num(c)}" for k, (a, c) in change.counters.items()))
        changes.append(change)
    return changes


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


def compare_files(base: str | Path, new: str | Path, threshold: float = 0.10, alpha: float = 0.05,
                  seed: int = 0) -> list[CaseChange]:
    """:func:`compare_frames` on two results files (CSV or Parquet).

    Raises ValueError naming the file when one is empty, has no rows or is not a results table.
    """
    from vorobench.results import load_checked

    return compare_frames(load_checked(base), load_checked(new), threshold=threshold, alpha=alpha, seed=seed)


def _machine_warning(base: Path, new: Path) -> Optional[str]:
    from vorobench.results import read_metadata

    def machine(path):
        runs = read_metadata(path).get("runs", [])
        return (runs[-1].get("hostname"), runs[-1].get("cpu")) if runs else None

    a, b = machine(base), machine(new)
    if a and b and a != b:
        return (f"BASE ran on {a[0]} ({a[1]}), NEW on {b[0]} ({b[1]}): times are not comparable across "
                "machines; counters and verdicts are.")
    return None


# ------------------------------------------------------------------------------ CLI

def add_arguments(p: argparse.ArgumentParser) -> None:
    from vorobench.cli_args import fraction, non_negative_int, positive_float

    p.add_argument("base", help="baseline results file (.csv or .parquet)")
    p.add_argument("new", help="new results file")
    p.add_argument("--threshold", type=positive_float, default=0.10,
                   help="flag slowdowns above this fraction, > 0 (default 0.10 = 10%%)")
    p.add_argument("--alpha", type=fraction, default=0.05,
                   help="significance level, between 0 and 1 (default 0.05)")
    p.add_argument("--seed", type=non_negative_int, default=0, help="bootstrap seed (default 0)")
    p.add_argument("--only-changes", action="store_true", help="show only flagged or changed cases")
    p.add_argument("--json", default=None, help="also write every comparison to this JSON file")


def _fmt_s(x: Optional[float]) -> str:
    if x is None:
        return "-"
    return f"{x * 1e3:.3g} ms" if x < 1 else f"{x:.3g} s"


#: Lost cases listed by name; the rest are counted.
_MISSING_LISTED = 5


def _print_missing(console, missing: list[CaseChange]) -> None:
    console.print(f"[bold red]NEW lacks {len(missing)} case(s) that BASE has[/bold red]:")
    for c in missing[:_MISSING_LISTED]:
        console.print(f"  {c.impl} {c.dataset} n={c.n} seed={c.seed}", markup=False, highlight=False)
    if len(missing) > _MISSING_LISTED:
        console.print(f"  and {len(missing) - _MISSING_LISTED} more")


def run(args: argparse.Namespace) -> int:
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    changes = compare_files(args.base, args.new, threshold=args.threshold, alpha=args.alpha, seed=args.seed)
    console = Console()
    if not console.is_terminal:
        console = Console(width=max(console.width, 140))     # logs (CI) are wide, keep rows on one line
    warning = _machine_warning(Path(args.base), Path(args.new))
    if warning:
        console.print(f"[yellow]warning[/yellow]: {warning}")
    table = Table(title=f"{args.new} vs {args.base} (threshold {args.threshold:.0%})")
    table.add_column("case", no_wrap=True)
    for col in ("base", "new", "ratio", "95% CI", "p"):
        table.add_column(col, justify="right", no_wrap=True)
    table.add_column("verdict")
    table.add_column("flags", overflow="fold")
    shown = 0
    for c in changes:
        notable = c.flagged or c.change in ("slower", "faster") or c.base_status is None or c.new_status is None
        if args.only_changes and not notable:
            continue
        shown += 1
        colour = {"slower": "red", "faster": "green"}.get(c.change, "")
        ratio = f"{c.ratio:.3f}" if c.ratio is not None else "-"
        if colour:
            ratio = f"[{colour}]{ratio}[/{colour}]"
        ci = f"{c.ci_low:.2f}-{c.ci_high:.2f}" if c.ci_low is not None else "-"
        p = f"{c.p_value:.3g}" if c.p_value is not None else "-"
        if c.base_status is None:
            verdict = f"only in NEW ({c.new_status})"
        elif c.new_status is None:
            verdict = f"only in BASE ({c.base_status})"
        elif c.base_verdict == c.new_verdict:
            verdict = "not checked" if c.new_verdict == "skipped" and c.new_status == "ok" else str(
                c.new_verdict or c.new_status)
        else:
            verdict = f"{c.base_verdict} -> {c.new_verdict}"
        flags = "; ".join(c.flags)
        table.add_row(f"{c.impl} {c.dataset} n={c.n} s={c.seed}", _fmt_s(c.base_median_s),
                      _fmt_s(c.new_median_s), ratio, ci, p, verdict,
                      f"[bold red]{flags}[/bold red]" if flags else "")
    if shown:
        console.print(table)
    missing = [c for c in changes if c.new_status is None]
    flagged = [c for c in changes if c.flagged and c.new_status is not None]
    compared = sum(1 for c in changes if c.base_status is not None and c.new_status is not None)
    if args.json:
        Path(args.json).write_text(json.dumps([asdict(c) | {"flagged": c.flagged} for c in changes],
                                              indent=2, default=str) + "\n")
    if not compared:
        console.print(f"[bold red]no case in common[/bold red]: {escape(args.new)} has none of the cases of "
                      f"{escape(args.base)}")
    if flagged:
        console.print(f"[bold red]{len(flagged)} of {compared} compared case(s) flagged[/bold red]")
    if missing:
        _print_missing(console, missing)
    if flagged or missing:
        return 1
    faster = sum(1 for c in changes if c.change == "faster")
    console.print(f"[green]no regression[/green] in {compared} compared case(s)"
                  + (f"; {faster} clearly faster" if faster else ""))
    return 0
