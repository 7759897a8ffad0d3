"""Exact stick-slip cycles: analytic slip phase against integration, limits, regimes, the closed form's order."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from faultslip.closed_form import closed_form_cycle, overshoot_factor
from faultslip.errors import MethodError
from faultslip.exact_cycle import exact_cycle, exact_cycle_arrays, slip_cycle
from faultslip.friction import PolynomialKinetic
from faultslip.slider import SliderSystem


def _integrate(zeta, eps):
    """Brute-force reference: integrate U'' + 2 zeta U' + U = 0 from (1 - 2 zeta eps, eps) to U' = eps."""
    def end(s, y):
        return y[1] - eps
    end.terminal, end.direction = True, 1
    sol = solve_ivp(lambda s, y: [y[1], -2 * zeta * y[1] - y[0]], [0, 60], [1 - 2 * zeta * eps, eps],
                    rtol=1e-13, atol=1e-15, events=end, dense_output=True)
    if sol.t_events[0].size == 0:
        return None
    s_end = sol.t_events[0][0]
    u = sol.sol(np.linspace(0, s_end, 100001))[0]
    return s_end, sol.y_events[0][0][0], u.max() - u.min()


@pytest.mark.parametrize("zeta, eps", [(0.0, 0.01), (0.0, 1.0), (0.05, 0.1), (0.3, 0.2), (-0.05, 0.3), (0.6, 0.02)])
def test_analytic_slip_phase_matches_brute_force_integration(zeta, eps):
    s_end, u_end, amplitude = _integrate(zeta, eps)
    cycle = slip_cycle(zeta, eps)
    assert cycle["slip_time"] == pytest.approx(s_end, rel=1e-10)
    assert cycle["u_end"] == pytest.approx(u_end, rel=1e-9, abs=1e-12)
    assert cycle["u_max"] - cycle["u_min"] == pytest.approx(amplitude, rel=1e-8)


def test_steady_sliding_is_detected_where_integration_never_returns():
    assert _integrate(0.2, 0.5) is None
    assert slip_cycle(0.2, 0.5)["regime"] == 1 and np.isnan(slip_cycle(0.2, 0.5)["slip_time"])


@given(eps=st.floats(1e-6, 50))
def test_undamped_cycle_is_a_circle_in_the_phase_plane(eps):
    """zeta = 0: energy is conserved, so the swing is 2 sqrt(1 + eps^2) and slip ends at -1."""
    cycle = slip_cycle(0.0, eps)
    assert cycle["regime"] == 0
    assert cycle["u_max"] - cycle["u_min"] == pytest.approx(2 * np.sqrt(1 + eps**2), rel=1e-12)
    assert cycle["u_end"] == pytest.approx(-1.0, rel=1e-10)


@pytest.mark.parametrize("zeta", [0.05, 0.2])
def test_closed_form_error_is_first_order_with_damping(zeta):
    """Closed form / exact - 1 -> 2 zeta eps as eps -> 0 (the CV term and the phase shift it neglects)."""
    ratios = []
    for eps in (1e-3, 1e-4, 1e-5):
        cycle = slip_cycle(zeta, eps)
        error = overshoot_factor(zeta) / float(cycle["u_max"] - cycle["u_min"]) - 1
        ratios.append(error / (2 * zeta * eps))
    assert ratios[-1] == pytest.approx(1.0, abs=1e-4)
    assert abs(ratios[-1] - 1) < abs(ratios[0] - 1)  # converging


def test_closed_form_error_is_second_order_without_damping():
    """zeta = 0: closed form / exact - 1 = 1/sqrt(1 + eps^2) - 1 -> -eps^2/2."""
    for eps in (1e-2, 1e-3, 1e-4):
        cycle = slip_cycle(0.0, eps)
        error = 2.0 / float(cycle["u_max"] - cycle["u_min"]) - 1
        assert error / (-(eps**2) / 2) == pytest.approx(1.0, abs=eps**2)


def test_closed_form_agrees_with_exact_at_low_rate_on_a_preset():
    system = SliderSystem.from_preset("granodiorite_water", loading_rate="1e-5 1/s", damping_ratio=0.05)
    exact, closed = exact_cycle(system), closed_form_cycle(system)
    eps = exact.dimensionless_rate
    assert closed.amplitude / exact.amplitude - 1 == pytest.approx(2 * 0.05 * eps, rel=1e-3)
    assert closed.period == pytest.approx(exact.period, rel=5 * eps)


def test_closed_form_is_wrong_near_the_critical_rate_and_warns_above_it():
    from faultslip.critical import critical
    from faultslip.errors import OutOfDomainWarning

    system = SliderSystem.from_preset("glass_dry", loading_rate="1 1/s", damping_ratio=0.05)
    theta_c = critical(system).critical_loading_rate
    near = system.at_loading_rate(0.9 * theta_c)
    error = closed_form_cycle(near).amplitude / exact_cycle(near).amplitude - 1
    assert abs(error) > 0.10, error  # measured: the closed form is off by more than 10 % at 0.9 theta_c
    above = system.at_loading_rate(1.2 * theta_c)
    assert exact_cycle(above).regime == "steady_sliding"
    with pytest.warns(OutOfDomainWarning, match="steady sliding"):
        assert closed_form_cycle(above).regime == "stick_slip"  # the wrong regime, flagged


def test_negative_damping_is_a_growing_oscillation_that_still_sticks():
    system = SliderSystem.from_preset("steel_dry", loading_rate="0.01 1/s", kinetic_slope="-5 s/m")
    assert system.damping_ratio < 0
    cycle = exact_cycle(system)
    assert cycle.regime == "growing_oscillation"
    assert cycle.amplitude > closed_form_cycle(system.with_(kinetic_law=system.kinetic_law.__class__(system.mu_m, 0.0))).amplitude


def test_vectorised_over_parameter_arrays():
    rates = np.logspace(-4, 0, 5)[:, None]
    zeta = np.array([0.0, 0.05, 0.2])[None, :]
    out = exact_cycle_arrays(rates, 1000.0, 3.4e6, 100.0, 0.1, zeta)
    assert out["amplitude"].shape == (5, 3) and out["regime"].shape == (5, 3)
    single = exact_cycle_arrays(rates[2, 0], 1000.0, 3.4e6, 100.0, 0.1, zeta[0, 1])
    assert out["amplitude"][2, 1] == pytest.approx(float(single["amplitude"]), rel=1e-14)


def test_period_stick_and_slip_relations():
    system = SliderSystem.from_preset("pyrite_dry", loading_rate="0.01 1/s", damping_ratio=0.1)
    c = exact_cycle(system)
    assert c.period == pytest.approx(c.stick_duration + c.slip_duration)
    assert c.slip_per_event == pytest.approx(system.platform_speed * c.period)
    assert c.stress_drop == pytest.approx(system.stiffness * system.platform_speed * c.stick_duration, rel=1e-12)


def test_exact_cycle_refuses_what_it_cannot_do():
    system = SliderSystem.from_preset("steel_dry", loading_rate="0.01 1/s")
    with pytest.raises(MethodError, match="not linear"):
        exact_cycle(system.with_(kinetic_law=PolynomialKinetic([0.39, -1.0, 30.0])))
    with pytest.raises(MethodError, match=r"\|zeta\| < 1"):
        slip_cycle(1.2, 0.1)
