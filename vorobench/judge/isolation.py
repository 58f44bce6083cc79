"""Worker processes that never outlive the harness, and never take it down with them.

Every process that runs an implementation (a benchmark worker, a judging sandbox) calls
:func:`enter_worker` first: it leads a session and process group of its own (so killing the group takes
any grandchild with it) and asks the kernel for SIGKILL when its parent dies (Linux
``PR_SET_PDEATHSIG``). A worker forked from the multiprocessing fork server has that server as its
parent, not the harness, and the kernel's signal reaches the worker alone, never its group: so the
worker also lets go of the fork server (which then ends with the harness) and starts a guard, a
process of its group that kills the whole group when the worker, its parent or the harness ends
(:func:`guard_group`). The harness side registers each worker with :func:`watch` and ends it
with :func:`kill_worker`. A reaper process (:mod:`vorobench.judge.reaper`) holds the same list and
kills what is left when the harness ends in any way, SIGKILL included: nothing spins on at
100 % CPU after a killed run. :func:`install_termination_handler` turns SIGTERM into a
:class:`Terminated` exception, so a terminated run unwinds (workers killed, results kept)
like Ctrl-C does.
"""

from __future__ import annotations

import ctypes
import gc
import multiprocessing as mp
import multiprocessing.forkserver
import os
import select
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Optional, Sequence

from vorobench.judge.outcomes import OutcomeKind

__all__ = ["FORKSERVER_PRELOAD", "enter_worker", "watch", "release", "kill_worker", "limit_memory", "describe_death", "Terminated",
           "install_termination_handler", "default_start_method", "guard_group"]

_PR_SET_PDEATHSIG = 1

#: Modules the fork server imports once, so that every worker forked from it (benchmark
#: workers and judging sandboxes alike: one server per process) starts with them loaded.
FORKSERVER_PRELOAD = ("numpy", "scipy.spatial", "numba", "datasets_gen", "impls", "impls.fortune", "impls.halfplane",
                      "impls.incremental", "impls.qhull", "vorobench.core.prepare",
                      "vorobench.judge.certificate", "vorobench.judge.comparison", "vorobench.judge.engine", "vorobench.judge.sandbox",
                      "vorobench.harness.worker")


class Terminated(BaseException):
    """SIGTERM arrived: unwind like KeyboardInterrupt (exit status 143)."""


#: Set in every sandbox process: code there owns the process and all its children.
SANDBOX_VARIABLE = "VOROBENCH_SANDBOX"


def enter_worker(expected_parent: Optional[int] = None) -> None:
    """Set up this process as an isolated worker: own process group, killed with its parent,
    the group killed with the worker, its parent or the harness.

    ``expected_parent`` is the pid the worker's parent had when it was started; if that parent
    is already gone, the worker exits at once instead of running orphaned.
    """
    _lead_own_group()
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if expected_parent is not None and os.getppid() != expected_parent:
        os._exit(1)     # the parent died before the kernel could be told
    owners = [os.getppid()]
    if _release_fork_server():
        harness = _parent_of(owners[0])     # the fork server's parent: the process that asked for this worker
        if harness is not None:
            owners.append(harness)
    guard_group(owners)


def _lead_own_group() -> None:
    """Lead a session and process group of our own, so that killpg(0, ...) cannot reach the harness."""
    try:
        os.setsid()
    except OSError:
        try:
            os.setpgid(0, 0)
        except OSError:     # already a group leader, or not allowed here: the kill falls back to the pid
            pass


def _release_fork_server() -> bool:
    """Close this process's copy of the fork server's "alive" pipe; True if it was forked from a
    fork server.

    The server ends when every holder of that pipe's write end has closed it; the harness
    holds one, and the fork server hands a copy to each child. A worker that kept its copy
    would keep the server, its parent, alive after the harness died (and with it the worker:
    its parent-death signal would never come)."""
    server = multiprocessing.forkserver._forkserver
    if server.get_inherited_fds() is None:      # not started by a fork server
        return False
    if server._forkserver_pid is None and server._forkserver_alive_fd is not None:   # a copy, not a server of ours
        try:
            os.close(server._forkserver_alive_fd)
        except OSError:
            pass
        server._forkserver_alive_fd = None
    return True


def _parent_of(pid: int) -> Optional[int]:
    """The parent pid of process ``pid`` (Linux /proc), or None if it cannot be read."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()    # the name in parentheses may hold spaces
        return int(fields[1])
    except (OSError, IndexError, ValueError):
        return None


def guard_group(owners: Sequence[int]) -> Optional[int]:
    """Fork a guard: a process of this worker's group that SIGKILLs the whole group as soon as
    this worker or any of ``owners`` ends. Returns the guard's pid, or None when this process
    does not lead its own group (killing "its" group could then reach the harness).

    The kernel's parent-death signal kills the worker alone; a grandchild the implementation
    started would be orphaned and run on. The guard runs no implementation code and ignores
    the signals a group gets from a terminal or a ``killpg(0, SIGTERM)``, so it is still there
    when the owners die, whatever they die of. (Where it cannot be started, the worker runs
    as before: killed with its parent, its group left to the reaper.)
    """
    group = os.getpid()
    if not hasattr(os, "fork") or os.getpgrp() != group:
        return None
    watched = [group, *(p for p in owners if p > 1)]     # pid 1 (or 0: outside our namespace) never ends
    try:
        pid = os.fork()
    except OSError:         # out of processes: no guard rather than no worker
        return None
    if pid:
        return pid
    try:
        _guard(group, watched)
    finally:
        os._exit(0)


def _guard(group: int, watched: list[int]) -> None:
    """The guard process: wait until one of ``watched`` ends, then kill ``group`` (and itself)."""
    gc.disable()        # no finalizer may close a descriptor number that is reused below
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP, signal.SIGQUIT, signal.SIGUSR1, signal.SIGUSR2):
        signal.signal(sig, signal.SIG_IGN)
    _drop_inherited_fds()
    _wait_for_any_end(watched)
    os.killpg(group, signal.SIGKILL)


def _drop_inherited_fds() -> None:
    """Close every descriptor the worker had: the guard must hold none of its pipes open."""
    null = os.open(os.devnull, os.O_RDWR)
    for fd in (0, 1, 2):
        if fd != null:
            os.dup2(null, fd)
    limit = os.sysconf("SC_OPEN_MAX")
    os.closerange(3, limit if limit > 0 else 65536)


def _wait_for_any_end(pids: list[int]) -> None:
    """Return when any of ``pids`` has ended (at once if one already has)."""
    handles = []
    try:
        for pid in pids:
            handles.append(os.pidfd_open(pid))
    except ProcessLookupError:
        return
    except (AttributeError, OSError):      # no pidfd here (not Linux, or a kernel before 5.3): poll
        _poll_for_any_end(pids)
        return
    select.select(handles, [], [])


def _poll_for_any_end(pids: list[int]) -> None:
    """:func:`_wait_for_any_end` without pidfd: look twice a second (a zombie counts as alive)."""
    worker = pids[0]
    while os.getppid() == worker:
        for pid in pids[1:]:
            try:
                os.kill(pid, 0)
            except ProcessLookupError:
                return
            except PermissionError:
                pass
        time.sleep(0.5)


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


def describe_death(exitcode: Optional[int]) -> tuple[OutcomeKind, str]:
    """(kind, how) for a worker that ended without a result: kind "oom" for SIGKILL (the
    out-of-memory killer's signal), "crashed" for any other signal or any exit status."""
    if exitcode is None:
        return OutcomeKind.CRASHED, "the worker ended without a result"
    if exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        if -exitcode == signal.SIGKILL:
            return OutcomeKind.OOM, (f"the worker was killed by {name} (most likely the out-of-memory killer; "
                                     f"or the implementation killed itself)")
        return OutcomeKind.CRASHED, f"the worker was killed by {name}"
    return OutcomeKind.CRASHED, (f"the worker exited with status {exitcode} (os._exit or sys.exit inside the "
                                 "implementation)")


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
