"""Test double for the executor tests, loaded with ``--plugin``: a correct implementation (Qhull's
build) that ends its whole process with ``os._exit`` on some inputs only, as a worker death
does; the other cases finish normally, so a test can check none of their results is lost."""

from __future__ import annotations

import os

from impls.base import Implementation
from impls.qhull import build as qhull_build

__all__ = ["IMPLEMENTATIONS", "dies_on", "square_or_die"]


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
