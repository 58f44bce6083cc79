#!/usr/bin/env python3
"""Set up the project's virtual environment if needed, then run a job in it.

    python3 dev.py demo    # default benchmark + cross-validation, report under reports/
    python3 dev.py test    # the test suite (what CI runs)
    python3 dev.py bench   # pytest-benchmark suite (not part of the tests)
    python3 dev.py setup [--references]
                           # the venv only; --references also installs the toolchains of the
                           # shipped executable references (apt-get as root: g++ libcgal-dev
                           # qhull-bin nodejs npm) and builds them (CGAL compile, npm ci)

Only python3 (3.11+) is assumed: the venv and every dependency are installed from
pyproject.toml into ./.venv the first time, and again whenever pyproject.toml changes.
``test`` first compiles the numba kernels into numba's cache, in two processes side by side
(about two minutes on a fresh clone; a few seconds of loading after that), then runs the tests
on up to four workers (pytest-xdist, one per core; ``-n 0`` runs them in this process).
"""

from __future__ import annotations

import os
import subprocess
import sys
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parent
VENV = ROOT / ".venv"
BIN = VENV / ("Scripts" if os.name == "nt" else "bin")
PYTHON = BIN / ("python.exe" if os.name == "nt" else "python")
STAMP = VENV / ".installed"
EXTRAS = "test,peers,dask"


def ensure_venv() -> None:
    """Create .venv and install the project (editable) with its test extra when stale."""
    if sys.version_info < (3, 11):
        sys.exit(f"vorobench needs Python 3.11 or newer, this is {sys.version.split()[0]}")
    if not PYTHON.exists():
        print(f"creating virtual environment in {VENV}", flush=True)
        venv.EnvBuilder(with_pip=True).create(VENV)
    wanted = (ROOT / "pyproject.toml").read_text() + EXTRAS
    if STAMP.exists() and STAMP.read_text() == wanted:
        return
    print("installing vorobench and its dependencies into .venv", flush=True)
    pip = [str(PYTHON), "-m", "pip", "--disable-pip-version-check"]
    subprocess.run(pip + ["install", "-q", "--upgrade", "pip"], check=True)
    subprocess.run(pip + ["install", "-q", "-e", f".[{EXTRAS}]"], check=True, cwd=ROOT)
    STAMP.write_text(wanted)


#: What each shipped executable reference needs, and the Debian package that provides it.
REFERENCE_TOOLS = {"g++": "g++", "/usr/include/CGAL/Delaunay_triangulation_2.h": "libcgal-dev",
                   "qvoronoi": "qhull-bin", "node": "nodejs", "npm": "npm"}


def _missing_tools() -> list[str]:
    """The Debian packages of REFERENCE_TOOLS whose program or file is not here."""
    import shutil

    return [package for tool, package in REFERENCE_TOOLS.items()
            if not (Path(tool).exists() if os.sep in tool else shutil.which(tool))]


def install_references() -> int:
    """Install the references' toolchains where this machine allows it (apt-get as root),
    then build every reference whose toolchain is present; the others are said, not failed."""
    missing = _missing_tools()
    if missing:
        command = ["apt-get", "install", "-y", "-q", "--no-install-recommends", *missing]
        if hasattr(os, "geteuid") and os.geteuid() == 0 and Path("/usr/bin/apt-get").exists():
            print(f"installing {' '.join(missing)} with apt-get", flush=True)
            env = {**os.environ, "DEBIAN_FRONTEND": "noninteractive"}
            if subprocess.call(["apt-get", "update", "-q"], env=env) != 0 or subprocess.call(command, env=env) != 0:
                print("apt-get failed: the references whose toolchain is missing stay unavailable", flush=True)
        else:
            print(f"not root (or no apt-get): install {' '.join(missing)} yourself, e.g. "
                  f"`sudo apt-get update && sudo {' '.join(command)}`", flush=True)
    return run(["-c", "from impls.executable import build_references; raise SystemExit(build_references())"])


#: The numba kernels most tests need, in two groups of about equal compile time on a fresh
#: clone (measured: 114 s for the sweeps and the judge's comparison, 136 s for the rest, each
#: alone on a core). Warming the outside libraries' adapters too did not make the run faster
#: (1,050 s against 995 s, one fresh clone each): few tests use them.
WARM_KERNELS = (
    """
import datasets_gen, impls
from vorobench.judge.comparison import compare
impls.builtin("fortune").warmup()
sites = datasets_gen.generate("uniform", 50, seed=1)
for weights in (None, datasets_gen.weights("radii", sites, seed=1)):
    exact = impls.build("fortune", sites, weights=weights)
    compare(exact, impls.build("incremental", sites, weights=weights))
    compare(exact, impls.build("qhull", sites, weights=weights))
exact.regions
""",
    """
import datasets_gen, impls
from vorobench.judge.engine import build_and_certify
for name in ("halfplane", "incremental"):
    impls.builtin(name).warmup()
sites = datasets_gen.generate("uniform", 50, seed=1)
build_and_certify("incremental", sites)
build_and_certify("incremental", sites, weights=datasets_gen.weights("radii", sites, seed=1))
""",
)


def warm_kernels() -> None:
    """Compile the numba kernels into numba's cache before the tests start, the groups of
    WARM_KERNELS side by side on two or more cores. Otherwise every test worker, and every
    sandbox a test starts, compiles the same kernels at once: a fresh clone took 1,173 s of
    tests on two cores against 635 s with the cache warm. With the cache warm this takes a few
    seconds (loading). A group that fails is said and the tests go on: they show why."""
    print("compiling the numba kernels (about two minutes on a fresh clone, seconds after that)", flush=True)

    def start(code: str) -> subprocess.Popen:
        return subprocess.Popen([str(PYTHON), "-c", code], cwd=ROOT, stdout=subprocess.DEVNULL,
                                stderr=subprocess.PIPE, text=True)

    if (os.cpu_count() or 1) >= 2:
        groups = [start(code) for code in WARM_KERNELS]
        ended = [(proc, proc.communicate()[1]) for proc in groups]
    else:
        ended = [(proc, proc.communicate()[1]) for proc in map(start, WARM_KERNELS)]
    for proc, err in ended:
        if proc.returncode != 0:
            last = err.strip().splitlines()[-1] if err.strip() else ""
            print(f"warming the kernels failed (exit {proc.returncode}): {last}; the tests will show why", flush=True)


#: pytest options that only work with the tests in one process.
_ONE_PROCESS = {"--pdb", "--trace", "-s", "--capture=no"}


def pytest_workers(args: list[str]) -> list[str]:
    """``-n K`` for pytest-xdist, one worker per core up to four, unless ``args`` choose a
    number, turn xdist off (``-p no:xdist``) or need one process (a debugger, no capture). Many
    tests wait on the processes they start (the judge's sandboxes), so two cores take the
    suite in about two thirds of the time (measured: 876 s of tests on one worker, 574 s on
    two)."""
    if any(a.startswith("-n") or a.startswith("--numprocesses") for a in args):
        return []
    # debugging and output options that need the tests in this process, and xdist turned off
    if any(a in _ONE_PROCESS for a in args) or any(a.endswith("no:xdist") for a in args):
        return []
    workers = min(os.cpu_count() or 1, 4)
    return ["-n", str(workers)] if workers > 1 else []


def run(args: list[str]) -> int:
    return subprocess.call([str(PYTHON), *args], cwd=ROOT)


def main(argv: list[str]) -> int:
    job = argv[0] if argv else "help"
    rest = argv[1:]
    if job not in {"demo", "test", "bench", "setup"}:
        print(__doc__)
        return 0 if job == "help" else 2
    ensure_venv()
    if job == "setup":
        return install_references() if "--references" in rest else 0
    if job == "test":
        warm_kernels()
        return run(["-m", "pytest", *pytest_workers(rest), *rest])
    if job == "bench":
        return run(["-m", "pytest", "benchmarks", "--benchmark-only", *rest])
    return run(["-m", "vorobench", "demo", *rest])


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
