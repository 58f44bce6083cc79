"""`vorobench validate --radii`: disks judged by their own certificate and comparison; a broken
construction of disks fails with a witness that names its radii and reproduces the failure."""

import json

import numpy as np
import pytest

import datasets_gen
import impls
from disk_doubles import oracle, ordinary_build, points_for_disks
from impls.base import Implementation
from vorobench.cli import main


@pytest.fixture
def disk_impls():
    names = ["test_points_for_disks", "test_disks"]
    impls.register(Implementation(names[0], "the centres' diagram for disks", "O(n^2)", ordinary_build,
                                  build_apollonius=points_for_disks))
    impls.register(Implementation(names[1], "the oracle again", "O(n^2)", ordinary_build,
                                  build_apollonius=oracle))
    yield names
    for name in names:
        impls.unregister(name)


def test_disks_pass_and_fail_where_they_should(tmp_path, capsys, disk_impls):
    wrong, right = disk_impls
    out_dir = tmp_path / "report"
    code = main(["validate", "--impls", f"halfplane,{wrong},{right},qhull", "--reference", "halfplane",
                 "--radii", "random", "--datasets", "uniform,grid", "--sizes", "12", "--out", str(out_dir)])
    out = capsys.readouterr().out
    assert code == 1 and "disks, random radii" in out and "qhull does not take disks" in out
    summary = json.loads((out_dir / "summary.json").read_text())
    assert summary["radii"] == "random" and summary["no_disks"] == ["qhull"]
    by_impl = {}
    for r in summary["results"]:
        assert r["radii"] == "random"
        if r["exact_peer"] is None:                     # against the reference
            by_impl.setdefault(r["impl"], set()).add(r["verdict"])
    assert by_impl[right] == {"exact"} and by_impl["halfplane"] == {"certified"}
    assert by_impl[wrong] == {"not_certified"} and by_impl["qhull"] == {"unsupported"}
    assert summary["failed_impls"] == [wrong]
    witness = summary["witnesses"][0]
    assert witness["n_points"] < 12 and witness["shrunk_verdict"] == "not_certified"       # shrunk, radii kept
    assert np.load(witness["points"].replace(".npy", ".radii.npy")).shape == (witness["n_points"],)
    command = open(witness["command"]).read().splitlines()[0]
    assert "--radii file:" in command and command.endswith(".radii.npy")
    # the witness's command judges the same disks again, and fails the same way
    assert main(command.split()[1:] + ["--out", str(tmp_path / "again")]) == 1


def test_radii_need_a_reference_that_takes_disks_and_no_weights(tmp_path):
    assert main(["validate", "--impls", "qhull", "--reference", "qhull", "--radii", "equal", "--sizes", "5",
                 "--out", str(tmp_path)]) == 2
    assert main(["validate", "--impls", "halfplane", "--reference", "halfplane", "--radii", "equal",
                 "--weights", "equal", "--sizes", "5", "--out", str(tmp_path)]) == 2


def test_equal_radii_on_the_oracle_pass(tmp_path):
    points = tmp_path / "pts.npy"
    np.save(points, datasets_gen.generate("cocircular", 16, seed=1))
    radii = tmp_path / "r.npy"
    np.save(radii, np.full(16, 0.25))
    assert main(["validate", "--impls", "halfplane", "--reference", "halfplane", "--points", str(points),
                 "--radii", f"file:{radii}", "--out", str(tmp_path / "o")]) == 0
