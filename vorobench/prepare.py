"""Input checking and deduplication: every implementation sees distinct finite float64 sites."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from vorobench.scaling import check_exact_range

__all__ = ["prepare"]


def _as_real_array(points: ArrayLike) -> NDArray[np.float64]:
    """Convert to a float64 array without silently accepting strings, complex or objects."""
    if isinstance(points, (str, bytes)):
        raise ValueError("points must be an array of shape (n, 2) of real numbers, got a string")
    try:
        arr = np.asarray(points)
    except (ValueError, TypeError) as exc:  # ragged nested sequences
        raise ValueError(f"points could not be read as an (n, 2) array: {exc}") from None
    kind = arr.dtype.kind
    if kind == "c":
        raise ValueError("points must be real numbers, got complex values")
    if kind in "USV":
        raise ValueError(f"points must be real numbers, got {arr.dtype} (strings or bytes)")
    if kind == "O":
        raise ValueError("points must be real numbers, got Python objects (ragged rows or mixed types?)")
    if kind not in "biuf":
        raise ValueError(f"points must be real numbers, got dtype {arr.dtype}")
    return arr


def prepare(points: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.intp]]:
    """Check points and return ``(sites, inverse)``.

    ``sites`` holds the distinct points in order of first appearance (float64, C-contiguous,
    shape (m, 2)); ``inverse[i]`` is the site of input row i. n = 0 is allowed. Raises
    ``ValueError`` naming the problem (and the first offending row for NaN/inf), and
    :class:`~vorobench.scaling.OutsideExactRange` (a ``ValueError``) for points whose nonzero
    magnitudes span more than the predicates' exact range after any power-of-two scaling
    (1.0 together with 1e-300; see :mod:`vorobench.scaling`): refused here, before any
    implementation sees them, every implementation is refused the same way.
    """
    arr = _as_real_array(points)
    if arr.ndim == 1 and arr.size == 0:
        arr = arr.reshape(0, 2)
    if arr.ndim != 2 or arr.shape[1] != 2:
        raise ValueError(f"points must have shape (n, 2), got shape {arr.shape}")
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    finite = np.isfinite(arr).all(axis=1)
    if not finite.all():
        row = int(np.flatnonzero(~finite)[0])
        raise ValueError(
            f"points must be finite: row {row} is {arr[row].tolist()} "
            f"({int((~finite).sum())} non-finite row(s) in all)"
        )
    n = arr.shape[0]
    if n == 0:
        return arr, np.zeros(0, dtype=np.intp)
    check_exact_range(arr)
    # -0.0 and 0.0 are the same point: normalise so that the byte-level unique agrees.
    arr = arr + 0.0
    _, first, inverse = np.unique(arr, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    if first.size == n:
        return arr, np.arange(n, dtype=np.intp)
    # Renumber the unique rows by first appearance.
    order = np.argsort(first, kind="stable")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    sites = np.ascontiguousarray(arr[first[order]])
    return sites, rank[inverse].astype(np.intp)
