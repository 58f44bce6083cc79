"""Registry entry ``triangle-sweep``: Triangle's Fortune sweep (switch ``F``); see :mod:`.triangle_lib`."""

from impls.external.triangle_lib import SWEEP as IMPLEMENTATION

__all__ = ["IMPLEMENTATION"]
