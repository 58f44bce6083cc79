"""scipy-style ``regions`` as a read-only sequence over two flat arrays.

scipy hands out a list of lists. Building a million small lists costs seconds. The caller could
also change them, and so the cached regions of an immutable ``Diagram``. A ``Regions`` keeps the
vertex ids of all cells in one read-only array, with an offset per cell. Each item it hands out
is a new list, so changing it changes nothing here.
"""

from __future__ import annotations

import gc
import operator
from collections.abc import Iterator, Sequence
from typing import overload

import numpy as np
from numpy.typing import NDArray

__all__ = ["Regions"]


class Regions(Sequence):
    """The vertices of each cell counter-clockwise, -1 where it is unbounded; item i is a new
    ``list[int]`` (equal to scipy's ``regions[i]``), and the whole compares equal to a list of
    lists with the same items."""

    __slots__ = ("_flat", "_offsets")

    def __init__(self, flat: NDArray[np.integer], offsets: NDArray[np.integer], *, copy: bool = True) -> None:
        """``copy=False`` keeps ``flat`` itself (read-only from then on): for an array no one
        else holds."""
        self._flat = np.array(flat) if copy else np.asarray(flat)   # int32 ids stay int32
        if self._flat.size == 0:
            self._flat = self._flat.reshape(0).astype(np.int64)
        if self._flat.ndim != 1 or not np.issubdtype(self._flat.dtype, np.integer):
            raise ValueError(f"vertex ids must be a 1-D integer array, not {self._flat.ndim}-D {self._flat.dtype}")
        offsets = np.asarray(offsets)
        if offsets.size and not np.issubdtype(offsets.dtype, np.integer):
            raise ValueError(f"offsets must be integers, not {offsets.dtype}")
        self._offsets = offsets.astype(np.int64)
        if self._offsets.ndim != 1 or self._offsets.size < 1 or self._offsets[0] != 0 \
                or self._offsets[-1] != self._flat.size or (np.diff(self._offsets) < 0).any():
            raise ValueError("offsets must rise from 0 to the number of vertex ids")
        self._flat.flags.writeable = False
        self._offsets.flags.writeable = False

    def __len__(self) -> int:
        return int(self._offsets.size - 1)

    @overload
    def __getitem__(self, i: int) -> list[int]: ...

    @overload
    def __getitem__(self, i: slice) -> list[list[int]]: ...

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        try:
            k = operator.index(i)
        except TypeError:
            raise TypeError(f"regions are indexed by integers or slices, not {type(i).__name__}") from None
        n = len(self)
        if k < -n or k >= n:
            raise IndexError(f"region {i} out of range for {n} regions")
        k %= n
        return self._flat[self._offsets[k]:self._offsets[k + 1]].tolist()

    def __iter__(self) -> Iterator[list[int]]:
        flat, bounds = self._flat.tolist(), self._offsets.tolist()
        for k in range(len(bounds) - 1):
            yield flat[bounds[k]:bounds[k + 1]]

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Regions):
            return np.array_equal(self._flat, other._flat) and np.array_equal(self._offsets, other._offsets)
        if isinstance(other, list):
            return len(other) == len(self) and all(mine == theirs for mine, theirs in zip(self, other))
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]  # equal to lists, which do not hash

    def __reduce__(self):
        # pickled as its two arrays (every protocol; __slots__ alone would refuse 0 and 1)
        return (Regions, (self._flat, self._offsets))

    def tolist(self) -> list[list[int]]:
        """All regions as a new list of lists (what scipy's ``regions`` is), e.g. for ``json``."""
        # A million small lists would wake the cyclic garbage collector hundreds of times
        # (4x the time at 10^6 sites, measured); none of them can be part of a cycle.
        collecting = gc.isenabled()
        gc.disable()
        try:
            return list(self)
        finally:
            if collecting:
                gc.enable()

    def __repr__(self) -> str:
        shown = ", ".join(str(r) for r in self[:3])
        return f"Regions({len(self)} cells: [{shown}{', ...' if len(self) > 3 else ''}])"
