"""Benchmark two revisions of a git repository and compare them, like ``asv continuous``.

    vorobench continuous REV_A REV_B [--repo DIR] [--env shared|fresh] [bench options] [compare options]

Each revision is checked out in its own git worktree (the repository's own checkout is never
touched) and benchmarked by its own code with ``vorobench bench``, one revision after the
other, into its own results file. Then ``vorobench compare`` judges REV_B against REV_A, with
the same rules and exit status: 1 when REV_B regressed, 0 when not, 2 when a revision could not
be benchmarked.

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
import os
import shutil
import subprocess
import sys
import tempfile
import venv
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Sequence

__all__ = ["add_arguments", "run", "Revision", "resolve_revision", "bench_arguments"]

#: bench options that continuous sets itself for each revision.
_OWN_OPTIONS = {"out", "resume", "overwrite"}
#: bench options whose values are paths of the caller's, made absolute before a revision runs
#: in its worktree.
_PATH_OPTIONS = {"store"}


@dataclass(frozen=True)
class Revision:
    """A revision as the user named it and the commit it resolved to."""

    name: str
    commit: str

    @property
    def short(self) -> str:
        return self.commit[:10]


def _git(repo: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["git", "-C", str(repo), *args], capture_output=True, text=True, timeout=120)


def repository_root(path: str | Path) -> Path:
    """The top folder of the git repository holding ``path``; ValueError in one line if none."""
    path = Path(path).resolve()
    if not path.exists():
        raise ValueError(f"--repo {path}: no such folder")
    try:
        top = _git(path, "rev-parse", "--show-toplevel")
    except FileNotFoundError:
        raise ValueError("git is not installed: continuous needs it to check revisions out") from None
    if top.returncode != 0:
        raise ValueError(f"{path} is not inside a git repository")
    return Path(top.stdout.strip())


def resolve_revision(repo: Path, name: str) -> Revision:
    """The commit ``name`` (a branch, tag, ``HEAD~1``, a hash...) stands for in ``repo``."""
    if not name or name.startswith("-"):
        raise ValueError(f"{name!r} is not a revision")
    found = _git(repo, "rev-parse", "--verify", "--quiet", f"{name}^{{commit}}")
    if found.returncode != 0:
        raise ValueError(f"{name!r} is not a commit of {repo}")
    return Revision(name, found.stdout.strip())


def bench_arguments(args: argparse.Namespace) -> list[str]:
    """The bench options of ``args`` that differ from bench's defaults, as command-line words
    (paths of the caller's made absolute), for a revision's own ``vorobench bench``."""
    from vorobench.cli import bench as bench_cmd

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
                words += [flag, _caller_path(str(item))]
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


class Worktree:
    """A detached worktree of ``commit`` under ``parent``, removed (with git's record of it) on exit."""

    def __init__(self, repo: Path, revision: Revision, parent: Path) -> None:
        self.repo, self.revision = repo, revision
        self.path = parent / f"tree-{revision.short}"

    def __enter__(self) -> Path:
        if self.path.exists():
            self._remove()
        added = _git(self.repo, "worktree", "add", "--detach", "--force", str(self.path), self.revision.commit)
        if added.returncode != 0:
            raise ValueError(f"could not check out {self.revision.name} ({self.revision.short}): "
                             f"{added.stderr.strip() or added.stdout.strip()}")
        return self.path

    def __exit__(self, *exc) -> None:
        self._remove()

    def _remove(self) -> None:
        _git(self.repo, "worktree", "remove", "--force", str(self.path))
        shutil.rmtree(self.path, ignore_errors=True)
        _git(self.repo, "worktree", "prune")


def _vorobench_source() -> Optional[Path]:
    """The source tree of the running vorobench, when it is one (an editable or source install)."""
    root = Path(__file__).resolve().parent.parent
    return root if (root / "pyproject.toml").exists() else None


def _is_vorobench(tree: Path) -> bool:
    return (tree / "vorobench" / "__init__.py").exists() and (tree / "impls").is_dir()


def fresh_environment(tree: Path, revision: Revision, env_dir: Path, console) -> Path:
    """A virtual environment with ``revision`` installed (made once per commit): its python."""
    env = env_dir / revision.commit
    python = env / ("Scripts" if os.name == "nt" else "bin") / "python"
    stamp = env / ".vorobench-installed"
    if stamp.exists() and python.exists():
        return python
    shutil.rmtree(env, ignore_errors=True)
    console.print(f"creating an environment for {revision.name} ({revision.short}) in {env}")
    venv.EnvBuilder(with_pip=True).create(env)
    wanted = [str(tree)]
    if not _is_vorobench(tree):
        source = _vorobench_source()
        if source is None:
            raise ValueError("--env fresh on a plugin repository needs vorobench installed from its source tree")
        wanted.append(str(source))
    pip = [str(python), "-m", "pip", "install", "--disable-pip-version-check", "-q", *wanted]
    done = subprocess.run(pip, capture_output=True, text=True)
    if done.returncode != 0:
        tail = "; ".join(done.stderr.strip().splitlines()[-3:])
        raise ValueError(f"installing {revision.name} ({revision.short}) failed: {tail}")
    stamp.write_text(revision.commit + "\n")
    return python


def bench_revision(revision: Revision, tree: Path, python: str, env_mode: str, words: Sequence[str],
                   out: Path, console) -> int:
    """Run the revision's own ``vorobench bench`` in its worktree; its exit status."""
    environ = dict(os.environ)
    if env_mode == "shared":
        # The worktree is the working directory, so its packages come first on the path of the
        # harness and of every worker it starts (``''`` leads sys.path for -m and -c).
        environ["PYTHONPATH"] = os.pathsep.join(p for p in (str(tree), environ.get("PYTHONPATH", "")) if p)
    command = [python, "-m", "vorobench", "bench", *words, "--out", str(out)]
    console.print(f"[bold]{revision.name}[/bold] ({revision.short}): vorobench bench {' '.join(words)}")
    return subprocess.call(command, cwd=tree, env=environ)


# ------------------------------------------------------------------------------ CLI

def add_arguments(p: argparse.ArgumentParser) -> None:
    from vorobench.cli import bench as bench_cmd
    from vorobench.harness import regress

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
    bench = p.add_argument_group("bench options (passed to each revision's vorobench bench)")
    bench_cmd.add_arguments(bench)
    compare = p.add_argument_group("compare options")
    regress.add_arguments(compare, positional=False)


def run(args: argparse.Namespace) -> int:
    from rich.console import Console

    from vorobench.harness import regress

    console = Console(stderr=True)
    repo = repository_root(args.repo)
    a, b = resolve_revision(repo, args.rev_a), resolve_revision(repo, args.rev_b)
    words = bench_arguments(args)
    env_dir = Path(args.env_dir).expanduser() if args.env_dir else Path.home() / ".cache" / "vorobench" / "envs"
    keep = Path(args.results_dir).resolve() if args.results_dir else None
    if keep is not None:
        keep.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="vorobench-continuous-") as scratch:
        results_dir = keep or Path(scratch)
        outs = []
        for side, revision in (("a", a), ("b", b)):
            out = results_dir / f"{side}-{revision.short}.csv"
            for stale in (out, out.with_suffix(".meta.json")):
                stale.unlink(missing_ok=True)
            with Worktree(repo, revision, Path(scratch)) as tree:
                python = (str(fresh_environment(tree, revision, env_dir, console)) if args.env == "fresh"
                          else sys.executable)
                status = bench_revision(revision, tree, python, args.env, words, out, console)
            if status != 0 or not out.exists():
                console.print(f"[bold red]vorobench continuous[/bold red]: the benchmark of {revision.name} "
                              f"({revision.short}) failed (exit status {status}); nothing compared")
                return 2
            outs.append(out)
        compare_args = argparse.Namespace(**{k: getattr(args, k) for k in regress.OPTION_NAMES})
        compare_args.base, compare_args.new = str(outs[0]), str(outs[1])
        compare_args.title = f"{b.name} ({b.short}) vs {a.name} ({a.short})"
        status = regress.run(compare_args)
        if keep is not None:
            console.print(f"results kept: {outs[0]} and {outs[1]}")
        return status
