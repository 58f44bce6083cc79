"""Power diagrams of collinear weighted sites (``collinear_diagram(sites, weights)``) and its exact
1-D predicate (``collinear_power_test``), against ``Fraction`` references.

References, written from the definitions and independent of the module:
* the predicate: the lifted height of the middle site minus the chord of its neighbours',
  h_b - ((1 - s) h_a + s h_c) with h = x**2 + y**2 - w and s = |b - a| / |c - a| (s read off
  one coordinate that varies), in ``Fraction``s (``Fraction(float)`` is exact);
* the diagram: a monotone chain over (position along the line, h) in ``Fraction``s, popping a
  site on or above the chord of its neighbours (a tie is hidden: its cell would be a line).
Exactly collinear float sites: lines y = c, x = c, y = x, y = 2x (exact in floats), and integer
lattice lines; ties are made exactly with integer weights, near ties by rounding the exact
tie weight to the nearest float.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

import impls
from vorobench.core.builder import COLLINEAR_POWER_ERRBOUND, collinear_diagram, collinear_power_test
from vorobench.core.predicates import EPSILON

RNG_SEED = 20250316


def sgn(x):
    return int(x > 0) - int(x < 0)


def chord_gap(a, b, c):
    """h_b - ((1 - s) h_a + s h_c) for collinear weighted points a < b < c, exactly."""
    (ax, ay, aw), (bx, by, bw), (cx, cy, cw) = ([Fraction(v) for v in p] for p in (a, b, c))
    s = (bx - ax) / (cx - ax) if cx != ax else (by - ay) / (cy - ay)
    h = [x * x + y * y - w for x, y, w in ((ax, ay, aw), (bx, by, bw), (cx, cy, cw))]
    return h[1] - ((1 - s) * h[0] + s * h[2])


def fraction_visible(sites, weights):
    """Visible site ids, in order along the line: the lower hull of (t, h), exactly."""
    order = np.lexsort((sites[:, 1], sites[:, 0]))
    p0 = [Fraction(v) for v in sites[order[0]]]
    p1 = [Fraction(v) for v in sites[order[-1]]]
    d = (p1[0] - p0[0], p1[1] - p0[1])
    lifted = {}
    for i in order:
        x, y = Fraction(sites[i, 0]), Fraction(sites[i, 1])
        lifted[int(i)] = ((x - p0[0]) * d[0] + (y - p0[1]) * d[1], x * x + y * y - Fraction(weights[i]))
    chain = []
    for i in (int(j) for j in order):
        while len(chain) >= 2:
            (ta, ha), (tb, hb), (tc, hc) = lifted[chain[-2]], lifted[chain[-1]], lifted[i]
            # b on or above the chord from a to c: cross((b - a), (c - a)) <= 0
            if (tb - ta) * (hc - ha) - (hb - ha) * (tc - ta) > 0:
                break
            chain.pop()
        chain.append(i)
    return chain


def line_points(rng, kind, k):
    """k distinct, exactly collinear float sites on a line of the given kind, random order."""
    if kind == "lattice":
        d = rng.integers(-4, 5, 2)
        while not d.any():
            d = rng.integers(-4, 5, 2)
        t = rng.choice(np.arange(-40, 40), k, replace=False)
        pts = rng.integers(-30, 30, 2) + t[:, None] * d
        return pts.astype(np.float64) * 2.0 ** int(rng.integers(-3, 4))
    t = rng.choice(np.arange(-10_000, 10_000), k, replace=False) * rng.random() * 1e-3 + rng.random()
    c = rng.random() * 3.0 - 1.0
    if kind == "horizontal":
        return np.column_stack([t, np.full(k, c)])
    if kind == "vertical":
        return np.column_stack([np.full(k, c), t])
    if kind == "diagonal":
        return np.column_stack([t, t])
    return np.column_stack([t, 2.0 * t])                      # y = 2x, exact in floats


def middle_on_chord_weight(a, c, b, aw, cw):
    """The weight of b (between a and c) whose lifted point is exactly on the chord."""
    s = (Fraction(b[0]) - Fraction(a[0])) / (Fraction(c[0]) - Fraction(a[0])) if a[0] != c[0] else \
        (Fraction(b[1]) - Fraction(a[1])) / (Fraction(c[1]) - Fraction(a[1]))
    dist2 = sum((Fraction(c[i]) - Fraction(a[i])) ** 2 for i in range(2))
    return (1 - s) * Fraction(aw) + s * Fraction(cw) - s * (1 - s) * dist2


def triples(rng, count):
    """Sorted collinear triples with weights: random, exact ties, and near ties (rounded)."""
    out = []
    kinds = ["lattice", "horizontal", "vertical", "diagonal", "double"]
    for it in range(count):
        p = line_points(rng, kinds[it % len(kinds)], 3)
        p = p[np.lexsort((p[:, 1], p[:, 0]))]
        scale = float(np.abs(p).max()) ** 2 + 1.0
        aw, cw = (rng.random(2) - 0.5) * scale
        mode = it % 3
        if kinds[it % len(kinds)] == "lattice":
            aw, cw = float(rng.integers(-50, 50)), float(rng.integers(-50, 50))
        tie = middle_on_chord_weight(p[0], p[2], p[1], aw, cw)
        if mode == 0:
            bw = float(tie)                        # exact when representable, else a near tie
        elif mode == 1:
            bw = float(tie) + (rng.random() - 0.5) * scale * 1e-13
        else:
            bw = (rng.random() - 0.5) * scale
        out.append(((p[0, 0], p[0, 1], aw), (p[1, 0], p[1, 1], bw), (p[2, 0], p[2, 1], cw)))
    return out


def test_collinear_power_test_matches_fraction():
    rng = np.random.default_rng(RNG_SEED)
    seen = {-1: 0, 0: 0, 1: 0}
    for a, b, c in triples(rng, 6000):
        want = sgn(chord_gap(a, b, c))
        assert collinear_power_test(*a, *b, *c) == want, (a, b, c)
        seen[want] += 1
    assert min(seen.values()) > 40, seen       # every sign, exact ties included


def test_plain_floats_are_wrong_on_near_ties_where_the_test_is_right():
    rng = np.random.default_rng(RNG_SEED + 1)
    wrong = 0
    for a, b, c in triples(rng, 3000):
        (ax, ay, aw), (bx, by, bw), (cx, cy, cw) = a, b, c
        el = (bx - ax) * (cx - ax) + (by - ay) * (cy - ay)
        em = (cx - bx) * (cx - ax) + (cy - by) * (cy - ay)
        naive = sgn((em * (aw - bw) + el * (cw - bw)) - el * em)
        wrong += naive != sgn(chord_gap(a, b, c))
    assert wrong > 20                            # so the filter and the exact stage matter


def test_error_bound_covers_gamma_11():
    u = Fraction(EPSILON)
    gamma11 = 11 * u / (1 - 11 * u)
    # the permanent is computed with seven roundings, each at worst a factor (1 - u)
    assert Fraction(COLLINEAR_POWER_ERRBOUND) * (1 - u) ** 7 > gamma11


@pytest.mark.parametrize("k", [-90, 0, 90])
def test_exact_at_the_ends_of_the_range(k):
    rng = np.random.default_rng(RNG_SEED + 2)
    for a, b, c in triples(rng, 300):
        scaled = [(x * 2.0 ** k, y * 2.0 ** k, w * 2.0 ** (2 * k)) for x, y, w in (a, b, c)]
        assert collinear_power_test(*scaled[0], *scaled[1], *scaled[2]) == sgn(chord_gap(a, b, c))


def test_a_tie_is_hidden_and_just_below_it_is_visible():
    sites = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    # pow_b at x = 1 is -w_b; min(pow_a, pow_c) there is 1: w_b = -1 touches at one point only
    tie = collinear_diagram(sites, np.array([0.0, -1.0, 0.0]))
    assert tie.hidden.tolist() == [1]
    assert sorted(map(tuple, np.sort(tie.ridge_points, axis=1).tolist())) == [(0, 2)]
    above = collinear_diagram(sites, np.array([0.0, np.nextafter(-1.0, 0.0), 0.0]))
    assert above.hidden.size == 0 and above.n_edges == 2


@pytest.mark.parametrize("kind", ["lattice", "horizontal", "vertical", "diagonal", "double"])
def test_collinear_diagram_keeps_the_exact_lower_hull(kind):
    rng = np.random.default_rng(RNG_SEED + 3)
    for it in range(40):
        k = int(rng.integers(2, 25))
        sites = line_points(rng, kind, k)
        span2 = float(np.ptp(sites, axis=0).max()) ** 2
        w = np.round(rng.random(k) * span2 * 0.3, 1) * (rng.random(k) < 0.7)
        if it % 4 == 0:                           # ties: one chord's middle put on it exactly
            order = np.lexsort((sites[:, 1], sites[:, 0]))
            if k >= 3:
                a, b, c = order[0], order[1], order[2]
                tie = middle_on_chord_weight(sites[a], sites[c], sites[b], w[a], w[c])
                w[b] = float(tie)
        d = collinear_diagram(sites, w).validate()
        chain = fraction_visible(sites, w)
        assert sorted(set(range(k)) - set(chain)) == d.hidden.tolist()
        assert d.n_edges == len(chain) - 1
        pairs = {tuple(sorted(p)) for p in d.ridge_points.tolist()}
        assert pairs == {tuple(sorted(p)) for p in zip(chain[:-1], chain[1:])}
        # every edge is a full line (no vertex), on the line's perpendicular
        assert d.n_vertices == 0 and np.all(d.origin == -1)


def test_hidden_sites_lose_to_their_neighbours_everywhere_on_the_line():
    # Probes along the line: the minimum power is always attained by a visible site, and
    # never strictly by a hidden one (exact, in fractions).
    rng = np.random.default_rng(RNG_SEED + 4)
    sites = line_points(rng, "lattice", 30)
    w = rng.integers(0, 200, 30).astype(np.float64)
    d = collinear_diagram(sites, w)
    hidden = set(d.hidden.tolist())
    assert 3 <= len(hidden) <= 27
    order = np.lexsort((sites[:, 1], sites[:, 0]))
    lo, hi = sites[order[0]], sites[order[-1]]
    for s in np.linspace(-0.2, 1.2, 281):
        x = [Fraction(lo[i]) + Fraction(s) * (Fraction(hi[i]) - Fraction(lo[i])) for i in range(2)]
        pw = [(x[0] - Fraction(p[0])) ** 2 + (x[1] - Fraction(p[1])) ** 2 - Fraction(wi) for p, wi in zip(sites, w)]
        best = min(pw)
        assert any(pw[i] == best for i in range(30) if i not in hidden)


def test_equal_weights_give_the_ordinary_diagram_exactly():
    rng = np.random.default_rng(RNG_SEED + 5)
    for kind in ("lattice", "diagonal", "vertical"):
        sites = line_points(rng, kind, 17)
        plain = collinear_diagram(sites)
        for value in (0.0, 3.5, -1e6):
            d = collinear_diagram(sites, np.full(17, value))
            assert d.hidden.size == 0
            for name in ("vertices", "origin", "twin", "next", "site"):
                assert np.array_equal(getattr(d, name), getattr(plain, name)), name
            assert np.array_equal(d.weights, np.full(17, value))


def test_qhull_sends_collinear_weighted_sites_here():
    rng = np.random.default_rng(RNG_SEED + 6)
    sites = line_points(rng, "double", 40)
    w = rng.random(40) * float(np.ptp(sites)) ** 2 * 0.2
    stats = {}
    d = impls.build("qhull", sites, weights=w, stats=stats)
    assert stats.get("collinear") == 1
    chain = fraction_visible(sites, w)
    assert d.hidden.tolist() == sorted(set(range(40)) - set(chain))
    assert d.n_edges == len(chain) - 1
