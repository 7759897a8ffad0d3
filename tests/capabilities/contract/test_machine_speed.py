"""Estimates follow the machine (faultslip.io.machine): every family's cost model is scaled by the reference work's
time now over its time where the group's constants were anchored (benchmarks/machine_speed.py)."""

from __future__ import annotations

import json
import math
import statistics
from pathlib import Path

import pytest

from conftest import assert_clean_error, load_benchmark
from faultslip import models
from faultslip.errors import InputError
from faultslip.io import machine
from faultslip.io.resources import read_bundled_table

from test_models import CONFIGS, SCENES

ROOT = Path(__file__).resolve().parents[3]


@pytest.mark.parametrize("family", sorted(SCENES))
@pytest.mark.parametrize("action", ["run", "simulate"])
def test_every_familys_estimate_follows_the_machine(family, action, monkeypatch):
    """A machine twice as slow doubles every family's estimated CPU time, run and simulation, through the contract
    (models.estimate), and leaves its memory and disk alone."""
    scene = CONFIGS / SCENES[family]
    monkeypatch.setenv(machine.ENVIRONMENT, "1")
    anchored = models.estimate(scene, action)
    monkeypatch.setenv(machine.ENVIRONMENT, "2")
    slower = models.estimate(scene, action)
    # the cost model's seconds, without the imports the first estimate measured (this machine's CPU already)
    modelled, modelled_slower = anchored.modelled_seconds, slower.modelled_seconds
    assert modelled > 0
    assert modelled_slower == pytest.approx(2 * modelled, rel=1e-12)
    assert (slower.memory, slower.disk) == (anchored.memory, anchored.disk)


def test_the_factor_is_the_reference_work_now_over_each_groups_anchor(monkeypatch):
    """Unset, the factor is the probe's time now over the group's anchored time; the probe is measured once a
    process (and again after its lifetime), on this thread."""
    monkeypatch.delenv(machine.ENVIRONMENT, raising=False)
    anchors = machine.references()
    for group, seconds in anchors.items():
        monkeypatch.setattr(machine, "reference_now", lambda seconds=seconds: 3.0 * seconds)
        assert machine.factor(group) == pytest.approx(3.0, rel=1e-12)
    assert set(anchors) == set(machine.GROUPS)
    with pytest.raises(ValueError, match="unknown cost group"):
        machine.factor("fault_4d")


def test_the_probe_is_measured_once_and_says_what_it_scaled(monkeypatch):
    monkeypatch.delenv(machine.ENVIRONMENT, raising=False)
    monkeypatch.setattr(machine, "_probe", {})
    calls = []
    monkeypatch.setattr(machine, "probe_seconds", lambda: calls.append(1) or 1e-3)
    assert machine.reference_now() == machine.reference_now() == 1e-3
    assert len(calls) == 1
    assert "reference work took 1 ms" in machine.describe()
    assert machine.on_this_machine(0.0, "families") == 0.0
    # the work itself: a positive, finite CPU time
    seconds = machine.reference_work(size=256, rounds=2)
    assert math.isfinite(seconds) and seconds >= 0.0


def test_an_estimate_says_how_it_was_scaled(monkeypatch):
    monkeypatch.setenv(machine.ENVIRONMENT, "1.5")
    report = models.estimate(CONFIGS / "fault_2d_small.toml").report()
    assert any("scaled by 1.5" in note for note in report.notes)


@pytest.mark.parametrize("text", ["fast", "0", "-1", "nan", "inf", "1e9", ""])
def test_a_bad_factor_is_one_sentence(text, monkeypatch, cli):
    monkeypatch.setenv(machine.ENVIRONMENT, text)
    with pytest.raises(InputError, match="FAULTSLIP_MACHINE_FACTOR"):
        machine.factor("families")
    assert_clean_error(cli("run", CONFIGS / "fault_2d_small.toml", "--estimate"), "FAULTSLIP_MACHINE_FACTOR")


def test_the_reference_is_what_its_benchmark_measured():
    """data/machine_reference.json is benchmarks/results/machine_speed.json's runs, recomputed: each group's
    reference is the median probe times the median of CPU then / now over its runs; and each run's "then" is what
    its fit's results file holds as it stands (a refit without rerunning machine_speed.py fails here)."""
    speed = load_benchmark("machine_speed")
    shipped = read_bundled_table(machine.REFERENCE_FILE, "reference", "benchmarks/machine_speed.py")["groups"]
    record = json.loads((ROOT / "benchmarks" / "results" / "machine_speed.json").read_text(encoding="utf-8"))
    for group in machine.GROUPS:
        runs = record["groups"][group]["runs"]
        assert len(runs) >= 3, group
        ratio = statistics.median(run["then"] / run["now"] for run in runs)
        probe = statistics.median(record["groups"][group]["probe_now_seconds"])
        assert shipped[group]["reference_work_seconds"] == pytest.approx(probe * ratio, rel=1e-12)
        fitted = speed.recorded(group)
        for run in runs:
            assert run["then"] == pytest.approx(fitted[run["run"]], rel=1e-12), (group, run["run"])


def test_the_families_cost_table_is_its_benchmarks_fit_of_the_recorded_cases():
    """data/family_costs.json is benchmarks/family_costs.py's fit of the cases benchmarks/results/family_costs.json
    records (least squares in the log of estimate over CPU), not numbers typed or left from another fit, each entry
    measured or borrowed from a measured one; and its cases, fitted and held out, are estimated within 2x of their
    CPU, 95 % of them at least, and every one within 3x. In seconds, the fit had set a rough-surface Radau entry's
    overhead at 0.37 s, its cheapest runs estimated at 2.9x their CPU; a rough-surface run whose refinement check
    tightens its rtol costs up to three times its siblings, which no estimate made before the run can know."""
    costs = load_benchmark("family_costs")
    shipped = read_bundled_table("family_costs.json", "the families' cost models", "benchmarks/family_costs.py")
    rows = json.loads((ROOT / "benchmarks" / "results" / "family_costs.json").read_text(encoding="utf-8"))["rows"]
    for family, entries in shipped["families"].items():
        for entry, fitted in entries.items():
            if fitted.get("borrowed_from"):
                assert entries[fitted["borrowed_from"]]["fitted_on"], (family, entry)
                continue
            cases = [row for row in rows if (row["family"], row["entry"]) == (family, entry) and not row["held_out"]]
            assert sorted(row["case"] for row in cases) == sorted(fitted["fitted_on"]), (family, entry)
            # a settle's row holds the work its estimate models; the fit took the work measured
            refit = costs.fit([{**row, "units": row.get("units_measured", row["units"])} for row in cases])
            for key in ("overhead", "seconds_per_unit"):
                assert fitted[key] == pytest.approx(refit[key], rel=1e-6, abs=1e-12), (family, entry, key)
    ratios = [row["ratio"] for row in rows]
    assert sum(0.5 <= ratio <= 2.0 for ratio in ratios) >= 0.95 * len(ratios)
    for row in rows:
        assert 1 / 3 <= row["ratio"] <= 3.0, row["case"]
