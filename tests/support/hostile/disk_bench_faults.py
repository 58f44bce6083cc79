"""Constructions of disks that a bench catches only if every timed repeat is judged, in the
judge's process, as a diagram of exactly the case's disks. Loaded with ``--plugin`` (so only in
the sandboxes of its implementations, never where verdicts are decided).

``centres_for_disks``: the ordinary diagram of the centres with the radii attached
(:func:`disk_doubles.points_for_disks`). ``wrong_after_first``: the oracle on its first two
builds (the warm-up and repeat 0), the centres' diagram after. ``radii_forger``: the oracle's
diagram, sent to the judge with other radii. ``Implementation.run`` attaches the caller's radii
to whatever a build returns, so only a process that rewrites its own answer can send others:
this one replaces the worker's conversion of a diagram to arrays, in its own process.
"""

from __future__ import annotations

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))          # tests/support: disk_doubles

from disk_doubles import oracle, ordinary_build, points_for_disks  # noqa: E402
from impls.base import Implementation  # noqa: E402

#: Builds so far in this process (a sandbox serves one case: the warm-up, then the repeats).
_BUILDS = [0]

#: How much larger the radii the forger sends are than the ones it was given.
FORGED_FACTOR = 1.5


def _wrong_after_first(sites, radii, stats=None):
    """The oracle on the warm-up and on repeat 0, the centres' diagram on every later repeat."""
    _BUILDS[0] += 1
    build = oracle if _BUILDS[0] <= 2 else points_for_disks
    return build(sites, radii, stats)


def _forge_answers() -> None:
    """Make this process's bench worker send every diagram with its radii times FORGED_FACTOR."""
    worker = sys.modules.get("vorobench.harness.worker")
    if worker is None or getattr(worker, "_forged", False):
        return
    honest = worker.diagram_arrays

    def forged(diagram):
        arrays = dict(honest(diagram))
        if "radii" in arrays:
            arrays["radii"] = arrays["radii"] * FORGED_FACTOR
        return arrays

    worker.diagram_arrays, worker._forged = forged, True


def _radii_forger(sites, radii, stats=None):
    """The right diagram; what reaches the judge carries other radii."""
    _forge_answers()
    return oracle(sites, radii, stats)


IMPLEMENTATIONS = [
    Implementation("centres_for_disks", "the centres' ordinary diagram, radii attached", "O(n^2)", ordinary_build,
                   build_apollonius=points_for_disks),
    Implementation("wrong_after_first", "right on its warm-up and first repeat only", "O(n^2)", ordinary_build,
                   build_apollonius=_wrong_after_first),
    Implementation("radii_forger", "sends its diagram with other radii", "O(n^2)", ordinary_build,
                   build_apollonius=_radii_forger),
]
