"""vorobench.harness.executors and bench --executor: a local process pool and a real Dask LocalCluster
(two worker processes on loopback) give the same verdicts, and a worker that dies loses no
finished result: its case is retried once, then recorded as lost."""

from __future__ import annotations

import concurrent.futures as cf
import math
import socket
import sys
import threading
import time
from pathlib import Path

import pytest

from vorobench.harness import executors
from vorobench.harness.executors import DaskMissing, check_spec, make_executor, parse_spec, run_tasks

HERE = Path(__file__).parent
SUPPORT = HERE.parent / "support"
PLUGIN = str(SUPPORT / "executor_doubles.py")


def test_parse_spec():
    assert parse_spec("local") == ("local", None)
    assert parse_spec("dask://10.0.0.5:8786") == ("dask", "tcp://10.0.0.5:8786")
    for bad in ("dask://", "spark://x:1", "thread"):
        with pytest.raises(ValueError, match="unknown executor"):
            parse_spec(bad)


def test_check_spec_refuses_a_scheduler_address_where_nothing_listens():
    check_spec("local")
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]              # closed again when the block ends
    with pytest.raises(ValueError, match="connection refused"):
        check_spec(f"dask://127.0.0.1:{port}")
    with pytest.raises(ValueError, match="not HOST:PORT"):
        check_spec("dask://127.0.0.1:port")
    with socket.socket() as listening:
        listening.bind(("127.0.0.1", 0))
        listening.listen(1)
        check_spec(f"dask://127.0.0.1:{listening.getsockname()[1]}")     # a port that accepts passes


def test_local_executor_is_a_process_pool():
    ex = make_executor("local", 2)
    try:
        assert isinstance(ex, cf.ProcessPoolExecutor)
        assert ex.submit(math.factorial, 5).result(timeout=60) == 120
    finally:
        ex.shutdown()
    with pytest.raises(ValueError):
        make_executor("local", 0)


def test_dask_missing_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "distributed", None)     # import distributed -> ImportError
    with pytest.raises(DaskMissing, match=r"pip install vorobench\[dask\]"):
        make_executor("dask://127.0.0.1:1", 1)


def test_run_tasks_loses_no_result_when_a_worker_dies():
    from executor_doubles import square_or_die

    results = list(run_tasks("local", 2, square_or_die, range(7)))
    by_item = {r.item: r for r in results}
    assert sorted(by_item) == list(range(7)) and len(results) == 7      # each item exactly once
    assert by_item[3].lost and by_item[3].attempts == 2 and by_item[3].value is None
    assert {x: r.value for x, r in by_item.items() if x != 3} == {x: x * x for x in range(7) if x != 3}


def test_run_tasks_reports_a_raising_task_as_an_error_not_a_death():
    results = {r.item: r for r in run_tasks("local", 1, math.sqrt, [4.0, -1.0, 9.0])}
    assert results[4.0].value == 2.0 and results[9.0].value == 3.0
    assert "ValueError" in results[-1.0].error and not results[-1.0].lost and results[-1.0].attempts == 1


# ----------------------------------------------------------------------- with a Dask cluster



def test_dask_executor_runs_tasks_on_the_cluster(dask_address):
    ex = make_executor(dask_address, 1)
    try:
        assert executors.capacity(ex) == 2
        assert "2 workers" in executors.describe(ex)
        assert ex.submit(math.factorial, 6).result(timeout=60) == 720
    finally:
        ex.shutdown()


def _bench(out: Path, executor: str, workers: int):
    from vorobench.cli import bench as bench_cmd
    from vorobench.harness import results
    from vorobench.harness.runner import RunConfig

    config = RunConfig(repeat=1, plugins=(PLUGIN,), timeout=60)
    code, _ = bench_cmd.execute(["fortune", "exit_on_some"], ["uniform"], [50, 156], [0], out, config,
                                progress=False, verbose=False, executor=executor, workers=workers)
    assert code == 0
    return results.load(out)


def test_bench_on_dask_and_local_same_verdicts_and_no_case_dropped(tmp_path, dask_address):
    local = _bench(tmp_path / "local.csv", "local", 2)
    dask = _bench(tmp_path / "dask.csv", dask_address, 1)
    expected = {(i, n) for i in ("fortune", "exit_on_some") for n in (50, 156)}
    for df in (local, dask):
        assert set(zip(df["impl"], df["n"])) == expected and len(df) == len(expected)   # one row each
        ran = df[df["status"] == "ok"]
        assert ran["host"].notna().all() and (ran["time_s"] > 0).all()

    def verdicts(df):
        return {(r.impl, r.n): (r.status, r.verdict) for r in df.itertuples()}

    lv, dv = verdicts(local), verdicts(dask)
    dying = ("exit_on_some", 156)
    # Each case has its own sandbox, locally and on a Dask worker that may start processes (the
    # session's cluster is not daemonic): the death is that case's crash, the worker lives on.
    assert lv.pop(dying) == ("crashed", "crashed")
    assert dv.pop(dying) == ("crashed", "crashed")
    assert "status" in dask.loc[(dask["impl"] == "exit_on_some") & (dask["n"] == 156), "error"].iloc[0]
    assert lv == dv and all(status == "ok" for status, _ in lv.values())


def test_report_warns_when_timings_come_from_several_hosts(tmp_path):
    import pandas as pd

    from vorobench.harness.analysis import mixed_hosts_note

    rows = pd.DataFrame({"impl": ["a", "b", "c"], "status": ["ok", "ok", "lost"], "host": ["n1", "n1", "n2"]})
    assert mixed_hosts_note(rows) is None                       # the lost row timed nothing
    rows.loc[1, "host"] = "n2"
    note = mixed_hosts_note(rows)
    assert note.startswith("WARNING") and "2 hosts (n1, n2)" in note
    assert mixed_hosts_note(rows.drop(columns="host")) is None  # results from before the column


# ------------------------------------------------------------------ timeouts on a busy machine

#: The tasks' own time limit in these tests: a task that does nothing stays far inside it.
TIMEOUT = 2.0


def _wait_for_mark(folder: Path, name: str, event: str, seconds: float = 120.0) -> None:
    """Wait until task ``name`` has left its ``event`` mark (the machine may be slow to start it)."""
    from executor_doubles import has_mark

    deadline = time.monotonic() + seconds
    while not has_mark(str(folder), name, event):
        assert time.monotonic() < deadline, f"task {name} never {event}"
        time.sleep(0.05)


def _then_open_gate(folder: Path, hold_s: float, *items):
    """Yield ``items`` to run_tasks, and open the gate in ``folder`` ``hold_s`` seconds after
    they were taken: tasks submitted behind a held worker queue at least that long."""
    from executor_doubles import open_gate

    timer = threading.Timer(hold_s, open_gate, [str(folder)])
    timer.daemon = True
    timer.start()
    yield from items


def test_queue_time_does_not_count_against_the_timeout_on_a_local_pool(tmp_path):
    from executor_doubles import hold_at_gate, open_gate

    ex = make_executor("local", 1)
    try:
        blocker = ex.submit(hold_at_gate, (str(tmp_path), "blocker"))
        _wait_for_mark(tmp_path, "blocker", "started")          # the pool's only worker is busy
        results = list(run_tasks("local", 1, math.sqrt, _then_open_gate(tmp_path, 2 * TIMEOUT, 4.0), executor=ex,
                                 timeout=TIMEOUT))
        assert [(r.value, r.error, r.timed_out) for r in results] == [(2.0, "", False)]
        assert blocker.result(timeout=60) == "blocker"
    finally:
        open_gate(str(tmp_path))
        ex.shutdown()


def test_queue_time_does_not_count_against_the_timeout_on_a_busy_dask_cluster(tmp_path, dask_address):
    from executor_doubles import hold_at_gate, open_gate

    ex = make_executor(dask_address, 1)
    try:
        workers = sorted(ex.client.scheduler_info()["workers"])
        blockers = [ex.client.submit(hold_at_gate, (str(tmp_path), f"blocker{i}"), workers=[w], pure=False)
                    for i, w in enumerate(workers)]
        for i in range(len(workers)):
            _wait_for_mark(tmp_path, f"blocker{i}", "started")   # every worker thread of the cluster is busy
        results = list(run_tasks(dask_address, 1, math.sqrt, _then_open_gate(tmp_path, 2 * TIMEOUT, 4.0, 9.0),
                                 timeout=TIMEOUT))
        assert sorted((r.value, r.error, r.timed_out) for r in results) == [(2.0, "", False), (3.0, "", False)]
        assert sorted(b.result(timeout=60) for b in blockers) == [f"blocker{i}" for i in range(len(workers))]
    finally:
        open_gate(str(tmp_path))
        ex.shutdown()


def test_a_task_that_overstays_its_timeout_is_reported_not_waited_for(tmp_path, dask_address):
    from executor_doubles import has_mark, hold_at_gate, open_gate

    opened, shut = tmp_path / "opened", tmp_path / "shut"
    opened.mkdir(), shut.mkdir()
    open_gate(str(opened))
    try:
        results = {r.item[1]: r for r in run_tasks(dask_address, 1, hold_at_gate,
                                                   [(str(opened), "quick"), (str(shut), "stuck")], timeout=TIMEOUT)}
        assert results["quick"].ok and results["quick"].value == "quick" and not results["quick"].timed_out
        assert results["stuck"].timed_out and f"no result within {TIMEOUT:g} s" in results["stuck"].error
        assert has_mark(str(shut), "stuck", "started") and not has_mark(str(shut), "stuck", "ended")   # still held
    finally:
        open_gate(str(shut))        # the abandoned task ends now and frees its worker thread
    _wait_for_mark(shut, "stuck", "ended")


def test_a_task_that_never_starts_is_given_up_after_its_start_allowance(tmp_path):
    from executor_doubles import hold_at_gate, open_gate

    ex = make_executor("local", 1)
    try:
        ex.submit(hold_at_gate, (str(tmp_path), "blocker"))
        _wait_for_mark(tmp_path, "blocker", "started")
        results = list(run_tasks("local", 1, math.sqrt, [4.0], executor=ex, timeout=TIMEOUT, start_timeout=1.0))
        assert len(results) == 1 and results[0].timed_out and "not started within 1 s" in results[0].error
    finally:
        open_gate(str(tmp_path))
        ex.shutdown()


def test_validate_on_a_pool_and_on_dask_gives_the_verdicts_of_a_serial_run(tmp_path, dask_address):
    import json

    from vorobench.cli import main

    def verdicts(out: Path, *extra: str) -> list[str]:
        code = main(["validate", "--impls", "fortune,incremental", "--datasets", "uniform,grid", "--sizes", "10,40",
                     "--probes", "200", "--out", str(out), *extra])
        summary = json.loads((out / "summary.json").read_text())
        assert code == 0 and summary["passed"] and summary["lost"] == 0
        return sorted(str((r["impl"], r["dataset"], r["n"], r["exact_peer"], r["verdict"])) for r in summary["results"])

    serial = verdicts(tmp_path / "serial")
    assert len(serial) == 4 * 4         # 4 cases x (qhull, fortune, incremental, incremental vs fortune)
    assert verdicts(tmp_path / "pool", "--workers", "2") == serial
    assert verdicts(tmp_path / "dask", "--executor", dask_address) == serial
