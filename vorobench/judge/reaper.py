"""The reaper: a tiny process that kills the harness's worker process groups when it dies.

Run as a script (``python reaper.py``; it imports nothing of vorobench, so it starts in
milliseconds). It reads lines ``+PGID`` and ``-PGID`` on its standard input and keeps the
set of live worker groups. When its input ends, which happens however the harness ends
(normal exit, an exception, SIGTERM, SIGKILL), it sends SIGKILL to every group still in the
set, so no worker nor any grandchild it started outlives the run.
"""

from __future__ import annotations

import os
import signal
import sys


def _kill(pgid: int) -> None:
    for kill in (os.killpg, os.kill):   # the group, or the worker alone if it has none yet
        try:
            kill(pgid, signal.SIGKILL)
            return
        except (ProcessLookupError, PermissionError):
            continue


def main() -> None:
    # The terminal's Ctrl-C and the harness's own group signals are not for the reaper: it
    # must outlive the harness to clean up after it.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    signal.signal(signal.SIGHUP, signal.SIG_IGN)
    groups: set[int] = set()
    for line in sys.stdin:
        line = line.strip()
        if len(line) < 2 or not line[1:].isdigit():
            continue
        pgid = int(line[1:])
        if line[0] == "+":
            groups.add(pgid)
        elif line[0] == "-":
            groups.discard(pgid)
    for pgid in groups:
        _kill(pgid)


if __name__ == "__main__":
    main()
