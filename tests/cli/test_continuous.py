"""vorobench continuous: two revisions of a repository benchmarked in their own worktrees and
compared; a changed revision exits 1, the same code exits 0, the checkout is left alone.

No test here asserts the outcome of a timing comparison of these live runs (a busy machine
would decide it): the changed revision is caught by a counter, exactly, and the same code is
compared with a threshold no load reaches. The timing rule itself is tested on recorded
timings (tests/harness/test_regress*.py, test_trend.py)."""

from __future__ import annotations

import argparse
import json
import subprocess
from pathlib import Path

import pytest

from vorobench.cli import build_parser, continuous, main

PLUGIN = '''
import time

from impls.base import Implementation
from impls.qhull import build as qhull_build

PAUSE = {pause}


def _build(sites, stats=None):
    time.sleep(PAUSE)
    if stats is not None:
        stats["sleeps"] = round(PAUSE * 100)         # a counter (2 or 4): the change shows exactly
    return qhull_build(sites, stats)


IMPLEMENTATIONS = [Implementation(name="plug", description="qhull after a pause", complexity="n/a",
                                  build=_build, exact=False, origin="tests")]
'''


def _git(repo: Path, *args: str) -> str:
    done = subprocess.run(["git", "-C", str(repo), *args], capture_output=True, text=True, check=True)
    return done.stdout.strip()


def _commit(repo: Path, pause: float, message: str) -> str:
    (repo / "plug.py").write_text(PLUGIN.format(pause=pause))
    _git(repo, "add", "plug.py")
    _git(repo, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", message)
    return _git(repo, "rev-parse", "HEAD")


@pytest.fixture(scope="module")
def plugin_repo(tmp_path_factory) -> tuple[Path, str, str]:
    """A plugin's repository: its first commit pauses 20 ms per build, the second 40 ms."""
    repo = tmp_path_factory.mktemp("plugin-repo")
    _git(repo, "init", "-q")
    fast = _commit(repo, 0.02, "fast")
    slow = _commit(repo, 0.04, "slow")
    return repo, fast, slow


BENCH = ["--plugin", "plug", "--impls", "plug", "--sizes", "20,40", "--repeat", "5", "--min-time", "0",
         "--no-check", "--quiet", "--rounds", "2"]


def test_a_slower_revision_is_flagged_and_both_runs_are_filed(plugin_repo, tmp_path, capsys):
    """...and the revisions ran in interleaved rounds, A, B, A, B, each round a process of its
    own with its share of the repeats; each revision's rounds were merged into one results
    file, repeats numbered on, one run id, the machine's load around each round in the metadata."""
    import pandas as pd

    from vorobench.harness.results import read_metadata

    repo, fast, slow = plugin_repo
    store = tmp_path / "store"
    junit = tmp_path / "junit.xml"
    keep = tmp_path / "kept"
    code = main(["continuous", fast, "HEAD", "--repo", str(repo), *BENCH, "--store", str(store),
                 "--junit", str(junit), "--json", str(tmp_path / "c.json"), "--results-dir", str(keep)])
    captured = capsys.readouterr()
    out = captured.out
    assert code == 1, out
    order = [line.split(", ")[1].split(":")[0] for line in captured.err.splitlines() if line.startswith("round ")]
    assert order == [fast, "HEAD", fast, "HEAD"], captured.err
    merged = sorted(keep.glob("a-*.csv"))
    assert [p.name for p in merged] == [f"a-{fast[:10]}.csv"]           # the rounds' parts are merged away
    df = pd.read_csv(merged[0])
    assert df["run_id"].nunique() == 1 and sorted(set(df["round"])) == [1, 2]
    for _, case in df.groupby(["impl", "dataset", "n", "seed"]):
        assert sorted(case["repeat"]) == list(range(6))                # 3 + 3, numbered on
    [run] = read_metadata(merged[0])["runs"]
    assert run["interleaved"] and [r["round"] for r in run["rounds"]] == [1, 2]
    assert all("load1" in r["before"] and "load1" in r["after"] for r in run["rounds"])
    cases = json.loads((tmp_path / "c.json").read_text())["cases"]
    assert [c["counters"] for c in cases] == [{"sleeps": [2, 4]}] * 2 and all(c["flagged"] for c in cases)
    assert junit.read_text().count("<failure") >= 2          # both cases failed the comparison
    # each revision's run is filed with the plugin's own commit, not the checkout's
    assert main(["history", str(store), "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    assert [r["meta"]["implementations"]["plug"]["commit"] for r in runs] == [fast, slow]
    # the repository's checkout and its list of worktrees are as they were
    assert _git(repo, "rev-parse", "HEAD") == slow and not _git(repo, "status", "--porcelain")
    assert len(_git(repo, "worktree", "list").splitlines()) == 1


def test_the_same_code_twice_passes(plugin_repo, capsys):
    repo, fast, _ = plugin_repo
    # a threshold of 1000 %: no machine load decides this test, only the plumbing and the counters
    # (one round each: the interleaving of rounds is the test above's)
    one_round = BENCH[:BENCH.index("--rounds")] + ["--rounds", "1"]
    assert main(["continuous", fast, fast, "--repo", str(repo), *one_round, "--threshold", "10"]) == 0, \
        capsys.readouterr().out


def test_unknown_revisions_and_folders_are_one_line_errors(plugin_repo, tmp_path, capsys):
    repo, fast, _ = plugin_repo
    assert main(["continuous", fast, "no-such-branch", "--repo", str(repo), *BENCH]) == 2
    assert "'no-such-branch' is not a commit" in capsys.readouterr().err
    assert main(["continuous", "HEAD~1", "HEAD", "--repo", str(tmp_path), *BENCH]) == 2
    assert "not inside a git repository" in capsys.readouterr().err


def test_a_revision_that_cannot_be_benchmarked_exits_2(plugin_repo, capsys):
    repo, fast, _ = plugin_repo
    code = main(["continuous", fast, fast, "--repo", str(repo), "--plugin", "no_such_module", "--impls", "plug",
                 "--sizes", "20", "--quiet"])
    assert code == 2
    assert "failed in round 1 (exit status 2); nothing compared" in capsys.readouterr().err


def test_bench_options_are_passed_on_with_the_callers_paths_made_absolute(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "mine.py").write_text("IMPLEMENTATIONS = []\n")
    args = build_parser().parse_args(["continuous", "A", "B", "--impls", "fortune,qhull", "--sizes", "1k,10k",
                                      "--repeat", "9", "--no-check", "--plugin", "mine.py", "--plugin", "pkg.mod",
                                      "--store", "runs", "--threshold", "0.2"])
    words = continuous.bench_arguments(args)
    # --repeat is shared out over the rounds and --store filed with the merged rounds: continuous's own
    assert words == ["--impls", "fortune,qhull", "--sizes", "1000,10000", "--no-check",
                     "--plugin", str(tmp_path / "mine.py"), "--plugin", "pkg.mod"]
    # every option bench knows parses back to what the caller asked for
    bench = argparse.ArgumentParser()
    from vorobench.cli import bench as bench_cmd

    bench_cmd.add_arguments(bench)
    again = bench.parse_args(words)
    assert again.impls == ["fortune", "qhull"] and again.sizes == [1000, 10000] and again.no_check


def test_round_order_alternates():
    assert continuous_order(3) == [(1, "a"), (1, "b"), (2, "a"), (2, "b"), (3, "a"), (3, "b")]


def continuous_order(rounds):
    from vorobench.harness.continuous import round_order

    return round_order(rounds)


EXECUTABLE = '''\
"""A test program: scipy's Delaunay triangles, and a counter-like marker of its revision."""
import sys
from pathlib import Path

import numpy as np
from scipy.spatial import Delaunay

assert Path("built").read_text() == "{revision}", "setup did not run in this worktree"
lines = sys.stdin.read().split("\\n")
n = int(lines[0])
sites = np.array([[float(v) for v in line.split()] for line in lines[1:1 + n]])
sys.stdout.write("".join(f"{{a}} {{b}} {{c}}\\n" for a, b, c in Delaunay(sites).simplices.tolist()))
'''
MANIFEST = '''\
[implementation]
name = "tri-exe"
command = ["{python}", "prog.py"]
output = "triangles"
exact = false
complexity = "O(n log n)"
setup = ["{python}", "-c", "open('built', 'w').write(open('REVISION').read())"]
'''


def test_an_executable_plugin_repository_sets_up_and_runs_each_revision_in_its_worktree(tmp_path, capsys,
                                                                                      monkeypatch):
    """Each revision's manifest and program run from its own worktree, after its own setup
    (which builds in place: the program refuses to run without that revision's build)."""
    import pandas as pd

    monkeypatch.setenv("VOROBENCH_CACHE_DIR", str(tmp_path / "cache"))
    repo = tmp_path / "exe-repo"
    (repo / "tri").mkdir(parents=True)
    _git(repo, "init", "-q")
    for revision in ("one", "two"):
        (repo / "tri" / "prog.py").write_text(EXECUTABLE.format(revision=revision))
        (repo / "tri" / "REVISION").write_text(revision)
        (repo / "tri" / "impl.toml").write_text(MANIFEST)
        _git(repo, "add", ".")
        _git(repo, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", revision)
    keep = tmp_path / "kept"
    code = main(["continuous", "HEAD~1", "HEAD", "--repo", str(repo), "--plugin", str(repo / "tri" / "impl.toml"),
                 "--impls", "tri-exe", "--sizes", "50", "--repeat", "1", "--min-time", "0", "--rounds", "1",
                 "--quiet", "--results-dir", str(keep), "--threshold", "1000"])
    assert code == 0, capsys.readouterr()
    frames = [pd.read_csv(keep / f"{side}-{_git(repo, 'rev-parse', rev)[:10]}.csv")
              for side, rev in (("a", "HEAD~1"), ("b", "HEAD"))]
    for frame in frames:
        assert set(frame.status) == {"ok"} and set(frame.verdict) <= {"exact", "within_tolerance"}
    assert not (repo / "tri" / "built").exists()          # the repository's own checkout is left alone
