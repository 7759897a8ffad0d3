"""Seed 001's nanoscale toy model: the damping threshold in closed form against simulation, charge, slides' numbers."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import assert_clean_error
from faultslip.dynamics.nanoscale import (NanoscaleModel, dipole_force, hertz_radius, jkr_radius)
from faultslip.errors import InputError


def test_the_uncharged_threshold_is_minus_the_weakening_slope():
    """A_c = (1/v_m)((v_a/v_m)^2 - 1)/(1 + (v_a/v_m)^2)^2: 100 * 3 / 25 = 12 for the slides' v_a, v_m."""
    assert NanoscaleModel(charge_force=0.0).critical_damping == pytest.approx(12.0, rel=1e-15)
    assert NanoscaleModel(drive_speed=0.005, charge_force=0.0).critical_damping < 0  # no weakening below v_m


@pytest.mark.parametrize("damping, sticks", [(11.0, True), (11.8, True), (12.2, False), (14.0, False)])
def test_simulation_agrees_with_the_threshold(damping, sticks):
    """Below A_c a disturbance grows into a sustained oscillation (a force swing), above it dies out."""
    run = NanoscaleModel(damping=damping).simulate(duration=1500.0 if sticks else 600.0, samples=3001)
    assert (run.force_swing() > 1e-3) == sticks
    if not sticks:
        assert run.force_swing() < 1e-8


@settings(max_examples=30, deadline=None)
@given(charge_force=st.floats(0.0, 5.0), tau=st.floats(0.1, 10.0), length=st.floats(0.1, 10.0),
       drive=st.floats(0.011, 0.1))
def test_charging_raises_the_threshold_and_the_roots_cross_there(charge_force, tau, length, drive):
    """Adhesion by charge stabilises: A_c(f_ch) >= A_c(0); at A_c a pair of roots has zero real part."""
    charged = NanoscaleModel(drive_speed=drive, charging_time=tau, charge_length=length, charge_force=charge_force)
    bare = NanoscaleModel(drive_speed=drive, charging_time=tau, charge_length=length, charge_force=0.0)
    assert charged.critical_damping >= bare.critical_damping - 1e-12
    at = NanoscaleModel(damping=max(charged.critical_damping, 0.0), drive_speed=drive, charging_time=tau,
                        charge_length=length, charge_force=charge_force)
    if charged.critical_damping > 0:
        assert np.min(np.abs(at.characteristic_roots().real)) < 1e-6 * (1 + charged.critical_damping)


def test_deposited_charge_follows_displacement_at_the_steady_rate():
    """Seed 001: displacement and cumulative charge 'have the same slope': Sigma_d / X -> Sigma*/a, where
    Sigma* = 1 / (1 + tau v_a / a) = 0.9752 for the slides' values."""
    model = NanoscaleModel()
    run = model.simulate(duration=1500.0, samples=3001)
    assert model.steady_charge == pytest.approx(1 / (1 + 2.0 * 0.02 / 1.57), rel=1e-15)
    # in stick-slip the charge is depleted during each slip: the slope is 3 % below Sigma*/a (measured 0.602
    # against 0.621); in steady sliding (A = 13) it is Sigma*/a exactly
    assert run.deposited[-1] / run.displacement[-1] == pytest.approx(model.steady_charge / 1.57, rel=0.05)
    assert run.charge_correlation() > 0.9999 and run.slip_events() > 10
    steady = NanoscaleModel(damping=13.0).simulate(duration=600.0, samples=601)
    assert steady.deposited[-1] / steady.displacement[-1] == pytest.approx(model.steady_charge / 1.57, rel=1e-4)


def test_the_slides_contact_numbers_recomputed():
    """Pinned against the slides (docs/seed_discrepancies.md): Hertz a = 30.7 um for E* = 1.3 GPa (printed
    22 um) and 26.6 um for 2 GPa (printed 2.67e-5 m, agrees); JKR 27.4 um for gamma 0.1 J/m^2 (printed
    3.4e-5 m); the mean stress 0.1 N / (pi (22 um)^2) = 6.58e7 Pa (printed 6.9e7); the dipole force at
    22 um and 1.67e-5 C/m^2 is 6.8e-9 N times mu (printed 'F_c = 1e-9 N': the order of magnitude)."""
    assert hertz_radius(0.1, 0.5e-3, 1.3e9) == pytest.approx(30.67e-6, rel=1e-3)
    assert hertz_radius(0.1, 0.5e-3, 2.0e9) == pytest.approx(26.57e-6, rel=1e-3)
    assert jkr_radius(0.1, 0.5e-3, 2.0e9, 0.1) == pytest.approx(27.44e-6, rel=1e-3)
    assert 0.1 / (math.pi * (22e-6) ** 2) == pytest.approx(6.577e7, rel=1e-3)
    assert dipole_force(22e-6, 1.67e-5) == pytest.approx(6.84e-9, rel=1e-2)


def test_the_cli_runs_the_slides_model_and_refuses_bad_scenes(cli, tmp_path):
    out = cli("nanoscale", "configs/nanoscale_seed001.toml", "--json").json
    assert out["regime"].startswith("stick_slip") and out["critical_damping"] == pytest.approx(12.0, rel=1e-6)
    assert out["slip_events"] > 10
    quiet = cli("nanoscale", "configs/nanoscale_seed001.toml", "--damping", "13", "--no-run", "--json").json
    assert quiet["regime"].startswith("steady_sliding") and "force_swing" not in quiet
    bad = tmp_path / "bad.toml"
    bad.write_text('[friction]\nlaw = "nanoscale"\n[slider]\ndamping = "3 N"\n', encoding="utf-8")
    assert_clean_error(cli("nanoscale", bad), "must be a number")
    bad.write_text('[friction]\nlaw = "nanoscale"\n[slider]\ndrive_speed = -1\n', encoding="utf-8")
    assert_clean_error(cli("nanoscale", bad), "drive speed")
    bad.write_text('[slider]\ndamping = 3\n', encoding="utf-8")
    assert_clean_error(cli("nanoscale", bad), 'law = "nanoscale"')
    assert_clean_error(cli("nanoscale", "configs/nanoscale_seed001.toml", "--damping", "-2"), "damping")
    from faultslip.models.nanoscale.scene import parse_nanoscale_scene

    with pytest.raises(InputError, match="unknown key"):
        parse_nanoscale_scene('[friction]\nlaw = "nanoscale"\n[slider]\ndamp = 3\n', "n.toml")
    with pytest.raises(InputError, match="tolerance"):
        parse_nanoscale_scene('[friction]\nlaw = "nanoscale"\n[method]\ntolerance = 2\n', "n.toml")


def test_lsoda_swing_error_is_within_its_declared_bound():
    """The force swing at rtol 1e-6 and 1e-8 against rtol 1e-12 (measured 6.2e-6 and 2.7e-7 for A = 3: about
    30 rtol) stays below the declared LSODA_ERROR_CONSTANT rtol = 100 rtol."""
    from faultslip.dynamics.nanoscale import LSODA_ERROR_CONSTANT

    model = NanoscaleModel()
    reference = model.simulate(1500.0, 3001, rtol=1e-12).force_swing()
    for rtol in (1e-6, 1e-8):
        error = abs(model.simulate(1500.0, 3001, rtol=rtol).force_swing() / reference - 1)
        assert rtol < error < LSODA_ERROR_CONSTANT * rtol, (rtol, error)


def test_run_and_simulate_take_a_nanoscale_scene_and_auto_integrates_only_when_needed(cli, tmp_path):
    text = open("configs/nanoscale_seed001.toml", encoding="utf-8").read().replace("3000.0", "600.0")
    scene = tmp_path / "nano.toml"
    scene.write_text(text, encoding="utf-8")
    out = cli("run", scene, "--json").json
    assert out["method"] == "nanoscale_LSODA" and out["estimated_relative_error"] == pytest.approx(1e-6)
    assert out["slip_events"] > 5
    quiet = tmp_path / "quiet.toml"
    quiet.write_text(text.replace("damping = 3.0", "damping = 13.0"), encoding="utf-8")
    steady = cli("run", quiet, "--json").json
    assert steady["method"] == "nanoscale_linear_stability" and steady["force_swing"] == 0.0
    assert "duration" not in steady  # nothing integrated
    assert "regime alone" not in steady["method_reason"] and "small disturbances decay" in steady["method_reason"]
    forced = cli("run", scene, "--method", "nanoscale_linear_stability", "--json").json
    assert forced["regime"].startswith("stick_slip") and "force_swing" not in forced
    simulated = cli("simulate", scene, "-o", tmp_path / "n.nc", "--plot", tmp_path / "n.png", "--json")
    assert simulated.code == 0, simulated.err
    import xarray as xr

    with xr.open_dataset(tmp_path / "n.nc") as data:
        assert data.sizes["time"] == 6001 and data.attrs["damping"] == 3.0
    assert (tmp_path / "n.png").stat().st_size > 10_000
    assert_clean_error(cli("simulate", scene, "--cycles", "3"), "--cycles applies to seed-law scenes")
    assert_clean_error(cli("run", scene, "--method", "closed_form"), "must be one of auto")
    from faultslip.fault.scene import load_scene

    with pytest.raises(InputError, match="nanoscale scene"):
        load_scene(str(scene))
