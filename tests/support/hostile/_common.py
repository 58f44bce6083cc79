"""What the hostile plugins share: where each import is recorded, and a wrong diagram."""

from __future__ import annotations

import os

import numpy as np

from impls.qhull import build as qhull_build
from vorobench.core.diagram import Diagram


def record_import(tag: str) -> None:
    """Append ``tag pid`` to $VOROBENCH_TEST_IMPORT_LOG: which processes imported a plugin."""
    log = os.environ.get("VOROBENCH_TEST_IMPORT_LOG")
    if log:
        with open(log, "a") as f:
            f.write(f"{tag} {os.getpid()}\n")


def swapped_cells(sites, stats=None) -> Diagram:
    """Qhull's diagram with the cells of sites 0 and 1 swapped: wrong for any n >= 3."""
    d = qhull_build(sites, stats)
    site = np.array(d.site)
    zero, one = site == 0, site == 1
    site[zero], site[one] = 1, 0
    return Diagram(d.sites, d.vertices, d.origin, d.twin, d.next, site)
