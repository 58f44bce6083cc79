"""Shared test set-up: the helper modules in tests/support (test doubles loaded as plugins or
imported by name, in this process and in its workers), one Dask cluster per session, and
Ctrl-C for the runs a test starts."""

from __future__ import annotations

import signal
import sys
from pathlib import Path

import pytest

SUPPORT = Path(__file__).resolve().parent / "support"
if str(SUPPORT) not in sys.path:
    sys.path.insert(0, str(SUPPORT))     # workers get sys.path from this process


@pytest.fixture(scope="session")
def dask_address():
    """A local Dask cluster for the whole session (two single-threaded worker processes), as
    ``dask://HOST:PORT``. Its workers are not daemonic, so the judge can isolate every build
    in a sandbox there too; a task whose worker dies fails at once (the runner and the
    executors do their own single retry)."""
    pytest.importorskip("distributed", reason="dask.distributed not installed (pip install vorobench[dask])")
    import dask
    from distributed import LocalCluster

    with dask.config.set({"distributed.scheduler.allowed-failures": 0, "distributed.worker.daemon": False}):
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=None) as cluster:
            yield cluster.scheduler_address.replace("tcp://", "dask://")


@pytest.fixture
def sigint_reaches_children():
    """Runs started by the test get SIGINT's default action, even when the tests themselves
    were started with SIGINT ignored (a background job of a shell without job control, as
    some CI runners start them): an ignored signal stays ignored across exec, Python then
    installs no KeyboardInterrupt handler, and a test of Ctrl-C waits for nothing."""
    before = signal.getsignal(signal.SIGINT)
    if before == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    if before is not None:
        signal.signal(signal.SIGINT, before)
