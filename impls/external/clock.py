"""Splits an adapter's build time into the library's own call and our conversion around it."""

from __future__ import annotations

import time
from contextlib import contextmanager
from typing import Iterator

from impls.base import record_timing

__all__ = ["BuildClock"]


class BuildClock:
    """Started when created; ``with clock.library():`` marks the time spent inside the library.

    :meth:`report` records the seconds of ``library`` and ``convert`` (the rest of the build) as
    timings of the build (:func:`impls.base.record_timing`), never as counters.
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

    def report(self) -> None:
        """Record the seconds of ``library``, ``convert`` and (if any) ``discarded`` as timings of
        the running build."""
        total = time.perf_counter_ns() - self._start
        record_timing("library", self.library_ns / 1e9)
        record_timing("convert", max(0, total - self.library_ns - self.discarded_ns) / 1e9)
        if self.discarded_ns:
            record_timing("discarded", self.discarded_ns / 1e9)
