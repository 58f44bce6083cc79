"""The worker side of a benchmark case: runs in its own process and reports step by step.

The parent (:mod:`vorobench.runner`) starts one worker per (implementation, dataset, n, seed).
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

import contextlib
import gc
import importlib
import importlib.util
import os
import resource
import signal
import sys
import time
import traceback
import zlib
from pathlib import Path
from typing import Any, Callable, Iterator, Optional, Sequence

from vorobench import peakmem

__all__ = ["worker_main", "run_and_report", "load_plugin", "plugins_registered", "check_against_reference", "reference_diagram"]

Send = Callable[[str, Any], None]

#: Smallest input used for the untimed warm-up build (capped by the case's own n).
WARMUP_N = 64

#: Most builds per case when short builds are repeated to fill ``min_time``.
MAX_REPEAT = 25


def load_plugin(spec: str) -> list[str]:
    """Import a module (dotted name or ``.py`` path) and register its ``IMPLEMENTATIONS``.

    A plugin module defines ``IMPLEMENTATIONS`` (a list of :class:`impls.Implementation`) or
    ``IMPLEMENTATION``; nothing happens at its import time, the runner registers them here, in
    the parent and in every worker. Returns the registered names.
    """
    import impls

    if spec.endswith(".py") or os.sep in spec:
        path = Path(spec).resolve()
        if not path.is_file():
            raise FileNotFoundError(f"plugin file not found: {spec}")
        name = f"vorobench_plugin_{zlib.crc32(str(path).encode()):08x}"
        module = sys.modules.get(name)
        if module is None:
            module_spec = importlib.util.spec_from_file_location(name, path)
            module = importlib.util.module_from_spec(module_spec)
            sys.modules[name] = module
            module_spec.loader.exec_module(module)
    else:
        module = importlib.import_module(spec)
    found = list(getattr(module, "IMPLEMENTATIONS", []))
    if hasattr(module, "IMPLEMENTATION"):
        found.append(module.IMPLEMENTATION)
    if not found:
        raise ValueError(f"plugin {spec!r} defines neither IMPLEMENTATIONS nor IMPLEMENTATION")
    for impl in found:
        impls.register(impl)
    return [impl.name for impl in found]


@contextlib.contextmanager
def plugins_registered(specs: Sequence[str]) -> Iterator[list[str]]:
    """Register plugin implementations for the duration of a run in this process, then remove
    them, so a test double never outlives the run that asked for it."""
    import impls

    before = set(impls.registered())          # a nested use leaves the outer registrations alone
    names: list[str] = []
    try:
        for spec in specs:
            names += load_plugin(spec)
        yield names
    finally:
        for name in names:
            if name not in before:
                impls.unregister(name)


def reference_diagram(reference: str, dataset: str, n: int, seed: int, sites, cache_dir: Optional[str]):
    """The reference implementation's diagram of these sites, from the on-disk cache if there.

    Ground truth is computed once per (dataset, n, seed) and stored as ``.npz`` so every other
    implementation's case loads it instead of rebuilding it.
    """
    import numpy as np

    import impls
    from vorobench.diagram import Diagram

    path = None
    if cache_dir:
        path = Path(cache_dir) / f"{reference}-{dataset}-{n}-{seed}.npz"
        if path.exists():
            try:
                cached = Diagram.load(path)
                if cached.sites.shape == sites.shape and np.array_equal(cached.sites, sites):
                    return cached
            except Exception:  # a damaged cache file is rebuilt, not trusted
                pass
    diagram = impls.get(reference).build(sites, None)
    if path is not None:
        store_reference(path, diagram)
    return diagram


def store_reference(path: Path, diagram) -> None:
    """Write a reference diagram atomically (a half-written file never looks complete)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}.npz")
    diagram.save(tmp)
    os.replace(tmp, path)


def check_against_reference(impl_name: str, diagram, reference: str, reference_diagram,
                            reference_error: str = "") -> dict:
    """The correctness verdict of one built diagram, as result columns.

    The single place that judges a case: the already-built diagram (no second build) and the
    reference's are certified, compared, and the cross-validation rules of
    :mod:`vorobench.crossval` decide the verdict and who is to blame.
    """
    import impls
    from vorobench import crossval
    from vorobench.certify import certify

    def exact(name: str) -> bool:
        try:
            return bool(impls.get(name).exact)
        except Exception:  # an unknown reference is judged strictly
            return True

    res = crossval.BuildResult(impl_name, exact(impl_name), diagram, certify(diagram))
    if impl_name == reference:
        ref = res
    elif reference_diagram is None:
        ref = crossval.BuildResult(reference, exact(reference), error=reference_error or "no reference diagram")
    else:
        ref = crossval.BuildResult(reference, exact(reference), reference_diagram, certify(reference_diagram))
    verdict = crossval._decide(impl_name, reference, res, ref)
    return {"verdict": verdict.verdict, "check_passed": bool(verdict.passed), "blame": verdict.blame or "",
            "verdict_detail": _first_line(verdict.message)}


def _first_line(obj: object) -> str:
    text = str(obj).strip().splitlines()
    return text[0][:300] if text else ""


def _limit_address_space(extra_mb: Optional[float]) -> None:
    """Cap the worker's address space so a runaway build raises MemoryError, not the OOM killer."""
    if not extra_mb:
        return
    try:
        size_kb = next(int(line.split()[1]) for line in Path("/proc/self/status").read_text().splitlines()
                       if line.startswith("VmSize:"))
    except (OSError, StopIteration, ValueError):
        return
    limit = int((size_kb / 1024.0 + extra_mb) * 1024 * 1024)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def _timed_build(build, sites, stats) -> tuple[object, int, float, float]:
    """One build: (diagram, wall ns, peak resident MiB during it, own peak above the start)."""
    gc.collect()
    peakmem.reset_peak()
    before = peakmem.current_rss_mb()
    gc.disable()
    try:
        t0 = time.perf_counter_ns()
        diagram = build(sites, stats)
        elapsed = time.perf_counter_ns() - t0
    finally:
        gc.enable()
    peak = peakmem.peak_rss_mb()
    return diagram, elapsed, peak, max(0.0, peak - before)


def _numeric_stats(stats: dict) -> dict[str, float]:
    """The implementation's counters as ``stat_<name>`` columns (numbers only)."""
    out = {}
    for key, value in stats.items():
        try:
            out[f"stat_{key}"] = float(value) if not isinstance(value, (int, bool)) else int(value)
        except (TypeError, ValueError):
            continue
    return out


def _run_steps(case: dict, config: dict, send: Send) -> None:
    if config.get("environ") is not None:
        os.environ.clear()
        os.environ.update(config["environ"])
    for spec in config.get("plugins", ()):
        load_plugin(spec)
    import datasets_gen
    import impls
    from vorobench.prepare import prepare

    impl = impls.get(case["impl"])
    send("data", {"rss_base_mb": peakmem.current_rss_mb()})

    send("step", "generate")
    t0 = time.perf_counter_ns()
    points = datasets_gen.generate(case["dataset"], case["n"], seed=case["seed"])
    sites, _ = prepare(points)
    send("data", {"setup_s": (time.perf_counter_ns() - t0) / 1e9,
                  "n_points": int(points.shape[0]), "n_sites": int(sites.shape[0])})
    del points
    if impl.supports is not None:
        reason = impl.supports(sites)
        if reason:
            send("failed", {"status": "unsupported", "error": str(reason)})
            return
    _limit_address_space(config.get("memory_limit_mb"))

    send("step", "warmup")
    t0 = time.perf_counter_ns()
    if impl.warmup is not None:
        impl.warmup()
    small = datasets_gen.generate(case["dataset"], min(case["n"], WARMUP_N), seed=case["seed"])
    impl.build(prepare(small)[0], {})
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
        diagram = None                      # free the previous result before the next build
        diagram, ns, peak, own = _timed_build(impl.build, sites, stats)
        timed_ns += ns
        row = {"time_s": ns / 1e9, "peak_rss_mb": peak, "mem_mb": own}
        if i == 0:
            counts = diagram.counts()
            row.update(V=counts["V"], E=counts["E"], **_numeric_stats(stats))
        send("repeat", row)
        i += 1

    if config.get("check", True) and config.get("reference"):
        send("step", "check")
        t0 = time.perf_counter_ns()
        try:
            ref, ref_error = None, ""
            if impl.name == config["reference"]:
                if config.get("reference_cache"):
                    store_reference(Path(config["reference_cache"]) /
                                    f"{impl.name}-{case['dataset']}-{case['n']}-{case['seed']}.npz", diagram)
            else:
                try:
                    ref = reference_diagram(config["reference"], case["dataset"], case["n"], case["seed"],
                                            sites, config.get("reference_cache"))
                except Exception as exc:            # the reference's failure is not this case's
                    ref_error = f"{type(exc).__name__}: {exc}"
            verdict = check_against_reference(impl.name, diagram, config["reference"], ref, ref_error)
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
    except MemoryError as exc:
        send("failed", {"status": "oom", "error": f"MemoryError: {exc}"[:500]})
    except BaseException as exc:  # noqa: BLE001 - every failure of the case is reported as data
        frames = traceback.extract_tb(exc.__traceback__)
        where = f" (at {Path(frames[-1].filename).name}:{frames[-1].lineno})" if frames else ""
        send("failed", {"status": "error", "error": f"{type(exc).__name__}: {exc}"[:400] + where})


def worker_main(conn, case: dict, config: dict) -> None:
    """Entry point of the worker process: run the case's steps, report over ``conn``."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)    # Ctrl-C is the parent's to handle

    def send(kind: str, payload: Any) -> None:
        conn.send((kind, payload))

    try:
        run_and_report(case, config, send)
    finally:
        conn.close()
