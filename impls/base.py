"""What an implementation is: a named build function plus what it declares about itself."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np
from numpy.typing import NDArray

from vorobench.diagram import Diagram

__all__ = ["Implementation", "BuildFunction"]

#: ``build(sites, stats)``: sites are prepared (distinct, finite float64); stats is a dict or None.
BuildFunction = Callable[[NDArray[np.float64], Optional[dict]], Diagram]


@dataclass(frozen=True)
class Implementation:
    """One Voronoi construction behind the common interface.

    ``exact``: every geometric decision is exact, so two exact implementations must agree
    exactly (not merely within tolerance). ``warmup``: compiles JIT kernels so that timings
    exclude compile time. ``supports``: returns None if it can take the sites, else the
    reason it cannot (the runner then skips the case instead of failing it).
    """

    name: str
    description: str
    complexity: str
    build: BuildFunction
    exact: bool = True
    origin: str = "vorobench"
    warmup: Optional[Callable[[], None]] = None
    supports: Optional[Callable[[NDArray[np.float64]], Optional[str]]] = None
    tags: tuple[str, ...] = field(default_factory=tuple)
