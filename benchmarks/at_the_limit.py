"""The constructions at 10^6 against Triangle and CGAL, degenerate families included, in one process.

    .venv/bin/python benchmarks/at_the_limit.py                          # the table at 10^6
    .venv/bin/python benchmarks/at_the_limit.py --sizes 1e4,1e5,1e6      # with fitted exponents
    .venv/bin/python benchmarks/at_the_limit.py --families uniform,grid --rounds 3 --json out.json
    .venv/bin/python benchmarks/at_the_limit.py --breakdown              # and every goal of issue 27

For each family the points are generated and prepared once; then the contenders take turns,
round after round (``--rounds``, best of them is kept), so all of them see the same machine
load. Columns:

* ``fortune``, ``incremental``: the whole build (``Implementation.run``: diagram included).
* ``triangle -F`` and ``triangle D&C``: Triangle's own call only (the adapters' ``library``
  timing; the dualisation is not counted), as in the issue's table.
* ``cgal``: ``Delaunay_triangulation_2.insert`` of the list of points only (the adapter's
  ``library`` timing; making the list and reading the faces back are not counted).

Below the table: each construction's time as a multiple of its own uniform time, the ratios
the goals name (fortune / Triangle -F, incremental / CGAL), ``prepare`` against one
``np.lexsort`` of the same points, and, with several sizes, the fitted exponent of every
family (least squares of log time on log n over the sizes of at least 10^4 sites). Missing
outside libraries are left out of the table, never an error. Numba compile time is spent in
each construction's warm-up before any timing. ``--breakdown`` then prints
``benchmarks/build_breakdown.py``'s rows at the largest size (the dual, the wrapper, ``regions``,
``to_shapely``, fortune's peak memory), so that one run prints every goal of issue 27.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from typing import Optional

import numpy as np

import datasets_gen
import impls
from vorobench.cli.args import sizes as parse_sizes
from vorobench.core.prepare import prepare
from vorobench.harness.analysis import loglog_fit

#: (column, implementation, which time): "total" is the whole run, "library" the outside
#: library's own call.
CONTENDERS = (
    ("fortune", "fortune", "total"),
    ("incremental", "incremental", "total"),
    ("triangle -F", "triangle-sweep", "library"),
    ("triangle D&C", "triangle", "library"),
    ("cgal", "cgal", "library"),
)
FAMILIES = ("uniform", "grid", "lattice_rotated", "near_grid", "kuzmin", "duplicates", "cocircular_many",
            "cocircular", "disk", "normal", "clusters", "corners", "diagonal", "cross", "parabola", "collinear",
            "huge_offset", "tiny_spacing", "sorted")
FIT_MIN_SITES = 10_000
#: Sizes a contender is first tried at, unrecorded, when a family starts above them, so that a
#: contender that is quadratic on the family (CGAL's insertion of collinear points: 0.67 s at
#: 16,000 sites, about 40 minutes at 10^6) is extrapolated and skipped instead of run.
PILOT_SIZES = (1_000, 10_000)


def _time_once(name: str, sites: np.ndarray, which: str) -> float:
    impl = impls.get(name)
    timings: dict = {}
    t0 = time.perf_counter()
    impl.run(sites, {}, timings=timings, check_supports=False)
    total = time.perf_counter() - t0
    return timings.get("library", math.nan) if which == "library" else total


def _available(rows) -> list:
    here = set(impls.available())
    return [row for row in rows if row[1] in here]


def _extrapolated(history: list[tuple[int, float]], n: int) -> Optional[float]:
    """Seconds a contender would take at n sites, from its times at smaller sizes (at least
    linear growth; the slope of the last two sizes when it is steeper)."""
    if not history:
        return None
    (n1, t1) = history[-1]
    slope = 1.0
    if len(history) >= 2:
        (n0, t0) = history[-2]
        if n1 > n0 and t0 > 0 and t1 > 0:
            slope = max(1.0, math.log(t1 / t0) / math.log(n1 / n0))
    return t1 * (n / n1) ** slope


def _pilot(name: str, family: str, which: str) -> list[tuple[int, float]]:
    """(n, seconds) of one run at each pilot size, for extrapolation only; empty if the
    contender cannot run the family."""
    times = []
    for n in PILOT_SIZES:
        sites, _ = prepare(datasets_gen.generate(family, n, seed=0))
        if impls.get(name).unsupported_reason(sites):
            return []
        try:
            times.append((int(sites.shape[0]), _time_once(name, sites, which)))
        except Exception:  # the real size records the failure
            return []
    return times


def measure(families, sizes, rounds: int, log=print, budget: float = 60.0) -> list[dict]:
    """One record per (family, n, column): the best of ``rounds`` timings, or the reason why
    none (unsupported, failed, or skipped: extrapolated past ``budget`` seconds)."""
    contenders = _available(CONTENDERS)
    for _, name, _ in contenders:
        impl = impls.get(name)
        if impl.warmup:
            impl.warmup()
    records = []
    for family in families:
        history: dict[str, list[tuple[int, float]]] = {}
        for n in sizes:
            sites, _ = prepare(datasets_gen.generate(family, n, seed=0))
            points = datasets_gen.generate(family, n, seed=0)
            t0 = time.perf_counter()
            prepare(points)
            prep = time.perf_counter() - t0
            t0 = time.perf_counter()
            np.lexsort((points[:, 0], points[:, 1]))
            lexsort = time.perf_counter() - t0
            best: dict[str, float] = {}
            why: dict[str, str] = {}
            for column, name, which in contenders:
                if column not in history and sites.shape[0] > 10 * PILOT_SIZES[-1]:
                    history[column] = _pilot(name, family, which)
                guess = _extrapolated(history.get(column, []), sites.shape[0])
                if guess is not None and guess > budget:
                    why[column] = f"skipped: extrapolated {guess:.0f} s > budget {budget:g} s"
            for _ in range(rounds):
                for column, name, which in contenders:
                    if column in why:
                        continue
                    reason = impls.get(name).unsupported_reason(sites)
                    if reason:
                        why[column] = f"unsupported: {reason}"
                        continue
                    try:
                        seconds = _time_once(name, sites, which)
                    except Exception as exc:  # a failing contender is recorded, the table goes on
                        why[column] = f"{type(exc).__name__}: {exc}"
                        continue
                    best[column] = min(best.get(column, math.inf), seconds)
            for column, seconds in best.items():
                history.setdefault(column, []).append((int(sites.shape[0]), seconds))
            for column, name, which in contenders:
                records.append({"family": family, "n": int(sites.shape[0]), "requested_n": n, "column": column,
                                "impl": name, "time": which, "seconds": best.get(column),
                                "note": why.get(column), "prepare_s": prep, "lexsort_s": lexsort})
            shown = ", ".join(f"{c} {best[c]:.3f}s" if c in best else f"{c} -" for c, _, _ in contenders)
            log(f"{family} n={sites.shape[0]}: {shown}  (prepare {prep:.3f}s, lexsort {lexsort:.3f}s)")
    return records


def cocircular_growth(rounds: int) -> list[str]:
    """The goal for cocircular input: 4x the sites (1,536 -> 6,144, one circle) at most 8x the time."""
    out = []
    small = prepare(datasets_gen.generate("cocircular", 1536, seed=0))[0]
    large = prepare(datasets_gen.generate("cocircular", 6144, seed=0))[0]
    for column, name, _ in _available(CONTENDERS[:2]):
        a = min(_time_once(name, small, "total") for _ in range(max(rounds, 3)))
        b = min(_time_once(name, large, "total") for _ in range(max(rounds, 3)))
        out.append(f"* cocircular {column}: 1,536 sites {a * 1e3:.1f} ms, 6,144 sites {b * 1e3:.1f} ms: "
                   f"{b / a:.1f}x the time for 4x the sites (goal: at most 8x)")
    return out


def _fit(points: list[tuple[int, float]]) -> Optional[float]:
    points = [(n, s) for n, s in points if n >= FIT_MIN_SITES and s and s > 0]
    if len({n for n, _ in points}) < 2:
        return None
    return loglog_fit([n for n, _ in points], [s for _, s in points])[0]


def table(records: list[dict]) -> str:
    """The Markdown table at the largest size, then the ratios and exponents."""
    columns = list(dict.fromkeys(r["column"] for r in records))
    largest = max(r["requested_n"] for r in records)
    at = [r for r in records if r["requested_n"] == largest]
    families = list(dict.fromkeys(r["family"] for r in at))
    cell = {(r["family"], r["column"]): r for r in at}

    def fmt(r) -> str:
        return "-" if r is None or r["seconds"] is None else f"{r['seconds']:.2f} s"

    lines = [f"| input ({largest:.0e} requested) | n | " + " | ".join(columns) + " |",
             "|---|---|" + "---|" * len(columns)]
    for f in families:
        n = next(r["n"] for r in at if r["family"] == f)
        lines.append(f"| {f} | {n} | " + " | ".join(fmt(cell.get((f, c))) for c in columns) + " |")
    out = ["\n".join(lines), ""]
    # each construction against its own uniform time
    own = [c for c in ("fortune", "incremental") if c in columns]
    if "uniform" in families:
        out.append("Multiple of the construction's own uniform time (goal: at most 2):")
        for c in own:
            base = cell[("uniform", c)]["seconds"]
            worst = [(cell[(f, c)]["seconds"] / base, f) for f in families
                     if base and cell.get((f, c)) and cell[(f, c)]["seconds"]]
            worst.sort(reverse=True)
            out.append(f"* {c}: " + ", ".join(f"{f} {x:.2f}x" for x, f in worst))
        pairs = [("fortune", "triangle -F", 1.0), ("incremental", "cgal", 1.5)]
        for a, b, goal in pairs:
            ra, rb = cell.get(("uniform", a)), cell.get(("uniform", b))
            if ra and rb and ra["seconds"] and rb["seconds"]:
                out.append(f"* uniform: {a} / {b} = {ra['seconds'] / rb['seconds']:.2f} (goal: at most {goal})")
        u = cell.get(("uniform", columns[0]))
        if u:
            out.append(f"* prepare / np.lexsort at uniform: {u['prepare_s'] / u['lexsort_s']:.2f} "
                       "(goal: at most 1.5)")
    sizes = sorted({r["requested_n"] for r in records})
    if len(sizes) >= 2:
        out.append("")
        out.append(f"Fitted exponents over sizes >= {FIT_MIN_SITES} (goal: at most 1.15):")
        for c in own:
            fits = []
            for f in families:
                e = _fit([(r["n"], r["seconds"]) for r in records if r["family"] == f and r["column"] == c])
                if e is not None:
                    fits.append((e, f))
            fits.sort(reverse=True)
            out.append(f"* {c}: " + ", ".join(f"{f} {e:.2f}" for e, f in fits))
    notes = [r for r in at if r["note"]]
    if notes:
        out.append("")
        out.extend(f"* {r['column']} on {r['family']}: {r['note']}" for r in notes)
    return "\n".join(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--families", default=",".join(FAMILIES), help="comma-separated dataset families")
    parser.add_argument("--sizes", type=parse_sizes, default=[1_000_000], help="sizes, e.g. 1e4,1e5,1e6")
    parser.add_argument("--rounds", type=int, default=2, help="rounds per case; the best is kept (default 2)")
    parser.add_argument("--budget", type=float, default=60.0,
                        help="skip a contender whose time, extrapolated from smaller sizes, exceeds this (s)")
    parser.add_argument("--json", default=None, help="also write the records to this JSON file")
    parser.add_argument("--breakdown", action="store_true",
                        help="then print build_breakdown's rows at the largest size (the dual, the wrapper, "
                             "regions, to_shapely, fortune's peak memory)")
    args = parser.parse_args(argv)
    families = [f for f in args.families.split(",") if f]
    unknown = [f for f in families if f not in datasets_gen.available()]
    if unknown:
        parser.error(f"unknown families: {', '.join(unknown)}")
    records = measure(families, args.sizes, args.rounds, log=lambda s: print(s, file=sys.stderr, flush=True),
                      budget=args.budget)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(records, f, indent=1)
    print(table(records))
    if "cocircular" in families:
        print("\n".join(cocircular_growth(args.rounds)))
    if args.breakdown:
        import build_breakdown

        print()
        sys.stdout.flush()
        return build_breakdown.main(["--n", str(max(args.sizes)), "--rounds", str(args.rounds)])
    return 0


if __name__ == "__main__":
    sys.exit(main())
