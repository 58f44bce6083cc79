"""Input checking and deduplication: every implementation sees distinct finite float64 sites."""

from __future__ import annotations

import numpy as np
from numba import njit
from numpy.typing import ArrayLike, NDArray

from vorobench.core.prefetch import prefetch
from vorobench.core.scaling import check_exact_range, check_span, check_weight_range

__all__ = ["prepare", "prepare_weighted", "prepare_disks"]


def _as_real_array(points: ArrayLike, what: str = "points") -> NDArray[np.float64]:
    """Convert to a float64 array without silently accepting strings, complex or objects;
    messages name ``what`` (points or weights)."""
    shape = "(n, 2)" if what == "points" else "(n,)"
    if isinstance(points, (str, bytes)):
        raise ValueError(f"{what} must be an array of shape {shape} of real numbers, got a string")
    try:
        arr = np.asarray(points)
    except (ValueError, TypeError) as exc:  # ragged nested sequences
        raise ValueError(f"{what} could not be read as an {shape} array: {exc}") from None
    kind = arr.dtype.kind
    if kind == "c":
        raise ValueError(f"{what} must be real numbers, got complex values")
    if kind in "USV":
        raise ValueError(f"{what} must be real numbers, got {arr.dtype} (strings or bytes)")
    if kind == "O":
        raise ValueError(f"{what} must be real numbers, got Python objects (ragged rows or mixed types?)")
    if kind not in "biuf":
        raise ValueError(f"{what} must be real numbers, got dtype {arr.dtype}")
    return arr


@njit(cache=True)
def _normalised_copy(arr, out):
    """One pass over (n, 2) float64 rows into ``out`` (numpy's: huge pages, see
    :func:`vorobench.core.delaunay_dual.voronoi_dcel`): (the copy with -0.0 made 0.0, so that equal
    points have equal bits; the first row with a non-finite value or -1; the largest magnitude;
    the smallest nonzero magnitude, inf if none). The copy stops at a non-finite row."""
    n = arr.shape[0]
    hi, lo = 0.0, np.inf
    for i in range(n):
        for k in range(2):
            v = arr[i, k]
            if not np.isfinite(v):
                return i, hi, lo
            out[i, k] = v + 0.0
            a = abs(v)
            if a > hi:
                hi = a
            if 0.0 < a < lo:
                lo = a
    return -1, hi, lo


@njit(cache=True)
def _mix(x):
    # splitmix64's finaliser: every input bit moves every output bit (uint64 arithmetic wraps)
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return x ^ (x >> np.uint64(31))


#: How many rows ahead :func:`_first_appearance` asks for the table slot it will probe: the
#: slots are random in a table larger than the caches, and the loop would otherwise wait on
#: each (0.073 s at 10^6 uniform before, 0.024 s after, with the tags below).
SLOT_AHEAD = 16


def _first_appearance(bits):
    """(site of each row, rows that start a site) for rows of two uint64 bit patterns: equal
    rows share a site, sites numbered in order of first appearance (:func:`_first_appearance_in`
    on tables numpy allocates: huge pages, 40 MB at 10^6 rows)."""
    n = bits.shape[0]
    size = 1
    while size < 2 * n:
        size *= 2
    table = np.full(size, -1, dtype=np.int64)          # (tag << 32) | row, or -1 for free
    site_of_row = np.empty(n, dtype=np.intp)
    firsts = np.empty(n, dtype=np.intp)
    m = _first_appearance_in(bits, np.empty(n, dtype=np.uint64), table, site_of_row, firsts)
    return site_of_row, firsts[:m]


@njit(cache=True)
def _first_appearance_in(bits, hashes, table, site_of_row, firsts):
    """:func:`_first_appearance` into its arrays; returns the number of sites. One pass over an
    open addressing table of twice the rows' size: O(n) expected, no sort.

    An entry holds the row that started a site and 31 more bits of its hash (a tag), so a
    probe that meets another site's row reads that row only when the tags agree: almost
    only at a true duplicate."""
    n = bits.shape[0]
    mask = np.uint64(table.size - 1)
    for i in range(n):
        hashes[i] = _mix(bits[i, 0] ^ _mix(bits[i, 1]))
    m = 0
    for i in range(n):
        if i + SLOT_AHEAD < n:
            prefetch(table, np.intp(hashes[i + SLOT_AHEAD] & mask))
        slot = hashes[i] & mask
        tag = np.int64(hashes[i] >> np.uint64(33))     # < 2**31: an entry is never negative
        while True:
            entry = table[slot]
            if entry < 0:
                table[slot] = (tag << 32) | i
                site_of_row[i] = m
                firsts[m] = i
                m += 1
                break
            if (entry >> 32) == tag:
                j = entry & 0xFFFFFFFF
                if bits[j, 0] == bits[i, 0] and bits[j, 1] == bits[i, 1]:
                    site_of_row[i] = site_of_row[j]
                    break
            slot = (slot + np.uint64(1)) & mask
    return m


def prepare(points: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """Check points and return ``(sites, inverse)``.

    ``sites`` holds the distinct points in order of first appearance (float64, C-contiguous,
    shape (m, 2)); ``inverse[i]`` is the site of input row i. n = 0 is allowed. Raises
    ``ValueError`` naming the problem (and the first offending row for NaN/inf), and
    :class:`~vorobench.core.scaling.OutsideExactRange` (a ``ValueError``) for points whose nonzero
    magnitudes span more than the predicates' exact range after any power-of-two scaling
    (1.0 together with 1e-300; see :mod:`vorobench.core.scaling`): refused here, before any
    implementation sees them, every implementation is refused the same way.
    """
    arr = _as_real_array(points)
    if arr.ndim == 1 and arr.size == 0:
        arr = arr.reshape(0, 2)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2), got shape {arr.shape}")
    given = np.ascontiguousarray(arr, dtype=np.float64)
    n = given.shape[0]
    if n == 0:
        return given, np.zeros(0, dtype=np.intp)
    if n >= 2**31 - 1:
        raise ValueError(f"{n} points: at most 2**31 - 2 are supported (row ids are 32-bit in the duplicate table)")
    # one pass: the finiteness check, the magnitudes for the range check, and our own copy
    arr = np.empty((n, 2), dtype=np.float64)
    bad, hi, lo = _normalised_copy(given, arr)
    if bad >= 0:
        finite = np.isfinite(given).all(axis=1)
        raise ValueError(f"points must be finite: row {bad} is {given[bad].tolist()} "
                         f"({int((~finite).sum())} non-finite row(s) in all)")
    check_span(hi, lo, arr)
    inverse, firsts = _first_appearance(arr.view(np.uint64))
    if firsts.size == n:
        return arr, np.arange(n, dtype=np.intp)
    return np.ascontiguousarray(arr[firsts]), inverse


def prepare_weighted(points: ArrayLike, weights: ArrayLike
                     ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """:func:`prepare` for weighted sites: ``(sites, site_weights, inverse)``.

    ``weights`` holds one real, finite number per input row (the power of x with respect to
    site i is |x - p_i|^2 - w_i). Equal rows become one site, which keeps the largest of
    their weights: the others' cells would be empty under it. Raises ``ValueError`` naming
    the problem and the first offending row.
    """
    sites, inverse = prepare(points)
    w = _as_real_array(weights, "weights")
    if w.ndim != 1 or w.shape[0] != inverse.shape[0]:
        raise ValueError(f"weights must have shape ({inverse.shape[0]},), one per point, got shape {w.shape}")
    w = np.asarray(w, dtype=np.float64)
    finite = np.isfinite(w)
    if not finite.all():
        row = int(np.flatnonzero(~finite)[0])
        raise ValueError(f"weights must be finite: row {row} is {w[row]} ({int((~finite).sum())} non-finite in all)")
    if sites.shape[0] == w.shape[0]:
        site_weights = w + 0.0
    else:
        site_weights = np.full(sites.shape[0], -np.inf)
        np.maximum.at(site_weights, inverse, w)
    check_weight_range(sites, site_weights)
    return sites, np.ascontiguousarray(site_weights), inverse


def prepare_disks(points: ArrayLike, radii: ArrayLike
                  ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """:func:`prepare` for disks: ``(centres, site_radii, inverse)``.

    ``radii`` holds one finite number >= 0 per input row. Rows with one centre become one
    site, which keeps the largest of their radii: the smaller disks lie inside it and are
    hidden (docs/apollonius.md). Raises ``ValueError`` naming the problem and the first
    offending row; the centres and radii together must fit the exact range after one
    power-of-two scaling.
    """
    sites, inverse = prepare(points)
    r = _as_real_array(radii, "radii")
    if r.ndim != 1 or r.shape[0] != inverse.shape[0]:
        raise ValueError(f"radii must have shape ({inverse.shape[0]},), one per point, got shape {r.shape}")
    r = np.asarray(r, dtype=np.float64)
    bad = ~np.isfinite(r) | (r < 0)
    if bad.any():
        row = int(np.flatnonzero(bad)[0])
        raise ValueError(f"radii must be finite and >= 0: row {row} is {r[row]} ({int(bad.sum())} such rows in all)")
    if sites.shape[0] == r.shape[0]:
        site_radii = r + 0.0
    else:
        site_radii = np.zeros(sites.shape[0])
        np.maximum.at(site_radii, inverse, r)
    check_exact_range(np.vstack([sites, np.column_stack([site_radii, site_radii])]))
    return sites, np.ascontiguousarray(site_radii), inverse
