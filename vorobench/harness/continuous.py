"""Two revisions of a git repository benchmarked in their own worktrees and environments, for vorobench continuous.

The command line is :mod:`vorobench.cli.continuous`; its help text describes the behaviour."""

from __future__ import annotations

import os
import shutil
import subprocess
import time
import venv
from dataclasses import dataclass
from pathlib import Path
from typing import Optional, Sequence

__all__ = ["Revision", "Worktree", "repository_root", "resolve_revision", "fresh_environment", "bench_revision",
           "round_order", "machine_state", "merge_rounds"]


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


class Worktree:
    """A detached worktree of ``commit`` under ``parent``, removed (with git's record of it) on exit."""

    def __init__(self, repo: Path, revision: Revision, parent: Path) -> None:
        self.repo, self.revision = repo, revision
        self.path = parent / f"tree-{revision.short}"

    def __enter__(self) -> Path:
        self.path.parent.mkdir(parents=True, exist_ok=True)
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


def round_order(rounds: int) -> list[tuple[int, str]]:
    """(round, side) in the order the revisions run: A, B in every round (A, B, A, B, ...), so
    that a change of machine load during the run falls on both revisions alike."""
    return [(r, side) for r in range(1, rounds + 1) for side in ("a", "b")]


def machine_state() -> dict:
    """The machine's load (1-minute average) and mean CPU frequency (MHz, Linux) now, recorded
    around each round so that a busy or throttled machine shows in the results' metadata."""
    state: dict = {"time": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    try:
        state["load1"] = round(os.getloadavg()[0], 2)
    except OSError:
        state["load1"] = None
    try:
        mhz = [float(line.split(":")[1]) for line in Path("/proc/cpuinfo").read_text().splitlines()
               if line.lower().startswith("cpu mhz")]
        state["cpu_mhz"] = round(sum(mhz) / len(mhz), 1) if mhz else None
    except (OSError, ValueError, IndexError):
        state["cpu_mhz"] = None
    return state


def merge_rounds(paths: Sequence[Path], out: Path, rounds: list[dict]) -> Path:
    """One results file of a revision's interleaved rounds: every round's rows (column ``round``),
    each case's repeats numbered after those of the rounds before, under the first round's run
    id, with the rounds (and the machine's state around each) in its metadata."""
    import pandas as pd

    from vorobench.harness import results

    first = results.read_metadata(paths[0])
    run = dict((first.get("runs") or [{}])[0])
    frames = [results.load(p) for p in paths]
    run_id = str(run.get("run_id") or frames[0]["run_id"].dropna().astype(str).iloc[0])
    key = [c for c in results.CASE_KEY if c in frames[0].columns]
    taken: dict[tuple, int] = {}
    parts = []
    for number, frame in enumerate(frames, start=1):
        frame = frame.assign(run_id=run_id, round=number)
        if "repeat" in frame.columns:
            repeat = pd.to_numeric(frame["repeat"], errors="coerce")
            cases = [tuple(k) for k in frame[key].astype(str).itertuples(index=False)]
            frame["repeat"] = [r + taken.get(c, 0) if r == r else r for r, c in zip(repeat, cases)]
            used: dict[tuple, int] = {}          # repeats this round gave each case
            for c, r in zip(cases, repeat):
                if r == r:
                    used[c] = max(used.get(c, 0), int(r) + 1)
            for c, k in used.items():
                taken[c] = taken.get(c, 0) + k
        parts.append(frame)
    merged = pd.concat(parts, ignore_index=True)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    merged.to_csv(out, index=False)
    results.metadata_path(out).unlink(missing_ok=True)
    run.update(run_id=run_id, rounds=rounds, interleaved=len(paths) > 1)
    results.append_run_metadata(out, run)
    return out
