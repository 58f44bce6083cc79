"""Peak resident memory of this process, resettable on Linux so each build's own peak shows.

On Linux, writing ``5`` to ``/proc/self/clear_refs`` resets the high-water mark ``VmHWM``;
elsewhere (or if that is refused) the never-reset ``ru_maxrss`` of ``getrusage`` is used, which
still shows a build's peak whenever it exceeds everything before it.
"""

from __future__ import annotations

import resource
import sys
from pathlib import Path

__all__ = ["current_rss_mb", "peak_rss_mb", "reset_peak"]

_STATUS = Path("/proc/self/status")
_CLEAR_REFS = Path("/proc/self/clear_refs")
_MB = 1024.0 * 1024.0


def _status_kb(field: str) -> int | None:
    try:
        for line in _STATUS.read_text().splitlines():
            if line.startswith(field + ":"):
                return int(line.split()[1])
    except (OSError, ValueError, IndexError):
        pass
    return None


def _maxrss_mb() -> float:
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    # ru_maxrss is in kilobytes on Linux but in bytes on macOS.
    return rss / _MB if sys.platform == "darwin" else rss / 1024.0


def current_rss_mb() -> float:
    """Resident memory now, in MiB (falls back to the peak where the current value is unknown)."""
    kb = _status_kb("VmRSS")
    return kb / 1024.0 if kb is not None else _maxrss_mb()


def peak_rss_mb() -> float:
    """Highest resident memory since the last successful :func:`reset_peak`, in MiB."""
    kb = _status_kb("VmHWM")
    return kb / 1024.0 if kb is not None else _maxrss_mb()


def reset_peak() -> bool:
    """Reset the high-water mark to the current resident size; False if the OS refuses."""
    try:
        _CLEAR_REFS.write_text("5")
        return True
    except OSError:
        return False
