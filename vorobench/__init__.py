"""vorobench: build, cross-validate and benchmark 2D Voronoi diagram implementations.

The package is layered (see ``docs/architecture.md``): ``vorobench.core`` (geometry),
``impls`` (the constructions), ``vorobench.judge`` and ``vorobench.harness``, with the
command line in ``vorobench.cli``. The names here are the public API; each is imported on
first use, so that importing one layer never pulls in the layers above it.
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["Diagram", "InvalidDiagramError", "prepare", "compare", "certify", "__version__"]
__version__ = "0.1.0"

_API = {
    "Diagram": "vorobench.core.diagram",
    "InvalidDiagramError": "vorobench.core.diagram",
    "prepare": "vorobench.core.prepare",
    "compare": "vorobench.judge.comparison",
    "certify": "vorobench.judge.certificate",
}


def __getattr__(name: str) -> Any:
    module = _API.get(name)
    if module is None:
        raise AttributeError(f"module 'vorobench' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
