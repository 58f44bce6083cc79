"""Constructions of disks for tests of the pipeline: the oracle under another name, and a broken
one (the ordinary diagram of the centres passed off as the diagram of the disks). Module-level
functions, so that an implementation registered in a test crosses to its sandbox."""

from __future__ import annotations

from impls.halfplane import build as ordinary_build
from impls.halfplane_disks import build as disks_build
from vorobench.core.diagram import Diagram


def points_for_disks(sites, radii, stats=None) -> Diagram:
    """The ordinary diagram of the centres, with the radii attached: wrong wherever radii differ."""
    d = ordinary_build(sites)
    return Diagram(d.sites, d.vertices, d.origin, d.twin, d.next, d.site, radii=radii)


def oracle(sites, radii, stats=None) -> Diagram:
    """The exact oracle for disks."""
    return disks_build(sites, radii, stats)
