"""vorobench trend: a page of every case's build time and counters across the runs of a store,
change points marked with their commit, machines kept apart, and the change points as JSON."""

from __future__ import annotations

import hashlib
import json
import re
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from plotly.offline import get_plotlyjs

from vorobench.cli import main
from vorobench.harness import trend
from vorobench.harness.store import Store

FAST, SLOW = "aaaa1111", "bbbb2222"


def commit(k: int) -> str:
    return hashlib.sha1(f"commit {k}".encode()).hexdigest()


def short(k: int) -> str:
    return commit(k)[:7]


def _file_run(store: Store, k: int, machine: str, date: str, cases: dict, *, dirty: bool = False,
              repeats: int = 5, seed: int = 0, code: int | None = None, module: str = "impls.fortune") -> str:
    """One run: ``cases`` maps (impl, dataset, n, seed) -> (median seconds, {counter: value});
    made of commit ``code`` (default: commit k)."""
    rng = np.random.default_rng(seed)
    code = k if code is None else code
    run_id = f"run{k:02d}-{machine[:4]}"
    rows = []
    for (impl, dataset, n, s), (level, counters) in cases.items():
        for r in range(repeats):
            rows.append({"run_id": run_id, "impl": impl, "dataset": dataset, "n": n, "seed": s, "repeat": r,
                         "status": "ok", "verdict": "exact", "time_s": level * (1 + rng.uniform(-0.03, 0.03)),
                         **{f"stat_{c}": v for c, v in counters.items()}})
    meta = {"run_id": run_id, "date": date, "commit": commit(code), "dirty": dirty, "machine_id": machine,
            "hostname": f"host-{machine[:4]}", "cpu": "Test CPU",
            "implementations": {impl: {"commit": commit(code), "dirty": dirty, "module": module}
                                for impl, *_ in cases}}
    assert store.add_run(pd.DataFrame(rows), meta)
    return run_id


def _cases(k: int, slow: float = 1.0) -> dict:
    return {
        # build time: 30 % slower from run 6 on
        ("fortune", "uniform", 1000, 0): (slow * (0.010 if k < 6 else 0.013), {"site_events": 1000}),
        # a counter changes at run 4, time steady
        ("fortune", "uniform", 10000, 0): (slow * 0.12, {"site_events": 10000,
                                                         "circle_events": 35000 if k < 4 else 35010}),
        ("qhull", "grid", 1000, 0): (slow * 0.004, {"qhull_vertices": 1980}),
    }


@pytest.fixture(scope="module")
def store(tmp_path_factory) -> Path:
    path = tmp_path_factory.mktemp("trend") / "runs"
    s = Store(path)
    for k in range(10):
        _file_run(s, k, FAST, f"2026-01-{k + 1:02d}T00:00:00+00:00", _cases(k), dirty=(k == 9), seed=k)
    # The other machine ran later and is twice as slow throughout, with no step of its own:
    # a series mixing machines would show a 2x step at its first run.
    for k in range(10):
        cases = {key: (level, counters) for key, (level, counters) in _cases(0, slow=2.0).items()}
        _file_run(s, 20 + k, SLOW, f"2026-02-{k + 1:02d}T00:00:00+00:00", cases, seed=100 + k)
    return path


@pytest.fixture(scope="module")
def outputs(store, tmp_path_factory):
    out = tmp_path_factory.mktemp("out")
    html, js = out / "trend.html", out / "changes.json"
    assert main(["trend", str(store), "-o", str(html), "--json", str(js)]) == 0
    return html.read_text(encoding="utf-8"), json.loads(js.read_text())


def test_the_time_step_is_found_at_its_commit(outputs):
    _, doc = outputs
    steps = [c for c in doc["change_points"] if c["kind"] == "time"]
    assert len(steps) == 1, steps
    step = steps[0]
    assert (step["machine_id"], step["impl"], step["dataset"], step["n"], step["seed"]) == \
        (FAST, "fortune", "uniform", 1000, 0)
    assert step["commit"] == commit(6) and step["commit_before"] == commit(5)
    assert step["run_id"] == "run06-aaaa" and step["run_id_before"] == "run05-aaaa"
    assert step["ratio"] == pytest.approx(1.3, rel=0.03)
    assert step["before"] == pytest.approx(0.010, rel=0.03) and step["after"] == pytest.approx(0.013, rel=0.03)
    assert step["p_value"] < 0.05 and step["same_code"] is False
    assert doc["threshold"] == 0.10 and doc["alpha"] == 0.05


def test_a_step_between_runs_of_the_same_code_says_so(tmp_path):
    """Same clean commit on both sides: the step is the machine's, not the code's."""
    s = Store(tmp_path / "runs")
    for k in range(6):
        level = 0.010 if k < 3 else 0.014
        _file_run(s, k, FAST, f"2026-01-0{k + 1}T00:00:00+00:00", {("fortune", "uniform", 1000, 0): (level, {})},
                  seed=k, code=0 if k < 4 else 1)
    js = tmp_path / "c.json"
    assert main(["trend", str(tmp_path / "runs"), "-o", str(tmp_path / "t.html"), "--json", str(js)]) == 0
    [step] = json.loads(js.read_text())["change_points"]
    assert step["run_id"] == "run03-aaaa" and step["commit"] == step["commit_before"] == commit(0)
    assert step["same_code"] is True
    page = (tmp_path / "t.html").read_text(encoding="utf-8")
    assert "same code" in page
    # Four runs of commit 0 and two of commit 1: each has a label of its own on the x axis.
    from vorobench.harness.trend import load

    [machine] = load(s)
    labels = [r.label for r in machine.runs]
    assert len(set(labels)) == 6 and labels[1] == commit(0)[:7] + " #2" and labels[4] == commit(1)[:7]


def test_a_plugin_replacing_an_implementation_at_the_same_commit_is_other_code(tmp_path):
    """Same commit, but the implementation's code came from another module (a plugin registered
    under its name): the step is the code's, not the machine's."""
    s = Store(tmp_path / "runs")
    for k in range(6):
        level = 0.010 if k < 3 else 0.014
        _file_run(s, k, FAST, f"2026-01-0{k + 1}T00:00:00+00:00", {("fortune", "uniform", 1000, 0): (level, {})},
                  seed=k, code=0, module="impls.fortune" if k < 3 else "slowdown")
    js = tmp_path / "c.json"
    assert main(["trend", str(tmp_path / "runs"), "-o", str(tmp_path / "t.html"), "--json", str(js)]) == 0
    [step] = json.loads(js.read_text())["change_points"]
    assert step["run_id"] == "run03-aaaa" and step["same_code"] is False


def test_the_counter_change_is_found_exactly(outputs):
    _, doc = outputs
    changes = [c for c in doc["change_points"] if c["kind"] == "counter"]
    assert len(changes) == 1, changes
    change = changes[0]
    assert (change["machine_id"], change["impl"], change["n"], change["counter"]) == \
        (FAST, "fortune", 10000, "circle_events")
    assert (change["before"], change["after"]) == (35000, 35010)
    assert change["commit"] == commit(4) and change["commit_before"] == commit(3)


def test_machines_are_kept_apart(store, outputs):
    _, doc = outputs
    assert not [c for c in doc["change_points"] if c["machine_id"] == SLOW]
    assert sorted(m["machine_id"] for m in doc["machines"]) == [FAST, SLOW]
    machines = trend.load(Store(store))
    assert {m.machine_id: len(m.runs) for m in machines} == {FAST: 10, SLOW: 10}
    for m in machines:
        own = {r.run_id for r in m.runs}
        for series in m.series:
            assert {m.runs[i].run_id for i in series.timed} <= own


def test_the_page_is_self_contained_with_plotly_inlined_once(outputs):
    page, doc = outputs
    assert page.count(get_plotlyjs()[:200]) == 1
    assert not re.search(r"<script[^>]*\bsrc=", page)
    # nothing but the inlined bundle (whose unused geo maps name a CDN) refers to the network
    own = page.replace(get_plotlyjs(), "")
    assert "cdn.plot.ly" not in own and "https://" not in own and "http://" not in own
    # the change point table at the top names both commits of each change
    table = page[page.index("<table"):page.index("<nav")]
    assert f"{short(5)} &rarr; {short(6)}" in table and f"{short(3)} &rarr; {short(4)}" in table
    step = next(c for c in doc["change_points"] if c["kind"] == "time")
    assert f"{step['ratio']:.2f}" in table and "35000 &rarr; 35010" in table
    # the x axis shows commits (the dirty run marked), one section per machine
    assert f"{short(9)}+" in page
    assert FAST in page and SLOW in page and "host-aaaa" in page


def test_machine_prefix_keeps_one_machine(store, tmp_path):
    js = tmp_path / "c.json"
    assert main(["trend", str(store), "--machine", "bbbb", "-o", str(tmp_path / "t.html"), "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    assert [m["machine_id"] for m in doc["machines"]] == [SLOW] and doc["change_points"] == []
    assert FAST not in (tmp_path / "t.html").read_text(encoding="utf-8")


def test_impl_and_dataset_filters(store, tmp_path):
    js = tmp_path / "c.json"
    assert main(["trend", str(store), "--impls", "qhull", "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    assert doc["change_points"] == [] and doc["series"] == 2            # qhull grid 1000 on two machines
    assert main(["trend", str(store), "--datasets", "uniform", "--machine", FAST, "--json", str(js)]) == 0
    doc = json.loads(js.read_text())
    assert {c["impl"] for c in doc["change_points"]} == {"fortune"} and doc["series"] == 2


@pytest.mark.parametrize("args, message", [
    (["--impls", "nosuch"], "no results"),
    (["--machine", "cccc"], "no run"),
])
def test_filters_that_match_nothing_fail_in_one_line(store, tmp_path, capsys, args, message):
    assert main(["trend", str(store), "-o", str(tmp_path / "t.html"), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and message in err
    assert not (tmp_path / "t.html").exists()


def test_not_a_store_or_an_empty_one_fails_in_one_line(tmp_path, capsys):
    assert main(["trend", str(tmp_path), "-o", str(tmp_path / "t.html")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "no run store" in err
    (tmp_path / "empty").mkdir()
    (tmp_path / "empty" / "runs.sqlite").touch()
    assert main(["trend", str(tmp_path / "empty"), "-o", str(tmp_path / "t.html")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "no run" in err


def test_an_output_is_required(store, capsys):
    assert main(["trend", str(store)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "-o" in err and "--json" in err


def test_names_are_escaped(tmp_path):
    s = Store(tmp_path / "runs")
    evil_impl, evil_dataset = "<img src=x onerror=alert(1)>", "</script><script>alert(2)</script>"
    for k in range(3):
        _file_run(s, k, FAST, f"2026-01-0{k + 1}T00:00:00+00:00", {(evil_impl, evil_dataset, 10, 0): (0.001, {})})
    assert main(["trend", str(tmp_path / "runs"), "-o", str(tmp_path / "t.html")]) == 0
    page = (tmp_path / "t.html").read_text(encoding="utf-8")
    assert evil_impl not in page and evil_dataset not in page
    assert "&lt;img src=x onerror=alert(1)&gt;" in page


def test_compare_and_trend_give_one_answer_for_every_case_of_a_shared_store(tmp_path, capsys):
    """One rule decides (vorobench.harness.timing_rule): for two runs in a store, trend marks a
    step exactly where compare calls the case slower or faster, in the same direction. Ten
    steady cases move by up to +-35 % between the runs (a busy machine: wide run-to-run noise,
    tight repeats), so a 1.5x step with tight repeats is inconclusive in both (trend used to
    draw it as a step while compare said inconclusive); 3x and 0.3x steps are beyond the noise."""
    rng = np.random.default_rng(7)
    s = Store(tmp_path / "runs")
    steps = {("fortune", "uniform", 1000 * (i + 1), 0): 1.0 + rng.uniform(-0.35, 0.35) for i in range(10)}
    steps[("qhull", "grid", 1000, 0)] = 3.0
    steps[("qhull", "grid", 2000, 0)] = 0.3
    steps[("qhull", "grid", 4000, 0)] = 1.5
    for k in range(2):
        rows = []
        for (impl, dataset, n, seed), step in steps.items():
            level = 0.01 * n / 1000 * (step if k else 1.0)
            for r in range(5):
                rows.append({"run_id": f"r{k}", "impl": impl, "dataset": dataset, "n": n, "seed": seed,
                             "repeat": r, "status": "ok", "verdict": "exact",
                             "time_s": level * (1 + rng.uniform(-0.01, 0.01))})
        meta = {"run_id": f"r{k}", "date": f"2026-03-0{k + 1}T00:00:00+00:00", "commit": commit(k),
                "dirty": False, "machine_id": FAST, "hostname": "h", "cpu": "c"}
        assert s.add_run(pd.DataFrame(rows), meta)
    js = tmp_path / "c.json"
    assert main(["compare", f"{s.path}@latest~1", f"{s.path}@latest", "--json", str(tmp_path / "cmp.json")]) == 1
    compared = {(c["impl"], c["dataset"], c["n"]): c["change"]
                for c in json.loads((tmp_path / "cmp.json").read_text())["cases"]}
    assert main(["trend", str(s.path), "--json", str(js)]) == 0
    stepped = {(p["impl"], p["dataset"], p["n"]): ("slower" if p["ratio"] > 1 else "faster")
               for p in json.loads(js.read_text())["change_points"] if p["kind"] == "time"}
    capsys.readouterr()
    assert compared[("qhull", "grid", 1000)] == "slower" and compared[("qhull", "grid", 2000)] == "faster"
    assert compared[("qhull", "grid", 4000)] == "inconclusive"
    for case, change in compared.items():
        assert stepped.get(case) == (change if change in ("slower", "faster") else None), (case, change, stepped)
