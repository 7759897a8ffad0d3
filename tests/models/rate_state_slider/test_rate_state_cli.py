"""The rate-and-state commands: simulate, stability, cycles, fit --law rate-state, and their refusals."""

import numpy as np
import pytest

from conftest import assert_clean_error
import xarray as xr

from faultslip.errors import InputError
from faultslip.models.rate_state_slider.scene import parse_rate_state_scene

STEP = "configs/rsf_velocity_step.toml"
BP1 = "configs/rsf_block_bp1.toml"


def test_simulate_reports_and_writes_the_time_series(cli, tmp_path):
    out = tmp_path / "step.nc"
    result = cli("rate-state", "simulate", STEP, "-o", out, "--json")
    assert result.code == 0, result.err
    report = result.json
    from faultslip.dynamics.rate_state.compiled import available

    assert report["method"] == ("dopri5_compiled" if available() else "lsoda") and report["samples"] == 4001
    assert report["final_friction"] == pytest.approx(report["steady_state_friction_at_final_speed"], abs=1e-7)
    assert report["peak_friction"] > report["initial_friction"] == pytest.approx(0.6)
    with xr.open_dataset(out) as ds:
        assert ds["friction"].attrs["units"] == "1" and ds["time"].attrs["units"] == "s"
        assert float(ds["load_point_displacement"][-1]) == pytest.approx(10e-6 + 30 * 10e-6)


def test_stability_and_cycles_of_the_bp1_fault(cli):
    stability = cli("rate-state", "stability", BP1, "--json").json
    from faultslip.models.rate_state_slider.one_slider import stiffness_factor

    # K = c G / W on BP1's 15 km seismogenic width (c calibrated against the 2-D fault), K_c = sigma (b - a) / D_c
    assert stability["stiffness_ratio"] == pytest.approx(stiffness_factor() * 32e9 / 15e3 / 3.125e7)
    assert stability["critical_stiffness_quasi_static"]["value"] == pytest.approx(50e6 * 0.005 / 0.008)
    assert stability["regime"].startswith("unstable")
    cycles = cli("rate-state", "cycles", BP1, "--cycles", "3", "--json").json
    assert cycles["cycles"] == 3 and cycles["plate_slip_balance"] == pytest.approx(1.0, rel=1e-3)
    assert cycles["recurrence_period"]["units"] == "s" and cycles["slip_per_event"]["value"] > 0


def test_fit_rate_state_recovers_the_example_record(cli):
    result = cli("fit", "--law", "rate-state", "configs/example_velocity_steps.csv", "--stiffness", "1e-2 1/um",
                 "--bootstrap", "6", "--json")
    assert result.code == 0, result.err
    fit = result.json
    for name in ("a", "b", "critical_slip"):  # both intervals are in the JSON, and each holds its estimate
        value = fit[name]["value"] if isinstance(fit[name], dict) else fit[name]
        for key in (f"{name}_95", f"{name}_95_bootstrap"):
            interval = fit[key]["value"] if isinstance(fit[key], dict) else fit[key]
            assert interval[0] < value < interval[1], (key, interval, value)
    assert fit["bootstrap_samples"] == 6
    assert fit["a"] == pytest.approx(0.006, rel=0.02) and fit["b"] == pytest.approx(0.009, rel=0.02)
    assert fit["critical_slip"]["value"] == pytest.approx(15e-6, rel=0.03)


@pytest.mark.parametrize("args, message", [
    (("rate-state",), "needs an action"),
    (("rate-state", "cycles", STEP), "describes a laboratory slider"),
    (("rate-state", "simulate", BP1), "no \\[load\\] table"),
    (("rate-state", "simulate", STEP, "--rtol", "1"), "--rtol must lie between"),
    (("rate-state", "simulate", STEP, "--method", "euler"), "method must be one of"),
    (("rate-state", "cycles", BP1, "--cycles", "0"), "--cycles must lie between"),
    (("fit", "--law", "rate-state", "configs/example_velocity_steps.csv"), "needs --stiffness"),
    (("fit", "--law", "rate-state", "configs/example_velocity_steps.csv", "--stiffness", "2 kg"), "a stiffness per normal load"),
    (("fit", "--law", "rate-state", "configs/example_friction_data.csv", "--stiffness", "1e-2 1/um"), "unknown column"),
])
def test_refusals_are_one_sentence_and_exit_2(cli, args, message):
    import re

    result = cli(*args)
    assert result.code == 2 and "Traceback" not in result.err
    assert re.search(message, result.err), result.err
    assert len(result.err.strip().splitlines()) == 1


@pytest.mark.parametrize("text, message", [
    ('[law]\npreset = "step_example"\n[load]\nduration = "1 s"\nspeed = "1 um/s"\n', "exactly one of \\[slider\\]"),
    ('[law]\na = 0.01\nb = 0.01\n[slider]\nstiffness = "1 1/um"\n[load]\nduration = "1 s"\nspeed = "1 um/s"\n',
     "needs critical_slip"),
    ('[law]\npreset = "step_example"\nfoo = 1\n', "unknown key 'foo'"),
    ('[law]\npreset = "step_example"\n[slider]\nstiffness = "1 1/um"\n[load]\nduration = "1 s"\n',
     "needs steps, slide_hold_slide or speed"),
    ('[law]\npreset = "step_example"\n[slider]\nstiffness = "1 1/um"\n[load]\nduration = "10 s"\n'
     'steps = [["1 s", "1 um/s"]]\n', "must start at 0 s"),
    ('[law]\npreset = "nope"\n[slider]\nstiffness = "1 1/um"\n', "unknown rate-and-state law"),
    ('[law]\npreset = "step_example"\n[fault]\nshear_modulus = "30 GPa"\n', "needs normal_stress"),
])
def test_bad_scenes_are_refused(text, message):
    with pytest.raises(InputError, match=message):
        parse_rate_state_scene(text, "scene.toml")


def test_a_saved_rate_state_fit_predicts_a_fault_with_uncertainty_and_the_seed_law_beside(cli, monkeypatch):
    """fit --name, then fault --lithology NAME: K / K_c over every resample, cycles, and the seed law."""
    result = cli("fit", "--law", "rate-state", "configs/example_velocity_steps.csv", "--stiffness", "1e-2 1/um",
                 "--bootstrap", "6", "--name", "test_gouge", "--shear-modulus", "30 GPa")
    assert result.code == 0, result.err
    from faultslip.friction.materials import user_presets, user_rate_state_fits

    law, entry = user_rate_state_fits()["test_gouge"]
    assert entry["kind"] == "rate_state" and len(entry["bootstrap"]) == 6
    assert "test_gouge" not in user_presets()  # never read as a seed-law preset
    # a small fault (D = 1 km, sigma_n 5 MPa, K / K_c about 0.03) keeps the cycles cheap
    from faultslip.fault import rate_state_fault

    monkeypatch.setattr(rate_state_fault, "fault_cycles", _fast_cycles(rate_state_fault.fault_cycles))
    result = cli("fault", "--lithology", "test_gouge", "--zone-width", "1 km", "--normal-stress", "5 MPa",
                 "--slip-rate", "30 mm/yr", "--json")
    assert result.code == 0, result.err
    out = result.json
    ratio = out["stiffness_ratio"]
    assert ratio == pytest.approx(30e9 / 1e3 * law.critical_slip / (5e6 * (law.b - law.a)), rel=1e-9)
    low, high = out["stiffness_ratio_95"]["value"] if isinstance(out["stiffness_ratio_95"], dict) else out["stiffness_ratio_95"]
    assert low <= ratio <= high
    assert out["regime"].startswith("stick_slip")
    assert out["slip_per_event"]["value"] > 0 and out["seed_law_slip_per_event"]["value"] > 0
    # on the ladder as a rate-and-state scene is: its model error against the 2-D fault (K = G / D) declared
    from faultslip.models.rate_state_slider.model_error import declared_model_error

    expected, ratio_w, _ = declared_model_error(law, 30e9, 5e6, 1e3, reduction="zone_width")
    assert out["width_over_nucleation"] == pytest.approx(ratio_w, rel=1e-12)
    assert out["model_error"] == (expected if expected == expected and expected != float("inf") else None)
    assert any("stands for the fault with its friction uniform from the surface to 1 km" in note for note in out["notes"])
    for flags, message in ((("--mu-so", "0.6"), "do not apply"), (("--radiation-damping",), "do not apply")):
        refused = cli("fault", "--lithology", "test_gouge", "--zone-width", "1 km", "--normal-stress", "5 MPa",
                      "--slip-rate", "30 mm/yr", *flags)
        assert_clean_error(refused, message)
    refused = cli("fault", "--lithology", "granodiorite", "--zone-width", "13 mi", "--shear-stress", "250 bar",
                  "--slip-rate", "2 in/yr", "--seed-law", "granodiorite")
    assert_clean_error(refused, "--seed-law goes with a rate-and-state fit")


def _fast_cycles(cycles):
    def run(*args, **kwargs):
        kwargs["cycles"] = min(kwargs.get("cycles", 2), 2)
        return cycles(*args, **kwargs)
    return run


def test_cycles_put_the_seed_law_beside_on_the_same_fault(cli):
    """The seed law on BP1's fault (G 32 GPa, sigma_n 50 MPa, V_pl 1e-9 m/s, the block's stiffness: D = G / K =
    W / c) with radiation damping equals Fault.estimate with those inputs."""
    from faultslip.models.rate_state_slider.one_slider import stiffness_factor
    from faultslip.fault.scaling import Fault

    out = cli("rate-state", "cycles", BP1, "--cycles", "3", "--seed-law", "granodiorite", "--json").json
    width = 15e3 / stiffness_factor()
    expected = Fault(lithology="granodiorite", shear_modulus="32 GPa", zone_width=f"{width!r} m", normal_stress="50 MPa",
                     slip_rate="1e-9 m/s", density="2670 kg/m^3", shear_wave_speed="3.464 km/s",
                     radiation_damping=True).estimate()
    assert out["seed_law_slip_per_event"]["value"] == pytest.approx(expected.slip_per_event, rel=1e-12)
    assert out["seed_law_recurrence_period"]["value"] == pytest.approx(expected.recurrence_period, rel=1e-12)
    assert out["slip_ratio_rate_state_to_seed"] == pytest.approx(
        out["slip_per_event"]["value"] / expected.slip_per_event, rel=1e-12)
    assert 0.5 < out["slip_ratio_rate_state_to_seed"] < 2.0
    assert_clean_error(cli("rate-state", "cycles", BP1, "--seed-law", "basalt"), "basalt")


def test_simulate_writes_a_rate_state_faults_cycles(cli, tmp_path):
    """simulate of a fault scene with [friction] law = "rate_state": the integrator's steps as a time series
    and the events; over the recorded cycles the fault slips as far as the plate moves (to 1e-5)."""
    out, plot = tmp_path / "cycles.nc", tmp_path / "cycles.png"
    result = cli("simulate", "configs/san_andreas_1906_rate_state.toml", "--cycles", "3", "-o", out, "--plot", plot,
                 "--json")
    assert result.code == 0, result.err
    assert result.json["cycles"] == 3 and plot.stat().st_size > 10_000
    with xr.open_dataset(out) as written:
        assert written["slip_rate"].attrs["units"] == "m/s" and written.sizes["event"] == 3
        starts = written["event_time"].values
        slip = np.interp(starts, written["time"].values, written["slip"].values)
        plate = written.attrs["plate_rate_m_per_s"]
        assert np.diff(slip) / (plate * np.diff(starts)) == pytest.approx(np.ones(2), rel=1e-3)
        assert written["slip_rate"].values.max() == pytest.approx(written["peak_slip_rate"].values.max(), rel=1e-12)
    assert_clean_error(cli("simulate", "configs/san_andreas_1906_rate_state.toml", "--rtol", "1e-9"),
                       "belong to the seed law's simulation")


def test_run_refuses_a_seed_method_for_a_rate_state_scene_rather_than_ignore_it(cli):
    assert_clean_error(cli("run", "configs/san_andreas_1906_rate_state.toml", "--method", "exact_cycle"),
                       "a rate-and-state fault runs one of auto, one_slider, fault_2d, got 'exact_cycle'")


def test_an_escalation_to_the_2d_fault_is_estimated_and_budgeted_before_any_work(cli, monkeypatch):
    """'run rsf_block_bp1.toml --tolerance 0.3' escalated silently to a six-minute 2-D run (issue 42): it now
    states the estimate first, and above the budget it asks for --allow-large before any work."""
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", "1")
    refused = cli("run", "configs/rsf_block_bp1.toml", "--tolerance", "0.3")
    assert refused.code == 2 and "escalating" in refused.err and "--allow-large" in refused.err
    assert "2-D fault" in refused.err
