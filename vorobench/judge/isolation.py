"""Worker processes that never outlive the harness, and never take it down with them.

Every process that runs an implementation (a benchmark worker, a judging sandbox) calls
:func:`enter_worker` first: it leads a session and process group of its own (so killing the group takes
any grandchild with it) and asks the kernel for SIGKILL when its parent dies (Linux
``PR_SET_PDEATHSIG``). The harness side registers each worker with :func:`watch` and ends it
with :func:`kill_worker`. A reaper process (:mod:`vorobench.judge.reaper`) holds the same list and
kills what is left when the harness ends in any way, SIGKILL included: nothing spins on at
100 % CPU after a killed run. :func:`install_termination_handler` turns SIGTERM into a
:class:`Terminated` exception, so a terminated run unwinds (workers killed, results kept)
like Ctrl-C does.
"""

from __future__ import annotations

import ctypes
import multiprocessing as mp
import os
import signal
import subprocess
import sys
import threading
from pathlib import Path
from typing import Optional

__all__ = ["FORKSERVER_PRELOAD", "enter_worker", "watch", "release", "kill_worker", "limit_memory", "describe_death", "Terminated",
           "install_termination_handler", "default_start_method"]

_PR_SET_PDEATHSIG = 1

#: Modules the fork server imports once, so that every worker forked from it (benchmark
#: workers and judging sandboxes alike: one server per process) starts with them loaded.
FORKSERVER_PRELOAD = ("numpy", "scipy.spatial", "numba", "datasets_gen", "impls", "vorobench.core.prepare",
                      "vorobench.judge.certificate", "vorobench.judge.comparison", "vorobench.judge.engine", "vorobench.judge.sandbox",
                      "vorobench.harness.worker")


class Terminated(BaseException):
    """SIGTERM arrived: unwind like KeyboardInterrupt (exit status 143)."""


def enter_worker(expected_parent: Optional[int] = None) -> None:
    """Set up this process as an isolated worker: own process group, killed with its parent.

    ``expected_parent`` is the pid the worker's parent had when it was started; if that parent
    is already gone, the worker exits at once instead of running orphaned.
    """
    try:
        os.setsid()     # a session and group of its own: its killpg(0, ...) cannot reach the harness
    except OSError:
        try:
            os.setpgid(0, 0)
        except OSError:     # already a group leader, or not allowed here: the kill falls back to the pid
            pass
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if expected_parent is not None and os.getppid() != expected_parent:
        os._exit(1)     # the parent died before the kernel could be told


def limit_memory(extra_mb: Optional[float]) -> None:
    """Cap this process's address space at its current size plus ``extra_mb`` MiB, so that a
    runaway build raises MemoryError instead of waking the out-of-memory killer."""
    if not extra_mb:
        return
    # POSIX only: imported where a memory limit is set, so the module loads everywhere
    import resource

    try:
        with open("/proc/self/status") as f:
            size_kb = next(int(line.split()[1]) for line in f if line.startswith("VmSize:"))
    except (OSError, StopIteration, ValueError):
        return
    limit = int((size_kb / 1024.0 + extra_mb) * 1024 * 1024)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def describe_death(exitcode: Optional[int]) -> tuple[str, str]:
    """(kind, how) for a worker that ended without a result: kind "oom" for SIGKILL (the
    out-of-memory killer's signal), "crashed" for any other signal or any exit status."""
    if exitcode is None:
        return "crashed", "the worker ended without a result"
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        if -exitcode == signal.SIGKILL:
            return "oom", (f"the worker was killed by {name} (most likely the out-of-memory killer; "
                           f"or the implementation killed itself)")
        return "crashed", f"the worker was killed by {name}"
    return "crashed", f"the worker exited with status {exitcode} (os._exit or sys.exit inside the implementation)"


class _Reaper:
    """The harness side of the reaper: one per harness process, started on first use."""

    def __init__(self) -> None:
        self._proc: Optional[subprocess.Popen] = None
        self._pid = 0
        self._lock = threading.Lock()

    def _send(self, line: str) -> None:
        with self._lock:
            if self._proc is None or self._pid != os.getpid():   # none yet, or inherited by a fork
                script = Path(__file__).with_name("reaper.py")
                self._proc = subprocess.Popen([sys.executable, "-S", str(script)], stdin=subprocess.PIPE,
                                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                              start_new_session=True, text=True, bufsize=1)
                self._pid = os.getpid()
            try:
                self._proc.stdin.write(line + "\n")
                self._proc.stdin.flush()
            except (BrokenPipeError, OSError, ValueError):   # reaper gone: workers still die with their parent
                self._proc = None


_REAPER = _Reaper()


def watch(pid: int) -> None:
    """Have the reaper kill worker ``pid`` (and its group) if this process ends first."""
    _REAPER._send(f"+{pid}")


def release(pid: int) -> None:
    """Worker ``pid`` is gone: forget it (its pid may be reused)."""
    _REAPER._send(f"-{pid}")


def kill_worker(proc, join_seconds: float = 10.0) -> None:
    """Kill a worker process and every process of its group, wait for it, forget it."""
    pid = proc.pid
    if pid is not None:
        for kill in (os.killpg, os.kill):
            try:
                kill(pid, signal.SIGKILL)
                break
            except (ProcessLookupError, PermissionError):
                continue
        proc.join(join_seconds)
        release(pid)


def install_termination_handler() -> None:
    """Raise :class:`Terminated` in the main thread on SIGTERM (and SIGHUP)."""
    if threading.current_thread() is not threading.main_thread():
        return

    def handler(signum, frame):
        raise Terminated(f"terminated by {signal.Signals(signum).name}")

    signal.signal(signal.SIGTERM, handler)
    signal.signal(signal.SIGHUP, handler)


def default_start_method() -> str:
    """"forkserver" where the platform has it (Linux, macOS), else "spawn"."""
    return "forkserver" if "forkserver" in mp.get_all_start_methods() else "spawn"
