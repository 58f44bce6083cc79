"""Summaries of a results table: per case, per size, fitted growth exponents, ratios, verdicts.

Pure pandas/numpy, shared by the report (figures and text) and the regression compare.
Sizes are measured in distinct sites (``n_sites``), the input the build actually receives
(grids round n up, duplicates shrink it).

**The complexity check** (:func:`complexity_check`). A fitted exponent (the least-squares
slope of log time against log n, :func:`fit_exponents`) is compared with the implementation's
declared complexity ``O(n^a log^b n)`` (:func:`parse_complexity`; a trailing "expected" is
ignored). The declared complexity's own exponent over the fitted sizes n_min..n_max is the slope
of the chord of log(n^a (ln n)^b) against log n (:func:`declared_exponent`):

    a + b * ln(ln n_max / ln n_min) / ln(n_max / n_min)

so n log n counts as about n^1.12 over 1k..30k, not as n^1. A fit is a **mismatch** when its
exponent exceeds that by more than :data:`MISMATCH_TOLERANCE` (0.3): the measured time then
grows at least n^0.3 faster than declared, a factor 2.8 over a 30x range of sizes, which is more
than timing noise on a loaded machine shifts a slope fitted over 3 or more sizes. A fit below
the declared exponent is no mismatch (O is an upper bound); an unreadable declaration is never
one.
"""

from __future__ import annotations

import math
import re
from typing import Callable, Mapping, Optional, Union

import numpy as np
import pandas as pd

from vorobench.judge.outcomes import Status, counter_columns, timing_columns, verdict_rank

__all__ = [
    "mixed_hosts_note",
    "loglog_fit",
    "worst_verdict",
    "case_table",
    "size_table",
    "fit_exponents",
    "r2_text",
    "speed_ratios",
    "correctness_matrix",
    "failures",
    "passed",
    "MISMATCH_TOLERANCE",
    "parse_complexity",
    "declared_exponent",
    "complexity_check",
    "complexity_mismatches",
    "case_repeats",
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
    certificate = {"certificate": ("certificate", "first")} if "certificate" in df.columns else {}
    out = grouped.agg(
        status=("status", "first"),
        verdict=("verdict", "first"),
        **certificate,
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
    """One row per (impl, dataset, n) over the successful repeats of every seed: the median time,
    its quartiles and extremes over the repeats, memory, and time per n log2 n in nanoseconds."""
    ok = df[df["status"] == Status.OK]
    if ok.empty:
        return pd.DataFrame(columns=["impl", "dataset", "n", "n_sites", "time_s", "time_q1_s", "time_q3_s",
                                     "time_min_s", "time_max_s", "seeds", "mem_mb", "peak_rss_mb", "repeats",
                                     "ns_per_nlogn"])
    grouped = ok.groupby(["impl", "dataset", "n"], sort=True)
    out = grouped.agg(
        n_sites=("n_sites", "median"),
        time_s=("time_s", "median"),
        time_q1_s=("time_s", lambda s: s.quantile(0.25)),
        time_q3_s=("time_s", lambda s: s.quantile(0.75)),
        time_min_s=("time_s", "min"),
        time_max_s=("time_s", "max"),
        seeds=("seed", "nunique"),
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


def case_repeats(df: pd.DataFrame) -> list[dict]:
    """Every case (impl, dataset, n, seed) with its repeats, for a drill-down: the identity,
    status, verdict and its detail, error, the successful repeats' build times (``times``, by
    repeat) and timings of parts (``phases``: column -> list aligned with ``times``), summary
    statistics of ``times``, and the counters (``stat_*``, the first value recorded, as ints)."""
    counters = counter_columns(df.columns)
    phases = [c for c in timing_columns(df.columns) if c != "time_s"]
    out = []
    for key, g in df.groupby(["impl", "dataset", "n", "seed"], sort=True, dropna=False):
        impl, dataset, n, seed = key
        first = g.iloc[0]
        ok = g[g["status"] == Status.OK] if "status" in g else g
        if "repeat" in ok.columns:
            ok = ok.sort_values("repeat", kind="stable")
        times = pd.to_numeric(ok["time_s"], errors="coerce") if "time_s" in ok else pd.Series(dtype=float)
        keep = times.notna().to_numpy()
        ok, times = ok[keep], times[keep].to_numpy(float)

        def text(column: str) -> str:
            value = first.get(column) if column in g.columns else None
            return "" if value is None or (isinstance(value, float) and value != value) else str(value)

        case = {
            "impl": str(impl), "dataset": str(dataset), "n": int(n),
            "seed": int(seed) if isinstance(seed, (int, np.integer)) or (isinstance(seed, float) and seed == seed)
            else str(seed),
            "n_sites": int(first["n_sites"]) if "n_sites" in g and pd.notna(first["n_sites"]) else None,
            "status": text("status"), "verdict": text("verdict"), "certificate": text("certificate"),
            "detail": text("verdict_detail"),
            "error": text("error"), "phase": text("phase"),
            "repeat_ids": [int(r) if pd.notna(r) else i for i, r in
                           enumerate(ok["repeat"] if "repeat" in ok else range(len(ok)))],
            "times": [float(t) for t in times],
            "phases": {c: [float(v) if pd.notna(v) else None for v in ok[c]] for c in phases if ok[c].notna().any()},
            "counters": {c: int(g[c].dropna().iloc[0]) for c in counters if g[c].notna().any()},
        }
        if times.size:
            q1, median, q3 = np.quantile(times, [0.25, 0.5, 0.75])
            case.update(median_s=float(median), min_s=float(times.min()), max_s=float(times.max()),
                        q1_s=float(q1), q3_s=float(q3))
        else:
            case.update(median_s=None, min_s=None, max_s=None, q1_s=None, q3_s=None)
        out.append(case)
    return out


def loglog_fit(sizes, seconds) -> tuple[float, float]:
    """(slope, intercept) of the least-squares line through (log n, log t): the slope is the
    fitted growth exponent (t ~ n**slope). The one fit of the project: reports, the runner's
    budget extrapolation and the benchmark scripts use it."""
    x, y = np.log(np.asarray(sizes, dtype=float)), np.log(np.asarray(seconds, dtype=float))
    slope, intercept = np.polyfit(x, y, 1)
    return float(slope), float(intercept)


def fit_exponents(sizes: pd.DataFrame, min_sites: int = FIT_MIN_SITES) -> pd.DataFrame:
    """Slope of log(time) against log(n) per (impl, dataset), with R^2 (NaN from fewer than three
    sizes, which any line fits) and the n range used.

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
        slope, intercept = loglog_fit(g["n_sites"], g["time_s"])
        resid = y - (slope * x + intercept)
        total = float(np.sum((y - y.mean()) ** 2))
        # Two sizes always fit a line exactly: their R^2 (1) would say nothing, so it is NaN.
        r2 = 1.0 - float(np.sum(resid ** 2)) / total if total > 0 and g["n_sites"].nunique() >= 3 else float("nan")
        rows.append({"impl": impl, "dataset": dataset, "exponent": float(slope), "r2": r2,
                     "n_min": int(g["n_sites"].min()), "n_max": int(g["n_sites"].max()),
                     "points": int(len(g))})
    return pd.DataFrame(rows, columns=["impl", "dataset", "exponent", "r2", "n_min", "n_max", "points"])


def r2_text(r2: float, bare: bool = False) -> str:
    """R² of a fit, or what it is when it cannot be measured (two sizes fit any line)."""
    if r2 == r2:
        return f"{r2:.3f}" if bare else f"R² {r2:.3f}"
    return "n/a (2 sizes)" if bare else "R² n/a: two sizes"


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
    bad_status = ~cases["status"].isin([Status.OK, Status.UNSUPPORTED, Status.SKIPPED])
    bad_verdict = pd.Series([passed(v, p) is False for v, p in zip(cases["verdict"], cases["check_passed"])],
                            index=cases.index, dtype=bool)
    return cases[bad_status | bad_verdict]


def mixed_hosts_note(df: pd.DataFrame) -> Optional[str]:
    """A warning when the timed rows come from several hosts (a Dask run): times and ratios
    then compare machines as well as implementations."""
    if "host" not in df.columns:
        return None
    hosts = sorted({str(h) for h in df.loc[df["status"] == Status.OK, "host"].dropna() if str(h)})
    if len(hosts) < 2:
        return None
    return (f"WARNING: the timings come from {len(hosts)} hosts ({', '.join(hosts[:6])}"
            f"{', ...' if len(hosts) > 6 else ''}); times and speed ratios mix machines. For fair ratios "
            f"run on one host, or report each host's rows separately (the `host` column).")


# ------------------------------------------------------------------------------ complexity check

#: A fitted exponent above the declared one by more than this is a mismatch (see the module docstring).
MISMATCH_TOLERANCE = 0.3

_EXPONENT = r"(?:\d+(?:\.\d+)?|\(\s*\d+(?:\.\d+)?\s*/\s*\d+(?:\.\d+)?\s*\))"
_FACTOR = re.compile(
    r"\s*(?:"
    rf"(?P<log>log(?:_?2)?|lg|ln)(?:\s*\^\s*(?P<logpow>{_EXPONENT}))?\s*(?:\(\s*n\s*\)|n)"   # log n, log^2(n)
    r"|(?P<sqrt>sqrt\s*\(\s*n\s*\)|sqrt\s*n|\u221an)"                                       # sqrt(n), \u221an
    rf"|n(?:\s*\^\s*(?P<pow>{_EXPONENT})|(?P<sup>[\u00b2\u00b3]))?"                               # n, n^2, n^(4/3), n\u00b2
    r"|(?P<one>1)"
    r")\s*[*\u00b7]?")


def _number(text: str) -> float:
    text = text.strip().strip("()")
    if "/" in text:
        num, den = text.split("/")
        return float(num) / float(den)
    return float(text)


def parse_complexity(text: object) -> Optional[tuple[float, float]]:
    """``O(n^a log^b n)`` as ``(a, b)``: "O(n log n)" -> (1, 1), "O(n^(4/3)) expected" -> (4/3, 0).

    None when ``text`` is not a product of powers of n and of log n inside ``O(...)``.
    """
    if not isinstance(text, str):
        return None
    match = re.fullmatch(r"\s*O\s*\((?P<body>.*)\)\s*(?:expected|amortized|average|worst[- ]case)?\s*",
                         text.strip(), flags=re.IGNORECASE)
    if not match:
        return None
    body, pos, a, b, found = match.group("body"), 0, 0.0, 0.0, False
    while pos < len(body):
        m = _FACTOR.match(body, pos)
        if not m or m.end() == pos:
            return None
        if m.group("log"):
            b += _number(m.group("logpow")) if m.group("logpow") else 1.0
        elif m.group("sqrt"):
            a += 0.5
        elif m.group("one"):
            pass
        elif m.group("sup"):
            a += 2.0 if m.group("sup") == "\u00b2" else 3.0
        else:
            a += _number(m.group("pow")) if m.group("pow") else 1.0
        found, pos = True, m.end()
    return (a, b) if found else None


def declared_exponent(complexity: object, n_min: float, n_max: float) -> float:
    """The exponent a declared complexity ``O(n^a log^b n)`` shows over sizes n_min..n_max: the
    slope of the chord of log(n^a (ln n)^b) against log n, or the local slope a + b / ln n when
    n_min == n_max; NaN when the declaration cannot be read."""
    parsed = parse_complexity(complexity)
    if parsed is None or not (n_min > 1 and n_max > 1):
        return float("nan")
    a, b = parsed
    lo, hi = float(min(n_min, n_max)), float(max(n_min, n_max))
    if b == 0:
        return a
    if hi / lo < 1 + 1e-9:
        return a + b / math.log(lo)
    return a + b * math.log(math.log(hi) / math.log(lo)) / math.log(hi / lo)


_CHECK_COLUMNS = ["impl", "dataset", "exponent", "r2", "n_min", "n_max", "points", "declared",
                  "declared_exponent", "excess", "finding", "mismatch"]


def complexity_check(exponents: pd.DataFrame,
                     declared: Union[Mapping[str, object], Callable[[str], object]],
                     tolerance: float = MISMATCH_TOLERANCE) -> pd.DataFrame:
    """Each fit of :func:`fit_exponents` against its implementation's declared complexity.

    ``declared`` maps an implementation to its complexity text (a mapping or a function; a
    missing or unreadable one gives finding "unknown"). Adds the columns ``declared``,
    ``declared_exponent`` (over the fit's own sizes), ``excess`` (fitted minus declared),
    ``finding`` ("above": mismatch, "as declared", "below", "unknown") and ``mismatch``
    (excess > ``tolerance``).
    """
    lookup = declared if callable(declared) else (lambda name: declared.get(name))
    rows = []
    for r in exponents.itertuples(index=False):
        text = lookup(r.impl)
        text = text if isinstance(text, str) else None
        expected = declared_exponent(text, r.n_min, r.n_max)
        excess = float(r.exponent) - expected
        if not math.isfinite(expected):
            finding = "unknown"
        elif excess > tolerance:
            finding = "above"
        elif excess < -tolerance:
            finding = "below"
        else:
            finding = "as declared"
        rows.append({**r._asdict(), "declared": text, "declared_exponent": expected, "excess": excess,
                     "finding": finding, "mismatch": finding == "above"})
    out = pd.DataFrame(rows, columns=_CHECK_COLUMNS)
    out["mismatch"] = out["mismatch"].astype(bool)
    return out


def complexity_mismatches(check: pd.DataFrame) -> pd.DataFrame:
    """The mismatches of :func:`complexity_check`, largest excess first."""
    bad = check[check["mismatch"].astype(bool)]
    return bad.sort_values(["excess", "impl", "dataset"], ascending=[False, True, True]).reset_index(drop=True)
