"""Item 9: exception messages with a lone surrogate (a non-UTF-8 byte), a terminal escape and
XML-forbidden control characters."""

from __future__ import annotations

from impls.base import Implementation


class _Unprintable(Exception):
    def __str__(self):
        raise RuntimeError("no message for you")


def _surrogate(sites, stats=None):
    raise RuntimeError("bad byte \udcff here \x1b[31mred\x1b[0m \x00\x07 <![CDATA[ ]]> & done")


def _unprintable(sites, stats=None):
    raise _Unprintable()


IMPLEMENTATIONS = [
    Implementation("stray_bytes", "raises with a stray byte", "O(1)", _surrogate, exact=True),
    Implementation("unprintable", "raises an exception that cannot be printed", "O(1)", _unprintable, exact=True),
]
