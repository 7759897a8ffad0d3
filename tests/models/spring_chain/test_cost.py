"""The chain's cost model counts the work an integrated run does: its slip sub-phases, by the exact closed form,
before the run (an integrator's cost is per sub-phase; events x blocks missed a 50-block chain's by 2.3x)."""

from __future__ import annotations

from pathlib import Path

import pytest

from faultslip.models.spring_chain import cost
from faultslip.models.spring_chain.dynamics import compiled_available, simulate_chain
from faultslip.models.spring_chain.scene import read_chain_scene

CONFIGS = Path(__file__).resolve().parents[3] / "configs"

needs_compiled = pytest.mark.skipif(not compiled_available(), reason="the compiled closed form was not built")


@needs_compiled
@pytest.mark.parametrize("scene, events", [("spring_chain_small.toml", 7), ("spring_chain.toml", 4)])
def test_the_count_is_the_integrated_runs_own(scene, events):
    loaded = read_chain_scene(CONFIGS / scene)
    counted, how = cost.subphases(loaded, events)
    run = simulate_chain(loaded.chain, events, initial_position=loaded.initial_position, slip_solver="RK45")
    assert counted == run.subphases
    assert "counted by the closed form" in how


@needs_compiled
def test_a_long_run_is_scaled_from_its_first_events(monkeypatch):
    loaded = read_chain_scene(CONFIGS / "spring_chain_small.toml")
    first = simulate_chain(loaded.chain, 6, initial_position=loaded.initial_position,
                           slip_solver="closed_form_compiled").subphases
    monkeypatch.setattr(cost, "COUNTED_EVENTS", 6)
    counted, how = cost.subphases(loaded, 600)
    assert counted == pytest.approx(first * 100)
    assert "over 6 events" in how


def test_without_the_compiled_form_it_says_it_did_not_count(monkeypatch):
    monkeypatch.setattr(cost, "compiled_available", lambda: False)
    loaded = read_chain_scene(CONFIGS / "spring_chain.toml")
    counted, how = cost.subphases(loaded, 10)
    assert counted == 10 * loaded.chain.blocks
    assert how.startswith("uncounted")


@pytest.mark.parametrize("solver", ["RK45", "DOP853", "Radau", "LSODA"])
def test_each_integrator_is_its_own_entry(solver):
    entry, units, what = cost.work(CONFIGS / "spring_chain_small.toml", "simulate", cycles=3, slip_solver=solver)
    assert entry == f"simulate:{solver}"
    assert units > 0 and "sub-phases" in what
    estimate = cost.estimate(CONFIGS / "spring_chain_small.toml", "simulate", cycles=3, slip_solver=solver)
    assert estimate.seconds > 0


def test_the_closed_form_counts_block_events():
    entry, units, _ = cost.work(CONFIGS / "spring_chain.toml", "simulate", cycles=10)
    assert (entry, units) == ("simulate", 500.0)


def test_the_closed_form_in_python_is_priced_as_itself(monkeypatch, cli):
    """Where the compiled loop was not built, auto runs the closed form in Python, about 160 times dearer a
    block-event; the estimate priced it as the compiled loop, so a run asked for a tolerance no chain meets
    (1e-300: a rerun at MOST_EVENTS events) was estimated at seconds and took about 15 minutes (found by the
    fuzzer, whose clone had not built the loop). Its own entries (run:closed_form, simulate:closed_form) price it,
    and the budget refuses that rerun in one sentence before it starts."""
    from faultslip.io import budget
    from faultslip.models.spring_chain import dynamics

    scene = CONFIGS / "spring_chain_small.toml"
    fitted = budget.family_costs()["families"]["spring_chain"]
    asked = cost.work(scene, "simulate", cycles=200, slip_solver="closed_form")
    assert asked[0] == "simulate:closed_form" and "in Python)" in asked[2]
    assert fitted["simulate:closed_form"]["seconds_per_unit"] > 50 * fitted["simulate"]["seconds_per_unit"]
    monkeypatch.setattr(dynamics, "_chain", None)
    for action in ("run", "simulate"):
        entry, units, what = cost.work(scene, action, cycles=200)
        assert entry == f"{action}:closed_form" and "the compiled loop is not built" in what
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", "15")
    out = cli("run", scene, "--tolerance", "1e-300")
    assert out.code == 2 and "100,000 events" in out.err and "--allow-large" in out.err, out.err
