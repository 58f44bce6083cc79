"""Figures plus a Markdown report and a self-contained interactive HTML page from a results file.

The command line is :mod:`vorobench.cli.report`; its help text describes the behaviour."""

from __future__ import annotations

import math
import re
import shlex
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from typing import Optional

import numpy as np
import pandas as pd

import impls
from vorobench.harness import analysis, figures
from vorobench.harness.analysis import (
    FIT_MIN_SITES,
    MISMATCH_TOLERANCE,
    complexity_check,
    complexity_mismatches,
    failures,
    mixed_hosts_note,
    r2_text,
)
from vorobench.harness.markdown_text import one_line, text
from vorobench.harness.case_figures import plot_disk_case, plot_power_case
from vorobench.harness.report_html import PageInput, plotly_styles, render
from vorobench.harness.results import load_checked, metadata_path, read_metadata, with_families_in_dataset
from vorobench.harness.units import factor_text, percent_text, seconds_text, size_text
from vorobench.judge.outcomes import CertificateLevel, Status, Verdict

__all__ = ["write_report", "Report", "reading", "busy_machine_note"]

FIGURES = {
    "time": "time_vs_n.png",
    "nlogn": "time_per_nlogn.png",
    "ratio": "speed_ratio.png",
    "memory": "memory_vs_n.png",
    "correctness": "correctness.png",
    "power": "power_diagram.png",
    "disks": "disks_diagram.png",
}


@dataclass
class Report:
    """Where a written report is."""

    folder: Path
    markdown: Path
    html: Path
    figures: dict[str, Path] = field(default_factory=dict)


# ------------------------------------------------------------------------------ formatting

_one_line, _text = one_line, text     # results text as Markdown (vorobench.harness.markdown_text)


def certificate_tally(cases: pd.DataFrame) -> str:
    """"12 certified, 3 certified within tolerance": the certificate levels of ``cases`` (from the
    ``certificate`` column; older results without it count their ``certified`` verdicts)."""
    if "certificate" in cases.columns and cases["certificate"].fillna("").astype(str).str.len().any():
        levels = cases["certificate"].fillna("").astype(str)
    else:
        levels = cases["verdict"].map(lambda v: CertificateLevel.CERTIFIED.value if v == Verdict.CERTIFIED else "")
    tally = levels[levels != ""].value_counts()
    order = [level.value for level in CertificateLevel]
    return ", ".join(f"{int(tally[k])} {k.replace('_', ' ')}" for k in order if k in tally) or "none certified"


def _code(value: object) -> str:
    """A value as a Markdown code span, whatever backticks it holds (the fence is longer)."""
    text = _one_line(value)
    fence = "`" * (max((len(run) for run in re.findall(r"`+", text)), default=0) + 1)
    pad = " " if text.startswith("`") or text.endswith("`") else ""
    return f"{fence}{pad}{text}{pad}{fence}"


def _md_table(header: list[str], rows: list[list[object]], align: Optional[str] = None) -> str:
    """A pipe table; cells are Markdown already (see :func:`_text`), pipes in them are escaped here."""
    align = align or "l" * len(header)
    marks = {"l": "---", "r": "--:", "c": ":-:"}
    lines = ["| " + " | ".join(header) + " |", "|" + "|".join(marks[a] for a in align) + "|"]
    for r in rows:
        lines.append("| " + " | ".join(_one_line(c).replace("|", "\\|") for c in r) + " |")
    return "\n".join(lines)


def _complexity(name: str) -> Optional[str]:
    """The complexity built-in ``name`` declares; None for anything else (a plugin or an entry
    point is never imported to find it: the run's metadata records what it declared)."""
    if not impls.is_builtin(name):
        return None
    try:
        return impls.builtin(name).complexity
    except Exception:  # an implementation that is not installed here is still reported
        return None


def _declared_complexity(name: str, recorded: dict) -> Optional[str]:
    """The complexity ``name`` declared when the run was made (``recorded``: its metadata's
    declarations), else :func:`_complexity`."""
    found = recorded.get(name)
    if isinstance(found, dict) and isinstance(found.get("complexity"), str):
        return found["complexity"]
    return _complexity(name)


def recorded_declarations(meta: dict) -> dict:
    """name -> declaration, as the runs of a results file pinned them (the latest run wins)."""
    out: dict = {}
    for run in meta.get("runs", []):
        if isinstance(run.get("declarations"), dict):
            out.update(run["declarations"])
    return out


# ------------------------------------------------------------------------------ reading

def reading(cases, sizes, exponents, ratios, reference: str, check=None, repeats=None) -> list[str]:
    """Bullet points that say what the numbers mean: who is fastest, how noisy the timings are,
    how things grow against their declared complexity, what failed. ``check`` is
    :func:`vorobench.harness.analysis.complexity_check` of ``exponents`` (computed when not given),
    ``repeats`` :func:`vorobench.harness.analysis.case_repeats` (no noise bullet without it)."""
    if check is None:
        check = complexity_check(exponents, _complexity)

    points: list[str] = []
    # Fastest implementation per dataset at the largest n that several implementations reached.
    wins: dict[str, list[str]] = {}
    for dataset, g in sizes.groupby("dataset", sort=False):
        counts = g.groupby("n")["impl"].nunique()
        shared = counts[counts >= 2]
        if shared.empty:
            continue
        n_top = shared.index.max()
        at = g[g["n"] == n_top].sort_values("time_s")
        best, second = at.iloc[0], at.iloc[1]
        wins.setdefault(best["impl"], []).append(
            f"{_text(dataset)} ({seconds_text(best['time_s'])} at n={size_text(best['n_sites'])}, "
            f"{factor_text(second['time_s'] / best['time_s'])}x ahead of {_code(second['impl'])})")
    for impl, where in sorted(wins.items(), key=lambda kv: -len(kv[1])):
        points.append(f"**Fastest at the largest common size**: {_code(impl)} on {len(where)} dataset(s): "
                      + "; ".join(where) + ".")
    # Speed against the reference, geometric mean over datasets and sizes.
    if not ratios.empty:
        for impl, g in ratios.groupby("impl", sort=True):
            big = g[g["n_sites"] >= FIT_MIN_SITES]
            g = big if not big.empty else g
            gm = float(np.exp(np.mean(np.log(g["ratio"]))))
            word = "slower" if gm > 1 else "faster"
            factor = gm if gm > 1 else 1 / gm
            points.append(f"{_code(impl)} is {factor_text(factor)}x {word} than {_code(reference)} (geometric mean of "
                          f"time ratios over {len(g)} dataset/size pairs, range "
                          f"{g['ratio'].min():.2g}-{g['ratio'].max():.2g}).")
    # Noise: how far the repeats of one case lie apart.
    spreads = [(c["max_s"] - c["min_s"]) / c["median_s"] for c in (repeats or [])
               if len(c["times"]) >= 2 and c["median_s"]]
    if spreads:
        points.append(f"**Noise**: the repeats of one case lie a median {percent_text(float(np.median(spreads)))} apart "
                      f"(spread = (slowest - fastest) / median; 90th percentile {percent_text(float(np.quantile(spreads, 0.9)))}, "
                      f"over {len(spreads)} cases with two or more repeats). A smaller difference between two "
                      "implementations or two runs is within the noise.")
    # Growth, against the declared complexity.
    for impl, g in check.groupby("impl", sort=True):
        lo, hi, med = g["exponent"].min(), g["exponent"].max(), g["exponent"].median()
        spread = f"median of {len(g)} datasets, range {lo:.2f}-{hi:.2f}, " if len(g) > 1 else ""
        r2 = g["r2"].dropna()
        fit = f"worst R² {r2.min():.3f}" if not r2.empty else "R² not measurable: two sizes fit any line"
        text = f"{_code(impl)} grows like n^{med:.2f} (fitted exponent, {spread}{fit})"
        declared = g["declared"].dropna()
        if declared.empty:
            points.append(text + "; no declared complexity to compare with.")
            continue
        if not np.isfinite(g["declared_exponent"].astype(float)).any():
            points.append(text + f"; declared {_text(declared.iloc[0])}, not of the form O(n^a log^b n): unchecked.")
            continue
        expected = float(g["declared_exponent"].median())
        text += f"; declared {_text(declared.iloc[0])}, about n^{expected:.2f} over these sizes"
        above, below = g[g["finding"] == "above"], g[g["finding"] == "below"]
        if not above.empty:
            text += (": **above it on " + ", ".join(
                f"{_text(r.dataset)} (n^{r.exponent:.2f} over {size_text(r.n_min)}-{size_text(r.n_max)}, "
                f"{int(r.points)} sizes)" for r in above.sort_values("excess", ascending=False).itertuples())
                + "**")
            rest = len(g) - len(above)
            text += f"; as declared or below on the other {rest}." if rest else "."
        elif len(below) == len(g):
            text += ": below it everywhere (O is an upper bound)."
        else:
            text += ": as declared" + (f" (below it on {len(below)})" if len(below) else "") + "."
        points.append(text)
    if not check.empty:
        points.append(f"Growth rule: a fit is a mismatch when its exponent exceeds the declared complexity's own "
                      f"exponent over the same sizes by more than {MISMATCH_TOLERANCE:g} (n log n counts as about "
                      "n^1.12 over 1k-30k, n^2 as 2).")
    # Correctness.
    ran = cases[cases["status"] == Status.OK]
    if not ran.empty:
        others, own = ran[ran["impl"] != reference], ran[ran["impl"] == reference]
        tally = others["verdict"].fillna("none").replace({Verdict.SKIPPED: "not checked"}).value_counts()
        parts = ", ".join(f"{v} {_text(str(k).replace('_', ' '))}" for k, v in tally.items()) or "none"
        text = f"**Correctness** of the {len(others)} cases that ran, against {_code(reference)}: {parts}."
        if not own.empty:
            text += (f" {_code(reference)}'s own {len(own)} cases are judged on their certificates alone: "
                     f"{certificate_tally(own)}.")
        if "certificate" in others.columns and others["certificate"].fillna("").astype(str).str.len().any():
            text += f" Certificates of the others: {certificate_tally(others)}."
        points.append(text)
    bad = failures(cases)
    if bad.empty:
        points.append("**No failures**: no case crashed, hung, ran out of memory or was refuted.")
    else:
        listed = [f"{_code(r.impl)} {_text(r.dataset)} n={size_text(r.n)}: {_text(r.status)}"
                  + (f" / {_text(r.verdict)}" if r.status == Status.OK else "") for r in bad.head(8).itertuples()]
        more = f" and {len(bad) - 8} more" if len(bad) > 8 else ""
        points.append(f"**{len(bad)} case(s) failed or were not verified**: " + "; ".join(listed) + more
                      + " (details in the table below).")
    skipped = cases[cases["status"] == Status.SKIPPED]
    if not skipped.empty:
        points.append(f"{len(skipped)} case(s) were skipped (a smaller size timed out, or the extrapolated "
                      "time exceeded the run's budget).")
    return points


# ------------------------------------------------------------------------------ writing

def _load_text(run: dict) -> str:
    start, end = run.get("load_average"), run.get("load_average_end")
    if not (isinstance(start, list) and start and _is_number(start[0])):
        return ""
    text = f"{start[0]:g} at the start"
    return text + (f", {end[0]:g} at the end" if isinstance(end, list) and end and _is_number(end[0]) else "")


def _is_number(x: object) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool)


def busy_machine_note(meta: dict) -> Optional[str]:
    """A warning when other processes competed for the CPU during the run (load above cores)."""
    runs = meta.get("runs", [])
    if not runs:
        return None
    r = runs[-1]
    loads = [x[0] for x in (r.get("load_average"), r.get("load_average_end"))
             if isinstance(x, list) and x and _is_number(x[0])]
    cores = r.get("cores") if _is_number(r.get("cores")) else 0
    if loads and cores and max(loads) > cores:
        return (f"**The machine was busy**: load average up to {max(loads):g} on {cores} cores, so other "
                "processes competed for the CPU. Times carry noise of tens of percent (and fitted exponents "
                "with them); the counters and verdicts do not depend on it.")
    return None


def _meta_pairs(meta: dict) -> list[tuple[str, str]]:
    """The run's metadata as (label, plain text) pairs; every value comes from the metadata file."""
    runs = meta.get("runs", [])
    if not runs:
        return [("metadata", "none (no .meta.json next to the results)")]
    r = runs[-1]
    v = r.get("versions") if isinstance(r.get("versions"), dict) else {}
    commit = str(r.get("commit") or "?")[:12] + (" (uncommitted changes)" if r.get("dirty") else "")
    load = _load_text(r)
    rows = [
        ("date", str(r.get("date", "?")) + (f" to {r['finished']}" if r.get("finished") else "")),
        ("commit", commit),
        ("machine", f"{r.get('cpu', '?')}, {r.get('cores', '?')} cores, {r.get('hostname', '?')}"
                    + (f"; load average {load}" if load else "")),
        ("software", f"Python {r.get('python', '?')}, numpy {v.get('numpy')}, scipy {v.get('scipy')}, "
                     f"numba {v.get('numba')}"),
        ("cases", f"repeat {r.get('repeat')}, timeout {r.get('timeout')} s per build, reference "
                  f"{r.get('reference')}, check {'on' if r.get('check') else 'off'}"),
    ]
    if len(runs) > 1:
        rows.append(("runs", f"{len(runs)} (resumed); ids {', '.join(str(x.get('run_id')) for x in runs)}"))
    return [(label, str(value)) for label, value in rows]


@dataclass
class _Data:
    """Every summary the two pages are written from."""

    df: object
    cases: object
    sizes: object
    exps: object
    check: object
    ratios: object
    matrix: object
    repeats: list
    reference: str
    order: list


def write_report(results_path: str | Path, out: str | Path, title: Optional[str] = None,
                 reference: Optional[str] = None, copy_results: bool = True) -> Report:
    """Write figures, README.md and report.html for a results file into folder ``out``.

    A figure with nothing to draw (no reference timed: no speed ratios; no memory measured) is
    not written, and a stale file of that name from an earlier report in ``out`` is removed.
    """
    results_path, out = Path(results_path), Path(out)
    df = load_checked(results_path)            # ValueError naming the file if it holds no results
    raw = df
    df = with_families_in_dataset(df)           # weighted cases, disks: datasets of their own, named so
    meta = read_metadata(results_path)
    out.mkdir(parents=True, exist_ok=True)
    runs = meta.get("runs", [])
    reference = str(reference or (runs[-1].get("reference") if runs else None) or impls.DEFAULT_REFERENCE)
    title = title or out.name

    cases = analysis.case_table(df)
    sizes = analysis.size_table(df)
    exps = analysis.fit_exponents(sizes)
    recorded = recorded_declarations(meta)
    declared = {str(name): _declared_complexity(str(name), recorded) for name in df["impl"].unique()}
    check = analysis.complexity_check(exps, declared)
    ratios = analysis.speed_ratios(sizes, reference)
    matrix = analysis.correctness_matrix(cases)
    styles = figures.impl_styles(sorted(df["impl"].unique()))
    order = list(dict.fromkeys(df["dataset"]))
    data = _Data(df, cases, sizes, exps, check, ratios, matrix, analysis.case_repeats(df), reference, order)

    drawn = {
        "time": figures.plot_time(sizes, out / FIGURES["time"], styles, order),
        "nlogn": figures.plot_time_per_nlogn(sizes, out / FIGURES["nlogn"], styles, order),
        "ratio": figures.plot_ratio(ratios, reference, out / FIGURES["ratio"], styles, order),
        "memory": figures.plot_memory(sizes, out / FIGURES["memory"], styles, order),
        "correctness": figures.plot_correctness(matrix, out / FIGURES["correctness"], order),
    }
    power = plot_power_case(raw, out / FIGURES["power"], reference)
    drawn["power"] = power[0] if power else None
    disks = plot_disk_case(raw, out / FIGURES["disks"], reference)
    drawn["disks"] = disks[0] if disks else None
    figs = {key: path for key, path in drawn.items() if path is not None}
    for key in set(drawn) - set(figs):
        (out / FIGURES[key]).unlink(missing_ok=True)       # an earlier report's figure would be stale
    copied = []
    if copy_results:
        for src in (results_path, metadata_path(results_path)):
            dst = out / ("results" + src.name[len(results_path.stem):])
            if src.exists():
                if src.resolve() != dst.resolve():
                    shutil.copyfile(src, dst)
                copied.append(dst.name)

    md = _markdown(title, data, figs, meta, results_path)
    if power:
        md = md.rstrip("\n") + ("\n\n## A power diagram of this run\n\n" + _text(power[1]) + ". Red crosses: hidden "
                                 "sites (empty power cells); grey circles: each weight w as a circle of radius "
                                 f"sqrt(w).\n\n![power diagram]({FIGURES['power']})\n")
    if disks:
        md = md.rstrip("\n") + ("\n\n## A diagram of disks of this run\n\n" + _text(disks[1]) + ". Each edge is "
                                 "sampled along its bisector branch; grey circles: the disks; red crosses: hidden "
                                 f"disks (inside another).\n\n![diagram of disks]({FIGURES['disks']})\n")
    md_path = out / "README.md"
    md_path.write_text(md)
    html_path = out / "report.html"
    html_path.write_text(_html(title, data, figs, meta, copied))
    return Report(out, md_path, html_path, figs)


def _skipped_md(cases) -> Optional[str]:
    skipped = cases[cases["status"] == Status.SKIPPED]
    if skipped.empty:
        return None
    first = skipped.sort_values("n").groupby(["impl", "dataset"], sort=True).first().reset_index()
    return ("Skipped (a smaller size timed out or ran out of memory, or the build time extrapolated "
            "from the smaller sizes exceeded the run's budget): "
            + "; ".join(f"{_code(r.impl)} {_text(r.dataset)} from n={size_text(r.n)}" for r in first.itertuples()) + ".")


def _warmup_md(cases) -> Optional[str]:
    warm = cases[cases["status"] == Status.OK].groupby("impl")["warmup_s"].median().dropna()
    if warm.empty:
        return None
    return ("Warm-up per worker (JIT compilation or cache load, plus one small build), median: "
            + ", ".join(f"{_code(k)} {seconds_text(v)}" for k, v in warm.items()) + ".")


def _command(meta: dict) -> Optional[str]:
    argv = (meta.get("runs") or [{}])[-1].get("argv")
    return "vorobench " + shlex.join(str(a) for a in argv) if isinstance(argv, list) else None


def _summary(d: _Data) -> tuple[str, str]:
    """The opening line, as Markdown and as plain text."""
    impl_names = sorted(d.df["impl"].unique())
    ns = sorted(d.df["n"].unique())
    head = f"{len(d.cases)} cases: {len(impl_names)} implementation(s) ("
    tail = (f") x {len(d.order)} dataset(s) ({{datasets}}) x sizes {', '.join(size_text(n) for n in ns)}; "
            f"{len(d.df)} result rows.")
    md = head + ", ".join(map(_text, impl_names)) + tail.replace("{datasets}", ", ".join(map(_text, d.order)))
    plain = head + ", ".join(map(str, impl_names)) + tail.replace("{datasets}", ", ".join(map(str, d.order)))
    return md, plain


def _mismatch_md(d: _Data) -> list[str]:
    bad = complexity_mismatches(d.check)
    if bad.empty:
        return []
    rows = [[_code(r.impl), _text(r.dataset), f"**n^{r.exponent:.2f}**", f"{_text(r.declared)} = n^{r.declared_exponent:.2f}",
             f"**{r.excess:+.2f}**", f"{size_text(r.n_min)}-{size_text(r.n_max)} ({int(r.points)} sizes, {r2_text(r.r2)})"]
            for r in bad.itertuples()]
    return ["## Growth above the declared complexity", "",
            f"The fitted exponent exceeds the declared complexity's own exponent over the same sizes by more "
            f"than {MISMATCH_TOLERANCE:g}:", "",
            _md_table(["impl", "dataset", "fitted", "declared, over these sizes", "excess", "fitted over"], rows,
                      "llrlrl"), ""]


def _markdown(title, d: _Data, figs: dict, meta: dict, results_path) -> str:
    cases, sizes, check, reference = d.cases, d.sizes, d.check, d.reference
    parts = [f"# vorobench report: {_text(title)}", "", _summary(d)[0], "",
             "Interactive version (filters, hover details, per-case repeats): [`report.html`](report.html).", ""]
    parts += _mismatch_md(d)
    parts += ["## Reading", ""]
    parts += [f"* {p}" for p in reading(cases, sizes, d.exps, d.ratios, reference, check, d.repeats)]
    note = busy_machine_note(meta)
    if note:
        parts.append(f"* {note}")
    hosts_note = mixed_hosts_note(d.df)
    if hosts_note:
        hosts_note = _text(hosts_note)             # it names the hosts found in the results
        parts.append(f"* {hosts_note}")
    parts += ["", "## Run", ""]
    parts += [f"* **{label}**: {_text(value)}" for label, value in _meta_pairs(meta)]
    parts += [""]

    if "time" in figs:
        parts += ["## Build time", "",
                  "Median wall time of one build (inputs generated and JIT warm-up done beforehand), "
                  "log-log; the band runs from the fastest to the slowest repeat (all seeds).", "",
                  f"![build time vs n]({FIGURES['time']})", ""]
    if "nlogn" in figs:
        parts += ["## Time per n log2 n", "",
                  "A flat line is O(n log n); a line rising to the right grows faster than that.", "",
                  f"![time / (n log2 n)]({FIGURES['nlogn']})", ""]
    if "ratio" in figs:
        parts += [f"## Speed relative to {_text(reference)}", "",
                  f"time / time({_text(reference)}) at the same dataset and size: below the dashed line is faster.",
                  "", *([hosts_note, ""] if hosts_note else []),
                  f"![speed ratio]({FIGURES['ratio']})", ""]
    if "memory" in figs:
        parts += ["## Peak memory", "",
                  "Rise of the worker's resident peak during one build (the input and the imported "
                  "libraries excluded); values below a page are not shown.", "",
                  f"![peak memory vs n]({FIGURES['memory']})", ""]
    if "correctness" in figs:
        parts += ["## Correctness", "",
                  "Every built diagram is certified (empty circles, bisectors, Euler, hull, nearest-site "
                  f"probes) and compared with {_text(reference)}'s. Colour = worst verdict over sizes and seeds.", "",
                  f"![correctness matrix]({FIGURES['correctness']})", ""]

    parts += ["## Fitted growth exponents", "",
              "Least-squares slope of log(time) against log(n); R² near 1 means a clean power law. "
              "Sizes under 1,000 sites are left out when three larger ones exist. *Declared here* is the "
              "declared complexity's own slope over the same sizes; a fit more than "
              f"{MISMATCH_TOLERANCE:g} above it is a mismatch (**above**).", ""]
    if check.empty:
        parts += ["(too few sizes to fit)", ""]
    else:
        rows = [[_code(r.impl), _text(r.dataset), f"{r.exponent:.2f}", r2_text(r.r2, bare=True),
                 f"{size_text(r.n_min)}-{size_text(r.n_max)} ({r.points})", _text(r.declared or "?"),
                 f"{r.declared_exponent:.2f}" if math.isfinite(r.declared_exponent) else "-",
                 f"**{r.finding}**" if r.mismatch else r.finding]
                for r in check.itertuples()]
        parts += [_md_table(["impl", "dataset", "exponent", "R²", "n range (sizes)", "declared", "declared here",
                             "finding"], rows, "llrrllrl"), ""]

    parts += ["## Median build time", ""]
    if sizes.empty:
        parts += ["(no successful cases)", ""]
    else:
        cols = sorted(sizes["n"].unique())
        rows = []
        for (dataset, impl), g in sizes.groupby(["dataset", "impl"], sort=False):
            by_n = {n: (t, lo, hi) for n, t, lo, hi in zip(g["n"], g["time_s"], g["time_min_s"], g["time_max_s"])}
            rows.append([_text(dataset), _code(impl)] + [_fmt_time_spread(*by_n.get(n, (float("nan"),) * 3))
                                                          for n in cols])
        parts += ["The median, with the fastest and the slowest repeat as a percentage of it.", "",
                  _md_table(["dataset", "impl"] + [f"n={size_text(n)}" for n in cols], rows, "ll" + "r" * len(cols)), ""]
        warm = _warmup_md(cases)
        if warm:
            parts += [warm, ""]

    bad = failures(cases)
    parts += ["## Failures", ""]
    if bad.empty:
        parts += ["None.", ""]
    else:
        rows = [[_code(r.impl), _text(r.dataset), size_text(r.n), _text(r.seed), _text(r.status),
                 _text(r.verdict if isinstance(r.verdict, str) else ""),
                 _text(r.phase if isinstance(r.phase, str) else ""),
                 _text((r.error if isinstance(r.error, str) else "")[:120])]
                for r in bad.itertuples()]
        parts += [_md_table(["impl", "dataset", "n", "seed", "status", "verdict", "step", "error"], rows), ""]
    skipped = _skipped_md(cases)
    if skipped:
        parts += [skipped, ""]

    command = _command(meta)
    parts += ["## Data", "",
              "Raw rows: [`results.csv`](results.csv) (one row per case and repeat; "
              "`pandas.read_csv`), metadata: [`results.meta.json`](results.meta.json)."]
    if command:
        # A fence longer than any backtick run in the command: nothing in it can close the block.
        fence = "`" * max(3, max((len(run) + 1 for run in re.findall(r"`+", command)), default=0))
        parts += ["", "Produced by:", "", fence, command, fence]
    return "\n".join(parts) + "\n"


def _fmt_time_spread(median: float, lo: float, hi: float) -> str:
    """"41.3 ms (-2%/+9%)": the median and how far the fastest and slowest repeat lie from it."""
    text = seconds_text(median)
    if not (math.isfinite(median) and math.isfinite(lo) and math.isfinite(hi)) or median <= 0:
        return text
    if hi - lo <= 0:
        return text
    return f"{text} ({(lo / median - 1) * 100:+.0f}%/{(hi / median - 1) * 100:+.0f}%)"


def _html(title: str, d: _Data, figs: dict, meta: dict, copied: list[str]) -> str:
    """The interactive page (:mod:`vorobench.harness.report_html`)."""
    busy, hosts = busy_machine_note(meta), mixed_hosts_note(d.df)
    notes = ([busy] if busy else []) + ([_text(hosts)] if hosts else [])    # Markdown; the hosts come from the data
    files = {f"{FIGURES[k]}": FIGURES[k] for k in figs}
    files.update({"README.md (Markdown report)": "README.md"})
    files.update({name: name for name in copied})
    page = PageInput(
        title=title, summary=_summary(d)[1],
        reading_md=reading(d.cases, d.sizes, d.exps, d.ratios, d.reference, d.check, d.repeats),
        notes_md=notes, run_rows=_meta_pairs(meta), df=d.df, cases=d.cases, sizes=d.sizes, ratios=d.ratios,
        check=d.check, matrix=d.matrix, failures=failures(d.cases), repeats=d.repeats, reference=d.reference,
        order=d.order, styles=plotly_styles(figures.impl_styles(sorted(d.df["impl"].unique()))),
        tolerance=MISMATCH_TOLERANCE, skipped_md=_skipped_md(d.cases), warmup_md=_warmup_md(d.cases),
        files=files, command=_command(meta))
    return render(page)
