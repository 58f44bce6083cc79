"""The sandbox side of a benchmark case: what runs in the implementation's process to time it.

The runner (:mod:`vorobench.harness.runner`) starts one :class:`~vorobench.judge.sandbox.Sandbox`
per (implementation, dataset, n, seed, weight or radius family), the same sandbox that judging uses, and
asks it for :func:`prepare_timing`, then one :func:`timed_repeat` per repeat, each with its own
timeout. A weighted case builds the power diagram of the points with weights of that family
(:func:`datasets_gen.weights`), a case of disks the diagram of the disks centred at the points
with radii of that family (:func:`datasets_gen.radii`, docs/apollonius.md), drawn with the points
before anything is timed (:mod:`vorobench.harness.site_attributes`). Every answer
crosses the bounded wire (:mod:`vorobench.judge.wire`): the runner checks sizes before it
allocates and judges every repeat's diagram itself. Nothing is judged in this process.

Timing protocol: inputs are generated and prepared before anything is timed; the warm-up
(``Implementation.warmup`` plus one untimed build of a small input from the same dataset)
absorbs JIT compilation and is timed on its own; each repeat is one ``perf_counter_ns`` wall
time with the garbage collector collected before and paused during the build; the resident
peak is reset before each build so the build's own peak memory is measured. An executable's
build is its program's process: wall time from its start to its end, its CPU time and peak
(:mod:`impls.executable`), the harness's conversion kept apart as ``time_protocol_s``. Repeat i builds the
sites scaled by ``2**shifts[i]`` (their weights by ``4**shifts[i]``, their radii by ``2**shifts[i]``; the
parent's choice: the same order and the same diagram, the vertices scaled alike, but other
bytes), so a result cached by its input cannot fake a timing.
Each repeat is a request of its own, so the runner's work never overlaps a timed build. Builds
shorter than a scheduler time slice are repeated until ``min_time`` seconds are timed (at most
``MAX_REPEAT`` builds).
"""

from __future__ import annotations

import gc
import time
from typing import Any, Callable, Optional

import numpy as np

import impls
from impls.base import BuildRaised
from vorobench.harness import peakmem
from vorobench.harness.site_attributes import SiteAttribute, attribute_of, generate_input, keywords
from vorobench.judge.engine import declined_reason, diagram_arrays
from vorobench.judge.outcomes import COUNTER_PREFIX, timing_column

__all__ = ["prepare_timing", "timed_repeat", "scaled_input", "MAX_REPEAT", "WARMUP_N"]

#: Smallest input used for the untimed warm-up build (capped by the case's own n).
WARMUP_N = 64

#: Most builds per case when short builds are repeated to fill ``min_time``.
MAX_REPEAT = 25


def scaled_input(sites: np.ndarray, values: Optional[np.ndarray], shift: int,
                 attribute: Optional[SiteAttribute] = None) -> tuple[np.ndarray, Optional[np.ndarray]]:
    """The sites times ``2**shift`` and their ``attribute`` values scaled with them (weights
    times ``4**shift``, a power being a squared length; radii times ``2**shift``): exactly the
    same diagram, its vertices times ``2**shift``."""
    if shift == 0:
        return sites, values
    return np.ldexp(sites, shift), (None if values is None else attribute.scaled(values, shift))


def _timed_build(impl, sites, stats, timings, extra: dict) -> tuple[object, int, float, float, int]:
    """One build (``extra``: the weights or radii by keyword, or nothing): (diagram, wall ns, peak
    resident MiB during it, own peak above the start, CPU ns of this process during it: the
    build's own run time, which a busy neighbour does not add to)."""
    gc.collect()
    peakmem.reset_peak()
    before = peakmem.current_rss_mb()
    process: dict = {}
    gc.disable()
    try:
        c0 = time.process_time_ns()
        t0 = time.perf_counter_ns()
        # A read-only copy; a change of it, or a counter that is not an integer, is an error.
        diagram = impl.run(sites, stats, timings=timings, check_supports=False, wrap_build_errors=True,
                           process=process, **extra)
        elapsed = time.perf_counter_ns() - t0
        cpu = time.process_time_ns() - c0
    finally:
        gc.enable()
    peak = peakmem.peak_rss_mb()
    if process:
        # An executable: its program's own process is the build (whole-process time, CPU and
        # peak); reading its answer and assembling the diagram is the harness's (time_protocol_s).
        return (diagram, int(process["wall_s"] * 1e9), process["peak_rss_mb"], process["peak_rss_mb"],
                int(process["cpu_s"] * 1e9))
    return diagram, elapsed, peak, max(0.0, peak - before), cpu


def _measured_columns(stats: dict, timings: dict) -> dict[str, float]:
    """The build's counters as ``stat_<name>`` columns (integers, checked by ``Implementation.run``)
    and the parts of its time as ``time_<phase>_s`` columns."""
    return ({f"{COUNTER_PREFIX}{key}": int(value) for key, value in stats.items()}
            | {timing_column(phase): float(seconds) for phase, seconds in timings.items()})


#: The case a sandbox times: its implementation, input and the repeats' powers of two, kept
#: between the requests of one case (a sandbox serves one case, then is closed).
_CASE: dict = {}


def prepare_timing(case: dict, shifts: list[int], warmup_shift: int) -> tuple[dict, None]:
    """Runs in the sandbox: generate and prepare the case's input (outside anything timed),
    screen it with ``supports``, run the untimed warm-up build on a small input of another
    scale, and keep the input for :func:`timed_repeat`. Returns the set-up's measurements, or
    ``{"unsupported": reason}``."""
    impl = impls.get(case["impl"])
    attribute, family = attribute_of(case.get("weights") or "", case.get("radii") or "")
    data: dict[str, Any] = {"rss_base_mb": peakmem.current_rss_mb()}

    def case_input(n: int):
        """(points, sites, site weights or radii or None) of the case's dataset at size ``n``."""
        return generate_input(case["dataset"], n, case["seed"], attribute, family)

    t0 = time.perf_counter_ns()
    points, sites, values = case_input(case["n"])
    data.update(setup_s=(time.perf_counter_ns() - t0) / 1e9, n_points=int(points.shape[0]))
    del points
    reason = declined_reason(impl, sites)
    if reason:
        return {"unsupported": reason}, None
    t0 = time.perf_counter_ns()
    _, small, small_values = case_input(min(case["n"], WARMUP_N))
    # Scaled by a power no repeat uses: a small case's warm-up input is not a repeat's input.
    small, small_values = scaled_input(small, small_values, int(warmup_shift), attribute)
    _unwrapped(impl.run, small, {}, wrap_build_errors=True, **keywords(attribute, small_values))
    data["warmup_s"] = (time.perf_counter_ns() - t0) / 1e9
    _CASE.update(impl=impl, sites=sites, values=values, attribute=attribute, shifts=list(shifts) or [0])
    # Everything alive now (libraries, inputs) is moved out of the collector's reach, so the
    # collection before each build costs microseconds instead of ~0.1 s.
    gc.collect()
    gc.freeze()
    return data, None


def timed_repeat(index: int) -> tuple[dict, dict]:
    """Runs in the sandbox: timed build number ``index`` of the prepared case, on its sites
    times ``2**shifts[index]`` (weights or radii scaled with them): (timings, memory and
    counters; the diagram's arrays)."""
    shifts = _CASE["shifts"]
    shift = shifts[index % len(shifts)]
    attribute = _CASE["attribute"]
    given, given_values = scaled_input(_CASE["sites"], _CASE["values"], shift, attribute)
    stats: dict = {}
    timings: dict = {}
    diagram, ns, peak, own, cpu = _unwrapped(_timed_build, _CASE["impl"], given, stats, timings,
                                             keywords(attribute, given_values))
    row = {"time_s": ns / 1e9, "cpu_s": cpu / 1e9, "peak_rss_mb": peak, "mem_mb": own, "input_scale_log2": shift} \
        | _measured_columns(stats if index == 0 else {}, timings)
    return row, diagram_arrays(diagram)


def _unwrapped(fn: Callable, *args, **kwargs):
    """``fn(...)``, with an exception the build raised passed on as itself (its class and
    message are what the judge reports), not as the wrapper that marked it."""
    try:
        return fn(*args, **kwargs)
    except BuildRaised as exc:
        raise (exc.__cause__ or exc) from None
