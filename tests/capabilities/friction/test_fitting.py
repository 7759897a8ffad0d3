"""Fitting eq. 2-18 to laboratory data: round trips, interval coverage, flags, degenerate data, the registry."""

import numpy as np
import pytest
import xarray as xr

from faultslip.errors import InputError
from faultslip.friction.fitting import PARAMETERS, FrictionData, fit_rate_law, read_friction_data, synthetic_data
from faultslip.friction.materials import get_preset, presets, table_i_presets


def _independent_seed(index, seed):
    return 7919 * (index + 1) + seed  # every preset draws its own noise


@pytest.mark.parametrize("index", range(11), ids=[p.name for p in table_i_presets()])
def test_round_trip_recovers_each_table_i_preset(index):
    """Within 4 standard errors (the 95 % rate itself is checked in aggregate below)."""
    preset = table_i_presets()[index]
    fit = fit_rate_law(synthetic_data(preset, noise=0.002, seed=_independent_seed(index, 100)), bootstrap=60, seed=1)
    for name in PARAMETERS:
        truth = getattr(preset.rate_law, name)
        assert abs(fit.values[name] - truth) <= 4 * fit.standard_errors[name], (name, fit.values[name], truth)
    assert fit.residual_rms == pytest.approx(0.002, rel=0.35)


def test_covariance_intervals_cover_the_truth_at_the_nominal_rate():
    """Wald (covariance) intervals over 11 presets x 40 independent noise draws x 4 constants."""
    hits = total = 0
    for index, preset in enumerate(table_i_presets()):
        for seed in range(40):
            fit = fit_rate_law(synthetic_data(preset, noise=0.002, seed=_independent_seed(index, seed)), bootstrap=0)
            for name in PARAMETERS:
                low, high = fit.intervals[name]
                hits += low <= getattr(preset.rate_law, name) <= high
                total += 1
    coverage = hits / total
    assert total == 1760
    assert 0.93 <= coverage <= 0.97, coverage  # measured: 0.952


def test_bootstrap_intervals_cover_the_truth_at_the_nominal_rate():
    """The reported intervals (bootstrap SE, t quantile) over 11 presets x 8 draws: measured 0.957."""
    hits = total = 0
    for index, preset in enumerate(table_i_presets()):
        for seed in range(8):
            fit = fit_rate_law(synthetic_data(preset, noise=0.002, seed=_independent_seed(index, seed)), bootstrap=60, seed=seed)
            for name in PARAMETERS:
                low, high = fit.intervals[name]
                hits += low <= getattr(preset.rate_law, name) <= high
                total += 1
    assert 0.91 <= hits / total <= 0.99, hits / total


def test_bootstrap_is_reproducible_with_its_seed():
    data = synthetic_data(get_preset("glass_dry"), noise=0.002, seed=3)
    a, b = fit_rate_law(data, bootstrap=30, seed=5), fit_rate_law(data, bootstrap=30, seed=5)
    np.testing.assert_array_equal(a.bootstrap, b.bootstrap)
    assert not np.array_equal(a.bootstrap, fit_rate_law(data, bootstrap=30, seed=6).bootstrap)


def test_joint_amplitude_fit():
    preset = get_preset("granodiorite_water")
    data = synthetic_data(preset, noise=0.003, seed=2, amplitude_noise=2e-6)
    fit = fit_rate_law(data, bootstrap=40)
    assert fit.residual_rms_amplitude == pytest.approx(2e-6, rel=0.4)
    for name in PARAMETERS:
        low, high = fit.intervals[name]
        assert low <= getattr(preset.rate_law, name) <= high


def test_robust_loss_resists_outliers():
    preset = get_preset("steel_dry")
    data = synthetic_data(preset, noise=0.002, seed=4)
    corrupted = data.static_friction.copy()
    corrupted[[5, 17, 29]] += 0.08
    dirty = FrictionData(data.loading_rate, corrupted, source="outliers")
    plain = fit_rate_law(dirty, bootstrap=0)
    robust = fit_rate_law(dirty, loss="soft_l1", bootstrap=0)
    truth = preset.rate_law
    assert abs(robust.values["mu_m"] - truth.mu_m) < abs(plain.values["mu_m"] - truth.mu_m)
    assert abs(robust.values["mu_so"] - truth.mu_so) < 0.01


def test_flags_when_the_data_cannot_pin_a_parameter():
    preset = get_preset("granodiorite_water")
    law = preset.rate_law
    half = (1 / (law.b * (law.mu_so - law.mu_m))) ** (1 / law.d)
    low_only = synthetic_data(preset, noise=0.002, seed=1, rates=np.geomspace(half / 1e4, half * 1.5, 30))
    fit = fit_rate_law(low_only, bootstrap=40)
    assert any("no points well above the half-drop rate" in flag for flag in fit.flags)
    full = fit_rate_law(synthetic_data(preset, noise=0.002, seed=1), bootstrap=40)
    assert full.flags == []


def _csv(tmp_path, text, name="data.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_speed_stiffness_load_route_and_netcdf_input(tmp_path):
    preset = get_preset("glass_dry")
    data = synthetic_data(preset, noise=0.001, seed=9)
    speeds = data.loading_rate * preset.normal_load / preset.stiffness / 0.0254  # in/s
    lines = ["platform_speed (in/s),stiffness (lbf/in),normal_load (lbf),static_friction"]
    lines += [f"{v!r},19400,137.8,{m!r}" for v, m in zip(speeds.tolist(), data.static_friction.tolist())]
    read = read_friction_data(_csv(tmp_path, "\n".join(lines) + "\n"))
    np.testing.assert_allclose(read.loading_rate, data.loading_rate, rtol=1e-6)
    netcdf = xr.Dataset({"loading_rate": ("n", data.loading_rate, {"units": "1/s"}),
                         "static_friction": ("n", data.static_friction)})
    netcdf.to_netcdf(tmp_path / "d.nc")
    fit = fit_rate_law(read_friction_data(tmp_path / "d.nc"), bootstrap=0)
    assert fit.values["mu_so"] == pytest.approx(0.85, abs=0.005)


GOOD = "loading_rate (1/s),static_friction\n" + "".join(f"{r},{0.55 + 0.1 / (1 + 3.8 * r ** 0.665)}\n"
                                                         for r in np.geomspace(1e-4, 1e3, 12))


@pytest.mark.parametrize("text, message", [
    (GOOD.replace("1e-4", "nan", 1).replace(str(1e-4), "nan", 1), "NaN"),
    ("loading_rate (1/s),static_friction\n-1,0.6\n0.1,0.6\n1,0.58\n10,0.56\n100,0.55\n", "loading rate must be positive"),
    ("loading_rate (1/s),static_friction\n0.1,0.6\n1,0.58\n10,0.56\n", "needs at least 5"),
    ("loading_rate (1/s),static_friction\n" + "1,0.6\n" * 8, "one loading rate"),
    ("loading_rate,static_friction\n0.1,0.6\n", "needs a unit in its header"),
    ("loading_rate (furlongs),static_friction\n0.1,0.6\n", "loading_rate"),
    ("loading_rate (bar),static_friction\n0.1,0.6\n", "must be a rate"),
    ("loading_rat (1/s),static_friction\n0.1,0.6\n", "unknown column 'loading_rat'.*did you mean loading_rate"),
    ("loading_rate (1/s),static_friction,kinetic_friction\n" + "".join(f"{r},0.6,0.9\n" for r in (0.01, 0.1, 1, 10, 100, 1000)),
     "below the kinetic friction"),
])
def test_degenerate_data_are_refused(tmp_path, text, message):
    with pytest.raises(InputError, match=message):
        fit_rate_law(read_friction_data(_csv(tmp_path, text)), bootstrap=0)


def test_failed_fit_never_changes_the_registry(tmp_path, cli, monkeypatch):
    registry = tmp_path / "fits.json"
    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(registry))
    good = _csv(tmp_path, GOOD, "good.csv")
    assert cli("fit", good, "--name", "first", "--bootstrap", "20").code == 0
    before = registry.read_bytes()
    bad = _csv(tmp_path, "loading_rate (1/s),static_friction\n" + "1,0.6\n" * 8, "bad.csv")
    result = cli("fit", bad, "--name", "second", "--bootstrap", "20")
    assert result.code == 2 and "one loading rate" in result.err and "Traceback" not in result.err
    assert registry.read_bytes() == before
    # an interrupted write leaves the old registry too
    import faultslip.io.atomic as atomic

    def crash(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(atomic.os, "replace", crash)
    with pytest.raises(KeyboardInterrupt):
        from faultslip.friction.materials import save_user_fit
        from faultslip.friction.fitting import fit_rate_law as fit

        save_user_fit("third", fit(read_friction_data(good), bootstrap=5))
    assert registry.read_bytes() == before
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".fits.json") and not p.name.endswith(".lock")]


def test_lab_csv_to_fitted_material_to_fault_prediction_with_uncertainty(tmp_path, cli, monkeypatch):
    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(tmp_path / "fits.json"))
    preset = get_preset("granodiorite_water")
    data = synthetic_data(preset, points=30, noise=0.003, seed=7, amplitude_noise=2e-6)
    lines = ["loading_rate (1/s),static_friction,amplitude (m),normal_load (lbf),stiffness (lbf/in)"]
    lines += [f"{r!r},{m!r},{a!r},169.9,19400" for r, m, a in zip(data.loading_rate.tolist(), data.static_friction.tolist(),
                                                                 data.amplitude.tolist())]
    csv_path = _csv(tmp_path, "\n".join(lines) + "\n", "gouge.csv")
    # 1. fit and save
    fitted = cli("fit", csv_path, "--name", "my_gouge", "--shear-modulus", "0.25e6 bar", "--plot", tmp_path / "fit.png", "--json")
    assert fitted.code == 0, fitted.err and (tmp_path / "fit.png").exists()
    assert set(fitted.json["mu_so_95"]) == {"value", "units"}
    # 2. it is listed beside the bundled presets
    listed = cli("materials", "--json").json
    assert any(row["name"] == "my_gouge" and row.get("user_fit") for row in listed["presets"])
    assert "my_gouge" in presets()
    # 3. a fault prediction with the fit carries its uncertainty
    fault = cli("fault", "--lithology", "my_gouge", "--zone-width", "13 mi", "--shear-stress", "250 bar",
                "--slip-rate", "2 in/yr", "--json").json
    low, high = fault["slip_per_event_95"]["value"]
    assert low < fault["slip_per_event"]["value"] < high and fault["slip_per_event_95"]["units"] == "m"
    low, high = fault["recurrence_period_95"]["value"]
    assert low < fault["recurrence_period"]["value"] < high
    assert fault["slip_per_event"]["value"] == pytest.approx(6.44, rel=0.05)  # the granodiorite truth, within noise


def test_registry_refuses_bundled_names_and_reports_its_path(tmp_path, monkeypatch, cli):
    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(tmp_path / "r.json"))
    result = cli("fit", _csv(tmp_path, GOOD), "--name", "granodiorite_water", "--bootstrap", "5")
    assert result.code == 2 and "bundled preset" in result.err
    assert not (tmp_path / "r.json").exists()
    from faultslip.friction.registry import registry_path

    assert registry_path() == tmp_path / "r.json"


def test_fit_json_has_quantities_and_intervals(tmp_path, cli):
    data = cli("fit", _csv(tmp_path, GOOD), "--bootstrap", "20", "--json").json
    assert data["b"]["units"].startswith("s^") and isinstance(data["mu_so"], float)
    assert len(data["d_95"]["value"]) == 2 and data["points"] == 12


def test_a_saved_fit_works_in_studies_and_maps(tmp_path, monkeypatch):
    monkeypatch.setenv("FAULTSLIP_REGISTRY", str(tmp_path / "fits.json"))
    from faultslip.friction.materials import save_user_fit
    from faultslip.studies.maps import read_map, run_map
    from faultslip.studies.grid import sweep

    preset = get_preset("black_marble_water")
    save_user_fit("my_marble", fit_rate_law(synthetic_data(preset, noise=0.001, seed=3), bootstrap=20),
                  shear_modulus=0.229e11)
    ds = sweep("san_andreas_1906.toml", lithology=["my_marble", "black_marble"])
    amplitudes = ds["slip_per_event"].values
    assert amplitudes[0] == pytest.approx(amplitudes[1], rel=0.02)  # the fit reproduces the preset it came from
    (tmp_path / "segments.csv").write_text(
        "segment,trace (degree),slip_rate (mm/yr),lithology,seismogenic_depth (km),zone_width (km)\n"
        "a,-120 35; -120 36,30,my_marble,12,20\n")
    (tmp_path / "map.toml").write_text('[map]\nbase = "san_andreas_1906.toml"\n[segments]\nfile = "segments.csv"\n'
                                       '[grid]\nlon = [-120.5, -119.5]\nlat = [35.0, 36.0]\n')
    mapped = run_map(read_map(tmp_path / "map.toml"))
    assert float(mapped["slip_per_event"].sel(segment="a")) > 0


def test_batched_bootstrap_matches_one_fit_per_resample(monkeypatch):
    """The resamples are solved all at once (Levenberg-Marquardt, analytic Jacobian); the same seed must
    give the intervals of one scipy least_squares per resample, to least_squares' own tolerance."""
    from faultslip.friction import fitting

    data = synthetic_data(get_preset("granodiorite_water"), points=120, noise=0.005, seed=4)
    batched = fitting.fit_rate_law(data, bootstrap=150, seed=7)
    monkeypatch.setattr(fitting, "_batched_fit",
                        lambda rate, mu, theta, *rest: (np.full((mu.shape[0], theta.size), np.nan), mu.shape[0]))
    single = fitting.fit_rate_law(data, bootstrap=150, seed=7)
    np.testing.assert_allclose(batched.bootstrap, single.bootstrap, rtol=1e-5)
    for name in batched.intervals:
        np.testing.assert_allclose(batched.intervals[name], single.intervals[name], rtol=1e-6)


def test_analytic_jacobian_matches_finite_differences():
    import math

    from faultslip.friction.fitting import _model_and_jacobian

    rate = np.geomspace(1e-4, 1e3, 30)
    theta = np.array([[0.55, math.log(0.1), math.log(38.0), math.log(0.665)]])
    _, jac = _model_and_jacobian(rate, theta, None)
    for k in range(4):
        step = np.zeros_like(theta)
        step[0, k] = 1e-6
        plus, _ = _model_and_jacobian(rate, theta + step, None)
        minus, _ = _model_and_jacobian(rate, theta - step, None)
        # central differences carry ~1e-10 absolute round-off: compare to that
        np.testing.assert_allclose(jac[0, k], (plus - minus)[0] / 2e-6, rtol=1e-6, atol=1e-9)
