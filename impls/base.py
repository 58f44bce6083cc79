"""What an implementation is: a named build function plus what it declares about itself."""

from __future__ import annotations

from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, replace
from typing import Callable, Iterator, Optional, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from vorobench.core.counters import CounterError, check_counters
from vorobench.core.diagram import Diagram
from vorobench.core.scaling import check_weight_range, exact_shift, scale_back_vertices, scale_points, scale_weights

__all__ = ["Implementation", "KINDS", "BuildFunction", "WeightedBuildFunction", "UnsupportedInput", "InputMutated",
           "BuildRaised", "CounterError", "record_timing", "record_process"]


@runtime_checkable
class BuildFunction(Protocol):
    """The construction behind an :class:`Implementation`: ``build(sites, stats) -> Diagram``.

    Any function taking two positional arguments fits (``def build(sites, stats=None)``);
    :meth:`Implementation.run` is its only caller. ``isinstance(f, BuildFunction)`` only
    checks that ``f`` is callable.
    """

    def __call__(self, sites: NDArray[np.float64], stats: Optional[dict[str, int]], /) -> Diagram:
        """The Voronoi diagram of ``sites``, cell i belonging to site i.

        ``sites``: an (n, 2) float64, C-contiguous, read-only array of distinct, finite
        points in the caller's order, already scaled into the exact range (nonzero magnitudes
        in [2**-100, 2**100)); n may be 0, 1 or 2. ``stats``: None, or a dict to put counters
        into: machine-independent integers (events, predicate calls, walk steps), never times
        (those go to :func:`record_timing`). Returns a
        :class:`~vorobench.core.diagram.Diagram` of exactly these sites; raises on failure.
        """
        ...


@runtime_checkable
class WeightedBuildFunction(Protocol):
    """The power-diagram construction of an :class:`Implementation` that takes weights:
    ``build_weighted(sites, weights, stats) -> Diagram``."""

    def __call__(self, sites: NDArray[np.float64], weights: NDArray[np.float64],
                 stats: Optional[dict[str, int]], /) -> Diagram:
        """The power diagram of ``sites`` with ``weights``: the power of x with respect to site i
        is |x - p_i|^2 - w_i. ``sites`` as for :class:`BuildFunction`; ``weights``: (n,)
        float64, finite, read-only, scaled with the sites (by 2**(2k) when the sites were
        scaled by 2**k). A hidden site (empty cell) gets no half-edge. Returns a
        :class:`~vorobench.core.diagram.Diagram` of exactly these sites."""
        ...


@runtime_checkable
class ApolloniusBuildFunction(Protocol):
    """The construction of the diagram of disks of an :class:`Implementation` that takes them:
    ``build_apollonius(centres, radii, stats) -> Diagram``."""

    def __call__(self, sites: NDArray[np.float64], radii: NDArray[np.float64],
                 stats: Optional[dict[str, int]], /) -> Diagram:
        """The diagram of the disks (``sites`` their centres, as for :class:`BuildFunction`;
        ``radii`` (n,) float64, finite, >= 0, read-only, scaled with the sites): the distance
        from x to disk i is |x - p_i| - r_i (docs/apollonius.md). A hidden disk (inside
        another) gets no half-edge. Returns a :class:`~vorobench.core.diagram.Diagram` of
        exactly these sites."""
        ...


#: What an implementation may say it is (``Implementation.kind``).
KINDS = ("own", "outside", "plugin", "executable")

#: Where :func:`record_timing` adds seconds during a build (None: nobody asked for them).
_PHASE_TIMES: ContextVar[Optional[dict]] = ContextVar("vorobench_phase_times", default=None)


def record_timing(phase: str, seconds: float) -> None:
    """Add ``seconds`` to the time of ``phase`` (e.g. ``library``: the outside library's own
    call) of the build that is running; kept apart from the counters, since it is a time."""
    times = _PHASE_TIMES.get()
    if times is not None:
        times[phase] = times.get(phase, 0.0) + float(seconds)


#: Where :func:`record_process` puts the measures of a build's child process (None: not asked).
_PROCESS: ContextVar[Optional[dict]] = ContextVar("vorobench_process", default=None)


def record_process(wall_s: float, cpu_s: float, peak_rss_mb: float) -> None:
    """The running build ran its construction in a child process (an executable): that
    process's own wall time, CPU time and peak resident memory, which stand for the build's
    (the harness's reading and assembling of its output is not the program's time)."""
    measures = _PROCESS.get()
    if measures is not None:
        measures.update(wall_s=float(wall_s), cpu_s=float(cpu_s), peak_rss_mb=float(peak_rss_mb))


@contextmanager
def _collecting_times(times: Optional[dict], process: Optional[dict] = None) -> Iterator[None]:
    token = _PHASE_TIMES.set(times)
    process_token = _PROCESS.set(process)
    try:
        yield
    finally:
        _PHASE_TIMES.reset(token)
        _PROCESS.reset(process_token)


class UnsupportedInput(ValueError):
    """The implementation declares (through ``supports``) that it cannot take these sites."""


class InputMutated(RuntimeError):
    """The implementation changed the sites it was given: a failure of that implementation."""


class BuildRaised(RuntimeError):
    """An exception raised by the build itself (its ``__cause__``), of whatever class: for the
    judge a crash, never a refusal (only ``supports`` declines sites)."""


@dataclass(frozen=True)
class Implementation:
    """One Voronoi construction behind the common interface.

    ``exact``: every geometric decision is exact, so two exact implementations must agree
    exactly (not merely within tolerance). ``kind`` says where it comes from: ``"own"``
    (written in this project), ``"outside"`` (an adapter to an outside library),
    ``"executable"`` (a program run through a TOML manifest: :mod:`impls.executable`) or
    ``"plugin"`` (anything registered from elsewhere, the default). ``warmup``: compiles JIT kernels so that timings
    exclude compile time. ``supports``: returns None if it can take the sites, else the
    reason it cannot (the runner then skips the case instead of failing it).
    ``build_weighted``: the power-diagram construction, for implementations that take
    weights (``weighted``); the others are refused weighted input as unsupported.
    ``build_apollonius``: the same for disks (``apollonius``; docs/apollonius.md).

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
    build_weighted: Optional[WeightedBuildFunction] = None
    build_apollonius: Optional[ApolloniusBuildFunction] = None
    #: How to read the version of the code behind it (None: its module's package version).
    version: Optional[Callable[[], str]] = None

    @property
    def weighted(self) -> bool:
        """Whether it builds power diagrams (it has a ``build_weighted``)."""
        return self.build_weighted is not None

    @property
    def apollonius(self) -> bool:
        """Whether it builds diagrams of disks (it has a ``build_apollonius``)."""
        return self.build_apollonius is not None

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
            timings: Optional[dict] = None, check_supports: bool = True,
            weights: Optional[NDArray[np.float64]] = None, wrap_build_errors: bool = False,
            process: Optional[dict] = None, radii: Optional[NDArray[np.float64]] = None) -> Diagram:
        """Build the diagram of prepared ``sites``.

        ``stats`` (a dict) receives the build's counters, ``timings`` the seconds of the parts
        it timed (:func:`record_timing`), ``process`` the measures of the child process an
        executable ran (:func:`record_process`; left empty by a build in this process). Raises :class:`UnsupportedInput` when ``supports``
        refuses the sites, :class:`InputMutated` when the build changed its input, and
        :class:`CounterError` when it put anything but integers into ``stats``. The implementation gets a
        read-only copy, so ``sites`` itself is never touched; writing through that copy
        raises inside the implementation, and a copy made writeable again and changed is
        caught by the comparison afterwards.

        ``weights`` (one per site) asks for the power diagram, through ``build_weighted``;
        an implementation without one raises :class:`UnsupportedInput`. The diagram
        returned carries the caller's weights. ``radii`` (one per site, >= 0) asks for the
        diagram of disks, through ``build_apollonius``, in the same way; they are scaled with
        the sites (the power of two is chosen for both together).

        Magnitudes: sites outside the range where the predicates are exact are scaled by a
        power of two into it first (exact; same combinatorics), the implementation builds
        (and ``supports`` screens, whatever ``check_supports`` says, since the caller
        screened other numbers) the scaled sites, and the vertices are scaled back; the
        diagram's ``sites`` are a copy of ``sites``, bit for bit. Sites that no power of two
        brings into the range, and diagrams whose vertices leave the float range when scaled
        back, raise :class:`~vorobench.core.scaling.OutsideExactRange` (a ``ValueError``); see
        :mod:`vorobench.core.scaling` for the rule. Inside the range this costs one pass over the
        coordinates.

        ``wrap_build_errors``: an exception the build raises (an ``UnsupportedInput`` among
        them) comes out as :class:`BuildRaised` from it, so a caller can tell the build's own
        failures from this method's refusals.
        """
        if weights is not None and self.build_weighted is None:
            raise UnsupportedInput(f"{self.name} does not support weighted sites (it builds ordinary diagrams only)")
        if radii is not None and self.build_apollonius is None:
            raise UnsupportedInput(f"{self.name} does not support disks as sites")
        if radii is not None and weights is not None:
            raise ValueError("weights (power diagram) and radii (disks) go one at a time")
        if radii is not None:
            radii = _checked_radii(radii, sites.shape[0])
            shift = exact_shift(np.vstack([np.asarray(sites, dtype=np.float64).reshape(-1, 2),
                                           np.column_stack([radii, radii])]))
        else:
            shift = exact_shift(sites)
        if shift == 0:
            expected = sites
            given = np.array(sites, dtype=np.float64, order="C", copy=True)
        else:
            expected = scale_points(sites, shift)
            given = expected.copy()
        given.setflags(write=False)
        if weights is not None:
            weights = np.asarray(weights, dtype=np.float64).reshape(-1)
            if weights.shape != (sites.shape[0],):
                raise ValueError(f"weights has shape {weights.shape}, there are {sites.shape[0]} sites")
            check_weight_range(sites, weights)
            expected_weights = scale_weights(weights, shift)
            given_weights = expected_weights.copy()
            given_weights.setflags(write=False)
        if radii is not None:
            expected_radii = np.ldexp(radii, shift)                # exact: a power of two, in range
            given_radii = expected_radii.copy()
            given_radii.setflags(write=False)
        if check_supports or shift != 0:
            reason = self.unsupported_reason(given)
            if reason:
                raise UnsupportedInput(f"{self.name} does not support these sites: {reason}")
        with _collecting_times(timings, process):
            try:
                if radii is not None:
                    diagram = self.build_apollonius(given, given_radii, stats)
                elif weights is None:
                    diagram = self.build(given, stats)
                else:
                    diagram = self.build_weighted(given, given_weights, stats)
            except Exception as exc:
                if not wrap_build_errors or isinstance(exc, MemoryError):
                    raise
                raise BuildRaised(f"{type(exc).__name__} raised inside the build") from exc
        if stats:
            stats.update(check_counters(stats, who=self.name))
        if not np.array_equal(given, expected):
            rows = np.flatnonzero((given != expected).any(axis=1)) if given.shape == expected.shape else []
            where = f" (row {int(rows[0])}; {len(rows)} row(s) changed)" if len(rows) else ""
            raise InputMutated(f"{self.name} changed the sites it was given{where}: inputs are read-only")
        if weights is not None and not np.array_equal(given_weights, expected_weights):
            raise InputMutated(f"{self.name} changed the weights it was given: inputs are read-only")
        if radii is not None and not np.array_equal(given_radii, expected_radii):
            raise InputMutated(f"{self.name} changed the radii it was given: inputs are read-only")
        if shift != 0:
            diagram = _scaled_back(diagram, sites, shift)
        if weights is not None:
            # The judge reads the weights from the diagram: they are the caller's, whatever the build kept.
            own = np.array(weights, dtype=np.float64, copy=True)
            own.setflags(write=False)
            diagram = replace(diagram, weights=own)
        if radii is not None:
            own = np.array(radii, dtype=np.float64, copy=True)
            own.setflags(write=False)
            diagram = replace(diagram, radii=own)
        return diagram


def _checked_radii(radii: NDArray[np.float64], n: int) -> NDArray[np.float64]:
    """The radii as an (n,) float64 array, refused (``ValueError``) unless finite and >= 0."""
    radii = np.asarray(radii, dtype=np.float64).reshape(-1)
    if radii.shape != (n,):
        raise ValueError(f"radii has shape {radii.shape}, there are {n} sites")
    bad = ~np.isfinite(radii) | (radii < 0)
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        raise ValueError(f"radii must be finite and >= 0: disk {k} has {radii[k]!r}")
    return radii


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
    radii = None if diagram.radii is None else np.ldexp(np.asarray(diagram.radii, dtype=np.float64), -shift)
    return Diagram(own, scale_back_vertices(diagram.vertices, shift), diagram.origin, diagram.twin,
                   diagram.next, diagram.site, weights=diagram.weights, radii=radii)
