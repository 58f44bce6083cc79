"""CI gate: every registered implementation against the reference, on every dataset family.

Implementations join by being registered: the parameters come from ``impls.available()`` at
collection time. Each must certify (exactly, or within tolerance if floating point), agree
with the reference (``exact``; ``within_tolerance`` against a floating-point reference), and,
if exact, agree exactly with the first exact implementation. The reference is certified too.
A failure message carries the verdict and, through ``vorobench validate``, a witness.
"""

from functools import lru_cache

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import datasets_gen
import impls
from vorobench.crossval import DEFAULT_REFERENCE, agree_exactly, build_and_certify, check_case
from vorobench.prepare import prepare

SIZES = (0, 1, 2, 3, 10, 100, 1000)
SEEDS = (0, 1)
PROBES = 4000
IMPLS = impls.available()
EXACT = [name for name in IMPLS if name != DEFAULT_REFERENCE and impls.get(name).exact]
ANCHOR = EXACT[0] if EXACT else None


@lru_cache(maxsize=None)
def _sites(dataset: str, n: int, seed: int):
    sites, _ = prepare(datasets_gen.generate(dataset, n, seed=seed))
    sites.setflags(write=False)
    return sites


@lru_cache(maxsize=None)
def _built(name: str, dataset: str, n: int, seed: int):
    return build_and_certify(name, _sites(dataset, n, seed), probes=PROBES)


def _problems(name: str, sites, ref, anchor=None, probes: int = PROBES) -> list[str]:
    out = []
    v = check_case(name, sites, reference=DEFAULT_REFERENCE, reference_result=ref, probes=probes)
    if not v.passed:
        out.append(f"{v.verdict}: {v.message}")
    if anchor is not None and name != ANCHOR and v.result is not None and v.result.diagram is not None:
        agreement = agree_exactly(anchor, v.result)
        if not agreement.passed:
            out.append(agreement.message)
    return out


@pytest.mark.parametrize("dataset", datasets_gen.available())
@pytest.mark.parametrize("name", IMPLS)
def test_implementation_on_dataset(name, dataset):
    failures = []
    for n in SIZES:
        for seed in SEEDS:
            sites = _sites(dataset, n, seed)
            ref = _built(DEFAULT_REFERENCE, dataset, n, seed)
            anchor = _built(ANCHOR, dataset, n, seed) if ANCHOR and name in EXACT else None
            for problem in _problems(name, sites, ref, anchor):
                failures.append(f"n={n} seed={seed}: {problem}")
    repro = f"vorobench validate --impls {name} --datasets {dataset} --sizes {','.join(map(str, SIZES))} " \
            f"--seeds {','.join(map(str, SEEDS))}"
    assert not failures, f"{name} on {dataset} ({repro} gives a witness):\n" + "\n".join(failures)


# ------------------------------------------------------------------------------ generated point sets
# Coordinates within the exact range of vorobench.predicates (|x| in [1e-50, 1e50], or 0): the
# contract every implementation is built on; smaller magnitudes are flushed to 0.
_real = st.floats(-1e3, 1e3, allow_nan=False).map(lambda x: 0.0 if abs(x) < 1e-30 else x)
_coord = st.integers(min_value=0, max_value=6)
integer_grid = st.lists(st.tuples(_coord, _coord), min_size=0, max_size=40)
# The twelve integer points on x^2 + y^2 = 25, and integer points inside: cocircular subsets.
_CIRCLE = [(3, 4), (4, 3), (5, 0), (4, -3), (3, -4), (0, -5), (-3, -4), (-4, -3), (-5, 0), (-4, 3), (-3, 4), (0, 5)]
cocircular = st.tuples(st.lists(st.sampled_from(_CIRCLE), min_size=0, max_size=12),
                       st.lists(st.tuples(st.integers(-3, 3), st.integers(-3, 3)), max_size=8)).map(
    lambda parts: parts[0] + parts[1])
repeated = st.lists(st.tuples(_real.map(lambda x: x / 1e3), _real.map(lambda x: x / 1e3)),
                    min_size=1, max_size=8).flatmap(
    lambda base: st.lists(st.sampled_from(base), min_size=0, max_size=30))
tiny = st.lists(st.tuples(_real, _real), max_size=5)
point_sets = st.one_of(integer_grid, cocircular, repeated, tiny)


@pytest.mark.parametrize("name", IMPLS)
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(points=point_sets)
def test_implementation_on_generated_points(name, points):
    sites, _ = prepare(np.array(points, dtype=np.float64).reshape(-1, 2))
    ref = build_and_certify(DEFAULT_REFERENCE, sites, probes=1000)
    anchor = build_and_certify(ANCHOR, sites, probes=1000) if ANCHOR and name in EXACT else None
    problems = _problems(name, sites, ref, anchor, probes=1000)
    assert not problems, f"{name} on {sites.tolist()}:\n" + "\n".join(problems)
