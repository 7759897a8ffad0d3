"""The Python API as a notebook user meets it (issue 32): one test per capability, public names only,
units in and units out. Expected values are computed here or by the CLI in the same test."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import faultslip
from faultslip.units import units

CONFIGS = Path(__file__).resolve().parents[2] / "configs"
DATA = Path(__file__).resolve().parents[2] / "data"


def test_the_1906_estimate_with_units():
    """Seed 003 §5-2: K = G/D, slip = 2 tau_excess / K times the overshoot; recomputed from the inputs."""
    fault = faultslip.models.Fault(lithology="granodiorite_water", shear_modulus=0.25e6 * units.bar,
                            zone_width="13 mi", shear_stress="250 bar", slip_rate=2 * units("in/yr"))
    estimate = fault.estimate()
    slip = estimate["slip_per_event"]
    recurrence = estimate["recurrence_period"]
    assert slip.check("[length]") and recurrence.check("[time]")
    # the recurrence is the slip over the loading rate, whatever the friction law gave
    assert (slip / (2 * units("in/yr"))).to("yr").magnitude == pytest.approx(recurrence.to("yr").magnitude, rel=1e-12)
    # and the stress drop is K times the slip, K = G / D, within the estimate's declared tolerance (1e-6:
    # the slip carries the overshoot, found by root-finding)
    stiffness = 0.25e6 * units.bar / (13 * units.mi)
    assert (stiffness * slip).to("bar").magnitude == pytest.approx(estimate["stress_drop"].to("bar").magnitude,
                                                                   rel=1e-6)
    result = faultslip.run("san_andreas_1906.toml")
    assert result["slip_per_event"].to("m").magnitude == pytest.approx(slip.to("m").magnitude, rel=1e-9)


def test_a_sweep_from_quantities():
    rates = [10, 20, 40] * units("mm/yr")
    dataset = faultslip.sweep("san_andreas_1906.toml", slip_rate=list(rates), zone_width=[10 * units.km, "13 mi"])
    assert dataset["slip_per_event"].dims == ("slip_rate", "zone_width") or set(dataset["slip_per_event"].dims) == {
        "slip_rate", "zone_width"}
    assert dataset["slip_rate"].attrs["units"] == "m/s"
    assert np.allclose(dataset["slip_rate"].values, rates.to("m/s").magnitude, rtol=1e-12)
    recurrence = dataset["recurrence_period"].transpose("slip_rate", "zone_width")
    slip = dataset["slip_per_event"].transpose("slip_rate", "zone_width")
    # recurrence is slip over the loading rate, cell by cell (the static friction itself depends on the rate)
    np.testing.assert_allclose(recurrence.values, (slip / dataset["slip_rate"]).values, rtol=1e-12)
    # a wider elastic zone is a softer spring: more slip per event
    assert np.all(slip.isel(zone_width=1) > slip.isel(zone_width=0))
    with pytest.raises(faultslip.InputError, match="slip_rate"):
        faultslip.sweep("san_andreas_1906.toml", slip_rate=[3 * units.s])


def test_a_map_from_python_objects_matches_the_same_map_from_files():
    table = pd.read_csv(DATA / "san_andreas_segments.csv")
    frame = pd.DataFrame({
        "segment": table["segment"],
        "trace": table["trace (degree)"],
        "slip_rate": [f"{value} mm/yr" for value in table["slip_rate (mm/yr)"]],
        "lithology": table["lithology"],
        "seismogenic_depth": list(table["seismogenic_depth (km)"].to_numpy() * units.km),
        "zone_width": (table["zone_width (mi)"].to_numpy() * units.mi).to("m").magnitude,  # floats are SI
    })
    lon, lat = np.linspace(-125.0, -114.5, 106), np.linspace(32.5, 40.5, 81)
    spec = faultslip.hazard.segment_map(frame, lon, lat, scene="san_andreas_1906.toml", max_distance=60 * units.km)
    from_python = faultslip.hazard.run_map(spec)
    from_files = faultslip.hazard.run_map(faultslip.hazard.read_map(CONFIGS / "san_andreas_map.toml"))
    for name in ("slip_per_event", "recurrence_period"):
        assert from_python[name].attrs["units"] == from_files[name].attrs["units"]
        np.testing.assert_allclose(from_python[name].values, from_files[name].values, rtol=1e-12, equal_nan=True)
    with pytest.raises(faultslip.InputError, match="slip_rate"):
        faultslip.hazard.segment_map(frame.assign(slip_rate="2 kg"), lon, lat)


def test_a_catalog_comparison():
    catalog = faultslip.io.read_catalog(CONFIGS / "catalog_san_andreas.csv")
    scene = faultslip.models.read_slider_scene(CONFIGS / "parkfield.toml")
    comparison = faultslip.hazard.compare_catalog(catalog, scene, trace=scene.trace, max_distance="25 km", horizon="30 yr",
                                           bootstrap=0, as_of=np.datetime64("2026-01-01"))
    same = faultslip.hazard.compare_catalog(catalog, scene, trace=scene.trace, max_distance=25e3,
                                     horizon=30 * faultslip.JULIAN_YEAR, bootstrap=0, as_of=np.datetime64("2026-01-01"))
    assert comparison.report("a").to_dict() == same.report("a").to_dict()
    report = comparison.report().to_dict()
    assert len(comparison.selected) >= 3 and comparison.fits
    # every probability printed is a probability
    for key, value in report.items():
        if "probability" in key and isinstance(value, (int, float)):
            assert 0 <= value <= 1


def test_a_rate_and_state_fit_from_a_dataframe():
    frame = pd.read_csv(CONFIGS / "example_velocity_steps.csv")
    fit = faultslip.lab.fit_velocity_steps(frame, "1e-2 1/um")
    from_file = faultslip.lab.fit_velocity_steps(faultslip.lab.read_step_record(CONFIGS / "example_velocity_steps.csv"),
                                             1e-2 / 1e-6)
    for name in ("a", "b", "critical_slip"):
        assert fit.parameters[name] == pytest.approx(from_file.parameters[name], rel=1e-12)
    # the fitted law is velocity weakening or strengthening by b - a, with a's interval around it
    low, high = fit.intervals["a"]
    assert low <= fit.parameters["a"] <= high
    columns = {"time": frame["time (s)"].to_numpy() * units.s, "friction": frame["friction"].to_numpy(),
               "load_point_speed": frame["load_point_speed (um/s)"].to_numpy() * units("um/s")}
    assert faultslip.lab.fit_velocity_steps(columns, 1e-2 / units.um).parameters["b"] == pytest.approx(
        fit.parameters["b"], rel=1e-12)


def test_a_phyphox_record():
    record = faultslip.lab.read_accelerometer(CONFIGS / "example_phyphox.csv")
    analysis = faultslip.lab.analyze_accelerometer(record)
    report = analysis.report().to_dict()
    assert record.time.size > 100 and np.all(np.diff(record.time) > 0)
    assert analysis.starts.size >= 3 and report
    # each friction drop is the break-away deceleration over g (a phone measures m/s^2)
    np.testing.assert_allclose(analysis.friction_drop * 9.80665, analysis.peak_acceleration, rtol=1e-12)
    figure = faultslip.plots.classroom_figure(analysis)
    assert figure.axes
    import matplotlib.pyplot as plt

    plt.close(figure)


def test_outputs_quantify_with_pint_xarray():
    """faultslip keeps units as CF attributes (netCDF keeps them); pint-xarray reads them as they are."""
    pytest.importorskip("pint_xarray")
    swept = faultslip.sweep("san_andreas_1906.toml", slip_rate=["10 mm/yr", "20 mm/yr"]).pint.quantify()
    recurrence = swept["recurrence_period"].pint.to("yr")
    slip = swept["slip_per_event"].pint.to("m")
    rate = swept["slip_rate"].pint.to("m/yr")
    np.testing.assert_allclose(recurrence.pint.magnitude, (slip / rate).pint.to("yr").pint.magnitude, rtol=1e-12)
    single = faultslip.run("san_andreas_1906.toml")
    quantified = single.to_xarray().pint.quantify()
    assert float(quantified["slip_per_event"].pint.to("ft").pint.magnitude) == pytest.approx(
        single["slip_per_event"].to("ft").magnitude, rel=1e-12)
