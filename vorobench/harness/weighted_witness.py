"""Witnesses of failures on weighted sites (power diagrams): shrunk with their weights, saved with them.

:mod:`vorobench.judge.shrink` shrinks and saves point sets; a weighted failure also needs its
weights, row for row. Here ddmin drops rows of points and weights together, and the witness
is ``NAME.npy`` (points) plus ``NAME.weights.npy``, with the command that reproduces it
(``vorobench validate --points NAME.npy --weights file:NAME.weights.npy``) and the picture of
:func:`vorobench.judge.shrink.write_witness`.
"""

from __future__ import annotations

import shlex
from pathlib import Path
from typing import Optional

import numpy as np
from numpy.typing import NDArray

from vorobench.judge.engine import CaseVerdict, Judge, agree_exactly, check_case, prepare_case
from vorobench.judge.shrink import Witness, ddmin, write_witness

__all__ = ["WEIGHTS_FILE_PREFIX", "load_weights", "judge_weighted", "shrink_weighted", "write_weighted_witness"]

#: ``--weights file:PATH`` reads the weights (one per point) from a file instead of a family.
WEIGHTS_FILE_PREFIX = "file:"


def load_weights(path: str | Path) -> NDArray[np.float64]:
    """One weight per point from ``.npy`` (a 1-D array) or text (one number per line, or one
    line of comma-separated numbers). Read as the point loader reads: only a regular file of
    bounded size, and no integer float64 cannot hold exactly (it is refused, never rounded)."""
    # Imported here only because this change was limited to this function: belongs at the top.
    from datasets_gen.loaders import first_inexact_integer, number_table, read_npy, read_text

    path = Path(path)
    try:
        if path.suffix == ".npy":
            w = read_npy(path, "weights file")
            inexact = first_inexact_integer(w)
            if inexact is not None:
                raise ValueError(f"{path}: integer {inexact[1]} at index {', '.join(map(str, inexact[0]))} "
                                 f"has no exact float64 value (it would be read as {float(inexact[1])!r})")
        else:
            w = number_table(read_text(path, "weights file"), path)
            if 1 in w.shape or w.size == 0:     # a column, a single row or nothing: the list of weights
                w = w.ravel()
    except FileNotFoundError:
        raise ValueError(f"{path}: no such weights file") from None
    w = np.asarray(w, dtype=np.float64)
    if w.ndim != 1:
        raise ValueError(f"{path}: weights must be one number per point, got an array of shape {w.shape}")
    return w


def judge_weighted(impl: str, points: NDArray[np.float64], weights: NDArray[np.float64], *, reference: str,
                   exact_peer: Optional[str] = None, probes: int = 2000, judge: Optional[Judge] = None) -> CaseVerdict:
    """``impl`` on the power diagram of ``points`` with ``weights``: against ``reference``, or with
    ``exact_peer``, exact agreement with that other exact implementation."""
    engine = judge or Judge(reference=reference, isolate=False)
    if exact_peer is None:
        return check_case(impl, points, reference=reference, probes=probes, judge=engine, weights=weights)
    sites, site_weights = prepare_case(points, weights)
    return agree_exactly(engine.build(exact_peer, sites, probes=probes, weights=site_weights),
                         engine.build(impl, sites, probes=probes, weights=site_weights))


def shrink_weighted(impl: str, points: NDArray[np.float64], weights: NDArray[np.float64], verdict: CaseVerdict, *,
                    reference: str, exact_peer: Optional[str] = None, probes: int = 2000, max_tests: int = 2000,
                    time_budget: float = 120.0, judge: Optional[Judge] = None
                    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The smallest rows of (``points``, ``weights``) found by ddmin on which ``impl`` fails the
    same way (same verdict and blame)."""
    want = (verdict.verdict, verdict.blame)

    def fails(idx: NDArray[np.int64]) -> bool:
        v = judge_weighted(impl, points[idx], weights[idx], reference=reference, exact_peer=exact_peer,
                           probes=probes, judge=judge)
        return (v.verdict, v.blame) == want and not v.passed

    keep = np.sort(ddmin(points.shape[0], fails, max_tests=max_tests, time_budget=time_budget))
    return points[keep], weights[keep]


def write_weighted_witness(directory: str | Path, name: str, impl: str, points: NDArray[np.float64],
                           weights: NDArray[np.float64], *, reference: str, exact_peer: Optional[str] = None,
                           probes: int = 2000, judge: Optional[Judge] = None,
                           verdict: Optional[CaseVerdict] = None) -> Witness:
    """:func:`~vorobench.judge.shrink.write_witness` for weighted sites: ``NAME.weights.npy`` is
    saved next to the points, and ``NAME.txt`` starts with the command that judges both."""
    if verdict is None:
        verdict = judge_weighted(impl, points, weights, reference=reference, exact_peer=exact_peer, probes=probes,
                                 judge=judge)
    witness = write_witness(directory, name, impl, points, reference=reference, exact_peer=exact_peer,
                            probes=probes, judge=judge, verdict=verdict)
    weights_path = Path(directory) / f"{name}.weights.npy"
    np.save(weights_path, np.asarray(weights, dtype=np.float64))
    lines = witness.command.read_text().splitlines()
    # The points-only command would judge the ordinary diagram: name the weights too.
    lines[0] = f"{lines[0]} --weights {shlex.quote(WEIGHTS_FILE_PREFIX + str(weights_path))}"
    witness.command.write_text("\n".join(lines) + "\n")
    return witness
