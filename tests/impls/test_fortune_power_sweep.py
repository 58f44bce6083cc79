"""The compiled weighted sweep (impls/fortune/power_sweep.py and power_predicates.py): its
interval filters enclose the exact values and agree with the exact stage wherever they decide,
the exact stage is what decides degenerate input (a wrong exact stage is caught), equal weights
give the ordinary sweep's diagram bit for bit, and its counters tell the truth. Its diagrams
are checked exactly against the oracles in test_fortune_power.py (``Way.COMPILED``) and in
tests/test_cross_validation_weighted.py."""

from fractions import Fraction

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import datasets_gen
import impls
from impls import fortune
from impls.fortune import power_exact, power_predicates, power_reference, power_sweep
from impls.fortune.power_exact import CENTRE, CONTACT, SITE, exact_context
from vorobench.core.prepare import prepare_weighted
from vorobench.judge.comparison import Verdict, compare


def _case(dataset: str, family: str, n: int):
    points = datasets_gen.generate(dataset, n, seed=0)
    sites, weights, _ = prepare_weighted(points, datasets_gen.weights(family, points, seed=0))
    return sites, weights


def _exact_against(oracle: str, sites, weights) -> Verdict:
    return compare(fortune.build_weighted(sites, weights), impls.get(oracle).build_weighted(sites, weights)).verdict


# small sets of sites: integers (ties everywhere) or floats, with integer or float weights
# (nonzero magnitudes above 1e-6: inside the project's input range, see vorobench.core.scaling)
def _floats(lo, hi):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False).filter(lambda v: v == 0 or abs(v) > 1e-6)


coordinate = st.one_of(st.integers(-6, 6).map(float), _floats(-8, 8))
site_sets = st.lists(st.tuples(coordinate, coordinate, st.one_of(st.integers(0, 9).map(float), _floats(0, 20))),
                     min_size=3, max_size=5, unique_by=lambda t: t[:2])


def _table(rows):
    sites = np.array([r[:2] for r in rows], dtype=np.float64)
    weights = np.array([r[2] for r in rows], dtype=np.float64)
    return sites, weights, fortune._shift_table(sites, weights)


def _specs(n):
    """Every spec of a few sites: sites, power centres, contacts with a lower site."""
    out = [(SITE, a, -1, -1) for a in range(n)]
    out += [(CENTRE, a, b, c) for a in range(n) for b in range(n) for c in range(n) if len({a, b, c}) == 3]
    out += [(CONTACT, a, b, -1) for a in range(n) for b in range(n) if a != b]
    return out


def _exact_spec(g, kind, a, b, c):
    """(x, y, t) of a spec as floats of the reference's exact numbers; None if undefined."""
    if kind == CENTRE and g.power_centre(a, b, c) is None:
        return None
    if kind == CONTACT and not g.y[b] < g.y[a]:
        return None
    cx, cy, t, h = power_exact._point(kind, a, b, c)
    root = Fraction(h) ** 0.5 if h else 0.0

    def value(part):
        return float(part[0]) + float(part[1]) * float(root)
    return value(cx), value(cy), float(t)


@settings(max_examples=60, deadline=None)
@given(site_sets)
def test_the_intervals_of_points_and_times_hold_the_exact_values(rows):
    sites, weights, table = _table(rows)
    with exact_context(sites, weights):
        g = power_exact._sweep()
        for spec in _specs(len(rows)):
            exact = _exact_spec(g, *spec)
            if exact is None:
                continue
            xl, xh, yl, yh, tl, th = power_predicates.spec_point(table, *spec)
            for (lo, hi), v in zip(((xl, xh), (yl, yh), (tl, th)), exact):
                # v is the exact value rounded once or twice: within a few ulps of the interval
                slack = 4 * np.spacing(abs(v)) + 1e-300
                assert lo - slack <= v <= hi + slack, (spec, lo, v, hi)


@settings(max_examples=25, deadline=None)
@given(site_sets)
def test_where_the_filters_decide_they_agree_with_the_exact_stage(rows):
    sites, weights, table = _table(rows)
    n = len(rows)
    counters = np.zeros(2, dtype=np.int64)
    with exact_context(sites, weights):
        g = power_exact._sweep()
        specs = [s for s in _specs(n) if _exact_spec(g, *s) is not None]
        for spec in specs:
            xl, xh, yl, yh, tl, th = power_predicates.spec_point(table, *spec)
            for l in range(n):
                for r in range(n):
                    if l == r:
                        continue
                    assert power_predicates.side(table, counters, l, r, *spec, xl, xh, tl, th) == \
                        power_exact.side(l, r, *spec), ("side", l, r, spec)
                    if spec[0] != SITE:
                        assert power_predicates.power_gap(table, counters, l, r, *spec, xl, xh, yl, yh) == \
                            power_exact.power_gap(l, r, *spec), ("gap", l, r, spec)
        for s1 in specs[:12]:
            for s2 in specs[:12]:
                lo1, hi1 = power_predicates.spec_point(table, *s1)[4:]
                lo2, hi2 = power_predicates.spec_point(table, *s2)[4:]
                assert power_predicates.time_order(table, counters, *s1, lo1, hi1, *s2, lo2, hi2) == \
                    power_exact.time_order(*s1, *s2)
    assert counters[power_predicates.FILTERED] > 0


def test_random_input_needs_no_exact_stage():
    stats = {}
    fortune.build_weighted(*_case("uniform", "radii", 400), stats)
    assert stats["weighted_exact"] == 0 and stats["weighted_filtered"] > 1000


@pytest.mark.parametrize("decision", ["side", "time_order", "power_gap"])
def test_a_wrong_exact_stage_is_caught(monkeypatch, decision):
    # a lattice with integer weights is decided partly in rationals; an exact stage that gives
    # the opposite answer must spoil the diagram (or stop the sweep), not pass unnoticed
    sites, weights = _case("grid", "integer", 100)
    assert _exact_against("incremental", sites, weights) == Verdict.EXACT
    honest = getattr(power_exact, decision)
    # ties (0) become orders and orders flip
    monkeypatch.setattr(power_exact, decision, lambda *args: -honest(*args) or 1)
    try:
        verdict = _exact_against("incremental", sites, weights)
    except RuntimeError:
        return
    assert verdict != Verdict.EXACT


@pytest.mark.parametrize("dataset", ["uniform", "grid", "cocircular", "duplicates"])
def test_equal_weights_give_the_ordinary_sweep_bit_for_bit(dataset):
    sites, _ = _case(dataset, "equal", 60)
    for value in (0.0, -3.5):
        weights = np.full(sites.shape[0], value)
        d, ordinary = fortune.build_weighted(sites, weights), fortune.build(sites)
        for field in ("vertices", "origin", "twin", "next", "site"):
            assert np.array_equal(getattr(d, field), getattr(ordinary, field)), field
        assert np.array_equal(d.weights, weights)


@pytest.mark.parametrize("dataset, family", [("uniform", "hidden"), ("grid", "integer"), ("clusters", "radii")])
def test_the_counters_tell_the_truth(dataset, family):
    sites, weights = _case(dataset, family, 200)
    stats = {}
    d = fortune.build_weighted(sites, weights, stats)
    assert stats["hidden_sites"] == d.hidden.size
    row = int(np.sum(sites[:, 1] == sites[:, 1].min()))
    assert stats["site_events"] == sites.shape[0] - row
    entered = stats["contacts_in_arc"] + stats["contacts_at_vertex"]
    assert stats["first_row"] + entered + stats["never_entered"] == sites.shape[0]
    assert stats["never_entered"] <= stats["hidden_sites"]
    assert stats["probes"] >= stats["contacts_in_arc"] + stats["contacts_at_vertex"]


def test_the_exact_stage_outside_a_build_is_a_clear_error():
    with pytest.raises(RuntimeError, match="outside exact_context"):
        power_exact.time_order(SITE, 0, -1, -1, SITE, 1, -1, -1)


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 5), st.integers(0, 5), st.integers(0, 3)), min_size=3, max_size=14,
                unique_by=lambda t: t[:2]))
def test_integer_lattices_with_integer_weights_agree_with_the_regular_triangulation(rows):
    sites = np.array([r[:2] for r in rows], dtype=np.float64)
    weights = np.array([r[2] for r in rows], dtype=np.float64)
    assume(np.linalg.matrix_rank(sites - sites[0]) == 2)
    assert _exact_against("incremental", sites, weights) == Verdict.EXACT


# three sites on one line: a lattice line with integer weights (bisectors that coincide are
# common there) or a horizontal or vertical line at any floats
_small = st.integers(-4, 4)


@st.composite
def _collinear_rows(draw):
    if draw(st.booleans()):
        ox, oy = draw(_small), draw(_small)
        dx, dy = draw(st.sampled_from([(1, 0), (0, 1), (1, 1), (2, -1), (1, 3)]))
        ts = draw(st.lists(_small, min_size=3, max_size=3, unique=True))
        points = [(float(ox + t * dx), float(oy + t * dy)) for t in ts]
        weights = draw(st.lists(st.integers(0, 12).map(float), min_size=3, max_size=3))
    else:
        fixed = draw(_floats(-8, 8))
        along = draw(st.lists(_floats(-8, 8), min_size=3, max_size=3, unique=True))
        vertical = draw(st.booleans())
        points = [(fixed, t) if vertical else (t, fixed) for t in along]
        weights = draw(st.lists(st.one_of(st.integers(0, 9).map(float), _floats(0, 20)), min_size=3, max_size=3))
    return [p + (w,) for p, w in zip(points, weights)]


@settings(max_examples=200, deadline=None)
@given(st.one_of(_collinear_rows(), site_sets.map(lambda rows: rows[:3])))
def test_the_collinear_decisions_agree_with_the_rationals(rows):
    # tied (one bisector line for three collinear sites) and line_inside (a bisector line on
    # the right side of a parallel one): the compiled filter and exact stage against the
    # reference's rationals, for every order of the three sites; the exact stages are also
    # asked directly, so they are checked where the filter would have decided
    sites, weights, table = _table(rows)
    counters = np.zeros(2, dtype=np.int64)
    with exact_context(sites, weights):
        for a, b, c in [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]:
            tied = power_exact.tied(a, b, c) == 1
            assert power_predicates.tied(table, counters, a, b, c) == tied, ("tied", a, b, c)
            if power_exact._sweep().orient(a, b, c) == 0 and power_predicates._between(table, a, b, c):
                assert (power_predicates._tied_exact(table, a, b, c) == 0) == tied, ("tied exact", a, b, c)
            inside = power_exact.line_inside(a, b, c) == 1
            assert power_predicates.line_inside(table, counters, a, b, c) == inside, ("line_inside", a, b, c)
            assert (power_predicates._line_inside_exact(table, a, b, c) >= 0) == inside, ("inside exact", a, b, c)


def test_ties_on_a_lattice_line_reach_the_exact_stage():
    # x = -1, 0, 1 on a line with weights 0, -1, 0: l_0 = l_1 and l_1 = l_2 both at x = 0, one
    # bisector line for both pairs, which the interval filter cannot tell from a near miss
    rows = [(-1.0, 0.0, 0.0), (0.0, 0.0, -1.0), (1.0, 0.0, 0.0)]
    sites, weights, table = _table(rows)
    counters = np.zeros(2, dtype=np.int64)
    with exact_context(sites, weights):
        assert power_exact.tied(0, 1, 2) == 1
    assert power_predicates.tied(table, counters, 0, 1, 2)
    assert counters[power_predicates.EXACT] == 1


@settings(max_examples=25, deadline=None)
@given(site_sets)
def test_gmp_rationals_and_fractions_give_the_same_exact_decisions(rows):
    # the exact stage runs on gmpy2's rationals when installed; the reference's formulas are
    # written for Fraction: every decision of the stage must be the same in both
    gmpy2 = pytest.importorskip("gmpy2")
    sites, weights, _ = _table(rows)
    n = len(rows)

    def decisions(rational):
        saved, power_exact.rational = power_exact.rational, rational
        try:
            with exact_context(sites, weights):
                g = power_exact._sweep()
                specs = [s for s in _specs(n) if _exact_spec(g, *s) is not None]
                out = [power_exact.time_order(*s1, *s2) for s1 in specs[:10] for s2 in specs[:10]]
                out += [power_exact.side(l, r, *s) for s in specs for l in range(n) for r in range(n) if l != r]
                out += [power_exact.power_gap(l, r, *s) for s in specs if s[0] != SITE
                        for l in range(n) for r in range(n) if l != r]
                return out
        finally:
            power_exact.rational = saved

    assert decisions(gmpy2.mpq) == decisions(Fraction)


def test_the_watch_pool_grows_mid_sweep_and_the_diagram_stays_exact(monkeypatch):
    # a first pool of 16 rows: every site watches at least one, so the loop hands back to grow
    # it (doubling) again and again, and goes on where it stopped
    monkeypatch.setattr(fortune, "WATCH_ROWS_PER_SITE", 0)
    sites, weights = _case("kuzmin", "radii", 1500)
    stats = {}
    d = fortune.build_weighted(sites, weights, stats)
    assert stats["site_events"] > 2 ** 6 * 16          # each watches a site: six doublings at least
    assert compare(d, impls.get("incremental").build_weighted(sites, weights)).verdict == Verdict.EXACT


def test_more_sites_than_int32_ids_allow_is_a_clear_error(monkeypatch):
    # the sweep's ids are int32: above MAX_SITES it refuses before it allocates anything
    monkeypatch.setattr(power_sweep, "MAX_SITES", 3)
    sites, weights = _case("uniform", "radii", 4)
    with pytest.raises(ValueError, match="at most 3 sites"):
        fortune.build_weighted(sites, weights)


def test_a_watch_pool_beyond_int32_ids_is_a_clear_error(monkeypatch):
    # the pool of watch-list rows doubles as it fills; past the largest int32 id it must stop
    # the build with an error saying so, not wrap its row numbers around
    monkeypatch.setattr(fortune, "WATCH_ROWS_PER_SITE", 0)
    monkeypatch.setattr(power_sweep, "MAX_WATCH_ROWS", 64)
    sites, weights = _case("uniform", "radii", 200)
    with pytest.raises(RuntimeError, match="int32 ids"):
        fortune.build_weighted(sites, weights)


def test_the_exact_points_kept_are_bounded_and_change_no_answer(monkeypatch):
    # the exact stage keeps the points of the specs it was asked about: a small bound must
    # clear them, never hand back another spec's point, and a build must come out the same
    monkeypatch.setattr(power_exact, "_POINTS_KEPT", 3)
    sites, weights = _case("grid", "integer", 30)
    with exact_context(sites, weights):
        g = power_exact._sweep()
        specs = [s for s in _specs(5) if _exact_spec(g, *s) is not None]
        for spec in specs + specs[::-1]:
            kept = power_exact._point(*spec)
            fresh = power_exact._new_point(g, *spec)
            assert kept[:2] == fresh[:2] and kept[2] == fresh[2] and kept[3] == fresh[3], spec
            assert len(g.spec_points) <= 3
    sites, weights = _case("grid", "integer", 200)
    assert _exact_against("incremental", sites, weights) == Verdict.EXACT


def test_collinear_decisions_below_the_exact_range_fall_back_to_the_rationals():
    # Implementation.run scales inputs into the exact range; a direct call need not be in it.
    # Sites near 2**-300 (weights near 2**-600) underflow the expansions' products, so there
    # the collinear decisions must be taken in rationals, as they were before they were compiled
    # (a helper's review found this one wrong without the fallback)
    k = -300
    sites = np.ldexp(np.array([[0.0, 1.0], [7.0, 8.0], [-3.0, -2.0]]), k)
    weights = np.ldexp(np.array([4.0, 7.0, 2.0]), 2 * k)
    table, counters = fortune._shift_table(sites, weights), np.zeros(2, dtype=np.int64)
    with exact_context(sites, weights):
        for i, j, m in [(1, 2, 0), (0, 1, 2), (2, 0, 1), (0, 2, 1)]:
            assert power_predicates.line_inside(table, counters, i, j, m) == (power_exact.line_inside(i, j, m) == 1)
            assert power_predicates.tied(table, counters, i, j, m) == (power_exact.tied(i, j, m) == 1)
    assert counters[power_predicates.EXACT] > 0


#: Sets where three or more sites on a line have equal power along one line, so that the middle
#: ones must stay hidden: simultaneous probes at one point enter farthest from the arc's site
#: first. When pending sites first joined a pending site's first bound (the slabs), a probe's
#: partner could be a site not on the beach line, which ranked such probes wrongly, and gave
#: wrong diagrams or stopped on these (found by a review). Such a probe is now ranked by the
#: arc it touches (``_UNKEYED``).
TIED_ALONG_A_LINE = [
    ([(0, 1), (0, 2), (0, 0), (1, -1)], [0, 1, 1, 4]),
    ([(-4, 1), (-4, 4), (-3, 1), (-3, 2), (-3, 3), (-2, -2)], [1, 0, 10, 8, 8, 17]),
    ([(1, 0), (0, 3), (0, 1), (1, 1), (0, 4), (4, 1), (4, 0), (0, 2), (2, 1), (3, 3), (4, 4)],
     [5, 2, 2, 0, 0, 0, 0, 1, 0, 0, 0]),
    ([(0, 4), (0, 3), (0, 2), (0, 0)], [2, 0, 0, 4]),
    ([(1, -6), (0, 0), (0, 6), (0, 8), (200, 200)], [-139, -140, -80, -44, 0]),
]


@pytest.mark.parametrize("sites, weights", TIED_ALONG_A_LINE)
def test_sites_tied_along_a_line_enter_outermost_first(sites, weights):
    points, w = np.array(sites, dtype=float), np.array(weights, dtype=float)
    d = impls.build("fortune", points, weights=w)
    assert compare(d, impls.build("incremental", points, weights=w)).verdict == Verdict.EXACT


@pytest.mark.parametrize("sites, weights", TIED_ALONG_A_LINE)
def test_the_reference_enters_sites_tied_along_a_line_outermost_first(sites, weights):
    # the specification takes the same rule: its probing sweep gives the oracle's diagram
    prepared, w, _ = prepare_weighted(np.array(sites, dtype=float), np.array(weights, dtype=float))
    got = power_reference.build_weighted(prepared, w, probing=True)
    assert compare(got, impls.get("incremental").build_weighted(prepared, w)).verdict == Verdict.EXACT


def _exact_gap_and_apex(sites, weights, left, right, x, t):
    """G and the apex quantity of ``power_predicates.side`` at (x, t), in rationals."""
    xl, yl = (Fraction(v) for v in sites[left])
    xr, yr = (Fraction(v) for v in sites[right])
    wl, wr, top = Fraction(weights[left]), Fraction(weights[right]), Fraction(weights.max())
    x, t = Fraction(x), Fraction(t)
    a, b = t - yl, t - yr
    gap = (yl - yr) * (a * b - (top - wr) - (x - xr) ** 2) + b * ((xl - xr) * (2 * x - xl - xr) + wl - wr)
    return gap, (x - xl) * b - (x - xr) * a


def _near_breakpoints(rng, cases):
    """Two sites, weights and a time, with x at the float-rounded roots of G in x (where G is
    near 0 and its float value is mostly rounding error) or near the apex, moved by a few ulps;
    a box of up to a few ulps around (x, t), as a spec's point and time have."""
    for _ in range(cases):
        sites = rng.random((2, 2)) * rng.choice([1.0, 1e-3, 1e6])
        if rng.random() < 0.3:
            sites[1, 1] = sites[0, 1] + rng.integers(-2, 3) * np.spacing(sites[0, 1])
        weights = (rng.random(2) * 0.1 * (sites[0, 0] - sites[1, 0]) ** 2) if rng.random() < 0.8 else rng.random(2)
        t = max(sites[:, 1]) + rng.random() * abs(sites[0, 1] - sites[1, 1] + 1e-3)
        left, right = (0, 1) if rng.random() < 0.5 else (1, 0)
        (xl, yl), (xr, yr) = sites[left], sites[right]
        sr = weights.max() - weights[right]
        a, b, dy, dx, ds = t - yl, t - yr, yl - yr, xl - xr, weights[left] - weights[right]
        # G(x) = -dy x^2 + 2 (dy x_r + b dx) x + dy (a b - s_r - x_r^2) - b dx (x_l + x_r) + b ds
        quad = [-dy, 2 * (dy * xr + b * dx), dy * (a * b - sr - xr * xr) - b * dx * (xl + xr) + b * ds]
        roots = [r.real for r in np.roots(quad)] if dy != 0 else []
        if dy != 0 and b != a:                               # (b - a may round to 0)
            roots.append((xl * b - xr * a) / (b - a))        # the apex quantity's root
        for x in (r for r in roots if np.isfinite(r)):
            for k in rng.integers(-3, 4, size=2):
                x0 = x + k * np.spacing(x)
                width = rng.choice([0, 1, 4])
                yield sites, weights, left, right, x0, x0 + width * np.spacing(x0), t, t + width * np.spacing(t)


def test_the_float_filters_of_the_breakpoint_test_decide_only_true_signs():
    # where the float evaluation of side's two quantities decides a sign, every point of the
    # box has that sign (checked at its corners and centre, in rationals); near the roots,
    # where the float value is mostly rounding error, a bound too small would decide wrongly
    rng = np.random.default_rng(7)
    decided = checked = 0
    for sites, weights, left, right, xl, xh, tl, th in _near_breakpoints(rng, 1500):
        table = fortune._shift_table(sites, weights)
        gap = power_predicates._gap_float(table, left, right, xl, xh, tl, th)
        apex = power_predicates._apex_float(table, left, right, xl, xh, tl, th)
        points = [(x, t) for x in (xl, xh) for t in (tl, th)]
        points.append((Fraction(xl) / 2 + Fraction(xh) / 2, Fraction(tl) / 2 + Fraction(th) / 2))
        for x, t in points:
            exact_gap, exact_apex = _exact_gap_and_apex(sites, weights, left, right, x, t)
            for filtered, exact in ((gap, exact_gap), (apex, exact_apex)):
                checked += 1
                if filtered != power_predicates.UNDECIDED:
                    decided += 1
                    assert filtered * exact > 0, (sites, weights, left, right, xl, xh, tl, th, filtered, exact)
    assert decided > checked // 4 and decided < checked      # both outcomes occur


def _near_collinear_triples(rng, cases):
    """Three sites, nearly collinear (down to a few ulps off the line) or not, at offsets up
    to 1e6, with weights that often cancel most of |p_b - p_a|^2 in r_b, or a at the origin and
    b, c nearly mirrored about its vertical (the centre's x then nearly cancels to 0, so its
    error is all the numerator's rounding): where the float power centre's error bound is tight
    or must give up."""
    for _ in range(cases):
        if rng.random() < 0.3:
            p, q = rng.random(2) + 0.1
            wiggle = rng.choice([1e-9, 1e-13, 1e-16], size=3) * rng.standard_normal(3)
            sites = np.array([[0.0, rng.random() * 0.1], [p, q], [-p * (1 + wiggle[0]), q * (1 + wiggle[1])]])
            weights = np.array([0.0, 0.3, 0.3 * (1 + wiggle[2])]) * rng.random()
            yield sites, weights
            continue
        scale, offset = rng.choice([1.0, 1e-3, 1e3]), rng.choice([0.0, 1.0, 1e6]) * rng.random(2)
        a, b = offset + rng.random(2) * scale, offset + rng.random(2) * scale
        along, off = rng.random() * 2 - 0.5, rng.choice([1e-2, 1e-8, 1e-13, 1e-16]) * rng.standard_normal()
        c = a + along * (b - a) + off * scale * np.array([-(b - a)[1], (b - a)[0]])
        sites = np.array([a, b, c])
        weights = rng.random(3) * scale * scale
        if rng.random() < 0.5:      # w_a - w_b close to -|p_b - p_a|^2: r_b nearly cancels
            weights[1] = weights[0] + float(np.sum((b - a) ** 2)) * (1 + rng.standard_normal() * 1e-9)
        yield sites, weights


def test_the_float_power_centre_holds_the_exact_centre_and_time():
    # where _centre_float answers, its box holds the exact power centre and its time (compared
    # in rationals, the time through squares), for every order of the three sites
    rng = np.random.default_rng(11)
    answered = asked = 0
    for sites, weights in _near_collinear_triples(rng, 400):
        table = fortune._shift_table(sites, weights)
        with exact_context(sites, weights):
            g = power_exact._sweep()
            for a, b, c in [(0, 1, 2), (1, 2, 0), (2, 0, 1), (0, 2, 1)]:
                v = g.power_centre(a, b, c)
                ok, xl, xh, yl, yh, tl, th = power_predicates._centre_float(table, a, b, c)
                asked += 1
                if v is None or not ok:
                    continue
                answered += 1
                vx, vy = Fraction(v[0]), Fraction(v[1])
                h = Fraction(g.ell(a, *v))
                assert Fraction(xl) <= vx <= Fraction(xh), (sites, weights, a, b, c)
                assert Fraction(yl) <= vy <= Fraction(yh), (sites, weights, a, b, c)
                low, high = Fraction(tl) - vy, Fraction(th) - vy
                assert (low <= 0 or low * low <= h) and high >= 0 and high * high >= h, (sites, weights, a, b, c)
    assert asked // 2 < answered < asked                 # near-collinear triples give up


def _contact_pairs(rng, cases):
    """Two sites, the second lower, at offsets up to 1e6: at nearly one height (down to an ulp
    apart, where the contact runs off far to the side), nearly one above the other, or
    neither; often moved so that the contact, or its x and its time, is near the origin, where
    they cancel to their last bits and the box is all error bound."""
    for _ in range(cases):
        scale, offset = rng.choice([1.0, 1e-3, 1e3]), rng.choice([0.0, 1.0, 1e6]) * rng.random(2)
        upper = offset + rng.random(2) * scale
        shape = rng.integers(3)
        if shape == 0:      # nearly one height
            lower = upper + scale * np.array([rng.random() - 0.5, -rng.choice([1e-3, 1e-9, 1e-15])])
            lower[1] = min(lower[1], np.nextafter(upper[1], -np.inf))
        elif shape == 1:    # nearly one above the other
            lower = upper + scale * np.array([rng.choice([0.0, 1e-9, 1e-15]) * rng.standard_normal(), -rng.random()])
        else:
            lower = upper + scale * np.array([rng.random() - 0.5, -rng.random() - 1e-3])
        weights = rng.random(2) * scale * scale
        if rng.random() < 0.5:      # the lower site has the largest weight: s_k = 0
            weights[1] = weights[0] + float(np.sum((upper - lower) ** 2)) * (1 + rng.choice([0.0, 1e-12]))
        sites = np.array([upper, lower])
        ok, xl, xh, yl, yh, tl, th = power_predicates._contact_float(fortune._shift_table(sites, weights), 0, 1)
        move = rng.integers(3)
        if ok and move:             # the float contact only places the sites; the exact one judges
            sites = sites - np.array([(xl + xh) / 2, (yl + yh) / 2 if move == 1 else (tl + th) / 2])
        yield sites, weights


def test_the_float_contact_holds_the_exact_contact_and_time():
    # where _contact_float answers, its box holds the exact contact point (c0 + c1 sqrt h in
    # each coordinate) and its time f_y + sqrt h, compared in rationals
    rng = np.random.default_rng(12)
    answered = asked = 0
    for sites, weights in _contact_pairs(rng, 1500):
        table = fortune._shift_table(sites, weights)
        with exact_context(sites, weights):
            found = power_exact._sweep().arc_contact(0, 1)
        ok, xl, xh, yl, yh, tl, th = power_predicates._contact_float(table, 0, 1)
        asked += 1
        if found is None or not ok:
            continue
        answered += 1
        time, (x0, x1), (y0, y1), h = found
        for (c0, c1), lo, hi in (((x0, x1), xl, xh), ((y0, y1), yl, yh), ((time.a, 1), tl, th)):
            assert power_reference.surd_sign(c0 - Fraction(lo), c1, h) >= 0, (sites, weights, lo, hi)
            assert power_reference.surd_sign(Fraction(hi) - c0, -c1, h) >= 0, (sites, weights, lo, hi)
    assert answered > asked // 2                         # it gives up only where a divisor may be 0


def test_the_float_power_gap_decides_only_true_signs():
    # points within a few ulps of the bisector of two weighted sites, with boxes of 0, 1 or 4
    # ulps: each sign _power_gap_float decides is that of l_j - l_k at every corner of the box
    # (it is affine in the point, so the corners are its extremes), in rationals
    rng = np.random.default_rng(13)
    decided = checked = 0
    for _ in range(3000):
        scale, offset = rng.choice([1.0, 1e-3, 1e3]), rng.choice([0.0, 1.0, 1e6]) * rng.random(2)
        sites = offset + rng.random((2, 2)) * scale
        weights = rng.random(2) * scale * scale
        table = fortune._shift_table(sites, weights)
        start, way = offset + rng.random(2) * scale, rng.standard_normal(2)
        lifted = [(float(w), site) for w, site in zip(weights, sites)]

        def gap(c):
            return sum(sign * (np.sum((c - site) ** 2) - w) for sign, (w, site) in zip((1, -1), lifted))

        g0, g1 = gap(start), gap(start + way) - gap(start)
        if g1 == 0:
            continue
        centre = start - g0 / g1 * way
        centre = centre + rng.integers(-3, 4, size=2) * np.spacing(centre)
        half = rng.choice([0, 1, 4], size=2) * np.spacing(centre)
        xl, xh, yl, yh = centre[0] - half[0], centre[0] + half[0], centre[1] - half[1], centre[1] + half[1]
        got = power_predicates._power_gap_float(table, 0, 1, xl, xh, yl, yh)
        checked += 1
        if got == power_predicates.UNDECIDED:
            continue
        decided += 1
        (pj, pk), (wj, wk) = [[Fraction(v) for v in site] for site in sites], [Fraction(w) for w in weights]
        for x in (xl, xh):
            for y in (yl, yh):
                x_, y_ = Fraction(x), Fraction(y)
                exact = (x_ - pj[0]) ** 2 + (y_ - pj[1]) ** 2 - wj - (x_ - pk[0]) ** 2 - (y_ - pk[1]) ** 2 + wk
                assert got * exact > 0, (sites, weights, xl, xh, yl, yh, got)
    assert checked // 10 < decided < checked                 # both outcomes occur


def test_the_float_filters_give_up_on_boxes_and_shifts_upside_down():
    # the sweep never makes them, but a filter must not turn one into a sign or a box (a
    # helper's review found that the bounds then went negative and a sign came out)
    sites, weights = np.array([[0.2, 0.1], [0.7, 0.3], [0.4, 0.9]]), np.array([0.0, 0.01, 0.02])
    table = fortune._shift_table(sites, weights)
    for box in ((0.5, -np.inf, 2.0, 2.0), (0.5, 0.5, 2.0, -np.inf), (0.5, 0.4, 2.0, 2.0)):
        assert power_predicates._apex_float(table, 0, 1, *box) == power_predicates.UNDECIDED, box
        assert power_predicates._gap_float(table, 0, 1, *box) == power_predicates.UNDECIDED, box
    upside_down = table.copy()
    upside_down[:, 2] = np.inf                          # s_lo above s_hi
    assert power_predicates._gap_float(upside_down, 0, 1, 0.5, 0.5, 2.0, 2.0) == power_predicates.UNDECIDED
    assert not power_predicates._centre_float(upside_down, 0, 1, 2)[0]
