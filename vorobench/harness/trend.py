"""Trends across the runs of a run store: every case's build time and counters, run after run, with change points found and a self-contained page drawn.

The command line is :mod:`vorobench.cli.trend`; its help text describes the behaviour. Names
and metadata are text on the page, made safe by :mod:`vorobench.harness.html_page`, which also
gives the page its skeleton and common style."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field
from datetime import datetime, timezone
from typing import Any, Optional

import numpy as np
import plotly.graph_objects as go
from plotly.colors import qualitative
from plotly.offline import get_plotlyjs
from plotly.subplots import make_subplots

from vorobench.harness.changepoints import counter_steps, time_steps
from vorobench.harness.html_page import escape, page
from vorobench.harness.results import with_families_in_dataset
from vorobench.harness.timing_rule import choose_measure, measured, noise_half_width
from vorobench.judge.outcomes import Status, counter_columns

__all__ = ["Run", "Series", "Machine", "ChangePoint", "load", "detect", "render",
           "trend_json"]

KEY = ["impl", "dataset", "n", "seed"]

#: Tick labels on a run axis beyond which only every k-th run is labelled.
_MAX_TICKS = 40


@dataclass
class Run:
    """One run of a machine, as the x axis shows it."""

    run_id: str
    date: str
    commit: Optional[str]
    dirty: bool
    #: implementation -> (commit, dirty, module) of its code: a plugin that replaces an
    #: implementation under the same commit is other code
    impl_code: dict[str, tuple[Optional[str], bool, Optional[str]]] = field(default_factory=dict)
    #: the run's place among the machine's runs of the same commit (1, 2, ...), 0 when it is the only one
    repeat_of_commit: int = 0

    @property
    def label(self) -> str:
        """Short commit, ``+`` when the tree was dirty, and ``#2``, ``#3``... for a later run of
        the same commit (so that no two runs share a label); the run id when no commit is known."""
        if not self.commit:
            return self.run_id
        return self.commit[:7] + ("+" if self.dirty else "") + (f" #{self.repeat_of_commit}"
                                                                if self.repeat_of_commit > 1 else "")

    @property
    def when(self) -> str:
        return (self.date or "-")[:19].replace("T", " ")


@dataclass
class Series:
    """One case on one machine: its timings and counters run by run (indexes into the machine's runs)."""

    impl: str
    dataset: str
    n: int
    seed: int
    timed: list[int] = field(default_factory=list)          # runs with at least one ok build time
    times: list[Any] = field(default_factory=list)          # per timed run: the repeats (numpy array)
    failed: dict[int, str] = field(default_factory=dict)    # run -> status, runs where the case did not run ok
    counters: dict[str, list[Optional[int]]] = field(default_factory=dict)   # name -> value per run (None: none)
    steps: list[Any] = field(default_factory=list)          # changepoints.TimeStep, indexes into ``timed``
    counter_changes: dict[str, list[Any]] = field(default_factory=dict)      # name -> changepoints.CounterStep

    @property
    def name(self) -> str:
        return f"{self.impl} {self.dataset} n={self.n} seed={self.seed}"


@dataclass
class Machine:
    """The runs of one machine fingerprint, oldest first, and its series."""

    machine_id: str
    hostname: str
    cpu: str
    runs: list[Run]
    series: list[Series]
    #: what the times are: "cpu" (each build's own CPU time) or "wall"
    measure: str = "wall"


@dataclass
class ChangePoint:
    """A change point of one series, as the table and ``--json`` give it."""

    machine_id: str
    impl: str
    dataset: str
    n: int
    seed: int
    kind: str                         # "time" or "counter"
    counter: Optional[str]            # the counter's name (without ``stat_``) for kind "counter"
    run_id: str                       # the first run after the change
    run_id_before: str                # the run before it (the previous one that has a value)
    commit: Optional[str]
    commit_before: Optional[str]
    dirty: bool
    dirty_before: bool
    date: str
    before: Any                       # time: median seconds of the segment before; counter: value
    after: Any
    ratio: Optional[float]            # after / before
    p_value: Optional[float]          # time: the two-sided Mann-Whitney U p-value
    run_index: int                    # position of run_id among the machine's runs
    #: Both runs were made of the same clean commit of vorobench and of the implementation's code:
    #: the change is the machine's (load, frequency), not the code's.
    same_code: bool = False

    @property
    def case(self) -> str:
        return f"{self.impl} {self.dataset} n={self.n} seed={self.seed}"


# ------------------------------------------------------------------------------ loading


def _int_or_none(value) -> Optional[int]:
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return None
    return int(value)


def load(store, machine: Optional[str] = None, impls: Optional[list[str]] = None,
         datasets: Optional[list[str]] = None, measure: str = "auto") -> list[Machine]:
    """The store's runs per machine fingerprint (prefix ``machine``), with a series per case.
    ``measure``: what a build's time is, chosen per machine as compare chooses it
    (:func:`vorobench.harness.timing_rule.choose_measure`).

    ValueError in one line when the store holds no run (of that machine) or the filters leave
    no result.
    """
    runs = store.runs(machine_id=machine)
    if runs.empty:
        raise ValueError(f"{store.path}: holds no run" + (f" of a machine {machine}*" if machine else "")
                         + "; file runs with `vorobench bench --store`")
    rows = with_families_in_dataset(store.results())     # a weighted case, disks: a dataset of its own
    rows = rows[rows["run_id"].astype(str).isin(set(runs["run_id"].astype(str)))]
    held_impls, held_datasets = sorted(rows["impl"].dropna().unique()), sorted(rows["dataset"].dropna().unique())
    if impls:
        rows = rows[rows["impl"].isin(impls)]
    if datasets:
        rows = rows[rows["dataset"].isin(datasets)]
    if rows.empty:
        wanted = ", ".join(p for p in (f"impls {','.join(impls)}" if impls else "",
                                       f"datasets {','.join(datasets)}" if datasets else "") if p)
        raise ValueError(f"{store.path}: no results" + (f" for {wanted}" if wanted else "")
                         + f" (it holds impls {','.join(held_impls) or 'none'}; "
                         f"datasets {','.join(held_datasets) or 'none'})")
    counters = [c for c in counter_columns(rows.columns) if rows[c].notna().any()]

    runs = runs.assign(machine_key=runs["machine_id"].fillna("").astype(str).replace("", "unknown"))
    machines = []
    for key, group in runs.groupby("machine_key", sort=False):
        machine_runs = []
        for r in group.itertuples(index=False):
            meta = _meta(r.meta)
            code = {str(name): (info.get("commit"), bool(info.get("dirty")), info.get("module"))
                    for name, info in (meta.get("implementations") or {}).items() if isinstance(info, dict)}
            machine_runs.append(Run(str(r.run_id), _text(r.date) or "", _text(r.commit),
                                    bool(r.dirty) if r.dirty == r.dirty and r.dirty is not None else False, code))
        _number_repeats(machine_runs)
        index = {r.run_id: i for i, r in enumerate(machine_runs)}
        mine = rows[rows["run_id"].astype(str).isin(index)]
        column = choose_measure(measure, mine)
        mine = measured(mine, column)
        series = _series_of(mine.assign(_run=mine["run_id"].astype(str).map(index)), len(machine_runs), counters)
        if not series:                  # the filters leave nothing of this machine
            continue
        first = group.iloc[0]
        machines.append(Machine(str(key), _text(first["hostname"]) or "-", _text(first["cpu"]) or "-",
                                machine_runs, series, "cpu" if column == "cpu_s" else "wall"))
    return machines


def _number_repeats(runs: list[Run]) -> None:
    """Number the runs (oldest first) that share a commit label: 1, 2, ... (0 for a single one)."""
    plain = [r.commit[:7] + ("+" if r.dirty else "") if r.commit else None for r in runs]
    seen: dict[str, int] = {}
    for run, key in zip(runs, plain):
        if key is not None and plain.count(key) > 1:
            seen[key] = seen.get(key, 0) + 1
            run.repeat_of_commit = seen[key]


def _text(value) -> Optional[str]:
    """A text cell of the runs table; None for NULL/NaN and empty text."""
    return value if isinstance(value, str) and value else None


def _series_of(rows, n_runs: int, counters: list[str]) -> list[Series]:
    """The series of one machine's rows (column ``_run``: the run's position), one per case, sorted."""
    group = KEY + ["_run"]
    ok = rows[rows["status"] == Status.OK]
    timed = ok[np.isfinite(ok["time_s"].to_numpy(float))].sort_values(group, kind="stable")
    by_case: dict[tuple, Series] = {}

    def series(impl, dataset, n, seed) -> Series:
        key = (str(impl), str(dataset), int(n), int(seed))
        if key not in by_case:
            by_case[key] = Series(*key, counters={c: [None] * n_runs for c in counters})
        return by_case[key]

    if len(timed):
        times = timed["time_s"].to_numpy(float)
        ids = timed.groupby(group, sort=False).ngroup().to_numpy()
        starts = np.flatnonzero(np.r_[True, ids[1:] != ids[:-1]])
        firsts = timed[group].iloc[starts].itertuples(index=False, name=None)
        for (impl, dataset, n, seed, run), chunk in zip(firsts, np.split(times, starts[1:])):
            s = series(impl, dataset, n, seed)
            s.timed.append(int(run))
            s.times.append(chunk)
    if counters and len(ok):
        firsts = ok.groupby(group, sort=False)[counters].first()        # first value present, per column
        for (impl, dataset, n, seed, run), values in zip(firsts.index, firsts.itertuples(index=False, name=None)):
            s = series(impl, dataset, n, seed)
            for c, v in zip(counters, values):
                s.counters[c][int(run)] = _int_or_none(v)
    statuses = rows.groupby(group, sort=False)["status"].first()
    for (impl, dataset, n, seed, run), status in statuses.items():
        s = series(impl, dataset, n, seed)
        if int(run) not in s.timed:
            s.failed[int(run)] = str(status) if isinstance(status, str) else "no time"
    out = []
    for key in sorted(by_case):
        s = by_case[key]
        s.counters = {c[len("stat_"):]: v for c, v in s.counters.items() if any(x is not None for x in v)}
        out.append(s)
    return out


def _meta(text) -> dict:
    try:
        meta = json.loads(text or "{}")
    except (TypeError, json.JSONDecodeError):
        return {}
    return meta if isinstance(meta, dict) else {}


# ------------------------------------------------------------------------------ detection


def detect(machines: list[Machine], threshold: float = 0.10, alpha: float = 0.05) -> list[ChangePoint]:
    """Find every series' change points (filling ``steps`` and ``counter_changes``); return
    them all, by machine, then case, then run."""
    found = []
    for m in machines:
        band = _noise_between(m)
        for s in m.series:
            s.steps = time_steps(s.times, threshold=threshold, alpha=alpha,
                                 noise=lambda k, s=s: band(s.timed[k - 1], s.timed[k]))
            for step in s.steps:
                i, j = s.timed[step.index], s.timed[step.index - 1]
                found.append(_point(m, s, "time", None, i, j, step.before, step.after, step.ratio, step.p_value))
            s.counter_changes = {}
            for name, values in s.counters.items():
                changes = counter_steps(values)
                if changes:
                    s.counter_changes[name] = changes
                for c in changes:
                    ratio = c.after / c.before if c.before else None
                    found.append(_point(m, s, "counter", name, c.index, c.previous_index, c.before, c.after,
                                        ratio, None))
    return found


def _noise_between(m: Machine):
    """band(j, i): the run-to-run noise between the machine's runs j and i, from the ratios of
    every case timed in both (:func:`vorobench.harness.timing_rule.noise_half_width`, as
    ``compare`` measures it), cached."""
    medians = [{run: float(np.median(t)) for run, t in zip(s.timed, s.times)} for s in m.series]
    cache: dict[tuple[int, int], Optional[float]] = {}

    def band(j: int, i: int) -> Optional[float]:
        if (j, i) not in cache:
            cache[(j, i)] = noise_half_width([med[i] / med[j] for med in medians if i in med and j in med and med[j] > 0])
        return cache[(j, i)]
    return band


def _point(m: Machine, s: Series, kind: str, counter: Optional[str], i: int, j: int, before, after,
           ratio, p) -> ChangePoint:
    run, prev = m.runs[i], m.runs[j]
    same = bool(run.commit) and run.commit == prev.commit and not (run.dirty or prev.dirty) and \
        run.impl_code.get(s.impl) == prev.impl_code.get(s.impl) and not run.impl_code.get(s.impl, (None, False, None))[1]
    return ChangePoint(m.machine_id, s.impl, s.dataset, s.n, s.seed, kind, counter, run.run_id, prev.run_id,
                       run.commit, prev.commit, run.dirty, prev.dirty, run.date, before, after, ratio, p, i, same)


def trend_json(store_path: str, machines: list[Machine], points: list[ChangePoint], threshold: float,
               alpha: float) -> dict[str, Any]:
    """What ``--json`` writes: the rule's parameters, the machines, and every change point."""
    return {
        "store": store_path, "threshold": threshold, "alpha": alpha,
        "machines": [{"machine_id": m.machine_id, "hostname": m.hostname, "cpu": m.cpu, "runs": len(m.runs),
                      "first_run": m.runs[0].run_id, "last_run": m.runs[-1].run_id} for m in machines],
        "series": sum(len(m.series) for m in machines),
        "change_points": [asdict(p) for p in points],
    }


# ------------------------------------------------------------------------------ the page


def format_seconds(x: float) -> str:
    if x is None or not math.isfinite(x):
        return "-"
    if x < 1e-3:
        return f"{x * 1e6:.3g} µs"
    return f"{x * 1e3:.3g} ms" if x < 1 else f"{x:.3g} s"


def _pct(ratio: Optional[float]) -> str:
    if ratio is None or not math.isfinite(ratio):
        return "-"
    change = (ratio - 1) * 100
    digits = 0 if abs(change) >= 10 else 1 if abs(change) >= 1 else 3
    return f"{change:+.{digits}f} %"


def _impl_note(run: Run, impl: str) -> str:
    commit, dirty, _ = run.impl_code.get(impl, (None, False, None))
    if not commit or commit == run.commit:
        return ""
    return f"<br>{escape(impl)} code at {escape(commit[:10])}{'+' if dirty else ''}"


def _figure(m: Machine, impl: str, dataset: str, series: list[Series]) -> tuple[Any, int]:
    """The plotly figure of one implementation and dataset on one machine, and its height."""
    changed = [(s, name) for s in series for name in s.counter_changes]
    rows = 2 if changed else 1
    height = 660 if rows == 2 else 430
    fig = make_subplots(rows=rows, cols=1, shared_xaxes=True, vertical_spacing=0.06,
                        row_heights=[0.6, 0.4] if rows == 2 else None)
    several_seeds = len({s.seed for s in series}) > 1
    colours = qualitative.Plotly
    for k, s in enumerate(series):
        colour = colours[k % len(colours)]
        label = escape(f"n={s.n}" + (f" seed={s.seed}" if several_seeds else ""))
        med = np.array([np.median(t) for t in s.times])
        lo = np.array([t.min() for t in s.times])
        hi = np.array([t.max() for t in s.times])
        custom = []
        for i, md, a, b, t in zip(s.timed, med, lo, hi, s.times):
            run = m.runs[i]
            commit = (run.commit or "no commit") + (" (dirty)" if run.dirty else "")
            custom.append([escape(run.when), escape(run.run_id), escape(commit),
                           format_seconds(md), format_seconds(a), format_seconds(b), int(t.size), _impl_note(run, s.impl)])
        fig.add_trace(go.Scatter(
            x=s.timed, y=med, mode="lines+markers", name=label, legendgroup=label, line=dict(color=colour),
            error_y=dict(type="data", symmetric=False, array=hi - med, arrayminus=med - lo, thickness=1, width=3),
            customdata=custom,
            hovertemplate=("<b>%{customdata[2]}</b><br>%{customdata[0]}<br>run %{customdata[1]}<br>"
                           "median %{customdata[3]}, min %{customdata[4]} - max %{customdata[5]} "
                           "(%{customdata[6]} repeats)%{customdata[7]}<extra>" + label + "</extra>")), row=1, col=1)
        if s.steps:
            xs = [s.timed[st.index] for st in s.steps]
            ys = [med[st.index] for st in s.steps]
            text = [f"<b>time step at {escape(m.runs[x].label)}</b> ({label})<br>{format_seconds(st.before)} \u2192 "
                    f"{format_seconds(st.after)}: {st.ratio:.2f}x ({_pct(st.ratio)}), p={st.p_value:.2g}"
                    for x, st in zip(xs, s.steps)]
            fig.add_trace(go.Scatter(x=xs, y=ys, mode="markers", name=f"{label} step", legendgroup=label,
                                     showlegend=False, hovertext=text, hoverinfo="text",
                                     marker=dict(symbol="star", size=15, color=colour,
                                                 line=dict(color="black", width=1))), row=1, col=1)
    dash = ["solid", "dot", "dash", "dashdot", "longdash"]
    for k, s in enumerate(series):
        colour = colours[k % len(colours)]
        label = escape(f"n={s.n}" + (f" seed={s.seed}" if several_seeds else ""))
        for c, name in enumerate(sorted(s.counter_changes)):
            values = s.counters[name]
            xs = [i for i, v in enumerate(values) if v is not None]
            first = values[xs[0]]
            ys = [values[i] / first if first else values[i] for i in xs]
            custom = [[escape(m.runs[i].label), f"{values[i]:,}"] for i in xs]
            fig.add_trace(go.Scatter(
                x=xs, y=ys, mode="lines+markers", line=dict(color=colour, dash=dash[c % len(dash)], shape="hv"),
                name=f"{label} {escape(name)}", legendgroup=label, customdata=custom,
                hovertemplate=f"{escape(name)} = %{{customdata[1]}}<br>at %{{customdata[0]}}<extra>{label}</extra>"),
                row=2, col=1)
    _mark_changes(fig, m, series, rows)
    ticks = list(range(len(m.runs)))
    step = max(1, math.ceil(len(ticks) / _MAX_TICKS))
    shown = ticks[::step]
    fig.update_xaxes(tickmode="array", tickvals=shown, ticktext=[escape(m.runs[i].label) for i in shown],
                     range=[-0.5, len(m.runs) - 0.5], tickangle=-45 if len(shown) > 12 else 0,
                     showgrid=False, zeroline=False)
    fig.update_xaxes(title_text="run (vorobench commit; + dirty)", row=rows, col=1)
    values = [v for s in series for r in s.times for v in (r.min(), r.max()) if v > 0]
    axis: dict[str, Any] = {}
    if values:
        low, high = _time_span(min(values), max(values))
        tickvals = _time_ticks(low, high)
        axis = dict(range=[math.log10(low), math.log10(high)], autorange=False)
        if len(tickvals) >= 2:
            axis.update(tickmode="array", tickvals=tickvals, ticktext=[format_seconds(v) for v in tickvals])
    fig.update_yaxes(type="log", title_text="build time: median, bars min-max", row=1, col=1, **axis)
    if rows == 2:
        fig.update_yaxes(title_text="counter / first value", tickformat=".4~f", row=2, col=1)
    fig.update_layout(height=height, margin=dict(l=80, r=20, t=50, b=70), hovermode="closest",
                      legend=dict(groupclick="togglegroup"))
    return fig, height


#: The time axis spans at least this factor, so that a few percent of noise looks like noise.
_MIN_SPAN = 1.6


def _time_span(low: float, high: float) -> tuple[float, float]:
    """The range of a log time axis showing [low, high]: 5 % padding, and at least ``_MIN_SPAN`` wide."""
    low, high = low / 1.05, high * 1.05
    if high / low < _MIN_SPAN:
        centre, half = math.sqrt(low * high), math.sqrt(_MIN_SPAN)
        low, high = centre / half, centre * half
    return low, high


def _time_ticks(low: float, high: float) -> list[float]:
    """Round times (1-2-5 per decade, finer for a narrow range) spanning [low, high], for a log axis."""
    for mantissas in ((1, 2, 5), (1, 1.5, 2, 3, 5, 7), (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 7, 8, 9)):
        ticks = [m * 10.0 ** e for e in range(math.floor(math.log10(low)) - 1, math.ceil(math.log10(high)) + 1)
                 for m in mantissas]
        inside = [v for v in ticks if low * 0.97 <= v <= high * 1.03]
        if len(inside) >= 3:
            break
    if len(inside) > 12:                       # many decades: label the decades only
        inside = [v for v in inside if math.isclose(10 ** round(math.log10(v)), v)]
    return [float(f"{v:.3g}") for v in inside]


def _mark_changes(fig, m: Machine, series: list[Series], rows: int) -> None:
    """A vertical line between the runs of each change, labelled with the commit after it."""
    kinds: dict[int, set[str]] = {}
    for s in series:
        for st in s.steps:
            kinds.setdefault(s.timed[st.index], set()).add("time")
        for changes in s.counter_changes.values():
            for c in changes:
                kinds.setdefault(c.index, set()).add("counter")
    for k, (i, what) in enumerate(sorted(kinds.items())):
        colour = "#d62728" if "time" in what else "#ff7f0e"
        fig.add_shape(type="line", xref="x", yref="paper", x0=i - 0.5, x1=i - 0.5, y0=0, y1=1,
                      line=dict(color=colour, width=1.5, dash="dash"))
        fig.add_annotation(xref="x", yref="y domain", x=i - 0.5, y=1, yanchor="bottom", xanchor="center",
                           yshift=2 + 15 * (k % 2),
                           text=escape(m.runs[i].label) + (" (time)" if what == {"time"} else " (counters)"
                                                         if what == {"counter"} else " (time, counters)"),
                           showarrow=False, font=dict(size=11, color=colour), bgcolor="rgba(255,255,255,0.85)")


# After html_page.BASE_CSS: this page's sizes, its change tables, figures and jump bar.
_CSS = """
body { margin: 1.5em 2em; }
h1 { font-size: 1.5em; margin-bottom: 0.2em; }
h3 { margin: 1.4em 0 0.2em; font-size: 1.1em; }
table { font-size: 0.9em; margin: 0.5em 0; }
th, td { padding: 3px 8px; }
th { background: #f3f3f3; } td.num { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
td.nowrap { white-space: nowrap; }
tr.time td.kind { color: #d62728; font-weight: 600; } tr.counter td.kind { color: #e36c00; font-weight: 600; }
.slower { color: #b00; } .faster { color: #070; }
.scroll { max-height: 28em; overflow: auto; display: inline-block; }
code { font-size: 0.95em; }
.plot { width: 100%; min-width: 600px; }
nav { position: sticky; top: 0; background: #fff; padding: 0.4em 0; border-bottom: 1px solid #eee; z-index: 10; }
details { margin: 0.3em 0 1em; } summary { cursor: pointer; color: #333; }
h2, h3 { scroll-margin-top: 3em; }      /* an anchor's heading is not hidden under the sticky nav */
"""

_JS = """
(function () {
  var figs = JSON.parse(document.getElementById('trend-figures').textContent);
  var template = figs.template;
  function draw(el) {
    if (el.getAttribute('data-drawn')) return;
    el.setAttribute('data-drawn', '1');
    var f = figs.figures[el.id];
    f.layout.template = template;
    Plotly.newPlot(el, f.data, f.layout, {responsive: true, displaylogo: false});
  }
  var plots = Array.prototype.slice.call(document.querySelectorAll('.plot'));
  if ('IntersectionObserver' in window) {
    var seen = new IntersectionObserver(function (entries) {
      entries.forEach(function (e) { if (e.isIntersecting) { seen.unobserve(e.target); draw(e.target); } });
    }, {rootMargin: '800px 0px'});
    plots.forEach(function (el) { seen.observe(el); });
  } else {
    plots.forEach(draw);
  }
  var jump = document.getElementById('jump');
  if (jump) jump.addEventListener('change', function () { if (jump.value) location.hash = jump.value; });
  var only = document.getElementById('only-changes');
  if (only) only.addEventListener('change', function () {
    document.querySelectorAll('section.figure').forEach(function (s) {
      s.style.display = only.checked && s.getAttribute('data-changes') === '0' ? 'none' : '';
    });
  });
})();
"""


def _change_table(points: list[ChangePoint], anchors: dict[tuple, str], machines: list[Machine]) -> str:
    """Two tables: the time steps, then the counter changes (those of one case at one run in one row)."""
    if not points:
        return "<p><b>No change point</b> in any series.</p>"
    several = len(machines) > 1

    def start(p: ChangePoint) -> str:
        anchor = anchors.get((p.machine_id, p.impl, p.dataset), "")
        return (f'<tr class="{p.kind}">' + (f"<td>{escape(p.machine_id)}</td>" if several else "")
                + f'<td><a href="#{anchor}-title">{escape(p.case)}</a></td>'
                f'<td class="nowrap" title="runs {escape(p.run_id_before)} &rarr; {escape(p.run_id)}">'
                f"{escape(run_label(p.commit_before, p.dirty_before, p.run_id_before))} &rarr; "
                f"{escape(run_label(p.commit, p.dirty, p.run_id))}"
                + (' <span class="note" title="both runs were made of the same clean code: the machine changed">'
                   "(same code)</span>" if p.same_code else "") + "</td>")

    def head(*columns: str) -> str:
        return ('<div class="scroll"><table><thead><tr>' + ("<th>machine</th>" if several else "")
                + "<th>case</th><th>commit before &rarr; commit</th>" + "".join(f"<th>{c}</th>" for c in columns)
                + "</tr></thead><tbody>")

    def date(p: ChangePoint) -> str:
        return f'<td class="nowrap">{escape(p.date[:19].replace("T", " "))}</td>'

    order = lambda p: (p.machine_id, p.run_index, p.impl, p.dataset, p.n, p.seed)   # noqa: E731
    out = []
    steps = sorted((p for p in points if p.kind == "time"), key=order)
    if steps:
        out.append(f"<h3>Build time steps ({len(steps)})</h3>")
        out.append(head("before &rarr; after", "ratio", "change", "p", "date"))
        for p in steps:
            out.append(start(p) + f'<td class="num">{format_seconds(p.before)} &rarr; {format_seconds(p.after)}</td>'
                       f'<td class="num">{p.ratio:.2f}</td><td class="num"><span class="'
                       f'{"slower" if p.ratio > 1 else "faster"}">{_pct(p.ratio)}</span></td>'
                       f'<td class="num">{p.p_value:.2g}</td>' + date(p) + "</tr>")
        out.append("</tbody></table></div>")
    groups: dict[tuple, list[ChangePoint]] = {}
    for p in sorted((p for p in points if p.kind == "counter"), key=order):
        groups.setdefault((p.machine_id, p.case, p.run_index), []).append(p)
    if groups:
        count = sum(len(g) for g in groups.values())
        out.append(f"<h3>Counter changes ({count}, exact)</h3>")
        out.append(head("counter", "before &rarr; after", "change", "date"))
        for group in groups.values():
            p = group[0]
            out.append(start(p) + '<td class="kind">' + "<br>".join(escape(g.counter) for g in group) + "</td>"
                       '<td class="num">' + "<br>".join(f"{g.before} &rarr; {g.after}" for g in group) + "</td>"
                       '<td class="num">' + "<br>".join(_pct(g.ratio) for g in group) + "</td>" + date(p) + "</tr>")
        out.append("</tbody></table></div>")
    return "\n".join(out)


def run_label(commit: Optional[str], dirty: bool, run_id: str) -> str:
    return (commit[:7] + ("+" if dirty else "")) if commit else run_id


def _counter_table(m: Machine, series: list[Series]) -> str:
    lines, changed_total, total = [], 0, 0
    for s in series:
        for name, values in sorted(s.counters.items()):
            total += 1
            present = [v for v in values if v is not None]
            changes = s.counter_changes.get(name, [])
            changed_total += bool(changes)
            text = "; ".join(f"at {escape(m.runs[c.index].label)}: {c.before:,} &rarr; {c.after:,} "
                             f"({_pct(c.after / c.before if c.before else None)})" for c in changes) or "constant"
            lines.append(f'<tr class="{"counter" if changes else ""}"><td>n={s.n} seed={s.seed}</td>'
                         f'<td class="kind">{escape(name)}</td><td class="num">{present[0]:,}</td>'
                         f'<td class="num">{present[-1]:,}</td><td>{text}</td></tr>')
    if not total:
        return '<p class="note">No counters recorded.</p>'
    runs = len(m.runs)
    summary = (f"counters: {changed_total} of {total} changed" if changed_total
               else f"counters: {'the one counter is' if total == 1 else f'all {total} are'} constant over the "
                    f"{runs} runs")
    return (f"<details{' open' if changed_total else ''}><summary>{summary}</summary><table><thead><tr>"
            "<th>case</th><th>counter</th><th>first</th><th>last</th><th>changes</th></tr></thead><tbody>"
            + "\n".join(lines) + "</tbody></table></details>")


def _failures(m: Machine, series: list[Series]) -> str:
    notes = [f"n={s.n} seed={s.seed}: " + ", ".join(f"{escape(m.runs[i].label)} ({escape(status)})"
                                                     for i, status in sorted(s.failed.items()))
             for s in series if s.failed]
    if not notes:
        return ""
    return '<p class="note">Runs without a build time (not drawn): ' + "; ".join(notes) + "</p>"


def render(store_path: str, machines: list[Machine], points: list[ChangePoint], threshold: float,
           alpha: float) -> str:
    """The whole page (see the module docstring)."""
    figures: dict[str, Any] = {}
    template = None
    anchors: dict[tuple, str] = {}
    sections, options = [], []
    for mi, m in enumerate(machines):
        groups: dict[tuple[str, str], list[Series]] = {}
        for s in m.series:
            groups.setdefault((s.impl, s.dataset), []).append(s)
        period = f"{m.runs[0].when} to {m.runs[-1].when}" if len(m.runs) > 1 else m.runs[0].when
        sections.append(f'<h2 id="machine-{mi}">Machine {escape(m.machine_id)} <span class="note">'
                        f"({escape(m.hostname)}, {escape(m.cpu)}): {len(m.runs)} run{'s' if len(m.runs) != 1 else ''}, "
                        f"{escape(period)}</span></h2>")
        options.append(f'<optgroup label="machine {escape(m.machine_id)} ({escape(m.hostname)})">')
        for fi, ((impl, dataset), series) in enumerate(sorted(groups.items())):
            fid = f"fig-{mi}-{fi}"
            anchors[(m.machine_id, impl, dataset)] = fid
            fig, height = _figure(m, impl, dataset, series)
            data = json.loads(fig.to_json())
            template = template or data["layout"].pop("template", None)
            data["layout"].pop("template", None)
            figures[fid] = data
            count = sum(len(s.steps) for s in series) + sum(
                len(c) for s in series for c in s.counter_changes.values())
            badge = f" &mdash; {count} change point{'s' if count != 1 else ''}" if count else ""
            sections.append(
                f'<section class="figure" data-changes="{count}"><h3 id="{fid}-title">{escape(impl)} on '
                f"{escape(dataset)}{badge}</h3>"
                f'<div class="plot" id="{fid}" style="height:{height}px"></div>'
                + _failures(m, series) + _counter_table(m, series) + "</section>")
            options.append(f'<option value="{fid}-title">{escape(impl)} on {escape(dataset)}'
                           f"{' (' + str(count) + ')' if count else ''}</option>")
        options.append("</optgroup>")

    n_time = sum(p.kind == "time" for p in points)
    n_counter = sum(p.kind == "counter" for p in points)
    runs = sum(len(m.runs) for m in machines)
    generated = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    head = (f"<h1>Trend of <code>{escape(store_path)}</code></h1>"
            f'<p class="note">{runs} runs on {len(machines)} machine{"s" if len(machines) != 1 else ""}, '
            f"{sum(len(m.series) for m in machines)} series (implementation, dataset, n, seed); generated "
            f"{generated}. Machines are kept apart: each has its own section and its own sequence of runs.</p>"
            f"<h2>Change points: {n_time} in build time, {n_counter} in counters</h2>"
            f'<p class="note">Build time: binary segmentation of the log median time of each run; a step is kept '
            f"when the medians of the repeats on its two sides differ by more than {threshold:.0%} and a "
            f"two-sided Mann-Whitney U test of those repeats gives p &lt; {alpha:g}. Counters are exact: every "
            f"change is listed. The commit is vorobench&rsquo;s (<code>+</code>: dirty tree); hover a commit "
            f"for its run ids. <i>Same code</i>: both runs were made of the same clean commit, so the step "
            f"is the machine&rsquo;s (load, clock), not the code&rsquo;s.</p>")
    nav = ('<nav><label>Go to <select id="jump"><option value="">(a figure)</option>' + "".join(options)
           + '</select></label> &nbsp; <label><input type="checkbox" id="only-changes"> only figures with '
           "change points</label></nav>")
    body = head + _change_table(points, anchors, machines) + nav + "\n".join(sections)
    return page(f"vorobench trend: {store_path}", _CSS, body, data_id="trend-figures",
                data={"template": template, "figures": figures}, script=_JS, libraries=[get_plotlyjs()])
