"""Event-driven simulation: agreement with the exact cycle, fault and lab scale, other laws, failures."""

import numpy as np
import pytest
import xarray as xr

from faultslip.dynamics.spring_slider.critical import critical
from faultslip.errors import InputError, SolverError
from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle
from faultslip.friction.laws import CallableKinetic, ConstantKinetic, PolynomialKinetic, TimeOfStickLaw
from faultslip.fault.scene import read_slider_scene
from faultslip.dynamics.spring_slider.simulate import simulate
from faultslip.dynamics.spring_slider.slider import SliderSystem

YEAR = 365.25 * 86400


def _agreement(dataset, exact):
    events = dataset["event_time"].values
    k = np.arange(events.size)
    return {
        "amplitude": np.max(np.abs(dataset["amplitude"].values / exact.amplitude - 1)),
        "period": np.max(np.abs(dataset["period"].values[1:] / exact.period - 1)),
        "event_times": np.max(np.abs(events / (events[0] + k * exact.period) - 1)),
        "stick": np.max(np.abs(dataset["stick_duration"].values[1:] / exact.stick_duration - 1)),
        "slip": np.max(np.abs(dataset["slip_duration"].values / exact.slip_duration - 1)),
    }


@pytest.mark.parametrize("solver, rtol", [("analytic", None), ("DOP853", 1e-12), ("LSODA", 1e-12)])
def test_simulator_reproduces_the_exact_cycle_to_1e_8(solver, rtol):
    system = SliderSystem.from_preset("glass_dry", loading_rate="0.05 1/s", damping_ratio=0.05)
    dataset = simulate(system, cycles=20, slip_solver=solver, **({"rtol": rtol} if rtol else {}))
    errors = _agreement(dataset, exact_cycle(system))
    assert max(errors.values()) < 1e-8, errors


def test_fault_scale_100_cycles_never_steps_through_the_interseismic_period():
    scene = read_slider_scene("san_andreas_1906.toml")
    system = scene.slider()
    dataset = simulate(system, cycles=100)
    assert dataset.sizes["event"] == 100 and dataset.attrs["slip_solver"] == "analytic"
    stick = dataset["phase"].values == 0
    assert stick.sum() == 2 * 100  # two samples per stick phase: its ends, nothing in between
    exact = exact_cycle(system)
    assert max(_agreement(dataset, exact).values()) < 1e-8
    assert exact.loading_rate == pytest.approx(5.0013e-11, rel=1e-4)
    assert exact.stick_duration / YEAR == pytest.approx(126.72, abs=0.01) and 10 < exact.slip_duration < 60


def test_fault_scale_with_an_integrator_agrees_with_the_exact_cycle():
    system = read_slider_scene("san_andreas_1906.toml").slider()
    dataset = simulate(system, cycles=5, slip_solver="DOP853", rtol=1e-11)
    assert max(_agreement(dataset, exact_cycle(system)).values()) < 1e-8


def test_radiation_damping_at_fault_scale():
    system = read_slider_scene("san_andreas_1906_radiation.toml").slider()
    assert system.radiation_damper == pytest.approx(np.sqrt(0.25e11 * 2700) / 2)  # G / (2 sqrt(G/rho))
    assert system.damping_ratio == pytest.approx(0.25)
    dataset = simulate(system, cycles=100)
    exact = exact_cycle(system)
    assert max(_agreement(dataset, exact).values()) < 1e-8
    plain = exact_cycle(read_slider_scene("san_andreas_1906.toml").slider())
    assert exact.amplitude < 0.8 * plain.amplitude  # radiation damping cuts the slip by about a quarter


@pytest.mark.parametrize("preset", ["steel_heavy_petrolatum", "glass_water", "pyrite_light_petrolatum", "black_marble_water"])
def test_lab_scale_1000_cycles_of_table_i_presets(preset):
    system = SliderSystem.from_preset(preset, platform_speed="1e-4 in/s", damping_ratio=0.01)
    dataset = simulate(system, cycles=1000)
    assert dataset.sizes["event"] == 1000
    assert max(_agreement(dataset, exact_cycle(system)).values()) < 1e-8


def test_above_the_critical_rate_the_slider_slides_steadily():
    system = SliderSystem.from_preset("glass_dry", loading_rate="1 1/s", damping_ratio=0.05)
    above = system.at_loading_rate(1.5 * critical(system).critical_loading_rate)
    dataset = simulate(above, cycles=10)
    assert dataset.attrs["regime"] == "steady_sliding" and dataset.sizes["event"] == 0
    integrated = simulate(above, cycles=10, slip_solver="DOP853")
    assert integrated.attrs["regime"] == "steady_sliding"


def test_cameron_time_of_stick_law_reproduces_seed_002_eq_9():
    """V = c alpha / ln(alpha_m / (alpha_m - alpha)) below V_c = c alpha_m (seed 002, Cameron)."""
    base = SliderSystem.from_preset("steel_dry", platform_speed="1e-3 in/s")
    law = TimeOfStickLaw(mu_lower=0.39, mu_upper=0.53, growth_rate=2.0)
    system = base.with_(static_law=law, kinetic_law=ConstantKinetic(0.39))
    alpha_m = 2 * system.normal_load / system.stiffness * (0.53 - 0.39)
    critical_speed = law.growth_rate * alpha_m
    for fraction in (0.12, 0.5, 0.85):
        speed = fraction * critical_speed
        dataset = simulate(system.with_(platform_speed=speed), cycles=300)
        alpha = dataset["amplitude"].values[-1]
        assert dataset["amplitude"].values[-2] == pytest.approx(alpha, rel=1e-9)  # converged limit cycle
        predicted_speed = law.growth_rate * alpha / np.log(alpha_m / (alpha_m - alpha))
        assert predicted_speed == pytest.approx(speed, rel=5e-3)


def test_polynomial_kinetic_law_limit_cycle_is_method_independent():
    scene = read_slider_scene("lab_steel_dry_polynomial.toml")
    system = scene.slider()
    assert isinstance(system.kinetic_law, PolynomialKinetic)
    a = simulate(system, cycles=8, slip_solver="DOP853", rtol=1e-12)
    b = simulate(system, cycles=8, slip_solver="Radau", rtol=1e-12)
    assert a["amplitude"].values[-1] == pytest.approx(b["amplitude"].values[-1], rel=1e-8)
    assert a["period"].values[-1] == pytest.approx(b["period"].values[-1], rel=1e-8)
    assert a.attrs["function_evaluations"] > 0


def test_dataset_carries_units_and_writes_to_netcdf(tmp_path):
    from faultslip.io.netcdf import write_dataset

    dataset = simulate(read_slider_scene("san_andreas_1906.toml").slider(), cycles=3)
    path = tmp_path / "sim.nc"
    write_dataset(dataset, path)
    with xr.open_dataset(path) as back:
        assert back["displacement"].attrs["units"] == "m"
        assert back["stress_drop"].attrs["units"] == "Pa"
        assert back.attrs["stiffness_units"] == "Pa/m"
        assert list(back["phase"].attrs["flag_meanings"].split()) == ["stick", "slip"]
        np.testing.assert_allclose(back["amplitude"].values, dataset["amplitude"].values)


def test_solver_failures_name_method_scene_and_remedy():
    system = SliderSystem.from_preset("steel_dry", platform_speed="1e-3 in/s")
    sharp = system.with_(kinetic_law=CallableKinetic(lambda u: 0.39 + 0.2 * np.tanh(u / 1e-9), name="sharp"))
    with pytest.raises(SolverError, match=r"simulate \(RK45.*budget of 20000 function evaluations exceeded.*steel_dry"):
        simulate(sharp, cycles=2, slip_solver="RK45", rtol=1e-6, max_evaluations=20000)
    runaway = system.with_(kinetic_law=PolynomialKinetic([0.39, -3 / 0.0254]))
    with pytest.raises(SolverError, match="friction must stay finite and non-negative"):
        simulate(runaway, cycles=2)


def test_bad_requests_are_refused():
    system = SliderSystem.from_preset("steel_dry", platform_speed="1e-3 in/s")
    with pytest.raises(InputError, match="unknown slip solver"):
        simulate(system, slip_solver="Euler")
    with pytest.raises(InputError, match="analytic slip phase needs a linear kinetic law"):
        simulate(system.with_(kinetic_law=PolynomialKinetic([0.39, -1.0, 30.0])), slip_solver="analytic")
    with pytest.raises(InputError, match="mass must be positive"):
        system.with_(mass=-1.0)
    with pytest.raises(InputError, match="stiffness must be positive"):
        system.with_(stiffness=0.0)
    with pytest.raises(InputError, match="damping ratio must lie in"):
        SliderSystem.from_preset("steel_dry", platform_speed="1e-3 in/s", damping_ratio=1.0)


def test_simulate_cli(cli, tmp_path):
    out, png = tmp_path / "run.nc", tmp_path / "saw.png"
    result = cli("simulate", "san_andreas_1906", "-o", out, "--plot", png, "--cycles", "10", "--json")
    assert result.code == 0, result.err
    data = result.json
    assert data["regime"] == "stick_slip" and data["events"] == 10
    assert data["slip_per_event"]["units"] == "m" and data["slip_per_event"]["value"] == pytest.approx(6.43737, rel=1e-5)
    with xr.open_dataset(out) as ds:
        assert ds.sizes["event"] == 10 and "scene_text" in ds.attrs
    assert png.stat().st_size > 10000


def test_cycle_cli_reports_the_regime(cli):
    below = cli("cycle", "lab_glass_dry", "--loading-rate", "0.01 1/s", "--json").json
    assert below["regime"] == "stick_slip" and below["method"] == "exact_cycle"
    assert set(below["slip_per_event"]) == {"value", "units"}


def test_phase_plane_plot_cli(cli, tmp_path):
    result = cli("plot", "phase-plane", "--preset", "pyrite_dry", "--damping-ratio", "0.05", "-o", tmp_path / "pp.png")
    assert result.code == 0, result.err
