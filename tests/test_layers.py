"""The layers are real: a static scan of every import (function-local ones included) finds each
layer importing only from the layers below it, and no cycle between modules.

Layers, bottom to top: ``vorobench.core`` < ``impls`` < ``vorobench.judge`` <
``vorobench.harness`` < ``vorobench.cli``; ``datasets_gen`` stands alone (only the harness,
the command line and tests use it). ``vorobench`` itself (the lazy public API) imports nothing
at import time. ``vorobench.plugin``, the names plugin authors import, stands with ``impls``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("vorobench", "impls", "datasets_gen")

#: layer of a module (longest prefix wins) and the layers it may import
LAYERS = {
    "vorobench.core": 0,
    "impls": 1,
    "vorobench.plugin": 1,
    "vorobench.judge": 2,
    "datasets_gen": 2,
    "vorobench.harness": 3,
    "vorobench.cli": 4,
    "vorobench.__main__": 4,
}
ALLOWED = {
    "vorobench.core": {"vorobench.core"},
    "impls": {"vorobench.core", "impls"},
    "vorobench.plugin": {"vorobench.core", "impls"},
    "datasets_gen": {"datasets_gen"},
    "vorobench.judge": {"vorobench.core", "impls", "vorobench.judge"},
    "vorobench.harness": {"vorobench.core", "impls", "vorobench.judge", "vorobench.harness", "datasets_gen"},
    "vorobench.cli": {"vorobench.core", "impls", "vorobench.judge", "vorobench.harness", "vorobench.cli",
                      "datasets_gen"},
    "vorobench.__main__": {"vorobench.cli"},
    "vorobench": set(),
}


def _modules() -> dict[str, Path]:
    found = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            found[name] = path
    return found


MODULES = _modules()


def _imports(name: str, path: Path) -> set[str]:
    """Project modules ``name`` imports anywhere in its file (the deepest module each import
    names; a package's own ``__init__`` only when a name is taken from it)."""
    is_package = path.name == "__init__.py"
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".") if is_package else name.split(".")[:-1]
                base = base[:len(base) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            targets = []
            for alias in node.names:
                sub = f"{module}.{alias.name}"
                targets.append(sub if sub in MODULES else module)
        else:
            continue
        for target in targets:
            while target and target not in MODULES:
                target = target.rpartition(".")[0]
            if target and target != name:
                out.add(target)
    return out


GRAPH = {name: _imports(name, path) for name, path in MODULES.items()}


def _layer(name: str) -> str:
    best = "vorobench" if name == "vorobench" else ""
    for prefix in ALLOWED:
        if (name == prefix or name.startswith(prefix + ".")) and len(prefix) > len(best):
            best = prefix
    assert best, f"{name} belongs to no layer"
    return best


@pytest.mark.parametrize("name", sorted(MODULES))
def test_each_module_imports_only_from_its_own_layer_or_below(name):
    layer = _layer(name)
    wrong = sorted(t for t in GRAPH[name] if _layer(t) not in ALLOWED[layer])
    assert not wrong, f"{name} ({layer}) imports {wrong}"


def test_no_import_cycle_between_modules():
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(GRAPH[node]):
            if state.get(nxt) == 1:
                cycle = stack[stack.index(nxt):] + [nxt]
                raise AssertionError("import cycle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for name in sorted(GRAPH):
        if name not in state:
            visit(name)


def test_the_scan_sees_real_imports():
    """Guard against a scan that finds nothing: known edges are there."""
    assert "vorobench.core.predicates" in GRAPH["impls.fortune.event_queue"]
    assert "vorobench.core.diagram" in GRAPH["vorobench.core.builder"]
    assert any(t.startswith("vorobench.judge") for t in GRAPH["vorobench.harness.worker"])


def test_the_repository_stands_alone():
    """The contract lives in docs/, not in a folder outside the clone."""
    outside = "../" + "shared"
    hits = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*")
            if p.is_file() and p.suffix in {".py", ".md", ".toml", ".yml", ".txt"}
            and ".venv" not in p.parts and outside in p.read_text(encoding="utf-8", errors="replace")]
    assert not hits, hits
