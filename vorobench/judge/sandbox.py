"""An isolated worker process: the only place where an implementation's code is imported or run.

A :class:`Sandbox` runs one implementation. Its process is forked from the ``forkserver``
(numpy, scipy, numba and the registry imported once), loads the run's plugins, runs the
implementation's warm-up (JIT compilation: its own allowance), declares what the
implementation is (:mod:`vorobench.judge.declarations`) and then serves requests. The judge
pins the first declaration of a run: a sandbox that later declares otherwise is refused.

Whatever the implementation does to its process becomes the outcome of that request alone: an
exception, a segfault, ``os._exit`` or ``SystemExit`` with any status, a hang past the
timeout, running out of memory. The sandbox is then killed (its process group too) and
restarted for the next request. A sandbox is reused across cases: judging needs no fresh
process per case, only one that cannot harm the judge.

Nothing the sandbox sends back is unpickled: a request's function returns ``(data, arrays)``,
which cross the bounded wire (:mod:`vorobench.judge.wire`): every size is checked against the
caller's schema before anything is allocated, and every string is cleaned. An implementation
owns its process, so its answers are data to check, never objects to trust.
"""

from __future__ import annotations

import multiprocessing as mp
import os
import pickle
import signal
import sys
import time
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Mapping, Optional, Sequence

import impls
from impls.plugins import load_plugin
from vorobench.judge import isolation, wire
from vorobench.judge.declarations import Declaration, DeclarationError, declaration_from_data, declaration_of
from vorobench.judge.defaults import WARMUP_TIMEOUT
from vorobench.judge.outcomes import OutcomeKind

__all__ = ["Sandbox", "Outcome", "OutcomeKind", "WARMUP_TIMEOUT", "safe_message"]


@dataclass
class Outcome:
    """What one request produced: ``kind`` (:class:`OutcomeKind`) is "ok" (``value`` holds the
    result), "error" (the function raised: ``message``), "crashed" (the process died or exited,
    or answered what the wire does not allow), "timeout" or "oom"."""

    kind: OutcomeKind
    value: Any = None
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.kind == OutcomeKind.OK


def _describe_death(exitcode: Optional[int], step: str) -> Outcome:
    kind, how = isolation.describe_death(exitcode)
    return Outcome(kind, message=f"{how} during {step}")


def safe_message(exc: BaseException) -> str:
    """``Type: message at file:line`` of an exception, even of one whose ``__str__`` raises."""
    try:
        text = str(exc)
    except BaseException:  # noqa: BLE001 - a message that cannot be printed is still a failure
        text = "<unprintable message>"
    if getattr(exc, "about_the_program", False):   # an executable's failure: our file and line say nothing
        return f"{type(exc).__name__}: {text}"[:600]
    try:
        origin = exc
        while origin.__cause__ is not None and origin.__cause__ is not origin:   # where it really began
            origin = origin.__cause__
        if origin is not exc:
            text = f"{text}: {type(origin).__name__}: {origin}"
        frames = traceback.extract_tb(origin.__traceback__)
        where = f" at {frames[-1].filename}:{frames[-1].lineno}" if frames else ""
        caller = next((f for f in reversed(frames) if not _library_file(f.filename)), None)
        if caller is not None and caller is not frames[-1]:
            # A plugin's mistake surfaces in the code it called: name its own line first.
            where = f" at {caller.filename}:{caller.lineno} (raised in {frames[-1].filename}:{frames[-1].lineno})"
    except BaseException:  # noqa: BLE001
        where = ""
    return f"{type(exc).__name__}: {text}{where}"[:600]


#: Where vorobench's own code and the installed libraries live: frames there are not a plugin's.
_LIBRARY_DIRS = tuple(str(Path(p).resolve()) + os.sep for p in (
    Path(__file__).resolve().parents[1], Path(__file__).resolve().parents[2] / "impls",
    Path(__file__).resolve().parents[2] / "datasets_gen", sys.prefix, sys.base_prefix, sys.exec_prefix))


def _library_file(filename: str) -> bool:
    """Whether ``filename`` is vorobench's, its built-in implementations' or an installed
    library's (anything under the interpreter's prefixes), not a plugin's."""
    try:
        path = str(Path(filename).resolve())
    except (OSError, ValueError):
        return True
    return path.startswith(_LIBRARY_DIRS) or filename.startswith("<")


def _serve(conn, parent: Optional[int], impl_blobs: dict, name: Optional[str], plugins: Sequence[str],
           memory_limit_mb: Optional[float], environ: dict) -> None:
    """The sandbox process: set up, warm up, declare, then answer (function, args) requests
    until EOF. ``name`` None: no implementation of its own (it reads declarations)."""
    isolation.enter_worker(parent)
    os.environ.clear()                      # forked from the fork server: take the judge's environment
    os.environ.update(environ)
    os.environ[isolation.SANDBOX_VARIABLE] = "1"    # what runs here may end what it starts (impls.executable)
    signal.signal(signal.SIGINT, signal.SIG_IGN)          # Ctrl-C is the judge's to handle

    def send(kind: str, payload: Any = None, arrays: Optional[dict] = None) -> None:
        conn.send_bytes(wire.encode(kind, payload, arrays))

    try:
        defined_by = {}
        for spec in plugins:
            defined_by.update(dict.fromkeys(load_plugin(spec), spec))
        for blob in impl_blobs.values():
            try:
                impls.register(pickle.loads(blob))
            except Exception:  # noqa: BLE001 - defined by a plugin not loaded here yet: found by name instead
                continue
        declared = None
        if name is not None:
            impl = impls.get(name)
            if impl.warmup is not None:
                impl.warmup()
            declared = declaration_of(impl, defined_by.get(name, ""))
        isolation.limit_memory(memory_limit_mb)
        send("ready", declared)
    except BaseException as exc:  # noqa: BLE001 - a sandbox that cannot start says why
        send(OutcomeKind.ERROR, safe_message(exc))
        return
    while True:
        try:
            fn, args, kwargs = conn.recv()
        except (EOFError, OSError):
            return
        try:
            data, arrays = fn(*args, **kwargs)
            send(OutcomeKind.OK, data, arrays)
        except MemoryError as exc:
            send(OutcomeKind.OOM, f"MemoryError: {exc}")
        except BaseException as exc:  # noqa: BLE001 - SystemExit included: it is the implementation's
            send(OutcomeKind.ERROR, safe_message(exc))


def _context(method: Optional[str] = None):
    method = method or isolation.default_start_method()
    ctx = mp.get_context(method)
    if method == "forkserver":
        ctx.set_forkserver_preload(list(isolation.FORKSERVER_PRELOAD))    # only takes effect when the server starts
    return ctx


def _registered_blobs(name: Optional[str]) -> dict[str, bytes]:
    """Implementations registered in this process (test doubles) that the sandbox should
    know: ``name``'s own, or all of them for a declarations sandbox; sent by pickle (their
    functions by reference). One that cannot be pickled is left for the sandbox to find."""
    wanted = impls.registered() if name is None else [n for n in impls.registered() if n == name]
    blobs = {}
    for n in wanted:
        try:
            blobs[n] = pickle.dumps(impls.get(n))
        except Exception:  # a closure or lambda: the sandbox looks it up by name (a plugin may define it)
            continue
    return blobs


class Sandbox:
    """One implementation in its own worker process; :meth:`call` runs a function there.

    ``expected``: the declaration pinned for the run; a sandbox whose implementation declares
    anything else does not start (its every request fails, saying so). ``name`` None: a
    sandbox with no implementation of its own, which reads declarations. ``start_method``:
    "forkserver" (the default where there is one) or "spawn" (a brand-new interpreter).
    """

    def __init__(self, name: Optional[str], *, plugins: Sequence[str] = (), memory_limit_mb: Optional[float] = None,
                 warmup_timeout: float = WARMUP_TIMEOUT, expected: Optional[Declaration] = None,
                 start_method: Optional[str] = None) -> None:
        self.name = name
        self.start_method = start_method
        self.plugins = tuple(plugins)
        self.memory_limit_mb = memory_limit_mb
        self.warmup_timeout = warmup_timeout
        self.expected = expected
        self._proc = None
        self._conn = None
        self.start_failure: Optional[Outcome] = None

    def _start(self) -> Optional[Outcome]:
        """Start the process and wait for its warm-up; a failure is the outcome of the request."""
        ctx = _context(self.start_method)
        receiver, sender = ctx.Pipe()
        proc = ctx.Process(target=_serve, name=f"vorobench-judge-{self.name or 'registry'}", daemon=True,
                           args=(sender, os.getpid() if ctx.get_start_method() != "forkserver" else None,
                                 _registered_blobs(self.name), self.name, self.plugins, self.memory_limit_mb,
                                 dict(os.environ)))
        proc.start()
        isolation.watch(proc.pid)
        sender.close()
        self._proc, self._conn = proc, receiver
        outcome = self._receive(self.warmup_timeout, "start-up and warm-up", None)
        if outcome.ok:
            outcome = self._check_declaration(outcome.value[0])
        if outcome.ok:
            return None
        self.close()
        return outcome

    def _check_declaration(self, data: Any) -> Outcome:
        """The ready answer's declaration against the run's pinned one."""
        if self.name is None:
            return Outcome(OutcomeKind.OK)
        try:
            declared = declaration_from_data(data, self.name)
        except DeclarationError as exc:
            return Outcome(OutcomeKind.CRASHED, message=f"declared nothing readable ({exc})")
        if self.expected is not None and declared != self.expected:
            changed = [k for k, v in declared.to_dict().items() if v != getattr(self.expected, k)]
            return Outcome(OutcomeKind.CRASHED,
                           message=f"declared {', '.join(f'{k}={getattr(declared, k)!r}' for k in changed)} "
                                   f"in this worker, not what it declared at the start of the run "
                                   f"({', '.join(f'{k}={getattr(self.expected, k)!r}' for k in changed)})")
        return Outcome(OutcomeKind.OK)

    def _receive(self, timeout: Optional[float], step: str, schema: Any) -> Outcome:
        """The next answer; a worker that died (even if a child of it still holds the pipe),
        overstayed ``timeout`` or sent what the wire does not allow is the outcome instead."""
        deadline = None if timeout is None else time.monotonic() + timeout
        try:
            while True:
                wait = 0.5 if deadline is None else min(0.5, max(0.0, deadline - time.monotonic()))
                if self._conn.poll(wait):
                    message = self._conn.recv_bytes(wire.MAX_MESSAGE_BYTES)
                    break
                if not self._proc.is_alive():
                    if self._conn.poll(0):      # it answered just before it ended
                        message = self._conn.recv_bytes(wire.MAX_MESSAGE_BYTES)
                        break
                    self._proc.join(5)
                    return _describe_death(self._proc.exitcode, step)
                if deadline is not None and time.monotonic() >= deadline:
                    return Outcome(OutcomeKind.TIMEOUT, message=f"no result within {timeout:g} s during {step}")
        except OSError as exc:
            if self._proc.is_alive() and "bad message length" in str(exc):
                return Outcome(OutcomeKind.CRASHED,
                               message=f"answered more than {wire.MAX_MESSAGE_BYTES} bytes during {step}")
            self._proc.join(10)
            return _describe_death(self._proc.exitcode, step)
        except EOFError:
            self._proc.join(10)
            return _describe_death(self._proc.exitcode, step)
        try:
            kind, data, arrays = wire.decode(message, schema)
        except wire.WireError as exc:   # not an answer the wire allows: the implementation's failure
            return Outcome(OutcomeKind.CRASHED, message=f"sent an answer the judge refuses during {step}: {exc}")
        finally:
            del message
        if kind in (OutcomeKind.OK, "ready"):
            return Outcome(OutcomeKind.OK, (data, arrays))
        failed = OutcomeKind(kind) if kind in (OutcomeKind.ERROR, OutcomeKind.OOM) else OutcomeKind.CRASHED
        return Outcome(failed, message=wire.clean_text(data, 600))

    def start(self) -> Optional[Outcome]:
        """Start the sandbox now if it is not running; its failure, or None."""
        if self.start_failure is not None:     # a warm-up that failed once is not paid for again
            return self.start_failure
        if self._proc is None or not self._proc.is_alive():
            self.close()
            failure = self._start()
            if failure is not None:
                self.start_failure = Outcome(failure.kind, message=f"{failure.message} (its worker could not start)")
                return failure
        return None

    def call(self, fn: Callable, *args, timeout: Optional[float], step: str = "build",
             schema: Optional[Mapping[str, wire.ArraySpec]] = None, **kwargs) -> Outcome:
        """``fn(*args, **kwargs)`` in the sandbox, within ``timeout`` seconds (None: no limit;
        start-up and warm-up have their own allowance). ``schema`` bounds the arrays of the
        answer (see :func:`vorobench.judge.wire.decode`); without one, none may come."""
        failure = self.start()
        if failure is not None:
            return failure
        try:
            self._conn.send((fn, args, kwargs))
        except (BrokenPipeError, OSError, EOFError):
            self._proc.join(10)
            outcome = _describe_death(self._proc.exitcode, "start of " + step)
            self.close()
            return outcome
        outcome = self._receive(timeout, step, schema)
        if outcome.kind != OutcomeKind.OK and (outcome.kind != OutcomeKind.ERROR or not self._proc.is_alive()):
            self.close()    # dead, stuck, out of memory (maybe fragmented) or lying: the next request gets a fresh one
        return outcome

    def close(self) -> None:
        """Kill the sandbox and its process group (a child it left behind included); safe to
        call twice."""
        if self._proc is not None:
            if self._conn is not None:
                self._conn.close()
            isolation.kill_worker(self._proc)
        self._proc, self._conn = None, None
