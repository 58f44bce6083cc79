"""vorobench: build, cross-validate and benchmark 2D Voronoi diagram implementations."""

from __future__ import annotations

from vorobench.diagram import Diagram, InvalidDiagramError
from vorobench.prepare import prepare

__all__ = ["Diagram", "InvalidDiagramError", "prepare", "compare", "certify", "__version__"]
__version__ = "0.1.0"


def __getattr__(name: str):
    # compare and certify pull in scipy's k-d tree and the predicates; load them on first use.
    if name == "compare":
        from vorobench.compare import compare
        return compare
    if name == "certify":
        from vorobench.certify import certify
        return certify
    raise AttributeError(f"module 'vorobench' has no attribute {name!r}")
