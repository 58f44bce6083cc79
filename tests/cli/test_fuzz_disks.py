"""`vorobench fuzz --radii`: a campaign of disks passes on the oracle, and a broken construction
of disks is caught, its witness shrunk with its radii kept row for row."""

import json

import numpy as np
import pytest

import impls
from disk_doubles import ordinary_build, points_for_disks
from impls.base import Implementation
from vorobench.cli import main


@pytest.fixture
def wrong_disks():
    name = "test_fuzz_points_for_disks"
    impls.register(Implementation(name, "the centres' diagram for disks", "O(n^2)", ordinary_build,
                                  build_apollonius=points_for_disks))
    yield name
    impls.unregister(name)


def test_a_campaign_of_disks_catches_a_broken_construction(tmp_path, wrong_disks):
    out = tmp_path / "fuzz"
    code = main(["fuzz", "--impls", f"halfplane,{wrong_disks},qhull", "--reference", "halfplane", "--radii", "tangent",
                 "--budget", "6", "--max-n", "12", "--generators", "uniform,grid", "--out", str(out)])
    summary = json.loads((out / "summary.json").read_text())
    assert code == 1 and not summary["passed"] and summary["radii"] == "tangent" and summary["no_disks"] == ["qhull"]
    setup, *cases = [json.loads(line) for line in (out / "cases.jsonl").read_text().splitlines()]
    assert setup["radii"] == "tangent" and all(c.get("radii") == "tangent" for c in cases if c["kind"] == "case")
    witness = summary["witnesses"][0]
    assert witness["impl"] == wrong_disks and witness["shrunk"] and witness["n_points"] < 12
    radii = np.load(witness["points"].replace(".npy", ".radii.npy"))
    assert radii.shape == (witness["n_points"],)


def test_disks_need_a_reference_that_takes_them(tmp_path):
    assert main(["fuzz", "--impls", "qhull", "--reference", "qhull", "--radii", "equal", "--budget", "2",
                 "--out", str(tmp_path)]) == 2
