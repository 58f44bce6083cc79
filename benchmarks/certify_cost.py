"""What the exact certifier costs against the float one it replaced (issue 22's bound: 1.5x at 10^6).

    .venv/bin/python benchmarks/certify_cost.py [--base REV] [--n N] [--rounds R] [--datasets a,b]

Both certifiers run in this one process on the same diagrams, alternating round by round (old,
new, old, new, ...), so a change of machine load falls on both; the old one is
``vorobench/judge/certificate.py`` as it was at ``--base`` (default: d3d1aa1, the last commit
before the exact topology check), loaded from git. Compilation is excluded (a small warm-up of
each first). Prints each round's seconds, the medians and their ratio per dataset.
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path


import datasets_gen
import impls
from vorobench.judge.certificate import certify

ROOT = Path(__file__).resolve().parent.parent


def certifier_at(rev: str):
    """``certify`` of vorobench/judge/certificate.py at git revision ``rev``, as a module of its own."""
    source = subprocess.run(["git", "-C", str(ROOT), "show", f"{rev}:vorobench/judge/certificate.py"],
                            check=True, capture_output=True, text=True).stdout
    path = Path(tempfile.mkdtemp()) / "certificate_before.py"
    path.write_text(source)
    spec = importlib.util.spec_from_file_location("certificate_before", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module.certify


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--base", default="d3d1aa1")
    parser.add_argument("--n", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--datasets", default="uniform,near_grid")
    args = parser.parse_args()
    before = certifier_at(args.base)
    warm = impls.build("incremental", datasets_gen.generate("uniform", 1000))
    before(warm), certify(warm)
    for dataset in args.datasets.split(","):
        d = impls.build("incremental", datasets_gen.generate(dataset, args.n, seed=0))
        seconds = {"before": [], "now": []}
        for r in range(args.rounds):
            for name, fn in (("before", before), ("now", certify)) if r % 2 == 0 else (("now", certify),
                                                                                      ("before", before)):
                t0 = time.perf_counter()
                cert = fn(d)
                seconds[name].append(time.perf_counter() - t0)
                print(f"{dataset} n={d.n_sites} round {r} {name:6s} {seconds[name][-1]:.2f} s ok={cert.ok}", flush=True)
        old, new = statistics.median(seconds["before"]), statistics.median(seconds["now"])
        print(f"{dataset} n={d.n_sites}: before {old:.2f} s, now {new:.2f} s (medians of {args.rounds}): "
              f"ratio {new / old:.2f}")


if __name__ == "__main__":
    main()
