"""vorobench: build, cross-validate and benchmark 2D Voronoi diagram implementations."""

from __future__ import annotations

from vorobench.diagram import Diagram, InvalidDiagramError
from vorobench.prepare import prepare

# Bound after the submodule imports: the function names shadow the modules of the same name.
from vorobench.compare import compare  # noqa: E402
from vorobench.certify import certify  # noqa: E402

__all__ = ["Diagram", "InvalidDiagramError", "prepare", "compare", "certify", "__version__"]
__version__ = "0.1.0"
