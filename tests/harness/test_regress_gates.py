"""`vorobench compare` cannot be passed by leaving things out: lost cases fail, files that are not
results (empty, header only, garbage) are errors, and nonsense numbers are refused in one line.

Fault doubles: a NEW results file with cases deleted, one with no case of BASE at all, and
damaged files on either side.
"""

from __future__ import annotations

import pytest

from vorobench.cli import main
from vorobench.harness import regress
from vorobench.harness.results import ResultsFile


def _write(path, impls=("a", "b"), sizes=(100, 200, 300), seeds=(0,)) -> str:
    rows = [{"run_id": "r1", "impl": impl, "dataset": "uniform", "n": n, "seed": seed, "repeat": rep,
             "status": "ok", "verdict": "exact", "time_s": 1.0 + 0.01 * rep}
            for impl in impls for n in sizes for seed in seeds for rep in range(3)]
    ResultsFile(path).append(rows)
    return str(path)


@pytest.fixture()
def base(tmp_path):
    return _write(tmp_path / "base.csv")


def test_new_that_lost_cases_fails_and_names_them(base, tmp_path, capsys):
    new = _write(tmp_path / "new.csv", impls=("a",))            # b's three cases are gone
    assert main(["compare", base, new]) == 1
    out = capsys.readouterr().out
    assert "NEW lacks 3 case(s) that BASE has" in out
    for n in (100, 200, 300):
        assert f"b uniform n={n} seed=0" in out
    missing = [c for c in regress.compare_files(base, new) if c.new_status is None]
    assert len(missing) == 3 and all(c.flagged for c in missing)


def test_many_lost_cases_are_counted_and_a_few_listed(tmp_path, capsys):
    base = _write(tmp_path / "base.csv", seeds=range(4))
    new = _write(tmp_path / "new.csv", impls=("a",), seeds=range(4))   # 12 cases of b lost
    assert main(["compare", base, new]) == 1
    out = capsys.readouterr().out
    assert "NEW lacks 12 case(s) that BASE has" in out and "and 7 more" in out
    assert out.count(" seed=") == 5                        # the table says "s=", the list "seed="


def test_cases_only_in_new_do_not_fail(base, tmp_path, capsys):
    new = _write(tmp_path / "new.csv", impls=("a", "b", "c"))
    assert main(["compare", base, new]) == 0
    assert "no regression in 6 compared case(s)" in capsys.readouterr().out


def test_new_with_no_case_in_common_does_not_pass(base, tmp_path, capsys):
    new = _write(tmp_path / "new.csv", impls=("other",))
    assert main(["compare", base, new]) == 1
    out = capsys.readouterr().out
    assert "no case in common" in out and "NEW lacks 6 case(s)" in out


DAMAGED = {
    "empty": (b"", "is empty"),
    "header only": (b"run_id,impl,dataset,n,seed,repeat,status,time_s\r\n", "no result rows"),
    "binary garbage": (bytes(range(256)) * 4, "results"),
    "unrelated text": (b"hello world\nfoo bar\n", "not a results table"),
    "rows without a key": (b"impl,dataset,n,seed,status\r\na,uniform,,0,ok\r\n", "lack a case key"),
}


@pytest.mark.parametrize("side", ["base", "new"])
@pytest.mark.parametrize("kind", list(DAMAGED))
def test_a_file_that_is_no_results_is_one_line_and_exit_2(kind, side, base, tmp_path, capsys):
    content, problem = DAMAGED[kind]
    bad = tmp_path / "bad.csv"
    bad.write_bytes(content)
    args = [str(bad), base] if side == "base" else [base, str(bad)]
    assert main(["compare", *args]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and str(bad) in lines[0] and problem in lines[0], captured.err
    assert "Traceback" not in captured.err and "no regression" not in captured.out


def test_a_directory_is_one_line_and_exit_2(base, tmp_path, capsys):
    assert main(["compare", base, str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(tmp_path) in err[0]


@pytest.mark.parametrize("option, value", [
    ("--threshold", "-1"), ("--threshold", "0"), ("--threshold", "nan"), ("--threshold", "inf"),
    ("--alpha", "0"), ("--alpha", "1"), ("--alpha", "2"), ("--alpha", "nan"), ("--alpha", "-0.5"),
    ("--seed", "-1"), ("--seed", "x"),
])
def test_nonsense_numbers_are_one_line_and_exit_2(option, value, base, capsys):
    with pytest.raises(SystemExit) as stop:
        main(["compare", base, base, option, value])
    assert stop.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and option in err[0] and value in err[0]


def test_only_changes_leaves_unchanged_cases_out_of_the_markdown_too(base, tmp_path):
    new = _write(tmp_path / "new.csv", impls=("a", "b", "c"))     # c's cases are new: notable
    md_all, md_changes = tmp_path / "all.md", tmp_path / "changes.md"
    assert main(["compare", base, new, "--markdown", str(md_all)]) == 0
    assert main(["compare", base, new, "--markdown", str(md_changes), "--only-changes"]) == 0
    every, changes = md_all.read_text(), md_changes.read_text()
    assert every.count("| a uniform") == 3 and every.count("| c uniform") == 3
    assert changes.count("| a uniform") == 0 and changes.count("| b uniform") == 0
    assert changes.count("| c uniform") == 3 and "6 unchanged case(s) left out" in changes


def test_relative_to_a_reference_cancels_a_machine_that_got_slower(tmp_path, capsys):
    """NEW ran on a machine 1.5x slower for everything: in seconds a is 1.5x slower; relative to
    b (timed in both runs) nothing changed, and a 1.4x change of a alone still shows."""
    def run(path, scale_a, scale_b):
        rows = [{"run_id": path.stem, "impl": impl, "dataset": "uniform", "n": n, "seed": 0, "repeat": rep,
                 "status": "ok", "verdict": "exact", "time_s": scale * base * (1 + 0.002 * rep)}
                for impl, scale, base in (("a", scale_a, 1.0), ("b", scale_b, 0.5)) for n in (100, 200)
                for rep in range(5)]
        ResultsFile(path).append(rows)
        return str(path)

    base = run(tmp_path / "base.csv", 1.0, 1.0)
    busy = run(tmp_path / "busy.csv", 1.5, 1.5)
    worse = run(tmp_path / "worse.csv", 1.5 * 1.4, 1.5)
    assert main(["compare", base, busy]) == 1                               # seconds: 1.5x slower
    assert main(["compare", base, busy, "--relative-to", "b"]) == 0         # relative: the same
    assert "times are relative to b" in capsys.readouterr().out
    assert main(["compare", base, worse, "--relative-to", "b"]) == 1        # a's own change shows
    assert main(["compare", base, busy, "--relative-to", "nobody"]) == 2
    assert "has no timed case of nobody" in capsys.readouterr().err


def test_cpu_time_is_compared_when_both_runs_recorded_it(tmp_path, capsys):
    """A busy neighbour stretched NEW's wall times by 1.5x, not the builds' own CPU time: by
    default (auto) compare judges the CPU time and passes; --measure wall sees the stretch."""
    def run(path, wall_scale):
        rows = [{"run_id": path.stem, "impl": "a", "dataset": "uniform", "n": n, "seed": 0, "repeat": rep,
                 "status": "ok", "verdict": "exact", "time_s": wall_scale * (1 + 0.002 * rep),
                 "cpu_s": 0.9 * (1 + 0.002 * rep)} for n in (100, 200) for rep in range(5)]
        ResultsFile(path).append(rows)
        return str(path)

    base, busy = run(tmp_path / "base.csv", 1.0), run(tmp_path / "busy.csv", 1.5)
    assert main(["compare", base, busy]) == 0
    assert "CPU time of each build" in capsys.readouterr().out
    assert main(["compare", base, busy, "--measure", "wall"]) == 1
    assert "build times compared: wall time" in capsys.readouterr().out
    older = _write(tmp_path / "older.csv")                     # no cpu_s: wall time, and --measure cpu refused
    assert main(["compare", older, older, "--measure", "cpu"]) == 2
    assert "no CPU time" in capsys.readouterr().err


def test_interleaved_rounds_are_the_samples_not_the_repeats(tmp_path):
    """Three of NEW's four rounds landed on a busy core (1.45x), each with five tight repeats:
    counted repeat by repeat that is a clear slowdown; counted by round (continuous's merged files
    carry ``round``), four rounds cannot rule out that it was luck: inconclusive, not a failure."""
    import pandas as pd

    def frame(levels, run_id):
        return pd.DataFrame([{"run_id": run_id, "impl": "a", "dataset": "uniform", "n": 100, "seed": 0,
                              "repeat": 5 * r + k, "round": r + 1, "status": "ok", "verdict": "exact",
                              "time_s": level * (1 + 0.001 * k)} for r, level in enumerate(levels) for k in range(5)])

    base, new = frame([1.0, 1.0, 1.0, 1.0], "b"), frame([1.45, 1.45, 1.45, 1.0], "n")
    [by_round] = regress.compare_frames(base, new)
    assert by_round.change == "inconclusive" and by_round.base_repeats == 4, by_round
    [by_repeat] = regress.compare_frames(base.drop(columns="round"), new.drop(columns="round"))
    assert by_repeat.change == "slower"
