"""The README's claim about its scipy snippet at a million points, checked (45 s: too long for
the test suite, which runs the snippet as written, at 300 points).

    .venv/bin/python benchmarks/readme_million.py

Runs the README's ``from_scipy`` block with ``random((1_000_000, 2))`` (seed 0, no plot) and
exits 1 unless it prints ``EQUAL within tolerance``: Qhull rounds four nearly cocircular sites
into one vertex, which compare forgives a floating-point library by the per-configuration rule
(issue 22), where a fixed edge-length limit said DIFFERENT.
"""

from __future__ import annotations

import contextlib
import io
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main() -> int:
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "README.md").read_text(), flags=re.S)
    block = next(b for b in blocks if "from_scipy" in b)
    if "random((300, 2))" not in block or "; voronoi_plot_2d(d)" not in block:
        print("the README's snippet changed: update this check")
        return 2
    block = block.replace("random((300, 2))", "random((1_000_000, 2))").replace("; voronoi_plot_2d(d)", "")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(block, "README.md", "exec"), {})
    head = out.getvalue().splitlines()[0]
    print(head)
    return 0 if "EQUAL within tolerance" in head else 1


if __name__ == "__main__":
    sys.exit(main())
