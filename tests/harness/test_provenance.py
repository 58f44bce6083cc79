"""Run metadata names the distribution an entry-point implementation comes from, even when its
build function lives in a module no distribution owns (here a ``functools.partial``), and a
``--plugin`` of the same name is not credited to that distribution."""

from __future__ import annotations

import importlib
import sys
import textwrap

import pytest
from installing import pip_install_into

import impls
from impls.base import Implementation
from vorobench.harness.sysinfo import code_provenance

NAME = "partial-qhull"
PYPROJECT = """\
[build-system]
requires = ["setuptools>=61"]
build-backend = "setuptools.build_meta"

[project]
name = "vb-partial-plugin"
version = "0.3"

[project.entry-points."vorobench.impls"]
partial-qhull = "vb_partial_plugin:IMPLEMENTATION"

[tool.setuptools]
py-modules = ["vb_partial_plugin"]
"""
MODULE = """\
import functools

from impls.qhull import build
from vorobench.plugin import Implementation

IMPLEMENTATION = Implementation("partial-qhull", "qhull through functools.partial", "O(n log n)",
                                functools.partial(build), exact=False)
"""


@pytest.fixture
def installed(tmp_path, monkeypatch):
    project = tmp_path / "vb-partial-plugin"
    project.mkdir()
    (project / "pyproject.toml").write_text(PYPROJECT)
    (project / "vb_partial_plugin.py").write_text(MODULE)
    (tmp_path / "scratch").mkdir()
    pip_install_into(project, tmp_path / "site", tmp_path / "scratch")
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    importlib.invalidate_caches()
    yield
    impls.unregister(NAME)
    sys.modules.pop("vb_partial_plugin", None)


def test_an_entry_point_implementation_is_credited_to_its_distribution(installed):
    assert NAME in impls.available()
    info = code_provenance([NAME])[NAME]
    assert info["module"] == "functools"                 # where the build's code says it lives
    assert (info["distribution"], info["version"]) == ("vb-partial-plugin", "0.3")


def test_a_plugin_registered_under_that_name_is_not(installed):
    impls.register(Implementation(NAME, "a --plugin double", "O(n)", textwrap.dedent, exact=False))
    info = code_provenance([NAME])[NAME]
    assert info["module"] == "textwrap" and info["distribution"] is None
