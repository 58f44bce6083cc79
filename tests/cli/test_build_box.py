"""`vorobench build --plot FILE --box XMIN,YMIN,XMAX,YMAX`: the picture shows that box; a bad box
is one line on standard error and exit status 2."""

import pytest

import vorobench.judge.plotting
from vorobench.cli import main


@pytest.fixture
def boxes_drawn(monkeypatch):
    """The box each save_plot call got (the picture is still written)."""
    seen = []
    real = vorobench.judge.plotting.save_plot

    def spy(d, path, title="", box=None):
        seen.append(box)
        return real(d, path, title, box=box)

    monkeypatch.setattr(vorobench.judge.plotting, "save_plot", spy)
    return seen


def test_the_box_goes_to_the_picture(tmp_path, boxes_drawn, capsys):
    png = tmp_path / "b.png"
    assert main(["build", "--impl", "fortune", "--n", "200", "--plot", str(png), "--box=-0.5,0.25,0.75,1e0"]) == 0
    assert boxes_drawn == [(-0.5, 0.25, 0.75, 1.0)]
    assert png.stat().st_size > 10_000
    assert f"wrote {png}" in capsys.readouterr().out


def test_without_a_box_the_picture_frames_the_sites(tmp_path, boxes_drawn):
    assert main(["build", "--impl", "fortune", "--n", "50", "--plot", str(tmp_path / "s.png")]) == 0
    assert boxes_drawn == [None]                     # save_plot's default: the site box


@pytest.mark.parametrize("text, problem", [
    ("0,0,1", "four numbers"),
    ("0,0,1,1,1", "four numbers"),
    ("0,zero,1,1", "not a number: 'zero'"),
    ("0,0,nan,1", "not a finite number"),
    ("1,0,1,1", "xmin < xmax"),
    ("0,2,1,1", "ymin < ymax"),
])
def test_a_bad_box_is_one_line_and_status_2(text, problem, tmp_path, capsys):
    with pytest.raises(SystemExit) as stop:
        main(["build", "--plot", str(tmp_path / "x.png"), "--box", text])
    assert stop.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--box" in err and problem in err
    assert not (tmp_path / "x.png").exists()


def test_a_box_without_a_picture_is_refused(capsys):
    assert main(["build", "--n", "10", "--box", "0,0,1,1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--plot" in err


def test_a_picture_format_that_cannot_be_written_is_refused_before_building(tmp_path, capsys):
    assert main(["build", "--impl", "fortune", "--n", "10", "--plot", str(tmp_path / "out.xyz")]) == 2
    captured = capsys.readouterr()
    assert "cannot write .xyz" in captured.err and ".png" in captured.err
    assert "V = " not in captured.out            # nothing was built
