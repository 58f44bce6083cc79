"""Items 4 and 5: faults that only a judge of every timed repeat, outside the implementation's
process, catches. ``late_right`` is wrong on every build but its sixth (the warm-up is the first,
so with five repeats only the last repeat is right); ``check_patcher`` replaces the judging
functions of whatever process imports it and builds a wrong diagram; ``input_cache`` returns
a cached diagram for input bytes it has seen, after a 0.2 s build on a miss."""

from __future__ import annotations

import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import _common  # noqa: E402
from impls.base import Implementation  # noqa: E402
from impls.qhull import build as qhull_build  # noqa: E402

_common.record_import("bench_faults")

_BUILDS = [0]


def _late_right(sites, stats=None):
    _BUILDS[0] += 1
    return qhull_build(sites, stats) if _BUILDS[0] == 6 else _common.swapped_cells(sites, stats)


def _patch_every_judge() -> None:
    """Whatever judging code this process holds now passes everything."""
    def passes(*args, **kwargs):
        return {"verdict": "exact", "check_passed": True, "blame": "", "verdict_detail": "all fine"}

    for module, name in (("vorobench.harness.worker", "check_against_reference"),
                         ("vorobench.harness.repeat_check", "RepeatJudging")):
        target = sys.modules.get(module)
        if target is not None and hasattr(target, name):
            if name == "RepeatJudging":
                getattr(target, name).verdicts = lambda self, count, *a, **k: [passes()] * count
            else:
                setattr(target, name, lambda *a, **k: passes())


_patch_every_judge()

_CACHE: dict = {}


def _input_cache(sites, stats=None):
    key = sites.tobytes()
    if key not in _CACHE:
        time.sleep(0.2)                     # an honest build's cost
        _CACHE[key] = qhull_build(sites, stats)
    return _CACHE[key]


IMPLEMENTATIONS = [
    Implementation("late_right", "right on its sixth build only", "O(n log n)", _late_right, exact=False),
    Implementation("check_patcher", "patches the judge where it is imported", "O(n log n)", _common.swapped_cells,
                   exact=False),
    Implementation("input_cache", "caches its diagram by the input's bytes", "O(n log n)", _input_cache, exact=False),
]
