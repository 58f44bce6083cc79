"""Does `vorobench continuous` hold on a busy machine? (issue 23's acceptance run)

    .venv/bin/python benchmarks/continuous_under_load.py [--times 5] [--sizes 1k,10k]

Builds a plugin repository (as tests/cli/test_continuous.py does) with three commits: BASE,
SAME (other file contents, the same code) and SLOW (the build does 25 % more work). A CPU-bound
process runs the whole time (one of this machine's two cores), and `vorobench continuous`
runs at its default options BASE..SAME and BASE..SLOW, ``--times`` each, alternately. Prints
every exit status: the same code must exit 0 and the slower revision 1, every time.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PLUGIN = '''
from impls.base import Implementation
from impls.qhull import build as qhull_build

WORK = {work}          # loop iterations per site: the build's CPU time
# {comment}


def _build(sites, stats=None):
    x = 0
    for i in range(WORK * sites.shape[0]):
        x += i
    return qhull_build(sites, stats)


IMPLEMENTATIONS = [Implementation(name="plug", description="a CPU loop, then qhull", complexity="O(n)",
                                  build=_build, exact=False, origin="benchmarks")]
'''


def _git(repo: Path, *args: str) -> str:
    return subprocess.run(["git", "-C", str(repo), *args], capture_output=True, text=True, check=True).stdout.strip()


def _commit(repo: Path, work: int, comment: str) -> str:
    (repo / "plug.py").write_text(PLUGIN.format(work=work, comment=comment))
    _git(repo, "add", "plug.py")
    _git(repo, "-c", "user.name=b", "-c", "user.email=b@b", "commit", "-qm", comment)
    return _git(repo, "rev-parse", "HEAD")


def _spin(stop) -> None:
    """A CPU-bound process: the busy neighbour of a shared machine."""
    x = 0
    while not stop.is_set():
        for i in range(100_000):
            x += i


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--times", type=int, default=5)
    parser.add_argument("--sizes", default="1k,3k")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="continuous-load-") as tmp:
        repo = Path(tmp) / "plugin"
        repo.mkdir()
        _git(repo, "init", "-q")
        # the loop is most of the build (the harness's own share, ~10 %, dilutes the step a little)
        base = _commit(repo, 2000, "base")
        same = _commit(repo, 2000, "the same code, another comment")
        slow = _commit(repo, 2600, "30 % more loop: the build 25 % slower")
        stop = mp.Event()
        hog = mp.Process(target=_spin, args=(stop,), daemon=True)
        hog.start()
        codes: dict[str, list[int]] = {"same": [], "slower": []}
        try:
            for k in range(args.times):
                for label, rev in (("same", same), ("slower", slow)):
                    t0 = time.perf_counter()
                    done = subprocess.run([sys.executable, "-m", "vorobench", "continuous", base, rev, "--repo",
                                           str(repo), "--plugin", "plug", "--impls", "plug", "--sizes", args.sizes,
                                           "--quiet"], cwd=repo, capture_output=True, text=True)
                    codes[label].append(done.returncode)
                    verdicts = [line.strip() for line in done.stdout.splitlines()
                                if "slower" in line or "no regression" in line or "inconclusive" in line][-2:]
                    print(f"{k + 1}/{args.times} {label:7s} exit {done.returncode} ({time.perf_counter() - t0:.0f} s): "
                          + " | ".join(verdicts), flush=True)
        finally:
            stop.set()
            hog.join(timeout=5)
    print(f"same code: exit {codes['same']} (want all 0); 25 % slower: exit {codes['slower']} (want all 1)")


if __name__ == "__main__":
    main()
