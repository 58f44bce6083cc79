"""An isolated worker process that builds and certifies diagrams for the judge, one at a time.

A :class:`Sandbox` runs one implementation. Its process is forked from the ``forkserver``
(numpy, scipy, numba and the implementations imported once), registers the run's plugins,
runs the implementation's warm-up (JIT compilation: its own allowance) and then serves
requests. Whatever the implementation does to its process becomes the outcome of that request
alone: an exception, a segfault, ``os._exit`` or ``SystemExit`` with any status, a hang past the
timeout, running out of memory. The sandbox is then killed (its process group too) and
restarted for the next request. A sandbox is reused across cases: judging needs no fresh
process per case, only one that cannot harm the judge.

Nothing the sandbox sends back is unpickled: a request's function returns ``(data, arrays)``,
JSON-able data and a dict of numpy arrays, which travel as JSON and ``.npz`` bytes and are
read with ``allow_pickle=False``. An implementation owns its process, so its answers are
data to check, never objects to trust.
"""

from __future__ import annotations

import io
import json
import multiprocessing as mp
import os
import pickle
import signal
import time
import traceback
from dataclasses import dataclass
from typing import Any, Callable, Optional, Sequence

import numpy as np

import impls
from impls.plugins import load_plugin
from vorobench.judge import isolation
from vorobench.judge.defaults import WARMUP_TIMEOUT

__all__ = ["Sandbox", "Outcome", "WARMUP_TIMEOUT"]




@dataclass
class Outcome:
    """What one request produced: ``kind`` is "ok" (``value`` holds the result), "error" (the
    function raised: ``message``), "crashed" (the process died or exited), "timeout" or "oom"."""

    kind: str
    value: Any = None
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.kind == "ok"


def _describe_death(exitcode: Optional[int], step: str) -> Outcome:
    kind, how = isolation.describe_death(exitcode)
    return Outcome(kind, message=f"{how} during {step}")


def _serve(conn, parent: int, impl_blob: Optional[bytes], name: str, plugins: Sequence[str],
           memory_limit_mb: Optional[float], environ: dict) -> None:
    """The sandbox process: set up, warm up, then answer (function, args) requests until EOF."""
    isolation.enter_worker(parent)
    os.environ.clear()                      # forked from the fork server: take the judge's environment
    os.environ.update(environ)
    signal.signal(signal.SIGINT, signal.SIG_IGN)          # Ctrl-C is the judge's to handle

    def send(kind: str, payload: Any = None, arrays: Optional[dict] = None) -> None:
        conn.send_bytes(encode(kind, payload, arrays))

    try:
        for spec in plugins:
            load_plugin(spec)
        impl = pickle.loads(impl_blob) if impl_blob is not None else impls.get(name)
        if impl_blob is not None:
            impls.register(impl)
        if impl.warmup is not None:
            impl.warmup()
        isolation.limit_memory(memory_limit_mb)
        send("ready", None)
    except BaseException as exc:  # noqa: BLE001 - a sandbox that cannot start says why
        send("error", f"{type(exc).__name__}: {exc}")
        return
    while True:
        try:
            fn, args, kwargs = conn.recv()
        except (EOFError, OSError):
            return
        try:
            data, arrays = fn(*args, **kwargs)
            send("ok", data, arrays)
        except MemoryError as exc:
            send("oom", f"MemoryError: {exc}")
        except BaseException as exc:  # noqa: BLE001 - SystemExit included: it is the implementation's
            frames = traceback.extract_tb(exc.__traceback__)
            where = f" at {frames[-1].filename}:{frames[-1].lineno}" if frames else ""
            send("error", f"{type(exc).__name__}: {exc}{where}"[:600])


def encode(kind: str, data: Any = None, arrays: Optional[dict] = None) -> bytes:
    """One answer: an 8-byte header length, a JSON header, then the arrays as ``.npz`` bytes."""
    header = json.dumps({"kind": kind, "data": data}).encode()
    blob = io.BytesIO()
    if arrays:
        np.savez(blob, **arrays)
    return len(header).to_bytes(8, "little") + header + blob.getvalue()


def decode(message: bytes) -> tuple[str, Any, dict]:
    """(kind, data, arrays) of an answer, without running anything the sender chose."""
    size = int.from_bytes(message[:8], "little")
    header = json.loads(message[8:8 + size])
    arrays: dict = {}
    rest = message[8 + size:]
    if rest:
        with np.load(io.BytesIO(rest), allow_pickle=False) as npz:
            arrays = {key: npz[key] for key in npz.files}
    return str(header["kind"]), header.get("data"), arrays


def _context():
    method = "forkserver" if "forkserver" in mp.get_all_start_methods() else "spawn"
    ctx = mp.get_context(method)
    if method == "forkserver":
        ctx.set_forkserver_preload(list(isolation.FORKSERVER_PRELOAD))    # only takes effect when the server starts
    return ctx


class Sandbox:
    """One implementation in its own worker process; :meth:`call` runs a function there."""

    def __init__(self, name: str, *, plugins: Sequence[str] = (), memory_limit_mb: Optional[float] = None,
                 warmup_timeout: float = WARMUP_TIMEOUT) -> None:
        self.name = name
        self.plugins = tuple(plugins)
        self.memory_limit_mb = memory_limit_mb
        self.warmup_timeout = warmup_timeout
        self._proc = None
        self._conn = None
        self.start_failure: Optional[Outcome] = None

    def _impl_blob(self) -> Optional[bytes]:
        """An implementation registered in this process (a test double, a plugin) is sent over by
        pickle (its functions by reference); None lets the sandbox look the name up itself."""
        if self.name not in impls.registered():
            return None
        try:
            return pickle.dumps(impls.get(self.name))
        except Exception:  # a closure or lambda: the sandbox looks it up by name (a plugin may define it)
            return None

    def _start(self) -> Optional[Outcome]:
        """Start the process and wait for its warm-up; a failure is the outcome of the request."""
        ctx = _context()
        receiver, sender = ctx.Pipe()
        proc = ctx.Process(target=_serve, name=f"vorobench-judge-{self.name}", daemon=True,
                           args=(sender, os.getpid() if ctx.get_start_method() != "forkserver" else None,
                                 self._impl_blob(), self.name, self.plugins, self.memory_limit_mb,
                                 dict(os.environ)))
        proc.start()
        isolation.watch(proc.pid)
        sender.close()
        self._proc, self._conn = proc, receiver
        outcome = self._receive(self.warmup_timeout, "start-up and warm-up")
        if outcome.kind == "ok":
            return None
        self.close()
        return outcome

    def _receive(self, timeout: Optional[float], step: str) -> Outcome:
        """The next answer; a worker that died (even if a child of it still holds the pipe)
        or overstayed ``timeout`` is the outcome instead."""
        deadline = None if timeout is None else time.monotonic() + timeout
        try:
            while True:
                wait = 0.5 if deadline is None else min(0.5, max(0.0, deadline - time.monotonic()))
                if self._conn.poll(wait):
                    message = self._conn.recv_bytes()
                    break
                if not self._proc.is_alive():
                    if self._conn.poll(0):      # it answered just before it ended
                        message = self._conn.recv_bytes()
                        break
                    self._proc.join(5)
                    return _describe_death(self._proc.exitcode, step)
                if deadline is not None and time.monotonic() >= deadline:
                    return Outcome("timeout", message=f"no result within {timeout:g} s during {step}")
        except (EOFError, OSError):
            self._proc.join(10)
            return _describe_death(self._proc.exitcode, step)
        try:
            kind, data, arrays = decode(message)
        except Exception as exc:  # not an answer of ours: the implementation wrote to the pipe
            return Outcome("error", message=f"unreadable answer from the worker ({type(exc).__name__})")
        if kind in ("ok", "ready"):
            return Outcome("ok", (data, arrays))
        return Outcome(kind if kind in ("error", "oom") else "error", message=str(data)[:600])

    def call(self, fn: Callable, *args, timeout: Optional[float], step: str = "build", **kwargs) -> Outcome:
        """``fn(*args, **kwargs)`` in the sandbox, within ``timeout`` seconds (None: no limit;
        start-up and warm-up have their own allowance)."""
        if self.start_failure is not None:     # a warm-up that failed once is not paid for again
            return self.start_failure
        if self._proc is None or not self._proc.is_alive():
            self.close()
            failure = self._start()
            if failure is not None:
                self.start_failure = Outcome(failure.kind, message=f"{failure.message} (its worker could not start)")
                return failure
        try:
            self._conn.send((fn, args, kwargs))
        except (BrokenPipeError, OSError, EOFError):
            self._proc.join(10)
            outcome = _describe_death(self._proc.exitcode, "start of " + step)
            self.close()
            return outcome
        outcome = self._receive(timeout, step)
        if outcome.kind in ("crashed", "timeout") or (outcome.kind == "oom" and not self._proc.is_alive()):
            self.close()                       # dead or stuck: the next request gets a fresh one
        elif outcome.kind == "oom":
            self.close()                       # memory may be fragmented or leaked: start anew
        return outcome

    def close(self) -> None:
        """Kill the sandbox and its process group (a child it left behind included); safe to
        call twice."""
        if self._proc is not None:
            if self._conn is not None:
                self._conn.close()
            isolation.kill_worker(self._proc)
        self._proc, self._conn = None, None
