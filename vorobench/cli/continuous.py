"""Benchmark two revisions of a git repository and compare them, like ``asv continuous``.

    vorobench continuous REV_A REV_B [--repo DIR] [--env shared|fresh] [bench options] [compare options]

Each revision is checked out in its own git worktree (the repository's own checkout is never
touched) and benchmarked by its own code with ``vorobench bench``. The revisions' repeats run
in interleaved rounds (``--rounds``, default 4): A, B, A, B, ..., each round a process of its
own with its share of ``--repeat``, so that a machine that gets busier half-way slows both
revisions alike instead of reading as a change (as asv's ``--interleave-rounds``). The load and
CPU frequency around each round are printed and kept in the results' metadata. Each
revision's rounds are merged into one results file, and ``vorobench compare`` judges REV_B
against REV_A, with the same rules and exit status: 1 when REV_B regressed, 0 when not (a
case whose noise cannot decide is inconclusive, and says so), 2 when a revision could not be
benchmarked.

Environments (``--env``):

* ``shared`` (default): both revisions run on this interpreter and its installed libraries,
  with the revision's worktree first on the import path. A change in the numbers is then a
  change in the code, never in a library. Entry points of the revision are not installed: a
  plugin repository names its module with ``--plugin``.
* ``fresh``: a virtual environment per revision, with the revision installed by pip
  (non-editable, dependencies included; for a repository that is not vorobench itself, this
  vorobench is installed beside it). Kept in ``--env-dir`` and reused for the same commit.

The repository may be vorobench itself (``continuous HEAD~1 HEAD``) or a plugin's. Runs are
also filed in ``--store DIR`` when given, so ``vorobench history``/``trend`` see them.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import sys
import tempfile
from pathlib import Path
from typing import Optional

from rich.console import Console

from vorobench.cli import bench as bench_cmd
from vorobench.cli import compare as compare_cmd
from vorobench.cli.args import positive_int
from vorobench.harness.continuous import (Worktree, bench_revision, fresh_environment, machine_state, merge_rounds,
                                          repository_root, resolve_revision, round_order)

# The harness and the judge are imported inside the functions that run the command, not here:
# the parser imports every command module (start-up time, measured in vorobench.cli).

__all__ = ["add_arguments", "run", "bench_arguments"]

#: bench options that continuous sets itself for each revision (each round).
_OWN_OPTIONS = {"out", "resume", "overwrite", "repeat", "store"}
#: bench options whose values are paths of the caller's, made absolute before a revision runs
#: in its worktree.
_PATH_OPTIONS = {"store"}


def bench_arguments(args: argparse.Namespace, repo: Optional[Path] = None) -> list[str]:
    """The bench options of ``args`` that differ from bench's defaults, as command-line words
    (paths of the caller's made absolute), for a revision's own ``vorobench bench``. A
    ``--plugin`` file inside ``repo`` is named relative to it: each revision runs its own copy
    (its worktree is the working directory), an executable's manifest and sources included."""
    parser = argparse.ArgumentParser(add_help=False)
    bench_cmd.add_arguments(parser)
    words: list[str] = []
    for action in parser._actions:
        dest = action.dest
        if dest in _OWN_OPTIONS or not action.option_strings or not hasattr(args, dest):
            continue
        value = getattr(args, dest)
        if value == action.default or value is None:
            continue
        flag = action.option_strings[-1]
        if isinstance(action, argparse._StoreTrueAction):
            words.append(flag)
        elif isinstance(action, argparse._AppendAction):
            for item in value:
                words += [flag, _revision_path(str(item), repo) if dest == "plugin" else _caller_path(str(item))]
        elif isinstance(value, (list, tuple)):
            words += [flag, ",".join(_caller_path(str(v)) if str(v).startswith("file:") else str(v) for v in value)]
        elif dest in _PATH_OPTIONS:
            words += [flag, str(Path(value).resolve())]
        else:
            words += [flag, str(value)]
    return words


def _caller_path(text: str) -> str:
    """A plugin or ``file:`` dataset that names a file of the caller's, made absolute (a module
    name stays as it is)."""
    prefix = "file:" if text.startswith("file:") else ""
    path = Path(text[len(prefix):])
    return prefix + str(path.resolve()) if path.exists() else text


def _revision_path(text: str, repo: Optional[Path]) -> str:
    """A plugin file of the repository as a path relative to its root (the revision's copy in
    its worktree); any other file made absolute, a module name left as it is."""
    path = Path(text)
    if repo is not None and path.exists():
        try:
            return str(path.resolve().relative_to(repo.resolve()))
        except ValueError:
            pass
    return _caller_path(text)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("rev_a", metavar="REV_A", help="the baseline revision (a commit, branch, tag, HEAD~1...)")
    p.add_argument("rev_b", metavar="REV_B", help="the revision judged against it")
    p.add_argument("--repo", default=".", help="the git repository (default: the one holding the current folder)")
    p.add_argument("--env", choices=("shared", "fresh"), default="shared",
                   help="shared: this interpreter and its libraries, the revision's code first on the path "
                        "(default); fresh: a virtual environment per revision with the revision installed")
    p.add_argument("--env-dir", default=None, metavar="DIR",
                   help="where --env fresh keeps its environments (default ~/.cache/vorobench/envs)")
    p.add_argument("--results-dir", default=None, metavar="DIR",
                   help="keep both results files here (default: a temporary folder, removed at the end)")
    p.add_argument("--rounds", type=positive_int, default=4,
                   help="interleaved rounds: the revisions run alternately, A, B, A, B, ..., each round in a "
                        "process of its own with its share of --repeat (default 4; 1 runs one revision after "
                        "the other)")
    bench = p.add_argument_group("bench options (passed to each revision's vorobench bench)")
    bench_cmd.add_arguments(bench)
    compare = p.add_argument_group("compare options")
    compare_cmd.add_arguments(compare, positional=False)


def run(args: argparse.Namespace) -> int:
    console = Console(stderr=True)
    repo = repository_root(args.repo)
    a, b = resolve_revision(repo, args.rev_a), resolve_revision(repo, args.rev_b)
    words = bench_arguments(args, repo)
    rounds = args.rounds
    per_round = max(1, math.ceil(args.repeat / rounds))
    env_dir = Path(args.env_dir).expanduser() if args.env_dir else Path.home() / ".cache" / "vorobench" / "envs"
    keep = Path(args.results_dir).resolve() if args.results_dir else None
    if keep is not None:
        keep.mkdir(parents=True, exist_ok=True)
    store = None
    if args.store:
        from vorobench.harness.store import Store

        store = Store(args.store)               # a file in its place is refused before any run
    revisions = {"a": a, "b": b}
    with tempfile.TemporaryDirectory(prefix="vorobench-continuous-") as scratch, contextlib.ExitStack() as stack:
        results_dir = keep or Path(scratch)
        trees, pythons = {}, {}
        for side, revision in revisions.items():
            trees[side] = stack.enter_context(Worktree(repo, revision, Path(scratch) / side))
            pythons[side] = (str(fresh_environment(trees[side], revision, env_dir, console)) if args.env == "fresh"
                             else sys.executable)
        console.print(f"{rounds} interleaved round(s), {per_round} repeat(s) each: "
                      + ", ".join(f"{revisions[side].name}" for _, side in round_order(rounds)))
        parts: dict[str, list[Path]] = {"a": [], "b": []}
        states: dict[str, list[dict]] = {"a": [], "b": []}
        for r, side in round_order(rounds):
            revision = revisions[side]
            out = results_dir / f"{side}-{revision.short}-round{r}.csv"
            for stale in (out, out.with_suffix(".meta.json")):
                stale.unlink(missing_ok=True)
            before = machine_state()
            status = bench_revision(revision, trees[side], pythons[side], args.env,
                                    [*words, "--repeat", str(per_round)], out, console)
            after = machine_state()
            states[side].append({"round": r, "before": before, "after": after})
            console.print(f"round {r}/{rounds}, {revision.name}: load {before['load1']} -> {after['load1']}"
                          + (f", CPU {before['cpu_mhz']:.0f} -> {after['cpu_mhz']:.0f} MHz"
                             if before.get("cpu_mhz") and after.get("cpu_mhz") else ""))
            if status != 0 or not out.exists():
                console.print(f"[bold red]vorobench continuous[/bold red]: the benchmark of {revision.name} "
                              f"({revision.short}) failed in round {r} (exit status {status}); nothing compared")
                return 2
            parts[side].append(out)
        outs = []
        for side, revision in revisions.items():
            merged = merge_rounds(parts[side], results_dir / f"{side}-{revision.short}.csv", states[side])
            if keep is None or rounds > 1:
                for part in parts[side]:
                    if part != merged:
                        part.unlink(missing_ok=True)
                        part.with_suffix(".meta.json").unlink(missing_ok=True)
            if store is not None:
                store.add_results(merged)
            outs.append(merged)
        compare_args = argparse.Namespace(**{k: getattr(args, k) for k in compare_cmd.OPTION_NAMES})
        compare_args.base, compare_args.new = str(outs[0]), str(outs[1])
        compare_args.title = f"{b.name} ({b.short}) vs {a.name} ({a.short})"
        status = compare_cmd.run(compare_args)
        if keep is not None:
            console.print(f"results kept: {outs[0]} and {outs[1]}")
        return status
