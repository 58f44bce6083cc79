"""The executable protocol's bytes: the sites a program reads and the answer it prints.

Input (stdin). Text: ``n`` (and ``weighted``, or ``apollonius`` for disks) on the first line,
then ``x y [w]`` (``x y r``) per site in Python's ``repr`` (the shortest form that reads back
to the same float64). Binary: an 8-byte little-endian n, a 1-byte flag (0 plain, 1 weighted,
2 disks), then the rows as little-endian float64.

Output (stdout). ``triangles``: ``i j k`` lines; for disks, the faces of the Apollonius graph
as ``i j k a b c`` (vertices counter-clockwise, -1 at infinity, then the faces opposite each).
``voronoi``: ``v x y`` lines, then ``e i j a b`` lines (-1 = at infinity). Either may hold one ``time SECONDS`` line. An answer
longer than what n sites allow (:func:`output_limit`) is refused before it is read to the end,
so whatever a program prints, what the harness holds stays bounded.
"""

from __future__ import annotations

import io
import math
import re
import struct
from dataclasses import dataclass
from typing import Optional

import numpy as np
from numpy.typing import NDArray

from impls.executable.manifest import InputFormat, OutputKind

__all__ = ["encode_sites", "output_limit", "parse_output", "ProgramOutput", "InvalidOutput"]


class InvalidOutput(RuntimeError):
    """What the program printed is not an answer the protocol allows (the verdict
    ``invalid_output``)."""

    #: Its message is about the program: where in vorobench it was noticed is no help.
    about_the_program = True


#: Longest line the limit allows for, by output kind: an ``i j k`` line of 20-digit indices,
#: a ``v x y`` line of 24-character floats (or an ``e i j a b`` line), with room to spare.
_LINE_BYTES = {OutputKind.TRIANGLES: 64, OutputKind.VORONOI: 96}


def encode_sites(sites: NDArray[np.float64], weights: Optional[NDArray[np.float64]], fmt: InputFormat,
                 radii: Optional[NDArray[np.float64]] = None) -> bytes:
    """The program's stdin for ``sites`` (and ``weights``, one per site, or None; or ``radii``)."""
    if radii is not None:
        n = sites.shape[0]
        rows = np.column_stack([sites, np.asarray(radii, dtype=np.float64)])
        if fmt == InputFormat.BINARY:
            return struct.pack("<QB", n, 2) + np.ascontiguousarray(rows, dtype="<f8").tobytes()
        return (f"{n} apollonius\n" + "".join(f"{x!r} {y!r} {r!r}\n" for x, y, r in rows.tolist())).encode()
    sites = np.ascontiguousarray(sites, dtype=np.float64).reshape(-1, 2)
    n = sites.shape[0]
    rows = sites if weights is None else np.column_stack([sites, np.asarray(weights, dtype=np.float64)])
    if fmt == InputFormat.BINARY:
        return struct.pack("<QB", n, weights is not None) + np.ascontiguousarray(rows, dtype="<f8").tobytes()
    header = f"{n} weighted\n" if weights is not None else f"{n}\n"
    words = list(map(float.__repr__, rows.reshape(-1).tolist()))      # repr: shortest round trip
    columns = [words[k::rows.shape[1]] for k in range(rows.shape[1])]
    body = "\n".join(map(" ".join, zip(*columns)))
    return (header + body + ("\n" if n else "")).encode("ascii")


def output_limit(n: int, kind: OutputKind, disks: bool = False) -> int:
    """The most bytes an honest answer for ``n`` sites needs: 2n triangles (2n faces with their
    neighbours, for disks), or 2n vertices and 3n edges, in lines of generous length, and a
    time line."""
    lines = 2 * n + 4 if kind == OutputKind.TRIANGLES else 5 * n + 8
    return (2 if disks else 1) * _LINE_BYTES[kind] * lines + 256


@dataclass
class ProgramOutput:
    """A parsed answer: ``triangles`` (m, 3), or ``vertices`` (V, 2) with ``edge_sites`` and
    ``edge_ends`` (E, 2) each; ``library_s``: the program's own time line, if any."""

    triangles: Optional[NDArray[np.int64]] = None
    vertices: Optional[NDArray[np.float64]] = None
    edge_sites: Optional[NDArray[np.int64]] = None
    edge_ends: Optional[NDArray[np.int64]] = None
    library_s: Optional[float] = None


_TIME_LINE = re.compile(rb"^[ \t]*time[ \t]+(\S+)[ \t]*(?:\n|$)", re.MULTILINE)
_BLANK_LINES = re.compile(rb"^[ \t]*\n", re.MULTILINE)
_VERTEX_TAG = re.compile(rb"^[ \t]*v[ \t]", re.MULTILINE)
_EDGE_TAG = re.compile(rb"^[ \t]*e[ \t]", re.MULTILINE)


def _time_line(body: bytes) -> tuple[bytes, Optional[float]]:
    """The body without its ``time`` line (the whole line), and that line's seconds."""
    found = _TIME_LINE.findall(body)
    if not found:
        return body, None
    if len(found) > 1:
        raise InvalidOutput(f"{len(found)} time lines; the protocol allows one")
    try:
        seconds = float(found[0])
    except ValueError:
        raise InvalidOutput(f"the time line's {found[0][:40]!r} is not a number of seconds") from None
    if not math.isfinite(seconds) or seconds < 0:
        raise InvalidOutput(f"the time line says {seconds!r} seconds")
    return _TIME_LINE.sub(b"", body, count=1), seconds


def _lines(body: bytes) -> int:
    return body.count(b"\n") + (1 if body and not body.endswith(b"\n") else 0)


def _table(text: bytes, columns: int, dtype: type, what: str) -> np.ndarray:
    """Whitespace-separated rows of ``columns`` numbers each."""
    if not text.strip():
        return np.empty((0, columns), dtype=dtype)
    try:
        table = np.loadtxt(io.BytesIO(text), dtype=dtype, ndmin=2, comments=None)
    except ValueError as exc:
        raise InvalidOutput(f"{what} do not parse: {str(exc)[:200]}") from None
    if table.shape[1] != columns:
        raise InvalidOutput(f"{what} have {table.shape[1]} numbers per line, not {columns}")
    return table


def _untagged(part: bytes, tag: re.Pattern, letter: str, what: str, most: int) -> bytes:
    """The lines of ``part`` without their tag (``v`` or ``e`` and a blank); every line must
    carry it, and there may be at most ``most`` of them."""
    lines = _lines(part)
    if lines > most:
        raise InvalidOutput(f"{lines} {what} lines, more than the {most} that these sites can have")
    stripped, tagged = tag.subn(b"", part)
    if tagged != lines:
        raise InvalidOutput(f"{lines - tagged} of the {lines} {what} lines do not start with {letter!r} "
                            f"(vertex lines come first, then edge lines)")
    return stripped


def parse_output(data: bytes, kind: OutputKind, n: int, disks: bool = False) -> ProgramOutput:
    """The answer in ``data`` for ``n`` sites (``disks``: the faces of an Apollonius graph);
    :class:`InvalidOutput` saying what is wrong. Blank lines are ignored; more lines than n
    sites can need are refused before any is parsed (2n triangles; 2n vertices and 3n edges,
    the bounds of a planar diagram, and a margin)."""
    body = _BLANK_LINES.sub(b"", data.replace(b"\r\n", b"\n"))
    body, seconds = _time_line(body)
    if kind == OutputKind.TRIANGLES and disks:
        most = 2 * n + 8                   # the faces of a planar graph on n sites and infinity
        if _lines(body) > most:
            raise InvalidOutput(f"{_lines(body)} face lines, more than the {most} that {n} disks can have")
        faces = _table(body, 6, np.int64, "face lines")
        if faces.size and (faces[:, :3].min() < -1 or faces[:, :3].max() >= n):
            raise InvalidOutput(f"a face names a site outside -1..{n - 1}")
        return ProgramOutput(triangles=faces, library_s=seconds)
    if kind == OutputKind.TRIANGLES:
        most = 2 * n + 8
        if _lines(body) > most:
            raise InvalidOutput(f"{_lines(body)} triangle lines, more than the {most} that {n} sites can have")
        triangles = _table(body, 3, np.int64, "triangle lines")
        if triangles.size and (triangles.min() < 0 or triangles.max() >= n):
            raise InvalidOutput(f"a triangle names a site outside 0..{n - 1}")
        return ProgramOutput(triangles=triangles, library_s=seconds)
    edge = _EDGE_TAG.search(body)
    vertex_part, edge_part = (body, b"") if edge is None else (body[:edge.start()], body[edge.start():])
    vertices = _table(_untagged(vertex_part, _VERTEX_TAG, "v", "vertex", 2 * n + 16), 2, np.float64,
                      "vertex lines")
    edges = _table(_untagged(edge_part, _EDGE_TAG, "e", "edge", 3 * n + 16), 4, np.int64, "edge lines")
    del body, vertex_part, edge_part
    if not np.isfinite(vertices).all():
        raise InvalidOutput(f"vertex {int(np.flatnonzero(~np.isfinite(vertices).all(axis=1))[0])} is not finite")
    if edges.size:
        if edges[:, :2].min() < 0 or edges[:, :2].max() >= n:
            raise InvalidOutput(f"an edge names a site outside 0..{n - 1}")
        if edges[:, 2:].min() < -1 or edges[:, 2:].max() >= vertices.shape[0]:
            raise InvalidOutput(f"an edge names a vertex outside -1..{vertices.shape[0] - 1}")
    return ProgramOutput(vertices=vertices, edge_sites=np.ascontiguousarray(edges[:, :2]),
                         edge_ends=np.ascontiguousarray(edges[:, 2:]), library_s=seconds)
