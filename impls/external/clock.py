"""Splits an adapter's build time into the library's own call and our conversion around it."""

from __future__ import annotations

import time
from contextlib import contextmanager
from typing import Iterator, Optional

__all__ = ["BuildClock"]


class BuildClock:
    """Started when created; ``with clock.library():`` marks the time spent inside the library.

    :meth:`report` writes ``library_s`` and ``convert_s`` (the rest of the build) into stats.
    An adapter that calls the library more than once and throws results away marks each
    thrown-away attempt with :meth:`discard`; that time counts in neither (``discarded_ns``).
    """

    def __init__(self) -> None:
        self._start = time.perf_counter_ns()
        self.library_ns = 0
        self.discarded_ns = 0

    @contextmanager
    def library(self) -> Iterator[None]:
        t0 = time.perf_counter_ns()
        try:
            yield
        finally:
            self.library_ns += time.perf_counter_ns() - t0

    def mark(self) -> tuple[int, int]:
        """A reading to pass to :meth:`discard` later: (now, library time so far)."""
        return time.perf_counter_ns(), self.library_ns

    def discard(self, since: tuple[int, int]) -> None:
        """Move everything since the reading ``since`` (library time included) to discarded."""
        t0, library_before = since
        self.discarded_ns += time.perf_counter_ns() - t0
        self.library_ns = library_before

    def report(self, stats: Optional[dict]) -> None:
        """Record ``library_s`` and ``convert_s`` (seconds) in ``stats`` if it is a dict."""
        if stats is None:
            return
        total = time.perf_counter_ns() - self._start
        stats["library_s"] = self.library_ns / 1e9
        stats["convert_s"] = max(0, total - self.library_ns - self.discarded_ns) / 1e9
