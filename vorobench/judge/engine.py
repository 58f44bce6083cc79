"""Cross-validation of one case: build with an implementation, certify it, compare it with a
reference that is certified too, and decide who is wrong.

The engine is :class:`Judge` (and :func:`judge_case` for one case): it builds every
implementation of a case in an isolated worker (:mod:`vorobench.judge.sandbox`) with a timeout and
an optional memory limit, certifies each diagram there, certifies the reference once per case,
and decides each verdict with :func:`decide`. ``vorobench validate``, ``vorobench fuzz``,
witness shrinking and the CI tests go through it; the benchmark worker's check step uses
:func:`decide` on the diagram it timed. Rules:

* A failure of the implementation is its own verdict and nobody else's: ``crashed`` (an
  exception, a signal such as SIGSEGV, or an exit with any status, 0 included), ``timeout``,
  ``oom``, ``mutated_input`` (it changed the sites it was given). An implementation that
  declares it cannot take the sites is ``unsupported``; so is one without weights
  (:data:`NO_WEIGHTS`) on a weighted case, which builds the power diagram of the sites.
* An implementation must certify: exactly if it is exact, within tolerance if it is a
  floating-point library (``Implementation.exact`` is False, e.g. qhull).
* Two exact implementations must agree ``exact``-ly; against a floating-point library,
  ``within_tolerance`` is a pass.
* The reference is not trusted: when the diagrams differ, the certificates decide. If the
  implementation certifies exactly and the reference does not, the difference is the
  reference's failure (a floating-point reference certified within tolerance is then
  "within tolerance"; a reference that does not certify at all fails on its own row).
"""

from __future__ import annotations

import atexit
import multiprocessing as mp
import time
from dataclasses import dataclass, field
from typing import Any, Mapping, Optional, Sequence

import numpy as np
from numpy.typing import ArrayLike

import impls
from impls import DEFAULT_REFERENCE
from impls.base import BuildRaised, InputMutated
from impls.executable.protocol import InvalidOutput
from vorobench.core.diagram import Diagram
from vorobench.core.prepare import prepare, prepare_disks, prepare_weighted
from vorobench.core.scaling import OutsideExactRange, exact_shift, scale_points
from vorobench.judge.certificate import DEFAULT_PROBES, Certificate, certify
from vorobench.judge.comparison import Comparison, compare
from vorobench.judge.disk_judging import certify_disks, compare_disks
from vorobench.judge.declarations import Declaration, declaration_from_data, declaration_of
from vorobench.judge.pinning import declare_in_sandbox
from vorobench.judge.defaults import DEFAULT_TIMEOUT
from vorobench.judge.outcomes import OutcomeKind, Verdict
from vorobench.judge.sandbox import WARMUP_TIMEOUT, Sandbox, safe_message
from vorobench.judge.wire import ArraySpec

__all__ = ["CaseVerdict", "BuildResult", "CaseJudgement", "Judge", "judge_case", "build_only", "certify_result", "build_and_certify", "build_in_sandbox", "diagram_arrays", "diagram_from_arrays", "diagram_schema", "check_case",
           "decide", "agree_exactly", "prepare_case", "prepare_disk_case", "other_attribute", "VERDICTS", "PASSING",
           "FAILURES", "NO_WEIGHTS", "NO_DISKS",
           "DEFAULT_TIMEOUT", "shared_judge", "close_shared_judges"]



#: Every verdict, from best to worst. "certified": no comparison was possible (this is the
#: reference, or the reference crashed) but the implementation certifies.
VERDICTS = tuple(v.value for v in Verdict
                 if v not in (Verdict.NO_REFERENCE, Verdict.SKIPPED, Verdict.CHECK_ERROR))

#: Verdicts that say the implementation produced no diagram it may be judged on.
FAILURES = (Verdict.NOT_CERTIFIED, Verdict.WRONG_SITES, Verdict.INVALID_OUTPUT, Verdict.MUTATED_INPUT, Verdict.OOM, Verdict.TIMEOUT, Verdict.CRASHED)

#: Verdicts that pass (``differs`` passes only when the reference is to blame: see ``passed``).
PASSING = (Verdict.EXACT, Verdict.WITHIN_TOLERANCE, Verdict.CERTIFIED, Verdict.UNSUPPORTED)

#: Why an implementation without ``build_weighted`` is ``unsupported`` on a weighted case.
NO_WEIGHTS = "does not take weights"
_NO_WEIGHTS_REASON = f"{NO_WEIGHTS} (it builds ordinary Voronoi diagrams only)"
#: Why an implementation without ``build_apollonius`` is ``unsupported`` on a case of disks.
NO_DISKS = "does not take disks"
_NO_DISKS_REASON = f"{NO_DISKS} (docs/apollonius.md)"


def prepare_case(points: ArrayLike, weights: Optional[ArrayLike] = None
                 ) -> tuple[np.ndarray, Optional[np.ndarray]]:
    """The sites of a case and their weights (None: an ordinary case): duplicate rows merged,
    the largest weight kept (:func:`~vorobench.core.prepare.prepare_weighted`)."""
    if weights is None:
        return prepare(points)[0], None
    sites, site_weights, _ = prepare_weighted(points, weights)
    return sites, site_weights


def prepare_disk_case(points: ArrayLike, radii: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """The centres and radii of a case of disks: rows with one centre merged, the largest radius
    kept (:func:`~vorobench.core.prepare.prepare_disks`)."""
    sites, site_radii, _ = prepare_disks(points, radii)
    return sites, site_radii


@dataclass
class BuildResult:
    """A diagram built with crash capture, and its certificate."""

    impl: str
    exact: bool
    diagram: Optional[Diagram] = None
    certificate: Optional[Certificate] = None
    error: str = ""
    unsupported: str = ""
    seconds: float = 0.0
    #: The failure verdict when ``error`` is set: "crashed", "timeout", "oom" or "mutated_input".
    failure: str = ""

    @property
    def crashed(self) -> bool:
        return bool(self.error)

    @property
    def certified(self) -> Optional[bool]:
        """Certified by this implementation's standard (exactly, or within tolerance for a
        floating-point library); None if there is no diagram."""
        if self.certificate is None:
            return None
        return self.certificate.ok if self.exact else self.certificate.ok_within_tolerance

    @property
    def certified_exactly(self) -> Optional[bool]:
        return None if self.certificate is None else self.certificate.ok

    @property
    def level(self) -> str:
        """The certificate's level (``CertificateLevel``), or "" if there is no diagram."""
        return "" if self.certificate is None else self.certificate.level.value


def declined_reason(impl: impls.Implementation, sites: np.ndarray) -> Optional[str]:
    """Why ``impl`` declines ``sites``: its ``supports`` (on the sites, and on the scaled sites it
    would be given), or sites that no power of two brings into the exact range. Nothing else
    declines a case."""
    try:
        shift = exact_shift(sites)
    except OutsideExactRange as exc:        # vorobench's own range: no implementation code has run
        return str(exc)
    reason = impl.unsupported_reason(sites)
    if reason is None and shift != 0:
        reason = impl.unsupported_reason(scale_points(sites, shift))
    return reason


def build_only(impl_name: str, sites: np.ndarray, weights: Optional[np.ndarray] = None,
               radii: Optional[np.ndarray] = None) -> BuildResult:
    """Build prepared ``sites`` with ``impl_name`` in this process; every failure is recorded in
    the result, not raised. No certificate yet: that is the judge's, outside the implementation's
    process. ``weights`` (one per site) asks for the power diagram; an implementation that
    does not take weights is ``unsupported`` (:data:`NO_WEIGHTS`); ``radii`` asks for the diagram
    of disks, the same way (:data:`NO_DISKS`). Only ``supports`` declines
    sites: an exception of any class raised inside the build is a crash."""
    try:
        impl = impls.get(impl_name)
    except Exception as exc:  # unknown or broken plugin: recorded like a crash
        return BuildResult(impl_name, True, error=safe_message(exc), failure=Verdict.CRASHED)
    result = BuildResult(impl_name, bool(impl.exact))
    if weights is not None and not impl.weighted:
        result.unsupported = _NO_WEIGHTS_REASON
        return result
    if radii is not None and not impl.apollonius:
        result.unsupported = _NO_DISKS_REASON
        return result
    try:
        reason = declined_reason(impl, sites)
    except Exception as exc:  # a supports() that raises is the implementation's crash
        result.error, result.failure = f"supports() raised {safe_message(exc)}", Verdict.CRASHED
        return result
    if reason:
        result.unsupported = reason
        return result
    t0 = time.perf_counter_ns()
    try:
        result.diagram = impl.run(sites, None, check_supports=False, weights=weights, radii=radii,
                                  wrap_build_errors=True)
        if type(result.diagram) is not Diagram:
            raise TypeError(f"build returned {type(result.diagram).__name__}, not a Diagram")
    except BuildRaised as exc:              # whatever the class, raised by the build: a crash
        cause = exc.__cause__ or exc
        # An executable's answer that the protocol refuses (raised by vorobench's reader, not the program).
        failure = Verdict.INVALID_OUTPUT if isinstance(cause, InvalidOutput) else Verdict.CRASHED
        result.diagram, result.error, result.failure = None, safe_message(cause), failure
    except InputMutated as exc:
        result.diagram, result.error, result.failure = None, str(exc), Verdict.MUTATED_INPUT
    except OutsideExactRange as exc:        # the diagram's vertices have no float representation
        result.diagram, result.unsupported = None, str(exc)
    except MemoryError as exc:
        result.diagram, result.error, result.failure = None, f"MemoryError: {exc}", Verdict.OOM
    except Exception as exc:  # a broken contract after the build (counters, weights): its crash
        result.diagram, result.error, result.failure = None, safe_message(exc), Verdict.CRASHED
    result.seconds = (time.perf_counter_ns() - t0) / 1e9
    return result


def certify_result(result: BuildResult, sites: np.ndarray, *, probes: int = DEFAULT_PROBES,
                   seed: int = 0, weights: Optional[np.ndarray] = None,
                   radii: Optional[np.ndarray] = None) -> BuildResult:
    """Certify ``result``'s diagram, which must be the diagram of exactly ``sites`` (with
    exactly ``weights`` or ``radii``, or neither): a diagram of other sites (moved, dropped,
    relabelled), other weights or other radii is a failure, however well it certifies."""
    d = result.diagram
    if d is None:
        return result
    if not (d.sites.shape == sites.shape and np.array_equal(d.sites, sites)):
        result.diagram, result.failure = None, Verdict.WRONG_SITES
        result.error = ("returned the diagram of other sites: "
                        + (f"{d.sites.shape[0]} sites for the {sites.shape[0]} it was given"
                           if d.sites.shape != sites.shape else "some of them moved"))
        return result
    for name, wanted in (("weights", weights), ("radii", radii)):
        problem = other_attribute(d, name, wanted)
        if problem:
            result.diagram, result.failure, result.error = None, Verdict.WRONG_SITES, problem
            return result
    try:
        result.certificate = certify_disks(d) if radii is not None else certify(d, probes=probes, seed=seed)
    except Exception as exc:  # a diagram the certifier cannot even read certifies nothing
        result.diagram, result.failure = None, Verdict.NOT_CERTIFIED
        result.error = f"the certifier could not read the diagram: {type(exc).__name__}: {exc}"
    return result


#: What a diagram is that lacks the case's weights or radii, or has them for a case without.
_ATTRIBUTE_TEXTS = {"weights": ("an ordinary diagram for weighted sites", "a power diagram for unweighted sites"),
                    "radii": ("a diagram of points for disks", "a diagram of disks for points")}


def other_attribute(d: Diagram, name: str, wanted: Optional[np.ndarray]) -> str:
    """Why diagram ``d``'s ``name`` ("weights" or "radii") are not exactly those of the case
    (``wanted``; None: the case has none), or "" if they are. Shared by :func:`certify_result`
    and the bench's judge of every repeat."""
    missing, extra = _ATTRIBUTE_TEXTS[name]
    given = getattr(d, name)
    got = None if given is None else np.asarray(given)
    if got is None and wanted is None:
        return ""
    if got is None:
        return f"returned {missing}"
    if wanted is None:
        return f"returned {extra}"
    return "" if got.shape == wanted.shape and np.array_equal(got, wanted) else f"returned the diagram of other {name}"


def build_and_certify(impl_name: str, sites: ArrayLike, *, probes: int = DEFAULT_PROBES, seed: int = 0,
                      weights: Optional[ArrayLike] = None, radii: Optional[ArrayLike] = None) -> BuildResult:
    """Build ``sites`` (with ``weights``: the power diagram; with ``radii``: the diagram of
    disks) with ``impl_name`` in this process and certify the result. Call it directly only where
    a hard crash of the implementation may take the calling process down; :class:`Judge`
    isolates the build."""
    if radii is not None:
        sites, radii = prepare_disk_case(sites, radii)
    else:
        sites, weights = prepare_case(sites, weights)
    return certify_result(build_only(impl_name, sites, weights, radii), sites, probes=probes, seed=seed,
                          weights=weights, radii=radii)


_DIAGRAM_FIELDS = ("sites", "vertices", "origin", "twin", "next", "site")


def diagram_arrays(d: Diagram) -> dict[str, np.ndarray]:
    """The DCEL's arrays by field name, and ``weights`` for a power diagram: what a sandbox
    sends instead of an object."""
    arrays = {f: np.asarray(getattr(d, f)) for f in _DIAGRAM_FIELDS}
    if d.weights is not None:
        arrays["weights"] = np.asarray(d.weights)
    if d.radii is not None:
        arrays["radii"] = np.asarray(d.radii)
    return arrays


def diagram_from_arrays(arrays: dict[str, np.ndarray]) -> Diagram:
    """A :class:`Diagram` of the judge's own class from arrays a sandbox sent (a power
    diagram when they hold ``weights``)."""
    return Diagram(*(arrays[f] for f in _DIAGRAM_FIELDS), weights=arrays.get("weights"), radii=arrays.get("radii"))


def diagram_schema(n_sites: int, weighted: bool = False, disks: bool = False) -> dict[str, ArraySpec]:
    """What the arrays of a diagram of ``n_sites`` sites may be on the wire: a Voronoi diagram
    of n sites has at most 2n - 5 vertices and 3n - 6 edges; a power diagram fewer (hidden
    sites); a diagram of n disks at most 2n - 2 vertices and 3n - 3 edges: two cells may share
    several edges, but every vertex still has degree 3 or more (zero-length edges included) and
    the k visible cells are the faces of a connected plane graph with one vertex at infinity, so
    V - E + k = 1 and 2E >= 3V give V <= 2k - 2 and E <= 3k - 3. Twice that (and a constant) leaves
    room for any honest layout and still bounds what the judge allocates."""
    n = max(int(n_sites), 0)
    ints = ("<i4", "<i8")
    half_edges = 12 * n + 32
    schema = {"sites": ArraySpec(("<f8",), (n, 2)), "vertices": ArraySpec(("<f8",), (4 * n + 16, 2)),
              "origin": ArraySpec(ints, (half_edges,)), "twin": ArraySpec(ints, (half_edges,)),
              "next": ArraySpec(ints, (half_edges,)), "site": ArraySpec(ints, (half_edges,))}
    if weighted:
        schema["weights"] = ArraySpec(("<f8",), (n,))
    if disks:
        schema["radii"] = ArraySpec(("<f8",), (n,))
    return schema


def build_in_sandbox(impl_name: str, sites: np.ndarray, weights: Optional[np.ndarray] = None,
                     radii: Optional[np.ndarray] = None) -> tuple[dict, dict]:
    """Runs in a sandbox: :func:`build_only` as plain data and arrays (nothing to unpickle)."""
    res = build_only(impl_name, sites, weights, radii)
    data = {"error": res.error, "unsupported": res.unsupported, "seconds": res.seconds,
            "failure": res.failure, "has_diagram": res.diagram is not None}
    arrays = diagram_arrays(res.diagram) if res.diagram is not None else None
    return data, arrays


_FAILURE_KINDS = (Verdict.CRASHED, Verdict.OOM, Verdict.MUTATED_INPUT, Verdict.INVALID_OUTPUT)


def _result_from_sandbox(impl_name: str, exact: bool, data: Any, arrays: dict) -> BuildResult:
    """A :class:`BuildResult` rebuilt in the judge from what a sandbox sent, held to the
    standard pinned for the run (``exact``), whatever the sandbox says of itself."""
    if not isinstance(data, dict):
        return BuildResult(impl_name, exact, error="answered no build record", failure=Verdict.CRASHED)
    text = {key: data.get(key) if isinstance(data.get(key), str) else "" for key in ("error", "unsupported", "failure")}
    seconds = data.get("seconds")
    failure = (Verdict(text["failure"]) if text["failure"] in _FAILURE_KINDS
               else Verdict.CRASHED if text["error"] else "")
    res = BuildResult(impl_name, exact, error=text["error"], unsupported=text["unsupported"],
                      seconds=float(seconds) if type(seconds) in (int, float) else 0.0, failure=failure)
    if res.failure and not res.error:
        res.error = "failed without saying why"
    if res.error or res.unsupported:
        res.diagram = None
    elif data.get("has_diagram") is True:
        try:
            res.diagram = diagram_from_arrays(arrays)
        except Exception as exc:  # arrays of the wrong kind or shape
            res.error, res.failure = f"returned an unreadable diagram: {type(exc).__name__}: {exc}", Verdict.CRASHED
    else:
        res.error, res.failure = "returned neither a diagram nor a reason", Verdict.CRASHED
    return res


@dataclass
class CaseVerdict:
    """The outcome of one implementation on one point set, judged against the reference."""

    impl: str
    reference: str
    verdict: str
    passed: bool
    certified: Optional[bool]
    reference_certified: Optional[bool]
    message: str
    #: Who is wrong: "impl", "reference", "unknown" (both certify, yet they differ) or "" (nobody).
    blame: str = ""
    n_sites: int = 0
    seconds: float = 0.0
    result: Optional[BuildResult] = field(default=None, repr=False)
    reference_result: Optional[BuildResult] = field(default=None, repr=False)
    comparison: Optional[Comparison] = field(default=None, repr=False)

    @property
    def certificate_level(self) -> str:
        """This diagram's certificate level (``CertificateLevel``), "" without a diagram."""
        return self.result.level if self.result is not None else ""

    @property
    def reference_certificate_level(self) -> str:
        return self.reference_result.level if self.reference_result is not None else ""

    def to_dict(self, *, details: bool = True) -> dict[str, Any]:
        """JSON-serialisable summary; with ``details``, the certificates and comparison too."""
        out: dict[str, Any] = {k: getattr(self, k) for k in (
            "impl", "reference", "verdict", "passed", "certified", "reference_certified", "certificate_level",
            "reference_certificate_level", "message", "blame", "n_sites", "seconds")}
        if details:
            for key, res in (("certificate", self.result), ("reference_certificate", self.reference_result)):
                if res is not None and res.certificate is not None:
                    out[key] = res.certificate.to_dict()
            if self.result is not None and self.result.error:
                out["error"] = self.result.error
            if self.comparison is not None:
                comp = self.comparison.to_dict()
                comp.pop("highlight_a", None)
                comp.pop("highlight_b", None)
                out["comparison"] = comp
        return out


def _failed_checks(res: BuildResult) -> str:
    cert = res.certificate
    if cert is None:
        return ""
    bad = [c for c in cert.checks if not (c.ok if res.exact else c.within_tolerance)]
    return "; ".join(f"{c.name}: {c.detail}" for c in bad)


def check_case(impl_name: str, sites: ArrayLike, reference_diagram: Optional[Diagram] = None,
               reference_certificate: Optional[Certificate] = None, *, reference: str = DEFAULT_REFERENCE,
               reference_result: Optional[BuildResult] = None, probes: int = DEFAULT_PROBES,
               seed: int = 0, judge: Optional["Judge"] = None, weights: Optional[ArrayLike] = None,
               radii: Optional[ArrayLike] = None) -> CaseVerdict:
    """Build, certify and compare ``impl_name`` on ``sites`` (with ``weights``: their power
    diagram; with ``radii``: the diagram of disks) against ``reference``.

    Builds go through ``judge`` (isolated workers) when given, else run in this process. The
    reference is built and certified here unless given (as ``reference_result``, or as a
    diagram with an optional certificate), so that a runner can reuse one reference for
    several implementations.
    """
    t0 = time.perf_counter_ns()
    if radii is not None:
        sites, radii = prepare_disk_case(sites, radii)
    else:
        sites, weights = prepare_case(sites, weights)
    judge = judge or Judge(isolate=False, reference=reference, probes=probes, seed=seed)
    if impl_name == reference and reference_result is not None:
        res = reference_result                    # the reference's own row: judged on its certificate
    else:
        res = judge.build(impl_name, sites, weights=weights, radii=radii)
    if reference_result is None:
        if reference_diagram is not None:
            cert = reference_certificate or (certify_disks(reference_diagram) if radii is not None else
                                             certify(reference_diagram, probes=probes, seed=seed))
            declared = judge.declaration(reference)
            reference_result = BuildResult(reference, declared.exact if declared else True, reference_diagram, cert)
        elif impl_name == reference:
            reference_result = res
        else:
            reference_result = judge.build(reference, sites, weights=weights, radii=radii)
    verdict = decide(impl_name, reference, res, reference_result)
    verdict.n_sites = int(sites.shape[0])
    verdict.seconds = (time.perf_counter_ns() - t0) / 1e9
    return verdict


def decide(impl_name: str, reference: str, res: BuildResult, ref: BuildResult) -> CaseVerdict:
    """The verdict of ``res`` (``impl_name``'s build and certificate) against the reference's
    ``ref``, by the rules of this module; ``res is ref`` judges the reference's own row."""
    def make(verdict: str, passed: bool, message: str, blame: str = "", comparison: Optional[Comparison] = None):
        return CaseVerdict(impl_name, reference, verdict, passed, res.certified, ref.certified, message, blame,
                           result=res, reference_result=ref, comparison=comparison)

    if res.unsupported:
        if res.unsupported.startswith((NO_WEIGHTS, NO_DISKS)):
            return make(Verdict.UNSUPPORTED, True, f"{impl_name} {res.unsupported}")
        return make(Verdict.UNSUPPORTED, True, f"{impl_name} does not support these sites: {res.unsupported}")
    if res.crashed:
        kind = res.failure or Verdict.CRASHED
        what = {Verdict.CRASHED: "crashed", Verdict.TIMEOUT: "timed out", Verdict.OOM: "ran out of memory",
                Verdict.MUTATED_INPUT: "changed its input", Verdict.WRONG_SITES: "failed",
                Verdict.INVALID_OUTPUT: "printed an answer the protocol refuses",
                Verdict.NOT_CERTIFIED: "failed"}.get(kind, kind)
        return make(kind, False, f"{impl_name} {what}: {res.error}", "impl")
    standard = "exactly" if res.exact else "within tolerance (floating point)"
    if not res.certified:
        return make(Verdict.NOT_CERTIFIED, False, f"{impl_name} is not certified: {_failed_checks(res)}", "impl")
    cert_note = "certified" if res.certificate.ok else "certified within tolerance (floating point)"
    # Judged on its certificate alone: the certificate's level is the verdict.
    alone = Verdict.CERTIFIED if res.certificate.ok else Verdict.WITHIN_TOLERANCE
    if res is ref or impl_name == reference:
        return make(alone, True, f"{impl_name} (the reference) is {cert_note}")
    if ref.diagram is None:
        why = ref.error or ref.unsupported or "no diagram"
        return make(alone, True, f"{impl_name} is {cert_note}; no comparison: reference {reference} "
                                       f"has no diagram ({why})", "reference" if ref.crashed else "")
    try:
        comp = _compare(ref.diagram, res.diagram, (reference, impl_name))
    except Exception as exc:  # a diagram the comparer cannot read is no pass
        return make(Verdict.DIFFERS, False, f"{impl_name} could not be compared with {reference}: "
                                      f"{type(exc).__name__}: {exc}", "impl")
    both_exact = res.exact and ref.exact
    if comp.equal and (comp.verdict == Verdict.EXACT or not both_exact):
        note = "" if comp.verdict == Verdict.EXACT else f" (within tolerance: {reference if not ref.exact else impl_name} " \
                                                     f"is floating point; that is a pass)"
        return make(comp.verdict, True, f"{impl_name} agrees with {reference}: {comp.verdict}{note}; {cert_note}",
                    comparison=comp)
    if comp.equal:  # two exact implementations agreeing only within tolerance
        return make(Verdict.DIFFERS, False, f"{impl_name} and {reference} are both exact but agree only within "
                                      f"tolerance: exact implementations must agree exactly", "impl", comp)
    impl_exactly = bool(res.certified_exactly)
    ref_exactly = bool(ref.certified_exactly)
    if impl_exactly and not ref_exactly:
        if ref.certified:  # a floating-point reference, certified within tolerance only
            return make(Verdict.WITHIN_TOLERANCE, True,
                        f"{impl_name} differs from {reference}, but {impl_name} is certified exactly and "
                        f"{reference} (floating point) only within tolerance ({_failed_near(ref)}): the difference "
                        f"is the reference's rounding", comparison=comp)
        return make(Verdict.DIFFERS, True, f"{impl_name} differs from {reference}; {impl_name} is certified, "
                                     f"{reference} is NOT: the reference is wrong ({_failed_checks(ref)})",
                    "reference", comp)
    who = f"{impl_name} certified {'exactly' if impl_exactly else standard}; " \
          f"{reference} certified {'exactly' if ref_exactly else 'within tolerance' if ref.certified else 'NOT'}"
    blame = "unknown" if impl_exactly and ref_exactly else "impl"
    return make(Verdict.DIFFERS, False, f"{impl_name} differs from {reference} ({comp.n_differences} differences; {who})",
                blame, comp)


def _compare(first: Diagram, second: Diagram, labels: tuple[str, str]) -> Any:
    """The comparison of two diagrams of the same sites: of disks (:func:`compare_disks`) when
    either has radii, else the general one."""
    if first.radii is not None or second.radii is not None:
        return compare_disks(first, second)
    return compare(first, second, labels=labels)


def _failed_near(res: BuildResult) -> str:
    cert = res.certificate
    return ", ".join(f"{c.name}: {c.detail}" for c in cert.checks if not c.ok) if cert else ""


def agree_exactly(first: BuildResult, second: BuildResult) -> CaseVerdict:
    """Two exact implementations on the same sites must give the same diagram after exact
    normalisation only (verdict ``exact``); anything else fails. Crashes and missing
    diagrams are judged on their own rows, so they pass here."""
    a, b = first.impl, second.impl
    if first.diagram is None or second.diagram is None:
        return CaseVerdict(b, a, Verdict.UNSUPPORTED, True, second.certified, first.certified,
                           f"no comparison of {a} and {b}: a diagram is missing", result=second, reference_result=first)
    try:
        comp = _compare(first.diagram, second.diagram, (a, b))
    except Exception as exc:  # a diagram the comparer cannot read is no pass
        return CaseVerdict(b, a, Verdict.DIFFERS, False, second.certified, first.certified,
                           f"{a} and {b} could not be compared: {type(exc).__name__}: {exc}", "impl",
                           result=second, reference_result=first)
    if comp.equal and comp.verdict == Verdict.EXACT:
        return CaseVerdict(b, a, Verdict.EXACT, True, second.certified, first.certified,
                           f"exact implementations {a} and {b} agree exactly", result=second, reference_result=first,
                           comparison=comp)
    blame = "impl" if not second.certified else "reference" if not first.certified else "unknown"
    return CaseVerdict(b, a, Verdict.DIFFERS, False, second.certified, first.certified,
                       f"exact implementations {a} and {b} disagree ({comp.verdict}, {comp.n_differences} differences): "
                       f"they must agree exactly", blame, result=second, reference_result=first, comparison=comp)


# ---------------------------------------------------------------------------- the engine

@dataclass
class CaseJudgement:
    """Every verdict of one case: ``rows`` holds (implementation, verdict, exact peer or None);
    the reference's own row comes first. ``weights``: the sites' weights (None: ordinary)."""

    sites: np.ndarray
    rows: list[tuple[str, CaseVerdict, Optional[str]]]
    weights: Optional[np.ndarray] = None
    radii: Optional[np.ndarray] = None

    @property
    def passed(self) -> bool:
        return all(v.passed for _, v, _ in self.rows)


class Judge:
    """The judging engine: builds and certifies each implementation in an isolated sandbox
    (timeout, memory limit, crash containment), the reference once per case, and decides.

    What each implementation declares (``exact``, ``weighted``, ...) is read once, in a sandbox,
    and pinned for the judge's life (:meth:`declarations`); ``declarations`` gives them pinned
    already (a run that read them up front). ``isolate=False`` runs the builds in this process
    (for callers that are themselves a disposable worker, or that imported the implementations
    themselves). Use as a context manager, or call :meth:`close`, to end the sandboxes.
    """

    def __init__(self, names: Sequence[str] = (), reference: str = DEFAULT_REFERENCE, *,
                 probes: int = DEFAULT_PROBES, seed: int = 0, timeout: float = DEFAULT_TIMEOUT,
                 warmup_timeout: Optional[float] = None, memory_limit_mb: Optional[float] = None,
                 plugins: Sequence[str] = (), isolate: bool = True,
                 declarations: Optional[Mapping[str, Declaration]] = None) -> None:
        self.names = list(dict.fromkeys(names))
        self.reference = reference
        self.probes = probes
        self.seed = seed
        self.timeout = timeout
        self.warmup_timeout = max(WARMUP_TIMEOUT if warmup_timeout is None else warmup_timeout, timeout)
        self.memory_limit_mb = memory_limit_mb
        self.plugins = tuple(plugins)
        self.isolate = isolate
        self._sandboxes: dict = {}
        self._declared: dict[str, Declaration] = dict(declarations or {})
        self._undeclared: dict[str, str] = {}

    def declarations(self, names: Optional[Sequence[str]] = None) -> dict[str, Declaration]:
        """The pinned declarations of ``names`` (default: this judge's and its reference), read
        in one sandbox the first time they are asked for; one that cannot be read is left out
        (:meth:`why_undeclared` says why)."""
        names = list(dict.fromkeys(self.names + [self.reference] if names is None else names))
        wanted = [n for n in names if n not in self._declared and n not in self._undeclared]
        if wanted:
            if self.isolate:
                _, declared, failed = declare_in_sandbox(wanted, self.plugins, timeout=self.warmup_timeout)
            else:
                declared, failed = {}, {}
                for name in wanted:
                    try:
                        declared[name] = declaration_from_data(declaration_of(impls.get(name)), name)
                    except Exception as exc:  # unknown or broken: its builds say why
                        failed[name] = safe_message(exc)
            self._declared.update(declared)
            self._undeclared.update({n: failed.get(n) or failed.get("*") or "declared nothing"
                                     for n in wanted if n not in declared})
        return {n: self._declared[n] for n in names if n in self._declared}

    def declaration(self, name: str) -> Optional[Declaration]:
        """``name``'s pinned declaration (None: it could not be read); the first miss reads the
        judge's whole set in one sandbox."""
        if name not in self._declared and name not in self._undeclared:
            self.declarations(self.names + [self.reference, name])
        return self._declared.get(name)

    def why_undeclared(self, name: str) -> str:
        """Why ``name`` has no declaration ("" if it has one)."""
        self.declarations([name])
        return self._undeclared.get(name, "")

    def __enter__(self) -> "Judge":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        for box in self._sandboxes.values():
            box.close()
        self._sandboxes.clear()

    def build(self, name: str, sites: np.ndarray, *, probes: Optional[int] = None,
              weights: Optional[np.ndarray] = None, radii: Optional[np.ndarray] = None) -> BuildResult:
        """``name``'s diagram of prepared ``sites`` (with ``weights``, one per site: the power
        diagram; with ``radii``: the diagram of disks) with its certificate; any failure is in
        the result."""
        probes = self.probes if probes is None else probes
        declared = self.declaration(name)
        if declared is None:
            return BuildResult(name, True, error=f"{name} could not be loaded: {self.why_undeclared(name)}",
                               failure=Verdict.CRASHED)
        if not self.isolate:
            res = build_and_certify(name, sites, probes=probes, seed=self.seed, weights=weights, radii=radii)
            res.exact = declared.exact
            return res
        if weights is not None and not declared.weighted:
            return BuildResult(name, declared.exact, unsupported=_NO_WEIGHTS_REASON)
        if radii is not None and not declared.apollonius:
            return BuildResult(name, declared.exact, unsupported=_NO_DISKS_REASON)

        box = self._sandboxes.get(name)
        if box is None:
            # Only the plugin that defines it: no other plugin's import-time code runs beside its builds.
            box = self._sandboxes[name] = Sandbox(name, plugins=(declared.plugin,) if declared.plugin else (),
                                                  memory_limit_mb=self.memory_limit_mb,
                                                  warmup_timeout=self.warmup_timeout, expected=declared)
        t0 = time.perf_counter_ns()
        outcome = box.call(build_in_sandbox, name, sites, weights, radii, timeout=self.timeout, step="build",
                           schema=diagram_schema(sites.shape[0], weights is not None, radii is not None))
        if outcome.ok:
            return certify_result(_result_from_sandbox(name, declared.exact, *outcome.value), sites, probes=probes,
                                  seed=self.seed, weights=weights, radii=radii)
        # An exception in the sandbox is the build's crash; timeout, oom and crashed are verdicts as they are.
        failure = Verdict.CRASHED if outcome.kind == OutcomeKind.ERROR else Verdict(outcome.kind)
        return BuildResult(name, declared.exact, error=outcome.message, failure=failure,
                           seconds=(time.perf_counter_ns() - t0) / 1e9)

    def judge(self, sites: ArrayLike, names: Optional[Sequence[str]] = None, *,
              weights: Optional[ArrayLike] = None, radii: Optional[ArrayLike] = None) -> CaseJudgement:
        """Every implementation on ``sites`` (with ``weights``, one per point: the power
        diagram; with ``radii``: the diagram of disks): the reference's own row first, then
        each against the reference, and each exact one also against the first exact one
        (exactly)."""
        if radii is not None:
            sites, radii = prepare_disk_case(sites, radii)
        else:
            sites, weights = prepare_case(sites, weights)
        names = list(dict.fromkeys(names if names is not None else self.names))
        reference = self.reference
        t0 = time.perf_counter_ns()
        ref = self.build(reference, sites, weights=weights, radii=radii)
        rows: list[tuple[str, CaseVerdict, Optional[str]]] = []
        anchor: Optional[BuildResult] = None
        for name in [reference] + [n for n in names if n != reference]:
            started = time.perf_counter_ns()
            res = ref if name == reference else self.build(name, sites, weights=weights, radii=radii)
            verdict = decide(name, reference, res, ref)
            verdict.n_sites = int(sites.shape[0])
            verdict.seconds = ((time.perf_counter_ns() - (t0 if name == reference else started)) / 1e9)
            rows.append((name, verdict, None))
            if res.exact and res.diagram is not None and name != reference:
                if anchor is None:
                    anchor = res
                else:
                    rows.append((name, agree_exactly(anchor, res), anchor.impl))
        return CaseJudgement(sites, rows, weights, radii)


def judge_case(sites: ArrayLike, names: Sequence[str], reference: str = DEFAULT_REFERENCE, *,
               weights: Optional[ArrayLike] = None, radii: Optional[ArrayLike] = None, **options: Any) -> CaseJudgement:
    """One case (with ``weights``: the power diagram; with ``radii``: the diagram of disks)
    through a fresh :class:`Judge` (``options`` as for Judge), its sandboxes closed after."""
    with Judge(names, reference, **options) as judge:
        return judge.judge(sites, weights=weights, radii=radii)


#: Judges kept for the life of this process (a pool worker judges many cases), one per setup.
_SHARED: dict[tuple, Judge] = {}


def shared_judge(names: Sequence[str], reference: str = DEFAULT_REFERENCE, **options: Any) -> Judge:
    """A :class:`Judge` kept in this process for these names and options, so that its sandboxes
    serve every case a worker gets. A daemonic process (a Dask worker) may not start processes:
    there the builds run in the process itself, and the executor's retry-then-lost rule covers
    a worker that dies."""
    key = (tuple(names), reference, tuple(sorted(options.items())))
    judge = _SHARED.get(key)
    if judge is None:
        options.setdefault("isolate", not mp.current_process().daemon)
        judge = _SHARED[key] = Judge(names, reference, **options)
    return judge


@atexit.register
def close_shared_judges() -> None:
    """End the sandboxes of every shared judge."""
    for judge in _SHARED.values():
        judge.close()
    _SHARED.clear()
