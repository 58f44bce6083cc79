"""Fuzz campaigns: many small random and degenerate cases, each cross-validated on an executor, failures shrunk to witnesses.

The command line is :mod:`vorobench.cli.fuzz`; its help text describes the behaviour. A campaign
with a weight family judges the power diagram of every case's points with weights of that
family (drawn with the case's seed); its witnesses keep their weights.

A duration budget covers the whole run: checking stops early enough to leave a share for
shrinking once something failed, each build is bounded by what is left, and a witness that
cannot be shrunk in time is written as found. The log's setup record holds digests of the
code under test, so a campaign whose implementations or plugins changed starts afresh."""

from __future__ import annotations

import hashlib
import importlib.util
import json
import multiprocessing as mp
import os
import socket
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Iterator, Optional, Sequence

import numpy as np
from rich.markup import escape

import datasets_gen
import impls
import vorobench.core
import vorobench.judge
from vorobench.harness.atomic import json_value
from vorobench.harness.campaign import INT_BOX, LOG_NAME, Budget, parse_budget
from vorobench.harness.executors import run_tasks
from vorobench.judge.engine import CaseVerdict, Judge, prepare_case, prepare_disk_case, shared_judge
from vorobench.judge.outcomes import Status, Verdict
from vorobench.judge.shrink import Witness, bounded_timeout, judge, shrink_rows, write_witness

__all__ = ["Budget", "parse_budget", "FuzzCase", "Failure", "plan", "generate", "check_fuzz_case",
           "shrink_failure", "run_campaign", "source_digest", "plugin_digest", "INT_BOX", "LOG_NAME",
           "SHRINK_SHARE", "SHRINK_PER_KIND"]

#: Share of a duration budget kept for shrinking and witnesses once a failure worth shrinking is found.
SHRINK_SHARE = 0.25
#: Failures of one implementation with one verdict (and exact peer) shrunk per run; the rest are
#: written as found: one more witness of the same finding is not worth a shrink each.
SHRINK_PER_KIND = 3
#: Verdicts whose every judging costs the whole allowance: their witnesses are written as found.
COSTLY_VERDICTS = (Verdict.TIMEOUT, Verdict.OOM)
#: A case is not started with less of the budget left (or a tenth of a short budget).
MIN_CASE_SECONDS = 1.0
#: The code whose change voids earlier verdicts: implementations, geometry, judge, case generators.
SOURCE_PACKAGES = (impls, vorobench.core, vorobench.judge, datasets_gen)


#: Lattice points on the circle of radius 5 (from 3-4-5 triangles): exactly cocircular.
_CIRCLE5 = np.array([(5, 0), (4, 3), (3, 4), (0, 5), (-3, 4), (-4, 3), (-5, 0), (-4, -3), (-3, -4), (0, -5),
                     (3, -4), (4, -3)], dtype=np.float64)


@dataclass(frozen=True)
class FuzzCase:
    """One case of a campaign and how to judge it (sent to a worker as it is)."""

    generator: str
    n: int
    seed: int
    impls: tuple[str, ...]
    reference: str
    probes: int = 500
    plugins: tuple[str, ...] = ()
    timeout: float = 60.0
    memory_limit_mb: Optional[float] = None
    #: The weight family of a power-diagram campaign ("" for ordinary diagrams).
    weights: str = ""
    #: When the budget ends, as ``time.time()`` (a worker may be another process or machine); None: never.
    deadline: Optional[float] = None
    #: Implementations not built: each timed out on an earlier case of this run.
    skip: tuple[str, ...] = ()
    #: (name, Declaration) pinned for the campaign (read in a sandbox; none: read on first use).
    declarations: tuple = ()
    #: The radius family of a campaign of disks ("" for points; docs/apollonius.md).
    radii: str = ""

    def judge(self):
        """This process's judge for the case's implementations and options; plugins are loaded
        only in the sandboxes of the implementations they define."""
        return shared_judge(self.impls, self.reference, probes=self.probes, plugins=self.plugins,
                            timeout=self.timeout, memory_limit_mb=self.memory_limit_mb,
                            declarations=self.declarations)

    @property
    def key(self) -> tuple[str, int, int]:
        return (self.generator, self.n, self.seed)

    def allowance(self) -> float:
        """Seconds each build of the case may take: the timeout, or less if the budget ends sooner."""
        return self.timeout if self.deadline is None else min(self.timeout, self.deadline - time.time())

    def __str__(self) -> str:
        weights = f" weights={self.weights}" if self.weights else ""
        radii = f" radii={self.radii}" if self.radii else ""
        return f"{self.generator} n={self.n} seed={self.seed}{weights}{radii}"

    def input(self) -> tuple[np.ndarray, Optional[np.ndarray]]:
        """The case's points and their weights (None for an ordinary case)."""
        points = generate(self.generator, self.n, self.seed)
        weights = datasets_gen.weights(self.weights, points, seed=self.seed) if self.weights else None
        return points, weights

    def disk_radii(self, points: np.ndarray) -> Optional[np.ndarray]:
        """The radii that make the case's points disks (None for a case of points)."""
        return datasets_gen.radii(self.radii, points, seed=self.seed) if self.radii else None

    def prepared(self) -> tuple[np.ndarray, Optional[np.ndarray], Optional[np.ndarray]]:
        """The case's sites as the judge gets them, with their weights or radii (or neither)."""
        points, weights = self.input()
        radii = self.disk_radii(points)
        if radii is not None:
            sites, site_radii = prepare_disk_case(points, radii)
            return sites, None, site_radii
        sites, site_weights = prepare_case(points, weights)
        return sites, site_weights, None


def int_box(n: int, seed: int) -> np.ndarray:
    """``n`` points of a small integer box (side 1 to 8: duplicates and collinear triples),
    some replaced by lattice points of a radius-5 circle (an exactly cocircular subset)."""
    rng = np.random.default_rng(seed)
    side = int(rng.integers(1, 9))
    points = rng.integers(0, side + 1, size=(n, 2)).astype(np.float64)
    k = int(rng.integers(0, min(n, len(_CIRCLE5)) + 1))
    if k:
        centre = rng.integers(-3, side + 4, size=2)
        points[:k] = _CIRCLE5[rng.choice(len(_CIRCLE5), size=k, replace=False)] + centre
    return points[rng.permutation(n)]


def generate(generator: str, n: int, seed: int) -> np.ndarray:
    """The points of a case."""
    if generator == INT_BOX:
        return int_box(n, seed)

    return datasets_gen.generate(generator, n, seed=seed)


def plan(generators: Sequence[str], min_n: int, max_n: int, campaign_seed: int) -> Iterator[tuple[str, int, int]]:
    """Case i = (generator i mod k, n drawn from [min_n, max_n], seed) for i = 0, 1, ...; the
    same campaign seed always gives the same sequence, so a rerun can skip what is done."""
    i = 0
    while True:
        rng = np.random.default_rng([campaign_seed, i])
        yield generators[i % len(generators)], int(rng.integers(min_n, max_n + 1)), campaign_seed * 1_000_000_000 + i
        i += 1


def _verdict_record(v, peer: Optional[str]) -> dict[str, Any]:
    return {"impl": v.impl, "peer": peer, "verdict": v.verdict, "passed": bool(v.passed), "blame": v.blame,
            "certificate": v.certificate_level, "message": v.message[:300]}


def _cut_record(case: FuzzCase, note: str) -> dict[str, Any]:
    """The record of a case the budget's end kept from being judged (a rerun checks it again)."""
    return {"generator": case.generator, "n": case.n, "seed": case.seed, "weights": case.weights, "status": "cut",
            "note": note, "results": [], "passed": False, **_radii_field(case)}


def _radii_field(case: FuzzCase) -> dict[str, str]:
    """A record's radius family, for a campaign of disks only (the logs of others stay as they were)."""
    return {"radii": case.radii} if case.radii else {}


def check_fuzz_case(case: FuzzCase) -> dict[str, Any]:
    """Run on a worker: every implementation not skipped on the case's points, through the
    judging engine (isolated builds, the reference certified once), each build bounded by
    what is left of the budget; a JSON-ready record. Its status is "cut" when a build timed
    out only because the budget was ending: the case was not judged."""
    t0 = time.perf_counter()
    allowance = case.allowance()
    if allowance <= 0:
        return _cut_record(case, "the budget ended before it started")
    names = [name for name in case.impls if name not in case.skip]
    points, weights = case.input()
    engine = case.judge()
    with bounded_timeout(engine, allowance):
        judged = engine.judge(points, names, weights=weights, radii=case.disk_radii(points))
    results = [_verdict_record(v, peer) for _, v, peer in judged.rows]
    late = [v["impl"] for v in results if v["verdict"] == Verdict.TIMEOUT]
    if late and allowance < case.timeout:
        return _cut_record(case, f"{', '.join(late)} did not finish in the {allowance:.1f} s left of the budget")
    record = {"generator": case.generator, "n": case.n, "seed": case.seed, "weights": case.weights, **_radii_field(case),
              "status": "checked", "n_points": int(points.shape[0]), "n_sites": int(judged.sites.shape[0]),
              "results": results, "passed": judged.passed, "seconds": time.perf_counter() - t0,
              "host": socket.gethostname()}
    if case.skip:
        record["skipped"] = list(case.skip)
    return record


@dataclass(frozen=True)
class Failure:
    """A failing row of a checked case: the case, who failed (against which exact peer), and
    the verdict as the log recorded it."""

    case: FuzzCase
    impl: str
    peer: Optional[str]
    verdict: str
    message: str = ""
    blame: str = "impl"

    @classmethod
    def from_row(cls, case: FuzzCase, row: dict[str, Any]) -> "Failure":
        """The failure a result row of the log records."""
        return cls(case, row["impl"], row.get("peer"), row.get("verdict", ""), row.get("message", ""),
                   row.get("blame") or "impl")

    @property
    def kind(self) -> tuple[str, Optional[str], str]:
        """What makes two failures the same finding, as far as shrinking goes."""
        return (self.impl, self.peer, self.verdict)

    @property
    def costly(self) -> bool:
        """Whether judging it again would cost the whole allowance (a timeout, memory run out)."""
        return self.verdict in COSTLY_VERDICTS

    def recorded_verdict(self) -> CaseVerdict:
        """The verdict as logged, without diagrams: what a witness written as found reports."""
        return CaseVerdict(self.impl, self.peer or self.case.reference, self.verdict, False, None, None, self.message,
                           self.blame)


@dataclass(frozen=True)
class ShrinkTask:
    """A failure to shrink within ``seconds``, and never past ``deadline`` (``time.time()``;
    None: the budget has no end)."""

    failure: Failure
    seconds: float = 30.0
    deadline: Optional[float] = None

    def time_budget(self) -> float:
        """Seconds this task may still take, counted from now."""
        left = self.seconds if self.deadline is None else min(self.seconds, self.deadline - time.time())
        return max(0.0, left)


@dataclass
class Shrunk:
    """What shrinking a failure gave: the witness's sites (with their weights, or None) and its
    verdict; ``radii`` for a case of disks."""

    sites: np.ndarray
    weights: Optional[np.ndarray]
    verdict: CaseVerdict
    radii: Optional[np.ndarray] = None


def _row_judge(failure: Failure, sites: np.ndarray, weights: Optional[np.ndarray],
               engine: Judge, radii: Optional[np.ndarray] = None) -> Callable[[np.ndarray], CaseVerdict]:
    """A function judging ``failure``'s implementation on some rows of the sites (and weights,
    or radii)."""
    case = failure.case

    def judge_rows(idx: np.ndarray) -> CaseVerdict:
        return judge(failure.impl, sites[idx], reference=case.reference, exact_peer=failure.peer,
                     probes=case.probes, judge=engine, weights=None if weights is None else weights[idx],
                     radii=None if radii is None else radii[idx])

    return judge_rows


def shrink_failure(task: ShrinkTask) -> Shrunk:
    """Run on a worker: the failing case's sites shrunk by ddmin to a small set that still fails
    the same way, with the verdict on it (for a weighted case, sites and weights together).
    Every build is bounded by what is left of the task's time. A failure that does not
    reproduce here comes back unshrunk, with this try's verdict (the logged one if the try
    ran out of time)."""
    failure = task.failure
    case = failure.case
    ends = time.monotonic() + task.time_budget()
    sites, weights, radii = case.prepared()
    if ends <= time.monotonic():        # sent before the budget ended, started after
        return Shrunk(sites, weights, failure.recorded_verdict(), radii)
    engine = case.judge()
    judge_rows = _row_judge(failure, sites, weights, engine, radii)
    with bounded_timeout(engine, ends - time.monotonic()):
        verdict = judge_rows(np.arange(sites.shape[0]))
    if verdict.passed or verdict.verdict != failure.verdict:
        return Shrunk(sites, weights, failure.recorded_verdict() if verdict.verdict == Verdict.TIMEOUT else verdict,
                      radii)
    keep, verdict = shrink_rows(sites.shape[0], judge_rows, verdict, judge=engine,
                                time_budget=ends - time.monotonic())
    return Shrunk(sites[keep], None if weights is None else weights[keep], verdict,
                  None if radii is None else radii[keep])


@dataclass
class CampaignSummary:
    """What a run of a campaign did."""

    checked: int = 0
    previously: int = 0
    failed: int = 0
    failed_before: int = 0
    lost: int = 0
    errors: int = 0
    #: Cases the budget's end kept from being judged (not logged: a rerun checks them).
    cut: int = 0
    seconds: float = 0.0
    witnesses: list[dict[str, Any]] = field(default_factory=list)
    #: Implementations that timed out on a case, and that case: not built again in this run.
    hung: dict[str, str] = field(default_factory=dict)
    #: Failures the budget left no time to write a witness for (a rerun writes them).
    unwitnessed: int = 0

    @property
    def rate(self) -> float:
        return self.checked / self.seconds if self.seconds > 0 else 0.0


def _read_log(path: Path) -> list[dict[str, Any]]:
    if not path.exists():
        return []
    records = []
    for line in path.read_text().splitlines():
        try:
            records.append(json.loads(line))
        except json.JSONDecodeError:        # a line cut short by a crash: that case is rerun
            continue
    return records


def _append(log, record: dict[str, Any]) -> None:
    log.write(json.dumps(record, default=json_value) + "\n")
    log.flush()


def _setup_text(setup: dict[str, Any]) -> str:
    return ", ".join(f"{k} {v}" for k, v in setup.items() if k not in ("kind", "code"))


def _witness_stem(key: tuple[str, int, int], impl: str, peer: Optional[str], weights: str = "") -> str:
    stem = f"{impl}-{key[0]}-n{key[1]}-s{key[2]}" + (f"-w{weights}" if weights else "")
    stem += f"-vs-{peer}" if peer else ""
    return "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in stem)


# ------------------------------------------------------------- what the log answers for


def _hash_tree(digest, root: Path) -> None:
    """Feed every ``.py`` file under ``root`` (its path below ``root``'s parent, and its bytes) to ``digest``."""
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root.parent).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")


def source_digest(packages: Sequence[Any] = SOURCE_PACKAGES) -> str:
    """SHA-256 of the ``.py`` files of ``packages`` (modules with a ``__file__``): any edit of
    the code under test changes it."""
    digest = hashlib.sha256()
    for package in packages:
        _hash_tree(digest, Path(package.__file__).resolve().parent)
    return digest.hexdigest()


def _is_plugin_file(spec: str) -> bool:
    """Whether a ``--plugin`` spec names a file rather than a module (the rule of ``load_plugin``)."""
    return spec.endswith(".py") or os.sep in spec


def plugin_digest(spec: str) -> str:
    """SHA-256 of a plugin's source: the file a ``.py`` spec names; for a module name, its file
    (every ``.py`` file of a package); "missing" when there is none to read."""
    digest = hashlib.sha256()
    if _is_plugin_file(spec):
        path = Path(spec)
        if not path.is_file():
            return "missing"
        digest.update(path.read_bytes())
        return digest.hexdigest()
    try:
        found = importlib.util.find_spec(spec)
    except (ImportError, ValueError):      # a parent package that does not import: no source to read
        found = None
    if found is None or not found.origin or not Path(found.origin).is_file():
        return "missing"
    if found.submodule_search_locations:   # a package: all of it
        for location in found.submodule_search_locations:
            _hash_tree(digest, Path(location))
    else:
        digest.update(Path(found.origin).read_bytes())
    return digest.hexdigest()


def _setup_record(impls: Sequence[str], reference: str, probes: int, plugins: Sequence[str], min_n: int, max_n: int,
                  campaign_seed: int, weights: str, radii: str = "") -> dict[str, Any]:
    """What a log answers for: the options that decide which cases are judged and how, and
    (under "code") digests of the code under test and of each plugin."""
    setup: dict[str, Any] = {"kind": "setup", "impls": sorted(impls), "reference": reference, "probes": probes,
                             "plugins": sorted(str(Path(p).resolve()) if p.endswith(".py") else p for p in plugins),
                             "min_n": min_n, "max_n": max_n, "campaign_seed": campaign_seed}
    if weights:         # only then: the logs of ordinary campaigns stay valid
        setup["weights"] = weights
    if radii:
        setup["radii"] = radii
    setup["code"] = {"source": source_digest(),
                     "plugins": {str(Path(p).resolve()) if _is_plugin_file(p) else p: plugin_digest(p)
                                 for p in plugins}}
    return setup


def _options(setup: dict[str, Any]) -> dict[str, Any]:
    """A setup record without its code digests."""
    return {k: v for k, v in setup.items() if k != "code"}


def _move_aside(out: Path) -> Path:
    """Move the log and witnesses of a superseded campaign to ``out/superseded/<time>/``."""
    stamp = time.strftime("%Y%m%d-%H%M%S")
    target = out / "superseded" / stamp
    n = 1
    while target.exists():
        target, n = out / "superseded" / f"{stamp}-{n}", n + 1
    target.mkdir(parents=True)
    for name in (LOG_NAME, "witnesses"):
        if (out / name).exists():
            os.replace(out / name, target / name)
    return target


def _load_log(out: Path, setup: dict[str, Any], console=None) -> list[dict[str, Any]]:
    """The records of earlier runs in ``out`` that answer for ``setup``. A log made with other
    options is refused; one made with other code (or without digests) is moved aside, and the
    campaign starts afresh: its passes say nothing of the code now under test."""
    log_path = out / LOG_NAME
    earlier = _read_log(log_path)
    logged = [r for r in earlier if r.get("kind") == "setup"]
    if logged and _options(logged[0]) != _options(setup):
        raise ValueError(f"{log_path} was made with another setup ({_setup_text(logged[0])}); "
                         f"use another --out for this one")
    if earlier and not logged:
        raise ValueError(f"{log_path} has no setup record (an older campaign): use another --out")
    if logged and logged[0].get("code") != setup["code"]:
        moved = _move_aside(out)
        if console is not None:
            console.print(f"[yellow]the code under test changed since {log_path} was written[/]: its cases and "
                          f"witnesses were moved to {moved}; starting afresh")
        return []
    return earlier


def _unwitnessed_failures(earlier: Sequence[dict[str, Any]], make_case: Callable[..., FuzzCase]) -> list[Failure]:
    """The failures logged by earlier runs that have no witness yet."""
    witnessed = {(r["generator"], r["n"], r["seed"], r["impl"], r.get("peer")) for r in earlier
                 if r.get("kind") == "witness"}
    failures = []
    for r in earlier:
        if r.get("kind", "case") == "case":
            for v in r.get("results", []):
                if not v["passed"] and (r["generator"], r["n"], r["seed"], v["impl"], v["peer"]) not in witnessed:
                    failures.append(Failure.from_row(make_case(r["generator"], r["n"], r["seed"]), v))
    return failures


# --------------------------------------------------------------------------- a run


@dataclass(frozen=True)
class _Clock:
    """A run's duration budget: its end here (monotonic) and for workers (wall clock)."""

    started: float
    seconds: Optional[float]
    wall_end: Optional[float]

    @classmethod
    def start(cls, budget: Budget) -> "_Clock":
        wall_end = None if budget.seconds is None else time.time() + budget.seconds
        return cls(time.monotonic(), budget.seconds, wall_end)

    def left(self) -> Optional[float]:
        """Seconds left of the budget (None: a case count, no end in time)."""
        return None if self.seconds is None else self.started + self.seconds - time.monotonic()

    def elapsed(self) -> float:
        return time.monotonic() - self.started


def _run_task(task: "FuzzCase | ShrinkTask") -> Any:
    """Run on a worker: a case to check or a failure to shrink. One pool serves both, so that
    shrinking finds the workers' sandboxes started and warm."""
    return check_fuzz_case(task) if isinstance(task, FuzzCase) else shrink_failure(task)


def _count_to_shrink(failures: Sequence[Failure], shrinking: dict[tuple, int]) -> int:
    """How many of ``failures`` would still be shrunk, ``shrinking`` counting those of each kind already sent."""
    counts = dict(shrinking)
    n = 0
    for failure in failures:
        if not failure.costly and counts.get(failure.kind, 0) < SHRINK_PER_KIND:
            counts[failure.kind] = counts.get(failure.kind, 0) + 1
            n += 1
    return n


@dataclass
class _Campaign:
    """One run of a campaign: its options, its clock, and what it found so far."""

    out: Path
    impls: tuple[str, ...]
    reference: str
    probes: int
    plugins: tuple[str, ...]
    timeout: float
    memory_limit_mb: Optional[float]
    weights: str
    executor: str
    workers: int
    shrink: bool
    clock: _Clock
    console: Any = None
    declarations: tuple = ()
    radii: str = ""
    summary: CampaignSummary = field(default_factory=CampaignSummary)
    failures: list[Failure] = field(default_factory=list)
    #: Failures whose witness is written as found: costly ones, repeated kinds, those left no time.
    as_found: list[Failure] = field(default_factory=list)
    #: How many of ``failures`` the shrinking phase has looked at (later ones are written as found).
    triaged: int = 0
    #: The longest a shrink task took, its witness written: one is not started with less time left.
    slowest_shrink: float = 0.0
    _sent: dict[int, float] = field(default_factory=dict)

    def case(self, generator: str, n: int, seed: int, skip: Sequence[str] = ()) -> FuzzCase:
        return FuzzCase(generator, n, seed, self.impls, self.reference, self.probes, self.plugins, self.timeout,
                        self.memory_limit_mb, self.weights, self.clock.wall_end, tuple(skip), self.declarations,
                        self.radii)

    def say(self, text: str) -> None:
        if self.console is not None:
            self.console.print(text)

    @property
    def in_flight(self) -> Optional[int]:
        """Tasks sent ahead of the workers: locally none, so that each task starts with the
        budget, the implementations to skip and the failures as they stand (the executor's
        default on Dask)."""
        return self.workers if self.executor.startswith("local") else None

    def _out_of_time(self) -> bool:
        left = self.clock.left()
        return left is not None and left <= 0

    def run(self, planned: Iterator[tuple[str, int, int]], budget: Budget, done: set[tuple[str, int, int]], log,
            shrink_seconds: float) -> None:
        """Check the planned cases, then shrink the failures, on one pool; then write the
        witnesses left to write as found (none at all without shrinking)."""
        limit = None
        if mp.current_process().daemon or not self.executor.startswith("local"):
            # Off this machine a build may run without its sandbox: the case as a whole is bounded.
            limit = (len(self.impls) + 1) * (self.timeout + 300.0)
        tasks = self._tasks(planned, budget, done, shrink_seconds)
        for res in run_tasks(self.executor, self.workers, _run_task, tasks, timeout=limit,
                             in_flight=self.in_flight):
            if isinstance(res.item, FuzzCase):
                self._take(res, log)
            else:
                self._take_shrunk(res, log)
        if self.shrink:
            self._write_all_as_found(log)

    def _tasks(self, planned: Iterator[tuple[str, int, int]], budget: Budget, done: set[tuple[str, int, int]],
               shrink_seconds: float) -> Iterator["FuzzCase | ShrinkTask"]:
        """The cases to check while the budget lasts, then the failures to shrink."""
        yield from self._todo(planned, budget, done)
        self.summary.seconds = self.clock.elapsed()
        if self.shrink:
            yield from self._shrink_tasks(shrink_seconds)

    # ------------------------------------------------------------------ checking

    def _time_for_a_case(self) -> bool:
        """Whether a case may start: time is left beyond a case's minimum and, once a failure
        worth shrinking is known, beyond the share of the budget kept for shrinking it."""
        left = self.clock.left()
        if left is None:
            return True
        worth_shrinking = self.shrink and any(not f.costly for f in self.failures)
        kept = SHRINK_SHARE * self.clock.seconds if worth_shrinking else 0.0
        return left - kept >= min(MIN_CASE_SECONDS, 0.1 * self.clock.seconds)

    def _todo(self, planned: Iterator[tuple[str, int, int]], budget: Budget,
              done: set[tuple[str, int, int]]) -> Iterator[FuzzCase]:
        """The planned cases not done yet, while the budget lasts."""
        for i, (gen, n, seed) in enumerate(planned):
            if budget.cases is not None and i >= budget.cases:
                return
            if not self._time_for_a_case():
                return
            if (gen, n, seed) not in done:
                yield self.case(gen, n, seed, skip=sorted(self.summary.hung))

    def _take(self, res, log) -> None:
        """Log one case's result and note its failures."""
        case: FuzzCase = res.item
        if res.ok and res.value["status"] == "cut":
            self.summary.cut += 1
            self.say(f"[yellow]cut short[/] {case}: {escape(res.value['note'])}; not judged (a rerun checks it)")
            return
        self.summary.checked += 1
        if res.ok:
            record = res.value
            self.failures += [Failure.from_row(case, v) for v in record["results"] if not v["passed"]]
            self.summary.failed += not record["passed"]
            self._note_hung(case, record)
        else:
            # The worker died (every try) or the task raised: recorded, never dropped.
            record = {"generator": case.generator, "n": case.n, "seed": case.seed, "weights": case.weights,
                      **_radii_field(case), "status": Status.LOST if res.lost else Status.ERROR, "error": res.lost or res.error,
                      "attempts": res.attempts, "results": [], "passed": False}
            self.summary.lost += bool(res.lost)
            self.summary.errors += bool(res.error)
        _append(log, {"kind": "case", **record})
        if not record["passed"]:
            self.say(f"[red]{record['status'] if not res.ok else 'FAIL'}[/] {case}: "
                     + escape(record.get("error") or "; ".join(f"{v['impl']}: {v['verdict']}" for v in
                                                               record["results"] if not v["passed"])))

    def _note_hung(self, case: FuzzCase, record: dict[str, Any]) -> None:
        """Remember the implementations that timed out on the whole allowance: later cases of
        this run do not build them, so a hanging implementation costs one timeout, not one a case."""
        for v in record["results"]:
            if v["verdict"] == Verdict.TIMEOUT and v["impl"] != self.reference and v["impl"] not in self.summary.hung:
                self.summary.hung[v["impl"]] = str(case)
                self.say(f"[yellow]{escape(v['impl'])} timed out on {case}[/]: not built again in this run")

    # ---------------------------------------------------------------- witnesses

    def _time_to_shrink(self) -> bool:
        """Whether a shrink task may start: more time is left than the slowest one took."""
        left = self.clock.left()
        return left is None or left > self.slowest_shrink

    def _shrink_tasks(self, seconds: float) -> Iterator[ShrinkTask]:
        """A task for each of the first :data:`SHRINK_PER_KIND` failures of each kind, none
        costly to judge, while there is time for one more; each has its share of what is left
        (at most ``seconds``). The other failures go to ``as_found``."""
        shrinking: dict[tuple, int] = {}
        while self.triaged < len(self.failures):        # the last cases may still add some
            failure = self.failures[self.triaged]
            self.triaged += 1
            if failure.costly or shrinking.get(failure.kind, 0) >= SHRINK_PER_KIND or not self._time_to_shrink():
                self.as_found.append(failure)
                continue
            shrinking[failure.kind] = shrinking.get(failure.kind, 0) + 1
            left = self.clock.left()
            share = seconds
            if left is not None:
                share = min(seconds, left / (1 + _count_to_shrink(self.failures[self.triaged:], shrinking)))
            task = ShrinkTask(failure, share, self.clock.wall_end)
            self._sent[id(task)] = time.monotonic()
            yield task

    def _take_shrunk(self, res, log) -> None:
        """Write the witness of a shrunk failure (or leave it to be written as found)."""
        task: ShrinkTask = res.item
        if res.ok:
            self._record(log, task.failure, self._write_shrunk(task.failure, res.value), shrunk=True)
        else:
            self.say(f"[yellow]could not shrink[/] {task.failure.impl} on {task.failure.case}: {res.lost or res.error}")
            self.as_found.append(task.failure)
        # Its picture included: drawing a diagram can take longer than the shrinking did.
        self.slowest_shrink = max(self.slowest_shrink, time.monotonic() - self._sent.pop(id(task), time.monotonic()))

    def _write_all_as_found(self, log) -> None:
        """Write the witnesses of the failures not shrunk, as found."""
        for failure in self.as_found + self.failures[self.triaged:]:
            if (self.weights or self.radii) and self._out_of_time():
                # A weighted witness comes with its picture (a fifth of a second each): past the
                # budget it is left to a rerun, which writes every failure still without a witness.
                self.summary.unwitnessed += 1
                continue
            self._record(log, failure, self._write_as_found(failure), shrunk=False)
        if self.summary.unwitnessed:
            self.say(f"[yellow]{self.summary.unwitnessed} failures have no witness yet[/] (the budget ran out): "
                     f"a rerun into the same --out writes them")

    def _write_shrunk(self, failure: Failure, shrunk: Shrunk) -> Witness:
        return self._write(failure, shrunk.sites, shrunk.weights, shrunk.verdict, picture=not self._out_of_time(),
                           radii=shrunk.radii)

    def _write_as_found(self, failure: Failure) -> Witness:
        """The failing case's sites with the logged verdict: nothing judged again, no picture."""
        sites, weights, radii = failure.case.prepared()
        return self._write(failure, sites, weights, failure.recorded_verdict(), picture=False, radii=radii)

    def _write(self, failure: Failure, sites: np.ndarray, weights: Optional[np.ndarray], verdict: CaseVerdict,
               picture: bool, radii: Optional[np.ndarray] = None) -> Witness:
        case = failure.case
        stem = _witness_stem(case.key, failure.impl, failure.peer, self.weights or self.radii)
        options = dict(reference=self.reference, exact_peer=failure.peer, probes=self.probes, judge=case.judge(),
                       verdict=verdict)
        return write_witness(self.out / "witnesses", stem, failure.impl, sites, picture=picture, weights=weights,
                             radii=radii, **options)

    def _record(self, log, failure: Failure, w: Witness, *, shrunk: bool) -> None:
        case = failure.case
        entry = {"kind": "witness", "generator": case.generator, "n": case.n, "seed": case.seed,
                 "impl": failure.impl, "peer": failure.peer, "n_points": w.n_points, "verdict": w.verdict.verdict,
                 "points": str(w.points), "shrunk": shrunk}
        _append(log, entry)
        self.summary.witnesses.append(entry)


def run_campaign(out: Path, impls: Sequence[str], generators: Sequence[str], budget: Budget, *,
                 executor: str = "local", workers: int = 1, reference: str = impls.DEFAULT_REFERENCE, min_n: int = 3,
                 max_n: int = 40, campaign_seed: int = 0, probes: int = 500, plugins: Sequence[str] = (),
                 shrink: bool = True, shrink_seconds: float = 30.0, console=None, timeout: float = 60.0,
                 memory_limit_mb: Optional[float] = None, weights: str = "",
                 declarations: tuple = (), radii: str = "") -> CampaignSummary:
    """Check cases until the budget is spent, skipping those already in ``out/cases.jsonl``;
    then shrink the failures not yet witnessed and write their witnesses. A duration budget
    covers all of it (see the module's docstring). Returns what this run did. ``weights``: a
    weight family of ``datasets_gen`` (power diagrams), or "" (ordinary diagrams); ``radii``: a
    radius family (diagrams of disks), or "".
    ``declarations``: (name, Declaration) pinned for the run (see :mod:`vorobench.judge.pinning`)."""
    out.mkdir(parents=True, exist_ok=True)
    # A log answers only for the setup it was made with: reusing it under other implementations,
    # reference, probes, plugins or code would skip cases nobody judged that way.
    setup = _setup_record(impls, reference, probes, plugins, min_n, max_n, campaign_seed, weights, radii)
    earlier = _load_log(out, setup, console)
    campaign = _Campaign(out, tuple(impls), reference, probes, tuple(plugins), timeout, memory_limit_mb, weights,
                         executor, workers, shrink, _Clock.start(budget), console, declarations=tuple(declarations),
                         radii=radii)
    done = {(r["generator"], r["n"], r["seed"]) for r in earlier if r.get("kind", "case") == "case"}
    campaign.summary.previously = len(done)
    campaign.summary.failed_before = sum(1 for r in earlier if r.get("kind", "case") == "case" and not r.get("passed"))
    campaign.failures = _unwitnessed_failures(earlier, campaign.case)
    with (out / LOG_NAME).open("a") as log:
        if not earlier:
            _append(log, setup)
        campaign.run(plan(generators, min_n, max_n, campaign_seed), budget, done, log, shrink_seconds)
    return campaign.summary
