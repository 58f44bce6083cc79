"""Draw the diagram of disks shown in docs/apollonius.md: 40 disks of the ``random`` radius family
(some hidden), built by every implementation that takes disks here, checked to agree exactly,
certified, and drawn with its curved edges.

    .venv/bin/python examples/apollonius/draw_apollonius_diagram.py [OUT.png]
"""

from __future__ import annotations

import sys

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402

import datasets_gen  # noqa: E402
import impls  # noqa: E402
from vorobench.judge.disk_judging import certify_disks, compare_disks  # noqa: E402
from vorobench.judge.outcomes import Verdict  # noqa: E402


def main(out: str = "docs/apollonius_diagram.png") -> int:
    points = datasets_gen.generate("uniform", 40, seed=3)
    radii = datasets_gen.radii("random", points, seed=3)
    names = impls.apollonius()
    diagrams = {name: impls.build(name, points, radii=radii) for name in names}
    reference = diagrams[names[0]]
    for name, d in diagrams.items():
        verdict = compare_disks(reference, d).verdict
        certified = certify_disks(d).ok
        print(f"{name}: {verdict.value} against {names[0]}, {'certified' if certified else 'NOT CERTIFIED'}")
        if verdict is not Verdict.EXACT or not certified:
            return 1
    fig, ax = plt.subplots(figsize=(7, 7))
    reference.plot(ax=ax, title=f"40 disks ({int(reference.hidden.size)} hidden): {', '.join(names)} agree exactly")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    plt.close(fig)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(*sys.argv[1:2]))
