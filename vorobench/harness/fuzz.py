"""Fuzz campaigns: many small random and degenerate cases, each cross-validated on an executor, failures shrunk to witnesses.

The command line is :mod:`vorobench.cli.fuzz`; its help text describes the behaviour. A campaign
with a weight family judges the power diagram of every case's points with weights of that
family (drawn with the case's seed); its witnesses keep their weights."""

from __future__ import annotations

import json
import multiprocessing as mp
import socket
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterator, Optional, Sequence

import numpy as np
from rich.markup import escape

import datasets_gen
import impls
from impls.plugins import plugins_registered
from vorobench.core.prepare import prepare
from vorobench.harness.atomic import replace_atomically
from vorobench.harness.campaign import INT_BOX, LOG_NAME, Budget, parse_budget
from vorobench.harness.executors import run_tasks
from vorobench.harness.weighted_witness import judge_weighted, shrink_weighted, write_weighted_witness
from vorobench.judge.engine import prepare_case, shared_judge
from vorobench.judge.shrink import judge, shrink_case, write_witness

__all__ = ["Budget", "parse_budget", "FuzzCase", "plan", "generate", "check_fuzz_case",
           "shrink_failure", "run_campaign", "INT_BOX", "LOG_NAME"]


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

    def judge(self):
        """This process's judge for the case's implementations and options."""
        return shared_judge(self.impls, self.reference, probes=self.probes, plugins=self.plugins,
                            timeout=self.timeout, memory_limit_mb=self.memory_limit_mb)

    @property
    def key(self) -> tuple[str, int, int]:
        return (self.generator, self.n, self.seed)

    def __str__(self) -> str:
        weights = f" weights={self.weights}" if self.weights else ""
        return f"{self.generator} n={self.n} seed={self.seed}{weights}"

    def input(self) -> tuple[np.ndarray, Optional[np.ndarray]]:
        """The case's points and their weights (None for an ordinary case)."""
        points = generate(self.generator, self.n, self.seed)
        weights = datasets_gen.weights(self.weights, points, seed=self.seed) if self.weights else None
        return points, weights


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
            "message": v.message[:300]}


def check_fuzz_case(case: FuzzCase) -> dict[str, Any]:
    """Run on a worker: every implementation on the case's points, through the judging engine
    (isolated builds, the reference certified once); a JSON-ready record."""
    t0 = time.perf_counter()
    with plugins_registered(case.plugins):
        points, weights = case.input()
        judged = case.judge().judge(points, weights=weights)
    results = [_verdict_record(v, peer) for _, v, peer in judged.rows]
    return {"generator": case.generator, "n": case.n, "seed": case.seed, "weights": case.weights, "status": "checked",
            "n_points": int(points.shape[0]), "n_sites": int(judged.sites.shape[0]), "results": results,
            "passed": judged.passed, "seconds": time.perf_counter() - t0, "host": socket.gethostname()}


@dataclass(frozen=True)
class ShrinkTask:
    """A failure to shrink: the case, the implementation (and exact peer) that failed."""

    case: FuzzCase
    impl: str
    peer: Optional[str]
    seconds: float = 30.0


def shrink_failure(task: ShrinkTask):
    """Run on a worker: the case's points shrunk by ddmin to a small set that still fails the
    same way (the points unshrunk if the failure does not reproduce in this process); for a
    weighted case, (points, weights) shrunk together."""
    case = task.case
    with plugins_registered(case.plugins):
        points, weights = case.input()
        engine = case.judge()
        if weights is not None:
            sites, site_weights = prepare_case(points, weights)
            verdict = judge_weighted(task.impl, sites, site_weights, reference=case.reference, exact_peer=task.peer,
                                     probes=case.probes, judge=engine)
            if verdict.passed or verdict.verdict in ("timeout", "oom"):
                return sites, site_weights
            return shrink_weighted(task.impl, sites, site_weights, verdict, reference=case.reference,
                                   exact_peer=task.peer, probes=case.probes, time_budget=task.seconds, judge=engine)
        sites, _ = prepare(points)
        verdict = judge(task.impl, sites, reference=case.reference, exact_peer=task.peer, probes=case.probes,
                        judge=engine)
        if verdict.passed or verdict.verdict in ("timeout", "oom"):   # each try would cost the whole allowance
            return sites
        return shrink_case(task.impl, sites, verdict, reference=case.reference, exact_peer=task.peer,
                           probes=case.probes, time_budget=task.seconds, judge=engine)


@dataclass
class CampaignSummary:
    """What a run of a campaign did."""

    checked: int = 0
    previously: int = 0
    failed: int = 0
    failed_before: int = 0
    lost: int = 0
    errors: int = 0
    seconds: float = 0.0
    witnesses: list[dict[str, Any]] = field(default_factory=list)

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
    log.write(json.dumps(record, default=_json_default) + "\n")
    log.flush()


def _json_default(x: Any) -> Any:
    if isinstance(x, np.generic):
        return x.item()
    return str(x)


def _setup_text(setup: dict[str, Any]) -> str:
    return ", ".join(f"{k} {v}" for k, v in setup.items() if k != "kind")


def write_json(path: Path, data: dict) -> None:
    """Write ``data`` atomically: a reader never sees half a summary."""
    replace_atomically(path, lambda f: json.dump(data, f, indent=1, default=_json_default))


def _witness_stem(key: tuple[str, int, int], impl: str, peer: Optional[str], weights: str = "") -> str:
    stem = f"{impl}-{key[0]}-n{key[1]}-s{key[2]}" + (f"-w{weights}" if weights else "")
    stem += f"-vs-{peer}" if peer else ""
    return "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in stem)


def run_campaign(out: Path, impls: Sequence[str], generators: Sequence[str], budget: Budget, *,
                 executor: str = "local", workers: int = 1, reference: str = impls.DEFAULT_REFERENCE, min_n: int = 3,
                 max_n: int = 40, campaign_seed: int = 0, probes: int = 500, plugins: Sequence[str] = (),
                 shrink: bool = True, shrink_seconds: float = 30.0, console=None, timeout: float = 60.0,
                 memory_limit_mb: Optional[float] = None, weights: str = "") -> CampaignSummary:
    """Check cases until the budget is spent, skipping those already in ``out/cases.jsonl``;
    then shrink every failure not yet witnessed. Returns what this run did. ``weights``: a
    weight family of ``datasets_gen`` (power diagrams), or "" (ordinary diagrams)."""
    out.mkdir(parents=True, exist_ok=True)
    log_path = out / LOG_NAME
    earlier = _read_log(log_path)
    # A log answers only for the setup it was made with: reusing it under other implementations,
    # reference, probes or plugins would skip cases nobody judged that way.
    setup = {"kind": "setup", "impls": sorted(impls), "reference": reference, "probes": probes,
             "plugins": sorted(str(Path(p).resolve()) if p.endswith(".py") else p for p in plugins),
             "min_n": min_n, "max_n": max_n, "campaign_seed": campaign_seed}
    if weights:         # only then: the logs of ordinary campaigns stay valid
        setup["weights"] = weights
    logged = [r for r in earlier if r.get("kind") == "setup"]
    if logged and {k: v for k, v in logged[0].items()} != setup:
        raise ValueError(f"{log_path} was made with another setup ({_setup_text(logged[0])}); "
                         f"use another --out for this one")
    if earlier and not logged:
        raise ValueError(f"{log_path} has no setup record (an older campaign): use another --out")
    done = {(r["generator"], r["n"], r["seed"]) for r in earlier if r.get("kind", "case") == "case"}
    witnessed = {(r["generator"], r["n"], r["seed"], r["impl"], r.get("peer")) for r in earlier
                 if r.get("kind") == "witness"}
    summary = CampaignSummary(previously=len(done))
    started = time.monotonic()
    deadline = started + budget.seconds if budget.seconds is not None else None

    def todo() -> Iterator[FuzzCase]:
        for i, (gen, n, seed) in enumerate(plan(generators, min_n, max_n, campaign_seed)):
            if budget.cases is not None and i >= budget.cases:
                return
            if deadline is not None and time.monotonic() >= deadline:
                return
            if (gen, n, seed) not in done:
                yield FuzzCase(gen, n, seed, tuple(impls), reference, probes, tuple(plugins), timeout, memory_limit_mb,
                               weights)

    failures: list[tuple[FuzzCase, str, Optional[str]]] = []
    for r in earlier:   # failures of earlier runs that were not shrunk yet
        if r.get("kind", "case") == "case":
            for v in r.get("results", []):
                if not v["passed"] and (r["generator"], r["n"], r["seed"], v["impl"], v["peer"]) not in witnessed:
                    failures.append((FuzzCase(r["generator"], r["n"], r["seed"], tuple(impls), reference, probes,
                                              tuple(plugins), timeout, memory_limit_mb, weights), v["impl"], v["peer"]))
    summary.failed_before = sum(1 for r in earlier if r.get("kind", "case") == "case" and not r.get("passed"))
    limit = None
    if mp.current_process().daemon or not executor.startswith("local"):
        # Off this machine a build may run without its sandbox: the case as a whole is bounded.
        limit = (len(impls) + 1) * (timeout + 300.0)
    with log_path.open("a") as log:
        if not logged:
            _append(log, setup)
        for res in run_tasks(executor, workers, check_fuzz_case, todo(), timeout=limit):
            case: FuzzCase = res.item
            summary.checked += 1
            if res.ok:
                record = res.value
                for v in record["results"]:
                    if not v["passed"]:
                        failures.append((case, v["impl"], v["peer"]))
                summary.failed += not record["passed"]
            else:
                # The worker died (every try) or the task raised: recorded, never dropped.
                record = {"generator": case.generator, "n": case.n, "seed": case.seed, "weights": case.weights,
                          "status": "lost" if res.lost else "error", "error": res.lost or res.error,
                          "attempts": res.attempts, "results": [], "passed": False}
                summary.lost += bool(res.lost)
                summary.errors += bool(res.error)
            _append(log, {"kind": "case", **record})
            if console is not None and not record["passed"]:
                console.print(f"[red]{record['status'] if not res.ok else 'FAIL'}[/] {case}: "
                              + escape(record.get("error") or "; ".join(f"{v['impl']}: {v['verdict']}" for v in
                                                                        record["results"] if not v["passed"])))
        summary.seconds = time.monotonic() - started
        if shrink and failures:
            tasks = [ShrinkTask(case, impl, peer, shrink_seconds) for case, impl, peer in failures]
            with plugins_registered(plugins):   # write_witness judges the witness here
                for res in run_tasks(executor, workers, shrink_failure, tasks):
                    task: ShrinkTask = res.item
                    if not res.ok:
                        if console is not None:
                            console.print(f"[yellow]could not shrink[/] {task.impl} on {task.case}: "
                                          f"{res.lost or res.error}")
                        continue
                    stem = _witness_stem(task.case.key, task.impl, task.peer, weights)
                    if weights:
                        small, small_weights = res.value
                        w = write_weighted_witness(out / "witnesses", stem, task.impl, small, small_weights,
                                                   reference=reference, exact_peer=task.peer, probes=probes,
                                                   judge=task.case.judge())
                    else:
                        w = write_witness(out / "witnesses", stem, task.impl, res.value, reference=reference,
                                          exact_peer=task.peer, probes=probes, judge=task.case.judge())
                    entry = {"kind": "witness", "generator": task.case.generator, "n": task.case.n,
                             "seed": task.case.seed, "impl": task.impl, "peer": task.peer,
                             "n_points": w.n_points, "verdict": w.verdict.verdict, "points": str(w.points)}
                    _append(log, entry)
                    summary.witnesses.append(entry)
    return summary
