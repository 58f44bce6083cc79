"""Cross-validation of one case: build with an implementation, certify it, compare it with a
reference that is certified too, and decide who is wrong.

Used by ``vorobench validate``, by the benchmark runner and by the CI gate. Rules:

* A crash (any exception) of the implementation is the verdict ``crashed``; an
  implementation that declares it cannot take the sites is ``unsupported``.
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

import time
import traceback
from dataclasses import dataclass, field
from typing import Any, Optional

import numpy as np
from numpy.typing import ArrayLike

from vorobench.certify import DEFAULT_PROBES, Certificate, certify
from vorobench.compare import Comparison, compare
from vorobench.diagram import Diagram
from vorobench.prepare import prepare

__all__ = ["CaseVerdict", "BuildResult", "build_and_certify", "check_case", "agree_exactly", "VERDICTS", "PASSING",
           "DEFAULT_REFERENCE"]

DEFAULT_REFERENCE = "qhull"

#: Every verdict, from best to worst. "certified": no comparison was possible (this is the
#: reference, or the reference crashed) but the implementation certifies.
VERDICTS = ("exact", "within_tolerance", "certified", "unsupported", "differs", "not_certified", "crashed")

#: Verdicts that pass (``differs`` passes only when the reference is to blame: see ``passed``).
PASSING = ("exact", "within_tolerance", "certified", "unsupported")


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


def build_and_certify(impl_name: str, sites: ArrayLike, *, probes: int = DEFAULT_PROBES, seed: int = 0) -> BuildResult:
    """Build ``sites`` with ``impl_name`` in this process (an exception is recorded, not raised)
    and certify the result."""
    import impls

    sites, _ = prepare(sites)
    try:
        impl = impls.get(impl_name)
    except Exception as exc:  # unknown or broken plugin: recorded like a crash
        return BuildResult(impl_name, True, error=f"{type(exc).__name__}: {exc}")
    result = BuildResult(impl_name, bool(impl.exact))
    if impl.supports is not None:
        reason = impl.supports(sites)
        if reason:
            result.unsupported = str(reason)
            return result
    t0 = time.perf_counter_ns()
    try:
        result.diagram = impl.build(sites, None)
        if not isinstance(result.diagram, Diagram):
            raise TypeError(f"build returned {type(result.diagram).__name__}, not a Diagram")
    except Exception as exc:  # any failure inside the implementation is its crash
        frames = traceback.extract_tb(exc.__traceback__)
        where = f" at {frames[-1].filename}:{frames[-1].lineno}" if frames else ""
        result.diagram = None
        result.error = f"{type(exc).__name__}: {exc}{where}"
    result.seconds = (time.perf_counter_ns() - t0) / 1e9
    if result.diagram is not None:
        result.certificate = certify(result.diagram, probes=probes, seed=seed)
    return result


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

    def to_dict(self, *, details: bool = True) -> dict[str, Any]:
        """JSON-serialisable summary; with ``details``, the certificates and comparison too."""
        out: dict[str, Any] = {k: getattr(self, k) for k in (
            "impl", "reference", "verdict", "passed", "certified", "reference_certified", "message", "blame",
            "n_sites", "seconds")}
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
               seed: int = 0) -> CaseVerdict:
    """Build, certify and compare ``impl_name`` on ``sites`` against ``reference``.

    The reference is built and certified here unless given (as ``reference_result``, or as a
    diagram with an optional certificate), so that a runner can reuse one reference for
    several implementations.
    """
    t0 = time.perf_counter_ns()
    sites, _ = prepare(sites)
    if impl_name == reference and reference_result is not None:
        res = reference_result                    # the reference's own row: judged on its certificate
    else:
        res = build_and_certify(impl_name, sites, probes=probes, seed=seed)
    if reference_result is None:
        if reference_diagram is not None:
            ref_exact = _is_exact(reference)
            cert = reference_certificate or certify(reference_diagram, probes=probes, seed=seed)
            reference_result = BuildResult(reference, ref_exact, reference_diagram, cert)
        elif impl_name == reference:
            reference_result = res
        else:
            reference_result = build_and_certify(reference, sites, probes=probes, seed=seed)
    ref = reference_result
    verdict = _decide(impl_name, reference, res, ref)
    verdict.n_sites = int(sites.shape[0])
    verdict.seconds = (time.perf_counter_ns() - t0) / 1e9
    return verdict


def _is_exact(name: str) -> bool:
    import impls

    try:
        return bool(impls.get(name).exact)
    except Exception:  # an unknown reference is judged strictly
        return True


def _decide(impl_name: str, reference: str, res: BuildResult, ref: BuildResult) -> CaseVerdict:
    def make(verdict: str, passed: bool, message: str, blame: str = "", comparison: Optional[Comparison] = None):
        return CaseVerdict(impl_name, reference, verdict, passed, res.certified, ref.certified, message, blame,
                           result=res, reference_result=ref, comparison=comparison)

    if res.unsupported:
        return make("unsupported", True, f"{impl_name} does not support these sites: {res.unsupported}")
    if res.crashed:
        return make("crashed", False, f"{impl_name} crashed: {res.error}", "impl")
    standard = "exactly" if res.exact else "within tolerance (floating point)"
    if not res.certified:
        return make("not_certified", False, f"{impl_name} is not certified: {_failed_checks(res)}", "impl")
    cert_note = "certified" if res.certificate.ok else "certified within tolerance (floating point)"
    if res is ref or impl_name == reference:
        return make("certified", True, f"{impl_name} (the reference) is {cert_note}")
    if ref.diagram is None:
        why = ref.error or ref.unsupported or "no diagram"
        return make("certified", True, f"{impl_name} is {cert_note}; no comparison: reference {reference} "
                                       f"has no diagram ({why})", "reference" if ref.crashed else "")
    comp = compare(ref.diagram, res.diagram, labels=(reference, impl_name))
    both_exact = res.exact and ref.exact
    if comp.equal and (comp.verdict == "exact" or not both_exact):
        note = "" if comp.verdict == "exact" else f" (within tolerance: {reference if not ref.exact else impl_name} " \
                                                     f"is floating point; that is a pass)"
        return make(comp.verdict, True, f"{impl_name} agrees with {reference}: {comp.verdict}{note}; {cert_note}",
                    comparison=comp)
    if comp.equal:  # two exact implementations agreeing only within tolerance
        return make("differs", False, f"{impl_name} and {reference} are both exact but agree only within "
                                      f"tolerance: exact implementations must agree exactly", "impl", comp)
    impl_exactly = bool(res.certified_exactly)
    ref_exactly = bool(ref.certified_exactly)
    if impl_exactly and not ref_exactly:
        if ref.certified:  # a floating-point reference, certified within tolerance only
            return make("within_tolerance", True,
                        f"{impl_name} differs from {reference}, but {impl_name} is certified exactly and "
                        f"{reference} (floating point) only within tolerance ({_failed_near(ref)}): the difference "
                        f"is the reference's rounding", comparison=comp)
        return make("differs", True, f"{impl_name} differs from {reference}; {impl_name} is certified, "
                                     f"{reference} is NOT: the reference is wrong ({_failed_checks(ref)})",
                    "reference", comp)
    who = f"{impl_name} certified {'exactly' if impl_exactly else standard}; " \
          f"{reference} certified {'exactly' if ref_exactly else 'within tolerance' if ref.certified else 'NOT'}"
    blame = "unknown" if impl_exactly and ref_exactly else "impl"
    return make("differs", False, f"{impl_name} differs from {reference} ({comp.n_differences} differences; {who})",
                blame, comp)


def _failed_near(res: BuildResult) -> str:
    cert = res.certificate
    return ", ".join(f"{c.name}: {c.detail}" for c in cert.checks if not c.ok) if cert else ""


def agree_exactly(first: BuildResult, second: BuildResult) -> CaseVerdict:
    """Two exact implementations on the same sites must give the same diagram after exact
    normalisation only (verdict ``exact``); anything else fails. Crashes and missing
    diagrams are judged on their own rows, so they pass here."""
    a, b = first.impl, second.impl
    if first.diagram is None or second.diagram is None:
        return CaseVerdict(b, a, "unsupported", True, second.certified, first.certified,
                           f"no comparison of {a} and {b}: a diagram is missing", result=second, reference_result=first)
    comp = compare(first.diagram, second.diagram, labels=(a, b))
    if comp.equal and comp.verdict == "exact":
        return CaseVerdict(b, a, "exact", True, second.certified, first.certified,
                           f"exact implementations {a} and {b} agree exactly", result=second, reference_result=first,
                           comparison=comp)
    blame = "impl" if not second.certified else "reference" if not first.certified else "unknown"
    return CaseVerdict(b, a, "differs", False, second.certified, first.certified,
                       f"exact implementations {a} and {b} disagree ({comp.verdict}, {comp.n_differences} differences): "
                       f"they must agree exactly", blame, result=second, reference_result=first, comparison=comp)
