"""The bounded wire: how answers cross from a sandbox (an implementation's process) to the judge.

An answer is plain data: an 8-byte header length, a JSON header, then raw little-endian array
bytes, back to back. The header names each array with its dtype and shape. The judge checks
every size against a schema (what n sites allow) *before* anything is allocated, and reads
the arrays as views of the received bytes: no pickle, no compression the sender controls, no
object the sender chose. Text in the header is cleaned on the way in (lone surrogates, control
characters and length), so that an exception message with a stray byte cannot break the
files the judge writes.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass
from typing import Any, Mapping, Optional

import numpy as np

__all__ = ["ArraySpec", "WireError", "encode", "decode", "escaped", "clean_text", "clean_data", "MAX_HEADER_BYTES",
           "MAX_MESSAGE_BYTES", "TEXT_LIMIT"]

#: Largest JSON header the judge reads (messages, counters, declarations).
MAX_HEADER_BYTES = 1 << 20
#: Largest answer of any kind, whatever n allows (1 GiB): above it the answer is the sender's failure.
MAX_MESSAGE_BYTES = 1 << 30
#: Longest string kept of anything the sender wrote.
TEXT_LIMIT = 2000

#: The dtypes an array may have on the wire (little-endian, by name).
_DTYPES = {"<f8": np.dtype("<f8"), "<i4": np.dtype("<i4"), "<i8": np.dtype("<i8")}

# What no reader should get raw: the characters XML 1.0 forbids (C0 controls but tab and line
# breaks, surrogates, U+FFFE, U+FFFF), which also make a UTF-8 writer raise (a lone surrogate
# from bytes read with surrogateescape) or a terminal obey (ESC), plus DEL and the C1 controls
# (U+009B is a terminal's CSI too). Shown as a visible escape instead.
_UNSAFE = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff]")


class WireError(ValueError):
    """An answer that is not what the schema allows: the sender's failure, said in one line."""


@dataclass(frozen=True)
class ArraySpec:
    """What one named array may be: its dtypes, and the largest shape (None: any length along
    that axis up to the message cap; an int: at most that many)."""

    dtypes: tuple[str, ...]
    shape: tuple[Optional[int], ...]


def escaped(text: Any) -> str:
    """``text`` as a string that every file format, XML parser and terminal takes: each unsafe
    character shown as its escape (``\\x1b``, ``\\udcff``), so it stays readable."""
    try:
        s = text if isinstance(text, str) else str(text)
    except Exception:  # an object whose __str__ raises still says what it is
        s = f"<unprintable {type(text).__name__}>"
    return _UNSAFE.sub(lambda m: m.group().encode("unicode_escape").decode("ascii"), s)


def clean_text(text: Any, limit: int = TEXT_LIMIT) -> str:
    """:func:`escaped` ``text``, cut to ``limit`` characters."""
    if isinstance(text, str) and len(text) > 2 * limit:
        text = text[:2 * limit]
    return escaped(text)[:limit]


def clean_data(data: Any, limit: int = TEXT_LIMIT, depth: int = 0) -> Any:
    """JSON data with every string (keys included) cleaned by :func:`clean_text`."""
    if depth > 20:
        raise WireError("the answer nests too deeply")
    if isinstance(data, str):
        return clean_text(data, limit)
    if isinstance(data, dict):
        return {clean_text(k, 200): clean_data(v, limit, depth + 1) for k, v in data.items()}
    if isinstance(data, list):
        return [clean_data(v, limit, depth + 1) for v in data]
    return data


def encode(kind: str, data: Any = None, arrays: Optional[Mapping[str, np.ndarray]] = None) -> bytes:
    """One answer: header length, JSON header (kind, data, array layout), raw array bytes."""
    layout, blobs = [], []
    for name, value in (arrays or {}).items():
        a = np.asarray(value)
        dtype = a.dtype.newbyteorder("<") if a.dtype.byteorder == ">" else a.dtype
        a = np.ascontiguousarray(a, dtype=dtype)
        layout.append({"name": str(name), "dtype": a.dtype.str, "shape": list(a.shape)})
        blobs.append(a.tobytes())
    header = json.dumps({"kind": kind, "data": data, "arrays": layout}).encode()
    return len(header).to_bytes(8, "little") + header + b"".join(blobs)


def _checked_layout(entry: Any, schema: Mapping[str, ArraySpec]) -> tuple[str, np.dtype, tuple[int, ...]]:
    if not isinstance(entry, dict):
        raise WireError("an array entry is not an object")
    name, dtype, shape = entry.get("name"), entry.get("dtype"), entry.get("shape")
    if name not in schema:
        raise WireError(f"unexpected array {clean_text(name, 40)!r}")
    spec = schema[name]
    if dtype not in spec.dtypes or dtype not in _DTYPES:
        raise WireError(f"array {name!r} has dtype {clean_text(dtype, 20)!r}, not one of {', '.join(spec.dtypes)}")
    if not (isinstance(shape, list) and len(shape) == len(spec.shape)
            and all(type(s) is int and s >= 0 for s in shape)):
        raise WireError(f"array {name!r} has shape {clean_text(shape, 40)}, not {len(spec.shape)}-dimensional")
    for got, most in zip(shape, spec.shape):
        if most is not None and got > most:
            raise WireError(f"array {name!r} has shape {tuple(shape)}, more than the {spec.shape} "
                            f"the sites allow")
    return name, _DTYPES[dtype], tuple(shape)


def decode(message: bytes, schema: Optional[Mapping[str, ArraySpec]] = None
           ) -> tuple[str, Any, dict[str, np.ndarray]]:
    """(kind, data, arrays) of an answer, every size checked before it is used.

    ``schema`` says which arrays may come and how large; none may come without one. Arrays are read-only views of
    ``message``. Raises :class:`WireError` for anything else.
    """
    if len(message) < 8:
        raise WireError("the answer is shorter than its header")
    size = int.from_bytes(message[:8], "little")
    if size > MAX_HEADER_BYTES or 8 + size > len(message):
        raise WireError(f"the answer's header claims {size} bytes")
    try:
        header = json.loads(bytes(message[8:8 + size]))
    except (ValueError, UnicodeDecodeError) as exc:
        raise WireError(f"the answer's header is not JSON ({type(exc).__name__})") from None
    if not isinstance(header, dict) or not isinstance(header.get("kind"), str):
        raise WireError("the answer's header has no kind")
    kind = clean_text(header["kind"], 40)
    data = clean_data(header.get("data"))
    layout = header.get("arrays") or []
    if not isinstance(layout, list):
        raise WireError("the answer's array layout is not a list")
    schema = schema or {}
    arrays: dict[str, np.ndarray] = {}
    offset = 8 + size
    for entry in layout:
        name, dtype, shape = _checked_layout(entry, schema)
        if name in arrays:
            raise WireError(f"array {name!r} sent twice")
        nbytes = dtype.itemsize * math.prod(shape)
        if offset + nbytes > len(message):
            raise WireError(f"array {name!r} is cut short")
        arrays[name] = np.frombuffer(message, dtype=dtype, count=math.prod(shape), offset=offset).reshape(shape)
        offset += nbytes
    if offset != len(message):
        raise WireError(f"{len(message) - offset} bytes after the last array")
    return kind, data, arrays
