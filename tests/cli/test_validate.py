"""`vorobench validate`: passes on qhull, fails on a broken implementation with a small witness."""

import json

import numpy as np
import pytest

import impls
from impls.base import Implementation
from impls.qhull import build as qhull_build
from vorobench.cli import main
from vorobench.core.diagram import Diagram


def _swapped_edge(sites, stats=None) -> Diagram:
    """qhull's diagram with the two sites of one edge swapped (its two cells trade places)."""
    d = qhull_build(sites, stats)
    if d.n_half_edges == 0:
        return d
    a, b = int(d.site[0]), int(d.site[d.twin[0]])
    site = np.where(d.site == a, b, np.where(d.site == b, a, d.site))
    return Diagram(d.sites, d.vertices, d.origin, d.twin, d.next, site)


def _crash(sites, stats=None):
    raise RuntimeError("deliberate crash")


@pytest.fixture
def broken():
    names = []
    for name, build in (("test_swapped_edge", _swapped_edge), ("test_crashing", _crash)):
        impls.register(Implementation(name, "deliberately broken", "O(n log n)", build, exact=True))
        names.append(name)
    yield names
    for name in names:
        impls.unregister(name)


def test_qhull_passes_on_every_dataset(tmp_path, capsys):
    code = main(["validate", "--impls", "qhull", "--datasets", "all", "--sizes", "10,100,1000",
                 "--out", str(tmp_path), "--no-shrink"])
    out = capsys.readouterr().out
    summary = json.loads((tmp_path / "summary.json").read_text())
    failures = [f"{r['dataset']} n={r['n']}: {r['verdict']}: {r['message']}" for r in summary["results"]
                if not r["passed"]]
    assert code == 0 and summary["passed"], "\n".join(failures) + "\n" + out
    assert "qhull is floating point" in out


def test_several_implementations_and_the_matrix(tmp_path, capsys):
    code = main(["validate", "--impls", "qhull", "--datasets", "uniform,grid,cocircular,collinear",
                 "--sizes", "0,3,50", "--seeds", "0,1", "--out", str(tmp_path)])
    out = capsys.readouterr().out
    assert code == 0
    for name in ("uniform", "grid", "cocircular", "collinear", "certified"):
        assert name in out
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["cases"] == 4 * 3 * 2 and len(summary["results"]) == 24


def test_broken_implementation_fails_with_a_small_witness(tmp_path, capsys, broken):
    swapped, crashing = broken
    out_dir = tmp_path / "report"
    code = main(["validate", "--impls", f"qhull,{swapped},{crashing}", "--datasets", "uniform",
                 "--sizes", "300", "--out", str(out_dir), "--shrink-seconds", "60"])
    out = capsys.readouterr().out
    assert code == 1
    assert "NOT CERTIFIED" in out and "CRASHED" in out
    summary = json.loads((out_dir / "summary.json").read_text())
    assert not summary["passed"] and summary["failures"] == 2
    by_impl = {w["impl"]: w for w in summary["witnesses"]}
    w = by_impl[swapped]
    assert w["verdict"] == "not_certified" and w["shrunk_verdict"] == "not_certified"
    pts = np.load(w["points"])
    assert 3 <= pts.shape[0] <= 20 and w["n_points"] == pts.shape[0]
    assert w["picture"] and open(w["picture"], "rb").read(4) == b"\x89PNG"
    command = open(w["command"]).read().splitlines()[0]
    assert command == f"vorobench validate --impls {swapped} --reference qhull --points {w['points']}"
    # The witness reproduces the failure through the command it names.
    assert main(command.split()[1:] + ["--out", str(tmp_path / "again")]) == 1
    crash = by_impl[crashing]
    assert crash["verdict"] == "crashed" and np.load(crash["points"]).shape[0] == 1
    assert "deliberate crash" in json.dumps(summary["results"])


def test_points_file(tmp_path):
    path = tmp_path / "pts.npy"
    np.save(path, np.random.default_rng(0).random((40, 2)))
    assert main(["validate", "--impls", "qhull", "--points", str(path), "--out", str(tmp_path / "o")]) == 0
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["datasets"] == ["pts.npy"] and summary["results"][0]["n_sites"] == 40


def test_unknown_dataset_is_an_error(tmp_path, capsys):
    assert main(["validate", "--impls", "qhull", "--datasets", "nosuch", "--out", str(tmp_path)]) == 2
    assert "nosuch" in capsys.readouterr().err


def test_a_dataset_can_be_left_out(tmp_path, capsys):
    import datasets_gen

    code = main(["validate", "--impls", "qhull", "--datasets", "all,-near_grid,-cocircular_many", "--sizes", "6",
                 "--no-shrink", "--out", str(tmp_path)])
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert code == 0, summary["notes"]
    expected = [d for d in datasets_gen.available() if d not in ("near_grid", "cocircular_many")]
    assert summary["datasets"] == expected
    assert main(["validate", "--impls", "qhull", "--datasets", "all,-no_such", "--out", str(tmp_path / "x")]) == 2
    assert "unknown dataset(s) no_such" in capsys.readouterr().err
