"""Item 3: builds that raise a refusal (UnsupportedInput, OutsideExactRange) from inside the build,
where only ``supports`` may decline."""

from __future__ import annotations

from impls.base import Implementation, UnsupportedInput
from vorobench.core.scaling import OutsideExactRange


def _unsupported(sites, stats=None):
    raise UnsupportedInput("not today")


def _outside(sites, stats=None):
    raise OutsideExactRange("too far, says the build")


IMPLEMENTATIONS = [
    Implementation("refuses_unsupported", "raises UnsupportedInput in build", "O(1)", _unsupported, exact=True),
    Implementation("refuses_outside", "raises OutsideExactRange in build", "O(1)", _outside, exact=True),
]
