"""The weighted sweep's specification (impls/fortune/power_reference.py) and its compiled form
(``fortune``'s ``build_weighted``): the exact number arithmetic, the contact geometry checked
against first principles, and the diagrams of all three ways of finding contacts checked
exactly against the half-plane oracle and the regular triangulation on every dataset and
weight family, on degenerate lattices, and where the contact rules matter (a cell away from
its site, cells of no area, ties along a line)."""

from decimal import Decimal, getcontext
from enum import Enum
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import datasets_gen
import impls
from impls import fortune
from impls.fortune.power_reference import Event, ProbingSweep, Sweep, Time, build_weighted, surd_sign
from vorobench.core.prepare import prepare_weighted
from vorobench.judge.comparison import Verdict, compare

getcontext().prec = 80


def _decimal(a: Fraction) -> Decimal:
    return Decimal(a.numerator) / Decimal(a.denominator)


def _case(dataset: str, family: str, n: int):
    points = datasets_gen.generate(dataset, n, seed=0)
    sites, weights, _ = prepare_weighted(points, datasets_gen.weights(family, points, seed=0))
    return sites, weights


class Way(Enum):
    """The ways of finding contacts: the specification trying every pending site against the
    whole beach line, the specification's probes, and the compiled sweep (probes, filtered)."""

    CANDIDATES = "candidates"
    PROBES = "probes"
    COMPILED = "compiled"


WAYS = pytest.mark.parametrize("way", list(Way), ids=[w.value for w in Way])


def _build(sites, weights, way: Way):
    if way is Way.COMPILED:
        return fortune.build_weighted(sites, weights)
    return build_weighted(sites, weights, probing=way is Way.PROBES)


def _assert_exact(sites, weights, oracle: str = "halfplane", way: Way = Way.CANDIDATES) -> None:
    got = _build(sites, weights, way)
    want = impls.get(oracle).build_weighted(sites, weights)
    result = compare(got, want, labels=("sweep", oracle))
    assert result.verdict == Verdict.EXACT, result.differences[:4]


# ------------------------------------------------------------------------------------------
# Number arithmetic: signs of a + b sqrt(h) and the order of times a + sqrt(b)
# ------------------------------------------------------------------------------------------

fractions = st.fractions(min_value=-50, max_value=50, max_denominator=12)
thirds = st.integers(0, 12).map(lambda k: Fraction(k, 3))


@settings(max_examples=150, deadline=None)
@given(fractions, fractions, st.fractions(min_value=0, max_value=50, max_denominator=12))
def test_surd_sign_is_the_sign_of_the_number(a, b, h):
    value = _decimal(a) + _decimal(b) * _decimal(h).sqrt()
    expected = (value > 0) - (value < 0)
    if abs(value) < Decimal(10) ** -60:           # zero: only when a^2 = b^2 h exactly
        expected = 0 if a * a == b * b * h and (a == 0 or (a > 0) != (b > 0)) else expected
    assert surd_sign(a, b, h) == expected


@settings(max_examples=150, deadline=None)
@given(fractions, thirds, fractions, thirds)
def test_times_with_square_radicands_tie_exactly(a1, root1, a2, root2):
    # radicands that are squares of rationals: the times are rational, so their exact order
    # (ties included) is known without square roots
    r1, r2 = a1 + root1, a2 + root2
    assert Time(a1, root1 * root1).compare(Time(a2, root2 * root2)) == (r1 > r2) - (r1 < r2)


def test_times_order_by_value_not_by_parts():
    # 1 + sqrt(1) = 2 + sqrt(0): equal, although neither part is
    assert Time(Fraction(1), Fraction(1)) == Time(Fraction(2))
    assert Time(Fraction(0), Fraction(2)) < Time(Fraction(1), Fraction(1) / 4 + 0)   # 1.414 < 1.5
    assert not Time(Fraction(3, 2)) < Time(Fraction(0), Fraction(9, 4))              # 1.5 = 1.5


# ------------------------------------------------------------------------------------------
# Contact geometry against first principles
# ------------------------------------------------------------------------------------------

def _wavefront_time(sweep: Sweep, i: int, x: float, y: float) -> float:
    """T_i(x) = y + sqrt(|x - p_i|^2 + s_i), in floats (for checking, not deciding)."""
    s = float(sweep.s[i])
    return y + ((x - float(sweep.x[i])) ** 2 + (y - float(sweep.y[i])) ** 2 + s) ** 0.5


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(st.integers(-9, 9), st.integers(-9, 9), st.integers(0, 30)), min_size=2, max_size=2,
                unique_by=lambda t: t[:2]))
def test_arc_contact_is_the_lowest_time_on_the_bisector(two):
    (xi, yi, wi), (xk, yk, wk) = two
    sites = np.array([[xi, yi], [xk, yk]], dtype=np.float64)
    sweep = Sweep(sites, np.array([wi, wk], dtype=np.float64))
    found = sweep.arc_contact(0, 1)
    if not yk < yi:
        assert found is None         # only a lower (wider) wavefront can be touched inside
        return
    t, cx, cy, h = found
    root = float(h) ** 0.5
    c = (float(cx[0]) + float(cx[1]) * root, float(cy[0]) + float(cy[1]) * root)
    # c is on the bisector (equal power), at time t for both sites
    assert _wavefront_time(sweep, 0, *c) == pytest.approx(float(t), rel=1e-9, abs=1e-9)
    assert _wavefront_time(sweep, 1, *c) == pytest.approx(float(t), rel=1e-9, abs=1e-9)
    # and every other point of the bisector is reached later
    direction = np.array([-(yk - yi), xk - xi], dtype=np.float64)
    direction /= np.hypot(*direction)
    for step in (-3.0, -0.5, -0.01, 0.01, 0.5, 3.0):
        p = (c[0] + step * direction[0], c[1] + step * direction[1])
        assert _wavefront_time(sweep, 1, *p) > float(t) - 1e-9


def test_one_constant_added_to_every_weight_gives_the_same_diagram():
    sites, weights = _case("uniform", "radii", 10)
    a = build_weighted(sites, weights)
    b = build_weighted(sites, weights + 7.0)
    assert compare(a, b.with_weights(weights)).verdict == Verdict.EXACT


# ------------------------------------------------------------------------------------------
# Diagrams, exactly against the oracles
# ------------------------------------------------------------------------------------------

@WAYS
@pytest.mark.parametrize("family", list(datasets_gen.WEIGHT_FAMILIES))
@pytest.mark.parametrize("dataset", datasets_gen.available())
def test_exact_against_the_halfplane_oracle(dataset, family, way):
    for n in (2, 3, 10):
        _assert_exact(*_case(dataset, family, n), way=way)


@WAYS
@pytest.mark.parametrize("dataset, family", [("uniform", "radii"), ("grid", "integer"), ("cocircular", "hidden"),
                                             ("near_grid", "integer")])
def test_exact_against_the_regular_triangulation_at_40(dataset, family, way):
    _assert_exact(*_case(dataset, family, 40), oracle="incremental", way=way)


lattice_sites = st.lists(st.tuples(st.integers(0, 4), st.integers(0, 4), st.integers(0, 2)),
                         min_size=2, max_size=9, unique_by=lambda t: t[:2])


@settings(max_examples=40, deadline=None)
@given(lattice_sites, st.sampled_from(list(Way)))
def test_exact_on_integer_lattices_with_integer_weights(rows, way):
    # weights differing by squared lattice distances: sites on each other's bisectors, lifted
    # points coplanar, cells that shrink to a point or a segment
    sites = np.array([r[:2] for r in rows], dtype=np.float64)
    weights = np.array([r[2] for r in rows], dtype=np.float64)
    assume(np.linalg.matrix_rank(sites - sites[0]) == 2)   # collinear sets go to collinear_diagram everywhere
    _assert_exact(sites, weights, way=way)


@pytest.mark.parametrize("sweep_class", [Sweep, ProbingSweep])
def test_a_cell_away_from_its_site_is_entered_where_the_cell_is(sweep_class):
    # Site 1 at (0, 1), weight 0, next to site 0 at (-1, 0.99), weight 101: their bisector is
    # near x = 50, so site 1's cell (between x = 50 and site 2's bisector near x = 60) is
    # nowhere above or below the site. It enters the beach line there, at the vertex where its
    # cell is lowest in time, between the arcs of sites 0 and 3.
    sites = np.array([[-1.0, 0.99], [0.0, 1.0], [120.0, 0.5], [30.0, -40.0]])
    weights = np.array([101.0, 0.0, 0.0, 0.0])
    sweep = sweep_class(sites, weights)
    sweep.log = []
    sweep.run()
    contacts = [(kind, sites_, here) for kind, _, sites_, here in sweep.log if kind != Event.CIRCLE and sites_[-1] == 1]
    assert len(contacts) == 1
    kind, between, here = contacts[0]
    assert kind == Event.CONTACT_VERTEX and sorted(between[:2]) == [0, 3]
    assert 49 < float(here[0]) < 51
    _assert_exact(sites, weights, way=Way.PROBES if sweep_class is ProbingSweep else Way.CANDIDATES)
    _assert_exact(sites, weights, way=Way.COMPILED)
    assert 1 not in build_weighted(sites, weights).hidden


@WAYS
def test_a_cell_that_is_one_point_is_hidden(way):
    # (1, 1) with weight 0 among four weight-1 sites at distance 1: all five have power 0 at
    # (1, 1), and at any other point one of the four has less than the centre
    sites = np.array([[1.0, 0.0], [0.0, 1.0], [2.0, 1.0], [1.0, 2.0], [1.0, 1.0]])
    weights = np.array([1.0, 1.0, 1.0, 1.0, 0.0])
    d = _build(sites, weights, way)
    assert list(d.hidden) == [4]
    _assert_exact(sites, weights, way=way)


@WAYS
def test_a_cell_that_lies_in_a_line_is_hidden(way):
    # (3, 1) between (3, 0) and (3, 2), all three with equal power along y = 1: only the
    # outer two own the sides of that line
    sites = np.array([[3.0, 0.0], [3.0, 1.0], [3.0, 2.0], [1.0, 1.0], [5.0, 1.0]])
    weights = np.array([1.0, 0.0, 1.0, 0.0, 0.0])
    d = _build(sites, weights, way)
    assert 1 in d.hidden
    _assert_exact(sites, weights, way=way)


@WAYS
@pytest.mark.parametrize("sites, weights", [
    # (-2, -3), (0, -4) and (4, -6) are collinear and tie along one line, all three on one side
    # of it; (-2, -3) and (0, -4) touch (4, -6)'s arc there at once, and (0, -4), in the middle,
    # has the smaller s: the outer one must enter first (found by an adversarial campaign)
    ([[-2.0, -3.0], [6.0, -2.0], [4.0, -6.0], [0.0, -4.0], [-3.0, 1.0]], [16.0, 49.0, 70.0, 24.0, 0.0]),
    ([[-5.0, -6.0], [5.0, 0.0], [3.0, -4.0], [6.0, 5.0], [-1.0, -5.0]], [52.0, 0.0, 6.0, 31.0, 12.0]),
])
def test_of_sites_touching_at_once_along_a_tie_the_outermost_enters(sites, weights, way):
    sites, weights = np.array(sites), np.array(weights)
    _assert_exact(sites, weights, way=way)


@WAYS
@pytest.mark.parametrize("sites, weights", [
    # four sites of equal power at one point, one inside the triangle of the other three: its
    # cell is that point. Entering there before the others, it must close again at once when
    # one of them enters around it (found by an adversarial campaign)
    ([[-5, 3], [1, 4], [1, -5], [-2, 3]], [29, 0, 9, 2]),
    ([[-5, 6], [-2, 4], [2, 6], [5, -4]], [63, 8, 0, 3]),
    ([[2, 7], [0, 3], [6, 9], [2, 6], [7, 9]], [0, 0, 0, 0, 71]),
    ([[2, 7], [0, 3], [3, 9], [2, 6], [7, 9], [9, 8], [9, 4]], [0, 0, 0, 0, 71, 0, 0]),
])
def test_a_site_inside_a_co_power_vertex_is_hidden_whatever_enters_first(sites, weights, way):
    _assert_exact(np.array(sites, dtype=np.float64), np.array(weights, dtype=np.float64), way=way)


def test_equal_weights_give_the_ordinary_diagram():
    for dataset in ("uniform", "grid", "cocircular"):
        sites, _ = _case(dataset, "equal", 10)
        weights = np.full(sites.shape[0], 0.25)
        d = build_weighted(sites, weights)
        ordinary = impls.get("fortune").build(sites)
        assert compare(d, ordinary.with_weights(weights)).verdict == Verdict.EXACT


# ------------------------------------------------------------------------------------------
# The tests can fail: a sweep without one of its rules is caught
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("rule, dataset, family", [
    ("arc_candidate", "uniform", "radii"),       # no contacts inside arcs
    ("vertex_candidate", "uniform", "hidden"),   # no contacts at breakpoints
])
def test_a_sweep_without_a_contact_rule_differs(monkeypatch, rule, dataset, family):
    monkeypatch.setattr(Sweep, rule, lambda self, pos, i: None)
    sites, weights = _case(dataset, family, 10)
    got = build_weighted(sites, weights)
    want = impls.get("halfplane").build_weighted(sites, weights)
    assert compare(got, want).verdict != Verdict.EXACT


def test_a_probing_sweep_that_trusts_its_first_bound_differs(monkeypatch):
    # entering every site at its first lower bound, without asking who owns that point
    def trusting(self, i, low, partner):
        t, cx, cy, h = low
        pos, _ = self.locate(cx, t.a, h)
        if self.power_gap(self.arcs[self.beach[pos]].site, i, cx, cy, h) < 0:
            self.pending.discard(i)          # its bound was not on the beach line: gives up on it
            return
        original(self, i, low, partner)
    original = ProbingSweep.probe
    monkeypatch.setattr(ProbingSweep, "probe", trusting)
    sites, weights = _case("uniform", "radii", 10)
    got = build_weighted(sites, weights, probing=True)
    want = impls.get("halfplane").build_weighted(sites, weights)
    assert compare(got, want).verdict != Verdict.EXACT


def test_probes_per_site_stay_few_on_a_uniform_set():
    # locality, counted (machine independent): on uniform sites with radii weights a pending
    # site needs about three probes whatever n (measured 1.95, 2.60, 2.70 at n = 40, 120, 360)
    for n in (40, 120):
        sites, weights = _case("uniform", "radii", n)
        sweep = ProbingSweep(sites, weights)
        sweep.run()
        assert sweep.counts["probes"] <= 3.5 * n


class _ConvergingChecked(ProbingSweep):
    """The specification, counting the arcs whose breakpoints converge (l, k, m turn
    counter-clockwise) and, of those, the ones whose power centre is earlier than now or is
    not on both breakpoints at its time: the compiled sweep schedules on the turn alone
    (docs/power.md, "Why the turn is enough")."""

    def __init__(self, sites, weights, meant=(0, 1)):
        super().__init__(sites, weights)
        self.converging, self.missed = 0, 0
        self.meant = meant              # which of the two sites goes left in the test (a fault double swaps them)

    def circle_candidate(self, pos: int) -> None:
        left, right = self.neighbours(pos)
        if left >= 0 and right >= 0:
            l, k, m = self.arcs[left].site, self.arcs[self.beach[pos]].site, self.arcs[right].site
            v = self.power_centre(l, k, m) if l != m and self.orient(l, k, m) > 0 else None
            if v is not None:
                self.converging += 1
                t = Time(v[1], self.ell(k, *v))
                on_both = all(self.is_breakpoint(pair[self.meant[0]], pair[self.meant[1]], v[0], Fraction(0), t.a, t.b)
                              for pair in ((l, k), (k, m)))
                self.missed += t < self.now or not on_both
        super().circle_candidate(pos)


def _converging_missed(sites, weights, meant=(0, 1)) -> tuple[int, int]:
    sweep = _ConvergingChecked(sites, weights, meant)
    sweep.run()
    return sweep.converging, sweep.missed


@settings(max_examples=60, deadline=None)
@given(lattice_sites)
def test_converging_breakpoints_meet_at_the_power_centre_never_before_now(rows):
    # the theorem the compiled sweep's circle events stand on, on lattices with exact ties
    sites = np.array([r[:2] for r in rows], dtype=np.float64)
    weights = np.array([r[2] for r in rows], dtype=np.float64)
    assume(np.linalg.matrix_rank(sites - sites[0]) == 2)
    assert _converging_missed(sites, weights)[1] == 0


@pytest.mark.parametrize("dataset, family", [("uniform", "radii"), ("clusters", "hidden"), ("grid", "integer"),
                                             ("duplicates", "radii"), ("cocircular", "integer")])
def test_converging_breakpoints_meet_at_the_power_centre_on_the_datasets(dataset, family):
    converging, missed = _converging_missed(*_case(dataset, family, 30))
    assert converging > 0 and missed == 0


def test_the_check_of_converging_breakpoints_can_fail():
    # the fault double: asking for the other crossing of each pair, the check finds misses
    assert _converging_missed(*_case("uniform", "radii", 30), meant=(1, 0))[1] > 0
