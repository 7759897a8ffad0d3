"""One contract over every model family (issue 32): a scene in, a Result out, the same in Python and on the CLI."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import faultslip
from conftest import assert_clean_error
from faultslip import models
from faultslip.errors import InputError

CONFIGS = Path(__file__).resolve().parent.parent / "configs"

#: A bundled scene of each family; a family added to the registry without one here fails the first test.
SCENES = {
    "spring_slider": "lab_glass_dry.toml",
    "rate_state_slider": "rsf_velocity_step.toml",
    "vibration": "vibration_seed002.toml",
    "nanoscale": "nanoscale_seed001.toml",
    "asperity": "asperity_seed004.toml",
    "rough_surface": "rough_surface_seed000.toml",
    "fault_2d": "fault_2d_small.toml",
}


def test_every_registered_family_has_a_scene_here():
    assert sorted(models.families()) == sorted(SCENES)


@pytest.mark.parametrize("family", sorted(SCENES))
def test_a_scene_names_its_family(family):
    assert models.family_of(CONFIGS / SCENES[family]).name == family


@pytest.mark.parametrize("family", sorted(SCENES))
def test_every_family_runs_through_one_contract(family, tmp_path, cli):
    import xarray as xr

    scene = CONFIGS / SCENES[family]
    result = faultslip.run(scene)
    assert isinstance(result, faultslip.Result) and result.family == family
    # the CLI prints the same report (wall times aside: the same keys, the same method)
    printed = cli("run", scene, "--json").json
    assert set(printed) == set(result.report().to_dict()) and printed.get("method") == result.method
    # the summary's quantities carry units (seed 001's model is written in dimensionless variables)
    quantities = [key for key in result.keys() if hasattr(result[key], "units")]
    assert quantities or family == "nanoscale", result.keys()
    # to_xarray round-trips through netCDF with its units
    dataset = result.to_xarray()
    dataset.to_netcdf(tmp_path / "r.nc")
    with xr.open_dataset(tmp_path / "r.nc") as back:
        for key in quantities:
            if key in back and back[key].ndim == 0:
                assert back[key].attrs["units"] == dataset[key].attrs["units"]
                assert float(back[key]) == pytest.approx(result[key].magnitude, rel=1e-12, nan_ok=True)
    # a run that recorded no time series says so; a simulation has one, and the family's figure
    if result.series is None:
        with pytest.raises(InputError, match="no time series"):
            result.time_series()
    simulated = models.simulate(scene)
    series = simulated.time_series()
    assert "time" in series.dims and series.sizes["time"] > 1
    assert simulated.to_xarray().attrs["faultslip_family"] == family
    figure = simulated.plot()
    assert figure.axes
    import matplotlib.pyplot as plt

    plt.close(figure)


def test_the_method_and_its_declared_error_travel_with_the_result():
    result = faultslip.run("san_andreas_1906.toml")
    assert result.method == "closed_form"
    assert result.method_reason
    assert 0 <= result.estimated_relative_error < 1e-6
    slip = result["slip_per_event"]
    assert slip.to("ft").magnitude == pytest.approx(21.12, abs=0.01)  # seed 003 §5-2 computed: 6.437 m
    assert result["recurrence_period"].to("yr").magnitude == pytest.approx(126.7, abs=0.1)
    assert result.to_xarray().attrs["method"] == "closed_form"


def test_an_option_a_family_does_not_take_is_one_sentence(cli):
    with pytest.raises(InputError, match="--slip-solver applies to seed-law scenes"):
        models.simulate(CONFIGS / "vibration_seed002.toml", slip_solver="DOP853")
    assert_clean_error(cli("simulate", CONFIGS / "asperity_seed004.toml", "--cycles", "3"), "--cycles applies")


def test_a_declared_family_wins_and_an_unknown_one_is_refused(tmp_path):
    scene = tmp_path / "v.toml"
    scene.write_text('family = "vibration"\n' + (CONFIGS / "vibration_seed002.toml").read_text(encoding="utf-8"),
                     encoding="utf-8")
    assert models.family_of(scene).name == "vibration"
    assert faultslip.run(scene).family == "vibration"
    scene.write_text('family = "vibraton"\n' + (CONFIGS / "vibration_seed002.toml").read_text(encoding="utf-8"),
                     encoding="utf-8")
    with pytest.raises(InputError, match="did you mean vibration"):
        models.family_of(scene)


def test_the_rate_and_state_slider_runs_through_run_too(cli):
    """'faultslip run' refused these scenes before the contract; a fault's cycles now answer."""
    result = cli("run", CONFIGS / "rsf_fault_bp1.toml", "--json")
    assert result.code == 0, result.err
    years = result.json["recurrence_period"]["value"] / (365.25 * 86400)
    assert 100 < years < 200  # one spring-block with BP1 friction: about 140 yr (docs/rate_state.md)
    assert np.isclose(result.json["plate_slip_balance"], 1.0, atol=0.01)


def test_a_fault_estimate_gives_its_values_with_units():
    """Fault.estimate() kept bare SI floats; its quantities now carry units (seed 003 §5-2, computed)."""
    estimate = faultslip.Fault(lithology="granodiorite_water", shear_modulus="0.25e6 bar", zone_width="13 mi",
                               shear_stress="250 bar", slip_rate="2 in/yr").estimate()
    assert estimate["slip_per_event"].to("ft").magnitude == pytest.approx(21.12, abs=0.01)
    assert estimate["recurrence_period"].to("yr").magnitude == pytest.approx(126.7, abs=0.1)
    assert estimate.quantities()["stress_drop"].to("bar").magnitude == pytest.approx(76.9, abs=0.1)
    with pytest.raises(KeyError, match="not a quantity"):
        estimate["slip"]


def test_run_takes_allow_large_where_a_family_has_a_budget(cli, monkeypatch):
    """A nanoscale run beyond the time budget is refused before any work; --allow-large runs it."""
    monkeypatch.setenv("FAULTSLIP_TIME_BUDGET", "1e-6")
    refused = cli("run", CONFIGS / "nanoscale_seed001.toml", "--json")
    assert refused.code == 2 and "--allow-large" in refused.err
    allowed = cli("run", CONFIGS / "nanoscale_seed001.toml", "--json", "--allow-large")
    assert allowed.code == 0, allowed.err
    # a family without a budget needs no permission, and takes the flag without complaint
    assert cli("run", "san_andreas_1906.toml", "--json", "--allow-large").code == 0
