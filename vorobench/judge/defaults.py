"""The judge's defaults, in a module that imports nothing: the command line shows them in its
help without loading the judge (numba and scipy)."""

from __future__ import annotations

__all__ = ["DEFAULT_PROBES", "DEFAULT_TIMEOUT", "WARMUP_TIMEOUT"]

#: Random probe points per certificate (each must lie in its nearest site's cell).
DEFAULT_PROBES = 10_000
#: Seconds an implementation may take to build and be certified on one case.
DEFAULT_TIMEOUT = 60.0
#: Seconds for starting an implementation's sandbox, JIT compilation included.
WARMUP_TIMEOUT = 300.0
