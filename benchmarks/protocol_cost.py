"""What the executable protocol costs: CGAL's C++ program fed text or binary input.

    .venv/bin/python benchmarks/protocol_cost.py [--n N] [--rounds R] [--dataset D]

One compiled program (the shipped ``cgal-cpp`` reference, set up first) is run through two
manifests that differ only in ``input`` (text or binary), alternating round by round (text,
binary, text, ...) on the same prepared sites, so a change of machine load falls on both.
Each round prints the program's whole-process wall time, its own ``time`` line (the range
insert), the part of the process that is not construction (start, reading input, writing
triangles) and the harness's side (encoding the input; parsing and assembling the answer),
then the medians per input format.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
from pathlib import Path

import datasets_gen
from impls.executable import REFERENCES, ensure_setup, implementation_of, read_manifest
from vorobench.core.prepare import prepare


def manifests(folder: Path) -> dict[str, Path]:
    """The text and binary manifests of the one compiled cgal-cpp program."""
    reference = read_manifest(REFERENCES / "cgal-cpp" / "impl.toml")
    ensure_setup(reference)
    program = reference.cache() / "cgal_triangulate"
    out = {}
    for fmt, extra in (("text", ""), ("binary", ', "--binary"')):
        path = folder / f"{fmt}.toml"
        path.write_text(f'[implementation]\nname = "cgal-{fmt}"\ncommand = ["{program}"{extra}]\n'
                        f'output = "triangles"\nexact = true\ncomplexity = "O(n log n)"\ninput = "{fmt}"\n')
        out[fmt] = path
    return out


def one_run(impl, sites) -> dict[str, float]:
    timings: dict = {}
    process: dict = {}
    impl.run(sites, None, timings=timings, process=process)
    return {"process": process["wall_s"], "library": timings.get("library", float("nan")),
            "protocol": timings["protocol"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=float, default=1e6)
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--dataset", default="uniform")
    args = parser.parse_args()
    sites, _ = prepare(datasets_gen.generate(args.dataset, int(args.n), seed=0))
    sites.setflags(write=False)
    with tempfile.TemporaryDirectory() as scratch:
        impls = {fmt: implementation_of(read_manifest(path)) for fmt, path in manifests(Path(scratch)).items()}
        for impl in impls.values():
            impl.build(sites[:100].copy(), None)                # page in the program and its libraries
        runs: dict[str, list[dict]] = {fmt: [] for fmt in impls}
        print(f"{args.dataset}, n = {sites.shape[0]}: seconds per round (process wall | its time line | "
              f"the rest of the process | harness: encode + parse + assemble)")
        for r in range(args.rounds):
            for fmt, impl in impls.items():
                run = one_run(impl, sites)
                runs[fmt].append(run)
                print(f"round {r + 1} {fmt:6s}: {run['process']:7.3f} | {run['library']:7.3f} | "
                      f"{run['process'] - run['library']:7.3f} | {run['protocol']:7.3f}", flush=True)
        print("medians:")
        for fmt, rows in runs.items():
            med = {k: statistics.median(r[k] for r in rows) for k in rows[0]}
            print(f"  {fmt:6s}: process {med['process']:.3f} s, construction {med['library']:.3f} s, "
                  f"rest of the process {med['process'] - med['library']:.3f} s, harness {med['protocol']:.3f} s")


if __name__ == "__main__":
    main()
