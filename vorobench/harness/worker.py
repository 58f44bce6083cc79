"""The worker side of a benchmark case: runs in its own process and reports step by step.

The parent (:mod:`vorobench.harness.runner`) starts one worker per (implementation, dataset, n, seed,
weight family); a weighted case builds the power diagram of the points with weights of that
family (:func:`datasets_gen.weights`), drawn with the points, before anything is timed.
The worker announces each step before it starts (``("step", name)``) and sends its measurements
as it gets them (``("data", dict)``), then ``("done", None)`` or ``("failed", dict)``. So when the
worker dies or hangs, the parent knows in which step and keeps what was measured before.

Timing protocol: inputs are generated and prepared before anything is timed; the warm-up
(``Implementation.warmup`` plus one untimed build of a small input from the same dataset)
absorbs JIT compilation and is timed on its own; each repeat is one ``perf_counter_ns`` wall
time with the garbage collector collected before and paused during the build; the resident
peak is reset before each build so the build's own peak memory is measured. Builds shorter
than a scheduler time slice are repeated until ``min_time`` seconds are timed (at most
``MAX_REPEAT`` builds), so one preemption on a busy machine cannot move the median.
"""

from __future__ import annotations

import gc
import os
import pickle
import signal
import time
import traceback
from pathlib import Path
from typing import Any, Callable

import numpy as np

import datasets_gen
import impls
from impls.base import InputMutated
from impls.plugins import load_plugin
from vorobench.harness import peakmem
from vorobench.harness.atomic import replace_atomically
from vorobench.judge import engine as crossval
from vorobench.judge import isolation
from vorobench.judge.certificate import certify
from vorobench.judge.engine import NO_WEIGHTS, diagram_arrays, prepare_case
from vorobench.judge.outcomes import COUNTER_PREFIX, timing_column

__all__ = ["worker_main", "run_and_report", "check_against_reference",
           "reference_path", "store_reference", "load_reference"]

Send = Callable[[str, Any], None]

#: Smallest input used for the untimed warm-up build (capped by the case's own n).
WARMUP_N = 64

#: Most builds per case when short builds are repeated to fill ``min_time``.
MAX_REPEAT = 25


def reference_path(cache_dir: str, reference: str, dataset: str, n: int, seed: int, weights: str = "") -> Path:
    """Where the reference's judged build of one (dataset, n, seed, weight family) is kept for the run."""
    family = f"-w-{weights}" if weights else ""
    return Path(cache_dir) / f"{reference}-{dataset}-{n}-{seed}{family}.pkl"


def store_reference(path: Path, result) -> None:
    """Write the reference's build and certificate atomically (a half-written file never looks
    complete; the temporary name is unpredictable)."""
    replace_atomically(path, lambda f: pickle.dump(result, f, protocol=pickle.HIGHEST_PROTOCOL), binary=True)


def load_reference(path: Path, sites, weights=None):
    """The stored reference build of ``sites`` with ``weights`` (a
    :class:`~vorobench.judge.engine.BuildResult`), or None when there is none or it belongs to
    other sites or weights."""
    try:
        with open(path, "rb") as f:
            result = pickle.load(f)
    except (OSError, EOFError, pickle.UnpicklingError, AttributeError, ValueError):
        return None
    diagram = getattr(result, "diagram", None)
    if diagram is not None and not (diagram.sites.shape == sites.shape and np.array_equal(diagram.sites, sites)):
        return None
    stored = None if diagram is None else diagram.weights
    if diagram is not None and ((stored is None) != (weights is None)
                                or (weights is not None and not np.array_equal(stored, weights))):
        return None
    return result


def _same_diagram(a, b) -> bool:
    first, second = diagram_arrays(a), diagram_arrays(b)
    return first.keys() == second.keys() and all(np.array_equal(first[k], second[k]) for k in first)


def check_against_reference(impl_name: str, diagram, reference: str, reference_result=None) -> dict:
    """The correctness verdict of one built diagram, as result columns.

    The already-built diagram (no second build) is certified and judged against the
    reference's build (judged once per case by the runner and stored) with the rules of
    :func:`vorobench.judge.engine.decide`. The reference's own row reuses the stored certificate
    when it built the same diagram.
    """
    stored = reference_result
    if impl_name == reference and stored is not None and stored.diagram is not None \
            and _same_diagram(stored.diagram, diagram):
        res = crossval.BuildResult(impl_name, crossval.is_exact(impl_name), diagram, stored.certificate)
    else:
        res = crossval.BuildResult(impl_name, crossval.is_exact(impl_name), diagram, certify(diagram))
    if impl_name == reference:
        ref = res
    elif stored is None:
        ref = crossval.BuildResult(reference, crossval.is_exact(reference), error="no reference diagram",
                                   failure="crashed")
    else:
        ref = stored
    verdict = crossval.decide(impl_name, reference, res, ref)
    return {"verdict": verdict.verdict, "check_passed": bool(verdict.passed), "blame": verdict.blame or "",
            "verdict_detail": _first_line(verdict.message)}


def _first_line(obj: object) -> str:
    text = str(obj).strip().splitlines()
    return text[0][:300] if text else ""


def _timed_build(impl, sites, stats, timings, weights=None) -> tuple[object, int, float, float]:
    """One build: (diagram, wall ns, peak resident MiB during it, own peak above the start)."""
    gc.collect()
    peakmem.reset_peak()
    before = peakmem.current_rss_mb()
    gc.disable()
    try:
        t0 = time.perf_counter_ns()
        # A read-only copy; a change of it, or a counter that is not an integer, is an error.
        diagram = impl.run(sites, stats, timings=timings, check_supports=False, weights=weights)
        elapsed = time.perf_counter_ns() - t0
    finally:
        gc.enable()
    peak = peakmem.peak_rss_mb()
    return diagram, elapsed, peak, max(0.0, peak - before)


def _measured_columns(stats: dict, timings: dict) -> dict[str, float]:
    """The build's counters as ``stat_<name>`` columns (integers, checked by ``Implementation.run``)
    and the parts of its time as ``time_<phase>_s`` columns."""
    return ({f"{COUNTER_PREFIX}{key}": int(value) for key, value in stats.items()}
            | {timing_column(phase): float(seconds) for phase, seconds in timings.items()})


def _run_steps(case: dict, config: dict, send: Send) -> None:
    if config.get("environ") is not None:
        os.environ.clear()
        os.environ.update(config["environ"])
    for spec in config.get("plugins", ()):
        load_plugin(spec)

    impl = impls.get(case["impl"])
    family = case.get("weights") or ""
    if family and not impl.weighted:
        send("failed", {"status": "unsupported", "error": f"{NO_WEIGHTS}: {impl.name} builds ordinary Voronoi "
                                                           f"diagrams only"})
        return
    send("data", {"rss_base_mb": peakmem.current_rss_mb()})

    def case_input(n: int):
        """(points, sites, site weights or None) of the case's dataset at size ``n``."""
        points = datasets_gen.generate(case["dataset"], n, seed=case["seed"])
        weights = datasets_gen.weights(family, points, seed=case["seed"]) if family else None
        return (points, *prepare_case(points, weights))

    send("step", "generate")
    t0 = time.perf_counter_ns()
    points, sites, weights = case_input(case["n"])
    send("data", {"setup_s": (time.perf_counter_ns() - t0) / 1e9,
                  "n_points": int(points.shape[0]), "n_sites": int(sites.shape[0])})
    del points
    reason = impl.unsupported_reason(sites)
    if reason:
        send("failed", {"status": "unsupported", "error": reason})
        return
    isolation.limit_memory(config.get("memory_limit_mb"))

    send("step", "warmup")
    t0 = time.perf_counter_ns()
    if impl.warmup is not None:
        impl.warmup()
    _, small, small_weights = case_input(min(case["n"], WARMUP_N))
    impl.run(small, {}, weights=small_weights)
    send("data", {"warmup_s": (time.perf_counter_ns() - t0) / 1e9})

    # Everything alive now (libraries, inputs) is moved out of the collector's reach, so the
    # collection before each build costs microseconds instead of ~0.1 s.
    gc.collect()
    gc.freeze()
    diagram = None
    repeat, min_time = config["repeat"], config.get("min_time") or 0.0
    timed_ns, i = 0, 0
    # At least `repeat` builds; fast ones are repeated until `min_time` of timed builds (capped).
    while i < repeat or (timed_ns < min_time * 1e9 and i < MAX_REPEAT):
        send("step", f"repeat {i + 1}/{repeat}" if i < repeat else f"repeat {i + 1} (filling min-time)")
        stats: dict = {}
        timings: dict = {}
        diagram = None                      # free the previous result before the next build
        diagram, ns, peak, own = _timed_build(impl, sites, stats, timings, weights)
        timed_ns += ns
        row = {"time_s": ns / 1e9, "peak_rss_mb": peak, "mem_mb": own} | _measured_columns({}, timings)
        if i == 0:
            counts = diagram.counts()
            row.update(V=counts["V"], E=counts["E"], **_measured_columns(stats, {}))
        send("repeat", row)
        i += 1

    if config.get("check", True) and config.get("reference"):
        send("step", "check")
        t0 = time.perf_counter_ns()
        try:
            stored = None
            if config.get("reference_cache"):
                stored = load_reference(reference_path(config["reference_cache"], config["reference"],
                                                       case["dataset"], case["n"], case["seed"], family),
                                        sites, weights)
            verdict = check_against_reference(impl.name, diagram, config["reference"], stored)
        except Exception as exc:                    # a failing check is reported, not fatal
            verdict = {"verdict": "check_error", "verdict_detail": _first_line(f"{type(exc).__name__}: {exc}")}
        send("data", {**verdict, "check_s": (time.perf_counter_ns() - t0) / 1e9})
    else:
        send("data", {"verdict": "skipped"})
    send("done", None)


def run_and_report(case: dict, config: dict, send: Send) -> None:
    """Run the case's steps in this process; every failure is sent as ``("failed", ...)``."""
    try:
        _run_steps(case, config, send)
    except InputMutated as exc:
        send("failed", {"status": "error", "verdict": "mutated_input", "error": str(exc)[:500]})
    except MemoryError as exc:
        send("failed", {"status": "oom", "error": f"MemoryError: {exc}"[:500]})
    except BaseException as exc:  # noqa: BLE001 - every failure of the case is reported as data
        frames = traceback.extract_tb(exc.__traceback__)
        where = f" (at {Path(frames[-1].filename).name}:{frames[-1].lineno})" if frames else ""
        send("failed", {"status": "error", "error": f"{type(exc).__name__}: {exc}"[:400] + where})


def worker_main(conn, case: dict, config: dict) -> None:
    """Entry point of the worker process: run the case's steps, report over ``conn``."""
    isolation.enter_worker()
    signal.signal(signal.SIGINT, signal.SIG_IGN)    # Ctrl-C is the parent's to handle

    def send(kind: str, payload: Any) -> None:
        conn.send((kind, payload))

    try:
        run_and_report(case, config, send)
    finally:
        conn.close()
