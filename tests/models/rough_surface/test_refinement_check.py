"""An event-driven run on a kinetic law the integrators' calibration never drew declares what a finer run shows.

The calibration (benchmarks/event_driven_calibration.py) drew seed 003's laws. On fresh rough-surface scenes (seed
000's tabulated law, kinks at its knots; stress drops a fifth of the slip) the calibrated error was exceeded, up
to 130 times on the stress drop (benchmarks/refinement_check.py). Such a run is now checked against one at a
hundredth of its rtol (faultslip.dynamics.methods.refinement_check).
"""

import math
from dataclasses import replace

import pytest
from hypothesis import given, settings, strategies as st

from faultslip import contract
from faultslip.contract.registry import read_scene
from faultslip.dynamics import methods
from faultslip.dynamics.shared.cycle import CycleResult
from faultslip.friction.laws import CallableKinetic, LinearKinetic, PolynomialKinetic
from faultslip.models.rough_surface.scene import read_rough_scene

#: Seed 20261207's draw 15 of the rough-surface probe: three parameters of the example moved (the draw that first
#: showed a miss: RK45 at tolerance 1e-3 was 1.6 times its declared error off, on the stress drop).
FRESH = {"hardness": 2.346e9, "mass": 0.4194, "normal_load": 32.17}


def _fresh_system():
    base = read_scene(contract.families()["rough_surface"].example.scene)[0]
    system, _, found = read_rough_scene(base.with_values(**FRESH))
    return system, found["cycles"]


def _largest_error(cycle, reference):
    return max(abs(getattr(cycle, name) / getattr(reference, name) - 1) for name in methods.CHECKED_OUTPUTS)


def test_only_the_laws_the_calibration_drew_are_held_to_it():
    system, _ = _fresh_system()
    assert not system.error_calibrated  # a rough-surface table
    assert LinearKinetic(0.3, 0.01).error_calibrated and PolynomialKinetic((0.3, -0.1, 0.2)).error_calibrated
    assert not CallableKinetic(lambda u: 0.3 + 0 * u).error_calibrated
    assert system.with_(kinetic_law=LinearKinetic(0.25, 0.0)).error_calibrated


@pytest.mark.filterwarnings("ignore")
def test_a_fresh_rough_surface_run_is_within_what_it_declares_and_was_not_before(monkeypatch):
    """RK45 at tolerance 1e-5 (rtol 1e-6): the stress drop is 2.3 times the calibrated 2.2e-6 off (it was 2.0 times
    5.3e-6 before the slip was integrated about its equilibrium and RK45 refitted). The check finds 4.9e-6 to rtol
    1e-8, past the tolerance, and takes rtol 1e-8, checked in turn; the run is within what it declares."""
    system, cycles = _fresh_system()
    reference = methods.solve(system, method="event_driven_DOP853", tolerance=1e-11, cycles=cycles)
    assert reference.estimated_relative_error < 1e-9
    checked = methods.solve(system, method="event_driven_RK45", tolerance=1e-5, cycles=cycles)
    assert "checked against rtol" in checked.method_reason
    assert _largest_error(checked.cycle, reference.cycle) <= checked.estimated_relative_error <= 1e-5
    # without the check, the same run declares its calibrated error, which it exceeds (the test can fail)
    monkeypatch.setattr(methods, "refinement_check",
                        lambda chosen, system, outputs, tolerance, cycles, settings, run, error, reason:
                        (*run, error, reason, settings))
    before = methods.solve(system, method="event_driven_RK45", tolerance=1e-5, cycles=cycles)
    assert _largest_error(before.cycle, reference.cycle) > 1.5 * before.estimated_relative_error


@pytest.mark.filterwarnings("ignore")
def test_a_tolerance_the_first_run_misses_is_met_by_a_finer_rtol():
    """Auto at 1e-4 takes DOP853 at rtol 1e-5 (its declared 2e-5 meets it), which the check finds 1.6e-4 from rtol
    1e-7: the finer run is taken and checked in turn, and meets the tolerance. (Before the slip was integrated about
    its equilibrium, RK45 at 1e-3 had missed so; it now meets that tolerance at its first rtol.)"""
    system, cycles = _fresh_system()
    solution = methods.solve(system, tolerance=1e-4, cycles=cycles)
    assert solution.estimated_relative_error <= 1e-4
    assert solution.settings["rtol"] < 1e-5 and "past the tolerance" in solution.method_reason


def _cycle(**values):
    base = dict(method="m", regime="stick_slip", loading_rate=1.0, platform_speed=0.01, static_friction=0.3,
                damping_ratio=0.0, dimensionless_rate=math.nan, amplitude=1e-4, slip_per_event=4e-4,
                stick_duration=0.01, slip_duration=0.03, period=0.04, peak_slip_speed=0.02, stress_drop=1.0,
                scale=1.0, stress_drop_slip=1e-4 / 1.3)
    return CycleResult(**{**base, **values})


@settings(max_examples=200, deadline=None)
@given(st.floats(-0.5, 0.5), st.sampled_from(methods.CHECKED_OUTPUTS))
def test_the_difference_is_the_relative_change_of_the_output_that_moved(change, name):
    coarse = _cycle()
    fine = replace(coarse, **{name: getattr(coarse, name) * (1 + change)})
    difference, graze = methods.refinement_difference(coarse, fine)
    assert graze is None
    assert difference == pytest.approx(abs(change) / (1 + change), rel=1e-9, abs=1e-15)


def test_a_grazes_stress_drop_has_no_relative_error_and_is_said_in_newtons():
    """Seed 000 at c = 0 grazes a stick once a period: its stress drop is zero, 1e-11 N at one rtol and 1e-5 N at
    another. The drops are compared in newtons, and the other outputs still relatively."""
    coarse = _cycle(stress_drop=1.3e-11, stress_drop_slip=1e-15)
    fine = _cycle(stress_drop=1.3e-5, stress_drop_slip=1e-9, period=0.04 * (1 + 1e-7))
    difference, graze = methods.refinement_difference(coarse, fine)
    assert graze == pytest.approx(1.3e-5, rel=1e-3)
    assert difference == pytest.approx(1e-7, rel=1e-3)
    # a drop above a thousandth of the swing is no graze: its relative difference counts
    difference, graze = methods.refinement_difference(_cycle(), _cycle(stress_drop=1.1))
    assert graze is None and difference == pytest.approx(0.1 / 1.1)


def test_a_missing_output_in_one_run_is_an_unbounded_difference():
    difference, _ = methods.refinement_difference(_cycle(), _cycle(period=math.nan))
    assert difference == math.inf


@pytest.mark.filterwarnings("ignore")
def test_a_grazing_run_says_its_stress_drop_is_zero_within_newtons_and_keeps_its_relative_error():
    base = read_scene(contract.families()["rough_surface"].example.scene)[0]
    system, _, found = read_rough_scene(base.with_values(separation_coefficient=0.0))
    solution = methods.solve(system, method="event_driven_DOP853", tolerance=1e-6, cycles=found["cycles"])
    assert "its stress drop is a graze" in solution.method_reason and " N, with no relative error" in \
        solution.method_reason
    assert solution.estimated_relative_error <= 1e-6
