"""Splits an adapter's build time into the library's own call and our conversion around it."""

from __future__ import annotations

import time
from contextlib import contextmanager
from typing import Iterator, Optional

__all__ = ["BuildClock"]


class BuildClock:
    """Started when created; ``with clock.library():`` marks the time spent inside the library.

    :meth:`report` writes ``library_s`` and ``convert_s`` (the rest of the build) into stats.
    """

    def __init__(self) -> None:
        self._start = time.perf_counter_ns()
        self.library_ns = 0

    @contextmanager
    def library(self) -> Iterator[None]:
        t0 = time.perf_counter_ns()
        try:
            yield
        finally:
            self.library_ns += time.perf_counter_ns() - t0

    def report(self, stats: Optional[dict]) -> None:
        """Record both times (seconds) in ``stats`` if it is a dict."""
        if stats is None:
            return
        total = time.perf_counter_ns() - self._start
        stats["library_s"] = self.library_ns / 1e9
        stats["convert_s"] = max(0, total - self.library_ns) / 1e9
