"""What the sites of a benchmark case may carry besides their coordinates, said once for the
whole bench path: weights (power diagrams, ``bench --weights``) or radii (disks, ``bench
--radii``, docs/apollonius.md).

A :class:`SiteAttribute` knows its results column (also the keyword by which the engine and
``Implementation.run`` take the values), how its values are drawn and prepared, how they scale
when the sites are scaled by a power of two (a weight is a squared length, a radius a length),
and which declaration says that an implementation builds such cases. A case has one attribute
or none (:func:`attribute_of`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Optional

import numpy as np
from numpy.typing import ArrayLike

import datasets_gen
from vorobench.judge.declarations import Declaration
from vorobench.judge.engine import NO_DISKS, NO_WEIGHTS, prepare_case, prepare_disk_case

__all__ = ["SiteAttribute", "WEIGHTS", "RADII", "ATTRIBUTES", "attribute_of", "keywords", "generate_input"]


@dataclass(frozen=True)
class SiteAttribute:
    """One value per site, of one kind: weights or radii."""

    #: The results column, the command-line option and the engine's keyword: "weights" or "radii".
    name: str
    #: The power of a length the values are: 2 for weights, 1 for radii (how they scale).
    length_power: int
    #: The :class:`Declaration` field that says an implementation builds such cases.
    declared: str
    #: The engine's reason an implementation that does not is ``unsupported`` (NO_WEIGHTS, NO_DISKS).
    refusal: str
    #: What an implementation that does not take them builds instead, for its row's error.
    instead: str
    #: Such cases, for messages ("weighted cases", "cases of disks").
    cases: str
    #: ``datasets_gen.weights`` or ``datasets_gen.radii``: the values of a family for points.
    draw_values: Callable[..., np.ndarray]
    #: ``prepare_case`` or ``prepare_disk_case``: rows at one place merged as the judge does.
    prepare_values: Callable[..., tuple]

    def takes(self, declared: Declaration) -> bool:
        """Whether an implementation so declared builds cases with this attribute."""
        return bool(getattr(declared, self.declared))

    def draw(self, family: str, points: np.ndarray, seed: int) -> np.ndarray:
        """The values of ``family`` for ``points`` (one per row, duplicates included)."""
        return self.draw_values(family, points, seed=seed)

    def prepare(self, points: ArrayLike, values: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """The case's sites and their values as the judge takes them (rows at one place merged)."""
        sites, site_values = self.prepare_values(points, values)
        return sites, site_values

    def scaled(self, values: np.ndarray, shift: int) -> np.ndarray:
        """The values of the sites times ``2**shift`` (exact, as the sites' own scaling)."""
        return values if shift == 0 else np.ldexp(values, self.length_power * shift)

    def range_rows(self, sites: np.ndarray, values: np.ndarray) -> np.ndarray:
        """The numbers the exact range is decided on: for radii, lengths scaled with the
        sites, the sites and the radii together (as ``Implementation.run`` places them); for
        weights the sites alone (a weight's own range is checked by the build)."""
        if self.length_power != 1:
            return sites
        return np.vstack([sites, np.column_stack([values, values])])


WEIGHTS = SiteAttribute("weights", 2, "weighted", NO_WEIGHTS, "builds ordinary Voronoi diagrams only",
                        "weighted cases", datasets_gen.weights, prepare_case)
RADII = SiteAttribute("radii", 1, "apollonius", NO_DISKS, "builds no diagrams of disks (docs/apollonius.md)",
                      "cases of disks", datasets_gen.radii, prepare_disk_case)

#: Every attribute, by its name.
ATTRIBUTES: dict[str, SiteAttribute] = {a.name: a for a in (WEIGHTS, RADII)}


def attribute_of(weights: str = "", radii: str = "") -> tuple[Optional[SiteAttribute], str]:
    """(attribute, family) of a case with weight family ``weights`` or radius family ``radii``
    ((None, "") for an ordinary case); ValueError for both: a case has weights or radii, never
    both (a power diagram of disks is no diagram vorobench knows)."""
    if weights and radii:
        raise ValueError("--weights (power diagrams) and --radii (disks) go one at a time")
    if weights:
        return WEIGHTS, weights
    if radii:
        return RADII, radii
    return None, ""


def keywords(attribute: Optional[SiteAttribute], values: Optional[np.ndarray]) -> dict[str, np.ndarray]:
    """The keyword by which the engine and ``Implementation.run`` take a case's values
    (``{"radii": r}``), or none for an ordinary case."""
    return {} if attribute is None or values is None else {attribute.name: values}


def generate_input(dataset: str, n: int, seed: int, attribute: Optional[SiteAttribute], family: str
                   ) -> tuple[np.ndarray, np.ndarray, Optional[np.ndarray]]:
    """(points, sites, site values or None) of a case: its dataset's points at size ``n``, the
    values of ``family`` drawn for them (seeded like the points), prepared as the judge takes them."""
    points = datasets_gen.generate(dataset, n, seed=seed)
    if attribute is None:
        return (points, *prepare_case(points))
    return (points, *attribute.prepare(points, attribute.draw(family, points, seed)))
