"""The worker side of a benchmark case: the implementation's sandbox for timing, one per case.

The parent (:mod:`vorobench.harness.runner`) starts one worker per (implementation, dataset, n,
seed, weight family); a weighted case builds the power diagram of the points with weights of
that family (:func:`datasets_gen.weights`), drawn with the points, before anything is timed.
The worker loads only the plugin that defines its implementation, announces each step before
it starts (``step``), sends its measurements as it gets them (``data``), each timed build's
diagram with its timings (``repeat``), then ``done`` or ``failed``. Every message crosses the
bounded wire (:mod:`vorobench.judge.wire`): the parent checks sizes before it allocates, and it
judges every repeat's diagram itself. Nothing is judged in this process.

Timing protocol: inputs are generated and prepared before anything is timed; the warm-up
(``Implementation.warmup`` plus one untimed build of a small input from the same dataset)
absorbs JIT compilation and is timed on its own; each repeat is one ``perf_counter_ns`` wall
time with the garbage collector collected before and paused during the build; the resident
peak is reset before each build so the build's own peak memory is measured. Repeat i builds the
sites scaled by ``2**shifts[i]`` (the parent's choice: the same order and the same diagram, the
vertices scaled alike, but other bytes), so a result cached by its input cannot fake a timing.
After each repeat the worker waits for the parent to take the diagram in, so the parent's work
never overlaps a timed build. Builds shorter than a scheduler time slice are repeated until
``min_time`` seconds are timed (at most ``MAX_REPEAT`` builds).
"""

from __future__ import annotations

import gc
import os
import signal
import time
from typing import Any, Callable, Optional

import numpy as np

import datasets_gen
import impls
from impls.base import BuildRaised, InputMutated
from impls.plugins import load_plugin
from vorobench.harness import peakmem
from vorobench.judge import isolation, wire
from vorobench.judge.engine import NO_WEIGHTS, _declined, diagram_arrays, prepare_case
from vorobench.judge.outcomes import COUNTER_PREFIX, timing_column
from vorobench.judge.sandbox import safe_message

__all__ = ["worker_main", "run_and_report", "scaled_input", "MAX_REPEAT", "WARMUP_N"]

#: ``send(kind, payload, arrays)``: one message to the parent.
Send = Callable[..., None]

#: Smallest input used for the untimed warm-up build (capped by the case's own n).
WARMUP_N = 64

#: Most builds per case when short builds are repeated to fill ``min_time``.
MAX_REPEAT = 25


def scaled_input(sites: np.ndarray, weights: Optional[np.ndarray], shift: int
                 ) -> tuple[np.ndarray, Optional[np.ndarray]]:
    """The sites times ``2**shift`` and the weights times ``4**shift`` (a power is a squared
    length): exactly the same diagram, its vertices times ``2**shift``."""
    if shift == 0:
        return sites, weights
    return np.ldexp(sites, shift), (None if weights is None else np.ldexp(weights, 2 * shift))


def _timed_build(impl, sites, stats, timings, weights=None) -> tuple[object, int, float, float]:
    """One build: (diagram, wall ns, peak resident MiB during it, own peak above the start)."""
    gc.collect()
    peakmem.reset_peak()
    before = peakmem.current_rss_mb()
    gc.disable()
    try:
        t0 = time.perf_counter_ns()
        # A read-only copy; a change of it, or a counter that is not an integer, is an error.
        diagram = impl.run(sites, stats, timings=timings, check_supports=False, weights=weights,
                           wrap_build_errors=True)
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


def _run_steps(case: dict, config: dict, send: Send, wait: Callable[[], None]) -> None:
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
    send("data", {"setup_s": (time.perf_counter_ns() - t0) / 1e9, "n_points": int(points.shape[0])})
    del points
    reason = _declined(impl, sites)
    if reason:
        send("failed", {"status": "unsupported", "error": reason})
        return
    isolation.limit_memory(config.get("memory_limit_mb"))

    send("step", "warmup")
    t0 = time.perf_counter_ns()
    if impl.warmup is not None:
        impl.warmup()
    _, small, small_weights = case_input(min(case["n"], WARMUP_N))
    # Scaled by a power no repeat uses: a small case's warm-up input is not a repeat's input.
    small, small_weights = scaled_input(small, small_weights, int(config.get("warmup_shift") or 0))
    impl.run(small, {}, weights=small_weights)
    send("data", {"warmup_s": (time.perf_counter_ns() - t0) / 1e9})

    # Everything alive now (libraries, inputs) is moved out of the collector's reach, so the
    # collection before each build costs microseconds instead of ~0.1 s.
    gc.collect()
    gc.freeze()
    shifts = list(config.get("shifts") or [0])
    repeat, min_time = config["repeat"], config.get("min_time") or 0.0
    timed_ns, i = 0, 0
    # At least `repeat` builds; fast ones are repeated until `min_time` of timed builds (capped).
    while i < repeat or (timed_ns < min_time * 1e9 and i < MAX_REPEAT):
        send("step", f"repeat {i + 1}/{repeat}" if i < repeat else f"repeat {i + 1} (filling min-time)")
        stats: dict = {}
        timings: dict = {}
        shift = shifts[i % len(shifts)]
        given, given_weights = scaled_input(sites, weights, shift)
        diagram, ns, peak, own = _timed_build(impl, given, stats, timings, given_weights)
        timed_ns += ns
        row = {"time_s": ns / 1e9, "peak_rss_mb": peak, "mem_mb": own, "input_scale_log2": shift} \
            | _measured_columns({}, timings)
        if i == 0:
            counts = diagram.counts()
            row.update(V=counts["V"], E=counts["E"], **_measured_columns(stats, {}))
        send("repeat", row, diagram_arrays(diagram))
        diagram = None                      # free this result before the next build
        wait()                              # the parent has taken the diagram in: nothing of it overlaps the next build
        i += 1
    send("done", None)


def run_and_report(case: dict, config: dict, send: Send, wait: Callable[[], None] = lambda: None) -> None:
    """Run the case's steps in this process; every failure is sent as ``("failed", ...)``."""
    try:
        _run_steps(case, config, send, wait)
    except InputMutated as exc:
        send("failed", {"status": "error", "verdict": "mutated_input", "error": str(exc)[:500]})
    except MemoryError as exc:
        send("failed", {"status": "oom", "error": f"MemoryError: {exc}"[:500]})
    except BuildRaised as exc:              # whatever its class, raised by the build: the implementation's error
        send("failed", {"status": "error", "error": safe_message(exc.__cause__ or exc)[:500]})
    except BaseException as exc:  # noqa: BLE001 - every failure of the case is reported as data
        send("failed", {"status": "error", "error": safe_message(exc)[:500]})


def worker_main(conn, case: dict, config: dict) -> None:
    """Entry point of the worker process: run the case's steps, report over ``conn`` (duplex:
    the parent answers each repeat when it has taken it in)."""
    isolation.enter_worker()
    signal.signal(signal.SIGINT, signal.SIG_IGN)    # Ctrl-C is the parent's to handle

    def send(kind: str, payload: Any = None, arrays: Optional[dict] = None) -> None:
        conn.send_bytes(wire.encode(kind, payload, arrays))

    def wait() -> None:
        conn.recv_bytes(16)

    try:
        run_and_report(case, config, send, wait)
    finally:
        conn.close()
