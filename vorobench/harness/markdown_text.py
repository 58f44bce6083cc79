"""Text from results as Markdown that shows exactly its characters: no markup, no line breaks."""

from __future__ import annotations

import re

__all__ = ["one_line", "text", "cell"]

# Characters that can start Markdown markup inside a line (emphasis, code, links, images, raw
# HTML, entities, strike-through, headings). A backslash makes any of them literal.
_MARKUP = re.compile(r"([\\`*_\[\]<>#!&~])")
_LINE_BREAKS = re.compile(r"[ \t]*[\r\n]+[ \t]*")


def one_line(value: object) -> str:
    """``value`` as one line: a line break inside a table cell or a list item would end it."""
    return _LINE_BREAKS.sub(" ", str(value))


def text(value: object) -> str:
    """A value from the results or metadata as Markdown that shows exactly its characters."""
    return _MARKUP.sub(r"\\\1", one_line(value))


def cell(value: object) -> str:
    """:func:`text` for a pipe-table cell (pipes escaped too)."""
    return text(value).replace("|", "\\|")
