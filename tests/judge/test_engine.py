"""check_case / agree_exactly: verdicts, crashes, blame, and the rules for exact vs. float."""

import json

import numpy as np
import pytest

import datasets_gen
import impls
from impls.base import Implementation
from impls.qhull import build as qhull_build
from vorobench.core.builder import assemble
from vorobench.core.diagram import Diagram
from vorobench.judge.engine import BuildResult, agree_exactly, check_case

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def _register(name, build, exact=True, supports=None):
    impl = Implementation(name, "test implementation", "O(n log n)", build, exact=exact, supports=supports)
    impls.register(impl)
    return name


@pytest.fixture
def registered():
    names = []

    def add(*args, **kwargs):
        names.append(_register(*args, **kwargs))
        return names[-1]

    yield add
    for name in names:
        impls.unregister(name)


def _crash(sites, stats=None):
    raise ZeroDivisionError("boom")


def _swapped(sites, stats=None):
    """qhull's diagram with the cells of sites 0 and 1 swapped."""
    d = qhull_build(sites, stats)
    site = np.where(d.site == 0, 1, np.where(d.site == 1, 0, d.site))
    return Diagram(d.sites, d.vertices, d.origin, d.twin, d.next, site)


def test_qhull_against_itself_and_a_copy():
    pts = datasets_gen.generate("uniform", 100, seed=2)
    v = check_case("qhull", pts)
    assert v.passed and v.verdict == "certified" and v.certified
    json.dumps(v.to_dict())


def test_an_exact_copy_of_the_reference_agrees_exactly(registered):
    name = registered("test_copy", qhull_build, exact=True)
    v = check_case(name, datasets_gen.generate("grid", 100))
    assert v.passed and v.verdict == "exact", v.message


def test_crash_is_recorded_not_raised(registered):
    name = registered("test_crash", _crash)
    v = check_case(name, datasets_gen.generate("uniform", 20))
    assert not v.passed and v.verdict == "crashed" and v.blame == "impl"
    assert "ZeroDivisionError: boom" in v.message


def test_unsupported_is_a_pass_with_the_reason(registered):
    name = registered("test_picky", qhull_build, supports=lambda s: "too many sites" if len(s) > 5 else None)
    v = check_case(name, datasets_gen.generate("uniform", 20))
    assert v.passed and v.verdict == "unsupported" and "too many sites" in v.message


def test_a_wrong_implementation_is_not_certified(registered):
    name = registered("test_swapped", _swapped)
    v = check_case(name, datasets_gen.generate("uniform", 50, seed=1))
    assert not v.passed and v.verdict == "not_certified" and v.blame == "impl"
    assert "probes" in v.message
    assert v.reference_certified


def test_a_wrong_reference_is_blamed_on_the_reference(registered):
    """The reference is certified too: with a broken reference, a correct implementation passes
    and the difference is reported as the reference's failure."""
    ref = registered("test_bad_reference", _swapped)
    pts = datasets_gen.generate("uniform", 50, seed=1)
    v = check_case("qhull", pts, reference=ref)
    assert v.verdict == "differs" and v.blame == "reference" and v.passed
    assert v.certified and v.reference_certified is False
    assert "the reference is wrong" in v.message
    own = check_case(ref, pts, reference=ref)
    assert not own.passed and own.verdict == "not_certified"


def test_exact_implementations_must_agree_exactly():
    """A merged vertex and a split with a 1e-13 edge are equal within tolerance only: two exact
    implementations giving them disagree; a float one against an exact one passes."""
    sites = SQUARE.copy()
    sites[3, 1] += 1e-13
    merged = assemble(sites, [[0.5, 0.5]], [[0, 1], [1, 2], [2, 3], [3, 0]], [[-1, 0]] * 4)
    split = assemble(sites, [[0.5, 0.5], [0.5, 0.5 + 5e-14]], [[0, 1], [1, 2], [2, 3], [3, 0], [0, 2]],
                     [[-1, 0], [-1, 0], [-1, 1], [-1, 1], [0, 1]])
    from vorobench.judge.certificate import certify

    a = BuildResult("exact_a", True, merged, certify(merged))
    b = BuildResult("exact_b", True, split, certify(split))
    v = agree_exactly(b, a)
    assert not v.passed and v.verdict == "differs" and "must agree exactly" in v.message
    assert agree_exactly(b, b).passed


def test_a_plugin_crash_points_at_the_plugins_own_line(tmp_path):
    """A plugin that hands vorobench's builder a broken edge list fails inside vorobench's code;
    the message names the plugin's line first, and where it was raised after it."""
    from vorobench.cli import main as cli_main

    plugin = tmp_path / "bad_assembly.py"
    plugin.write_text(
        "import numpy as np\n"
        "from impls.base import Implementation\n"
        "from vorobench.core.builder import assemble\n"
        "\n"
        "def build(points, stats):\n"
        "    return assemble(points, np.zeros((1, 2)), np.array([[0, 10**6]]), np.array([[0, -1]]))  # line 6\n"
        "\n"
        "IMPLEMENTATIONS = [Implementation('bad_assembly', 'a broken edge list', 'O(n)', build, exact=True)]\n")
    import contextlib
    import io

    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        code = cli_main(["build", "--impl", "bad_assembly", "--plugin", str(plugin), "--n", "10"])
    assert code == 1
    text = err.getvalue()
    assert f"at {plugin}:6 (raised in " in text, text
    assert "vorobench" in text.split("(raised in ", 1)[1]
