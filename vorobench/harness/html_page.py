"""What the harness's self-contained HTML pages (``report.html``, the trend page) share: text made
safe for HTML, JSON data a script reads without it ending its element, the common style and the
page skeleton. One place, so a name from the results is made safe the same way on every page.

Everything from the results or their metadata is text. Characters no valid page holds (control
characters, lone surrogates, which also make a UTF-8 writer raise) are shown as visible escapes
(``\\x1b``, ``\\udcff``) by :func:`vorobench.harness.ci_outputs.printable`, as in the CI outputs.
"""

from __future__ import annotations

import html
import json
import re
from typing import Any, Callable, Optional, Sequence

from vorobench.harness.ci_outputs import printable

__all__ = ["escape", "script_json", "page", "BASE_CSS"]

#: The style both pages start from; each adds its own sizes and components after it.
BASE_CSS = """
body { font-family: system-ui, -apple-system, "Segoe UI", sans-serif; color: #222; }
h2 { margin-top: 1.6em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; }
th, td { border: 1px solid #ddd; text-align: left; vertical-align: top; }
.note { color: #555; font-size: 0.9em; }
"""

# What would end a script element early (the HTML parser ends it at the first "</script").
_SCRIPT_END = re.compile(r"</script", re.IGNORECASE)


def escape(value: object) -> str:
    """``value`` as HTML text or a quoted attribute value: cleaned (see the module docstring), then
    ``& < > " '`` escaped."""
    return html.escape(printable(value), quote=True)


def script_json(data: Any, default: Optional[Callable[[Any], Any]] = None) -> str:
    """``data`` as JSON for a ``<script type="application/json">`` element, every string (keys too)
    cleaned as :func:`escape` cleans it, so a name in the data equals the name in the markup.

    ASCII only, so U+2028/U+2029 (line ends to older script parsers) arrive as ``\\u`` escapes, and
    ``<``, ``>``, ``&`` as ``\\u003c`` ..., so no ``</script>`` nor ``<!--`` can form in the element.
    ``default`` converts what ``json`` does not know (numpy numbers); NaN is refused, not written.
    """
    convert = None if default is None else (lambda value: _cleaned(default(value)))
    text = json.dumps(_cleaned(data), separators=(",", ":"), ensure_ascii=True, allow_nan=False, default=convert)
    return text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")


def _cleaned(data: Any) -> Any:
    """``data`` with every string, keys included, passed through :func:`printable`."""
    if isinstance(data, str):
        return printable(data)
    if isinstance(data, dict):
        return {printable(k) if isinstance(k, str) else k: _cleaned(v) for k, v in data.items()}
    if isinstance(data, (list, tuple)):
        return [_cleaned(v) for v in data]
    return data


def page(title: str, style: str, body: str, *, data_id: str, data: Any, script: str,
         libraries: Sequence[str] = (), json_default: Optional[Callable[[Any], Any]] = None) -> str:
    """The whole page: a head (charset, viewport, ``title`` as text, :data:`BASE_CSS` then ``style``,
    the inlined ``libraries``), the ``body`` markup, the page's ``data`` as a JSON element of id
    ``data_id`` (see :func:`script_json`), and last its ``script``, which reads that element.

    The body is cleaned as a whole: markup made elsewhere (Markdown rendered by markdown-it) may
    carry what :func:`escape` cleans. A script that would end its element early is refused.
    """
    for code in (*libraries, script):
        if _SCRIPT_END.search(code):
            raise ValueError("a script of the page holds '</script' and would end its element early")
    head = "".join(f"<script>{code}</script>\n" for code in libraries)
    return ("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
            f"<title>{escape(title)}</title>\n<style>{BASE_CSS}{style}</style>\n{head}</head>\n<body>\n"
            + printable(body)
            + f'\n<script type="application/json" id="{escape(data_id)}">{script_json(data, json_default)}</script>\n'
            + f"<script>{script}</script>\n</body>\n</html>\n")
