"""The impls registry: own names, lookup errors, test registration and entry points."""

import sys
import textwrap
from importlib.metadata import EntryPoint

import numpy as np
import pytest

import impls
from impls.base import Implementation
from vorobench.core.builder import collinear_diagram


def test_qhull_is_always_available():
    assert "qhull" in impls.available()
    impl = impls.get("qhull")
    assert impl.name == "qhull" and impl.description and impl.complexity


def test_unknown_name_lists_available():
    with pytest.raises(KeyError, match="qhull"):
        impls.get("no-such-impl")


def _lines_only(sites, stats=None):
    if stats is not None:
        stats["calls"] = stats.get("calls", 0) + 1
    return collinear_diagram(sites)


def test_register_and_build_prepares_points():
    impls.register(Implementation("dummy-lines", "parallel lines", "O(n log n)", _lines_only))
    try:
        assert "dummy-lines" in impls.available()
        stats: dict = {}
        d = impls.build("dummy-lines", [[0, 0], [1, 0], [1, 0], [2, 0]], stats)
        assert d.n_sites == 3 and stats == {"calls": 1}   # the duplicate was removed first
        with pytest.raises(ValueError, match="finite"):
            impls.build("dummy-lines", [[0, np.nan]])
    finally:
        impls.unregister("dummy-lines")
    assert "dummy-lines" not in impls.available()


def test_entry_point_plugin_is_found(tmp_path, monkeypatch):
    (tmp_path / "vb_dummy_plugin.py").write_text(textwrap.dedent("""
        from impls.base import Implementation
        from vorobench.core.builder import collinear_diagram

        def make():
            return Implementation("plugin-lines", "from an entry point", "O(n log n)",
                                  lambda sites, stats=None: collinear_diagram(sites), origin="plugin")
    """))
    monkeypatch.syspath_prepend(str(tmp_path))
    ep = EntryPoint(name="plugin-lines", value="vb_dummy_plugin:make", group=impls.ENTRY_POINT_GROUP)
    monkeypatch.setattr(impls, "entry_points", lambda group: [ep] if group == impls.ENTRY_POINT_GROUP else [])
    try:
        assert "plugin-lines" in impls.available()
        impl = impls.get("plugin-lines")
        assert impl.origin == "plugin"
        d = impls.build("plugin-lines", [[0, 0], [0, 1], [0, 2]]).validate()
        assert d.n_edges == 2
    finally:
        impls.unregister("plugin-lines")
        sys.modules.pop("vb_dummy_plugin", None)
