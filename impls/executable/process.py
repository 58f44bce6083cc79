"""Running a program once: its stdin written, its stdout read up to a limit, its own measures.

The program is a child of the sandbox, in the sandbox's process group: a timeout of the
request kills both. Its stdout is read in chunks and the program is killed the moment it
passes the limit (so a 10 GB answer costs the harness the limit, not 10 GB); stderr keeps
its last ``STDERR_BYTES``. Wall time runs from the start of the process to its end, CPU time
and peak memory are the kernel's accounting of that process (``wait4``).
"""

from __future__ import annotations

import os
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


def run_program(argv: list[str], cwd: Path, stdin: bytes, limit: int, env: Optional[dict] = None) -> ProgramRun:
    """Run ``argv`` in ``cwd`` with ``stdin``; raise :class:`InvalidOutput` when it prints more than
    ``limit`` bytes, :class:`ProgramFailed` when it fails, ``MemoryError`` when it says it ran out
    of memory (under the sandbox's limit)."""
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
    writer.join(5)
    reader.join(5)
    stderr = err.decode("utf-8", "replace")
    if too_long:
        raise InvalidOutput(f"printed more than {limit} bytes, more than the answer for these sites can need")
    if status != 0:
        text = _describe(status, stderr)
        if any(word in stderr for word in ("bad_alloc", "MemoryError", "out of memory", "Cannot allocate memory")):
            raise MemoryError(text)
        raise ProgramFailed(text)
    return ProgramRun(bytes(out), stderr, wall, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0)
