"""Registry entry ``triangle-incremental``: Triangle's incremental insertion (switch ``i``); see :mod:`.triangle_lib`."""

from impls.external.triangle_lib import INCREMENTAL as IMPLEMENTATION

__all__ = ["IMPLEMENTATION"]
