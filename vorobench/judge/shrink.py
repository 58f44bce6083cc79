"""Witnesses: shrink a failing point set by delta debugging, save it with a command and a picture.

``ddmin`` (Zeller and Hildebrandt's minimising delta debugging) drops chunks of points while
the failure persists, then ever smaller chunks, until no single point can be dropped: a
1-minimal witness, usually a handful of points. ``write_witness`` saves it as ``.npy``, a
text file with the command that reproduces it, and a PNG overlaying the implementation's
diagram on the reference's with the differing edges in red. A weighted failure (a power
diagram) keeps its weights row for row: every function here takes them as ``weights``, and
its witness saves them beside the points (``NAME.weights.npy``).
"""

from __future__ import annotations

import contextlib
import os
import shlex
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator, Optional

import numpy as np
from numpy.typing import NDArray

from impls.executable import REFERENCES, manifest_named, program_input, rerun_command
from vorobench.core.diagram import Diagram
from vorobench.core.prepare import prepare
from vorobench.judge.engine import CaseVerdict, Judge, agree_exactly, check_case, prepare_case, prepare_disk_case
from vorobench.judge.plotting import save_overlay

__all__ = ["ddmin", "judge", "bounded_timeout", "shrink_rows", "shrink_case", "write_witness", "Witness",
           "WEIGHTS_FILE_PREFIX"]

#: ``--weights file:PATH`` reads the weights (one per point) from a file instead of a family.
WEIGHTS_FILE_PREFIX = "file:"


def ddmin(n: int, fails: Callable[[NDArray[np.int64]], bool], *, max_tests: int = 2000,
          time_budget: float = 120.0) -> NDArray[np.int64]:
    """Indices of a small subset of ``range(n)`` on which ``fails`` still holds (``fails`` must
    hold on all of them). Each round splits the current set into ``k`` chunks and keeps one
    chunk, or drops one chunk, if the failure persists; otherwise it doubles ``k``. Stops at
    a 1-minimal set, after ``max_tests`` calls or within ``time_budget`` seconds: a test that
    would end past the budget, judging by the slowest test so far, is not started."""
    items = np.arange(n, dtype=np.int64)
    k = 2
    tests = 0
    slowest = 0.0
    deadline = time.monotonic() + time_budget
    cache: dict[bytes, bool] = {}

    def out_of_budget() -> bool:
        return tests >= max_tests or time.monotonic() + slowest >= deadline

    def test(subset: NDArray[np.int64]) -> bool:
        nonlocal tests, slowest
        key = subset.tobytes()
        if key not in cache:
            if out_of_budget():
                return False                          # out of budget: keep what we have
            tests += 1
            started = time.monotonic()
            cache[key] = bool(fails(subset))
            slowest = max(slowest, time.monotonic() - started)
        return cache[key]

    while items.size >= 2 and not out_of_budget():
        chunks = np.array_split(items, min(k, items.size))
        reduced = False
        for chunk in chunks:                          # one chunk alone still fails?
            if chunk.size < items.size and test(chunk):
                items, k, reduced = chunk, 2, True
                break
        if not reduced:
            for i in range(len(chunks)):              # everything but one chunk still fails?
                rest = np.concatenate([c for j, c in enumerate(chunks) if j != i])
                if rest.size and test(rest):
                    items, k, reduced = rest, max(k - 1, 2), True
                    break
        if not reduced:
            if k >= items.size:
                break
            k = min(items.size, 2 * k)
    return items


def judge(impl: str, points: NDArray[np.float64], *, reference: str, exact_peer: Optional[str] = None,
          probes: int = 2000, judge: Optional[Judge] = None, weights: Optional[NDArray[np.float64]] = None,
          radii: Optional[NDArray[np.float64]] = None) -> CaseVerdict:
    """``impl`` on ``points`` (with ``weights``: their power diagram; with ``radii``: the diagram
    of disks): against ``reference`` (:func:`check_case`), or, with ``exact_peer``, exact
    agreement with that other exact implementation. Builds go through ``judge`` (isolated
    workers: a crashing implementation can be shrunk) when given."""
    engine = judge or Judge(reference=reference, isolate=False)
    if exact_peer is None:
        return check_case(impl, points, reference=reference, probes=probes, judge=engine, weights=weights,
                          radii=radii)
    if radii is not None:
        sites, site_radii = prepare_disk_case(points, radii)
        return agree_exactly(engine.build(exact_peer, sites, probes=probes, radii=site_radii),
                             engine.build(impl, sites, probes=probes, radii=site_radii))
    sites, site_weights = prepare_case(points, weights)
    return agree_exactly(engine.build(exact_peer, sites, probes=probes, weights=site_weights),
                         engine.build(impl, sites, probes=probes, weights=site_weights))


_judge = judge     # the module function, for callers whose parameter is also called ``judge``


@contextlib.contextmanager
def bounded_timeout(judge: Optional[Judge], seconds: float) -> Iterator[None]:
    """Within the block, each build ``judge`` isolates may take at most ``seconds`` (and never more
    than its own timeout), so that one slow build cannot overrun a budget. A judge that builds
    in this process (or none) cannot stop a build: it is left as it is."""
    if judge is None or not judge.isolate:
        yield
        return
    own = judge.timeout
    judge.timeout = max(0.0, seconds if own is None else min(own, seconds))
    try:
        yield
    finally:
        judge.timeout = own


def shrink_rows(n: int, judge_rows: Callable[[NDArray[np.int64]], CaseVerdict], verdict: CaseVerdict, *,
                judge: Optional[Judge] = None, max_tests: int = 2000, time_budget: float = 120.0
                ) -> tuple[NDArray[np.int64], CaseVerdict]:
    """The sorted indices of the smallest subset of ``range(n)`` found by :func:`ddmin` on which
    ``judge_rows`` fails the way ``verdict`` did (same verdict and blame), with its verdict
    (``verdict`` itself when no row could be dropped). The builds of each step go through
    ``judge`` bounded by what is left of ``time_budget``: a step cut short does not count as
    failing, so the budget ends the shrinking instead of being overrun."""
    want = (verdict.verdict, verdict.blame)
    deadline = time.monotonic() + time_budget
    failing: dict[bytes, CaseVerdict] = {}

    def fails(idx: NDArray[np.int64]) -> bool:
        with bounded_timeout(judge, deadline - time.monotonic()):
            v = judge_rows(idx)
        if (v.verdict, v.blame) != want or v.passed:
            return False
        failing[np.sort(idx).tobytes()] = v
        return True

    keep = np.sort(ddmin(n, fails, max_tests=max_tests, time_budget=time_budget))
    return keep, failing.get(keep.tobytes(), verdict)


def shrink_case(impl: str, points: NDArray[np.float64], verdict: CaseVerdict, *, reference: str,
                exact_peer: Optional[str] = None, probes: int = 2000, max_tests: int = 2000,
                time_budget: float = 120.0, judge: Optional[Judge] = None,
                weights: Optional[NDArray[np.float64]] = None, radii: Optional[NDArray[np.float64]] = None
                ) -> tuple[NDArray[np.float64], Optional[NDArray[np.float64]]]:
    """(points, weights or radii or None): the smallest subset of the rows of ``points`` (and
    ``weights`` or ``radii``, kept row for row) found by :func:`ddmin` on which ``impl`` fails
    the same way (same verdict and blame) against ``reference`` (or against ``exact_peer``),
    within ``time_budget`` seconds (see :func:`shrink_rows`)."""
    attribute = radii if radii is not None else weights

    def judge_rows(idx: NDArray[np.int64]) -> CaseVerdict:
        return _judge(impl, points[idx], reference=reference, exact_peer=exact_peer, probes=probes, judge=judge,
                      weights=None if weights is None else weights[idx],
                      radii=None if radii is None else radii[idx])

    keep, _ = shrink_rows(points.shape[0], judge_rows, verdict, judge=judge, max_tests=max_tests,
                          time_budget=time_budget)
    return points[keep], None if attribute is None else attribute[keep]


@dataclass
class Witness:
    """Files written for one failure."""

    points: Path
    command: Path
    picture: Optional[Path]
    n_points: int
    verdict: CaseVerdict


def _plugin_word(spec: str) -> str:
    """A ``--plugin`` of the run as the witness's command names it: a file by its absolute path
    (the command may be run from anywhere), a module by its name."""
    return str(Path(spec).resolve()) if spec.endswith((".py", ".toml")) or os.sep in spec else spec


def write_witness(directory: str | Path, name: str, impl: str, points: NDArray[np.float64], *, reference: str,
                  exact_peer: Optional[str] = None, probes: int = 2000, judge: Optional[Judge] = None,
                  verdict: Optional[CaseVerdict] = None, picture: bool = True,
                  weights: Optional[NDArray[np.float64]] = None, radii: Optional[NDArray[np.float64]] = None) -> Witness:
    """Save ``points`` as ``NAME.npy`` (and ``weights`` as ``NAME.weights.npy``) with ``NAME.txt``
    (the command that reproduces the failure, with the ``--plugin`` modules of ``judge`` and the
    weights, and what it reports; ``verdict`` if given, else ``points`` judged again) and, with
    ``picture``, ``NAME.png`` (both diagrams, differing edges in red; a campaign out of time
    leaves it out). ``radii`` make the points disks: saved as ``NAME.radii.npy`` and named in the
    command (a picture of curved cells is not drawn yet)."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    npy = directory / f"{name}.npy"
    np.save(npy, np.asarray(points, dtype=np.float64))
    if verdict is None:     # given when judging again would only cost the same timeout twice
        verdict = _judge(impl, points, reference=reference, exact_peer=exact_peer, probes=probes, judge=judge,
                         weights=weights, radii=radii)
    names = impl if exact_peer is None else f"{exact_peer},{impl}"
    specs = list(judge.plugins if judge else ())
    program = _program_of(impl, judge)
    if program is not None and not program.path.is_relative_to(REFERENCES) and str(program.path) not in map(
            _plugin_word, specs):
        specs.append(str(program.path))     # found through VOROBENCH_IMPLS_PATH: the command names it
    plugins = "".join(f"--plugin {shlex.quote(_plugin_word(spec))} " for spec in specs)
    command = (f"vorobench validate {plugins}--impls {shlex.quote(names)} --reference {shlex.quote(reference)} "
               f"--points {shlex.quote(str(npy))}")
    if weights is not None:             # the points alone would judge the ordinary diagram: name the weights too
        weights_path = directory / f"{name}.weights.npy"
        np.save(weights_path, np.asarray(weights, dtype=np.float64))
        command += f" --weights {shlex.quote(WEIGHTS_FILE_PREFIX + str(weights_path))}"
    if radii is not None:               # likewise the radii of disks
        radii_path = directory / f"{name}.radii.npy"
        np.save(radii_path, np.asarray(radii, dtype=np.float64))
        command += f" --radii {shlex.quote(WEIGHTS_FILE_PREFIX + str(radii_path))}"
        picture = False
    lines = [command]
    if program is not None and radii is None:       # the program alone, on exactly the bytes it was given
        stdin = directory / f"{name}.stdin"
        stdin.write_bytes(program_input(program, points, weights))
        lines += ["", f"the program alone ({impl}, {program.input} input):", rerun_command(program, stdin)]
    lines += ["", f"{points.shape[0]} points; verdict {verdict.verdict}: {verdict.message}"]
    shown: list = []
    for res in (verdict.result, verdict.reference_result):
        if res is not None and res.certificate is not None and all(res is not r for r in shown):
            shown.append(res)
            lines += ["", f"{res.impl}:", str(res.certificate)]
    if verdict.comparison is not None:
        lines += ["", str(verdict.comparison)]
    txt = directory / f"{name}.txt"
    txt.write_text("\n".join(lines) + "\n")
    if not picture:
        return Witness(npy, txt, None, int(points.shape[0]), verdict)
    png: Optional[Path] = directory / f"{name}.png"
    ref_d = verdict.reference_result.diagram if verdict.reference_result is not None else None
    own_d = verdict.result.diagram if verdict.result is not None else None
    if own_d is ref_d:
        ref_d = None
    if own_d is None and ref_d is None:            # crashed: draw the points at least
        own_d = Diagram.empty(prepare(points)[0])
    comp = verdict.comparison
    hl_ref = comp.highlight_a if comp is not None else _offending_half_edges(verdict.reference_result)
    hl_own = comp.highlight_b if comp is not None else _offending_half_edges(verdict.result)
    marks = _offending_sites(verdict.result) + _offending_sites(verdict.reference_result)
    try:
        other = exact_peer or reference
        save_overlay(ref_d, own_d, png, labels=(other, impl), highlight_first=hl_ref,
                     highlight_second=hl_own, mark_sites=marks,
                     title=f"{impl} vs {other}: {verdict.verdict} ({points.shape[0]} points)")
    except Exception:  # nothing to draw (both crashed) or a drawing failure: the witness stands without it
        png = None
    return Witness(npy, txt, png, int(points.shape[0]), verdict)


def _program_of(impl: str, judge: Optional[Judge]):
    """The manifest of ``impl`` when the judge declared it an executable (else None)."""
    declared = judge.declaration(impl) if judge is not None else None
    if declared is None or declared.kind != "executable":
        return None
    return manifest_named(impl, declared.plugin)


def _offending_half_edges(res) -> list[int]:
    if res is None or res.certificate is None or res.diagram is None:
        return []
    out: list[int] = []
    for c in res.certificate.checks:
        if not c.ok and c.id_kind == "half-edge":
            out += [h for h in c.offending if 0 <= h < res.diagram.n_half_edges]
    return out


def _offending_sites(res) -> list[int]:
    if res is None or res.certificate is None or res.diagram is None:
        return []
    out: list[int] = []
    for c in res.certificate.checks:
        if not c.ok and c.id_kind == "site":
            out += [i for i in c.offending if 0 <= i < res.diagram.n_sites]
    return out
