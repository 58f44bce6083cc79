"""Where a whole build's time goes, from ``impls.build`` to the returned ``Diagram``, and what
the first views cost after it: the breakdown issue 27 asks to be rerun, not remembered.

    .venv/bin/python benchmarks/build_breakdown.py                    # 10^6 uniform, best of 3
    .venv/bin/python benchmarks/build_breakdown.py --n 100000 --rounds 5

Per construction (``incremental``, ``fortune``), one process, the rounds alternated:

* ``prepare``: ``vorobench.prepare`` (range check, sorting, duplicates);
* ``run around the build``: what ``Implementation.run`` adds around the implementation's own
  ``build`` (the scaling decision, the read-only copy, the input-mutation check), timed as
  ``run`` of the same implementation whose build hands back a diagram made before; the
  wrapper is this plus ``prepare`` (and ``with_input``, which uniform sites do not need);
* the build's own stages, timed by calling them in the order the build does (the diagram
  they give is checked against ``impls.build``'s, so the stages are the build's):
  ``incremental``: insertion order, triangulation, dual (Voronoi vertices and DCEL);
  ``fortune``: event order, sweep, DCEL (``assemble``), site ids mapped back;
* ``whole``: ``impls.build`` as a user calls it.

Then, on the last diagram: ``regions`` (first call), ``to_shapely`` against
``shapely.voronoi_polygons`` of the same points, and the peak resident memory of a fresh
process that builds with ``fortune`` (from ``/proc``, the build alone, after the imports and
the points). Numba compile time is spent in warm-ups before any timing.
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
import time
from dataclasses import replace
from typing import Callable

import numpy as np

import datasets_gen
import impls
from impls.fortune import _event_order
from impls.fortune.sweep import N_COUNTERS as FORTUNE_COUNTERS
from impls.fortune.sweep import OK, sweep
from impls.incremental import _triangulate
from vorobench.core.builder import assemble
from vorobench.core.delaunay_dual import voronoi_dcel
from vorobench.core.diagram import Diagram
from vorobench.core.prepare import prepare

#: The goals of issue 27 this script reads.
DUAL_GOAL_S = 0.15
WRAPPER_GOAL = 0.05
REGIONS_GOAL_S = 0.3
SHAPELY_GOAL = 2.0
PEAK_GOAL_MB = 700.0

_PEAK = """
import sys, numpy as np, datasets_gen, impls
from vorobench.harness.peakmem import peak_rss_mb, reset_peak
n = int(sys.argv[1])
impls.get("fortune").warmup()
points = datasets_gen.generate("uniform", n, seed=0)
reset_peak()
before = peak_rss_mb()
d = impls.build("fortune", points)
print(before, peak_rss_mb())
"""


def _timed(fn: Callable[[], object]) -> tuple[float, object]:
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def incremental_stages(sites: np.ndarray) -> tuple[dict[str, float], Diagram]:
    """The incremental build's stages, as ``impls.incremental.build`` runs them."""
    times: dict[str, float] = {}
    t0 = time.perf_counter()
    points, ids, tri, opp, ntri, ok = _triangulate(sites, None)
    times["order + triangulation"] = time.perf_counter() - t0
    assert ok, "the breakdown needs sites that are not all collinear"
    counters = np.zeros(4, dtype=np.int64)
    t, (vertices, origin, twin, nxt, site, _) = _timed(lambda: voronoi_dcel(points, ids, tri, opp, ntri, counters))
    times["dual"] = t
    t, d = _timed(lambda: Diagram(sites, vertices, origin, twin, nxt, site))
    times["Diagram"] = t
    return times, d


def fortune_stages(sites: np.ndarray) -> tuple[dict[str, float], Diagram]:
    """The ordinary sweep's stages, as ``impls.fortune.build`` runs them."""
    times: dict[str, float] = {}
    t, order = _timed(lambda: _event_order(sites))
    times["event order"] = t
    t, swept = _timed(lambda: np.ascontiguousarray(sites[order]))
    times["copy in event order"] = t
    counters = np.zeros(FORTUNE_COUNTERS, dtype=np.int64)
    t, (status, edge_sites, edge_vertices, vertices) = _timed(lambda: sweep(swept, counters))
    assert status == OK
    times["sweep"] = t
    t, built = _timed(lambda: assemble(swept, vertices, edge_sites, edge_vertices))
    times["DCEL (assemble)"] = t
    t, d = _timed(lambda: Diagram(sites, built.vertices, built.origin, built.twin, built.next, order[built.site]))
    times["ids back + Diagram"] = t
    return times, d


STAGES = {"incremental": incremental_stages, "fortune": fortune_stages}


def _same(a: Diagram, b: Diagram) -> bool:
    return all(np.array_equal(getattr(a, f), getattr(b, f)) for f in ("vertices", "origin", "twin", "next", "site"))


def breakdown(n: int, rounds: int, log=print) -> dict[str, dict[str, float]]:
    """Best-of-``rounds`` seconds of every part, per construction."""
    points = datasets_gen.generate("uniform", n, seed=0)
    for name in STAGES:
        impls.get(name).warmup()
    best: dict[str, dict[str, float]] = {name: {} for name in STAGES}

    def keep(name: str, part: str, seconds: float) -> None:
        best[name][part] = min(best[name].get(part, math.inf), seconds)

    for r in range(rounds):
        for name, stages in STAGES.items():
            impl = impls.get(name)
            t, (sites, _) = _timed(lambda: prepare(points))
            keep(name, "prepare", t)
            given = np.array(sites, copy=True)
            given.setflags(write=False)
            t, bare = _timed(lambda: impl.build(given, None))
            keep(name, "bare build", t)
            made_before = replace(impl, build=lambda s, stats=None: bare)
            t, _ = _timed(lambda: made_before.run(sites))
            keep(name, "run around the build", t)
            times, staged = stages(given)
            if not _same(staged, bare):
                raise SystemExit(f"{name}: the stages timed here no longer give the build's diagram")
            for part, seconds in times.items():
                keep(name, part, seconds)
            t, whole = _timed(lambda: impls.build(name, points))
            keep(name, "whole", t)
            log(f"round {r + 1}/{rounds} {name}: whole {t:.3f} s")
    return best


def views(n: int, rounds: int) -> dict[str, float]:
    """First-call seconds of ``regions``, ``to_shapely`` and ``shapely.voronoi_polygons``."""
    import shapely

    points = datasets_gen.generate("uniform", n, seed=0)
    out: dict[str, float] = {}
    d = impls.build("incremental", points)
    d.to_shapely()                                   # compiles the clipping kernels
    box = d.bounding_box(0.1)
    for _ in range(rounds):
        d = impls.build("incremental", points)
        t, _ = _timed(lambda: d.regions)
        out["regions"] = min(out.get("regions", math.inf), t)
        t, _ = _timed(lambda: d.to_shapely(box))
        out["to_shapely"] = min(out.get("to_shapely", math.inf), t)
        multipoint = shapely.multipoints(points)
        t, _ = _timed(lambda: shapely.voronoi_polygons(multipoint, extend_to=shapely.box(*box), ordered=True))
        out["shapely.voronoi_polygons"] = min(out.get("shapely.voronoi_polygons", math.inf), t)
    return out


def fortune_peak_mb(n: int) -> tuple[float, float]:
    """(resident MB before the build, peak MB during it) in a fresh process."""
    out = subprocess.run([sys.executable, "-c", _PEAK, str(n)], capture_output=True, text=True, check=True)
    before, peak = out.stdout.split()[-2:]
    return float(before), float(peak)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=1_000_000, help="uniform sites (default 10^6)")
    parser.add_argument("--rounds", type=int, default=3, help="rounds; the best of each part is kept")
    parser.add_argument("--views-n", type=int, default=None,
                        help="sites for to_shapely against shapely (default: --n, at most 10^5)")
    parser.add_argument("--skip-memory", action="store_true")
    args = parser.parse_args(argv)
    log = lambda s: print(s, file=sys.stderr, flush=True)  # noqa: E731

    best = breakdown(args.n, args.rounds, log)
    print(f"Whole build of {args.n:,} uniform sites, best of {args.rounds} (seconds, share of `whole`):\n")
    for name, parts in best.items():
        whole = parts["whole"]
        wrapper = parts["prepare"] + parts["run around the build"]
        print(f"{name}:")
        for part, seconds in parts.items():
            if part != "whole":
                print(f"  {part:<24} {seconds:8.3f} s  {seconds / whole:6.1%}")
        print(f"  {'wrapper (prepare + run)':<24} {wrapper:8.3f} s  {wrapper / whole:6.1%}  "
              f"(goal: at most {WRAPPER_GOAL:.0%})")
        print(f"  {'whole':<24} {whole:8.3f} s")
        if "dual" in parts:
            print(f"  the dual: {parts['dual']:.3f} s (goal: at most {DUAL_GOAL_S} s)")
    regions_n = args.n
    shapely_n = args.views_n or min(args.n, 100_000)
    v = views(regions_n, args.rounds)
    print(f"\n`regions`, first call, at {regions_n:,}: {v['regions']:.3f} s (goal: at most {REGIONS_GOAL_S} s)")
    if shapely_n != regions_n:
        v = views(shapely_n, args.rounds)
    ratio = v["to_shapely"] / v["shapely.voronoi_polygons"]
    print(f"`to_shapely` at {shapely_n:,}: {v['to_shapely']:.3f} s, shapely.voronoi_polygons "
          f"{v['shapely.voronoi_polygons']:.3f} s: {ratio:.2f}x (goal: at most {SHAPELY_GOAL:g}x)")
    if not args.skip_memory:
        before, peak = fortune_peak_mb(args.n)
        print(f"fortune at {args.n:,}: peak resident {peak:.0f} MB ({before:.0f} MB before the build; "
              f"goal: under {PEAK_GOAL_MB:.0f} MB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
