"""Read-only views, so that a compiled kernel meets one kind of array.

numba compiles a kernel once for each type of argument, and a read-only array is another type
than a writable one. A kernel handed the Diagram's arrays (read-only) in one call and fresh
arrays in the next is compiled twice, in every process that meets it. Handing its input arrays
over as read-only views, always, keeps one compilation; a view copies nothing.
"""

from __future__ import annotations

from numpy.typing import NDArray

__all__ = ["read_only"]


def read_only(arr: NDArray) -> NDArray:
    """A read-only view of ``arr`` (the same memory; ``arr`` itself keeps its flags)."""
    view = arr.view()
    view.setflags(write=False)
    return view
