"""The seed-law slider's simulation estimate where the slip phase is stiff, and the evaluation cap behind it.

The fuzzer (seed 40219) mutated configs/lab_steel_dry_polynomial.toml to a platform speed of 100 m/s: the
simulation was estimated at 7 ms (2.5 ms a cycle, whatever the stiffness) and DOP853 took 65 s, stepping a slip
phase of eps ~ 1.7e4 at its stability limit for the 200 natural periods of simulate's horizon.
"""

import json
import math
from pathlib import Path

import pytest
from conftest import assert_clean_error

import faultslip
from faultslip import models
from faultslip.dynamics import methods
from faultslip.errors import EvaluationBudgetError
from faultslip.io import machine
from faultslip.io.budget import Estimate
from faultslip.models.spring_slider import cost

ROOT = Path(__file__).resolve().parents[3]
SCENE = ROOT / "configs" / "lab_steel_dry_polynomial.toml"


def _at_speed(tmp_path, speed: str) -> Path:
    text = SCENE.read_text(encoding="utf-8")
    line = next(line for line in text.splitlines() if line.split("=")[0].strip() == "platform_speed")
    path = tmp_path / f"polynomial_{speed.split()[0]}.toml"
    path.write_text(text.replace(line, f'platform_speed = "{speed}"'), encoding="utf-8")
    return path


def test_an_explicit_solver_on_a_stiff_slip_phase_is_estimated_by_its_stability(tmp_path):
    """DOP853's steps on a stiff phase number stages x 2 pi x eps / 6.0 a natural period (Hairer & Wanner IV.2):
    the estimate grows as eps, an implicit solver's does not, and the ratio of the two is the stiff steps'."""
    slow, mild = _at_speed(tmp_path, "100 m/s"), _at_speed(tmp_path, "0.01 m/s")
    eps = methods.slip_stiffness(faultslip.models.read_slider_scene(slow).slider())
    assert eps > 1e4
    explicit = models.estimate(slow, "simulate", cycles=3, slip_solver="DOP853").seconds
    implicit = models.estimate(slow, "simulate", cycles=3, slip_solver="LSODA").seconds
    # (3 cycles + the 200-period horizon) x 12 stages x 2 pi eps / 6.0 evaluations over LSODA's accurate steps
    stiff = machine.on_this_machine((3 + cost.HORIZON_PERIODS) * 12 * 2 * math.pi * eps / 6.0 * 2.0e-5, "families")
    assert stiff <= explicit <= 1.01 * stiff + implicit
    assert explicit > 100 * models.estimate(mild, "simulate", cycles=3, slip_solver="DOP853").seconds
    # RK23 is explicit too (3 stages, stability limit 2.5): it is not priced as an implicit solver
    assert models.estimate(slow, "simulate", cycles=3, slip_solver="RK23").seconds > 100 * implicit


def test_the_fuzzed_scene_is_refused_before_it_runs(cli, tmp_path, monkeypatch):
    """The fuzzer's case, with its budget (a quarter of its 60 s timeout): one sentence naming the override."""
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", "15")
    result = cli("simulate", _at_speed(tmp_path, "100 m/s"), "--cycles", "3", "--slip-solver", "DOP853")
    assert_clean_error(result, "allow-large")


def test_a_simulation_past_the_budgets_evaluations_stops_and_names_the_implicit_solvers(tmp_path, monkeypatch):
    """Where the estimate were wrong, the run still stops at the evaluations the budget affords (as run's
    event-driven method does), and says which solvers step a stiff phase cheaply."""
    monkeypatch.setattr(cost, "simulation_estimate", lambda *args, **kwargs: Estimate(what="x", seconds=0.0))
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", "0.2")  # 10,000 DOP853 evaluations; the run takes 290,000
    with pytest.raises(EvaluationBudgetError, match="LSODA.*allow-large"):
        faultslip.simulate(_at_speed(tmp_path, "1 m/s"), cycles=3, slip_solver="DOP853")


def test_the_estimate_bounds_the_cpu_the_benchmark_measured():
    """benchmarks/slider_simulation_cost.py (results file): no run of the shipped law or of the two held-out ones
    (a quadratic and a cubic in m/s, each breaking away into slip), at eps up to ~5e3, by DOP853, RK45 or LSODA,
    used more CPU than its estimate (lowest estimated / CPU 1.0); the shipped law's stiff explicit runs are within 10x of it. It is an upper
    bound, not a fit: a run that re-sticks in milliseconds is still estimated with one phase to the horizon, which
    swings for up to the whole horizon where the motion about steady sliding is lightly damped (~75x over at
    0.01 m/s). Before the phase's decay was counted, lightly damped phases that slid had used up to 4x the
    estimate."""
    result = json.loads((ROOT / "benchmarks" / "results" / "slider_simulation_cost.json").read_text())
    rows = result["rows"]
    assert len(rows) >= 90 and {row["solver"] for row in rows} == {"DOP853", "RK45", "LSODA"}
    assert {row["law"] for row in rows} == {"shipped", "held out, quadratic", "held out, cubic"}
    assert max(row["eps"] for row in rows) > 1e3
    assert sum(row["events"] < row["cycles"] for row in rows) >= 60  # most end sliding: the horizon term is tried
    # measured: none under 1.0; 0.8 leaves a rerun's CPU noise room without letting an under-estimate through
    assert all(row["ratio"] >= 0.8 for row in rows), [row for row in rows if row["ratio"] < 0.8]
    stiff = [row for row in rows if row["law"] == "shipped" and row["solver"] != "LSODA" and row["eps"] > 100]
    assert len(stiff) >= 16 and all(1 <= row["ratio"] <= 10 for row in stiff)
