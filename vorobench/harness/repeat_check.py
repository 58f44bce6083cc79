"""Judging every timed repeat of a benchmark case, in the judge's process.

Repeat i built the sites scaled by ``2**shifts[i]`` (their weights by ``4**shifts[i]``, their
radii by ``2**shifts[i]``): its diagram must be of exactly those sites, weights and radii, and
scaled back (exactly) it is the diagram the case is judged on. The first repeat is certified
(a diagram of disks by the exact certificate of disks) and decided against the reference
(:func:`vorobench.judge.engine.decide`); every other repeat whose scaled-back arrays have the
same digest shares that verdict, and one that differs is judged in full on its own. So a build
that is wrong on some repeats, or a cache keyed by its input, shows in the verdict of those rows.
"""

from __future__ import annotations

import hashlib
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from vorobench.core.diagram import Diagram
from vorobench.core.scaling import exact_shift
from vorobench.harness.site_attributes import ATTRIBUTES, SiteAttribute, keywords
from vorobench.judge.declarations import Declaration
from vorobench.judge.engine import BuildResult, certify_result, decide, diagram_from_arrays, other_attribute
from vorobench.judge.outcomes import Verdict

__all__ = ["RepeatJudging", "repeat_shifts", "reference_result", "SHIFTS_NOTE"]

#: What the results say of the repeats' inputs.
SHIFTS_NOTE = ("repeat i builds the sites times 2**input_scale_log2 (weights times 4**input_scale_log2, radii "
               "times 2**input_scale_log2): the same order and diagram, other bytes; every repeat's diagram is judged")


def repeat_shifts(sites: np.ndarray, count: int) -> list[int]:
    """Powers of two for ``count`` repeats, 0, 1, -1, 2, -2, ...: every repeat's bytes differ, and
    none leaves the exact range where the sites lie in it (where they do not, the
    implementation scales them anyway; then a shift is kept only if it stays out of the range
    alike, else 0). For disks pass the centres and radii together
    (:meth:`~vorobench.harness.site_attributes.SiteAttribute.range_rows`): the radii scale with
    the centres, and a shift keeps both in the range."""
    try:
        base = exact_shift(sites)
    except ValueError:
        return [0] * count
    shifts = [0]
    step = 1
    while len(shifts) < count and step < 64:
        for k in (step, -step):
            if len(shifts) < count and _keeps_range(sites, k, base):
                shifts.append(k)
        step += 1
    return shifts + [0] * (count - len(shifts))


def _keeps_range(sites: np.ndarray, k: int, base: int) -> bool:
    """Whether ``sites * 2**k`` is exact (scaled back, every bit is there) and lies where
    :func:`repeat_shifts` wants it."""
    with np.errstate(over="ignore", under="ignore"):
        scaled = np.ldexp(sites, k)
        if not np.array_equal(np.ldexp(scaled, -k), sites):
            return False
    try:
        return exact_shift(scaled) == base - k if base else exact_shift(scaled) == 0
    except ValueError:
        return False


def _digest(d: Diagram) -> bytes:
    """A digest of the diagram's arrays, their integer fields as int64 (the layout an
    implementation chose does not change it), and its weights or radii."""
    h = hashlib.sha256()
    for name in ("sites", "vertices"):
        h.update(np.ascontiguousarray(getattr(d, name), dtype=np.float64).tobytes())
    for name in ("origin", "twin", "next", "site"):
        h.update(np.ascontiguousarray(getattr(d, name), dtype=np.int64).tobytes())
    for name in ATTRIBUTES:
        values = getattr(d, name)
        if values is not None:
            h.update(name.encode("ascii"))
            h.update(np.ascontiguousarray(values, dtype=np.float64).tobytes())
    return h.digest()


@dataclass
class RepeatJudging:
    """Takes in each repeat's diagram as it arrives, then gives each repeat's verdict columns.
    ``values``: the case's weights or radii (``attribute`` says which), None for points."""

    impl: str
    declared: Declaration
    sites: np.ndarray
    values: Optional[np.ndarray]
    shifts: list[int]
    attribute: Optional[SiteAttribute] = None
    judged: Optional[Diagram] = None
    judged_digest: bytes = b""
    #: Repeat index -> its own diagram (it differs from the judged one), or the failure it is.
    others: dict[int, object] = field(default_factory=dict)
    counts: dict[str, int] = field(default_factory=dict)

    def take(self, index: int, arrays: dict) -> None:
        """Repeat ``index``'s arrays: scaled back and digested now, judged later."""
        shift = self.shifts[index % len(self.shifts)]
        try:
            got = diagram_from_arrays(arrays)
        except Exception as exc:  # arrays of the wrong kind or shape
            self._keep(index, f"returned an unreadable diagram: {type(exc).__name__}: {exc}", Verdict.CRASHED)
            return
        expected = self.sites if shift == 0 else np.ldexp(self.sites, shift)
        if not (got.sites.shape == expected.shape and np.array_equal(got.sites, expected)):
            self._keep(index, "returned the diagram of other sites than the ones it was given")
            return
        problem = self._other_values(got, shift)
        if problem:
            self._keep(index, f"{problem} (repeat {index}: its input was the case's times 2**{shift})")
            return
        with np.errstate(over="ignore", under="ignore"):
            vertices = np.asarray(got.vertices) if shift == 0 else np.ldexp(got.vertices, -shift)
        diagram = Diagram(self.sites, vertices, got.origin, got.twin, got.next, got.site,
                          **keywords(self.attribute, self.values))
        digest = _digest(diagram)
        if self.judged is None and index == 0:
            self.judged, self.judged_digest = diagram, digest
            self.counts = {k: int(v) for k, v in diagram.counts().items() if k in ("V", "E")}
        elif digest != self.judged_digest:
            self.others[index] = diagram

    def _other_values(self, got: Diagram, shift: int) -> str:
        """Why the weights and radii of a repeat's diagram are not exactly the case's, scaled
        by the repeat's power of two (none where the case has none); "" if they are."""
        for name in ATTRIBUTES:
            wanted = None
            if self.attribute is not None and self.attribute.name == name:
                wanted = self.attribute.scaled(self.values, shift)
            problem = other_attribute(got, name, wanted)
            if problem:
                return problem
        return ""

    def _keep(self, index: int, why: str, failure: Verdict = Verdict.WRONG_SITES) -> None:
        self.others[index] = (why, failure)
        if index == 0:
            self.judged_digest = b"-"

    def verdicts(self, count: int, reference: Optional[str], ref: Optional[BuildResult], probes: int
                 ) -> list[dict]:
        """The verdict columns of repeats 0 .. count - 1 (``ref``: the reference's judged build of
        the same sites; for the reference's own case, None)."""
        judged = self._judge(self.judged if self.judged is not None
                             else self.others.get(0, ("returned no diagram", Verdict.CRASHED)),
                             reference, ref, probes)
        out = []
        for index in range(count):
            own = self.others.get(index)
            out.append(judged if own is None or index == 0 else self._judge(own, reference, ref, probes, index))
        return out

    def _judge(self, diagram: object, reference: Optional[str], ref: Optional[BuildResult], probes: int,
               index: int = 0) -> dict:
        if isinstance(diagram, tuple):           # (why, failure verdict): no diagram to certify
            res = BuildResult(self.impl, self.declared.exact, error=diagram[0], failure=diagram[1])
        else:
            res = certify_result(BuildResult(self.impl, self.declared.exact, diagram), self.sites, probes=probes,
                                 **keywords(self.attribute, self.values))
        own_case = ref is None
        verdict = decide(self.impl, reference or self.impl, res, res if own_case else ref)
        detail = verdict.message.strip().splitlines()[0][:300] if verdict.message.strip() else ""
        if index:
            detail = f"repeat {index} differs from repeat 0: {detail}"
        return {"verdict": verdict.verdict, "check_passed": bool(verdict.passed), "blame": verdict.blame or "",
                "certificate": verdict.certificate_level, "verdict_detail": detail}


#: The reference's judged builds, by (reference, dataset, n, seed, weight family, radius family): the last few.
_REFERENCES: "OrderedDict[tuple, BuildResult]" = OrderedDict()


def reference_result(key: tuple, build) -> BuildResult:
    """The reference's build of one case input, kept in this process as arrays and a
    certificate (``build()`` makes it the first time; a failure is not kept)."""
    if key in _REFERENCES:
        _REFERENCES.move_to_end(key)
        return _REFERENCES[key]
    result = build()
    if result.diagram is not None or result.unsupported:
        _REFERENCES[key] = result
        while len(_REFERENCES) > 8:
            _REFERENCES.popitem(last=False)
    return result
