"""Seed 001's toy model at its Hopf point: the normal form of the small cycle, its measured error, and the
subcritical case where steady sliding above A_c is stable to small disturbances only.

At A = 12 (the slides' model, 1.05e-6 % below A_c) LSODA had run 3059 cycles without settling and declared a
relative error of 47 beside a swing 50 times the small cycle's. A strongly charged model (f_ch = 0.05) loses
stability at a subcritical Hopf point: 1 % above A_c a tip started from rest stick-slips with a swing of 0.07
while linear stability said "steady sliding, swing 0, error 0"; 5 % above it the run from rest decayed, and the
settling test raised a math domain error on the vanishing oscillation.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from faultslip.errors import InputError
from faultslip.dynamics.shared.settling import Settling, assess_settling
from faultslip.models.nanoscale.dynamics import (HOPF_REFERENCE, NanoscaleModel, choose_method, damping_at_growth,
                                                 normal_form, settle)
from faultslip.models.nanoscale.hopf import (growth_rate, hopf_point, jacobian, normal_form_cycle, taylor_forms,
                                             weakening_derivatives)

#: a strongly charged model whose Hopf point is subcritical (l_1 > 0)
SUBCRITICAL = dict(charge_force=0.05, drive_speed=0.03, charging_time=5.0, charge_length=0.5)
#: a strongly charged model whose Hopf point is supercritical, with other v_a, tau and a than the slides'
CHARGED = dict(charge_force=0.3, drive_speed=0.015, charging_time=1.0, charge_length=2.0)

models = st.builds(NanoscaleModel, damping=st.floats(0.5, 20.0), drive_speed=st.floats(0.012, 0.06),
                   charging_time=st.floats(0.3, 10.0), charge_length=st.floats(0.3, 5.0),
                   charge_force=st.floats(0.0, 0.3))


def _at(model: NanoscaleModel, ratio: float) -> NanoscaleModel:
    """The model at the damping below A_c where sigma / omega_0 = ``ratio``."""
    return replace(model, damping=damping_at_growth(model, hopf_point(model), ratio))


@settings(max_examples=60, deadline=None)
@given(speed_ratio=st.floats(0.3, 6.0))
def test_the_weakening_law_s_derivatives_are_its_taylor_coefficients(speed_ratio):
    """phi', phi'', phi''' in closed form against central differences of phi itself."""
    model = NanoscaleModel(drive_speed=speed_ratio * 0.01)
    first, second, third = weakening_derivatives(model)
    u, h = model.drive_speed, 1e-4 * model.peak_speed
    phi = lambda x: float(model.weakening(x))  # noqa: E731
    assert first == pytest.approx((phi(u + h) - phi(u - h)) / (2 * h), rel=1e-5, abs=1e-6 / model.peak_speed)
    assert second == pytest.approx((phi(u + h) - 2 * phi(u) + phi(u - h)) / h ** 2, rel=1e-4,
                                   abs=1e-4 / model.peak_speed ** 2)
    assert third == pytest.approx((phi(u + 2 * h) - 2 * phi(u + h) + 2 * phi(u - h) - phi(u - 2 * h)) / (2 * h ** 3),
                                  rel=1e-3, abs=1e-2 / model.peak_speed ** 3)


@settings(max_examples=40, deadline=None)
@given(model=models)
def test_the_jacobian_s_characteristic_polynomial_is_the_module_s_cubic(model):
    """det(lambda - J) = lambda^3 + (c + d) lambda^2 + (1 + c d - g h) lambda + c: the same roots as the
    Routh-Hurwitz analysis that gives A_c."""
    assert np.sort_complex(np.linalg.eigvals(jacobian(model))) == pytest.approx(
        np.sort_complex(model.characteristic_roots()), rel=1e-7, abs=1e-9)


@settings(max_examples=30, deadline=None)
@given(model=models, direction=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3))
def test_the_quadratic_and_cubic_forms_are_the_equations_own_derivatives(model, direction):
    """B(x, x) and C(x, x, x) against second and third differences of the right-hand side the integrator runs
    (u, F, Sigma of eqs. 1, 2, 4), along a random direction about steady sliding."""
    x = np.array(direction) * np.array([0.1 * model.peak_speed, 1.0, 0.1])
    if not np.any(x):
        return
    rhs = model._rhs()
    steady = np.array([0.0, model.drive_speed, 0.0, model.steady_charge, 0.0])
    steady[2] = model.damping * model.drive_speed + float(model.weakening(model.drive_speed)) + \
        model.charge_force * model.steady_charge ** 2

    def f(step):
        state = steady.copy()
        state[[1, 2, 3]] += step * x
        out = np.asarray(rhs(0.0, state), float)
        return out[[1, 2, 3]]

    h = 1e-3
    quadratic, cubic = taylor_forms(model)
    second = (f(h) - 2 * f(0.0) + f(-h)) / h ** 2
    third = (f(2 * h) - 2 * f(h) + 2 * f(-h) - f(-2 * h)) / (2 * h ** 3)
    # differences of O(1) values: round-off eps |f| / h^2 and / h^3 (1e-10, 1e-7), and truncation O(h^2)
    assert np.allclose(second, quadratic(x, x), rtol=1e-3, atol=1e-6)
    assert np.allclose(third, cubic(x, x, x), rtol=2e-2, atol=1e-5)


def test_the_slides_model_and_a_charged_one_lose_stability_supercritically_and_a_third_subcritically():
    assert hopf_point(NanoscaleModel()).supercritical
    assert hopf_point(NanoscaleModel(**CHARGED)).supercritical
    assert not hopf_point(NanoscaleModel(**SUBCRITICAL)).supercritical


@pytest.mark.parametrize("parameters", [{}, CHARGED], ids=["slides", "charged"])
def test_the_normal_form_s_error_vanishes_as_sigma_at_the_hopf_point(parameters):
    """Against LSODA's settled cycle (rtol 1e-12) at sigma / omega_0 = 3e-3 and 1e-3 the normal form's errors in
    swing and period fall with sigma (O(sigma): a third, measured 0.33-0.34 for both models), and the cycle grows
    as sqrt(sigma). Nearer A_c LSODA's own settling error (its declared 2e-3 at 1e-4) exceeds the normal form's."""
    base = NanoscaleModel(**parameters)
    point = hopf_point(base)
    errors, periods, swings, sigmas = [], [], [], []
    for ratio in (3e-3, 1e-3):
        model = _at(base, ratio)
        cycle = model.settled_cycle(1e-10, rtol=1e-12, max_cycles=20000)
        assert cycle.settling.settled
        swing, period, least = normal_form_cycle(model, point)
        errors.append(abs(swing / cycle.force_swing - 1))
        periods.append(abs(period / cycle.period - 1))
        swings.append(cycle.force_swing)
        sigmas.append(growth_rate(model))
        assert least == pytest.approx(cycle.least_speed, rel=ratio)
    assert 0.25 < errors[1] / errors[0] < 0.42 and 0.25 < periods[1] / periods[0] < 0.42
    assert errors[0] < 2 * HOPF_REFERENCE
    assert swings[1] / swings[0] == pytest.approx(math.sqrt(sigmas[1] / sigmas[0]), rel=1.5 * errors[0])


@settings(max_examples=3, deadline=None)
@given(ratio=st.floats(1e-3, HOPF_REFERENCE), which=st.sampled_from([{}, CHARGED]))
def test_the_normal_form_s_declared_error_holds_against_a_tight_settled_cycle(ratio, which):
    """Within its domain the normal form's declared error (measured at the reference, scaled by sigma) bounds its
    actual error in swing, period and least speed, against LSODA settled to 1e-9 at rtol 1e-12 (from 1e-3 of
    A_c: nearer, LSODA's settling error approaches the normal form's; benchmarks/nanoscale_hopf_check.py measures
    14 random models there against LSODA at rtol 1e-12: 0.29-0.54 of the declared error)."""
    model = _at(NanoscaleModel(**which), ratio)
    cycle, why = normal_form(model)
    assert cycle is not None, why
    truth = model.settled_cycle(1e-9, rtol=1e-12, max_cycles=20000)
    assert truth.settling.settled
    for ours, theirs in ((cycle.force_swing, truth.force_swing), (cycle.period, truth.period),
                         (cycle.least_speed, truth.least_speed)):
        assert abs(ours / theirs - 1) <= cycle.estimated_error, (ratio, ours, theirs, cycle.estimated_error)


def test_next_to_the_hopf_point_auto_answers_by_the_normal_form_within_the_tolerance():
    """At A = 12 (sigma = 6.3e-8) LSODA cannot settle; the normal form declares ~1e-7 and meets 1e-6. Its swing
    is the sqrt(sigma) law from LSODA's settled cycle at sigma / omega_0 = 3e-3, to that law's O(sigma) there
    (measured 3.3e-3)."""
    model = NanoscaleModel(damping=12.0)
    choice, cycle = settle(model, choose_method(model), 1e-6)
    assert choice.method == "nanoscale_hopf_normal_form" and cycle.hopf is not None
    assert cycle.estimated_error <= 1e-6 and choice.estimated_error == cycle.estimated_error
    farther = _at(NanoscaleModel(), 3e-3)
    settled = farther.settled_cycle(1e-8)
    expected = settled.force_swing * math.sqrt(growth_rate(model) / growth_rate(farther))
    assert cycle.force_swing == pytest.approx(expected, rel=1.5 * 1.1 * 3e-3)
    assert abs(cycle.force_swing / expected - 1) > 1e-3  # the law's O(sigma) is there, and the normal form is not it
    assert cycle.regime == "oscillating_sliding"


def test_auto_hands_over_to_lsoda_where_the_normal_form_declares_more_than_the_tolerance():
    model = _at(NanoscaleModel(), 1e-3)  # the normal form declares ~2e-3
    choice, cycle = settle(model, choose_method(model), 1e-6)
    assert choice.method == "nanoscale_LSODA" and "normal form declared" in choice.reason
    assert cycle.hopf is None and cycle.settling.settled


def test_the_normal_form_by_name_outside_its_reach_refuses_or_declares_what_it_measured():
    with pytest.raises(InputError, match="subcritical"):
        choose_method(NanoscaleModel(**SUBCRITICAL), method="nanoscale_hopf_normal_form")
    with pytest.raises(InputError, match="above it"):
        choose_method(NanoscaleModel(damping=13.0), method="nanoscale_hopf_normal_form")
    with pytest.raises(InputError, match="no time series"):
        choose_method(NanoscaleModel(damping=11.99), ("regime", "time_series"), "nanoscale_hopf_normal_form")
    model = NanoscaleModel(damping=3.0)  # a stick-slip cycle: far from the small one
    choice, cycle = settle(model, choose_method(model, method="nanoscale_hopf_normal_form"), 1e-6)
    truth = model.settled_cycle(1e-8)
    assert abs(cycle.force_swing / truth.force_swing - 1) <= cycle.estimated_error
    assert cycle.estimated_error > 0.5


def test_above_a_subcritical_hopf_point_a_tip_started_from_rest_is_integrated(cli, tmp_path):
    """1 % above A_c steady sliding is stable to small disturbances and a large stick-slip cycle coexists: from rest
    the tip sticks and slips. 5 % above it the run from rest decays to steady sliding: swing 0."""
    base = NanoscaleModel(**SUBCRITICAL)
    bistable = replace(base, damping=1.01 * base.critical_damping)
    assert not bistable.stick_slip and max(growth_rate(bistable), 0.0) == 0.0
    choice, cycle = settle(bistable, choose_method(bistable), 1e-6)
    assert choice.method == "nanoscale_LSODA" and "subcritical" in choice.reason
    assert cycle.regime == "stick_slip" and cycle.force_swing > 0.05
    decayed = replace(base, damping=1.05 * base.critical_damping)
    cycle = decayed.settled_cycle(1e-6)
    assert cycle.settling.settled and cycle.force_swing == 0.0 and cycle.regime == "steady_sliding"
    # by name, linear stability answers the regime to small disturbances and says what it cannot
    with pytest.raises(InputError, match="subcritical"):
        choose_method(bistable, method="nanoscale_linear_stability")
    scene = tmp_path / "bistable.toml"
    scene.write_text(f"""name = "charged"
[slider]
damping = {bistable.damping!r}
drive_speed = 0.03
[friction]
law = "nanoscale"
peak_speed = 0.01
charging_time = 5.0
charge_length = 0.5
charge_force = 0.05
""")
    closed = cli("run", str(scene), "--method", "nanoscale_linear_stability", "--json")
    assert closed.code == 0 and "force_swing" not in closed.json
    assert any("subcritical" in note for note in closed.json["notes"])
    ran = cli("run", str(scene), "--json")
    assert ran.code == 0 and ran.json["regime"].startswith("stick_slip (A >= A_c, from rest")


def test_a_vanishing_oscillation_or_a_zero_distance_never_breaks_the_settling_test():
    """A spiral whose envelope vanishes between two cycles, and a verdict with nothing left, give words, not a
    math domain error."""
    history = [[1.0, 5.0, 0.1], [0.5, 5.0, 0.1]] + [[0.5 * (-1) ** k * 0.0 + 1e-3, 5.0 + k, 0.1] for k in range(12)]
    verdict = assess_settling(history, 1e-6, (0.03, 0.0, 0.03), noise=1e-8)
    assert isinstance(verdict, Settling) and verdict.reason
    assert Settling(False, 5, 0.5, 0.0, np.zeros(3), "").cycles_to_settle(1e-6) == 0.0


def test_the_estimate_counts_the_cycle_a_run_or_simulation_will_find():
    """A simulation's estimate had counted a settled cycle only below A_c: above a subcritical A_c (integrated from
    rest) it left it out, and next to a supercritical one it counted LSODA's from rest, not the normal form's
    reference. auto's normal form expected to miss the tolerance counts LSODA at A too."""
    from faultslip.models.nanoscale import cost
    from faultslip.models.nanoscale.family import _cycle_estimate

    base = NanoscaleModel(**SUBCRITICAL)
    bistable = replace(base, damping=1.01 * base.critical_damping)
    assert _cycle_estimate(bistable, choose_method(bistable).method, 1e-6, True) is not None
    assert _cycle_estimate(NanoscaleModel(damping=13.0), "nanoscale_linear_stability", 1e-6, True) is None
    nearest = NanoscaleModel(damping=12.0)  # the normal form meets 1e-6: its reference alone
    alone = _cycle_estimate(nearest, choose_method(nearest).method, 1e-6, True)
    assert alone.seconds < cost.settle_estimate(nearest).seconds
    near = _at(NanoscaleModel(), 5e-4)  # it declares ~1e-3: LSODA runs too
    both = _cycle_estimate(near, choose_method(near).method, 1e-6, True)
    assert both.seconds > cost.settle_estimate(near).seconds and "at A" in both.what
