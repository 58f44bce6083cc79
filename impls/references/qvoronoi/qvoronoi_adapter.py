"""Qhull's ``qvoronoi`` program behind the vorobench executable protocol (output "voronoi").

Standard library only: it runs under ``{python}`` but depends on nothing installed there.

* stdin: the protocol's text input (``n``, then ``x y`` per site). Weighted input is refused.
* Qhull input: ``2 n`` then one ``x y`` line per site (repr floats, which Qhull's strtod reads
  exactly). Options: ``Qz`` (a point at infinity; without it qvoronoi refuses n = 3 and
  cocircular initial sites) and the outputs ``o Fv``. ``Qbb`` and ``Qc``, which scipy passes,
  are qvoronoi's defaults (it rejects them as options), so this is scipy.spatial.Voronoi's
  "Qbb Qc Qz".
* ``o``: ``2``, ``nv nr 1``, nv vertex lines (the first one is Qhull's vertex at infinity),
  then nr region lines (unused here). ``Fv``: a count, then one ``4 p q v1 v2`` line per
  ridge between the cells of sites p and q, vertex 0 being the vertex at infinity. So the
  protocol's vertex id is Qhull's id - 1, and infinity (0) becomes -1.
* stdout: ``v x y`` lines, ``e p q a b`` lines, and a ``time`` line: the wall time of the
  qvoronoi process, so it includes Qhull's process start and its text input and output
  (about as long as the construction itself at 10^5-10^6 sites), not the adapter's own work.

Qhull prints vertex coordinates with 16 significant digits (its compiled-in ``%.16g``), so
vertices are within a few units in the last place of Qhull's own doubles, not bit-exact.

Qhull cannot start on all-collinear sites (its initial simplex is flat). They are recognised
exactly here (integer cross products) and answered directly: sorted along their line,
consecutive sites are separated by parallel bisector lines, ``e i j -1 -1`` (the ``time``
line is then the sort's). n <= 1: no output. Any other input goes to qvoronoi; if it fails,
its stderr is passed on and the exit status is nonzero.
"""

from __future__ import annotations

import subprocess
import sys
import time
from typing import Iterator

QVORONOI = ["qvoronoi", "Qz", "o", "Fv"]
CHUNK = 1 << 16  # output lines translated at a time


def read_sites(stream) -> tuple[list[float], list[float]]:
    header = stream.readline().split()
    if not header:
        return [], []
    n = int(header[0])
    if len(header) > 1:
        words = b" ".join(header).decode(errors="replace")
        raise ValueError(f"qvoronoi adapter: unsupported input header {words!r} (no weights)")
    values = list(map(float, stream.read().split()))
    if len(values) != 2 * n:
        raise ValueError(f"qvoronoi adapter: expected {2 * n} coordinates, got {len(values)}")
    return values[0::2], values[1::2]


def _scaled_integers(values: list[float]) -> list[int]:
    """The values times one common power of two, as exact integers."""
    ratios = [v.as_integer_ratio() for v in values]
    top = max(d.bit_length() for _, d in ratios)  # denominators are powers of two
    return [m << (top - d.bit_length()) for m, d in ratios]


def all_collinear(xs: list[float], ys: list[float]) -> bool:
    """Whether every site lies on the line through sites 0 and 1 (distinct), decided exactly."""
    n = len(xs)
    if n <= 2:
        return True
    x0, y0 = xs[0], ys[0]
    dx, dy = xs[1] - x0, ys[1] - y0
    # Float filter: each difference and product is within a relative 2**-53 of the truth, so
    # the cross product's error is below 5e-16 * s unless something over- or underflowed.
    for i in range(2, n):
        left, right = dx * (ys[i] - y0), dy * (xs[i] - x0)
        s = abs(left) + abs(right)
        if 1e-290 < s < 1e290 and abs(left - right) > 1e-14 * s:
            return False
    # Undecided (probably truly collinear): exact integer cross products.
    X, Y = _scaled_integers(xs), _scaled_integers(ys)
    DX, DY = X[1] - X[0], Y[1] - Y[0]
    return all(DX * (Y[i] - Y[0]) == DY * (X[i] - X[0]) for i in range(2, n))


def collinear_output(xs: list[float], ys: list[float]) -> Iterator[str]:
    """Collinear sites: sorted along the line (x, then y), neighbours share a bisector line."""
    start = time.perf_counter()
    order = sorted(range(len(xs)), key=lambda i: (xs[i], ys[i]))
    elapsed = time.perf_counter() - start
    yield "".join([f"e {a} {b} -1 -1\n" for a, b in zip(order, order[1:])])
    yield f"time {elapsed!r}\n"


def qvoronoi_output(xs: list[float], ys: list[float]) -> Iterator[str]:
    coordinates = "\n".join(map("{!r} {!r}".format, xs, ys))
    data = ("2 %d\n%s\n" % (len(xs), coordinates)).encode("ascii")
    del coordinates
    # Wall time of the whole qvoronoi process: it includes Qhull's process start, reading
    # its input and printing its output, not only the construction.
    start = time.perf_counter()
    run = subprocess.run(QVORONOI, input=data, capture_output=True)
    elapsed = time.perf_counter() - start
    if run.returncode != 0:
        sys.stderr.buffer.write(run.stderr or b"qvoronoi failed without a message\n")
        raise SystemExit(run.returncode if run.returncode > 0 else 1)
    if run.stderr:  # Qhull's warnings, if any
        sys.stderr.buffer.write(run.stderr)

    rows = run.stdout.split(b"\n")
    del run
    if rows[0].strip() != b"2":
        raise ValueError(f"qvoronoi adapter: unexpected first output line {rows[0]!r}")
    nv, nr = (int(t) for t in rows[1].split()[:2])
    # 'o': rows[2] is the vertex at infinity, rows[3:2 + nv] the finite vertices.
    for first in range(3, 2 + nv, CHUNK):
        block = rows[first:min(first + CHUNK, 2 + nv)]
        coordinates = list(map(float, b" ".join(block).split()))
        if len(coordinates) != 2 * len(block):
            raise ValueError("qvoronoi adapter: malformed vertex lines in qvoronoi's output")
        xy = iter(coordinates)
        yield "".join(["v %r %r\n" % pair for pair in zip(xy, xy)])
    # 'Fv', after the nr region lines of 'o': "4 p q v1 v2" per ridge, vertex 0 at infinity.
    at = 2 + nv + nr
    end = at + 1 + int(rows[at])
    for first in range(at + 1, end, CHUNK):
        block = rows[first:min(first + CHUNK, end)]
        ridges = list(map(int, b" ".join(block).split()))
        if len(ridges) != 5 * len(block) or ridges[0::5].count(4) != len(block):
            raise ValueError("qvoronoi adapter: malformed ridge lines (a 2-d ridge has 2 vertices)")
        yield "".join(["e %d %d %d %d\n" % (p, q, a - 1, b - 1) for p, q, a, b
                       in zip(ridges[1::5], ridges[2::5], ridges[3::5], ridges[4::5])])
    yield f"time {elapsed!r}\n"


def main() -> int:
    try:
        xs, ys = read_sites(sys.stdin.buffer)
        if len(xs) <= 1:
            return 0
        output = collinear_output(xs, ys) if all_collinear(xs, ys) else qvoronoi_output(xs, ys)
        for text in output:
            sys.stdout.write(text)
    except (ValueError, OSError) as error:
        print(error, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
