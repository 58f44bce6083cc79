"""Installs a project folder with pip into a folder of its own, for tests of installed plugins:
the project's virtual environment and the source folder stay untouched, and nothing is
downloaded (no dependencies, no build isolation: the environment's setuptools builds it)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

__all__ = ["pip_install_into", "environment_with"]


def pip_install_into(project: Path, target: Path, scratch: Path) -> None:
    """``pip install --target target`` a copy of ``project`` made in ``scratch`` (building writes
    ``build/`` and ``*.egg-info`` next to the sources it builds)."""
    copy = scratch / project.name
    shutil.copytree(project, copy, ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__", ".pytest_cache"))
    run = subprocess.run([sys.executable, "-m", "pip", "install", "--no-deps", "--no-build-isolation", "--no-index",
                          "--disable-pip-version-check", "--quiet", "--target", str(target), str(copy)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, f"pip install of {project} failed:\n{run.stdout}{run.stderr}"


def environment_with(*paths: Path) -> dict[str, str]:
    """This process's environment with ``paths`` first on ``PYTHONPATH``."""
    existing = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    return {**os.environ, "PYTHONPATH": os.pathsep.join([str(p) for p in paths] + existing)}
