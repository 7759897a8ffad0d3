"""The critical loading rate: exact tangency, the seed's Appendix I formula, and where they disagree."""

import numpy as np
import pytest

from faultslip.dynamics.spring_slider.critical import (
    comparison_dataset,
    comparison_markdown,
    critical,
    critical_dimensionless_rate,
    seed_critical_loading_rate,
)
from faultslip.dynamics.spring_slider.exact_cycle import _Oscillator, exact_cycle
from faultslip.dynamics.spring_slider.slider import SliderSystem

PRESETS = ["steel_heavy_petrolatum", "glass_dry", "pyrite_dry", "granodiorite_water"]
ZETAS = [0.001, 0.01, 0.05, 0.2, 0.3]
# Exact theta_c (1/s) on the Table I apparatus, computed by faultslip (tangency of the exact slip
# trajectory; each verified below by the regime flipping from stick-slip to steady sliding across it).
EXACT = np.array([
    [2.330785170059, 1.333711972858, 0.862078936651, 0.507728011276, 0.397786463115],
    [0.47304319354, 0.29138495459, 0.199947921671, 0.12716742468, 0.10346681269],
    [0.612734174578, 0.284367960947, 0.156113828677, 0.075584006846, 0.054196093281],
    [10.033780820177, 4.849840305445, 2.737207386987, 1.360530233763, 0.983867311353],
])
# Seed 003 eq. I-22 as printed (+ root of R), same apparatus.
SEED = np.array([
    [1.582090391475e-02, 7.749792271489e-02, 1.922487161883e-01, 4.304054061005e-01, 5.790477944369e-01],
    [9.651853795491e-03, 2.807090373596e-02, 5.674619803984e-02, 1.105715361586e-01, 1.422077092766e-01],
    [1.119486919665e-03, 6.387336737889e-03, 2.039416690079e-02, 6.033237505764e-02, 9.046434963645e-02],
    [1.680095354368e-02, 1.123461046721e-01, 3.728274004733e-01, 1.092579720024e+00, 1.619272843240e+00],
])


def test_comparison_table_pins_exact_and_seed_values():
    ds = comparison_dataset(PRESETS, ZETAS)
    np.testing.assert_allclose(ds["critical_loading_rate"].values, EXACT, rtol=1e-9)
    np.testing.assert_allclose(ds["seed_appendix_I_loading_rate"].values, SEED, rtol=1e-9)


@pytest.mark.parametrize("preset", PRESETS)
@pytest.mark.parametrize("zeta", ZETAS)
def test_regime_flips_at_the_exact_critical_rate(preset, zeta):
    system = SliderSystem.from_preset(preset, loading_rate="1 1/s", damping_ratio=zeta)
    theta_c = critical(system).critical_loading_rate
    assert exact_cycle(system.at_loading_rate(theta_c * (1 - 1e-7))).regime == "stick_slip"
    assert exact_cycle(system.at_loading_rate(theta_c * (1 + 1e-7))).regime == "steady_sliding"


def test_tangency_condition_holds_at_epsilon_c():
    for zeta in (0.001, 0.05, 0.3, 0.8):
        eps = critical_dimensionless_rate(zeta)
        osc = _Oscillator(np.float64(zeta), 1 - 2 * zeta * eps, np.float64(eps))
        s_max = osc.first_zero("a") + np.pi / osc.omega
        assert osc("v", s_max) == pytest.approx(eps, rel=1e-12)  # x' = V
        assert abs(osc("a", s_max)) < 1e-12  # x'' = 0


def test_light_damping_asymptote_and_no_critical_rate_without_damping():
    for zeta in (1e-6, 1e-7):
        assert critical_dimensionless_rate(zeta) * np.sqrt(4 * np.pi * zeta) == pytest.approx(1.0, rel=3e-3)
    assert critical_dimensionless_rate(0.0) == np.inf and critical_dimensionless_rate(-0.1) == np.inf
    system = SliderSystem.from_preset("glass_dry", loading_rate="1 1/s")
    assert critical(system).critical_loading_rate == np.inf
    assert critical(system).seed_loading_rate == 0.0  # the seed's Z vanishes with damping


def test_exact_and_seed_disagree_on_the_trend_with_damping():
    ds = comparison_dataset(PRESETS, ZETAS)
    assert np.all(np.diff(ds["critical_loading_rate"].values, axis=1) < 0)  # exact: damping lowers theta_c
    assert np.all(np.diff(ds["seed_appendix_I_loading_rate"].values, axis=1) > 0)  # seed: damping raises it
    ratio = ds["seed_over_exact"].values
    assert np.all(ratio[:, 0] < 0.03)  # at zeta = 0.001 the seed is 49-600 times too low
    assert np.all((ratio[:, 3] > 0.75) & (ratio[:, 3] < 0.9))  # they cross between zeta = 0.2 and 0.3
    assert np.all(ratio[:, 4] > 1.3)
    text = comparison_markdown(ds)
    assert "Within 25 % of each other only at zeta = 0.2" in text


def test_seed_equation_i9a_drops_a_factor_lambda():
    """The exact tangency satisfies seed eqs. I-7a, I-10a and a corrected I-9a, but not I-9a as printed.

    Printed I-9a: (V/w_d) e^(lam t) = (V/w_d) cos - [A(1 + lam^2) + V/w_d] sin.
    From I-9 with B = V/w_d + lam A the bracket is A(1 + lam^2) + lam V/w_d.
    """
    for zeta in (0.01, 0.05, 0.2):
        eps = critical_dimensionless_rate(zeta)
        w = np.sqrt(1 - zeta**2)
        lam, amplitude, h = zeta / w, 1 - 2 * zeta * eps, eps / w
        osc = _Oscillator(np.float64(zeta), amplitude, np.float64(eps))
        tau = w * (osc.first_zero("a") + np.pi / w)
        growth = np.exp(lam * tau)
        i7a = -2 * zeta * eps * growth - (amplitude * np.cos(tau) + (h + lam * amplitude) * np.sin(tau))
        i10a = (amplitude * (1 + lam**2) + 2 * lam * h) * np.cos(tau) + (h * (1 - lam**2) - lam * amplitude * (1 + lam**2)) * np.sin(tau)
        corrected = h * growth - (h * np.cos(tau) - (amplitude * (1 + lam**2) + lam * h) * np.sin(tau))
        printed = h * growth - (h * np.cos(tau) - (amplitude * (1 + lam**2) + h) * np.sin(tau))
        assert max(abs(i7a), abs(i10a), abs(corrected)) < 1e-11
        assert abs(printed) > 0.1


def test_seed_formula_is_vectorised_and_uses_the_plus_root():
    rates = seed_critical_loading_rate(np.array([100.0, 200.0]), np.array([0.05, 0.05]), 0.65, 0.55, 38.0, 0.665)
    assert rates.shape == (2,) and np.all(rates > 0)


def test_critical_cli_contract(cli, tmp_path):
    data = cli("critical", "--preset", "glass_dry", "--damping-ratio", "0.05", "--json").json
    for key in ("critical_loading_rate", "critical_platform_speed", "seed_appendix_I_loading_rate"):
        assert set(data[key]) == {"value", "units"}
    assert data["method"] == "exact_tangency"
    assert data["critical_loading_rate"]["value"] == pytest.approx(EXACT[1, 2], rel=1e-9)
    result = cli("critical", "--table", "--output-dir", tmp_path)
    assert result.code == 0, result.err
    import xarray as xr

    with xr.open_dataset(tmp_path / "critical_comparison.nc") as ds:
        assert ds["critical_loading_rate"].attrs["units"] == "1/s"
        np.testing.assert_allclose(ds["critical_loading_rate"].values, EXACT, rtol=1e-9)
    assert (tmp_path / "critical_comparison.png").stat().st_size > 10000
    assert "seed" in (tmp_path / "critical_comparison.md").read_text()
