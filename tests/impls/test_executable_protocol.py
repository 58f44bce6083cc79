"""The executable protocol's bytes and manifests: what a program reads, what it may print."""

import struct

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from impls.executable.manifest import InputFormat, ManifestError, OutputKind, read_manifest
from impls.executable.protocol import InvalidOutput, encode_sites, output_limit, parse_output

FINITE = st.floats(allow_nan=False, allow_infinity=False, width=64)


@given(arrays(np.float64, st.tuples(st.integers(0, 20), st.just(3)), elements=FINITE))
def test_text_input_reads_back_bit_for_bit(rows):
    text = encode_sites(rows[:, :2], rows[:, 2], InputFormat.TEXT).decode()
    lines = text.split("\n")
    assert lines[0] == f"{len(rows)} weighted"
    back = np.array([[float(v) for v in line.split()] for line in lines[1:1 + len(rows)]]).reshape(-1, 3)
    assert np.array_equal(back.view(np.uint64), rows.view(np.uint64))       # -0.0 and subnormals included
    assert text.endswith("\n") or len(rows) == 0


def test_text_input_without_weights_is_two_numbers_a_line():
    text = encode_sites(np.array([[0.1, -2.5e17], [1e-300, 3.0]]), None, InputFormat.TEXT).decode()
    assert text == "2\n0.1 -2.5e+17\n1e-300 3.0\n"


def test_binary_input_is_a_count_a_flag_and_little_endian_rows():
    sites = np.array([[1.5, -2.0], [3.25, 4.0]])
    data = encode_sites(sites, np.array([0.5, 0.25]), InputFormat.BINARY)
    n, flag = struct.unpack_from("<QB", data)
    assert (n, flag) == (2, 1) and len(data) == 9 + 2 * 3 * 8
    assert np.frombuffer(data, "<f8", offset=9).tolist() == [1.5, -2.0, 0.5, 3.25, 4.0, 0.25]
    assert encode_sites(sites, None, InputFormat.BINARY)[8] == 0


def test_triangles_and_the_time_line_parse():
    out = parse_output(b"0 1 2\r\ntime 0.25\n2 1 3\n", OutputKind.TRIANGLES, 4)
    assert out.triangles.tolist() == [[0, 1, 2], [2, 1, 3]] and out.library_s == 0.25
    assert parse_output(b"", OutputKind.TRIANGLES, 2).triangles.shape == (0, 3)


def test_blank_lines_tabs_and_a_time_line_anywhere_are_allowed():
    out = parse_output(b"v 0 0\n\ntime 2\nv\t1 1\n  \ne 0 1 0 1\n", OutputKind.VORONOI, 4)
    assert out.vertices.shape == (2, 2) and out.edge_sites.tolist() == [[0, 1]] and out.library_s == 2.0


def test_voronoi_output_parses_vertices_then_edges():
    out = parse_output(b"v 0.5 0.5\nv 1e300 -2\ne 0 1 0 -1\ne 1 2 -1 1\ntime 1e-3\n", OutputKind.VORONOI, 3)
    assert out.vertices.tolist() == [[0.5, 0.5], [1e300, -2.0]]
    assert out.edge_sites.tolist() == [[0, 1], [1, 2]] and out.edge_ends.tolist() == [[0, -1], [-1, 1]]
    assert out.library_s == 1e-3


@pytest.mark.parametrize("data, kind, says", [
    (b"0 1\n", OutputKind.TRIANGLES, "numbers per line|parse"),
    (b"0 1 2\n0 1\n", OutputKind.TRIANGLES, "parse"),
    (b"0 1 7\n", OutputKind.TRIANGLES, "outside 0..3"),
    (b"0 1 x\n", OutputKind.TRIANGLES, "parse"),
    (b"0 1 2\ntime soon\n", OutputKind.TRIANGLES, "not a number"),
    (b"time 1\ntime 2\n", OutputKind.TRIANGLES, "2 time lines"),
    (b"time -1\n", OutputKind.TRIANGLES, "seconds"),
    (b"v 0 0\ne 0 1 0 -1\nv 1 1\n", OutputKind.VORONOI, "do not start with 'e'"),
    (b"w 0 0\n", OutputKind.VORONOI, "do not start with 'v'"),
    (b"v nan 0\n", OutputKind.VORONOI, "not finite"),
    (b"v 0 0\ne 0 9 0 -1\n", OutputKind.VORONOI, "site outside"),
    (b"v 0 0\ne 0 1 0 3\n", OutputKind.VORONOI, "vertex outside"),
    (b"v 0 0\n" * 30, OutputKind.VORONOI, "30 vertex lines, more than the 24"),
    (b"v 0 0\n" + b"e 0 1 0 -1\n" * 40, OutputKind.VORONOI, "40 edge lines, more than the 28"),
    (b"0 1 2\n" * 20, OutputKind.TRIANGLES, "20 triangle lines, more than the 16"),
])
def test_what_the_protocol_does_not_allow_is_said(data, kind, says):
    with pytest.raises(InvalidOutput, match=says):
        parse_output(data, kind, 4)


def test_the_output_limit_leaves_room_for_any_honest_answer_and_no_more():
    n = 1000
    honest = "".join(f"{n - 1} {n - 2} {n - 3}\n" for _ in range(2 * n - 5)) + "time 1.2345678901234567e-05\n"
    assert len(honest) < output_limit(n, OutputKind.TRIANGLES) < 100 * len(honest)
    vertex = f"v {-1.2345678901234567e-300!r} {-1.2345678901234567e-300!r}\n"
    edge = f"e {n - 1} {n - 2} {2 * n - 1} {2 * n - 2}\n"
    assert (2 * n) * len(vertex) + (3 * n) * len(edge) < output_limit(n, OutputKind.VORONOI)


def _manifest(tmp_path, body: str):
    path = tmp_path / "impl.toml"
    path.write_text(body)
    return read_manifest(path)


GOOD = '''[implementation]
name = "mine"
command = ["./mine", "--fast"]
output = "triangles"
exact = false
complexity = "O(n log n)"
'''


def test_a_manifest_reads_with_its_defaults_and_placeholders(tmp_path):
    m = _manifest(tmp_path, GOOD + 'weights = "power"\nrequires = ["sh"]\n')
    assert (m.name, m.output, m.input, m.weighted, m.exact) == ("mine", OutputKind.TRIANGLES, InputFormat.TEXT, True, False)
    assert m.argv(m.command)[0] == str(tmp_path / "mine") and m.argv(m.command)[1] == "--fast"
    assert m.argv(("{cache}/x",), tmp_path / "c") == [str(tmp_path / "c" / "x")]
    assert m.missing() == []


def test_a_manifest_that_needs_what_is_not_here_says_so(tmp_path):
    m = _manifest(tmp_path, GOOD + 'requires = ["no-such-program-xyz", "/no/such/file"]\n')
    assert m.missing() == ["no-such-program-xyz", "/no/such/file"]


def test_each_manifest_folder_has_its_own_cache(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    first, second = (_manifest(tmp_path / d, GOOD) for d in "ab")
    assert first.cache() != second.cache() and first.cache().parent == second.cache().parent


def test_sources_leave_out_what_builds_and_tools_make(tmp_path):
    m = _manifest(tmp_path, GOOD)
    for name in ("mine.c", "node_modules/x/index.js", ".git/HEAD", "build/mine.o", "lib/util.c"):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(name)
    assert sorted(m.sources()) == ["impl.toml", "lib/util.c", "mine.c"]


@pytest.mark.parametrize("change, says", [
    (("exact = false\n", ""), "exact"),
    (('command = ["./mine", "--fast"]\n', 'command = "./mine"\n'), "list of words"),
    (('output = "triangles"', 'output = "mesh"'), "one of"),
    (('name = "mine"', 'name = "my impl"'), "spaces or commas"),
    (("[implementation]", "[impl]"), r"\[implementation\] table"),
    (("complexity", "complexity_typo"), "unknown field"),
    (('output = "triangles"', 'output = "triangles"\nweights = "additive"'), "power"),
    (("exact = false", "exact = "), "not valid TOML"),
])
def test_a_wrong_manifest_is_refused_naming_the_field(tmp_path, change, says):
    with pytest.raises(ManifestError, match=says):
        _manifest(tmp_path, GOOD.replace(*change))


def test_disks_go_as_x_y_r_with_their_own_header_and_flag():
    sites, radii = np.array([[0.1, -2.0], [3.0, 1e-300]]), np.array([0.5, 0.0])
    assert encode_sites(sites, None, InputFormat.TEXT, radii).decode() == "2 apollonius\n0.1 -2.0 0.5\n3.0 1e-300 0.0\n"
    data = encode_sites(sites, None, InputFormat.BINARY, radii)
    assert struct.unpack_from("<QB", data) == (2, 2)
    assert np.frombuffer(data, "<f8", offset=9).tolist() == [0.1, -2.0, 0.5, 3.0, 1e-300, 0.0]


def test_faces_of_an_apollonius_graph_parse_with_infinity_and_neighbours():
    out = parse_output(b"0 1 2 1 1 1\n-1 2 1 0 0 0\ntime 0.5\n", OutputKind.TRIANGLES, 3, disks=True)
    assert out.triangles.tolist() == [[0, 1, 2, 1, 1, 1], [-1, 2, 1, 0, 0, 0]] and out.library_s == 0.5
    with pytest.raises(InvalidOutput, match="6"):
        parse_output(b"0 1 2\n", OutputKind.TRIANGLES, 3, disks=True)
    with pytest.raises(InvalidOutput, match="outside -1"):
        parse_output(b"0 1 -2 0 0 0\n", OutputKind.TRIANGLES, 3, disks=True)
    with pytest.raises(InvalidOutput, match="more than"):
        parse_output(b"0 1 2 0 0 0\n" * 20, OutputKind.TRIANGLES, 3, disks=True)
    assert output_limit(10, OutputKind.TRIANGLES, disks=True) > output_limit(10, OutputKind.TRIANGLES)


@pytest.mark.parametrize("weights, power, disks", [
    ('"apollonius"', False, True), ('["power", "apollonius"]', True, True), ('["power"]', True, False)])
def test_a_manifest_may_take_disks(tmp_path, weights, power, disks):
    m = _manifest(tmp_path, GOOD + f"weights = {weights}\n")
    assert (m.weighted, m.apollonius) == (power, disks)


@pytest.mark.parametrize("weights", ['["power", "power"]', '[]', '["disks"]', "3"])
def test_a_manifest_with_other_weights_is_refused(tmp_path, weights):
    with pytest.raises(ManifestError, match="apollonius"):
        _manifest(tmp_path, GOOD + f"weights = {weights}\n")
