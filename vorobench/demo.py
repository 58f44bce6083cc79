"""The main job: build the qhull diagram of a default dataset and draw it under reports/.

(The benchmark + cross-validation version replaces this once the runner exists.)
"""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", default="reports/demo", help="output folder (default reports/demo)")
    p.add_argument("--n", type=int, default=2000, help="number of points (default 2000)")


def run(args: argparse.Namespace) -> int:
    import datasets_gen
    import impls
    from vorobench.plotting import save_plot

    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    points = datasets_gen.generate("uniform", args.n, seed=0)
    d = impls.build("qhull", points).validate()
    path = save_plot(d, out / "qhull_uniform.png", title=f"qhull: uniform n={args.n}")
    print(f"qhull on uniform n={args.n}: V={d.n_vertices} E={d.n_edges}; wrote {path}")
    return 0
