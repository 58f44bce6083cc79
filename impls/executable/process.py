"""Running a program once: its stdin written, its stdout read up to a limit, its own measures.

The program is a child of the sandbox, in the sandbox's process group: a timeout of the
request kills both. The sandbox is the reaper of the program's descendants, so a grandchild
that does the work is counted in the CPU time, and one left running is ended. Its stdout is read in chunks and the program is killed the moment it
passes the limit (so a 10 GB answer costs the harness the limit, not 10 GB); stderr keeps
its last ``STDERR_BYTES``. Wall time runs from the start of the process to its end, CPU time
and peak memory are the kernel's accounting of that process (``wait4``).
"""

from __future__ import annotations

import contextlib
import os
import resource
import signal
import subprocess
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Optional

from impls.executable.protocol import InvalidOutput

__all__ = ["ProgramRun", "run_program", "ProgramFailed", "STDERR_BYTES"]

#: How much of the program's stderr is kept (its end: where the reason usually is).
STDERR_BYTES = 16384

_CHUNK = 1 << 20


class ProgramFailed(RuntimeError):
    """The program exited with a nonzero status or was killed by a signal."""

    about_the_program = True


@dataclass
class ProgramRun:
    """One finished run: its stdout, the end of its stderr and the process's own measures."""

    stdout: bytes
    stderr: str
    wall_s: float
    cpu_s: float
    peak_rss_mb: float


def _feed(pipe, data: bytes) -> None:
    try:
        pipe.write(data)
    except (BrokenPipeError, OSError):   # it stopped reading: its exit status says the rest
        pass
    finally:
        try:
            pipe.close()
        except OSError:
            pass


def _drain(pipe, keep: bytearray) -> None:
    while True:
        chunk = pipe.read1(_CHUNK) if hasattr(pipe, "read1") else pipe.read(_CHUNK)
        if not chunk:
            return
        keep += chunk
        if len(keep) > STDERR_BYTES:
            del keep[:len(keep) - STDERR_BYTES]


def _describe(status: int, stderr: str) -> str:
    code = os.waitstatus_to_exitcode(status)
    tail = stderr.strip().splitlines()[-3:]
    said = (": " + " | ".join(tail))[:500] if tail else " (nothing on stderr)"
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        return f"the program was killed by {name}{said}"
    return f"the program exited with status {code}{said}"


#: Words on stderr's last lines by which a program says it ran out of memory.
_OUT_OF_MEMORY = ("bad_alloc", "MemoryError", "out of memory", "Cannot allocate memory", "heap out of memory")


def _adopt_orphans() -> None:
    """Make this process the reaper of its descendants (Linux ``PR_SET_CHILD_SUBREAPER``): a
    program's grandchild, even one that started a session of its own, then stays ours to
    account for and to end."""
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(36, 1, 0, 0, 0)
    except (OSError, AttributeError):    # not Linux: a double fork escapes, as it would anyway
        pass


def _children() -> list[int]:
    pids: list[int] = []
    try:
        for task in Path("/proc/self/task").iterdir():
            pids += [int(p) for p in (task / "children").read_text().split()]
    except (OSError, ValueError):
        pass
    return pids


def _end_leftovers() -> int:
    """Kill and reap whatever the program left running (daemons, grandchildren): they would
    load the machine during the next timing. Returns how many there were."""
    ended = 0
    for _ in range(100):                 # each round's dead may leave orphans of their own
        pids = _children()
        if not pids:
            break
        for pid in pids:
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGKILL)
        for pid in pids:
            with contextlib.suppress(ChildProcessError, OSError):
                os.waitpid(pid, 0)
                ended += 1
    return ended


def _cpu_of_children() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def run_program(argv: list[str], cwd: Path, stdin: bytes, limit: int, env: Optional[dict] = None) -> ProgramRun:
    """Run ``argv`` in ``cwd`` with ``stdin``; raise :class:`InvalidOutput` when it prints more than
    ``limit`` bytes, :class:`ProgramFailed` when it fails, ``MemoryError`` when it says it ran out
    of memory (under the sandbox's limit). CPU time counts the program's descendants too (they
    are reaped here, and any still running when it ends are killed first)."""
    # In a sandbox (a process of its own) the program's descendants are adopted, counted and
    # ended; anywhere else (a build called in the caller's process) other children may be the
    # caller's, so only the program itself is accounted for.
    owned = os.environ.get("VOROBENCH_SANDBOX") == "1"
    if owned:
        _adopt_orphans()
        _end_leftovers()
    cpu_before = _cpu_of_children()
    started = time.perf_counter_ns()
    try:
        proc = subprocess.Popen(argv, cwd=cwd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, env=env, close_fds=True)
    except OSError as exc:
        raise ProgramFailed(f"cannot start {argv[0]}: {exc}") from None
    err = bytearray()
    writer = threading.Thread(target=_feed, args=(proc.stdin, stdin), daemon=True)
    reader = threading.Thread(target=_drain, args=(proc.stderr, err), daemon=True)
    writer.start()
    reader.start()
    out = bytearray()
    too_long = False
    fd = proc.stdout.fileno()
    while True:
        chunk = os.read(fd, _CHUNK)
        if not chunk:
            break
        out += chunk
        if len(out) > limit:
            too_long = True
            proc.kill()
            break
    proc.stdout.close()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = (time.perf_counter_ns() - started) / 1e9
    proc.returncode = os.waitstatus_to_exitcode(status)      # reaped here: Popen must not wait again
    if owned:
        _end_leftovers()
    cpu = _cpu_of_children() - cpu_before
    writer.join(5)
    reader.join(5)
    with contextlib.suppress(OSError):
        proc.stderr.close()
    stderr = err.decode("utf-8", "replace")
    if too_long:
        raise InvalidOutput(f"printed more than {limit} bytes, more than the answer for these sites can need")
    if status != 0:
        text = _describe(status, stderr)
        last = "\n".join(stderr.strip().splitlines()[-3:])
        signalled = os.WIFSIGNALED(status) and os.WTERMSIG(status) not in (signal.SIGABRT, signal.SIGKILL)
        if not signalled and any(word in last for word in _OUT_OF_MEMORY):
            raise MemoryError(text)
        raise ProgramFailed(text)
    return ProgramRun(bytes(out), stderr, wall, max(cpu, usage.ru_utime + usage.ru_stime), usage.ru_maxrss / 1024.0)
