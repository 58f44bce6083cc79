#!/usr/bin/env python3
"""Set up the project's virtual environment if needed, then run a job in it.

    python3 dev.py demo    # default benchmark + cross-validation, report under reports/
    python3 dev.py test    # the test suite (what CI runs)
    python3 dev.py bench   # pytest-benchmark suite (not part of the tests)

Only python3 (3.11+) is assumed: the venv and every dependency are installed from
pyproject.toml into ./.venv the first time, and again whenever pyproject.toml changes.
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
        return 0
    if job == "test":
        return run(["-m", "pytest", *rest])
    if job == "bench":
        return run(["-m", "pytest", "benchmarks", "--benchmark-only", *rest])
    return run(["-m", "vorobench", "demo", *rest])


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
