"""datasets_gen.load: formats, round trips, and error messages naming file and line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

import datasets_gen as dg


def write(tmp_path: Path, name: str, text: str) -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def check_points(arr: np.ndarray, expected: list[list[float]]) -> None:
    assert arr.dtype == np.float64 and arr.flags.c_contiguous
    assert arr.shape == (len(expected), 2)
    assert arr.tolist() == expected


@pytest.mark.parametrize("name", ["uniform", "kuzmin", "grid", "cocircular", "huge_offset", "tiny_spacing"])
@pytest.mark.parametrize("suffix", [".npy", ".csv", ".txt", ".xy", ".pts", ".dat"])
def test_round_trip_exact(tmp_path: Path, name: str, suffix: str) -> None:
    pts = dg.generate(name, 64, seed=1)
    p = tmp_path / f"pts{suffix}"
    if suffix == ".npy":
        np.save(p, pts)
    else:
        # repr of a float round-trips exactly
        sep = "," if suffix == ".csv" else " "
        p.write_text("".join(f"{x!r}{sep}{y!r}\n" for x, y in pts.tolist()))
    loaded = dg.load(p)
    assert loaded.dtype == np.float64 and loaded.flags.c_contiguous
    assert loaded.tobytes() == pts.tobytes()
    assert dg.load(str(p)).tobytes() == pts.tobytes()


finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@settings(max_examples=30, deadline=None)
@given(arrays(np.float64, st.tuples(st.integers(0, 20), st.just(2)), elements=finite))
def test_round_trip_property(tmp_path_factory: pytest.TempPathFactory, pts: np.ndarray) -> None:
    d = tmp_path_factory.mktemp("rt")
    (d / "a.csv").write_text("x,y\n" + "".join(f"{x!r},{y!r}\n" for x, y in pts.tolist()))
    (d / "a.txt").write_text("".join(f"{x!r}\t{y!r}\n" for x, y in pts.tolist()))
    np.save(d / "a.npy", pts)
    for name in ("a.csv", "a.txt", "a.npy"):
        got = dg.load(d / name)
        assert got.shape == pts.shape and np.array_equal(got, pts)


def test_csv_header_variants(tmp_path: Path) -> None:
    check_points(dg.load(write(tmp_path, "a.csv", "x,y\n1,2\n3.5,-4e3\n")), [[1, 2], [3.5, -4000]])
    check_points(dg.load(write(tmp_path, "b.csv", "1,2\n3,4\n")), [[1, 2], [3, 4]])
    # Any two-column header is just labels; x/y names select and order columns.
    check_points(dg.load(write(tmp_path, "c.csv", "lon,lat\n1,2\n")), [[1, 2]])
    check_points(dg.load(write(tmp_path, "d.csv", "Y, X\n1,2\n")), [[2, 1]])
    check_points(
        dg.load(write(tmp_path, "e.csv", "id,x,label,y\n7,1.5,foo,2.5\n8,3,bar,4\n")),
        [[1.5, 2.5], [3, 4]],
    )
    check_points(dg.load(write(tmp_path, "f.csv", "\ufeffx,y\r\n1,2\r\n\r\n# note\r\n3,4\r\n")), [[1, 2], [3, 4]])
    check_points(dg.load(write(tmp_path, "g.csv", ' "x" , "y" \n 1 , 2 \n')), [[1, 2]])


def test_whitespace_text_variants(tmp_path: Path) -> None:
    text = "# points\n\n1 2\n  3\t4   # trailing comment\n5e-1 -6\n"
    for suffix in (".txt", ".xy", ".pts", ".anything", ""):
        check_points(dg.load(write(tmp_path, f"p{suffix}", text)), [[1, 2], [3, 4], [0.5, -6]])
    check_points(dg.load(write(tmp_path, "h.txt", "x y\n1 2\n")), [[1, 2]])
    check_points(dg.load(write(tmp_path, "i.txt", "id x y\n0 1 2\n")), [[1, 2]])


@pytest.mark.parametrize("name", ["empty.csv", "empty.txt", "blank.xy"])
def test_empty_files_give_0_by_2(tmp_path: Path, name: str) -> None:
    text = "" if name.startswith("empty") else "\n   \n# only a comment\n"
    check_points(dg.load(write(tmp_path, name, text)), [])


def test_header_only_gives_0_by_2(tmp_path: Path) -> None:
    check_points(dg.load(write(tmp_path, "h.csv", "x,y\n")), [])
    check_points(dg.load(write(tmp_path, "h.txt", "x y\n")), [])


def test_npy_variants(tmp_path: Path) -> None:
    np.save(tmp_path / "int.npy", np.array([[1, 2], [3, 4]], dtype=np.int32))
    check_points(dg.load(tmp_path / "int.npy"), [[1, 2], [3, 4]])
    np.save(tmp_path / "f32.npy", np.array([[0.5, 0.25]], dtype=np.float32))
    check_points(dg.load(tmp_path / "f32.npy"), [[0.5, 0.25]])
    np.save(tmp_path / "fortran.npy", np.asfortranarray(np.arange(6.0).reshape(3, 2)))
    check_points(dg.load(tmp_path / "fortran.npy"), [[0, 1], [2, 3], [4, 5]])
    np.save(tmp_path / "empty.npy", np.zeros((0,)))
    check_points(dg.load(tmp_path / "empty.npy"), [])
    np.save(tmp_path / "empty2.npy", np.zeros((0, 2)))
    check_points(dg.load(tmp_path / "empty2.npy"), [])


@pytest.mark.parametrize(
    "text, line, fragment",
    [
        ("1,2\n3,4,5\n", 2, "expected 2 columns, found 3"),
        ("x,y\n1,2\n\n3\n", 4, "expected 2 columns, found 1"),
        ("1,2\n3,abc\n", 2, "non-numeric value 'abc' in column 2"),
        ("x,y\n1,2\n# c\n1e,2\n", 4, "non-numeric value '1e' in column 1"),
        ("1,2\nnan,3\n", 2, "non-finite value 'nan'"),
        ("1,2\n3,inf\n", 2, "non-finite value 'inf'"),
        ("1,abc\n", 1, "non-numeric value 'abc'"),
        ("a,b,c\n1,2,3\n", 1, "header has 3 columns"),
        ("x,y,x\n1,2,3\n", 1, "more than once"),
        ("id,x,y\n1,2\n", 2, "expected 3 columns, found 2"),
    ],
)
def test_csv_errors_name_file_and_line(tmp_path: Path, text: str, line: int, fragment: str) -> None:
    p = write(tmp_path, "bad.csv", text)
    with pytest.raises(ValueError) as info:
        dg.load(p)
    msg = str(info.value)
    assert f"{p}:{line}:" in msg
    assert fragment in msg


@pytest.mark.parametrize(
    "text, line, fragment",
    [
        ("1 2\n3 4 5\n", 2, "expected 2 columns, found 3"),
        ("# c\n\n1 2\n3\n", 4, "expected 2 columns, found 1"),
        ("1 2\n1,5 3\n", 2, "non-numeric value '1,5'"),
        ("1 2\n3 NaN\n", 2, "non-finite"),
        ("a b c\n", 1, "header has 3 columns"),
    ],
)
def test_text_errors_name_file_and_line(tmp_path: Path, text: str, line: int, fragment: str) -> None:
    p = write(tmp_path, "bad.xy", text)
    with pytest.raises(ValueError) as info:
        dg.load(p)
    assert f"{p}:{line}:" in str(info.value)
    assert fragment in str(info.value)


def test_missing_file_and_directory(tmp_path: Path) -> None:
    missing = tmp_path / "nope.csv"
    with pytest.raises(FileNotFoundError, match="nope.csv"):
        dg.load(missing)
    with pytest.raises(ValueError, match="not a regular file"):
        dg.load(tmp_path)


def test_npy_errors(tmp_path: Path) -> None:
    np.save(tmp_path / "three.npy", np.zeros((4, 3)))
    with pytest.raises(ValueError, match=r"three.npy: expected an array of shape \(m, 2\), got \(4, 3\)"):
        dg.load(tmp_path / "three.npy")
    np.save(tmp_path / "flat.npy", np.zeros(4))
    with pytest.raises(ValueError, match="flat.npy"):
        dg.load(tmp_path / "flat.npy")
    np.save(tmp_path / "obj.npy", np.array([[1, "a"]], dtype=object), allow_pickle=True)
    with pytest.raises(ValueError, match="obj.npy"):
        dg.load(tmp_path / "obj.npy")
    np.save(tmp_path / "cplx.npy", np.zeros((2, 2), dtype=complex))
    with pytest.raises(ValueError, match="cplx.npy: expected a real numeric array"):
        dg.load(tmp_path / "cplx.npy")
    np.save(tmp_path / "nan.npy", np.array([[0.0, 1.0], [np.nan, 2.0]]))
    with pytest.raises(ValueError, match="nan.npy: non-finite value in row 1"):
        dg.load(tmp_path / "nan.npy")
    (tmp_path / "junk.npy").write_bytes(b"definitely not numpy")
    with pytest.raises(ValueError, match="junk.npy: cannot read .npy file"):
        dg.load(tmp_path / "junk.npy")


def test_non_utf8_text(tmp_path: Path) -> None:
    p = tmp_path / "latin.txt"
    p.write_bytes(b"1 2\n\xff\xfe 3\n")
    with pytest.raises(ValueError, match="latin.txt: not UTF-8"):
        dg.load(p)


def test_file_dataset_names(tmp_path: Path) -> None:
    p = write(tmp_path, "pts.csv", "x,y\n1,2\n3,4\n5,6\n")
    name = f"file:{p}"
    check_points(dg.generate(name, 10), [[1, 2], [3, 4], [5, 6]])
    check_points(dg.generate(name, 2, seed=9), [[1, 2], [3, 4]])
    assert dg.actual_n(name, 10) == 3 and dg.actual_n(name, 2) == 2
    assert dg.describe(name) == f"points loaded from {p}"
    with pytest.raises(FileNotFoundError):
        dg.generate(f"file:{tmp_path / 'missing.txt'}", 3)
    with pytest.raises(ValueError, match="empty file path"):
        dg.generate("file:", 3)


# ------------------------------------------------------------- integers float64 cannot hold exactly

BIG = 2**53 + 1        # the first integer float64 cannot hold: it would be read as 2**53


def test_int64_npy_beyond_2_53_is_refused_not_rounded(tmp_path: Path) -> None:
    # Five distinct sites; read as float64 the last two would be one.
    sites = np.array([[0, 0], [1, 1], [2, 2], [2**53, 5], [BIG, 5]], dtype=np.int64)
    np.save(tmp_path / "big.npy", sites)
    with pytest.raises(ValueError, match=rf"big.npy: integer {BIG} in row 4, column 1 has no exact float64 value "
                                         rf"\(it would be read as 9007199254740992.0\)"):
        dg.load(tmp_path / "big.npy")


@pytest.mark.parametrize("dtype, value", [(np.int64, 2**63 - 1), (np.int64, -(2**53) - 1), (np.uint64, 2**64 - 1),
                                          (np.uint64, BIG)])
def test_every_inexact_64_bit_integer_is_refused(tmp_path: Path, dtype, value: int) -> None:
    np.save(tmp_path / "p.npy", np.array([[1, 2], [3, value]], dtype=dtype))
    with pytest.raises(ValueError, match=rf"p.npy: integer {value} in row 1, column 2 has no exact float64 value"):
        dg.load(tmp_path / "p.npy")


def test_64_bit_integers_that_float64_holds_load_exactly(tmp_path: Path) -> None:
    exact = [[-(2**63), 2**62], [2**53, -(2**53)], [3 * 2**60, 7]]
    np.save(tmp_path / "i.npy", np.array(exact, dtype=np.int64))
    check_points(dg.load(tmp_path / "i.npy"), [[float(v) for v in row] for row in exact])
    np.save(tmp_path / "u.npy", np.array([[2**63, 2**64 - 2**11]], dtype=np.uint64))
    check_points(dg.load(tmp_path / "u.npy"), [[2.0**63, 2.0**64 - 2.0**11]])


@pytest.mark.parametrize("name, text, line, literal", [("big.csv", f"x,y\n1,2\n{BIG},5\n", 3, f"{BIG}"),
                                                       ("big.txt", f"1 2\n# c\n+{BIG} 5\n", 3, f"+{BIG}")])
def test_integer_text_beyond_2_53_is_refused_naming_file_line_and_value(tmp_path: Path, name: str, text: str,
                                                                        line: int, literal: str) -> None:
    p = write(tmp_path, name, text)
    with pytest.raises(ValueError) as info:
        dg.load(p)
    assert str(info.value) == (f"{p}:{line}: integer {literal} has no exact float64 value "
                               f"(it would be read as 9007199254740992.0) in column 1")


def test_text_numbers_float64_holds_or_written_as_decimals_load(tmp_path: Path) -> None:
    # A decimal is read as the nearest float64, as always; only integer text has an exact value to lose.
    check_points(dg.load(write(tmp_path, "ok.csv", f"{2**60},-{2**53}\n9007199254740993.0,1_000\n")),
                 [[2.0**60, -(2.0**53)], [2.0**53, 1000.0]])


# ---------------------------------------------------------------------------- files out of bounds

def test_npy_header_announcing_more_than_the_file_holds_is_refused_unallocated(tmp_path: Path) -> None:
    p = tmp_path / "liar.npy"
    with p.open("wb") as f:
        np.lib.format.write_array_header_1_0(f, {"descr": "<f8", "fortran_order": False, "shape": (10**15, 2)})
        f.write(b"\0" * 32)
    with pytest.raises(ValueError, match=r"liar.npy: cannot read .npy file: its header announces shape"):
        dg.load(p)


def test_a_file_larger_than_the_limit_is_refused(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from datasets_gen import loaders

    monkeypatch.setattr(loaders, "MAX_FILE_BYTES", 64)
    p = write(tmp_path, "long.csv", "1,2\n" * 100)
    with pytest.raises(ValueError, match=r"long.csv: 400 bytes, more than the 64 read from one file"):
        dg.load(p)
    np.save(tmp_path / "long.npy", np.zeros((100, 2)))
    with pytest.raises(ValueError, match=r"long.npy: \d+ bytes, more than the 64"):
        dg.load(tmp_path / "long.npy")
