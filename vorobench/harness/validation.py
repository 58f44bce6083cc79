"""The cross-validation campaign behind ``vorobench validate``: every case judged, failures
shrunk to witnesses, the gate decided and summarised. The command line only parses and prints.

Each case goes through the judging engine (:class:`~vorobench.judge.engine.Judge`: sandboxes,
pinned declarations) here or on an executor; a case whose worker died on every try is
``lost``, a failure on every implementation's row. Witnesses are shrunk and written with
:mod:`vorobench.judge.shrink` (weights kept row for row), as ``fuzz`` does.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Optional, Sequence

import numpy as np

import datasets_gen
from datasets_gen.loaders import TEXT_SUFFIXES
from vorobench.harness.atomic import write_json
from vorobench.judge.declarations import Declaration
from vorobench.judge.engine import VERDICTS, CaseVerdict, shared_judge
from vorobench.judge.outcomes import Verdict

__all__ = ["ValidationCase", "Failure", "Campaign", "judge_case_task", "run_campaign", "write_failure_witness",
           "write_witnesses", "witness_stem", "write_json", "mark_unfinished", "summarise", "worst"]


@dataclass(frozen=True)
class ValidationCase:
    """One case of a campaign: a named dataset at (n, seed), or given points (``seed`` None)
    with their weights; ``family`` names the weights of generated points ("" for none), and
    ``radii_family`` the radii that make them disks (docs/apollonius.md; "" for points)."""

    dataset: str
    n: int
    seed: Optional[int]
    family: str = ""
    points: Optional[np.ndarray] = field(default=None, compare=False, repr=False)
    weights: Optional[np.ndarray] = field(default=None, compare=False, repr=False)
    radii_family: str = ""
    radii: Optional[np.ndarray] = field(default=None, compare=False, repr=False)

    @property
    def label(self) -> str:
        text = f"{self.dataset} n={self.n}" + (f" seed={self.seed}" if self.seed is not None else "")
        return text + (f" weights={self.family}" if self.family else "") + \
            (f" radii={self.radii_family}" if self.radii_family else "")

    def input(self) -> tuple[np.ndarray, Optional[np.ndarray]]:
        """(points, weights or None), generated from the dataset when none were given."""
        if self.points is not None:
            return self.points, self.weights
        points = datasets_gen.generate(self.dataset, self.n, seed=self.seed)
        weights = datasets_gen.weights(self.family, points, seed=self.seed) if self.family else None
        return points, weights

    def disk_radii(self, points: np.ndarray) -> Optional[np.ndarray]:
        """The radii of the case's disks (None: a case of points)."""
        if self.radii is not None or not self.radii_family:
            return self.radii
        return datasets_gen.radii(self.radii_family, points, seed=self.seed or 0)

    def key(self) -> dict[str, Any]:
        """The case's columns in every record: dataset, weight family, n, seed (and the radius
        family of a run of disks)."""
        key = dict(dataset=self.dataset, weights=self.family, n=self.n, seed=self.seed)
        if self.radii_family:
            key["radii"] = self.radii_family
        return key


@dataclass
class Failure:
    """A failing verdict and what reproduces it."""

    case: ValidationCase
    impl: str
    exact_peer: Optional[str]
    verdict: CaseVerdict
    sites: np.ndarray
    weights: Optional[np.ndarray]
    radii: Optional[np.ndarray] = None

    @property
    def blamed(self) -> str:
        """Who failed: the exact peer when the comparison blames it, else the implementation."""
        return self.exact_peer if self.verdict.blame == "reference" and self.exact_peer else self.impl


@dataclass
class Campaign:
    """Everything a campaign produced: the records (one per verdict), the failures, the lost
    cases, how many were judged, the witnesses."""

    records: list[dict[str, Any]] = field(default_factory=list)
    failures: list[Failure] = field(default_factory=list)
    lost: list[tuple[str, str]] = field(default_factory=list)
    judged: int = 0
    witnesses: list[dict[str, Any]] = field(default_factory=list)


def judge_case_task(item: tuple) -> tuple:
    """One case on any worker, through the judging engine: (sites, [(impl, verdict, peer)],
    site weights or None, site radii or None)."""
    case, names, reference, options = item
    points, weights = case.input()
    radii = case.disk_radii(points)
    judged = shared_judge(names, reference, **dict(options)).judge(points, weights=weights, radii=radii)
    return judged.sites, judged.rows, judged.weights, judged.radii


def run_campaign(cases: Sequence[ValidationCase], names: Sequence[str], reference: str, options: tuple, *,
                 executor: str = "local", workers: int = 1, case_limit: Optional[float] = None,
                 on_case: Callable[[ValidationCase], None] = lambda case: None) -> Campaign:
    """Judge every case (here one at a time, or on ``executor``); ``on_case`` hears of each."""
    campaign = Campaign()
    items = [(case, list(names), reference, options) for case in cases]
    if executor == "local" and workers == 1:
        judged_cases = ((item, judge_case_task(item), "") for item in items)
    else:
        from vorobench.harness.executors import run_tasks

        judged_cases = ((r.item, r.value, r.lost or r.error)
                        for r in run_tasks(executor, workers, judge_case_task, items, timeout=case_limit))
    for (case, *_), judged, lost in judged_cases:
        on_case(case)
        if lost:                        # its worker died (twice): every implementation's row says so
            campaign.lost.append((case.label, lost))
            campaign.records += [dict(case.key(), exact_peer=None, impl=name, reference=reference,
                                      verdict=Verdict.CRASHED, passed=False, certified=None, reference_certified=None,
                                      message=f"case lost: {lost}", blame="unknown", n_sites=0, seconds=0.0)
                                 for name in names]
            continue
        campaign.judged += 1
        sites, checks, site_weights, site_radii = judged
        for name, verdict, peer in checks:
            campaign.records.append(dict(case.key(), exact_peer=peer, **verdict.to_dict()))
            if not verdict.passed:
                campaign.failures.append(Failure(case, name, peer, verdict, sites, site_weights, site_radii))
    return campaign


def witness_stem(impl: str, dataset: str, n: int, seed: Optional[int], family: str = "",
                 exact_peer: Optional[str] = None) -> str:
    """A file name for a witness: who, on what, against whom; only safe characters. A points file
    (a replayed witness) is named by its stem, without repeating the implementation's name."""
    if Path(dataset).suffix.lower() in (".npy", *TEXT_SUFFIXES):
        dataset = Path(dataset).stem
        dataset = dataset[len(impl) + 1:] if dataset.startswith(f"{impl}-") and len(dataset) > len(impl) + 1 \
            else dataset
    stem = f"{impl}-{dataset}-n{n}" + (f"-s{seed}" if seed is not None else "")
    stem += f"-w{family.rpartition('/')[2]}" if family else ""
    stem = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in stem)
    return stem + (f"-vs-{exact_peer}" if exact_peer else "")


def write_failure_witness(folder: Path, stem: str, impl: str, sites: np.ndarray, weights: Optional[np.ndarray],
                          verdict: CaseVerdict, *, reference: str, exact_peer: Optional[str], probes: int,
                          shrink: bool, seconds: float, judge, radii: Optional[np.ndarray] = None):
    """Shrink a failure (unless ``shrink`` is False, or it is a hang or an exhausted memory,
    which cost their whole allowance per try) and write its witness, weights kept with the
    points: the :class:`~vorobench.judge.shrink.Witness`. A case of disks keeps its ``radii`` row
    for row the same way."""
    from vorobench.judge.shrink import shrink_case, write_witness

    shrinkable = shrink and verdict.verdict not in (Verdict.TIMEOUT, Verdict.OOM)
    attribute = radii if radii is not None else weights
    small, small_attribute = (sites, attribute) if not shrinkable else shrink_case(
        impl, sites, verdict, reference=reference, exact_peer=exact_peer, probes=probes, time_budget=seconds,
        judge=judge, weights=weights, radii=radii)
    return write_witness(folder, stem, impl, small, reference=reference, exact_peer=exact_peer, probes=probes,
                         judge=judge, verdict=None if shrinkable else verdict,
                         weights=None if radii is not None else small_attribute,
                         radii=small_attribute if radii is not None else None)


def write_witnesses(campaign: Campaign, out: Path, names: Sequence[str], reference: str, options: tuple, *,
                    shrink: bool, probes: int, seconds: float,
                    on_witness: Callable[[Failure], Any] = lambda failure: None) -> None:
    """A witness of every failure, through a judge of this process (sandboxed like the cases)."""
    judge = shared_judge(list(names), reference, **dict(options))
    for failure in campaign.failures:
        case = failure.case
        with on_witness(failure) or contextlib.nullcontext():
            w = write_failure_witness(out / "witnesses", witness_stem(failure.impl, case.dataset, case.n, case.seed,
                                                                       case.family or case.radii_family,
                                                                       failure.exact_peer),
                                      failure.impl, failure.sites, failure.weights, failure.verdict,
                                      reference=reference, exact_peer=failure.exact_peer, probes=probes,
                                      shrink=shrink, seconds=seconds, judge=judge, radii=failure.radii)
        campaign.witnesses.append(dict(impl=failure.impl, **case.key(), verdict=failure.verdict.verdict,
                                       points=str(w.points), command=str(w.command),
                                       picture=str(w.picture) if w.picture else None, n_points=w.n_points,
                                       shrunk_verdict=w.verdict.verdict))


def worst(verdicts: Sequence[str]) -> str:
    """The worst of ``verdicts`` (:data:`~vorobench.judge.engine.VERDICTS` order)."""
    return max(verdicts, key=VERDICTS.index)


def summarise(campaign: Campaign, cases: int, names: Sequence[str], reference: str,
              declared: dict[str, Declaration], family: str, timeout: float, radii_family: str = "") -> dict[str, Any]:
    """The gate and its summary: every planned case judged, every verdict a pass, and every
    implementation judged at least once (one that does not take weights, on a weighted run,
    or disks, on a run of disks, is declared so up front and left out)."""
    records = campaign.records
    unweighted = [n for n in names if family and not declared[n].weighted]
    no_disks = [n for n in names if radii_family and not declared[n].apollonius]
    notes = []
    float_impls = [n for n in names if not declared[n].exact]
    if float_impls:
        one = len(float_impls) == 1
        notes.append(f"{', '.join(float_impls)} {'is' if one else 'are'} floating point: 'within tolerance' against "
                     f"{'it' if one else 'them'} is a pass, and {'its' if one else 'their'} certificates are judged "
                     f"within tolerance; exact implementations must agree with each other exactly.")
    pairs = [r for r in records if r["exact_peer"]]
    if pairs:
        bad_pairs = sum(not r["passed"] for r in pairs)
        notes.append(f"{len(pairs)} comparisons between exact implementations (against "
                     f"{', '.join(sorted({r['exact_peer'] for r in pairs}))}): "
                     + ("all exact." if not bad_pairs else f"{bad_pairs} NOT exact."))
    blamed = [r for r in records if r["blame"] == "reference"]
    if blamed:
        notes.append(f"{len(blamed)} difference(s) were the reference's failure (see the {reference} row).")
    never_judged = sorted({r["impl"] for r in records if r["impl"] not in unweighted + no_disks}
                          - {r["impl"] for r in records if r["verdict"] != Verdict.UNSUPPORTED})
    if unweighted:
        notes.append(f"{', '.join(unweighted)} {'does' if len(unweighted) == 1 else 'do'} not take weights: "
                     f"unsupported on every weighted case, and not part of the gate.")
    if no_disks:
        notes.append(f"{', '.join(no_disks)} {'does' if len(no_disks) == 1 else 'do'} not take disks: "
                     f"unsupported on every case of disks, and not part of the gate.")
    if never_judged:
        notes.append(f"{', '.join(never_judged)} declared every case unsupported: nothing of "
                     f"{'it' if len(never_judged) == 1 else 'them'} was judged, so the gate does not pass.")
    # A gate with nothing judged fails: the implementations asked for (besides the reference)
    # must have had at least one verdict that is not "unsupported".
    asked = [n for n in names if n != reference] or list(names)
    judged_impls = {r["impl"] for r in records if r["verdict"] != Verdict.UNSUPPORTED}
    nothing_judged = bool(cases) and not (set(asked) & judged_impls)
    if nothing_judged:
        notes.append(f"nothing of {', '.join(asked)} was judged (unsupported on every case"
                     + (f"; {family} weights" if family else "") + (f"; {radii_family} radii" if radii_family else "")
                     + "): a gate with nothing judged does not pass.")
    passed = (not campaign.failures and not campaign.lost and campaign.judged == cases and not never_judged
              and not nothing_judged)
    return dict(reference=reference, impls=list(names), datasets=list(dict.fromkeys(r["dataset"] for r in records)),
                weights=family or None, unweighted=unweighted, radii=radii_family or None, no_disks=no_disks, cases=cases, judged=campaign.judged,
                complete=campaign.judged == cases, passed=passed, failures=len(campaign.failures),
                lost=len(campaign.lost), failed_impls=sorted({f.blamed for f in campaign.failures}),
                never_judged=never_judged, nothing_judged=asked if nothing_judged else [], timeout=timeout, notes=notes, witnesses=campaign.witnesses,
                declarations={n: d.to_dict() for n, d in declared.items()}, results=records)


def mark_unfinished(out: Path, **fields: Any) -> Path:
    """The summary on disk says the run has not passed until it has: a run killed at any point
    (even while starting) leaves no earlier green gate behind."""
    out.mkdir(parents=True, exist_ok=True)
    path = out / "summary.json"
    write_json(path, dict(fields, complete=False, passed=False,
                          note="validation started and has not finished (or was killed)"))
    return path
