"""The report's interactive page, ``report.html``: one self-contained file that works offline.

plotly.js is inlined once. Every figure is a JSON spec in the page, drawn by a short script that
also wires the filter bar (implementations, datasets, sizes) to the figures, the correctness
matrix and the case table, and the drill-down: clicking a case (a row of the case table, or a
point of a build-time or spread figure) shows its repeats, timings and counters. A figure is one
dataset's panel of one view; a panel or a view with nothing to draw is left out, never drawn
empty, and a panel the filters empty is hidden.

Everything taken from the results and their metadata (names, errors, host, argv) is text, made
safe by :mod:`vorobench.harness.html_page` (which also gives the page its skeleton and common
style): HTML-escaped in the markup and in the figures' labels (plotly reads the entities), and
written into the JSON so that nothing can end the script element. The Markdown parts (the
reading) are rendered by markdown-it with raw HTML off.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any, Optional, Sequence

import numpy as np
import pandas as pd
import plotly.graph_objects as go
import plotly.io as pio
from markdown_it import MarkdownIt
from matplotlib.colors import to_hex
from plotly.offline import get_plotlyjs

from vorobench.harness.analysis import complexity_mismatches, r2_text, worst_verdict
from vorobench.harness.figures import (MEMORY_RESOLUTION_MB, VERDICT_COLOURS, has_data, text_colour,
                                       verdict_colour, verdict_label)
from vorobench.harness.html_page import escape, page
from vorobench.harness.markdown_text import one_line
from vorobench.harness.units import seconds_text, size_text
from vorobench.judge.outcomes import Status, status_rank

__all__ = ["PageInput", "render", "plotly_styles", "VIEW_TITLES"]

#: The figure views of the page, in page order, with their section titles.
VIEW_TITLES = {
    "time": "Build time vs n",
    "spread": "Spread of the repeats",
    "noise": "Noise band",
    "growth": "Growth against the declared complexity",
    "nlogn": "Time per n log2 n",
    "ratio": "Speed relative to the reference",
    "memory": "Peak memory",
}

_SYMBOLS = {"o": "circle", "s": "square", "D": "diamond", "^": "triangle-up", "v": "triangle-down",
            "P": "cross", "*": "star", "X": "x", "h": "hexagon", "<": "triangle-left", ">": "triangle-right"}


def _esc(value: object) -> str:
    """Text from the results as HTML text, on one line."""
    return escape(one_line(value))


def _plain(value: Any) -> Any:
    """numpy values as the JSON types they stand for (a non-finite float as null)."""
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, np.ndarray):
        return value.tolist()
    raise TypeError(f"not JSON: {type(value).__name__}")


def _finite(x: object) -> bool:
    return isinstance(x, (int, float, np.integer, np.floating)) and math.isfinite(float(x))


def plotly_styles(styles: dict) -> dict[str, dict[str, str]]:
    """The matplotlib styles of :func:`vorobench.harness.figures.impl_styles` as plotly colours and symbols."""
    return {impl: {"color": to_hex(s["color"]), "symbol": _SYMBOLS.get(s["marker"], "circle")}
            for impl, s in styles.items()}


@dataclass
class PageInput:
    """What the page shows. Markdown fields are Markdown built through :mod:`vorobench.harness.markdown_text`
    (results text escaped); plain fields are plain text and get escaped here."""

    title: str
    summary: str                                   # plain text
    reading_md: list[str]                          # Markdown, one bullet each
    notes_md: list[str]                            # Markdown warnings for the top (busy machine, hosts)
    run_rows: list[tuple[str, str]]                # plain text (label, value)
    df: pd.DataFrame
    cases: pd.DataFrame                            # analysis.case_table
    sizes: pd.DataFrame                            # analysis.size_table
    ratios: pd.DataFrame                           # analysis.speed_ratios
    check: pd.DataFrame                            # analysis.complexity_check
    matrix: pd.DataFrame                           # analysis.correctness_matrix
    failures: pd.DataFrame                         # analysis.failures(cases)
    repeats: list[dict]                            # analysis.case_repeats
    reference: str
    order: list[str]                               # datasets in page order
    styles: dict[str, dict[str, str]]              # plotly_styles
    tolerance: float
    skipped_md: Optional[str] = None
    warmup_md: Optional[str] = None
    files: dict[str, str] = field(default_factory=dict)       # label -> file name next to the page
    command: Optional[str] = None


@dataclass
class Panel:
    fid: str
    dataset: Optional[str]
    heading: str                                   # HTML
    figure: dict
    keys: list[dict]                               # per trace: impl / dataset / n, a value or one per point
    height: int


@dataclass
class View:
    key: str
    title: str
    intro: str                                     # HTML
    panels: list[Panel]
    single: bool = False                           # one full-width panel
    after: str = ""                                # HTML after the panels


# ------------------------------------------------------------------------------ formatting

def _fmt_time(seconds: object) -> str:
    return seconds_text(float(seconds)) if _finite(seconds) else "-"


def _fmt_n(n: object) -> str:
    return size_text(n)


def _tmpl(value: object) -> str:
    """Text from the results inside a plotly hovertemplate: escaped, and no ``%{`` left to expand."""
    return _esc(value).replace("%", "&#37;")


def _pct(x: float) -> str:
    return f"{x * 100:.0f}%" if abs(x) >= 0.1 else f"{x * 100:.1f}%"


def _counters_html(counters: dict, limit: int = 10) -> str:
    if not counters:
        return ""
    names = sorted(counters)
    lines = [f"{_esc(k[len('stat_'):] if k.startswith('stat_') else k)} {counters[k]:,}" for k in names[:limit]]
    more = f"<br>... {len(names) - limit} more" if len(names) > limit else ""
    return "<br><i>counters</i><br>" + "<br>".join(lines) + more


def _figure(data: list, layout: dict) -> dict:
    """A plotly figure as plain JSON (lists, no typed arrays), template left to the page."""
    fig = go.Figure(data=data, layout=layout)
    spec = json.loads(fig.to_json())
    spec["layout"].pop("template", None)
    return spec


def _template() -> dict:
    """plotly's white template, once for the whole page (the figures leave theirs out)."""
    return json.loads(json.dumps(pio.templates["plotly_white"].to_plotly_json(), default=_plain))


def _base_layout(height: int, xtitle: str, ytitle: str, logx: bool = True, logy: bool = True) -> dict:
    return dict(
        height=height, margin=dict(l=62, r=12, t=12, b=46), showlegend=False, hovermode="closest",
        xaxis=dict(title=dict(text=_esc(xtitle), standoff=6), type="log" if logx else "-", zeroline=False),
        yaxis=dict(title=dict(text=_esc(ytitle), standoff=4), type="log" if logy else "-", zeroline=False),
        font=dict(size=12), hoverlabel=dict(align="left"),
    )


def _size_ticks(values: Sequence[float]) -> dict:
    ns = sorted({float(v) for v in values if _finite(v) and v > 0})
    if 0 < len(ns) <= 8:
        return dict(tickmode="array", tickvals=ns, ticktext=[_fmt_n(v) for v in ns])
    return {}


# ------------------------------------------------------------------------------ per-size facts

class _Facts:
    """What a hover says about a size of an implementation on a dataset: its cases' verdict,
    counters and spread, and which case a click opens."""

    def __init__(self, cases: pd.DataFrame, repeats: list[dict]):
        self.index = {(c["impl"], c["dataset"], c["n"], c["seed"]): i for i, c in enumerate(repeats)}
        self.repeats = repeats
        self.by_size: dict[tuple, list[int]] = {}
        for i, c in enumerate(repeats):
            self.by_size.setdefault((c["impl"], c["dataset"], c["n"]), []).append(i)
        self.verdict = {}
        for key, g in cases.groupby(["impl", "dataset", "n"], sort=False):
            self.verdict[(str(key[0]), str(key[1]), int(key[2]))] = worst_verdict(g["verdict"].tolist()) or ""

    def case(self, impl: str, dataset: str, n: int) -> Optional[int]:
        """The case a click opens: the size's first seed that has times."""
        ids = self.by_size.get((impl, dataset, int(n)), [])
        timed = [i for i in ids if self.repeats[i]["times"]]
        return (timed or ids or [None])[0]

    def describe(self, impl: str, dataset: str, n: int) -> str:
        ids = self.by_size.get((impl, dataset, int(n)), [])
        verdict = self.verdict.get((impl, dataset, int(n)), "")
        text = f"<br>verdict {_esc(verdict or '-')}"
        first = self.case(impl, dataset, n)
        if first is not None:
            seeds = f" (seed {_esc(self.repeats[first]['seed'])} of {len(ids)})" if len(ids) > 1 else ""
            counters = _counters_html(self.repeats[first]["counters"])
            text += counters.replace("<i>counters</i>", f"<i>counters{seeds}</i>", 1) if counters else ""
        return text


# ------------------------------------------------------------------------------ views

def _metric_view(key: str, table: pd.DataFrame, column: str, ytitle: str, facts: _Facts, inp: PageInput,
                 intro: str, fmt, band: Optional[tuple[str, str]] = None, hline: Optional[float] = None,
                 warnings: Optional[dict[str, str]] = None) -> View:
    """One panel per dataset: ``column`` against n for every implementation (None if no value)."""
    panels: list[Panel] = []
    if not has_data(table, column):
        return View(key, VIEW_TITLES[key], intro, panels)
    ok = table[pd.to_numeric(table[column], errors="coerce") > 0]
    datasets = [d for d in inp.order if d in set(ok["dataset"])] + sorted(set(ok["dataset"]) - set(inp.order))
    for di, dataset in enumerate(datasets):
        part = ok[ok["dataset"] == dataset]
        traces, keys = [], []
        for impl, g in part.groupby("impl", sort=True):
            g = g.sort_values("n_sites")
            style = inp.styles.get(impl, {"color": "#444", "symbol": "circle"})
            custom = []
            for r in g.itertuples(index=False):
                spread = ""
                if band and _finite(getattr(r, band[0])) and _finite(getattr(r, band[1])):
                    spread = f"<br>fastest {fmt(getattr(r, band[0]))}, slowest {fmt(getattr(r, band[1]))}"
                if key == "time" and _finite(getattr(r, "time_q1_s", None)):
                    spread += f"<br>IQR {fmt(r.time_q1_s)} - {fmt(r.time_q3_s)}"
                reps = f"<br>{int(r.repeats)} repeat(s)" if hasattr(r, "repeats") and _finite(r.repeats) else ""
                custom.append([_fmt_n(r.n_sites), fmt(getattr(r, column)),
                               spread + reps + facts.describe(impl, dataset, int(r.n)),
                               facts.case(impl, dataset, int(r.n))])
            error = None
            if band:
                hi = (g[band[1]] - g[column]).clip(lower=0).fillna(0)
                lo = (g[column] - g[band[0]]).clip(lower=0).fillna(0)
                error = dict(type="data", symmetric=False, array=hi.tolist(), arrayminus=lo.tolist(),
                             thickness=1.2, width=4, color=style["color"])
            traces.append(dict(
                type="scatter", mode="lines+markers", name=_esc(impl), x=g["n_sites"].astype(float).tolist(),
                y=g[column].astype(float).tolist(), error_y=error, customdata=custom,
                line=dict(color=style["color"], width=1.6), marker=dict(color=style["color"], symbol=style["symbol"],
                                                                        size=7),
                hovertemplate=(f"<b>{_tmpl(impl)}</b> on {_tmpl(dataset)}, n=%{{customdata[0]}}<br>"
                               f"{_tmpl(ytitle)}: %{{customdata[1]}}%{{customdata[2]}}<extra></extra>")))
            keys.append({"impl": impl, "dataset": dataset, "n": [int(v) for v in g["n"]]})
        layout = _base_layout(330, "n (distinct sites)", ytitle)
        layout["xaxis"].update(_size_ticks(part["n_sites"]))
        shown = list(part[column]) + (list(part[band[0]]) + list(part[band[1]]) if band else [])
        layout["yaxis"].update(_log_ticks(shown))
        if hline is not None:
            layout["shapes"] = [dict(type="line", xref="paper", x0=0, x1=1, yref="y", y0=hline, y1=hline,
                                     line=dict(color="#555", dash="dash", width=1))]
        heading = _esc(dataset) + (warnings or {}).get(dataset, "")
        panels.append(Panel(f"fig-{key}-{di}", dataset, heading, _figure(traces, layout), keys, 330))
    return View(key, VIEW_TITLES[key], intro, panels)


def _log_ticks(values) -> dict:
    """A log axis labels decades only when it spans three or more, else 1, 2 and 5 of each decade
    (plotly's default would label every digit of a short range)."""
    v = pd.to_numeric(pd.Series(list(values)), errors="coerce")
    v = v[np.isfinite(v) & (v > 0)]
    if v.empty:
        return {}
    return {"dtick": 1} if v.max() / v.min() >= 1000 else {"dtick": "D2"}


def _spread_view(inp: PageInput) -> View:
    """Per dataset: every case's repeats relative to the case's median, a box per implementation and size."""
    intro = ("Every repeat of every case divided by that case&rsquo;s median, as a box (quartiles, whiskers to "
             "1.5 IQR) over its points: a tight box is a steady timing, a tall one a noisy case. Hover a point for "
             "its time; click it for the case. The levels themselves are in <a href=\"#time\">build time</a>.")
    panels: list[Panel] = []
    timed = [(i, c) for i, c in enumerate(inp.repeats) if c["times"] and c["median_s"]]
    present = {c["dataset"] for _, c in timed}
    datasets = [d for d in inp.order if d in present] + sorted(present - set(inp.order))
    for di, dataset in enumerate(datasets):
        part = [(i, c) for i, c in timed if c["dataset"] == dataset]
        ns = sorted({c["n"] for _, c in part})
        labels = {n: _fmt_n(n) for n in ns}
        traces, keys = [], []
        for impl in sorted({c["impl"] for _, c in part}):
            xs, ys, custom, nkey = [], [], [], []
            for i, c in part:
                if c["impl"] != impl:
                    continue
                for rep, t in zip(c["repeat_ids"], c["times"]):
                    xs.append(labels[c["n"]])
                    ys.append(round(t / c["median_s"], 5))
                    custom.append([_fmt_n(c["n_sites"] or c["n"]), _esc(c["seed"]), rep, _fmt_time(t), i])
                    nkey.append(c["n"])
            style = inp.styles.get(impl, {"color": "#444", "symbol": "circle"})
            traces.append(dict(
                type="box", name=_esc(impl), x=xs, y=ys, customdata=custom, offsetgroup=_esc(impl),
                boxpoints="all", jitter=0.5, pointpos=0, line=dict(color=style["color"], width=1.2),
                fillcolor="rgba(0,0,0,0)", marker=dict(color=style["color"], size=3.5, opacity=0.75),
                hoveron="points",
                hovertemplate=(f"<b>{_tmpl(impl)}</b> on {_tmpl(dataset)}, n=%{{customdata[0]}}, seed "
                               "%{customdata[1]}<br>repeat %{customdata[2]}: %{customdata[3]} "
                               "(%{y:.3f} x the case median)<extra></extra>")))
            keys.append({"impl": impl, "dataset": dataset, "n": nkey})
        layout = _base_layout(340, "n (requested sites)", "repeat time / case median", logx=False, logy=False)
        layout.update(boxmode="group", boxgap=0.2, boxgroupgap=0.08)
        layout["xaxis"].update(type="category", categoryorder="array", categoryarray=[labels[n] for n in ns])
        layout["yaxis"].update(tickformat=".2f")
        layout["shapes"] = [dict(type="line", xref="paper", x0=0, x1=1, yref="y", y0=1, y1=1,
                                 line=dict(color="#555", dash="dash", width=1))]
        panels.append(Panel(f"fig-spread-{di}", dataset, _esc(dataset), _figure(traces, layout), keys, 340))
    return View("spread", VIEW_TITLES["spread"], intro, panels)


def _noise_view(inp: PageInput) -> View:
    """One figure: every repeat divided by its case's median, a box per implementation."""
    cases = [(i, c) for i, c in enumerate(inp.repeats) if len(c["times"]) >= 2 and c["median_s"]]
    intro = ("Each repeat's time divided by its own case's median, over all datasets and sizes: the width of "
             "these boxes is the run-to-run noise of one case, the band a difference between two "
             "implementations or two runs has to exceed to mean anything. Cases with one repeat are left out.")
    if not cases:
        return View("noise", VIEW_TITLES["noise"], intro, [])
    traces, keys, rows = [], [], []
    impls = sorted({c["impl"] for _, c in cases})
    for impl in impls:
        ys, custom, dkey, nkey, spreads = [], [], [], [], []
        for i, c in cases:
            if c["impl"] != impl:
                continue
            spreads.append((c["max_s"] - c["min_s"]) / c["median_s"])
            for rep, t in zip(c["repeat_ids"], c["times"]):
                ys.append(round(t / c["median_s"], 5))
                custom.append([_esc(c["dataset"]), _fmt_n(c["n_sites"] or c["n"]), _esc(c["seed"]), rep,
                               _fmt_time(t), i])
                dkey.append(c["dataset"])
                nkey.append(c["n"])
        style = inp.styles.get(impl, {"color": "#444", "symbol": "circle"})
        traces.append(dict(
            type="box", name=_esc(impl), y=ys, customdata=custom, boxpoints="all", jitter=0.6, pointpos=0,
            line=dict(color=style["color"], width=1.2), fillcolor="rgba(0,0,0,0)",
            marker=dict(color=style["color"], size=3.5, opacity=0.7), hoveron="points",
            hovertemplate=(f"<b>{_tmpl(impl)}</b> on %{{customdata[0]}}, n=%{{customdata[1]}}, seed %{{customdata[2]}}"
                           "<br>repeat %{customdata[3]}: %{customdata[4]} (%{y:.3f} x the case median)"
                           "<extra></extra>")))
        keys.append({"impl": impl, "dataset": dkey, "n": nkey})
        s = np.array(spreads)
        rows.append((impl, len(s), float(np.median(s)), float(np.quantile(s, 0.9)), float(s.max())))
    layout = _base_layout(380, "", "repeat time / case median", logx=False)
    layout["xaxis"].update(type="category")
    layout["yaxis"].update(tickformat=".2f")
    layout["shapes"] = [dict(type="line", xref="paper", x0=0, x1=1, yref="y", y0=1, y1=1,
                             line=dict(color="#555", dash="dash", width=1))]
    table = ('<table class="num"><thead><tr><th>impl</th><th>cases</th><th>(slowest - fastest) / median: '
             "median</th><th>90th percentile</th><th>largest</th></tr></thead><tbody>"
             + "".join(f'<tr data-impl="{_esc(impl)}"><td>{_esc(impl)}</td><td>{k}</td><td>{_pct(m)}</td>'
                       f"<td>{_pct(p)}</td><td>{_pct(x)}</td></tr>" for impl, k, m, p, x in rows)
             + "</tbody></table>")
    panel = Panel("fig-noise-0", None, "all datasets and sizes", _figure(traces, layout), keys, 380)
    return View("noise", VIEW_TITLES["noise"], intro, [panel], single=True, after=table)


def _growth_view(inp: PageInput) -> View:
    """One figure: each fitted exponent (a point per dataset) against the declared complexity."""
    check = inp.check
    intro = (f"Fitted exponent of every implementation on every dataset (least-squares slope of log time "
             f"against log n) next to its declared complexity's own slope over the same sizes (grey tick; "
             f"n log n shows as about n^1.12 over 1k-30k). A point more than {inp.tolerance:g} right of the tick "
             f"(the grey bar) grows faster than declared: a <b>mismatch</b>, ringed and labelled.")
    if check.empty:
        return View("growth", VIEW_TITLES["growth"], intro, [])
    impls = sorted(check["impl"].unique())
    datasets = [d for d in inp.order if d in set(check["dataset"])] + sorted(set(check["dataset"]) - set(inp.order))
    offset = {d: (j - (len(datasets) - 1) / 2) * min(0.1, 0.6 / max(1, len(datasets))) for j, d in enumerate(datasets)}
    traces, keys = [], []
    for i, impl in enumerate(impls):
        g = check[check["impl"] == impl]
        style = inp.styles.get(impl, {"color": "#444", "symbol": "circle"})
        declared = g["declared_exponent"].dropna()
        if not declared.empty:
            traces.append(dict(
                type="scatter", mode="markers", x=[float(declared.median())], y=[i], name="declared",
                legendgroup="declared", showlegend=i == 0,
                marker=dict(symbol="line-ns-open", size=22, color="#666", line=dict(width=3, color="#666")),
                error_x=dict(type="data", symmetric=False, array=[inp.tolerance], arrayminus=[0], color="#bbb",
                             thickness=6, width=0),
                hovertemplate=(f"<b>{_esc(impl)}</b> declared {_esc(g['declared'].iloc[0])}: n^%{{x:.2f}} over "
                               f"the fitted sizes<br>mismatch above n^{float(declared.median()) + inp.tolerance:.2f}"
                               "<extra></extra>")))
            keys.append({"impl": impl})
        custom = [[_esc(impl), _esc(r.dataset), f"{r.exponent:.2f}", r2_text(r.r2, bare=True),
                   f"{_fmt_n(r.n_min)}-{_fmt_n(r.n_max)} ({int(r.points)} sizes)", _esc(r.declared or "?"),
                   f"n^{r.declared_exponent:.2f}" if _finite(r.declared_exponent) else "-",
                   f"{r.excess:+.2f}" if _finite(r.excess) else "-", _esc(r.finding)] for r in g.itertuples()]
        traces.append(dict(
            type="scatter", mode="markers", name=_esc(impl), showlegend=False, x=g["exponent"].tolist(),
            y=[i + offset[d] for d in g["dataset"]], customdata=custom,
            marker=dict(color=style["color"], symbol=style["symbol"], size=9, line=dict(width=0.5, color="#333")),
            hovertemplate=("<b>%{customdata[0]}</b> on %{customdata[1]}: n^%{customdata[2]} (R\u00b2 %{customdata[3]}, "
                           "n %{customdata[4]})<br>declared %{customdata[5]} = %{customdata[6]} here; "
                           "excess %{customdata[7]}: %{customdata[8]}<extra></extra>")))
        keys.append({"impl": impl, "dataset": g["dataset"].tolist()})
    bad = check[check["mismatch"]]
    if not bad.empty:
        traces.append(dict(
            type="scatter", mode="markers+text", name="mismatch", x=bad["exponent"].tolist(),
            y=[impls.index(r.impl) + offset[r.dataset] for r in bad.itertuples()],
            text=[f"{_esc(r.dataset)} n^{r.exponent:.2f}" for r in bad.itertuples()], textposition="top center",
            textfont=dict(color="#b2182b", size=12), hoverinfo="skip", cliponaxis=False,
            marker=dict(symbol="circle-open", size=20, color="#111", line=dict(width=2.5))))
        keys.append({"impl": bad["impl"].tolist(), "dataset": bad["dataset"].tolist()})
    height = 90 + 46 * len(impls)
    layout = _base_layout(max(260, height), "fitted exponent (time ~ n^x)", "", logx=False, logy=False)
    xs = check["exponent"].tolist() + (check["declared_exponent"] + inp.tolerance).dropna().tolist()
    layout["xaxis"].update(range=[min(0.8, min(xs) - 0.1), max(xs) + 0.25], autorange=False)
    layout["yaxis"].update(tickmode="array", tickvals=list(range(len(impls))), ticktext=[_esc(i) for i in impls],
                           range=[-0.7, len(impls) - 0.3], autorange=False)
    layout.update(showlegend=True, legend=dict(orientation="h", x=0, y=1.02, yanchor="bottom"),
                  margin=dict(l=100, r=20, t=36, b=46))
    panel = Panel("fig-growth-0", None, "all datasets", _figure(traces, layout), keys, max(260, height))
    return View("growth", VIEW_TITLES["growth"], intro, [panel], single=True, after=_growth_table(inp))


def _growth_table(inp: PageInput) -> str:
    """Every fit with its declared complexity, mismatches first."""
    check = inp.check.copy()
    check["rank"] = check["finding"].map({"above": 0, "as declared": 1, "below": 2, "unknown": 3}).fillna(3)
    rows = []
    for r in check.sort_values(["rank", "impl", "dataset"]).itertuples():
        declared = f"{r.declared_exponent:.2f}" if _finite(r.declared_exponent) else "-"
        excess = f"{r.excess:+.2f}" if _finite(r.excess) else "-"
        cls = ' class="mismatch"' if r.mismatch else ""
        rows.append(f'<tr data-impl="{_esc(r.impl)}" data-dataset="{_esc(r.dataset)}"{cls}>'
                    f"<td>{_esc(r.impl)}</td><td>{_esc(r.dataset)}</td><td>{r.exponent:.2f}</td><td>{r2_text(r.r2, bare=True)}</td>"
                    f"<td>{_fmt_n(r.n_min)}-{_fmt_n(r.n_max)} ({int(r.points)})</td><td>{_esc(r.declared or '?')}</td>"
                    f"<td>{declared}</td><td>{excess}</td><td>{_esc(r.finding)}</td></tr>")
    return (f"<details><summary>All fitted exponents ({len(check)})</summary>"
            '<table class="num"><thead><tr><th>impl</th><th>dataset</th><th>fitted exponent</th><th>R\u00b2</th>'
            "<th>n range (sizes)</th><th>declared</th><th>declared, as an exponent here</th><th>excess</th>"
            "<th>finding</th></tr></thead><tbody>" + "".join(rows) + "</tbody></table></details>")


# ------------------------------------------------------------------------------ HTML parts

def _attention(inp: PageInput) -> str:
    parts = []
    bad = complexity_mismatches(inp.check) if not inp.check.empty else inp.check
    if not bad.empty:
        rows = "".join(
            f"<tr><td><b>{_esc(r.impl)}</b></td>"
            f"<td>{_esc(r.dataset)}</td><td><b>n^{r.exponent:.2f}</b></td><td>{_esc(r.declared)} = "
            f"n^{r.declared_exponent:.2f} here</td><td><b>{r.excess:+.2f}</b></td>"
            f"<td>{_fmt_n(r.n_min)}-{_fmt_n(r.n_max)}, {int(r.points)} sizes, {r2_text(r.r2)}</td></tr>"
            for r in bad.itertuples())
        parts.append(
            f'<div class="alert"><h2 id="mismatches">Growth above the declared complexity: {len(bad)} '
            f"fit{'s' if len(bad) != 1 else ''}</h2>"
            f"<p>The fitted exponent exceeds the declared complexity&rsquo;s own exponent over the same sizes by "
            f"more than {inp.tolerance:g} (see <a href=\"#growth\">growth</a>).</p>"
            '<div class="wide"><table class="num"><thead><tr><th>impl</th><th>dataset</th><th>fitted</th>'
            f"<th>declared</th><th>excess</th><th>fitted over</th></tr></thead><tbody>{rows}</tbody></table></div></div>")
    if not inp.failures.empty:
        parts.append(f'<div class="alert"><b>{len(inp.failures)} case(s) failed or were not verified</b>: '
                     'see <a href="#failures">failures</a>.</div>')
    for note in inp.notes_md:
        parts.append(f'<div class="warn">{_md_inline(note)}</div>')
    return "\n".join(parts)


def _md_inline(text: str) -> str:
    return MarkdownIt("commonmark", {"html": False}).renderInline(text)


def _md_list(items: list[str]) -> str:
    return MarkdownIt("commonmark", {"html": False}).render("\n".join(f"* {i}" for i in items))


def _filters(inp: PageInput) -> str:
    impls = sorted(str(i) for i in inp.df["impl"].unique())
    present = set(str(d) for d in inp.df["dataset"].unique())
    datasets = [d for d in inp.order if d in present] + sorted(present - set(inp.order))
    sizes = sorted(int(n) for n in inp.df["n"].unique())

    def box(group: str, value: str, label: str, swatch: str = "") -> str:
        return (f'<label><input type="checkbox" data-group="{group}" value="{_esc(value)}" checked>'
                f"{swatch}{label}</label>")

    def swatch(impl: str) -> str:
        colour = inp.styles.get(impl, {}).get("color", "#444")
        return f'<span class="swatch" style="background:{_esc(colour)}"></span>'

    def group(name: str, title: str, items: list[str]) -> str:
        return (f'<fieldset><legend>{title} <button type="button" data-all="{name}">all</button>'
                f'<button type="button" data-none="{name}">none</button></legend>{"".join(items)}</fieldset>')

    return ('<nav id="filters" aria-label="filters">'
            + group("impl", "implementations", [box("impl", i, _esc(i), swatch(i)) for i in impls])
            + group("dataset", "datasets", [box("dataset", d, _esc(d)) for d in datasets])
            + group("n", "sizes", [box("n", str(n), _fmt_n(n)) for n in sizes])
            + '<span class="note">The filters apply to every figure and table below. Click a point of a '
              "build-time or spread figure, or a row of the case table, for that case&rsquo;s repeats.</span></nav>")


def _verdict_legend(verdicts: Sequence[str]) -> str:
    present = set(verdicts)
    shown = [v for v in VERDICT_COLOURS if v in present] + sorted(present - set(VERDICT_COLOURS))
    others = [v for v in VERDICT_COLOURS if v not in present]

    def chip(v: str) -> str:
        return f'<span class="chip" style="background:{verdict_colour(v)}"></span>{_esc(verdict_label(v))} '

    return ('<p class="legend"><b>Verdicts here:</b> ' + "".join(chip(v) for v in shown)
            + (' <span class="others">&nbsp; other verdicts: ' + "".join(chip(v) for v in others) + "</span>"
               if others else "") + "</p>")


def _correctness(inp: PageInput) -> str:
    m = inp.matrix
    if m.empty:
        return ""
    impls = sorted(m["impl"].unique())
    present = set(m["dataset"])
    datasets = [d for d in inp.order if d in present] + sorted(present - set(inp.order))
    cells = {(r.impl, r.dataset): r for r in m.itertuples()}
    head = "".join(f'<th data-dataset="{_esc(d)}">{_esc(d)}</th>' for d in datasets)
    body = []
    for impl in impls:
        tds = []
        for d in datasets:
            r = cells.get((impl, d))
            if r is None:
                tds.append(f'<td data-dataset="{_esc(d)}" class="notrun">not run</td>')
                continue
            colour = verdict_colour(r.worst)
            counts = f"{r.good}/{r.checked} good" if r.checked else f"{r.cases} case(s)"
            tds.append(f'<td data-dataset="{_esc(d)}" style="background:{colour};color:{text_colour(colour)}" '
                       f'title="{_esc(impl)} on {_esc(d)}: worst verdict {_esc(r.worst)}, {counts}, {r.cases} '
                       f'case(s)">{_esc(verdict_label(r.worst))}<br><small>{counts}</small></td>')
        body.append(f'<tr data-impl="{_esc(impl)}"><th scope="row">{_esc(impl)}</th>{"".join(tds)}</tr>')
    return (f'<p>Every built diagram is certified (empty circles, bisectors, Euler, hull, nearest-site probes) and '
            f"compared with {_esc(inp.reference)}&rsquo;s. A cell is the worst verdict over sizes and seeds; "
            "k/m good = passed the cross-validation, of checked.</p>"
            + _verdict_legend(m["worst"].astype(str).tolist())
            + '<div class="wide"><table class="matrix"><thead><tr><th scope="col">impl \\ dataset</th>' + head
            + "</tr></thead><tbody>" + "".join(body) + "</tbody></table></div>")


def _case_rows(inp: PageInput) -> str:
    seeds = len({str(c["seed"]) for c in inp.repeats}) > 1          # one seed: no seed column
    rows = []
    for i, c in enumerate(inp.repeats):
        verdict = c["verdict"] or "-"
        chip = f'<span class="chip" style="background:{verdict_colour(verdict)}"></span>' if c["verdict"] else ""
        if c["times"]:
            spread = (c["max_s"] - c["min_s"]) / c["median_s"] if c["median_s"] else float("nan")
            timing = (f"<td>{_fmt_time(c['median_s'])}</td><td>{_fmt_time(c['min_s'])} - {_fmt_time(c['max_s'])}</td>"
                      f"<td>{_pct(spread) if math.isfinite(spread) else '-'}</td>")
        else:
            timing = "<td>-</td><td>-</td><td>-</td>"
        bad = (status_rank(c["status"]) or 0) > 0
        status = ("" if c["status"] in (Status.OK, c["verdict"]) else
                  f' <span class="{"bad" if bad else "note"}">{_esc(c["status"])}</span>')
        rows.append(f'<tr data-case="{i}" data-impl="{_esc(c["impl"])}" data-dataset="{_esc(c["dataset"])}" '
                    f'data-n="{c["n"]}" tabindex="0"><td>{_esc(c["impl"])}</td><td>{_esc(c["dataset"])}</td>'
                    f'<td>{_fmt_n(c["n"])}</td>' + (f'<td>{_esc(c["seed"])}</td>' if seeds else "")
                    + f'<td>{chip}{_esc(verdict)}{status}</td>'
                    f'<td>{len(c["times"])}</td>{timing}</tr>')
    return ('<div class="scroll"><table class="num cases"><thead><tr><th>impl</th><th>dataset</th><th>n</th>'
            + ("<th>seed</th>" if seeds else "") + "<th>verdict</th><th>repeats</th><th>median</th><th>range</th>"
            "<th>spread</th></tr></thead><tbody>" + "".join(rows) + "</tbody></table></div>")


def _case_detail(i: int, c: dict) -> str:
    facts = [("status", c["status"]), ("verdict", c["verdict"] or "-")]
    if c["detail"]:
        facts.append(("verdict detail", c["detail"]))
    if c["error"]:
        facts.append(("error", c["error"]))
    if c["phase"]:
        facts.append(("step", c["phase"]))
    if c["n_sites"] is not None:
        facts.append(("distinct sites", f"{c['n_sites']:,}"))
    if c["times"]:
        facts.append(("build time", f"median {_fmt_time(c['median_s'])}, quartiles {_fmt_time(c['q1_s'])} - "
                                    f"{_fmt_time(c['q3_s'])}, fastest {_fmt_time(c['min_s'])}, slowest "
                                    f"{_fmt_time(c['max_s'])} over {len(c['times'])} repeat(s)"))
    dl = "".join(f'<tr><th scope="row">{_esc(k)}</th><td>{_esc(v)}</td></tr>' for k, v in facts)
    phases = list(c["phases"])
    rep_rows = "".join(
        f"<tr><td>{rep}</td><td>{_fmt_time(t)}</td>"
        + "".join(f"<td>{_fmt_time(c['phases'][p][k])}</td>" if c["phases"][p][k] is not None else "<td>-</td>"
                  for p in phases) + "</tr>"
        for k, (rep, t) in enumerate(zip(c["repeat_ids"], c["times"])))
    repeats = ("" if not c["times"] else
               '<table class="num"><thead><tr><th>repeat</th><th>time_s</th>'
               + "".join(f"<th>{_esc(p)}</th>" for p in phases) + f"</tr></thead><tbody>{rep_rows}</tbody></table>")
    counters = ("" if not c["counters"] else
                '<table class="num"><thead><tr><th>counter</th><th>value</th></tr></thead><tbody>'
                + "".join(f"<tr><td>{_esc(k)}</td><td>{v:,}</td></tr>" for k, v in sorted(c["counters"].items()))
                + "</tbody></table>")
    plot = f'<div class="case-plot" id="case-plot-{i}" style="height:280px"></div>' if c["times"] else ""
    return (f'<div class="case-detail" id="case-{i}" hidden><h3>{_esc(c["impl"])} on {_esc(c["dataset"])}, '
            f'n={_fmt_n(c["n"])}, seed {_esc(c["seed"])}</h3><table class="facts"><tbody>{dl}</tbody></table>'
            f'{plot}<div class="tables">{repeats}{counters}</div></div>')


def _failures(inp: PageInput) -> str:
    bad = inp.failures
    if bad.empty:
        text = "<p>None.</p>"
    else:
        def s(v: object) -> str:
            return _esc(v) if isinstance(v, str) else ""

        rows = "".join(
            f'<tr data-impl="{_esc(r.impl)}" data-dataset="{_esc(r.dataset)}" data-n="{int(r.n)}">'
            f"<td>{_esc(r.impl)}</td><td>{_esc(r.dataset)}</td><td>{_fmt_n(r.n)}</td><td>{_esc(r.seed)}</td>"
            f"<td>{_esc(r.status)}</td><td>{s(r.verdict)}</td><td>{s(r.phase)}</td>"
            f"<td>{_esc(' '.join(str(r.error).split())[:300]) if isinstance(r.error, str) else ''}</td></tr>"
            for r in bad.itertuples())
        text = ('<table class="filterable"><thead><tr><th>impl</th><th>dataset</th><th>n</th><th>seed</th><th>status</th>'
                f"<th>verdict</th><th>step</th><th>error</th></tr></thead><tbody>{rows}</tbody></table>")
    if inp.skipped_md:
        text += f"<p>{_md_inline(inp.skipped_md)}</p>"
    return text


def _run(inp: PageInput) -> str:
    rows = "".join(f'<tr><th scope="row">{_esc(k)}</th><td>{_esc(v)}</td></tr>' for k, v in inp.run_rows)
    out = f'<table class="run"><tbody>{rows}</tbody></table>'
    if inp.warmup_md:
        out += f"<p>{_md_inline(inp.warmup_md)}</p>"
    return out


def _data(inp: PageInput) -> str:
    links = " &middot; ".join(f'<a href="{_esc(name)}">{_esc(label)}</a>' for label, name in inp.files.items())
    out = (f"<p>Files next to this page: {links}.</p>" if links else "")
    if inp.command:
        out += f"<p>Produced by:</p><pre>{escape(inp.command)}</pre>"
    return out


# ------------------------------------------------------------------------------ the page

def views(inp: PageInput) -> list[View]:
    """The figure views of the page, each with its non-empty panels (a view may have none)."""
    facts = _Facts(inp.cases, inp.repeats)
    warnings: dict[str, str] = {}
    if not inp.check.empty:
        for dataset, g in inp.check[inp.check["mismatch"]].groupby("dataset"):
            detail = "; ".join(f"{r.impl} grows like n^{r.exponent:.2f}, declared {r.declared}" for r in g.itertuples())
            warnings[str(dataset)] = (f' <span class="badge" title="{_esc(detail)}">above declared: '
                                      + ", ".join(f"{_esc(r.impl)} n^{r.exponent:.2f}" for r in g.itertuples())
                                      + "</span>")
    sizes = inp.sizes
    out = [
        _metric_view("time", sizes, "time_s", "time (s)", facts, inp,
                     "Median wall time of one build (inputs generated and JIT warm-up done beforehand), log-log. "
                     "The bars run from the fastest to the slowest repeat (all seeds). Hover a point for its "
                     "spread, verdict and counters; click it for the case.",
                     _fmt_time, band=("time_min_s", "time_max_s"), warnings=warnings),
        _spread_view(inp),
        _noise_view(inp),
        _growth_view(inp),
    ]
    if not sizes.empty:
        per = sizes.copy()
        norm = per["n_sites"] * np.log2(np.maximum(per["n_sites"], 2)) / 1e9
        per["lo"], per["hi"] = per["time_min_s"] / norm, per["time_max_s"] / norm
        out.append(_metric_view("nlogn", per, "ns_per_nlogn", "ns per n log2 n", facts, inp,
                                "Time divided by n log2 n: a flat line is O(n log n), a line rising to the right "
                                "grows faster than that.", lambda v: f"{float(v):.3g} ns", band=("lo", "hi"),
                                warnings=warnings))
    ratio_intro = (f"time / time({_esc(inp.reference)}) at the same dataset and size: below the dashed line is "
                   "faster.")
    view = _metric_view("ratio", inp.ratios, "ratio", f"time / time({inp.reference})", facts, inp,
                        ratio_intro, lambda v: f"{float(v):.3g}x", hline=1.0)
    view.title = f"Speed relative to {inp.reference}"
    out.append(view)
    memory = sizes
    hidden = 0
    if has_data(sizes, "mem_mb"):
        mem = pd.to_numeric(sizes["mem_mb"], errors="coerce")
        hidden = int(((mem > 0) & (mem < MEMORY_RESOLUTION_MB)).sum())
        memory = sizes[~(mem < MEMORY_RESOLUTION_MB)]
    out.append(_metric_view("memory", memory, "mem_mb", "peak memory (MiB)", facts, inp,
                            "Rise of the worker&rsquo;s resident peak during one build (the input and the imported "
                            f"libraries excluded). A rise below {MEMORY_RESOLUTION_MB:g} MiB is allocator noise, not "
                            f"the build&rsquo;s own need: it cannot be measured and is not drawn"
                            + (f" ({hidden} point(s) left out)." if hidden else "."),
                            lambda v: f"{float(v):.3g} MiB"))
    return out


# After html_page.BASE_CSS: this page's sizes, its filter bar, panels, matrix and drill-down.
_CSS = """
body { margin: 1.2em 2em 4em; line-height: 1.4; max-width: 1500px; }
h1 { font-size: 1.6em; margin: 0.2em 0; } h2 { font-size: 1.3em; }
h3 { font-size: 1.02em; margin: 0.3em 0; } h2, h3 { scroll-margin-top: 7em; }
table { font-size: 0.88em; margin: 0.4em 0; }
th, td { padding: 2px 7px; }
thead th { background: #f1f1f1; } th[scope=row] { background: #f7f7f7; font-weight: 600; white-space: nowrap; }
table.num td { font-variant-numeric: tabular-nums; }
.legend { color: #555; font-size: 0.9em; }
.legend .others { color: #888; font-size: 0.92em; }
.alert { border: 2px solid #b2182b; background: #fff5f3; padding: 0.5em 1em; margin: 0.8em 0; border-radius: 4px; }
.alert h2 { margin: 0.2em 0; border: 0; color: #b2182b; }
.warn { border-left: 4px solid #e69f00; background: #fffaf0; padding: 0.4em 0.8em; margin: 0.5em 0; }
tr.mismatch td { background: #fde0dc; font-weight: 600; }
.badge { color: #b2182b; font-weight: 600; font-size: 0.92em; }
.bad { color: #b2182b; font-weight: 600; }
nav#filters { position: sticky; top: 0; z-index: 20; background: rgba(255,255,255,0.97); border-bottom: 1px solid #ddd;
              padding: 0.3em 0; display: flex; flex-wrap: wrap; gap: 0.3em 1.2em; align-items: baseline; }
nav#filters fieldset { border: 0; padding: 0; margin: 0; }
nav#filters legend { float: left; font-weight: 600; margin-right: 0.4em; font-size: 0.9em; }
nav#filters label { margin-right: 0.55em; white-space: nowrap; font-size: 0.9em; }
nav#filters button { font-size: 0.75em; padding: 0 0.3em; margin-left: 0.2em; }
.swatch { display: inline-block; width: 0.8em; height: 0.8em; margin: 0 0.25em 0 0.1em; border-radius: 2px; }
.chip { display: inline-block; width: 0.9em; height: 0.9em; margin: 0 0.3em 0 0.6em; border: 1px solid #888;
        vertical-align: -0.1em; }
td .chip { margin-left: 0; }
.panels { display: grid; grid-template-columns: repeat(auto-fill, minmax(400px, 1fr)); gap: 0.6em 1em; }
.panels.single { grid-template-columns: minmax(0, 1fr); }
.panel { border: 1px solid #eee; padding: 0.2em 0.4em; min-width: 0; }
.empty-note { color: #777; font-style: italic; }
table.matrix td { text-align: center; min-width: 6.5em; font-size: 0.9em; }
table.matrix td.notrun { color: #888; background: #fafafa; }
.drill { display: grid; grid-template-columns: minmax(0, 1.3fr) minmax(0, 1fr); gap: 1em; align-items: start; }
table.cases { font-size: 0.82em; } table.cases td { white-space: nowrap; padding: 2px 5px; }
.scroll { max-height: 34em; overflow: auto; border: 1px solid #eee; }
table.cases tbody tr { cursor: pointer; } table.cases tbody tr:hover { background: #f4f8ff; }
table.cases tr.selected td { background: #dbe9ff; }
table.cases thead th { position: sticky; top: 0; }
.tables { display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start; }
#case-view { position: sticky; top: 7em; }
pre { background: #f5f5f5; padding: 0.6em; overflow-x: auto; }
.wide { overflow-x: auto; max-width: 100%; }
@media (max-width: 1000px) { .drill { grid-template-columns: 1fr; } #case-view { position: static; } }
"""

_JS = r"""
(function () {
  'use strict';
  var payload = JSON.parse(document.getElementById('report-data').textContent);
  var figures = payload.figures, template = payload.template;
  var config = {responsive: true, displaylogo: false, modeBarButtonsToRemove: ['select2d', 'lasso2d']};
  var state = {impl: {}, dataset: {}, n: {}};
  var boxes = Array.prototype.slice.call(document.querySelectorAll('#filters input[type=checkbox]'));

  function readState() { boxes.forEach(function (b) { state[b.getAttribute('data-group')][b.value] = b.checked; }); }
  function ok(group, value) { return value === undefined || value === null || state[group][String(value)] !== false; }
  function at(v, i) { return Array.isArray(v) ? v[i] : v; }
  function keep(key, i) { return ok('impl', at(key.impl, i)) && ok('dataset', at(key.dataset, i)) && ok('n', at(key.n, i)); }
  function pick(a, idx) { return Array.isArray(a) ? idx.map(function (i) { return a[i]; }) : a; }

  // A figure's traces with the points the filters leave; how many traces still show something.
  function filtered(fig) {
    var shown = 0;
    var data = JSON.parse(JSON.stringify(fig.data)).map(function (t, k) {
      var key = fig.keys[k] || {};
      var len = -1;
      [key.impl, key.dataset, key.n].forEach(function (v) { if (Array.isArray(v)) len = v.length; });
      if (len < 0) {
        if (keep(key, 0)) { shown += 1; } else { t.visible = false; }
        return t;
      }
      var idx = [];
      for (var i = 0; i < len; i++) { if (keep(key, i)) idx.push(i); }
      ['x', 'y', 'customdata', 'text', 'hovertext'].forEach(function (name) { if (name in t) t[name] = pick(t[name], idx); });
      ['error_x', 'error_y'].forEach(function (name) {
        if (t[name]) { t[name].array = pick(t[name].array, idx); t[name].arrayminus = pick(t[name].arrayminus, idx); }
      });
      if (idx.length) { shown += 1; } else { t.visible = false; }
      return t;
    });
    return {data: data, shown: shown};
  }

  function draw(el) {
    var fig = figures[el.id];
    var f = filtered(fig);
    var panel = el.closest('.panel');
    panel.hidden = f.shown === 0;
    if (panel.hidden) return;
    var layout = JSON.parse(JSON.stringify(fig.layout));
    layout.template = template;
    Plotly.react(el, f.data, layout, config);
    if (!el.getAttribute('data-wired')) {
      el.setAttribute('data-wired', '1');
      el.on('plotly_click', function (ev) {
        var p = ev.points && ev.points[0];
        var cd = p && p.customdata;
        if (Array.isArray(cd) && typeof cd[cd.length - 1] === 'number') { showCase(cd[cd.length - 1], true); }
      });
    }
  }

  function rowVisible(el) {
    var n = el.getAttribute('data-n');
    return ok('impl', el.getAttribute('data-impl')) && ok('dataset', el.getAttribute('data-dataset')) && ok('n', n);
  }

  function apply() {
    readState();
    document.querySelectorAll('.plot').forEach(draw);
    document.querySelectorAll('section.view').forEach(function (s) {
      var any = Array.prototype.some.call(s.querySelectorAll('.panel'), function (p) { return !p.hidden; });
      var note = s.querySelector('.empty-note');
      if (note) note.hidden = any;
    });
    document.querySelectorAll('tr[data-impl], tr[data-dataset]').forEach(function (tr) { tr.hidden = !rowVisible(tr); });
    document.querySelectorAll('table.matrix [data-dataset]').forEach(function (c) {
      c.hidden = !ok('dataset', c.getAttribute('data-dataset'));
    });
  }

  var current = null;
  function showCase(i, scroll) {
    var c = payload.cases[i];
    if (!c) return;
    current = i;
    document.querySelectorAll('.case-detail').forEach(function (d) { d.hidden = d.id !== 'case-' + i; });
    document.querySelectorAll('table.cases tr.selected').forEach(function (r) { r.classList.remove('selected'); });
    var row = document.querySelector('table.cases tr[data-case="' + i + '"]');
    if (row) {
      row.classList.add('selected');
      var box = row.closest('.scroll');          // scroll the table, never the page
      if (box && !row.hidden) box.scrollTop = Math.max(0, row.offsetTop - box.clientHeight / 2);
    }
    var hint = document.getElementById('case-hint');
    if (hint) hint.hidden = true;
    var el = document.getElementById('case-plot-' + i);
    // The build time and each timed part in its own panel, each with its own axis, so every spread shows.
    var traces = [];
    var layout = {template: template, height: 280, margin: {l: 60, r: 10, t: 10, b: 40}, showlegend: false};
    var series = [['build (time_s)', c.times]].concat(c.phases);
    series.forEach(function (s) {
      var ys = [], text = [];
      s[1].forEach(function (v, k) { if (v !== null) { ys.push(v * 1000); text.push('repeat ' + c.repeats[k]); } });
      if (!ys.length) return;
      var k = traces.length + 1;
      traces.push({type: 'box', name: s[0], y: ys, text: text, boxpoints: 'all', jitter: 0.4, pointpos: 0,
                   xaxis: 'x' + k, yaxis: 'y' + k,
                   marker: {size: 6, color: c.color}, line: {color: c.color}, fillcolor: 'rgba(0,0,0,0)',
                   hovertemplate: '%{text}: %{y:.4g} ms<extra>%{fullData.name}</extra>'});
      layout['yaxis' + k] = {title: {text: k === 1 ? 'time (ms)' : ''}};
    });
    layout.grid = {rows: 1, columns: Math.max(1, traces.length), pattern: 'independent', xgap: 0.25};
    if (el && traces.length) { Plotly.react(el, traces, layout, config); }
    if (scroll) { document.getElementById('cases').scrollIntoView({behavior: 'smooth'}); }
  }

  boxes.forEach(function (b) { b.addEventListener('change', apply); });
  document.querySelectorAll('#filters button').forEach(function (btn) {
    btn.addEventListener('click', function () {
      var group = btn.getAttribute('data-all') || btn.getAttribute('data-none');
      var on = btn.hasAttribute('data-all');
      boxes.forEach(function (b) { if (b.getAttribute('data-group') === group) b.checked = on; });
      apply();
    });
  });
  var table = document.querySelector('table.cases');
  if (table) {
    table.addEventListener('click', function (e) {
      var tr = e.target.closest('tr[data-case]');
      if (tr) showCase(+tr.getAttribute('data-case'), false);
    });
    table.addEventListener('keydown', function (e) {
      var tr = e.target.closest('tr[data-case]');
      if (tr && (e.key === 'Enter' || e.key === ' ')) { e.preventDefault(); showCase(+tr.getAttribute('data-case'), false); }
    });
  }
  apply();
  if (payload.first_case !== null) showCase(payload.first_case, false);
})();
"""


def render(inp: PageInput) -> str:
    """The whole page (see the module docstring)."""
    all_views = views(inp)
    figures: dict[str, Any] = {}
    sections = []
    toc = []
    for view in all_views:
        if not view.panels:
            continue                                     # no data, no figure, no placeholder
        anchor = view.key
        toc.append(f'<a href="#{anchor}">{_esc(view.title)}</a>')
        panels = []
        for p in view.panels:
            figures[p.fid] = {"data": p.figure["data"], "layout": p.figure["layout"], "keys": p.keys}
            attr = f' data-dataset="{_esc(p.dataset)}"' if p.dataset is not None else ""
            panels.append(f'<div class="panel"{attr}><h3>{p.heading}</h3>'
                          f'<div class="plot" id="{p.fid}" style="height:{p.height}px"></div></div>')
        sections.append(f'<section class="view" id="{anchor}"><h2>{_esc(view.title)}</h2><p>{view.intro}</p>'
                        f'<div class="panels{" single" if view.single else ""}">{"".join(panels)}</div>'
                        '<p class="empty-note" hidden>Nothing here matches the filters.</p>'
                        f"{view.after}</section>")

    correctness = _correctness(inp)
    if correctness:
        toc.append('<a href="#correctness">Correctness</a>')
    toc += ['<a href="#cases">Cases</a>', '<a href="#failures">Failures</a>', '<a href="#run">Run</a>']

    cases_payload = []
    for c in inp.repeats:
        cases_payload.append({
            "times": c["times"], "repeats": c["repeat_ids"],
            "phases": [[_esc(p), v] for p, v in c["phases"].items()],
            "color": inp.styles.get(c["impl"], {}).get("color", "#444")})
    payload = {"template": _template(), "figures": figures, "cases": cases_payload, "first_case": _first_case(inp)}

    body = [
        f"<h1>vorobench report: {_esc(inp.title)}</h1>",
        f'<p class="note">{_esc(inp.summary)}</p>',
        '<p class="note">' + " &middot; ".join(toc) + "</p>",
        _attention(inp),
        '<h2 id="reading">Reading</h2>', _md_list(inp.reading_md),
        _filters(inp),
        *sections,
    ]
    if correctness:
        body += ['<section id="correctness"><h2>Correctness</h2>', correctness, "</section>"]
    body += [
        '<section id="cases"><h2>Cases</h2><p>Every case (implementation, dataset, n, seed) with its repeats. '
        "Click a row (or a point in a build-time or spread figure) for its repeat distribution, timings and "
        "counters. Range: the fastest and the slowest repeat; spread: (slowest - fastest) / median.</p>",
        '<div class="drill">', _case_rows(inp),
        '<div id="case-view"><p id="case-hint" class="note">Click a case to see its repeats.</p>'
        + "".join(_case_detail(i, c) for i, c in enumerate(inp.repeats)) + "</div>",
        "</div></section>",
        '<section id="failures"><h2>Failures</h2>', _failures(inp), "</section>",
        '<section id="run"><h2>Run</h2>', _run(inp), "</section>",
        '<section id="data"><h2>Data</h2>', _data(inp), "</section>",
    ]
    return page(f"vorobench report: {one_line(inp.title)}", _CSS, "\n".join(body), data_id="report-data",
                data=payload, script=_JS, libraries=[get_plotlyjs()], json_default=_plain)


def _first_case(inp: PageInput) -> Optional[int]:
    """The case the drill-down opens with: the largest size of the worst complexity mismatch, else a failure,
    else none."""
    index = {(c["impl"], c["dataset"], c["n"]): i for i, c in reversed(list(enumerate(inp.repeats)))}
    if not inp.check.empty:
        bad = complexity_mismatches(inp.check)
        if not bad.empty:
            top = bad.iloc[0]
            ns = sorted((c["n"], i) for i, c in enumerate(inp.repeats)
                        if c["impl"] == top["impl"] and c["dataset"] == top["dataset"] and c["times"])
            if ns:
                return ns[-1][1]
    if not inp.failures.empty:
        r = inp.failures.iloc[0]
        return index.get((str(r["impl"]), str(r["dataset"]), int(r["n"])))
    return None
