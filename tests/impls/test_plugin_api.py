"""``vorobench.plugin``, the names a plugin author imports: they are the project's own objects,
and the complete example in its docstring loads with ``--plugin``, builds and certifies."""

from __future__ import annotations

import re
import textwrap
from pathlib import Path

import numpy as np

import datasets_gen
import impls
import vorobench
import vorobench.plugin
from impls.base import BuildFunction, Implementation
from impls.plugins import plugins_registered
from vorobench.core import builder, diagram, hull


def test_the_facade_reexports_the_projects_own_objects():
    assert vorobench.plugin.Implementation is Implementation
    assert vorobench.plugin.BuildFunction is BuildFunction
    assert vorobench.plugin.Diagram is diagram.Diagram
    assert vorobench.plugin.assemble is builder.assemble
    assert vorobench.plugin.collinear_diagram is builder.collinear_diagram
    assert vorobench.plugin.all_collinear is hull.all_collinear
    assert vorobench.plugin.UnsupportedInput is impls.UnsupportedInput
    assert all(hasattr(vorobench.plugin, name) for name in vorobench.plugin.__all__)


def test_build_function_is_a_protocol_every_build_satisfies():
    assert isinstance(impls.get("incremental").build, BuildFunction)
    assert isinstance(lambda sites, stats=None: None, BuildFunction)
    assert not isinstance("build", BuildFunction)
    assert "sites" in BuildFunction.__call__.__doc__ and "read-only" in BuildFunction.__call__.__doc__


def _docstring_example() -> str:
    """The code block of ``vorobench.plugin``'s docstring (after ``::``, up to the prose)."""
    block = vorobench.plugin.__doc__.split("::\n", 1)[1]
    lines = []
    for line in block.splitlines():
        if line and not line.startswith("    "):
            break
        lines.append(line)
    return textwrap.dedent("\n".join(lines))


def test_the_docstring_example_is_a_working_plugin(tmp_path):
    path = tmp_path / "my_voronoi.py"
    path.write_text(_docstring_example())
    points = datasets_gen.generate("uniform", 300, seed=4)
    with plugins_registered([str(path)]) as names:
        assert names == ["my-voronoi"]
        stats: dict = {}
        built = impls.build("my-voronoi", points, stats)
        collinear = impls.build("my-voronoi", np.array([[0.0, 1.0], [1.0, 2.0], [2.0, 3.0]]))
    assert "my-voronoi" not in impls.available()
    assert vorobench.certify(built).ok_within_tolerance
    assert vorobench.compare(impls.build("incremental", points), built).equal
    assert stats["ridges"] == built.counts()["E"]
    assert collinear.counts()["V"] == 0 and collinear.counts()["E"] == 2


def test_the_guide_shows_the_same_minimal_plugin():
    guide = (Path(__file__).resolve().parents[2] / "docs" / "implementations.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", guide, flags=re.S)
    assert _docstring_example().strip() in [b.strip() for b in blocks]
