"""The error every DCEL check raises, in a module of its own so that the modules that link
and walk half-edges can raise it without importing the :class:`Diagram` they serve."""

from __future__ import annotations

__all__ = ["InvalidDiagramError"]


class InvalidDiagramError(ValueError):
    """A DCEL invariant is broken; the message names the invariant and the ids involved."""
