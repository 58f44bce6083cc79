"""Machine and software metadata recorded with every benchmark run, so results can be traced."""

from __future__ import annotations

import datetime as _dt
import hashlib
import os
import platform
import socket
import subprocess
import sys
from importlib import metadata
from pathlib import Path
from typing import Optional, Sequence

import impls

__all__ = ["provenance_here", "sandboxed_provenance", "cpu_model", "git_commit", "load_average", "package_versions", "library_versions", "machine_id",
           "code_provenance", "run_metadata"]

#: Distributions whose versions change timings (or results) and so are recorded.
_PACKAGES = ("vorobench", "numpy", "scipy", "numba", "llvmlite", "pandas", "matplotlib", "triangle", "pyvoronoi",
             "shapely", "cgal")


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


def library_versions() -> dict[str, Optional[str]]:
    """The geometry libraries behind the outside references, as far as each one tells (None if
    absent): Qhull comes inside scipy, Boost.Polygon inside pyvoronoi, GEOS inside shapely, CGAL
    compiled into its bindings (the release from ``CGAL_VERSION_NR``, then the package's version)."""
    versions = package_versions()
    out: dict[str, Optional[str]] = {
        "qhull": f"bundled with scipy {versions['scipy']}" if versions.get("scipy") else None,
        "triangle": versions.get("triangle"),
        "boost_polygon": f"bundled with pyvoronoi {versions['pyvoronoi']}" if versions.get("pyvoronoi") else None,
        "geos": None,
        "cgal": versions.get("cgal"),
    }
    if versions.get("shapely"):
        try:
            # an optional outside library: its version only where it is installed
            import shapely

            out["geos"] = str(shapely.geos_version_string)
        except Exception:  # a broken shapely install is recorded as "unknown", not fatal
            out["geos"] = "unknown"
    if versions.get("cgal"):
        try:
            # an optional outside library, as above
            from CGAL.CGAL_Triangulation_2 import CGAL_VERSION_NR

            nr = int(CGAL_VERSION_NR)       # 1MMmmbiiii: major, minor, bug-fix release
            out["cgal"] = (f"{nr // 10**7 % 100}.{nr // 10**5 % 100}.{nr // 10**4 % 10} "
                           f"(Python package cgal {versions['cgal']})")
        except Exception:  # bindings that do not load: the package version alone
            pass
    return out


def _total_memory_gb() -> Optional[float]:
    try:
        return round(os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30, 1)
    except (ValueError, OSError, AttributeError):
        return None


def machine_id() -> str:
    """A short fingerprint of the hardware and OS that timings depend on (CPU model, core
    count, memory, architecture, OS), not of the host name: two runners of one kind share it,
    and timings are only compared within one fingerprint."""
    parts = [cpu_model(), str(os.cpu_count()), str(_total_memory_gb()), platform.machine(), platform.system()]
    return hashlib.sha256("|".join(parts).encode()).hexdigest()[:12]


def _entry_point_distribution(name: str) -> Optional[metadata.Distribution]:
    """The installed distribution whose entry point in the group ``vorobench.impls`` is called
    ``name`` (None if there is none)."""
    try:
        for ep in metadata.entry_points(group=impls.ENTRY_POINT_GROUP):
            if ep.name == name and ep.dist is not None:
                return ep.dist
    except Exception:  # a broken installed distribution must not cost us the run
        pass
    return None


def code_provenance(names: Sequence[str]) -> dict[str, dict[str, object]]:
    """Where each implementation's code comes from: its module, file, distribution and version,
    and the commit and dirty flag of the git tree holding its file (plugins under development
    are usually in one); None where a piece cannot be found.

    The distribution is the one that installs the build function's top-level package; for an
    implementation registered by an entry point, the entry point's own distribution when that
    package has several owners or none (a build imported from another library, a partial).
    """
    try:
        owners = metadata.packages_distributions()
    except Exception:  # a broken installed distribution must not cost us the run
        owners = {}
    out: dict[str, dict[str, object]] = {}
    for name in names:
        info: dict[str, object] = {"module": None, "file": None, "distribution": None, "version": None,
                                   "commit": None, "dirty": None}
        try:
            build = impls.get(name).build
            module_name = str(getattr(build, "__module__", None) or "")
            module = sys.modules.get(module_name)
            info["module"] = module_name or None
            path = Path(getattr(module, "__file__", "") or "")
            if path.is_file():
                info["file"] = str(path.resolve())
                info.update(git_commit(path.resolve().parent))
            dists = owners.get(module_name.split(".")[0], []) if module_name else []
            # A --plugin module registered in this process shadows an entry point of its name.
            registrar = None if name in impls.registered() else _entry_point_distribution(name)
            if registrar is not None and (len(dists) != 1 or registrar.name in dists):
                info["distribution"], info["version"] = registrar.name, registrar.version
            elif dists:
                info["distribution"] = dists[0]
                info["version"] = metadata.version(dists[0])
        except Exception:  # an implementation that cannot load is reported by the run itself
            pass
        out[name] = info
    return out


def provenance_here(names: Sequence[str], plugins: Sequence[str] = ()) -> tuple[dict, None]:
    """Runs in a sandbox: :func:`code_provenance` of ``names`` with ``plugins`` loaded there
    (finding a module's file imports it: never in the judging process)."""
    from impls.plugins import load_plugin

    for spec in plugins:
        load_plugin(spec)
    return code_provenance(names), None


def sandboxed_provenance(names: Sequence[str], plugins: Sequence[str] = (), timeout: float = 120.0
                         ) -> dict[str, dict[str, object]]:
    """:func:`code_provenance` of ``names``, read in a throwaway sandbox: plain data back, each
    entry's fields kept only when they are what provenance is (text, a flag or nothing)."""
    from vorobench.judge.sandbox import Sandbox

    box = Sandbox(None, warmup_timeout=timeout)
    try:
        outcome = box.call(provenance_here, list(names), tuple(plugins), timeout=timeout, step="reading provenance")
    finally:
        box.close()
    data = outcome.value[0] if outcome.ok else None
    empty = {"module": None, "file": None, "distribution": None, "version": None, "commit": None, "dirty": None}
    out = {}
    for name in names:
        entry = data.get(name) if isinstance(data, dict) else None
        entry = entry if isinstance(entry, dict) else {}
        out[name] = {k: (entry.get(k) if type(entry.get(k)) in (str, bool, type(None)) else None) for k in empty}
    return out


def load_average() -> Optional[list[float]]:
    """The 1, 5 and 15 minute load averages (None where the OS has none): above the core count,
    other processes compete for the CPU and timings are noisy."""
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except (OSError, AttributeError):
        return None


def run_metadata(impl_names: Sequence[str] = (), plugins: Sequence[str] = ()) -> dict[str, object]:
    """Everything needed to interpret a run later: date, commit, versions, machine, and where
    the code of each implementation in ``impl_names`` comes from (read in a sandbox, with the
    run's ``plugins``)."""
    git = git_commit()
    return {
        "date": _dt.datetime.now(_dt.timezone.utc).astimezone().isoformat(timespec="seconds"),
        "commit": git["commit"],
        "dirty": git["dirty"],
        "python": platform.python_version(),
        "python_implementation": platform.python_implementation(),
        "versions": package_versions(),
        "libraries": library_versions(),
        "implementations": sandboxed_provenance(impl_names, plugins) if impl_names else {},
        "machine_id": machine_id(),
        "memory_gb": _total_memory_gb(),
        "cpu": cpu_model(),
        "cores": os.cpu_count(),
        "machine": platform.machine(),
        "platform": platform.platform(),
        "hostname": socket.gethostname(),
        "load_average": load_average(),
    }
