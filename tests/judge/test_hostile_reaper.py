"""No sandbox, nor any process it started, outlives the judging process, whatever dies first.

The reaper (:mod:`vorobench.judge.reaper`) kills what is left when the judge ends; but the
reaper can be killed too (an OOM killer, a careless ``kill -9``). The sandbox is forked from
the fork server, not from the judge, so its own parent-death signal is no help either: the
sandbox must see the judge's death itself and take its process group with it.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

from processes import alive

ROOT = Path(__file__).resolve().parents[2]
DOUBLES = str(ROOT / "tests" / "support" / "doubles.py")

#: A judging process: one sandbox running the ``hang_with_grandchild`` double (it starts a
#: sleeping child, writes both pids to $VOROBENCH_TEST_PIDFILE, then spins forever).
JUDGE_SCRIPT = textwrap.dedent("""
    import json, os, sys

    import numpy as np

    from vorobench.judge import isolation
    from vorobench.judge.engine import build_in_sandbox
    from vorobench.judge.sandbox import Sandbox

    def main(doubles: str, info: str) -> None:
        box = Sandbox("hang_with_grandchild", plugins=(doubles,))
        failure = box.start()
        if failure is not None:
            sys.exit(f"the sandbox did not start: {failure}")
        with open(info + ".tmp", "w") as f:
            json.dump({"reaper": isolation._REAPER._proc.pid}, f)
        os.replace(info + ".tmp", info)
        box.call(build_in_sandbox, "hang_with_grandchild", np.random.default_rng(0).random((20, 2)), None,
                 timeout=None)

    if __name__ == "__main__":     # the sandbox's process is started from here: import-safe
        main(*sys.argv[1:3])
""")


_alive = alive


def _parent_of(pid: int) -> int:
    """The parent pid of a running process."""
    return int(Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[1])


def _survivors(pids: list[int], seconds: float) -> list[int]:
    """The pids still running after up to ``seconds`` of waiting for all of them to end."""
    deadline = time.monotonic() + seconds
    while any(_alive(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.2)
    return [p for p in pids if _alive(p)]


def _wait_for_file(path: Path, judge: subprocess.Popen, seconds: float) -> None:
    """Wait until ``path`` exists; fail at once if the judge ends first."""
    deadline = time.monotonic() + seconds
    while not path.exists():
        assert judge.poll() is None, f"the judge ended first (status {judge.returncode})"
        assert time.monotonic() < deadline, f"{path.name} never appeared"
        time.sleep(0.1)


def _kill_leftovers(pids: list[int]) -> None:
    """Kill what a failed test left running (the double spins at 100 % CPU)."""
    for pid in pids:
        for kill in (os.killpg, os.kill):
            try:
                kill(pid, signal.SIGKILL)
            except (ProcessLookupError, PermissionError):
                pass


def test_killing_the_reaper_then_the_judge_leaves_no_sandbox_nor_its_child(tmp_path):
    script, info, pidfile = tmp_path / "judge.py", tmp_path / "info.json", tmp_path / "pids"
    script.write_text(JUDGE_SCRIPT)
    judge = subprocess.Popen([sys.executable, str(script), DOUBLES, str(info)], cwd=ROOT,
                             env={**os.environ, "VOROBENCH_TEST_PIDFILE": str(pidfile)},
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    pids: list[int] = []
    try:
        _wait_for_file(info, judge, 120)
        _wait_for_file(pidfile, judge, 120)
        pids = [int(p) for p in pidfile.read_text().split()]         # the sandbox, then its child
        reaper = json.loads(info.read_text())["reaper"]
        assert len(pids) == 2 and all(_alive(p) for p in pids + [reaper])
        server = _parent_of(pids[0])
        if server != judge.pid:             # forked from the fork server: it must end with the judge too
            pids.append(server)

        os.kill(reaper, signal.SIGKILL)
        assert not _survivors([reaper], 20), "the reaper did not die"
        judge.kill()
        judge.wait(timeout=60)

        assert not _survivors(pids, 20), "the sandbox, its child or the fork server outlived the judge"
    finally:
        if judge.poll() is None:
            judge.kill()
            judge.wait(timeout=60)
        _kill_leftovers(pids)
