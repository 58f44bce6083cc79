"""What an implementation is: a named build function plus what it declares about itself."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional

import numpy as np
from numpy.typing import NDArray

from vorobench.diagram import Diagram

__all__ = ["Implementation", "BuildFunction", "UnsupportedInput", "InputMutated"]

#: ``build(sites, stats)``: sites are prepared (distinct, finite float64); stats is a dict or None.
BuildFunction = Callable[[NDArray[np.float64], Optional[dict]], Diagram]


class UnsupportedInput(ValueError):
    """The implementation declares (through ``supports``) that it cannot take these sites."""


class InputMutated(RuntimeError):
    """The implementation changed the sites it was given: a failure of that implementation."""


@dataclass(frozen=True)
class Implementation:
    """One Voronoi construction behind the common interface.

    ``exact``: every geometric decision is exact, so two exact implementations must agree
    exactly (not merely within tolerance). ``warmup``: compiles JIT kernels so that timings
    exclude compile time. ``supports``: returns None if it can take the sites, else the
    reason it cannot (the runner then skips the case instead of failing it).

    Callers go through :meth:`run`, never ``build`` directly: it is the one place that
    honours ``supports`` and keeps the caller's sites out of the implementation's reach.
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

    def unsupported_reason(self, sites: NDArray[np.float64]) -> Optional[str]:
        """Why this implementation cannot take ``sites`` (None if it can)."""
        if self.supports is None:
            return None
        reason = self.supports(sites)
        return str(reason) if reason else None

    def run(self, sites: NDArray[np.float64], stats: Optional[dict] = None, *,
            check_supports: bool = True) -> Diagram:
        """Build the diagram of prepared ``sites``.

        Raises :class:`UnsupportedInput` when ``supports`` refuses the sites, and
        :class:`InputMutated` when the build changed its input. The implementation gets a
        read-only copy, so ``sites`` itself is never touched; writing through that copy
        raises inside the implementation, and a copy made writeable again and changed is
        caught by the comparison afterwards.
        """
        if check_supports:
            reason = self.unsupported_reason(sites)
            if reason:
                raise UnsupportedInput(f"{self.name} does not support these sites: {reason}")
        given = np.array(sites, dtype=np.float64, order="C", copy=True)
        given.setflags(write=False)
        diagram = self.build(given, stats)
        if not np.array_equal(given, sites):
            rows = np.flatnonzero((given != sites).any(axis=1)) if given.shape == sites.shape else []
            where = f" (row {int(rows[0])}; {len(rows)} row(s) changed)" if len(rows) else ""
            raise InputMutated(f"{self.name} changed the sites it was given{where}: inputs are read-only")
        return diagram
