"""Test-only implementations that misbehave on purpose, loaded into workers with ``--plugin``.

Each wraps Qhull's build (a correct diagram) with one fault: a hard exit (status 3 or 0),
``SystemExit(0)``, a segfault, a hang, a hang in a grandchild process, an impossible allocation,
a Python exception, a change to its input, a refusal, a sleep, a large allocation, a wrong
diagram, or seconds passed off as a counter (``timing_in_counters``; ``timed_parts`` reports
them the right way). ``steady`` sleeps for
``VOROBENCH_TEST_SLEEP`` seconds (default 0.02) before building and reports counters scaled by
``VOROBENCH_TEST_COUNTER_SCALE`` (default 1): the environment variables let a test slow it
down or change its counters between two runs without renaming it.
"""

from __future__ import annotations

import ctypes
import dataclasses
import os
import signal
import subprocess
import sys
import time

import numpy as np

from impls.base import Implementation
from impls.qhull import build as qhull_build
from vorobench.core.diagram import Diagram

__all__ = ["IMPLEMENTATIONS", "HUNGRY_MB"]

#: What the ``hungry`` double allocates (and frees) during each build, in MiB.
HUNGRY_MB = 200


def _crash_exit(sites, stats=None):
    os._exit(3)                                  # no exception, no cleanup: the process is gone


def _exit_zero(sites, stats=None):
    os._exit(0)                                  # a "successful" exit in the middle of a build


def _system_exit(sites, stats=None):
    raise SystemExit(0)


def _mutate(sites, stats=None):
    sites.setflags(write=True)                   # a copy it owns may be made writeable again
    sites[0] += 0.25                             # moves a site, then builds the moved sites correctly
    return qhull_build(sites, stats)


def _hang_with_grandchild(sites, stats=None):
    """Starts a child that sleeps for an hour, writes both pids to $VOROBENCH_TEST_PIDFILE, spins."""
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(3600)"])
    path = os.environ.get("VOROBENCH_TEST_PIDFILE")
    if path:
        with open(path + ".tmp", "w") as f:
            f.write(f"{os.getpid()} {child.pid}\n")
        os.replace(path + ".tmp", path)
    while True:                                  # 100 % CPU, like a runaway sweep
        pass


def _other_sites(sites, stats=None):
    """The diagram of other sites: the first one moved, the sites labelled as moved."""
    moved = np.array(sites)
    moved[0] += 0.05
    return qhull_build(moved, stats)


class _Booby(Diagram):
    """A Diagram whose unpickling would end the process that reads it."""

    def __reduce__(self):
        return (os._exit, (0,))


def _booby_trapped(sites, stats=None):
    d = qhull_build(sites, stats)
    return _Booby(d.sites, d.vertices, d.origin, d.twin, d.next, d.site)


def _kill_group(sites, stats=None):
    os.killpg(0, signal.SIGTERM)                 # "its" process group: must not reach the judge
    time.sleep(5)
    return qhull_build(sites, stats)


def _fork_and_die(sites, stats=None):
    """Leaves a child sleeping for an hour (pid in $VOROBENCH_TEST_PIDFILE), then ends itself."""
    child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(3600)"])
    path = os.environ.get("VOROBENCH_TEST_PIDFILE")
    if path:
        with open(path, "w") as f:
            f.write(f"{child.pid}\n")
    os._exit(3)


def _crash_segfault(sites, stats=None):
    ctypes.string_at(0)                          # reads address 0: SIGSEGV


def _hang(sites, stats=None):
    time.sleep(3600)


def _hog(sites, stats=None):
    return np.empty((1 << 50,), dtype=np.float64)    # 8 PiB: numpy raises MemoryError


def _fail(sites, stats=None):
    raise RuntimeError("deliberate failure")


def _steady(sites, stats=None):
    time.sleep(float(os.environ.get("VOROBENCH_TEST_SLEEP", "0.02")))
    if stats is not None:
        stats["sites_seen"] = int(sites.shape[0]) * int(os.environ.get("VOROBENCH_TEST_COUNTER_SCALE", "1"))
    return qhull_build(sites, stats)


def _hang_after_warmup(sites, stats=None):
    if sites.shape[0] > 64:                      # the warm-up build is small; the timed one hangs
        time.sleep(3600)
    return qhull_build(sites, stats)


def _hungry(sites, stats=None):
    block = np.ones(HUNGRY_MB * (1 << 20) // 8)  # touched, so resident: the peak must show it
    block[-1] = 2.0
    return qhull_build(sites, stats)


def _wrong(sites, stats=None):
    moved = sites.copy()
    moved[0] += 0.05                             # the diagram of other sites, labelled with these
    return dataclasses.replace(qhull_build(moved, stats), sites=sites)


def _timing_in_counters(sites, stats=None):
    t0 = time.perf_counter()
    diagram = qhull_build(sites, None)
    if stats is not None:
        stats["build_seconds"] = time.perf_counter() - t0      # a time is not a counter
    return diagram


def _timed_parts(sites, stats=None):
    from impls.base import record_timing

    t0 = time.perf_counter()
    diagram = qhull_build(sites, stats)
    record_timing("library", time.perf_counter() - t0)
    record_timing("convert", 1e-6)
    if stats is not None:
        stats["calls"] = 1
    return diagram


def _refuse(sites):
    return "refuses every input (test double)"


def _double(name: str, build, **kw) -> Implementation:
    return Implementation(name=name, description=f"test double: {name}", complexity="n/a",
                          build=build, exact=False, origin="tests", **kw)


IMPLEMENTATIONS = [
    _double("crash_exit", _crash_exit),
    _double("crash_segfault", _crash_segfault),
    _double("exit_zero", _exit_zero),
    _double("system_exit", _system_exit),
    _double("mutate", _mutate),
    _double("hang_with_grandchild", _hang_with_grandchild),
    _double("other_sites", _other_sites),
    _double("booby_trapped", _booby_trapped),
    _double("kill_group", _kill_group),
    _double("fork_and_die", _fork_and_die),
    _double("hang", _hang),
    _double("hang_after_warmup", _hang_after_warmup),
    _double("hog", _hog),
    _double("fail", _fail),
    _double("steady", _steady),
    _double("hungry", _hungry),
    _double("wrong", _wrong),
    _double("refuse", qhull_build, supports=_refuse),
    _double("timing_in_counters", _timing_in_counters),
    _double("timed_parts", _timed_parts),
]
