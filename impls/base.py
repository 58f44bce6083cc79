"""What an implementation is: a named build function plus what it declares about itself."""

from __future__ import annotations

from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass
from typing import Callable, Iterator, Optional

import numpy as np
from numpy.typing import NDArray

from vorobench.core.counters import CounterError, check_counters
from vorobench.core.diagram import Diagram
from vorobench.core.scaling import exact_shift, scale_back_vertices, scale_points

__all__ = ["Implementation", "KINDS", "BuildFunction", "UnsupportedInput", "InputMutated", "CounterError", "record_timing"]

#: ``build(sites, stats)``: sites are prepared (distinct, finite float64); stats is a dict or
#: None, for counters only (machine-independent integers); times go to :func:`record_timing`.
BuildFunction = Callable[[NDArray[np.float64], Optional[dict]], Diagram]

#: Where :func:`record_timing` adds seconds during a build (None: nobody asked for them).
#: What an implementation may say it is (``Implementation.kind``).
KINDS = ("own", "outside", "plugin")

_PHASE_TIMES: ContextVar[Optional[dict]] = ContextVar("vorobench_phase_times", default=None)


def record_timing(phase: str, seconds: float) -> None:
    """Add ``seconds`` to the time of ``phase`` (e.g. ``library``: the outside library's own
    call) of the build that is running; kept apart from the counters, since it is a time."""
    times = _PHASE_TIMES.get()
    if times is not None:
        times[phase] = times.get(phase, 0.0) + float(seconds)


@contextmanager
def _collecting_times(times: Optional[dict]) -> Iterator[None]:
    token = _PHASE_TIMES.set(times)
    try:
        yield
    finally:
        _PHASE_TIMES.reset(token)


class UnsupportedInput(ValueError):
    """The implementation declares (through ``supports``) that it cannot take these sites."""


class InputMutated(RuntimeError):
    """The implementation changed the sites it was given: a failure of that implementation."""


@dataclass(frozen=True)
class Implementation:
    """One Voronoi construction behind the common interface.

    ``exact``: every geometric decision is exact, so two exact implementations must agree
    exactly (not merely within tolerance). ``kind`` says where it comes from: ``"own"``
    (written in this project), ``"outside"`` (an adapter to an outside library) or
    ``"plugin"`` (anything registered from elsewhere, the default). ``warmup``: compiles JIT kernels so that timings
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
    kind: str = "plugin"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"implementation {self.name!r}: kind must be one of {', '.join(KINDS)}, not {self.kind!r}")

    def unsupported_reason(self, sites: NDArray[np.float64]) -> Optional[str]:
        """Why this implementation cannot take ``sites`` (None if it can)."""
        if self.supports is None:
            return None
        reason = self.supports(sites)
        return str(reason) if reason else None

    def run(self, sites: NDArray[np.float64], stats: Optional[dict] = None, *,
            timings: Optional[dict] = None, check_supports: bool = True) -> Diagram:
        """Build the diagram of prepared ``sites``.

        ``stats`` (a dict) receives the build's counters, ``timings`` the seconds of the parts
        it timed (:func:`record_timing`). Raises :class:`UnsupportedInput` when ``supports``
        refuses the sites, :class:`InputMutated` when the build changed its input, and
        :class:`CounterError` when it put anything but integers into ``stats``. The implementation gets a
        read-only copy, so ``sites`` itself is never touched; writing through that copy
        raises inside the implementation, and a copy made writeable again and changed is
        caught by the comparison afterwards.

        Magnitudes: sites outside the range where the predicates are exact are scaled by a
        power of two into it first (exact; same combinatorics), the implementation builds
        (and ``supports`` screens, whatever ``check_supports`` says, since the caller
        screened other numbers) the scaled sites, and the vertices are scaled back; the
        diagram's ``sites`` are a copy of ``sites``, bit for bit. Sites that no power of two
        brings into the range, and diagrams whose vertices leave the float range when scaled
        back, raise :class:`~vorobench.core.scaling.OutsideExactRange` (a ``ValueError``); see
        :mod:`vorobench.core.scaling` for the rule. Inside the range this costs one pass over the
        coordinates.
        """
        shift = exact_shift(sites)
        if shift == 0:
            expected = sites
            given = np.array(sites, dtype=np.float64, order="C", copy=True)
        else:
            expected = scale_points(sites, shift)
            given = expected.copy()
        given.setflags(write=False)
        if check_supports or shift != 0:
            reason = self.unsupported_reason(given)
            if reason:
                raise UnsupportedInput(f"{self.name} does not support these sites: {reason}")
        with _collecting_times(timings):
            diagram = self.build(given, stats)
        if stats:
            stats.update(check_counters(stats, who=self.name))
        if not np.array_equal(given, expected):
            rows = np.flatnonzero((given != expected).any(axis=1)) if given.shape == expected.shape else []
            where = f" (row {int(rows[0])}; {len(rows)} row(s) changed)" if len(rows) else ""
            raise InputMutated(f"{self.name} changed the sites it was given{where}: inputs are read-only")
        if shift == 0:
            return diagram
        return _scaled_back(diagram, sites, shift)


def _scaled_back(diagram: Diagram, sites: NDArray[np.float64], shift: int) -> Diagram:
    """The diagram built on ``sites * 2**shift``, for ``sites``: the same DCEL, the vertices
    times 2**-shift, and a read-only copy of the caller's sites (bit for bit) when the
    diagram is of the sites it was given; a diagram of other sites keeps its own sites,
    scaled back, so the judge still sees the difference."""
    built = np.asarray(diagram.sites, dtype=np.float64)
    if built.shape == sites.shape and np.array_equal(built, scale_points(sites, shift)):
        own = np.array(sites, dtype=np.float64, order="C", copy=True)
    else:
        own = scale_back_vertices(built, shift)
    own.setflags(write=False)
    return Diagram(own, scale_back_vertices(diagram.vertices, shift), diagram.origin, diagram.twin,
                   diagram.next, diagram.site)
