"""Run benchmark cases, each in a sandbox of its own, and turn every outcome into rows.

A case is one (implementation, dataset, n, seed, weight or radius family): with a weight family
(``bench --weights``) it times the power diagram of the dataset's points, with a radius family
(``bench --radii``) the diagram of the disks centred at them (docs/apollonius.md; a case has one
family or none, :mod:`vorobench.harness.site_attributes`), and an implementation that does not
take weights, or disks, is recorded as ``unsupported`` without being started. Its sandbox
(:class:`vorobench.judge.sandbox.Sandbox`, the one judging uses, serving the requests of
:mod:`vorobench.harness.worker`) is a fresh process, so a hard crash (segfault, ``os._exit``), a
hang or running out of memory ends that case only: the runner records the status and goes on.
Sandboxes are forked from a ``forkserver`` that has imported numpy, scipy, numba and
vorobench's own implementations once (never a plugin: a plugin is loaded in the sandbox of its
implementation only); ``start_method="spawn"`` gives a brand-new interpreter per case instead.
``timeout`` bounds each timed repeat; start-up and the warm-up, which may include JIT
compilation, have their own allowance. Every repeat's diagram is judged here
(:mod:`vorobench.harness.repeat_check`). Rows of each finished case go to ``sink`` before the
next case starts.
"""

from __future__ import annotations

import datetime as _dt
import multiprocessing as mp
import math
import os
import socket
import time
from dataclasses import asdict, dataclass, field
from typing import Callable, Iterable, Optional, Sequence

import numpy as np
from rich.console import Console
from rich.progress import BarColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn, TimeRemainingColumn

import datasets_gen
import impls
from vorobench.harness.analysis import declared_exponent, loglog_fit
from vorobench.harness.executors import LOCAL, parse_spec, run_tasks
from vorobench.harness.results import case_key, dataset_label
from vorobench.harness.site_attributes import RADII, WEIGHTS, SiteAttribute, attribute_of, generate_input, keywords
from vorobench.harness.repeat_check import RepeatJudging, reference_result, repeat_shifts
from vorobench.harness.worker import MAX_REPEAT, prepare_timing, timed_repeat
from vorobench.judge import wire
from vorobench.judge.declarations import Declaration
from vorobench.judge.engine import diagram_schema, shared_judge
from vorobench.judge.isolation import default_start_method
from vorobench.judge.outcomes import COUNTER_PREFIX, OutcomeKind, Status, Verdict, status_rank, verdict_rank
from vorobench.judge.sandbox import Sandbox

__all__ = ["Case", "RunConfig", "CaseOutcome", "plan_cases", "run_case", "run_case_in_process", "run_cases",
           "exit_status", "case_input", "case_row"]

#: Allowance for starting the worker, importing, and generating the input (not the impl's time).
STARTUP_TIMEOUT = 180.0



@dataclass(frozen=True)
class Case:
    """One benchmark case; ``weights``: the weight family of a power-diagram case, ``radii``: the
    radius family of a case of disks ("" for none; a case has one or neither)."""

    impl: str
    dataset: str
    n: int
    seed: int = 0
    weights: str = ""
    radii: str = ""

    def __post_init__(self) -> None:
        attribute_of(self.weights, self.radii)         # both: refused

    @property
    def attribute(self) -> tuple[Optional[SiteAttribute], str]:
        """(what the sites carry, its family), (None, "") for points."""
        return attribute_of(self.weights, self.radii)

    @property
    def label(self) -> str:
        """The dataset named with its weight or radius family, as results name it."""
        return dataset_label(self.dataset, self.weights, self.radii)

    @property
    def key(self) -> tuple[str, str, int, int]:
        """(impl, dataset, n, seed), the dataset named with its weight or radius family if any (as
        :func:`~vorobench.harness.results.case_key` names a row's)."""
        return (self.impl, self.label, self.n, self.seed)

    @property
    def history_key(self) -> tuple[str, str, int]:
        """The case without its size: the smaller sizes it is extrapolated from share it."""
        return (self.impl, self.label, self.seed)

    def __str__(self) -> str:
        attribute, family = self.attribute
        carried = f" {attribute.name}={family}" if attribute else ""
        return f"{self.impl} {self.dataset}{carried} n={self.n} seed={self.seed}"


@dataclass(frozen=True)
class RunConfig:
    """How every case of a run is measured."""

    repeat: int = 3
    min_time: float = 0.0               # repeat short builds until this many seconds are timed
    timeout: float = 60.0               # seconds per repeat and for the check
    warmup_timeout: float = 300.0       # seconds for the warm-up (JIT compilation included)
    reference: Optional[str] = impls.DEFAULT_REFERENCE
    check: bool = True
    plugins: tuple[str, ...] = ()
    #: (name, Declaration) of every implementation of the run, read in a sandbox and pinned.
    declarations: tuple = ()
    memory_limit_mb: Optional[float] = None
    budget: Optional[float] = None      # skip a case whose extrapolated build time exceeds this
    start_method: str = field(default_factory=default_start_method)
    run_id: str = field(default_factory=lambda: _dt.datetime.now().strftime("%Y%m%dT%H%M%S-") + os.urandom(2).hex())

    def declaration(self, impl: str) -> Optional[Declaration]:
        """``impl``'s declaration pinned for the run (read now, in a sandbox, if the run has none)."""
        found = dict(self.declarations).get(impl)
        if found is None:
            found = shared_judge([], impl, plugins=self.plugins).declaration(impl)
        return found

    def allowance(self, step: str) -> float:
        """Seconds the worker may spend in ``step`` before the case counts as hung."""
        if step in ("startup", "generate"):
            return max(STARTUP_TIMEOUT, self.timeout)
        if step == "warmup":
            return max(self.warmup_timeout, self.timeout)
        return self.timeout


@dataclass
class CaseOutcome:
    """What a finished case produced: its status and its rows (one per repeat, or one)."""

    case: Case
    status: str
    rows: list[dict]
    seconds: float

    @property
    def median_time(self) -> Optional[float]:
        times = sorted(r["time_s"] for r in self.rows if r.get("time_s") is not None)
        if not times:
            return None
        mid = len(times) // 2
        return times[mid] if len(times) % 2 else 0.5 * (times[mid - 1] + times[mid])

    @property
    def verdict(self) -> Optional[str]:
        return self.rows[0].get("verdict") if self.rows else None

    @property
    def error(self) -> Optional[str]:
        return self.rows[0].get("error") if self.rows else None


def _distinct_sizes(dataset: str, sizes: Sequence[int]) -> list[int]:
    """The sizes that give different inputs: a dataset that caps its size (cocircular points
    on one circle) gives the same points for every larger n, so only the first is kept."""
    kept, seen = [], set()
    for n in sorted(set(sizes)):
        try:
            actual = datasets_gen.actual_n(dataset, n)
        except Exception:  # unknown here: the worker will report it
            actual = ("n", n)
        if actual not in seen:
            seen.add(actual)
            kept.append(n)
    return kept


def plan_cases(impls: Sequence[str], datasets: Sequence[str], sizes: Sequence[int],
               seeds: Sequence[int], reference: Optional[str] = None, weights: str = "",
               radii: str = "") -> list[Case]:
    """All combinations, smallest n first: an interrupted run has covered every pair early,
    and a size is only reached after the smaller ones it is extrapolated from. Within a
    (size, dataset, seed) the reference comes last, so it knows whether anyone needs it.
    ``weights``: the weight family of every case, ``radii`` the radius family ("" for ordinary
    diagrams; one of them at most)."""
    attribute_of(weights, radii)                        # both: refused before anything is planned
    ordered = [i for i in impls if i != reference] + [i for i in impls if i == reference]
    per_dataset = {d: set(_distinct_sizes(d, sizes)) for d in datasets}
    return [Case(i, d, n, s, weights or "", radii or "") for n in sorted(set(sizes)) for d in datasets
            if n in per_dataset[d] for s in seeds for i in ordered]


def case_input(case: Case) -> tuple[np.ndarray, Optional[np.ndarray]]:
    """(sites, site weights or radii or None) of a case, generated and prepared as its worker does."""
    attribute, family = case.attribute
    _, sites, values = generate_input(case.dataset, case.n, case.seed, attribute, family)
    return sites, values


def _reference_of(case: Case, config: RunConfig, sites: np.ndarray, values: Optional[np.ndarray]):
    """The reference's judged build of the case's input (with its weights or radii), in a sandbox
    of the judging engine, kept in this process as arrays and a certificate."""
    key = (config.reference, case.dataset, case.n, case.seed, case.weights, case.radii)

    def build():
        judge = shared_judge([], config.reference, timeout=config.timeout, warmup_timeout=config.warmup_timeout,
                             memory_limit_mb=config.memory_limit_mb, plugins=config.plugins,
                             declarations=config.declarations)
        return judge.build(config.reference, sites, **keywords(case.attribute[0], values))

    return reference_result(key, build)


#: What a sandbox may report of a case's set-up and of each repeat: anything else is dropped.
_SETUP_KEYS = ("rss_base_mb", "setup_s", "n_points", "warmup_s")
_REPEAT_KEYS = ("time_s", "cpu_s", "peak_rss_mb", "mem_mb", "input_scale_log2")

#: A sandbox's failure (``Outcome.kind``) as the case's status.
_STATUS_OF = {OutcomeKind.CRASHED: Status.CRASHED, OutcomeKind.TIMEOUT: Status.TIMEOUT, OutcomeKind.OOM: Status.OOM,
              OutcomeKind.ERROR: Status.ERROR}


def _numbers(payload, keys: Sequence[str], phases: bool = False, counters: bool = False) -> dict:
    """The numbers of ``payload`` under ``keys`` (and phase timings ``time_<phase>_s``, counters
    ``stat_<name>`` by their prefix when asked): all the judge takes of what an
    implementation's process says."""
    if not isinstance(payload, dict):
        return {}
    return {k: v for k, v in payload.items() if type(v) in (int, float) and (
        k in keys or (counters and k.startswith(COUNTER_PREFIX))
        or (phases and k.startswith("time_") and k.endswith("_s")))}


def _failure(outcome, info: dict) -> str:
    """Record a sandbox's failed request in ``info``; the case's status."""
    info["error"] = wire.clean_text(outcome.message, 500)
    if outcome.kind == OutcomeKind.ERROR and outcome.message.startswith("InputMutated"):
        info["verdict"] = Verdict.MUTATED_INPUT
    elif outcome.kind == OutcomeKind.ERROR and outcome.message.startswith("InvalidOutput"):
        info["verdict"] = Verdict.INVALID_OUTPUT      # an executable's answer the protocol refuses
    return _STATUS_OF.get(outcome.kind, Status.CRASHED)


def _builds_to_time(config: RunConfig, index: int, timed_s: float) -> bool:
    """Whether build ``index`` is timed: at least ``repeat`` builds; short ones are repeated
    until ``min_time`` seconds are timed (at most ``MAX_REPEAT``)."""
    return index < config.repeat or (timed_s < (config.min_time or 0.0) and index < MAX_REPEAT)


class _InProcess:
    """The sandbox's interface, run in this process (a daemonic Dask worker, which may not start
    processes: no per-request timeout, no memory cap, and a hard crash takes the worker down,
    which the executor records). ``plugin``: loaded here, since nowhere else can."""

    def __init__(self, plugin: str = "") -> None:
        self.plugin = plugin

    def start(self):
        from impls.plugins import load_plugin
        from vorobench.judge.sandbox import Outcome, safe_message

        try:
            if self.plugin:
                load_plugin(self.plugin)
        except Exception as exc:  # noqa: BLE001 - a plugin that cannot load here fails its case
            return Outcome(OutcomeKind.ERROR, message=safe_message(exc))
        return None

    def call(self, fn, *args, timeout=None, step="", schema=None):
        from vorobench.judge.sandbox import Outcome, safe_message

        try:
            return Outcome(OutcomeKind.OK, fn(*args))
        except MemoryError as exc:
            return Outcome(OutcomeKind.OOM, message=f"MemoryError: {exc}")
        except Exception as exc:  # noqa: BLE001 - the implementation's failure, as a sandbox reports it
            return Outcome(OutcomeKind.ERROR, message=safe_message(exc))

    def close(self) -> None:
        return None


def run_case(case: Case, config: RunConfig, on_step: Optional[Callable[[str], None]] = None,
             in_process: bool = False) -> CaseOutcome:
    """Run one case in a fresh sandbox (the one judging uses: its plugin loaded there alone) and
    return its rows, whatever happens to it; every repeat's diagram is judged here, in the
    judge's process. ``in_process``: build in this process instead (see :class:`_InProcess`)."""
    declared = config.declaration(case.impl)
    if declared is None:
        return lost_outcome(case, config, f"{case.impl} declared nothing readable: it could not be loaded",
                            Status.ERROR)
    attribute, _ = case.attribute
    if attribute is not None and not attribute.takes(declared):
        return _not_taken(case, config, attribute)
    started = time.perf_counter()
    sites, values = case_input(case)
    builds = max(config.repeat, MAX_REPEAT if config.min_time else 0)
    shifts = repeat_shifts(sites if attribute is None else attribute.range_rows(sites, values), builds + 1)
    judging = RepeatJudging(case.impl, declared, sites, values, shifts[:builds], attribute)
    schema = diagram_schema(sites.shape[0], **_schema_options(attribute))
    box = _InProcess(declared.plugin) if in_process else Sandbox(
        case.impl, plugins=(declared.plugin,) if declared.plugin else (), memory_limit_mb=config.memory_limit_mb,
        warmup_timeout=config.allowance("startup") + config.allowance("warmup"), expected=declared,
        start_method=config.start_method)
    info: dict = {}
    repeats: list[dict] = []
    step, status = "warmup", None

    def announce(text: str) -> None:
        nonlocal step
        step = text
        if on_step:
            on_step(text)

    try:
        announce("warmup")
        t0 = time.perf_counter()
        failure = box.start()               # start-up, imports and the implementation's own warm-up
        start_s = time.perf_counter() - t0
        if failure is not None:
            status = _failure(failure, info)
        else:
            outcome = box.call(prepare_timing, asdict(case), judging.shifts, shifts[-1], step="warm-up build",
                               timeout=config.allowance("generate") + config.allowance("warmup"))
            if not outcome.ok:
                status = _failure(outcome, info)
            elif isinstance(outcome.value[0], dict) and outcome.value[0].get("unsupported"):
                status, info["error"] = Status.UNSUPPORTED, wire.clean_text(outcome.value[0]["unsupported"], 500)
            else:
                info.update(_numbers(outcome.value[0], _SETUP_KEYS))
                info["warmup_s"] = start_s + float(info.get("warmup_s", 0.0))
        timed_s, index = 0.0, 0
        while status is None and _builds_to_time(config, index, timed_s):
            announce(f"repeat {index + 1}/{config.repeat}" if index < config.repeat
                     else f"repeat {index + 1} (filling min-time)")
            outcome = box.call(timed_repeat, index, timeout=config.timeout, step=step, schema=schema)
            if not outcome.ok:
                status = _failure(outcome, info)
                break
            row, arrays = outcome.value
            judging.take(index, arrays)
            repeats.append(_numbers(row, _REPEAT_KEYS, phases=True, counters=index == 0))
            timed_s += float(repeats[-1].get("time_s", 0.0))
            index += 1
        status = status or Status.OK
    finally:
        box.close()                         # its process group too: nothing it started lives on
    _judge_repeats(case, config, status, judging, repeats, info, sites, values, on_step)
    seconds = time.perf_counter() - started
    info["case_s"] = seconds
    return CaseOutcome(case, status, _rows(case, config, status, step, info, repeats), seconds)


def run_case_in_process(case: Case, config: RunConfig) -> CaseOutcome:
    """Run one case on a Dask worker: in a sandbox, as locally, where the worker may start
    processes; in the worker's own process where it is daemonic (one case per worker thread,
    no per-step timeout, no memory cap: a hard crash takes the worker down, and the parent
    retries the case or records it as lost; the implementation then shares the process with
    the judging, so its verdicts are only as trustworthy as it is)."""
    return run_case(case, config, in_process=mp.current_process().daemon)


def _judge_repeats(case: Case, config: RunConfig, status: Optional[str], judging: RepeatJudging,
                   repeats: list[dict], info: dict, sites, values, on_step=None) -> None:
    """Each repeat's verdict columns, decided here (never in the worker): the first repeat
    against the reference, every other one against the first."""
    info["n_sites"] = int(sites.shape[0])
    if status != Status.OK or not repeats:
        return
    repeats[0].update(judging.counts)       # V and E of the judged diagram, counted here
    if not (config.check and config.reference):
        info["verdict"] = Verdict.SKIPPED
        return
    if on_step:
        on_step("check")
    t0 = time.perf_counter_ns()
    try:
        ref = None if case.impl == config.reference else _reference_of(case, config, sites, values)
        verdicts = judging.verdicts(len(repeats), config.reference, ref, probes=10_000)
    except Exception as exc:  # a failing check is reported, not fatal
        verdicts = [{"verdict": Verdict.CHECK_ERROR, "verdict_detail": wire.clean_text(f"{type(exc).__name__}: {exc}", 300)}
                    ] * len(repeats)
    for row, verdict in zip(repeats, verdicts):
        row.update(verdict)
    info["check_s"] = (time.perf_counter_ns() - t0) / 1e9


def case_row(case: Case, config: RunConfig, status: str, host: Optional[str] = None, **fields) -> dict:
    """The one way a results row starts: the run, the case's key (weight or radius family
    included), its status, where and when it finished; ``fields`` add the rest."""
    return {"run_id": config.run_id, "impl": case.impl, "dataset": case.dataset, "weights": case.weights,
            "radii": case.radii, "n": case.n, "seed": case.seed, "status": status,
            "host": socket.gethostname() if host is None else host,
            "finished_at": _dt.datetime.now().isoformat(timespec="seconds"), **fields}


def _not_taken(case: Case, config: RunConfig, attribute: SiteAttribute) -> CaseOutcome:
    """The record of a weighted case, or a case of disks, of an implementation that does not
    take weights, or disks: declared out of its scope (``unsupported``), like sites it
    refuses; no worker is started."""
    row = case_row(case, config, Status.UNSUPPORTED, verdict=Verdict.UNSUPPORTED,
                   error=f"{attribute.refusal}: {case.impl} {attribute.instead}")
    return CaseOutcome(case, Status.UNSUPPORTED, [row], 0.0)


def _schema_options(attribute: Optional[SiteAttribute]) -> dict[str, bool]:
    """:func:`~vorobench.judge.engine.diagram_schema`'s options for a case's attribute: which
    array besides the DCEL's may come back (``weights``, ``radii``), none for points."""
    return {"weighted": attribute == WEIGHTS, "disks": attribute == RADII}


def lost_outcome(case: Case, config: RunConfig, why: str, status: str = Status.LOST) -> CaseOutcome:
    """The record of a case whose worker died on every try (status ``lost``), whose task failed
    outside the case (``error``) or overstayed (``timeout``): nothing came back, but the case is
    never dropped."""
    row = case_row(case, config, status, host="", error=why,
                   verdict=Verdict.TIMEOUT if status == Status.TIMEOUT else Verdict.CRASHED)
    return CaseOutcome(case, status, [row], 0.0)


def _once_per_case(column: str) -> bool:
    """Whether a measurement is taken on the first build only: the structure's size and the
    counters, which the same input gives whatever the repeat."""
    return column in ("V", "E") or column.startswith("stat_")


def _rows(case: Case, config: RunConfig, status: str, step: str, info: dict, repeats: list[dict]) -> list[dict]:
    common = case_row(case, config, status)
    common.update({k: v for k, v in info.items() if k not in ("status",)})
    if status == Status.OK:
        counters = repeats[0] if repeats else {}
        rows = []
        for i, rep in enumerate(repeats):
            row = dict(common)
            # Structure sizes and counters are measured once (they do not depend on the repeat);
            # timings and memory are each repeat's own.
            row.update({k: v for k, v in counters.items() if _once_per_case(k)})
            row.update({k: v for k, v in rep.items() if not _once_per_case(k)})
            row["repeat"] = i
            rows.append(row)
        return rows
    row = dict(common)
    row["phase"] = step
    if status in (Status.CRASHED, Status.TIMEOUT, Status.OOM, Status.ERROR):
        row["verdict"] = info.get("verdict") or (Verdict.TIMEOUT if status == Status.TIMEOUT else Verdict.CRASHED)
    elif status in (Status.UNSUPPORTED, Status.SKIPPED):
        row["verdict"] = status
    return [row]


# ---------------------------------------------------------------------------- a whole run

def _growth_exponent(timed: list[tuple[int, float]]) -> float:
    """Least-squares slope of log t against log n over the last three sizes, in [1, 3] (1 if unknown)."""
    timed = timed[-3:]
    if len({n for n, _ in timed}) < 2:
        return 1.0
    slope, _ = loglog_fit([n for n, _ in timed], [t for _, t in timed])
    return min(3.0, max(1.0, slope))


def _skip_reason(case: Case, history: dict, config: RunConfig) -> Optional[str]:
    """Why ``case`` need not run, judging from smaller n of the same impl/dataset/seed/weights/radii."""
    done = sorted(history.get(case.history_key, []))
    smaller = [(n, st, t) for n, st, t in done if n < case.n]
    if not smaller:
        return None
    n_last, st_last, t_last = smaller[-1]
    if st_last in (Status.TIMEOUT, Status.OOM):
        return f"n={n_last} already ended in {st_last}"
    if st_last == Status.SKIPPED:
        return f"n={n_last} was skipped"
    if not (config.budget and t_last):
        return None
    if case.impl == config.reference:
        # The reference runs wherever another implementation did: their ratios need it.
        others = [st for (impl, ds, seed), entries in history.items()
                  if impl != case.impl and ds == case.history_key[1] and seed == case.seed
                  for n, st, _ in entries if n == case.n]
        if Status.OK in others:
            return None
    timed = [(n, t) for n, st, t in smaller if st == Status.OK and t]
    exponent, basis = _growth_exponent(timed), "measured"
    if len({n for n, _ in timed[-3:]}) < 2:
        # One size tells no growth: the implementation's declared complexity does.
        declared = dict(config.declarations).get(case.impl)
        slope = declared_exponent(declared.complexity, n_last, case.n) if declared else float("nan")
        exponent, basis = (slope, f"declared {declared.complexity}") if slope == slope else (1.0, "assumed")
    predicted = t_last * (case.n / n_last) ** exponent
    if predicted > config.budget:
        return (f"extrapolated build time {predicted:.3g} s (from n={n_last}, {basis} exponent "
                f"{exponent:.2f}) exceeds the budget of {config.budget:g} s")
    return None


def _skipped(case: Case, config: RunConfig, reason: str) -> CaseOutcome:
    row = case_row(case, config, Status.SKIPPED, verdict=Verdict.SKIPPED, error=reason)
    return CaseOutcome(case, Status.SKIPPED, [row], 0.0)


def history_from_rows(rows: Iterable[dict]) -> dict:
    """(impl, dataset, seed) -> [(n, status, median time)] from rows already on file (the dataset
    of a weighted case, or a case of disks, named with its family)."""
    by_case: dict = {}
    for r in rows:
        key = case_key(r)
        entry = by_case.setdefault(key, {"status": r.get("status", ""), "times": []})
        t = r.get("time_s")
        if t not in (None, ""):
            entry["times"].append(float(t))
    history: dict = {}
    for (impl, ds, n, seed), entry in by_case.items():
        times = sorted(entry["times"])
        median = times[len(times) // 2] if times else None
        history.setdefault((impl, ds, seed), []).append((n, entry["status"], median))
    return history


def _case_weight(case: Case, config: RunConfig) -> float:
    """Rough relative cost of a case, for the progress bar's ETA (worker start-up ~ 1 unit)."""
    return 1.0 + config.repeat * case.n * math.log2(case.n + 2) / 2e6


def run_cases(cases: Sequence[Case], config: RunConfig, sink: Callable[[list[dict]], None],
              done: Iterable[tuple] = (), previous_rows: Iterable[dict] = (), progress: bool = True,
              console=None, verbose: bool = True, executor: Optional[str] = None,
              workers: int = 1) -> list[CaseOutcome]:
    """Run ``cases``; ``sink(rows)`` receives each finished case's rows as it finishes.

    Without ``executor`` (or ``local`` with one worker) the cases run one worker process at a
    time, here. Otherwise each is a task on the executor (:mod:`vorobench.harness.executors`): on
    ``local`` a pool of ``workers`` processes, each running one case at a time in its own
    worker process (:func:`run_case`); on ``dask://`` the case runs inside the Dask worker
    (:func:`run_case_in_process`), whose death makes the case retried once, then ``lost``.
    Cases whose key is in ``done`` are skipped (resume). ``previous_rows`` (rows already on
    file) seed the extrapolation that skips hopeless larger sizes (in parallel runs only from
    the cases finished when a case is submitted). Ctrl-C stops after killing the running
    workers; everything already passed to ``sink`` is kept.
    """
    console = console or Console(stderr=True)
    done = set(done)
    todo = [c for c in cases if c.key not in done]
    history = history_from_rows(previous_rows)
    outcomes: list[CaseOutcome] = []
    columns = [SpinnerColumn(), TextColumn("[progress.description]{task.description}"), BarColumn(),
               TextColumn("{task.fields[count]}"), TextColumn("elapsed"), TimeElapsedColumn(),
               TextColumn("ETA"), TimeRemainingColumn()]
    with Progress(*columns, console=console, disable=not progress, transient=False) as bar:
        total = sum(_case_weight(c, config) for c in todo)
        task = bar.add_task("starting", total=total, count=f"0/{len(todo)} cases")

        def finish(outcome: CaseOutcome) -> None:
            case = outcome.case
            sink(outcome.rows)
            outcomes.append(outcome)
            history.setdefault(case.history_key, []).append(
                (case.n, outcome.status, outcome.median_time))
            bar.update(task, advance=_case_weight(case, config), count=f"{len(outcomes)}/{len(todo)} cases")
            if verbose:
                console.print(_one_line(outcome))

        if executor is not None and not (executor == "local" and workers == 1):
            _run_on_executor(todo, config, history, finish, executor, workers,
                             lambda text: bar.update(task, description=text))
            return outcomes
        for case in todo:
            bar.update(task, description=f"{case}")
            reason = _skip_reason(case, history, config)
            if reason:
                outcome = _skipped(case, config, reason)
            else:
                outcome = run_case(case, config,
                                   on_step=lambda step, c=case: bar.update(task, description=f"{c}: {step}"))
            finish(outcome)
    return outcomes


def _case_task(item: tuple[Case, RunConfig, bool]) -> CaseOutcome:
    """One executor task: one timed case (in its own worker process, or in this process)."""
    case, config, in_process = item
    return run_case_in_process(case, config) if in_process else run_case(case, config)


def _run_on_executor(todo: Sequence[Case], config: RunConfig, history: dict,
                     finish: Callable[[CaseOutcome], None], executor: str, workers: int,
                     describe: Callable[[str], None]) -> None:
    in_process = parse_spec(executor)[0] != LOCAL

    def items():
        for case in todo:
            reason = _skip_reason(case, history, config)
            if reason:
                finish(_skipped(case, config, reason))
            else:
                describe(f"{executor}: submitted {case}")
                yield (case, config, in_process)

    # One case per worker at a time (timing fairness). Locally each case's own worker process
    # enforces the timeouts; in a Dask worker the case as a whole gets their sum.
    limit = None
    if in_process:
        builds = max(config.repeat, MAX_REPEAT if config.min_time else 0)
        # start-up and warm-up (the sandbox's, then the warm-up build), every build, and the check
        limit = (config.allowance("startup") + config.allowance("generate") + 2 * config.allowance("warmup")
                 + (builds + 2) * config.timeout)
    for res in run_tasks(executor, workers, _case_task, items(), in_flight=None if in_process else workers,
                         timeout=limit):
        case = res.item[0]
        if res.ok:
            finish(res.value)
        elif res.timed_out:
            finish(lost_outcome(case, config, f"{res.error} on the Dask worker (its worker thread stays busy "
                                              f"until the build returns)", Status.TIMEOUT))
        else:
            finish(lost_outcome(case, config, res.lost or f"task failed: {res.error}",
                                Status.LOST if res.lost else Status.ERROR))


def _one_line(outcome: CaseOutcome) -> str:
    c = outcome.case
    if outcome.status == Status.OK:
        t = outcome.median_time
        verdict = outcome.verdict or ""
        passed = verdict == Verdict.SKIPPED or verdict_rank(verdict) in (0, 1)
        verdict = "not checked" if verdict == Verdict.SKIPPED else verdict
        colour = "green" if passed else "yellow"
        return f"[green]ok[/green] {c}: median {t:.4g} s  [{colour}]{verdict}[/{colour}]"
    colour = "yellow" if status_rank(outcome.status) is None else "red"
    return f"[{colour}]{outcome.status}[/{colour}] {c}: {outcome.error or ''}"


def exit_status(outcomes: Sequence[CaseOutcome]) -> dict[str, int]:
    """How many cases ended in each status."""
    counts: dict[str, int] = {}
    for o in outcomes:
        counts[o.status] = counts.get(o.status, 0) + 1
    return counts
