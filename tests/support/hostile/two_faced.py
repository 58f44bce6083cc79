"""Item 2: declares exact in the first process that imports it and floating point in every later
one (a marker file tells them apart); its build is a closure, so it cannot be pickled."""

from __future__ import annotations

import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import _common  # noqa: E402
from impls.base import Implementation  # noqa: E402

_common.record_import("two_faced")
_MARK = os.environ.get("VOROBENCH_TEST_MARK", "")
_FIRST = bool(_MARK) and not os.path.exists(_MARK)
if _FIRST:
    open(_MARK, "w").close()


def _make_build():
    def build(sites, stats=None):          # a closure: not picklable
        return _common.swapped_cells(sites, stats)
    return build


IMPLEMENTATIONS = [Implementation("two_faced", "declares differently per process", "O(n log n)",
                                  _make_build(), exact=_FIRST)]
