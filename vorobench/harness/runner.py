"""Run benchmark cases, each in its own worker process, and turn every outcome into rows.

A case is one (implementation, dataset, n, seed, weight family): with a weight family (``bench
--weights``) it times the power diagram of the dataset's points, and an implementation that
does not take weights is recorded as ``unsupported`` without being started. Its worker (:mod:`vorobench.harness.worker`) is a
fresh process, so a hard crash (segfault, ``os._exit``), a hang or running out of memory ends
that case only: the parent records the status and goes on. Workers are forked from a
``forkserver`` that has imported numpy, scipy, numba and the implementations once (a fresh
``spawn`` interpreter per case costs about 2 s of imports on a busy 2-core machine; the
server never runs a case, so no state passes from one case to the next). ``start_method=
"spawn"`` gives a brand-new interpreter per case instead. ``timeout`` bounds each
step the implementation runs (every repeat, and the check); the warm-up, which may include JIT
compilation, has its own allowance. Rows of each finished case go to ``sink`` before the next
case starts.
"""

from __future__ import annotations

import atexit
import dataclasses
import datetime as _dt
import math
import multiprocessing as mp
import os
import shutil
import socket
import tempfile
import time
from dataclasses import asdict, dataclass, field
from typing import Callable, Iterable, Optional, Sequence

from rich.console import Console
from rich.progress import BarColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn, TimeRemainingColumn

import datasets_gen
import impls
from vorobench.harness.analysis import loglog_fit
from vorobench.harness.executors import LOCAL, parse_spec, run_tasks
from vorobench.harness.results import case_key, weighted_label
from vorobench.harness.worker import MAX_REPEAT, reference_path, run_and_report, store_reference, worker_main
from vorobench.judge import isolation
from vorobench.judge.engine import NO_WEIGHTS, prepare_case, shared_judge
from vorobench.judge.isolation import FORKSERVER_PRELOAD, default_start_method
from vorobench.judge.outcomes import Status, Verdict, status_rank, verdict_rank

__all__ = ["Case", "RunConfig", "CaseOutcome", "plan_cases", "run_case", "run_case_in_process", "run_cases",
           "exit_status", "case_input", "takes_weights"]

#: Allowance for starting the worker, importing, and generating the input (not the impl's time).
STARTUP_TIMEOUT = 180.0



@dataclass(frozen=True)
class Case:
    """One benchmark case; ``weights``: the weight family of a power-diagram case ("" for none)."""

    impl: str
    dataset: str
    n: int
    seed: int = 0
    weights: str = ""

    @property
    def key(self) -> tuple[str, str, int, int]:
        """(impl, dataset, n, seed), the dataset named with its weight family if any (as
        :func:`~vorobench.harness.results.case_key` names a row's)."""
        return (self.impl, weighted_label(self.dataset, self.weights), self.n, self.seed)

    @property
    def history_key(self) -> tuple[str, str, int]:
        """The case without its size: the smaller sizes it is extrapolated from share it."""
        return (self.impl, weighted_label(self.dataset, self.weights), self.seed)

    def __str__(self) -> str:
        weights = f" weights={self.weights}" if self.weights else ""
        return f"{self.impl} {self.dataset}{weights} n={self.n} seed={self.seed}"


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
    reference_cache: Optional[str] = None
    memory_limit_mb: Optional[float] = None
    budget: Optional[float] = None      # skip a case whose extrapolated build time exceeds this
    start_method: str = field(default_factory=default_start_method)
    run_id: str = field(default_factory=lambda: _dt.datetime.now().strftime("%Y%m%dT%H%M%S-") + os.urandom(2).hex())

    def for_worker(self) -> dict:
        return {k: v for k, v in asdict(self).items() if k not in ("budget", "run_id", "start_method")}

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
               seeds: Sequence[int], reference: Optional[str] = None, weights: str = "") -> list[Case]:
    """All combinations, smallest n first: an interrupted run has covered every pair early,
    and a size is only reached after the smaller ones it is extrapolated from. Within a
    (size, dataset, seed) the reference comes last, so it knows whether anyone needs it.
    ``weights``: the weight family of every case ("" for ordinary diagrams)."""
    ordered = [i for i in impls if i != reference] + [i for i in impls if i == reference]
    per_dataset = {d: set(_distinct_sizes(d, sizes)) for d in datasets}
    return [Case(i, d, n, s, weights or "") for n in sorted(set(sizes)) for d in datasets if n in per_dataset[d]
            for s in seeds for i in ordered]


def takes_weights(impl: str) -> Optional[bool]:
    """Whether implementation ``impl`` builds power diagrams (None: it cannot be loaded here;
    its worker reports why)."""
    try:
        return impls.get(impl).weighted
    except Exception:  # a broken plugin is the worker's to report
        return None


def case_input(case: Case):
    """(sites, site weights or None) of a case, generated and prepared as its worker does."""
    points = datasets_gen.generate(case.dataset, case.n, seed=case.seed)
    weights = datasets_gen.weights(case.weights, points, seed=case.seed) if case.weights else None
    return prepare_case(points, weights)


def _context(method: str, impl: str):
    ctx = mp.get_context(method)
    if method == "forkserver":
        modules = list(FORKSERVER_PRELOAD)
        try:
            modules.append(impls.get(impl).build.__module__)
        except Exception:  # the worker reports an implementation that cannot load
            pass
        ctx.set_forkserver_preload(modules)   # only takes effect when the server starts
    return ctx


_SCRATCH: list = []


def _reference_cache(config: RunConfig) -> str:
    """The run's reference cache, or a scratch folder of this process (removed at its exit)
    when a single case is run with none."""
    if config.reference_cache:
        return config.reference_cache
    if not _SCRATCH:
        _SCRATCH.append(tempfile.mkdtemp(prefix="vorobench-reference-"))
        atexit.register(shutil.rmtree, _SCRATCH[0], True)
    return _SCRATCH[0]


def prepare_reference(case: Case, config: RunConfig) -> Optional[str]:
    """Build and certify the reference of the case's input once, in a sandbox of the judging
    engine, and store it where the case's worker will look (nothing to do if it is there).
    Returns the cache folder, or None when the case is not checked against a reference."""
    if not (config.check and config.reference):
        return None

    cache = _reference_cache(config)
    if case.impl == config.reference:
        return cache                        # its own case: judged on its own timed build
    if case.weights and takes_weights(case.impl) is False:
        return cache                        # the case is unsupported: nothing to check
    path = reference_path(cache, config.reference, case.dataset, case.n, case.seed, case.weights)
    if path.exists():
        return cache
    # Not stored: build it here (a failure is then passed on to this case, never cached).
    try:
        sites, weights = case_input(case)
        judge = shared_judge([], config.reference, timeout=config.timeout, warmup_timeout=config.warmup_timeout,
                             memory_limit_mb=config.memory_limit_mb, plugins=config.plugins)
        result = judge.build(config.reference, sites, weights=weights)
        if result.diagram is not None or result.unsupported:
            store_reference(path, result)   # a failure is not kept: a later run must try again
    except Exception:  # the input cannot be generated: the case's own worker reports why
        pass
    return cache


def run_case(case: Case, config: RunConfig, on_step: Optional[Callable[[str], None]] = None) -> CaseOutcome:
    """Run one case in a fresh worker process and return its rows, whatever happens to it."""
    if case.weights and takes_weights(case.impl) is False:
        return _no_weights(case, config)
    started = time.perf_counter()
    if on_step and config.check and config.reference and case.impl != config.reference:
        on_step(f"reference {config.reference}")
    cache = prepare_reference(case, config)
    ctx = _context(config.start_method, case.impl)
    receiver, sender = ctx.Pipe(duplex=False)
    worker_config = config.for_worker()
    worker_config["reference_cache"] = cache
    # A forked worker would see the fork server's environment; it gets the parent's, as now.
    worker_config["environ"] = dict(os.environ)
    proc = ctx.Process(target=worker_main, args=(sender, asdict(case), worker_config),
                       name=f"vorobench-{case.impl}", daemon=True)
    info: dict = {}
    repeats: list[dict] = []
    step = "startup"
    status: Optional[str] = None
    try:
        proc.start()
        isolation.watch(proc.pid)
        sender.close()
        deadline = time.monotonic() + config.allowance(step)
        while status is None:
            if receiver.poll(max(0.0, deadline - time.monotonic())):
                try:
                    kind, payload = receiver.recv()
                except (EOFError, OSError):
                    proc.join(10)
                    status, info["error"] = isolation.describe_death(proc.exitcode)
                    break
                if kind == "step":
                    step = payload
                    deadline = time.monotonic() + config.allowance(step)
                    if on_step:
                        on_step(step)
                status = _absorb(kind, payload, info, repeats) or status
            elif proc.is_alive():
                status = Status.TIMEOUT
                info["error"] = f"no result within {config.allowance(step):g} s during {step}"
            else:
                proc.join(10)
                status, info["error"] = isolation.describe_death(proc.exitcode)
    finally:
        if status == Status.OK:
            proc.join(5)                    # a finished worker is only exiting: let it
        isolation.kill_worker(proc)         # its process group too: nothing it started lives on
        receiver.close()
    seconds = time.perf_counter() - started
    info["case_s"] = seconds
    return CaseOutcome(case, status, _rows(case, config, status, step, info, repeats), seconds)


def _absorb(kind: str, payload, info: dict, repeats: list[dict]) -> Optional[str]:
    """Take one worker message into ``info``/``repeats``; the case's status if it ends it."""
    if kind == "data":
        info.update(payload)
    elif kind == "repeat":
        repeats.append(payload)
    elif kind == "done":
        return Status.OK
    elif kind == "failed":
        info.update(payload)
        return payload["status"]
    return None


def run_case_in_process(case: Case, config: RunConfig) -> CaseOutcome:
    """Run one case in this process (a Dask worker: one case per worker thread, no per-step
    timeout, no memory cap). A hard crash takes this process down; the executor sees the
    worker die, and the parent retries the case or records it as lost."""
    if case.weights and takes_weights(case.impl) is False:
        return _no_weights(case, config)
    started = time.perf_counter()
    info: dict = {}
    repeats: list[dict] = []
    state = {"step": "startup", "status": None}

    def send(kind: str, payload) -> None:
        if kind == "step":
            state["step"] = payload
        state["status"] = _absorb(kind, payload, info, repeats) or state["status"]

    worker_config = config.for_worker()
    worker_config.update(environ=None, memory_limit_mb=None,   # this process is shared: leave it as it is
                         reference_cache=prepare_reference(case, config))
    run_and_report(asdict(case), worker_config, send)
    status = state["status"] or Status.CRASHED
    seconds = time.perf_counter() - started
    info["case_s"] = seconds
    return CaseOutcome(case, status, _rows(case, config, status, state["step"], info, repeats), seconds)


def _no_weights(case: Case, config: RunConfig) -> CaseOutcome:
    """The record of a weighted case of an implementation that does not take weights: declared
    out of its scope (``unsupported``), like sites it refuses; no worker is started."""
    row = {"run_id": config.run_id, "impl": case.impl, "dataset": case.dataset, "weights": case.weights,
           "n": case.n, "seed": case.seed, "status": Status.UNSUPPORTED, "verdict": Verdict.UNSUPPORTED,
           "error": f"{NO_WEIGHTS}: {case.impl} builds ordinary Voronoi diagrams only",
           "host": socket.gethostname(), "finished_at": _dt.datetime.now().isoformat(timespec="seconds")}
    return CaseOutcome(case, Status.UNSUPPORTED, [row], 0.0)


def lost_outcome(case: Case, config: RunConfig, why: str, status: str = "lost") -> CaseOutcome:
    """The record of a case whose worker died on every try (status ``lost``), whose task failed
    outside the case (``error``) or overstayed (``timeout``): nothing came back, but the case is
    never dropped."""
    row = {"run_id": config.run_id, "impl": case.impl, "dataset": case.dataset, "weights": case.weights,
           "n": case.n, "seed": case.seed, "status": status,
           "verdict": Verdict.TIMEOUT if status == Status.TIMEOUT else Verdict.CRASHED,
           "error": why, "host": "",
           "finished_at": _dt.datetime.now().isoformat(timespec="seconds")}
    return CaseOutcome(case, status, [row], 0.0)


def _once_per_case(column: str) -> bool:
    """Whether a measurement is taken on the first build only: the structure's size and the
    counters, which the same input gives whatever the repeat."""
    return column in ("V", "E") or column.startswith("stat_")


def _rows(case: Case, config: RunConfig, status: str, step: str, info: dict, repeats: list[dict]) -> list[dict]:
    common = {"run_id": config.run_id, "impl": case.impl, "dataset": case.dataset, "weights": case.weights,
              "n": case.n, "seed": case.seed, "status": status, "host": socket.gethostname(),
              "finished_at": _dt.datetime.now().isoformat(timespec="seconds")}
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
    """Why ``case`` need not run, judging from smaller n of the same impl/dataset/seed/weights."""
    done = sorted(history.get(case.history_key, []))
    smaller = [(n, st, t) for n, st, t in done if n < case.n]
    if not smaller:
        return None
    n_last, st_last, t_last = smaller[-1]
    if st_last in ("timeout", "oom"):
        return f"n={n_last} already ended in {st_last}"
    if st_last == "skipped":
        return f"n={n_last} was skipped"
    if not (config.budget and t_last):
        return None
    if case.impl == config.reference:
        # The reference runs wherever another implementation did: their ratios need it.
        others = [st for (impl, ds, seed), entries in history.items()
                  if impl != case.impl and ds == case.history_key[1] and seed == case.seed
                  for n, st, _ in entries if n == case.n]
        if "ok" in others:
            return None
    exponent = _growth_exponent([(n, t) for n, st, t in smaller if st == "ok" and t])
    predicted = t_last * (case.n / n_last) ** exponent
    if predicted > config.budget:
        return (f"extrapolated build time {predicted:.3g} s (from n={n_last}, exponent "
                f"{exponent:.2f}) exceeds the budget of {config.budget:g} s")
    return None


def _skipped(case: Case, config: RunConfig, reason: str) -> CaseOutcome:
    row = {"run_id": config.run_id, "impl": case.impl, "dataset": case.dataset, "weights": case.weights,
           "n": case.n, "seed": case.seed, "status": Status.SKIPPED, "verdict": Verdict.SKIPPED, "error": reason,
           "host": socket.gethostname(), "finished_at": _dt.datetime.now().isoformat(timespec="seconds")}
    return CaseOutcome(case, Status.SKIPPED, [row], 0.0)


def history_from_rows(rows: Iterable[dict]) -> dict:
    """(impl, dataset, seed) -> [(n, status, median time)] from rows already on file (the dataset
    of a weighted case named with its weight family)."""
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
    if config.check and config.reference and not config.reference_cache:
        # The reference is judged once per input and shared through files: a folder for this run.
        with tempfile.TemporaryDirectory(prefix="vorobench-reference-") as folder:
            return run_cases(cases, dataclasses.replace(config, reference_cache=folder), sink, done, previous_rows,
                             progress, console, verbose, executor, workers)
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
        limit = config.allowance("generate") + config.allowance("warmup") + (builds + 1) * config.timeout
    for res in run_tasks(executor, workers, _case_task, items(), in_flight=None if in_process else workers,
                         timeout=limit):
        case = res.item[0]
        if res.ok:
            finish(res.value)
        elif res.timed_out:
            finish(lost_outcome(case, config, f"{res.error} on the Dask worker (its worker thread stays busy "
                                              f"until the build returns)", "timeout"))
        else:
            finish(lost_outcome(case, config, res.lost or f"task failed: {res.error}",
                                "lost" if res.lost else "error"))


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
