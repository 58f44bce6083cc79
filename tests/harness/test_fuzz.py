"""vorobench fuzz: budgets, the case sequence, the integer-box generator, resuming (and starting
afresh once the code under test changed), witnesses, and the same verdicts from a local pool
and a Dask LocalCluster with a worker killed mid-run."""

from __future__ import annotations

import argparse
import itertools
import json
import sys
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from vorobench.cli import main
from vorobench.core.prepare import prepare
from vorobench.harness import fuzz
from vorobench.harness.fuzz import Budget, int_box, parse_budget, plan, plugin_digest, run_campaign, source_digest

HERE = Path(__file__).parent
SUPPORT = HERE.parent / "support"
DOUBLES = str(SUPPORT / "doubles.py")
DYING = str(SUPPORT / "executor_doubles.py")

#: A plugin that is halfplane under another name; WRONG_BUILD makes it build the reversed sites.
WRAPPED = """\
import impls
from vorobench.plugin import Implementation


def build(sites, stats=None):
    return impls.get("halfplane").build(sites, stats)


IMPLEMENTATIONS = [Implementation("wrapped", "halfplane, wrapped", "O(n log n)", build, exact=True)]
"""
RIGHT_BUILD = 'impls.get("halfplane").build(sites, stats)'
WRONG_BUILD = 'impls.get("halfplane").build(sites[::-1].copy(), stats)'


def test_parse_budget():
    assert parse_budget("100000") == Budget(cases=100000)
    assert parse_budget("10m") == Budget(seconds=600.0)
    assert parse_budget("90s") == Budget(seconds=90.0) and parse_budget("2h") == Budget(seconds=7200.0)
    for bad in ("0", "-5m", "ten", ""):
        with pytest.raises(argparse.ArgumentTypeError):
            parse_budget(bad)


def test_plan_is_fixed_by_the_campaign_seed():
    first = list(itertools.islice(plan(["uniform", "int_box"], 3, 12, 7), 50))
    assert first == list(itertools.islice(plan(["uniform", "int_box"], 3, 12, 7), 50))
    assert first != list(itertools.islice(plan(["uniform", "int_box"], 3, 12, 8), 50))
    assert [g for g, _, _ in first[:4]] == ["uniform", "int_box", "uniform", "int_box"]
    assert all(3 <= n <= 12 for _, n, _ in first)
    assert len({s for _, _, s in first}) == 50                   # a fresh seed per case


def test_int_box_has_duplicates_collinear_and_cocircular_points():
    duplicates = cocircular = 0
    for seed in range(30):
        p = int_box(20, seed)
        assert p.shape == (20, 2) and np.array_equal(p, np.round(p))
        duplicates += prepare(p)[0].shape[0] < 20
        # Four or more points at squared distance exactly 25 from one integer centre.
        centres = {tuple(c) for c in np.round(p).astype(int)} | {(x, y) for x in range(-3, 12) for y in range(-3, 12)}
        cocircular += any(np.sum(np.sum((p - np.array(c)) ** 2, axis=1) == 25) >= 4 for c in centres)
    assert duplicates >= 10 and cocircular >= 5


def test_campaign_resumes_without_rerunning_checked_cases(tmp_path):
    first = run_campaign(tmp_path, ["fortune"], ["uniform", "int_box"], Budget(cases=4), max_n=10, probes=100)
    assert (first.checked, first.previously, first.failed, first.lost) == (4, 0, 0, 0)
    second = run_campaign(tmp_path, ["fortune"], ["uniform", "int_box"], Budget(cases=7), max_n=10, probes=100)
    assert (second.checked, second.previously) == (3, 4) and second.rate > 0
    records = [json.loads(line) for line in (tmp_path / fuzz.LOG_NAME).read_text().splitlines()]
    assert records[0]["kind"] == "setup" and records[0]["impls"] == ["fortune"]    # what the log answers for
    records = records[1:]
    keys = [(r["generator"], r["n"], r["seed"]) for r in records]
    assert keys == list(itertools.islice(plan(["uniform", "int_box"], 3, 10, 0), 7))    # each once, in order
    assert all(r["passed"] and {v["impl"] for v in r["results"]} == {"qhull", "fortune"} for r in records)


def test_failures_are_shrunk_to_saved_witnesses(tmp_path):
    s = run_campaign(tmp_path, ["wrong"], ["uniform"], Budget(cases=2), min_n=8, max_n=12, probes=100,
                     plugins=[DOUBLES], shrink_seconds=20)
    assert s.failed == 2 and len(s.witnesses) == 2
    for w in s.witnesses:
        points = np.load(w["points"])
        assert points.shape[0] == w["n_points"] < w["n"]
        assert w["verdict"] not in ("exact", "within_tolerance", "certified")   # the witness still fails
        assert Path(w["points"]).with_suffix(".txt").read_text().startswith("vorobench validate")
    # A rerun has nothing left to check or shrink.
    again = run_campaign(tmp_path, ["wrong"], ["uniform"], Budget(cases=2), min_n=8, max_n=12, probes=100,
                         plugins=[DOUBLES])
    assert (again.checked, again.witnesses) == (0, [])


def _fuzz_wrapped(plugin: Path, out: Path) -> int:
    return main(["fuzz", "--plugin", str(plugin), "--impls", "wrapped", "--generators", "uniform", "--budget", "2",
                 "--max-n", "10", "--probes", "100", "--no-shrink", "--out", str(out)])


def test_a_rerun_after_the_plugin_changed_checks_its_cases_again(tmp_path):
    plugin = tmp_path / "wrapped.py"
    plugin.write_text(WRAPPED)
    out = tmp_path / "campaign"
    assert _fuzz_wrapped(plugin, out) == 0
    plugin.write_text(WRAPPED.replace(RIGHT_BUILD, WRONG_BUILD))      # same path, now wrong
    assert _fuzz_wrapped(plugin, out) == 1
    summary = json.loads((out / "summary.json").read_text())
    assert summary["checked"] == 2 and summary["failed"] == 2 and summary["previously_checked"] == 0
    (old_log,) = (out / "superseded").glob(f"*/{fuzz.LOG_NAME}")      # the old passes are kept aside
    assert sum(json.loads(line).get("kind") == "case" for line in old_log.read_text().splitlines()) == 2


def test_a_rerun_after_the_implementations_changed_starts_afresh(tmp_path):
    first = run_campaign(tmp_path, ["halfplane"], ["uniform"], Budget(cases=2), max_n=8, probes=100, shrink=False)
    assert first.checked == 2
    log = tmp_path / fuzz.LOG_NAME
    records = [json.loads(line) for line in log.read_text().splitlines()]
    records[0]["code"] = {**records[0].get("code", {}), "source": "0" * 64}      # as if made by other code
    log.write_text("".join(json.dumps(r) + "\n" for r in records))
    again = run_campaign(tmp_path, ["halfplane"], ["uniform"], Budget(cases=2), max_n=8, probes=100, shrink=False)
    assert (again.checked, again.previously) == (2, 0)


def test_the_source_digest_follows_every_python_file(tmp_path):
    package = tmp_path / "pkg"
    (package / "sub").mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "sub" / "part.py").write_text("X = 1\n")
    module = SimpleNamespace(__file__=str(package / "__init__.py"))
    before = source_digest([module])
    assert source_digest([module]) == before
    (package / "sub" / "part.py").write_text("X = 2\n")
    assert source_digest([module]) != before


def test_a_module_plugin_is_digested_by_its_source(tmp_path, monkeypatch):
    package = tmp_path / "digest_probe_pkg"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "impl.py").write_text("IMPLEMENTATIONS = []\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    before = plugin_digest("digest_probe_pkg")
    (package / "impl.py").write_text("IMPLEMENTATIONS = []  # edited\n")
    assert plugin_digest("digest_probe_pkg") != before
    assert plugin_digest("no_such_module_here") == "missing"
    sys.modules.pop("digest_probe_pkg", None)


def test_cli_fuzz_reports_cases_per_second(tmp_path, capsys):
    code = main(["fuzz", "--impls", "incremental", "--generators", "int_box,collinear", "--budget", "3",
                 "--max-n", "8", "--out", str(tmp_path)])
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert code == 0 and summary["checked"] == 3 and summary["cases_per_second"] > 0
    assert "cases/s" in capsys.readouterr().out


# ----------------------------------------------------------------------- with a Dask cluster



def _campaign(out: Path, executor: str, workers: int) -> dict:
    s = run_campaign(out, ["fortune", "exit_on_some"], ["uniform", "int_box"], Budget(cases=8), executor=executor,
                     workers=workers, max_n=12, campaign_seed=3, probes=100, plugins=[DYING], shrink=False)
    assert s.checked == 8
    records = [json.loads(line) for line in (out / fuzz.LOG_NAME).read_text().splitlines()]
    records = [r for r in records if r["kind"] == "case"]
    by_key = {(r["generator"], r["n"], r["seed"]): r for r in records}
    assert len(by_key) == len(records) == 8                                 # none dropped, none twice
    return by_key


def test_campaign_on_dask_and_local_same_verdicts_with_a_build_that_kills_its_process(tmp_path, dask_address):
    from executor_doubles import dies_on

    local = _campaign(tmp_path / "local", "local", 2)
    dask = _campaign(tmp_path / "dask", dask_address, 1)
    assert local.keys() == dask.keys()
    dying = {k for k in local if dies_on(prepare(fuzz.generate(*k))[0].shape[0])}
    assert dying                                    # this campaign kills a build's process
    for key in local:
        # The dying build is contained in its sandbox: the case is judged, and only that
        # implementation fails, with the same verdicts on both executors.
        assert local[key]["status"] == dask[key]["status"] == "checked"
        verdicts = [(v["impl"], v["verdict"], v["passed"]) for v in local[key]["results"]]
        assert verdicts == [(v["impl"], v["verdict"], v["passed"]) for v in dask[key]["results"]]
        for impl, verdict, passed in verdicts:
            if impl == "exit_on_some" and key in dying:
                assert (verdict, passed) == ("crashed", False)
            else:
                assert passed, (impl, verdict)
