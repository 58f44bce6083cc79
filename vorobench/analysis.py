"""Summaries of a results table: per case, per size, fitted growth exponents, ratios, verdicts.

Pure pandas/numpy, shared by the report (figures and text) and the regression compare.
Sizes are measured in distinct sites (``n_sites``), the input the build actually receives
(grids round n up, duplicates shrink it).
"""

from __future__ import annotations

from typing import Optional

import numpy as np
import pandas as pd

from vorobench.schema import VERDICT_RANK, verdict_rank

__all__ = [
    "VERDICT_RANK",
    "mixed_hosts_note",
    "verdict_rank",
    "worst_verdict",
    "case_table",
    "size_table",
    "fit_exponents",
    "speed_ratios",
    "correctness_matrix",
    "failures",
    "passed",
]

#: Fits of log time against log n use sizes from here up (smaller ones measure overheads).
FIT_MIN_SITES = 1000


def worst_verdict(verdicts) -> Optional[str]:
    """The worst ranked verdict of a collection (None if none of them says anything)."""
    ranked = [(verdict_rank(v), str(v)) for v in verdicts if verdict_rank(v) is not None]
    if not ranked:
        present = [str(v) for v in verdicts if isinstance(v, str) and v]
        return present[0] if present else None
    return max(ranked)[1]


def case_table(df: pd.DataFrame) -> pd.DataFrame:
    """One row per case (impl, dataset, n, seed): status, verdict, median time and memory."""
    keys = ["impl", "dataset", "n", "seed"]
    grouped = df.groupby(keys, sort=True, dropna=False)
    out = grouped.agg(
        status=("status", "first"),
        verdict=("verdict", "first"),
        check_passed=("check_passed", "first"),
        time_s=("time_s", "median"),
        time_min_s=("time_s", "min"),
        repeats=("time_s", "count"),
        n_sites=("n_sites", "first"),
        mem_mb=("mem_mb", "median"),
        peak_rss_mb=("peak_rss_mb", "max"),
        warmup_s=("warmup_s", "first"),
        error=("error", "first"),
        phase=("phase", "first"),
    ).reset_index()
    return out


def size_table(df: pd.DataFrame) -> pd.DataFrame:
    """One row per (impl, dataset, n) over the successful repeats of every seed."""
    ok = df[df["status"] == "ok"]
    if ok.empty:
        return pd.DataFrame(columns=["impl", "dataset", "n", "n_sites", "time_s", "time_q1_s",
                                     "time_q3_s", "mem_mb", "peak_rss_mb", "repeats"])
    grouped = ok.groupby(["impl", "dataset", "n"], sort=True)
    out = grouped.agg(
        n_sites=("n_sites", "median"),
        time_s=("time_s", "median"),
        time_q1_s=("time_s", lambda s: s.quantile(0.25)),
        time_q3_s=("time_s", lambda s: s.quantile(0.75)),
        # The first build at a size grows the heap; later ones reuse freed memory, so the
        # largest rise over the repeats is the build's peak.
        mem_mb=("mem_mb", "max"),
        peak_rss_mb=("peak_rss_mb", "max"),
        repeats=("time_s", "count"),
    ).reset_index()
    # Sizes past a dataset's cap give the same input again: keep the first, one point per input size.
    out = out.sort_values("n").drop_duplicates(["impl", "dataset", "n_sites"], keep="first")
    out = out.sort_values(["impl", "dataset", "n"]).reset_index(drop=True)
    out["ns_per_nlogn"] = out["time_s"] * 1e9 / (out["n_sites"] * np.log2(np.maximum(out["n_sites"], 2)))
    return out


def fit_exponents(sizes: pd.DataFrame, min_sites: int = FIT_MIN_SITES) -> pd.DataFrame:
    """Slope of log(time) against log(n) per (impl, dataset), with R^2 and the n range used.

    Sizes below ``min_sites`` are left out when at least three larger ones remain, since
    there start-up overheads, not growth, dominate.
    """
    rows = []
    for (impl, dataset), g in sizes.groupby(["impl", "dataset"], sort=True):
        g = g[(g["n_sites"] > 1) & (g["time_s"] > 0)].sort_values("n_sites")
        if (g["n_sites"] >= min_sites).sum() >= 3:
            g = g[g["n_sites"] >= min_sites]
        if g["n_sites"].nunique() < 2:
            continue
        x, y = np.log(g["n_sites"].to_numpy(float)), np.log(g["time_s"].to_numpy(float))
        slope, intercept = np.polyfit(x, y, 1)
        resid = y - (slope * x + intercept)
        total = float(np.sum((y - y.mean()) ** 2))
        r2 = 1.0 - float(np.sum(resid ** 2)) / total if total > 0 else float("nan")
        rows.append({"impl": impl, "dataset": dataset, "exponent": float(slope), "r2": r2,
                     "n_min": int(g["n_sites"].min()), "n_max": int(g["n_sites"].max()),
                     "points": int(len(g))})
    return pd.DataFrame(rows, columns=["impl", "dataset", "exponent", "r2", "n_min", "n_max", "points"])


def speed_ratios(sizes: pd.DataFrame, reference: str) -> pd.DataFrame:
    """time(impl) / time(reference) per (impl, dataset, n): above 1 = slower than the reference."""
    ref = sizes[sizes["impl"] == reference][["dataset", "n", "time_s"]].rename(columns={"time_s": "ref_time_s"})
    merged = sizes[sizes["impl"] != reference].merge(ref, on=["dataset", "n"], how="inner")
    merged["ratio"] = merged["time_s"] / merged["ref_time_s"]
    return merged[["impl", "dataset", "n", "n_sites", "time_s", "ref_time_s", "ratio"]]


def passed(verdict: object, check_passed: object = None) -> Optional[bool]:
    """Did a case pass its check? The cross-validation's own judgement when recorded (a
    difference blamed on the reference passes), else exact/within tolerance/certified."""
    if isinstance(check_passed, (bool, np.bool_)):
        return bool(check_passed)
    if isinstance(check_passed, str) and check_passed in ("True", "False"):
        return check_passed == "True"
    rank = verdict_rank(verdict)
    return None if rank is None else rank <= 1


def correctness_matrix(cases: pd.DataFrame) -> pd.DataFrame:
    """Worst verdict and counts per (impl, dataset): columns worst, cases, checked, good (passed)."""
    rows = []
    for (impl, dataset), g in cases.groupby(["impl", "dataset"], sort=True):
        verdicts = g["verdict"].tolist()
        outcomes = [passed(v, p) for v, p in zip(verdicts, g["check_passed"])]
        good = sum(1 for o in outcomes if o)
        checked = sum(1 for o in outcomes if o is not None)
        rows.append({"impl": impl, "dataset": dataset, "worst": worst_verdict(verdicts),
                     "cases": len(g), "checked": checked, "good": good})
    return pd.DataFrame(rows, columns=["impl", "dataset", "worst", "cases", "checked", "good"])


def failures(cases: pd.DataFrame) -> pd.DataFrame:
    """Cases that did not run to completion (crashed, timeout, oom, error) or were not certified."""
    bad_status = ~cases["status"].isin(["ok", "unsupported", "skipped"])
    bad_verdict = pd.Series([passed(v, p) is False for v, p in zip(cases["verdict"], cases["check_passed"])],
                            index=cases.index, dtype=bool)
    return cases[bad_status | bad_verdict]


def mixed_hosts_note(df: pd.DataFrame) -> Optional[str]:
    """A warning when the timed rows come from several hosts (a Dask run): times and ratios
    then compare machines as well as implementations."""
    if "host" not in df.columns:
        return None
    hosts = sorted({str(h) for h in df.loc[df["status"] == "ok", "host"].dropna() if str(h)})
    if len(hosts) < 2:
        return None
    return (f"WARNING: the timings come from {len(hosts)} hosts ({', '.join(hosts[:6])}"
            f"{', ...' if len(hosts) > 6 else ''}); times and speed ratios mix machines. For fair ratios "
            f"run on one host, or report each host's rows separately (the `host` column).")
