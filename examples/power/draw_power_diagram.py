"""Draw the power diagram shown in the README: 150 random sites with weights from the
``radii`` family, built by every weighted implementation here, checked to agree, certified,
and drawn with its hidden sites marked.

    .venv/bin/python examples/power/draw_power_diagram.py [OUT.png]
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

import datasets_gen  # noqa: E402
import impls  # noqa: E402
from vorobench import certify, compare  # noqa: E402


def main(out: str = "docs/power_diagram.png") -> int:
    points = datasets_gen.generate("uniform", 150, seed=2)
    weights = datasets_gen.weights("radii", points, seed=2)
    names = impls.weighted()
    diagrams = {name: impls.build(name, points, weights=weights) for name in names}
    reference = diagrams[names[0]]
    for name, d in diagrams.items():
        verdict = compare(reference, d, labels=(names[0], name)).verdict
        print(f"{name:12s} hidden {d.hidden.size:3d}  certified {certify(d).ok}  vs {names[0]}: {verdict}")
    ax = reference.plot(title=f"power diagram of 150 sites, {reference.hidden.size} hidden "
                              f"({', '.join(names)} agree)")
    ax.figure.set_size_inches(7, 7)
    ax.figure.savefig(out, dpi=100, bbox_inches="tight")
    plt.close(ax.figure)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
