"""Item 3: builds that raise a refusal (UnsupportedInput, OutsideExactRange) from inside the build,
where only ``supports`` may decline. Also (item 7) ``swapped_exact``: an exact-declared build
that returns a wrong diagram and does nothing else."""

from __future__ import annotations

import sys
from pathlib import Path

from impls.base import Implementation, UnsupportedInput
from vorobench.core.scaling import OutsideExactRange

sys.path.insert(0, str(Path(__file__).parent))

import _common  # noqa: E402


def _unsupported(sites, stats=None):
    raise UnsupportedInput("not today")


def _outside(sites, stats=None):
    raise OutsideExactRange("too far, says the build")


IMPLEMENTATIONS = [
    Implementation("refuses_unsupported", "raises UnsupportedInput in build", "O(1)", _unsupported, exact=True),
    Implementation("refuses_outside", "raises OutsideExactRange in build", "O(1)", _outside, exact=True),
    Implementation("swapped_exact", "exact-declared, two cells swapped", "O(n log n)", _common.swapped_cells,
                   exact=True),
]
