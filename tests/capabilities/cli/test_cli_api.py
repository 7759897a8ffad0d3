"""Every computing command's --json against the same call in Python (issue 40, item 6): the command line is a
thin layer over the library, so a notebook gets the command's numbers, every one of them.

``faultslip run`` over every bundled scene is tests/capabilities/contract/test_models.py::test_the_cli_and_python_give_the_same_numbers.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import faultslip
from conftest import modelled_seconds, report_numbers
from faultslip.units import to_si

CONFIGS = Path(__file__).resolve().parents[3] / "configs"
_numbers = report_numbers


def _report(result):
    """A Result's or a Report's JSON dictionary."""
    report = result.report() if callable(getattr(result, "report", None)) else getattr(result, "report", result)
    return report.to_dict()


def _fit():
    data = faultslip.friction.read_friction_data(CONFIGS / "example_friction_data.csv")
    return faultslip.friction.fit_rate_law(data, bootstrap=50, seed=1).report("fit")


def _record():
    load = to_si("137.8 lbf", "force", "load")
    return faultslip.lab.analyze_record(faultslip.lab.read_record(CONFIGS / "example_record.csv"), load / 9.80665,
                                    to_si("1.94e4 lbf/in", "stiffness", "k"), load, None, 0.0).report("record")


#: command -> the Python call that computes the same report
CASES = {
    "fault": (["fault", "--lithology", "granodiorite_water", "--shear-modulus", "0.25e6 bar", "--zone-width", "13 mi",
               "--shear-stress", "250 bar", "--slip-rate", "2 in/yr", "--rupture-length", "270 mi", "--depth", "12 km"],
              lambda: faultslip.run(lithology="granodiorite_water", shear_modulus="0.25e6 bar", zone_width="13 mi",
                                    shear_stress="250 bar", slip_rate="2 in/yr", rupture_length="270 mi",
                                    seismogenic_depth="12 km", name="fault")),
    "simulate": (["simulate", "lab_glass_dry.toml", "--cycles", "5"],
                 lambda: faultslip.simulate("lab_glass_dry.toml", cycles=5)),
    "simulate_rate_state": (["simulate", "rsf_block_bp1.toml", "--cycles", "2"],
                            lambda: faultslip.simulate("rsf_block_bp1.toml", cycles=2)),
    "critical": (["critical", "--preset", "glass_dry", "--damping-ratio", "0.1"],
                 lambda: faultslip.models.critical(faultslip.models.SliderSystem.from_preset("glass_dry", loading_rate="1 1/s",
                                                                               damping_ratio=0.1))),
    "cycle": (["cycle", "lab_glass_dry.toml", "--loading-rate", "0.1 1/s"],
              lambda: faultslip.models.scene_cycle("lab_glass_dry.toml", loading_rate="0.1 1/s")),
    "decay": (["decay", "--stiffness", "70.5 lbf/in", "--ratio", "1.225", "--cycles-between", "10", "--frequency", "19.9 Hz"],
              lambda: faultslip.lab.free_decay(1.225, 10.0, 19.9, to_si("70.5 lbf/in", "stiffness", "k"))),
    "decay_record": (["decay", CONFIGS / "example_decay_record.csv", "--stiffness", "12346 N/m"],
                     lambda: faultslip.lab.free_decay_from_record(faultslip.lab.read_record(CONFIGS / "example_decay_record.csv"),
                                                              12346.0)),
    "fit": (["fit", CONFIGS / "example_friction_data.csv", "--bootstrap", "50", "--seed", "1"], _fit),
    "record": (["record", CONFIGS / "example_record.csv", "--stiffness", "1.94e4 lbf/in", "--normal-load", "137.8 lbf"],
               _record),
    "rate_state_simulate": (["rate-state", "simulate", "rsf_velocity_step.toml"],
                            lambda: faultslip.models.velocity_step("rsf_velocity_step.toml")),
    "rate_state_stability": (["rate-state", "stability", "rsf_block_bp1.toml"],
                             lambda: faultslip.models.rate_state_stability("rsf_block_bp1.toml")),
    "rate_state_cycles": (["rate-state", "cycles", "rsf_block_bp1.toml", "--cycles", "2"],
                          lambda: faultslip.models.earthquake_cycles("rsf_block_bp1.toml", 2)),
    "quasi_harmonic": (["quasi-harmonic", "vibration_seed002.toml", "--speeds", "5 in/s", "16 in/s", "5"],
                       lambda: faultslip.models.amplitude_study("vibration_seed002.toml", speeds=("5 in/s", "16 in/s", 5))),
    "nanoscale": (["nanoscale", "nanoscale_seed001.toml", "--damping", "13"],
                  lambda: faultslip.models.nanoscale_swing("nanoscale_seed001.toml", damping=13.0)),
    "asperity": (["asperity", "asperity_seed004.toml", "--from", "2 mm/s", "--to", "4 mm/s", "--points", "3"],
                 lambda: faultslip.models.asperity_speed_study("asperity_seed004.toml", "2 mm/s", "4 mm/s", 3)),
    "model_error": (["model-error", "rsf_block_bp1.toml", "--tolerance", "0.2"],
                    lambda: faultslip.models.model_error("rsf_block_bp1.toml", 0.2)),
    "surface": (["surface", "--synthetic", "2 um", "20 um", "--size", "64", "--modulus", "200 GPa", "--hardness",
                 "2 GPa"],
                lambda: faultslip.lab.analyze_surface(synthetic=("2 um", "20 um"), size=64, modulus="200 GPa",
                                                  hardness="2 GPa")),
    "predictability": (["predictability", CONFIGS / "catalog_san_andreas.csv", "--name", "Parkfield"],
                       lambda: faultslip.hazard.catalog_predictability(CONFIGS / "catalog_san_andreas.csv", name="Parkfield")),
    "catalog": (["catalog", CONFIGS / "catalog_san_andreas.csv", "--fault", "san_andreas_1906.toml",
                 "--as-of", "2026-01-01", "--bootstrap", "200"],
                lambda: faultslip.hazard.compare_catalog(
                    faultslip.io.read_catalog(CONFIGS / "catalog_san_andreas.csv"),
                    faultslip.models.read_slider_scene("san_andreas_1906.toml"), trace=faultslip.models.read_slider_scene("san_andreas_1906.toml").trace,
                    max_distance=25e3, cluster_fraction=0.01, horizon=to_si("30 yr", "time", "h"), bootstrap=200,
                    seed=0, as_of=np.datetime64("2026-01-01", "ms"), since=None, until=None, min_magnitude=None,
                    max_magnitude=None)),
}


@pytest.mark.parametrize("command", sorted(CASES))
def test_every_computing_command_gives_the_python_numbers(command, cli, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv, call = CASES[command]
    printed = cli(*argv, "--json")
    assert printed.code == 0, printed.err
    cli_numbers = _numbers(printed.json)
    python_numbers = _numbers(_report(call()))
    assert cli_numbers, f"{command} printed no numbers"
    assert set(cli_numbers) == set(python_numbers), set(cli_numbers) ^ set(python_numbers)
    for where, value in cli_numbers.items():  # the same code in both: the same numbers, not close ones
        other = python_numbers[where]
        assert value == other or (value != value and other != other), (where, value, other)


def test_a_sweep_file_holds_the_python_sweep(cli, tmp_path):
    import xarray as xr

    out = tmp_path / "s.nc"
    assert cli("sweep", CONFIGS / "study_vibration.toml", "-o", out, "--json").code == 0
    python = faultslip.sweep("vibration_seed002.toml", speed={"linspace": ["10 in/s", "16 in/s", 13]},
                             damping=["0.00368 lbf*s/in", "0.01 lbf*s/in"], tolerance=1e-3)
    with xr.open_dataset(out) as written:
        for name in python.data_vars:
            np.testing.assert_array_equal(written[name].values, python[name].values, err_msg=name)
        # the study file itself, swept in Python as the command sweeps it (it had been refused as a scene)
        from_file = faultslip.sweep(CONFIGS / "study_vibration.toml")
        for name in python.data_vars:
            np.testing.assert_array_equal(written[name].values, from_file[name].values, err_msg=name)
    lazy = faultslip.sweep(CONFIGS / "study_vibration.toml", chunks={"speed": 7})
    assert lazy["amplitude"].chunks is not None
    np.testing.assert_array_equal(lazy["amplitude"].values, from_file["amplitude"].values)
    from faultslip.errors import InputError

    with pytest.raises(InputError, match="is a study, which states its own grid, method, tolerance and cycles; give "
                                         "tolerance, speed in its file"):
        faultslip.sweep(CONFIGS / "study_vibration.toml", tolerance=1e-3, speed=["10 in/s"])


def test_a_sweeps_estimate_is_asked_in_python_as_on_the_command_line(cli, tmp_path):
    """faultslip.hazard.sweep_estimate gives what 'faultslip sweep STUDY --estimate' prints: the same cost model
    on the same workers (a small study in this process whatever is asked), memory and disk; a bad option is one
    sentence, as on the command line."""
    from faultslip.errors import InputError

    out = tmp_path / "s.nc"
    for workers in (1, 2):
        printed = cli("sweep", "study_rate_state.toml", "-o", out, "--estimate", "--workers", str(workers), "--json")
        assert printed.code == 0, printed.err
        python = faultslip.hazard.sweep_estimate("study_rate_state.toml", output=out, workers=workers)
        # the imports are measured in each process, and apart
        assert modelled_seconds(printed.json) == pytest.approx(python.modelled_seconds, rel=1e-9)
        assert (printed.json["memory"]["value"], printed.json["disk"]["value"]) == (python.memory, python.disk)
        assert printed.json["what"] == python.what
    assert not out.exists()
    for bad, match in (({"workers": 0}, "workers must be a whole number"), ({"chunks": 0}, "chunks must be")):
        with pytest.raises(InputError, match=match):
            faultslip.hazard.sweep_estimate("study_rate_state.toml", **bad)


def test_a_rung_is_asked_for_as_model_in_python_as_on_the_command_line(cli):
    """'faultslip run SCENE --model one_slider' is run(SCENE, model="one_slider"), as --model is --method; in
    Python a model= keyword had been taken for a fault's quantity and refused as a scene and quantities together."""
    from faultslip.errors import InputError

    by_model = faultslip.run("seas_bp1.toml", model="one_slider")
    assert by_model.method == "one_slider"
    assert _numbers(_report(by_model)) == _numbers(cli("run", "seas_bp1.toml", "--model", "one_slider", "--json").json)
    by_model, by_method = (faultslip.models.estimate("seas_bp1.toml", **{key: "one_slider"})
                           for key in ("model", "method"))
    # the same cost model; the imports the first measured, the second finds done
    assert by_model.modelled_seconds == by_method.modelled_seconds
    with pytest.raises(InputError, match="give method or model"):
        faultslip.run("seas_bp1.toml", model="one_slider", method="fault_2d")
    with pytest.raises(InputError, match="takes method \\(or model\\), tolerance and its options, not rungs"):
        faultslip.run("seas_bp1.toml", rungs="one_slider")


def test_a_map_file_holds_the_python_map(cli, tmp_path):
    import xarray as xr

    out = tmp_path / "m.nc"
    assert cli("map", CONFIGS / "san_andreas_map.toml", "-o", out, "--json").code == 0
    python = faultslip.hazard.run_map(faultslip.hazard.read_map(CONFIGS / "san_andreas_map.toml"))
    with xr.open_dataset(out) as written:
        for name in python.data_vars:
            if python[name].dtype.kind in "fi":
                np.testing.assert_array_equal(written[name].values, python[name].values, err_msg=name)


def test_a_bundled_example_is_fitted_by_name_in_python_as_on_the_command_line(cli, tmp_path, monkeypatch):
    """``faultslip.fit("example_friction_data.csv")`` outside a clone reads the bundled example, as ``faultslip fit``
    does, and gives its numbers; a name in neither place is the command's sentence, raised."""
    import json

    monkeypatch.chdir(tmp_path)
    fitted = faultslip.fit("example_friction_data.csv", bootstrap=20)
    printed = json.loads(cli("fit", "example_friction_data.csv", "--bootstrap", "20", "--json").out)
    assert fitted.values["mu_so"] == pytest.approx(printed["mu_so"], rel=1e-12)
    with pytest.raises(faultslip.errors.InputError, match="does not exist here or among the bundled examples"):
        faultslip.fit("nothere.csv")


WHOLE_CYCLES = r"cycles \(--cycles\) must be a whole number"


@pytest.mark.parametrize("options, said", [
    ({"cycles": "ten"}, WHOLE_CYCLES), ({"cycles": 2.5}, WHOLE_CYCLES), ({"cycles": float("nan")}, WHOLE_CYCLES),
    ({"cycles": True}, WHOLE_CYCLES), ({"rtol": "1e-8"}, r"rtol \(--rtol\) is a number")])
def test_a_keyword_of_the_wrong_kind_is_refused_in_one_sentence(options, said):
    """A notebook's simulate(cycles="ten") is refused naming the keyword and its kind, as the command line's parser
    refuses --cycles ten (it had met a TypeError from the family: "'<' not supported between 'str' and 'int'")."""
    with pytest.raises(faultslip.errors.InputError, match=said):
        faultslip.simulate("lab_glass_dry.toml", **options)


def test_a_whole_count_of_another_type_is_taken_as_the_count():
    """cycles=3.0 and numpy's int64 3 simulate the 3 cycles cycles=3 does."""
    counts = {faultslip.simulate("lab_glass_dry.toml", cycles=cycles).to_xarray().sizes["event"]
              for cycles in (3, 3.0, np.int64(3))}
    assert counts == {3}


@pytest.mark.parametrize("options", [{"bootstrap": -1}, {"bootstrap": "many"}, {"bootstrap": 2.5}, {"seed": -3},
                                     {"seed": True}])
def test_a_fits_resamples_and_seed_are_whole_numbers_in_python_as_on_the_command_line(options, cli):
    """fit(bootstrap=-1) is refused as --bootstrap -1 is (it had run, and bootstrap='many' had met a TypeError);
    200.0 resamples are 200."""
    name = next(iter(options))
    with pytest.raises(faultslip.errors.InputError, match=f"{name} must be a whole number"):
        faultslip.fit("example_friction_data.csv", **options)
    if options[name] in (-1, -3):
        result = cli("fit", "example_friction_data.csv", f"--{name}", options[name])
        assert result.code == 2 and f"--{name} must be a whole number" in result.err
    whole, counted = (faultslip.fit("example_friction_data.csv", bootstrap=count, seed=1) for count in (20.0, 20))
    assert len(whole.bootstrap) == 20 and np.array_equal(whole.bootstrap, counted.bootstrap)
    assert whole.intervals == counted.intervals


def test_a_maps_tolerance_is_read_in_python_as_on_the_command_line():
    """map(tolerance='x') is refused in one sentence (it had met numpy's UFuncTypeError), and '10 %' is 0.1."""
    for call in (faultslip.map, faultslip.hazard.map_estimate):
        with pytest.raises(faultslip.errors.InputError, match="tolerance must be a relative error"):
            call("san_andreas_map.toml", tolerance="x")
    assert faultslip.map("san_andreas_map.toml", tolerance="10 %").equals(
        faultslip.map("san_andreas_map.toml", tolerance=0.1))
