"""Test double: every implementation slowed down by a fixed fraction, under its own name.

Loaded with ``--plugin``, it registers, for each implementation available here, a copy whose
build spins for ``VOROBENCH_TEST_SLOWDOWN`` (default 0.25) times the build's own time after
building: a uniform slowdown of every case, with the same counters and diagrams, the way a
regression in shared code would look.
"""

from __future__ import annotations

import dataclasses
import os
import time

import impls
from impls.base import Implementation


def _slowed(impl: Implementation) -> Implementation:
    fraction = float(os.environ.get("VOROBENCH_TEST_SLOWDOWN", "0.25"))

    def build(sites, stats=None):
        t0 = time.perf_counter()
        diagram = impl.build(sites, stats)
        until = time.perf_counter() + fraction * (time.perf_counter() - t0)
        while time.perf_counter() < until:       # busy, like extra work, not a sleep
            pass
        return diagram

    return dataclasses.replace(impl, build=build, description=f"{impl.description} (slowed down for a test)")


IMPLEMENTATIONS = [_slowed(impls.get(name)) for name in impls.available() if name not in impls.registered()]
