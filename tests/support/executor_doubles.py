"""Test doubles for the executor tests. Loaded with ``--plugin``: a correct implementation (Qhull's
build) that ends its whole process with ``os._exit`` on some inputs only, as a worker death
does; the other cases finish normally, so a test can check none of their results is lost.
Imported: tasks for ``run_tasks`` that kill their worker, or hold it until a gate opens."""

from __future__ import annotations

import os
import time
from pathlib import Path

from impls.base import Implementation
from impls.qhull import build as qhull_build

__all__ = ["IMPLEMENTATIONS", "dies_on", "square_or_die", "HOLD_LIMIT_S", "open_gate", "mark", "has_mark",
           "hold_at_gate"]


def dies_on(n_sites: int) -> bool:
    """The inputs that kill the process: a number of sites ending in 6."""
    return n_sites % 10 == 6


def _exit_on_some(sites, stats=None):
    if dies_on(int(sites.shape[0])):
        os._exit(3)                              # no exception, no cleanup: the process is gone
    return qhull_build(sites, stats)


IMPLEMENTATIONS = [
    Implementation(name="exit_on_some", description="test double: os._exit when the site count ends in 6",
                   complexity="n/a", build=_exit_on_some, exact=False, origin="tests"),
]


def square_or_die(x: int) -> int:
    """A task for :func:`vorobench.harness.executors.run_tasks`: ``x * x``, except that 3 kills its worker."""
    if x == 3:
        os._exit(3)
    return x * x


#: The longest a held task waits for its gate: a test that fails before opening it leaves no task for ever.
HOLD_LIMIT_S = 120.0


def open_gate(folder: str) -> None:
    """Let every task held at the gate in ``folder`` go on."""
    (Path(folder) / "open").touch()


def mark(folder: str, name: str, event: str) -> None:
    """Leave the file ``name.event`` in ``folder``: what a task did, seen by the test."""
    (Path(folder) / f"{name}.{event}").touch()


def has_mark(folder: str, name: str, event: str) -> bool:
    """True once the task ``name`` has left its ``event`` mark in ``folder``."""
    return (Path(folder) / f"{name}.{event}").exists()


def hold_at_gate(job: tuple[str, str]) -> str:
    """A task for ``run_tasks``: ``job`` is (gate folder, name). Marks ``name`` started, waits
    until the gate is open (at most :data:`HOLD_LIMIT_S`), marks it ended; returns ``name``.
    A test uses it to keep a worker busy for as long as it wants, whatever the machine's load."""
    folder, name = job
    mark(folder, name, "started")
    deadline = time.monotonic() + HOLD_LIMIT_S
    while not (Path(folder) / "open").exists() and time.monotonic() < deadline:
        time.sleep(0.02)
    mark(folder, name, "ended")
    return name
