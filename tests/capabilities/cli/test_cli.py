"""The command line: the main job, the --json contract, and clean errors (exit 2, one sentence)."""

import subprocess
import sys

import pint
import pytest

from conftest import assert_clean_error

FAULT = ["fault", "--lithology", "granodiorite", "--zone-width", "13 mi", "--shear-stress", "250 bar",
         "--slip-rate", "2 in/yr"]


def test_run_without_arguments_prints_the_1906_estimate(cli):
    result = cli("run")
    assert result.code == 0, result.err
    assert "San Andreas fault, 1906" in result.out
    assert "21.12 ft" in result.out and "126.72 yr" in result.out and "5.001e-11 1/s" in result.out


def test_fault_json_contract(cli):
    result = cli(*FAULT, "--rupture-length", "270 mi", "--depth", "12 km", "--json")
    assert result.code == 0, result.err
    data = result.json
    ureg = pint.UnitRegistry()
    for key in ("stiffness", "normal_stress", "loading_rate", "slip_per_event", "recurrence_period",
                "stress_drop", "seismic_moment"):
        assert set(data[key]) == {"value", "units"}, key
        ureg.Quantity(data[key]["value"], data[key]["units"])  # pint-parsable
    assert isinstance(data["static_friction"], float) and isinstance(data["moment_magnitude"], float)
    assert data["slip_per_event"]["units"] == "m"
    assert data["slip_per_event"]["value"] == pytest.approx(6.43737, rel=1e-5)
    assert ureg.Quantity(data["recurrence_period"]["value"], data["recurrence_period"]["units"]).to("year").m == pytest.approx(126.72, abs=0.01)


def test_fault_without_rupture_size_omits_moment(cli):
    data = cli(*FAULT, "--json").json
    assert "seismic_moment" not in data and "moment_magnitude" not in data


def test_inverse_form_reports_implied_kinetic_friction(cli):
    result = cli("fault", "--lithology", "granite", "--zone-width", "13 mi", "--shear-stress", "250 bar",
                 "--slip-rate", "2 in/yr", "--mu-so", "0.65", "--observed-slip", "21 ft", "--json")
    assert result.code == 0, result.err
    assert result.json["kinetic_friction"] == pytest.approx(0.570455, abs=1e-6)


def test_materials_lists_presets_and_lithologies(cli):
    text = cli("materials")
    assert text.code == 0 and "granodiorite_water" in text.out and "green_schist_dry" in text.out
    data = cli("materials", "--json").json
    assert len(data["presets"]) == 14 and {row["name"] for row in data["lithologies"]} >= {"granite", "pyrite"}
    steel = next(row for row in data["presets"] if row["name"] == "steel_heavy_petrolatum")
    assert steel["mass"]["units"] == "kg" and steel["source"] == "seed 003 Table I row 1"


def test_rate_law_plot_is_written(cli, tmp_path):
    out = tmp_path / "rate_law.png"
    result = cli("plot", "rate-law", "--preset", "glass_dry", "--preset", "granodiorite_water", "-o", out)
    assert result.code == 0, result.err
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not list(tmp_path.glob(".*tmp"))  # no temporary left behind


# --- every bad-input case of DEVELOPERS.md: exit 2, one sentence naming the input ---


def test_negative_modulus(cli):
    assert_clean_error(cli(*FAULT, "--shear-modulus", "-0.25e6 bar"), "shear modulus", "positive")


def test_mu_m_not_below_mu_so_where_stick_slip_is_required(cli):
    assert_clean_error(cli(*FAULT, "--mu-m", "0.65"), "mu_m", "mu_so", "stick-slip")
    assert_clean_error(cli(*FAULT, "--mu-m", "0.7"), "mu_m", "mu_so")


def test_unknown_lithology_suggests_near_matches(cli):
    assert_clean_error(cli(*[a if a != "granodiorite" else "granodorite" for a in FAULT]),
                       "unknown lithology", "granodorite", "did you mean granodiorite")


def test_unit_that_does_not_fit(cli):
    assert_clean_error(cli(*FAULT[:-1], "2 bar"), "slip rate", "speed", "2 bar")
    assert_clean_error(cli(*FAULT, "--depth", "12 s", "--rupture-length", "270 mi"), "seismogenic depth", "length")


def test_nan_in_the_input(cli):
    assert_clean_error(cli(*FAULT, "--mu-m", "nan"), "mu_m", "finite")
    assert_clean_error(cli(*FAULT, "--shear-modulus", "nan bar"), "shear modulus", "finite")


def test_unknown_key_in_a_config(cli, tmp_path):
    scene = tmp_path / "bad.toml"
    scene.write_text('[scene]\nkind = "fault"\n[fault]\nzone_widht = "13 mi"\n')
    assert_clean_error(cli("run", scene), "zone_widht", "did you mean zone_width", "bad.toml")


def test_missing_scene_file_and_bad_flags(cli):
    assert_clean_error(cli("run", "/no/such/scene.toml"), "does not exist")
    assert_clean_error(cli("fault", "--bogus"), "unrecognized arguments")


def test_console_script_exits_2_without_traceback():
    result = subprocess.run(
        [sys.executable, "-m", "faultslip.cli", *FAULT[:-1], "2 bar"], capture_output=True, text=True, timeout=120
    )
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert result.stderr.strip() == (
        'faultslip: error: slip rate must be a speed such as "2 in/yr" or "24 mm/yr", got 2 bar'
    )


@pytest.mark.parametrize("command, wanted", [(("run",), "scene"), (("methods",), "scene"), (("simulate",), "scene"),
                                             (("sweep", "-o", "out.nc"), "study"), (("map", "-o", "out.nc"), "map")])
def test_a_study_map_or_scene_given_to_the_wrong_command_is_named_with_the_command_that_runs_it(command, wanted,
                                                                                                 cli, tmp_path):
    """A study given to 'faultslip run' had been refused as a scene with 'unknown table [study]', and a scene given
    to 'faultslip sweep' as a study with 'unknown table [name]': each now says what it is and what runs it."""
    files = {"study": ("configs/study_asperity.toml", "faultslip sweep study_asperity.toml -o OUTPUT"),
             "map": ("configs/san_andreas_map.toml", "faultslip map san_andreas_map.toml -o OUTPUT"),
             "scene": ("configs/asperity_seed004.toml", "faultslip run asperity_seed004.toml")}
    for kind, (path, runs) in files.items():
        if kind == wanted:
            continue
        verb, *options = command
        options = [str(tmp_path / option) if option.endswith(".nc") else option for option in options]
        refused = cli(verb, path, *options)
        assert_clean_error(refused, f"is a {kind}, not a {wanted}", runs)
        assert not list(tmp_path.iterdir())  # nothing written
    # a study's base scene is named where a scene was wanted
    if wanted == "scene":
        assert "its base scene, asperity_seed004.toml, is one" in cli(verb, "configs/study_asperity.toml").err


def test_the_methods_listing_is_folded_and_says_what_its_json_says(cli):
    """'faultslip methods' printed each field on one line (up to 600 characters); folded at a report's width, its
    text still carries every word of every field its --json gives."""
    from faultslip.io.report import LINE_WIDTH

    text, rows = cli("methods").out, cli("methods", "--json").json["methods"]
    assert max(len(line) for line in text.splitlines()) <= LINE_WIDTH
    words = " ".join(text.split())
    for row in rows:
        for key in ("friction_laws", "domain", "cost_model", "declared_error", "selected_by"):
            assert " ".join(row[key].split()) in words, (row["name"], key)


def test_a_data_command_finds_a_bundled_example_by_bare_name_and_a_local_file_first(cli, tmp_path, monkeypatch):
    """Outside a clone, the data commands' examples are found by name (a wheel ships them in the package), and the
    command says so on stderr; a file of that name here is read instead; a name in neither is one sentence listing
    the examples, exit 2."""
    import json

    from faultslip.io.resources import bundled_examples

    monkeypatch.chdir(tmp_path)
    examples = bundled_examples()
    assert {"example_velocity_steps.csv", "example_record.csv", "catalog_san_andreas.csv", "example_surface.csv",
            "example_lab_glass.zarr", "p655_r"} <= set(examples)
    assert not any(name.endswith((".toml", ".py", ".md")) for name in examples)
    bundled = cli("fit", "example_friction_data", "--bootstrap", "20", "--json")
    assert bundled.code == 0 and "bundled example example_friction_data.csv" in bundled.err
    assert 0.5 < json.loads(bundled.out)["mu_so"] < 1
    # the same name here wins: the first 12 rows of the example, fitted to their own numbers
    rows = examples["example_friction_data.csv"].read_text(encoding="utf-8").splitlines()
    (tmp_path / "example_friction_data.csv").write_text("\n".join(rows[:13]) + "\n", encoding="utf-8")
    local = cli("fit", "example_friction_data.csv", "--bootstrap", "20", "--json")
    assert local.code == 0 and "bundled" not in local.err
    assert json.loads(local.out)["mu_so"] != json.loads(bundled.out)["mu_so"]
    missing = assert_clean_error(cli("record", "nothere.csv"), "does not exist here or among the bundled examples",
                                 "example_record.csv")
    assert not list(tmp_path.glob("*.nc")), missing
    # refused after finding an example, or before: one sentence, no note of the example found
    assert_clean_error(cli("record", "example_record.csv"), "needs --stiffness")
    # a further record missing: one sentence, no note of the example found before it
    assert_clean_error(cli("fit", "--law", "rate-state", "example_velocity_steps.csv", "--joint", "nothere.csv",
                           "--stiffness", "1e-2 1/um"), "record 'nothere.csv' does not exist here")
    (tmp_path / "example_record.csv").symlink_to(tmp_path / "gone.csv")  # the user's own, gone: not the bundled one
    assert_clean_error(cli("record", "example_record.csv"), "is a link to a file that does not exist")
