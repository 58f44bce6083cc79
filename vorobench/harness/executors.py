"""Where tasks run: a process pool on this machine, or a running Dask cluster, behind one
``concurrent.futures`` interface.

``make_executor("local", N)`` is a :class:`concurrent.futures.ProcessPoolExecutor`;
``make_executor("dask://HOST:PORT", N)`` is the executor of a ``distributed.Client`` connected
to that scheduler (Dask does the scheduling, transport and pickling). :func:`run_tasks` maps a
function over items on either, keeps a bounded number in flight, and survives worker deaths:
a task whose worker died is retried once, alone, and then reported as lost, never dropped.
A task's timeout counts its own run time: each task says when it starts on its worker (a file
here, a Dask event on a cluster), so time spent queued behind other work, or waiting for a
worker to start, has a separate and generous allowance.
"""

from __future__ import annotations

import concurrent.futures as cf
import functools
import math
import multiprocessing as mp
import os
import shutil
import socket
import tempfile
import threading
import time
import uuid
from collections import deque
from dataclasses import dataclass
from typing import Any, Callable, Iterable, Iterator, Optional

from vorobench.judge.isolation import default_start_method

__all__ = ["LOCAL", "DASK_PREFIX", "make_executor", "describe", "parse_spec", "check_spec", "TaskResult", "run_tasks",
           "is_worker_death", "DaskMissing"]

LOCAL = "local"
DASK_PREFIX = "dask://"

#: Exception types (by name, so that dask need not be imported) meaning "the worker died".
_DEATHS = ("BrokenProcessPool", "BrokenExecutor", "KilledWorker", "CommClosedError")

#: Seconds a task may wait to start on a worker (queued behind other work, the worker starting
#: up), on top of ``timeout`` for each task that may run before it in its worker slot.
QUEUE_ALLOWANCE_S = 600.0

#: How often run_tasks looks whether tasks in flight have started (a start is noticed this late
#: at most, which lengthens a timeout by as much).
START_POLL_S = 0.1

#: The Dask event topic on which tasks say they started (one topic: the scheduler keeps a
#: bounded log per topic, so a fixed name keeps its memory bounded too).
_STARTED_TOPIC = "vorobench-task-started"


class DaskMissing(ValueError):
    """``dask://`` was asked for but dask.distributed is not installed."""


def parse_spec(spec: str) -> tuple[str, Optional[str]]:
    """("local", None) or ("dask", "tcp://HOST:PORT"); ValueError for anything else."""
    spec = (spec or LOCAL).strip()
    if spec == LOCAL:
        return LOCAL, None
    if spec.startswith(DASK_PREFIX) and len(spec) > len(DASK_PREFIX):
        return "dask", "tcp://" + spec[len(DASK_PREFIX):]
    raise ValueError(f"unknown executor {spec!r}: use 'local' or 'dask://HOST:PORT'")


#: Seconds to reach a Dask scheduler before giving up with a plain error.
CONNECT_TIMEOUT = 10.0


def _open_port(address: str, timeout: float) -> None:
    """ValueError at once when nothing listens at ``address`` ("tcp://HOST:PORT"): Dask's own
    connect retries a refused port until its timeout, which would make a typo cost seconds."""
    host, _, port = address[len("tcp://"):].rpartition(":")
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=timeout).close()
    except ValueError:
        raise ValueError(f"{address} is not HOST:PORT") from None
    except ConnectionRefusedError:
        raise ValueError(f"cannot reach the Dask scheduler at {address}: connection refused "
                         f"(nothing listens there)") from None
    except OSError as exc:         # unknown host, unreachable network, no answer in time
        raise ValueError(f"cannot reach the Dask scheduler at {address} ({type(exc).__name__}: {exc})") from None


def check_spec(spec: Optional[str]) -> None:
    """:func:`parse_spec`, and for a Dask scheduler a TCP connection to it: a mistyped executor
    is a ValueError before a run starts anything, not seconds into it."""
    kind, address = parse_spec(spec)
    if kind == "dask":
        _open_port(address, CONNECT_TIMEOUT)


def _reach_scheduler(address: str, timeout: float) -> None:
    """Ask the scheduler who it is, within ``timeout`` seconds in all; ValueError if it does not
    answer. (``distributed.Client`` bounds the TCP connection but can wait forever for a port
    that accepts and never speaks.)"""
    _open_port(address, timeout)
    # Dask is an optional extra (vorobench[dask]): imported only for a dask:// executor.
    import asyncio

    from distributed.comm import connect

    async def identity() -> None:
        comm = await connect(address, timeout=timeout)
        try:
            await comm.write({"op": "identity", "reply": True})
            await comm.read()
        finally:
            comm.abort()

    try:
        asyncio.run(asyncio.wait_for(identity(), timeout))
    except (OSError, asyncio.TimeoutError, TimeoutError, EOFError) as exc:
        raise ValueError(f"cannot reach the Dask scheduler at {address} within {timeout:g} s "
                         f"({type(exc).__name__})") from None
    except Exception as exc:  # the peer answered, but not as a Dask scheduler
        raise ValueError(f"{address} does not answer as a Dask scheduler ({type(exc).__name__}: {exc})") from None


def _dask_client(address: str):
    try:
        # optional extra, as above
        from distributed import Client
    except ImportError as exc:
        raise DaskMissing("the dask executor needs dask.distributed: pip install vorobench[dask]") from exc
    _reach_scheduler(address, CONNECT_TIMEOUT)
    try:
        return Client(address, set_as_default=False, timeout=f"{CONNECT_TIMEOUT:g}s")
    except (OSError, TimeoutError) as exc:
        raise ValueError(f"cannot reach the Dask scheduler at {address} within {CONNECT_TIMEOUT:g} s "
                         f"({type(exc).__name__})") from None


class _DaskExecutor(cf.Executor):
    """Tasks submitted to a Dask cluster through its client, as ``concurrent.futures`` futures.

    Each result is fetched as soon as its task finishes and the Dask future released, so the
    cluster does not keep finished results (nor recompute them when the worker holding one
    dies). ``pure=False``: resubmitting an item is a new task, not the old (failed) one.
    """

    def __init__(self, client) -> None:
        self.client = client
        self.starts = _DaskStarts(client)

    def submit(self, fn, /, *args, **kwargs) -> cf.Future:
        result: cf.Future = cf.Future()
        task = self.client.submit(fn, *args, pure=False, **kwargs)

        def deliver(done) -> None:
            try:
                result.set_result(done.result())
            except BaseException as exc:  # noqa: BLE001 - the task's failure goes to its future
                result.set_exception(exc)
            finally:
                done.release()

        result.set_running_or_notify_cancel()
        result.abandon = task.cancel          # used by run_tasks when a task overstays its timeout
        task.add_done_callback(deliver)
        return result

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        self.client.close()


def make_executor(spec: str = LOCAL, workers: int = 1) -> cf.Executor:
    """A ``concurrent.futures`` executor: ``local`` = a pool of ``workers`` processes here;
    ``dask://HOST:PORT`` = the workers of that Dask scheduler (``workers`` is not used: the
    cluster decides)."""
    kind, address = parse_spec(spec)
    if kind == LOCAL:
        if workers < 1:
            raise ValueError("--workers must be at least 1")
        # forkserver/spawn: a pool worker never inherits the parent's threads (progress bar, Dask).
        return cf.ProcessPoolExecutor(max_workers=workers, mp_context=mp.get_context(default_start_method()))
    return _DaskExecutor(_dask_client(address))


def describe(executor: cf.Executor) -> str:
    """One line for logs: how many workers and where."""
    if isinstance(executor, _DaskExecutor):
        info = executor.client.scheduler_info()
        workers = info.get("workers", {})
        hosts = sorted({w.get("host", "?") for w in workers.values()})
        return f"dask {executor.client.scheduler.address}: {len(workers)} workers on {', '.join(hosts) or 'no host'}"
    return f"local process pool: {getattr(executor, '_max_workers', '?')} workers"


def capacity(executor: cf.Executor) -> int:
    """How many tasks the executor can run at once (threads across a Dask cluster)."""
    if isinstance(executor, _DaskExecutor):
        workers = executor.client.scheduler_info().get("workers", {})
        return max(1, sum(int(w.get("nthreads", 1)) for w in workers.values()))
    return max(1, int(getattr(executor, "_max_workers", 1)))


def is_worker_death(exc: BaseException) -> bool:
    """True if ``exc`` says the process running the task died (not that the task raised)."""
    return any(type(e).__name__ in _DEATHS for e in (exc, exc.__cause__) if e is not None)


def _run_started(stamp: Callable[[], None], fn: Callable[[Any], Any], item: Any) -> Any:
    """Runs on the worker: say the task has started, then ``fn(item)``."""
    stamp()
    return fn(item)


def _touch(path: str) -> None:
    """The start stamp of a task on this machine: an empty file."""
    try:
        with open(path, "x"):
            pass
    except FileNotFoundError:   # run_tasks has ended (and given this task up): nobody looks any more
        pass


def _log_started(token: str) -> None:
    """The start stamp of a task on a Dask worker: an event its client hears."""
    # Dask is an optional extra: only a task sent to a Dask cluster gets here.
    from distributed import get_worker

    get_worker().log_event(_STARTED_TOPIC, token)


class _FileStarts:
    """Which tasks have started, for workers on this machine: each task creates a file named by
    its token in a folder of ours."""

    def __init__(self) -> None:
        self.folder = tempfile.mkdtemp(prefix="vorobench-starts-")
        self._seen: dict[str, float] = {}

    def stamp(self, token: str) -> Callable[[], None]:
        return functools.partial(_touch, os.path.join(self.folder, token))

    def started_at(self, token: str) -> Optional[float]:
        """When the start of task ``token`` was noticed here (monotonic), or None."""
        if token not in self._seen and os.path.exists(os.path.join(self.folder, token)):
            self._seen[token] = time.monotonic()
        return self._seen.get(token)

    def forget(self, token: str) -> None:
        self._seen.pop(token, None)
        try:
            os.unlink(os.path.join(self.folder, token))
        except FileNotFoundError:
            pass

    def close(self) -> None:
        shutil.rmtree(self.folder, ignore_errors=True)


class _DaskStarts:
    """Which tasks have started, for the workers of a Dask cluster: each task logs an event
    with its token, which the scheduler passes on to this client. One per client, kept by its
    executor (the subscription ends with the client)."""

    def __init__(self, client) -> None:
        self._heard: dict[str, Optional[float]] = {}     # token of each of our tasks -> when it started
        self._lock = threading.Lock()
        client.subscribe_topic(_STARTED_TOPIC, self._hear)

    def _hear(self, event: tuple[float, Any]) -> None:
        """Runs on the client's event loop, for every task started by any client of the cluster:
        only the start of one of ours is kept."""
        token = event[1]
        with self._lock:
            if isinstance(token, str) and token in self._heard and self._heard[token] is None:
                self._heard[token] = time.monotonic()

    def stamp(self, token: str) -> Callable[[], None]:
        with self._lock:
            self._heard[token] = None
        return functools.partial(_log_started, token)

    def started_at(self, token: str) -> Optional[float]:
        """When the start of task ``token`` was heard here (monotonic), or None."""
        return self._heard.get(token)

    def forget(self, token: str) -> None:
        with self._lock:
            self._heard.pop(token, None)


class _Deadlines:
    """The time limits of the tasks in flight. ``timeout`` counts from the moment a task is
    seen starting on its worker; until then the task has ``start_timeout`` seconds from its
    submission. Without a ``timeout`` tasks are submitted as they are and never expire."""

    def __init__(self, timeout: Optional[float], start_timeout: float, starts) -> None:
        self.timeout = timeout
        self.start_timeout = start_timeout
        self.starts = starts
        self._tasks: dict[cf.Future, tuple[str, float]] = {}     # future -> (token, submitted at)

    def submit(self, ex: cf.Executor, fn: Callable[[Any], Any], item: Any) -> cf.Future:
        """``fn(item)`` on ``ex``; with a timeout, stamped so that its start can be seen."""
        if self.timeout is None:
            return ex.submit(fn, item)
        token = uuid.uuid4().hex
        stamp = self.starts.stamp(token)
        try:
            fut = ex.submit(_run_started, stamp, fn, item)
        except BaseException:
            self.starts.forget(token)
            raise
        self._tasks[fut] = (token, time.monotonic())
        return fut

    def _deadline(self, fut: cf.Future) -> tuple[float, bool]:
        """(when ``fut`` expires, whether it has started)."""
        token, submitted = self._tasks[fut]
        started = self.starts.started_at(token)
        if started is None:
            return submitted + self.start_timeout, False
        return started + self.timeout, True

    def wait_seconds(self, pending: Iterable[cf.Future]) -> Optional[float]:
        """How long to wait for results before the next look (None: as long as it takes)."""
        if self.timeout is None:
            return None
        deadlines = [self._deadline(f) for f in pending]
        if not deadlines:
            return None
        wait = min(d for d, _ in deadlines) - time.monotonic()
        if not all(started for _, started in deadlines):
            wait = min(wait, START_POLL_S)
        return max(0.0, wait)

    def expired(self, pending: Iterable[cf.Future]) -> list[tuple[cf.Future, str]]:
        """The tasks past their limit, each with the reason it is given up."""
        if self.timeout is None:
            return []
        now = time.monotonic()
        late = []
        for fut in pending:
            deadline, started = self._deadline(fut)
            if now >= deadline:
                late.append((fut, f"no result within {self.timeout:g} s" if started else
                             f"not started within {self.start_timeout:g} s (its worker stayed busy)"))
        return late

    def forget(self, fut: cf.Future) -> None:
        entry = self._tasks.pop(fut, None)
        if entry is not None:
            self.starts.forget(entry[0])


def _start_allowance(timeout: Optional[float], limit: int, slots: int) -> float:
    """The default ``start_timeout``: :data:`QUEUE_ALLOWANCE_S`, plus ``timeout`` for every task
    that may run before this one in its worker slot."""
    return QUEUE_ALLOWANCE_S + math.ceil(limit / slots) * (timeout or 0.0)


@dataclass
class TaskResult:
    """One item's outcome: its ``value``, or why it has none (``lost``: its worker died on every
    try; ``error``: the task raised)."""

    item: Any
    value: Any = None
    lost: str = ""
    error: str = ""
    attempts: int = 1
    timed_out: bool = False

    @property
    def ok(self) -> bool:
        return not (self.lost or self.error)


_END = object()


def run_tasks(spec: str, workers: int, fn: Callable[[Any], Any], items: Iterable[Any], *, retries: int = 1,
              in_flight: Optional[int] = None, executor: Optional[cf.Executor] = None,
              timeout: Optional[float] = None, start_timeout: Optional[float] = None) -> Iterator[TaskResult]:
    """``fn(item)`` for every item, on the executor ``spec``; yields results as they finish.

    ``items`` is consumed lazily (at most ``in_flight`` tasks are submitted ahead), so a
    generator may stop producing when a budget runs out. A task whose worker died is retried
    up to ``retries`` times; retries run one at a time, so a death during a retry can be
    blamed on that item alone (a broken local pool fails every task in it, innocent ones
    included). A task still running ``timeout`` seconds after it started on its worker is
    given up (``timed_out``; on Dask its task is cancelled, though a running Python call cannot
    be stopped and keeps its worker thread until it returns); so is one that has not started
    ``start_timeout`` seconds after its submission (default: :data:`QUEUE_ALLOWANCE_S` plus
    ``timeout`` for each task that may run before it). Tasks run on this machine or on the
    Dask cluster of a ``dask://`` executor. Every item yields exactly one :class:`TaskResult`.
    """
    own = executor is None
    ex = executor or make_executor(spec, workers)
    slots = capacity(ex)
    limit = in_flight or 2 * slots
    # A Dask executor hears its tasks start; tasks on this machine leave a file.
    files = _FileStarts() if timeout is not None and not hasattr(ex, "starts") else None
    if start_timeout is None:
        start_timeout = _start_allowance(timeout, limit, slots)
    clock = _Deadlines(timeout, start_timeout, getattr(ex, "starts", files))
    source = iter(items)
    backlog: deque = deque()        # taken from `source` but not submitted (the pool was broken)
    retry: deque = deque()
    pending: dict[cf.Future, tuple[Any, int]] = {}
    exhausted = False
    try:
        while True:
            careful = bool(retry) or any(a > 1 for _, a in pending.values())
            broken = False
            while len(pending) < (1 if careful else limit):
                if retry:
                    item, attempt = retry.popleft()
                elif careful:
                    break
                elif backlog:
                    item, attempt = backlog.popleft()
                elif exhausted:
                    break
                else:
                    item = next(source, _END)
                    if item is _END:
                        exhausted = True
                        break
                    attempt = 1
                try:
                    fut = clock.submit(ex, fn, item)
                except cf.BrokenExecutor:       # a worker died since the last look: not this item's fault
                    (retry if attempt > 1 else backlog).appendleft((item, attempt))
                    broken = True
                    break
                pending[fut] = (item, attempt)
            if not broken:
                if not pending:
                    if retry or backlog:
                        continue
                    break
                done, _ = cf.wait(pending, timeout=clock.wait_seconds(pending), return_when=cf.FIRST_COMPLETED)
                for fut, reason in clock.expired(f for f in pending if f not in done):
                    item, attempt = pending.pop(fut)
                    clock.forget(fut)
                    getattr(fut, "abandon", fut.cancel)()
                    yield TaskResult(item, error=reason, attempts=attempt, timed_out=True)
                for fut in done:
                    item, attempt = pending.pop(fut)
                    clock.forget(fut)
                    exc = fut.exception()
                    if exc is None:
                        yield TaskResult(item, fut.result(), attempts=attempt)
                    elif is_worker_death(exc):
                        broken = broken or isinstance(exc, cf.BrokenExecutor)
                        if attempt <= retries:
                            retry.append((item, attempt + 1))
                        else:
                            yield TaskResult(item, lost=f"worker died on each of {attempt} tries "
                                                        f"({type(exc).__name__}: {exc})"[:400], attempts=attempt)
                    else:
                        yield TaskResult(item, error=f"{type(exc).__name__}: {exc}"[:400], attempts=attempt)
            if broken:
                if not own:
                    raise RuntimeError("the executor is broken (a worker process died)")
                # A broken pool fails everything in it: collect those tasks for a retry, start anew.
                for fut, (item, attempt) in list(pending.items()):
                    cf.wait([fut])
                    del pending[fut]
                    clock.forget(fut)
                    exc = fut.exception()
                    if exc is None:
                        yield TaskResult(item, fut.result(), attempts=attempt)
                    elif not is_worker_death(exc):
                        yield TaskResult(item, error=f"{type(exc).__name__}: {exc}"[:400], attempts=attempt)
                    elif attempt <= retries:
                        retry.append((item, attempt + 1))
                    else:
                        yield TaskResult(item, lost=f"worker pool broke on each of {attempt} tries", attempts=attempt)
                ex.shutdown(wait=False, cancel_futures=True)
                ex = make_executor(spec, workers)       # "broken" is a local pool's state: the file stamps still serve
    finally:
        if own:
            for fut in pending:
                fut.cancel()
            ex.shutdown(wait=True, cancel_futures=True)
        if files is not None:
            files.close()
