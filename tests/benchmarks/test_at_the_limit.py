"""benchmarks/at_the_limit.py: a contender that is quadratic on a family is extrapolated from
pilot runs and skipped, never run at the full size (synthetic timings, no real run is timed)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
import at_the_limit  # noqa: E402


@pytest.fixture
def timed_sizes(monkeypatch):
    """Replace the real timing by n**2 * 1e-9 s (quadratic: 40 s at 200,000 sites),
    and record the sizes the contender was asked to run."""
    asked = []

    def fake_time_once(name, sites, which):
        asked.append(sites.shape[0])
        return sites.shape[0] ** 2 * 1e-9

    monkeypatch.setattr(at_the_limit, "_time_once", fake_time_once)
    monkeypatch.setattr(at_the_limit, "CONTENDERS", (("fortune", "fortune", "total"),))
    return asked


def test_a_quadratic_contender_is_skipped_at_the_full_size(timed_sizes):
    records = at_the_limit.measure(["uniform"], [200_000], rounds=1, log=lambda _: None, budget=30.0)
    (record,) = records
    assert record["seconds"] is None
    assert record["note"] == "skipped: extrapolated 40 s > budget 30 s"
    assert max(timed_sizes) <= at_the_limit.PILOT_SIZES[-1]


def test_a_contender_within_budget_is_run_at_the_full_size(timed_sizes):
    records = at_the_limit.measure(["uniform"], [200_000], rounds=1, log=lambda _: None, budget=100.0)
    (record,) = records
    assert record["seconds"] == pytest.approx(200_000 ** 2 * 1e-9)
    assert timed_sizes == [*at_the_limit.PILOT_SIZES, 200_000]


def test_breakdown_runs_build_breakdown_at_the_largest_size(monkeypatch, capsys):
    import build_breakdown

    asked = []
    monkeypatch.setattr(at_the_limit, "measure", lambda *args, **kwargs: [])
    monkeypatch.setattr(at_the_limit, "table", lambda records: "the table")
    monkeypatch.setattr(build_breakdown, "main", lambda argv: asked.append(argv) or 0)
    assert at_the_limit.main(["--families", "uniform", "--sizes", "1e4,2e4", "--rounds", "3", "--breakdown"]) == 0
    assert asked == [["--n", "20000", "--rounds", "3"]]
    assert at_the_limit.main(["--families", "uniform", "--sizes", "1e4"]) == 0
    assert len(asked) == 1
