"""The CLI's foundation commands: impls, datasets, build (+ plot and save) on every family."""

import numpy as np
import pytest

import datasets_gen
from vorobench import Diagram
from vorobench.cli import main, parse_sizes


def test_impls_and_datasets_list_their_names(capsys):
    assert main(["impls"]) == 0
    assert "qhull" in capsys.readouterr().out
    assert main(["datasets"]) == 0
    out = capsys.readouterr().out
    for name in ("uniform", "cocircular", "near_grid"):
        assert name in out
    assert "weight families" in out and "radius families" in out
    for name in (*datasets_gen.WEIGHT_FAMILIES, *datasets_gen.RADIUS_FAMILIES):
        assert name in out


@pytest.mark.parametrize("dataset", datasets_gen.available())
def test_build_every_family_plots_and_saves(dataset, tmp_path, capsys):
    png, npz = tmp_path / "d.png", tmp_path / "d.npz"
    assert main(["build", "--impl", "qhull", "--dataset", dataset, "--n", "200",
                 "--plot", str(png), "--save", str(npz)]) == 0
    out = capsys.readouterr().out
    assert "structure valid" in out
    assert png.stat().st_size > 10_000                 # a real picture, not an empty file
    d = Diagram.load(npz).validate()
    assert f"V = {d.n_vertices}  E = {d.n_edges}  H = {d.n_half_edges}" in out


def test_build_from_a_points_file(tmp_path, capsys):
    path = tmp_path / "pts.txt"
    path.write_text("0 0\n1 0\n0 1\n1 1\n")
    assert main(["build", "--points", str(path)]) == 0
    assert "V = 1  E = 4" in capsys.readouterr().out


def test_bad_dataset_and_bad_points_are_clear_errors(tmp_path, capsys):
    assert main(["build", "--dataset", "nope"]) == 2
    assert "unknown dataset" in capsys.readouterr().err
    bad = tmp_path / "bad.npy"
    np.save(bad, np.array([[0.0, np.nan], [1.0, 1.0]]))
    assert main(["build", "--points", str(bad)]) == 2
    assert "error" in capsys.readouterr().err


def test_parse_sizes_accepts_suffixes():
    assert parse_sizes("10,1e3,2k,1M") == [10, 1000, 2000, 1_000_000]


def _help(command: str, capsys) -> str:
    import pytest as _pytest

    with _pytest.raises(SystemExit):
        main([command, "--help"])
    return capsys.readouterr().out


def test_help_texts_speak_to_users(capsys):
    """No internal names, no words broken across lines, a description for every command, and
    a usage line that says what trend needs."""
    report = _help("report", capsys)
    assert "_text" not in report and "_code" not in report and ":func:" not in report
    demo = _help("demo", capsys)
    assert "DEMO_REFERENCES" not in demo and "cocircul\n" not in demo and "cocircular" in demo
    assert "List every implementation" in _help("impls", capsys)
    assert "List the dataset families" in _help("datasets", capsys)
    assert "{-o HTML | --json FILE | both}" in _help("trend", capsys)
