"""Closed-form stick-slip (seed 003 eqs. 2-3, 2-8, 2-16 to 2-19): exact limits and invariants."""

import numpy as np
import pytest
import xarray as xr
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from faultslip.dynamics.spring_slider import closed_form as cf
from faultslip.dynamics.spring_slider.slider import SliderSystem

W, K = 1000.0, 3.4e6
mu_m_st = st.floats(0.05, 0.8)
drop_st = st.floats(1e-4, 0.4)
b_st = st.floats(1e-3, 1e4)
d_st = st.floats(0.2, 2.0)
rate_st = st.floats(1e-12, 1e3)
zeta_st = st.floats(0.0, 0.6)


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.2, 0.45])
def test_amplitude_sign_from_direct_integration_of_the_half_cycle(zeta):
    """Eq. 2-15 => alpha = (W/K)(mu_s - mu_m)(1 + exp(-lambda pi)): the plus sign of eq. 2-19.

    Seed eq. 2-17 prints a minus sign; that would give zero amplitude at zeta = 0.
    """
    mass, mu_s, mu_m = 100.0, 0.6, 0.5
    dashpot = cf.dashpot_for_damping_ratio(zeta, K, mass)
    start = W * mu_s / K

    def at_rest(t, y):
        return y[1]

    solution = solve_ivp(
        lambda t, y: [y[1], (W * mu_m - K * y[0] - dashpot * y[1]) / mass],
        [0, 0.1], [start, 0.0], rtol=1e-12, atol=1e-16, events=at_rest,
    )
    stop = solution.y_events[0][solution.t_events[0] > 1e-9][0][0]
    expected = cf.slip_amplitude(W, K, mu_s - mu_m, zeta)
    assert start - stop == pytest.approx(expected, rel=1e-8)
    assert expected == pytest.approx(W / K * 0.1 * (1 + np.exp(-np.pi * zeta / np.sqrt(1 - zeta**2))))


def test_decay_parameter_and_slip_duration():
    assert cf.decay_parameter(0.0) == 0.0
    assert cf.decay_parameter(0.6) == pytest.approx(0.75)
    assert np.isnan(cf.decay_parameter(1.0))
    assert cf.slip_duration(4.0, 1.0, 0.0) == pytest.approx(np.pi / 2)


@given(mu_m=mu_m_st, drop=drop_st, b=b_st, d=d_st, rate=rate_st, factor=st.floats(1.01, 1e3), zeta=zeta_st)
def test_amplitude_falls_monotonically_as_loading_rate_rises(mu_m, drop, b, d, rate, factor, zeta):
    low = cf.rate_law_amplitude(rate, W, K, mu_m + drop, mu_m, b, d, zeta)
    high = cf.rate_law_amplitude(rate * factor, W, K, mu_m + drop, mu_m, b, d, zeta)
    assert 0 <= high <= low


@given(mu_m=mu_m_st, drop=drop_st, b=b_st, d=d_st)
def test_amplitude_tends_to_twice_w_over_k_drop_at_zero_rate_without_damping(mu_m, drop, b, d):
    limit = 2 * W / K * drop
    assert cf.rate_law_amplitude(0.0, W, K, mu_m + drop, mu_m, b, d, 0.0) == pytest.approx(limit, rel=1e-15)
    tiny = (1e-9 / (b * drop)) ** (1 / d)  # drop b theta^d = 1e-9
    assert cf.rate_law_amplitude(tiny, W, K, mu_m + drop, mu_m, b, d, 0.0) == pytest.approx(limit, rel=2e-9)
    assert cf.low_rate_amplitude(W, K, mu_m + drop, mu_m) == pytest.approx(limit)


@given(mu_m=mu_m_st, drop=drop_st, b=b_st, d=d_st)
def test_amplitude_tends_to_zero_at_infinite_rate(mu_m, drop, b, d):
    huge = (1e12 / (b * drop)) ** (1 / d)  # b theta^d = 1e12 / drop
    assert cf.rate_law_amplitude(huge, W, K, mu_m + drop, mu_m, b, d, 0.0) < 2 * W / K * 1e-12 * 1.001


@given(mu=mu_m_st, b=b_st, d=d_st, rate=rate_st, zeta=zeta_st)
def test_amplitude_is_zero_when_static_equals_kinetic(mu, b, d, rate, zeta):
    assert cf.rate_law_amplitude(rate, W, K, mu, mu, b, d, zeta) == 0.0


@given(mu_m=mu_m_st, drop=drop_st, b=b_st, d=d_st, rate=rate_st, scale=st.floats(1e-3, 1e3), zeta=zeta_st)
def test_amplitude_is_linear_in_w_over_k(mu_m, drop, b, d, rate, scale, zeta):
    # scale W at fixed loading rate: alpha scales exactly with W/K
    base = cf.rate_law_amplitude(rate, W, K, mu_m + drop, mu_m, b, d, zeta)
    scaled = cf.rate_law_amplitude(rate, W * scale, K, mu_m + drop, mu_m, b, d, zeta)
    assert scaled == pytest.approx(base * scale, rel=1e-12)


def test_vectorised_over_numpy_and_xarray():
    rates = xr.DataArray(np.logspace(-4, 2, 7), dims="loading_rate")
    zeta = xr.DataArray([0.0, 0.1], dims="damping_ratio")
    alpha = cf.rate_law_amplitude(rates, W, K, 0.65, 0.55, 38.0, 0.665, zeta)
    assert set(alpha.dims) == {"loading_rate", "damping_ratio"} and alpha.shape == (7, 2)
    np.testing.assert_allclose(
        alpha.sel(damping_ratio=0).values if "damping_ratio" in alpha.coords else alpha.isel(damping_ratio=0).values,
        cf.rate_law_amplitude(rates.values, W, K, 0.65, 0.55, 38.0, 0.665, 0.0),
    )


def test_stick_duration_is_amplitude_over_speed_and_period_adds_slip():
    system = SliderSystem.from_preset("granodiorite_water", platform_speed="1e-4 in/s")
    cycle = cf.closed_form_cycle(system)
    assert cycle.stick_duration == pytest.approx(cycle.amplitude / system.platform_speed)
    assert cycle.slip_duration == pytest.approx(np.pi / system.natural_frequency)
    assert cycle.period == pytest.approx(cycle.stick_duration + cycle.slip_duration)
    assert cycle.stress_drop == pytest.approx(system.stiffness * cycle.amplitude)
    # loading rate theta_dot = K V / W (eq. 2-3)
    assert system.loading_rate == pytest.approx(system.stiffness * system.platform_speed / system.normal_load)


def test_peak_slip_speed_matches_an_undamped_half_cycle():
    system = SliderSystem.from_preset("glass_dry", platform_speed="1e-6 in/s")
    cycle = cf.closed_form_cycle(system)
    u0 = system.normal_load / system.stiffness * system.static_excess
    assert cycle.peak_slip_speed == pytest.approx(system.natural_frequency * u0)
