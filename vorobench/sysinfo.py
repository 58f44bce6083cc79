"""Machine and software metadata recorded with every benchmark run, so results can be traced."""

from __future__ import annotations

import datetime as _dt
import os
import platform
import socket
import subprocess
from importlib import metadata
from pathlib import Path
from typing import Optional

__all__ = ["cpu_model", "git_commit", "load_average", "package_versions", "run_metadata"]

#: Distributions whose versions change timings (or results) and so are recorded.
_PACKAGES = ("vorobench", "numpy", "scipy", "numba", "llvmlite", "pandas", "matplotlib")


def cpu_model() -> str:
    """The CPU's marketing name (Linux /proc/cpuinfo, else platform's guess)."""
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.lower().startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine() or "unknown"


def git_commit(root: Optional[Path] = None) -> dict[str, object]:
    """The checked-out commit of the project tree and whether it has uncommitted changes."""
    root = Path(root) if root is not None else Path(__file__).resolve().parent.parent
    info: dict[str, object] = {"commit": None, "dirty": None}
    try:
        commit = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True,
                                text=True, timeout=10)
        if commit.returncode == 0:
            info["commit"] = commit.stdout.strip()
            status = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                                    cwd=root, capture_output=True, text=True, timeout=10)
            info["dirty"] = bool(status.stdout.strip()) if status.returncode == 0 else None
    except (OSError, subprocess.SubprocessError):
        pass
    return info


def package_versions() -> dict[str, Optional[str]]:
    """Installed versions of the packages that matter for timings (None if absent)."""
    out: dict[str, Optional[str]] = {}
    for name in _PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = None
    return out


def load_average() -> Optional[list[float]]:
    """The 1, 5 and 15 minute load averages (None where the OS has none): above the core count,
    other processes compete for the CPU and timings are noisy."""
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except (OSError, AttributeError):
        return None


def run_metadata() -> dict[str, object]:
    """Everything needed to interpret a run later: date, commit, versions, machine."""
    git = git_commit()
    return {
        "date": _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds"),
        "commit": git["commit"],
        "dirty": git["dirty"],
        "python": platform.python_version(),
        "python_implementation": platform.python_implementation(),
        "versions": package_versions(),
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "machine": platform.machine(),
        "platform": platform.platform(),
        "hostname": socket.gethostname(),
        "load_average": load_average(),
    }
