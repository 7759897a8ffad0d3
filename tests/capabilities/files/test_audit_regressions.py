"""Regression tests for the second audit (issue 26): each case was a traceback or a silent wrong answer."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from conftest import assert_clean_error
from faultslip.cli.main import build_parser

ROOT = Path(__file__).resolve().parents[3]
CONFIGS = ROOT / "configs"


def _subcommands(parser, prefix=()):
    for action in parser._actions:  # argparse keeps its subparsers here
        if hasattr(action, "choices") and isinstance(action.choices, dict):
            for name, sub in action.choices.items():
                yield prefix + (name,)
                yield from _subcommands(sub, prefix + (name,))


@pytest.mark.parametrize("words", sorted(set(_subcommands(build_parser()))))
def test_every_help_text_renders(cli, words):
    """'fit --help' crashed on the '%' of "95 % band" (argparse formats help with %)."""
    result = cli(*words, "--help")
    assert result.code == 0, result.err
    assert "usage:" in result.out


def test_an_unknown_scheduler_is_one_sentence_before_any_work(cli, tmp_path):
    result = cli("sweep", CONFIGS / "study_spring_slider.toml", "-o", tmp_path / "s.nc", "--scheduler", "x")
    assert_clean_error(result, "--scheduler", "'x'")
    assert not list(tmp_path.iterdir())


def test_a_runaway_polynomial_is_refused_with_the_friction_it_reaches(cli, tmp_path):
    scene = tmp_path / "qh.toml"
    scene.write_text((CONFIGS / "vibration_seed002.toml").read_text(encoding="utf-8").replace(
        "polynomial = [0.5, -0.01, 0.0, 1.4814814814814815e-05]", "polynomial = [0.5, -0.01, 0.0, 1e300]"),
        encoding="utf-8")
    assert "1e300" in scene.read_text(encoding="utf-8")
    assert_clean_error(cli("run", scene), "polynomial", "friction coefficient")


def test_kinetic_friction_above_static_is_refused(cli, tmp_path):
    scene = tmp_path / "poly.toml"
    scene.write_text((CONFIGS / "lab_steel_dry_polynomial.toml").read_text(encoding="utf-8").replace(
        "polynomial = [0.39, -0.05, 0.5]", "polynomial = [0.9, -0.05, 0.5]"), encoding="utf-8")
    for command in ("run", "simulate"):
        assert_clean_error(cli(command, scene), "kinetic friction at rest", "not below")


def test_a_stream_past_year_9999_is_refused_before_anything_is_written(cli, tmp_path):
    """100 cycles of 1906 span 12,957 yr from 2000: obspy cannot date the end (the audit: 65 MB, then a crash)."""
    result = cli("simulate", "san_andreas_1906.toml", "--stream", tmp_path / "x.mseed", "--events", tmp_path / "x.xml")
    assert_clean_error(result, "past year 9999", "at most 60 cycles")
    assert not list(tmp_path.iterdir())
    assert cli("simulate", "san_andreas_1906.toml", "--cycles", "60", "--events", tmp_path / "x.xml").code == 0


@pytest.mark.parametrize("header, needle", [
    ('"Time (s)","Linear Acceleration y (m/s^2)","Linear Acceleration y (m/s^2)"', "appears twice"),
    ('"Time (ms)","Linear Acceleration x (m/s^2)","Linear Acceleration y (m/s^2)"', "check the time column's unit"),
])
def test_phyphox_header_mistakes_are_refused(cli, tmp_path, header, needle):
    lines = (CONFIGS / "example_phyphox.csv").read_text(encoding="utf-8").splitlines()
    rows = [",".join(line.split(",")[:3]) for line in lines[1:]]
    path = tmp_path / "phone.csv"
    path.write_text("\n".join([header] + rows) + "\n", encoding="utf-8")
    assert_clean_error(cli("record", path), needle)


def test_the_bundled_phyphox_record_still_gives_a_positive_pull_speed(cli):
    result = cli("record", CONFIGS / "example_phyphox.csv", "--json")
    assert result.code == 0
    assert result.json["pull_speed"]["value"] > 0


@pytest.mark.parametrize("mu0", ["-0.6", "0.0", "5.0"])
def test_a_reference_friction_outside_the_physical_range_is_refused(cli, tmp_path, mu0):
    text = (CONFIGS / "rsf_velocity_step.toml").read_text(encoding="utf-8")
    scene = tmp_path / "rsf.toml"
    scene.write_text(text.replace('preset = "step_example"',
                                   f'a = 0.005\nb = 0.01\ncritical_slip = "10 um"\nmu0 = {mu0}'), encoding="utf-8")
    assert f"mu0 = {mu0}" in scene.read_text(encoding="utf-8")
    assert_clean_error(cli("rate-state", "simulate", scene), "mu0")


def test_a_catalog_depth_above_the_land_is_refused(cli, tmp_path):
    lines = (CONFIGS / "catalog_san_andreas.csv").read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    column = next(i for i, name in enumerate(header) if name.startswith("depth"))
    row = lines[1].split(",")
    row[column] = "-5"
    path = tmp_path / "c.csv"
    path.write_text("\n".join([lines[0], ",".join(row)] + lines[2:]) + "\n", encoding="utf-8")
    assert_clean_error(cli("catalog", path, "--fault", CONFIGS / "parkfield.toml"), "depth -5 km")


def test_a_nanoscale_run_beyond_the_budget_is_refused_up_front(cli, tmp_path):
    scene = tmp_path / "nano.toml"
    scene.write_text((CONFIGS / "nanoscale_seed001.toml").read_text(encoding="utf-8").replace(
        "duration = 3000.0", "duration = 1e9"), encoding="utf-8")
    assert "duration = 1e9" in scene.read_text(encoding="utf-8")
    for argv in (["nanoscale", scene], ["simulate", scene]):
        assert_clean_error(cli(*argv), "--allow-large", "days")
    # run reports the settled cycle, which integrates until it settles (within its own bounded horizon),
    # not over the scene's duration
    assert cli("run", scene, "--json").code == 0


def test_a_map_of_1e10_cells_is_refused_with_its_estimate(cli, tmp_path):
    text = (CONFIGS / "california_faults_map.toml").read_text(encoding="utf-8")
    text = text.replace("-116.0, 71]", "-116.0, 100000]").replace("38.5, 56]", "38.5, 100000]")
    text = text.replace('"../data/', f'"{ROOT}/data/').replace('base = "', f'base = "{CONFIGS}/')
    path = tmp_path / "huge.toml"
    path.write_text(text, encoding="utf-8")
    assert_clean_error(cli("map", path, "-o", tmp_path / "h.nc"), "1e+10 cells", "memory")


def test_a_field_constant_within_the_tolerance_draws_as_one_colour():
    from faultslip.studies.maps import colour_limits

    limits, constant = colour_limits(6.43737 + 1e-6 * np.random.default_rng(0).random(50), 1e-6)
    assert constant == pytest.approx(6.43737, rel=1e-6)
    assert limits[1] - limits[0] == pytest.approx(0.02 * constant)
    limits, constant = colour_limits(np.array([1.0, 2.0, np.nan]), 1e-6)
    assert constant is None and limits == (1.0, 2.0)


def test_no_observed_figure_is_written_where_nothing_is_observed(cli, tmp_path):
    result = cli("map", CONFIGS / "california_faults_map.toml", "-o", tmp_path / "m.nc", "--plot", tmp_path / "m.png",
                 "--json")
    assert result.code == 0, result.err
    assert not (tmp_path / "m_observed.png").exists()
    assert any("observed figure is not drawn" in note for note in result.json["notes"])
    assert cli("map", CONFIGS / "san_andreas_map.toml", "-o", tmp_path / "s.nc", "--plot", tmp_path / "s.png").code == 0
    assert (tmp_path / "s_observed.png").exists()  # the segment table has observations


def test_sweep_flags_list_every_value_they_use(tmp_path):
    """-1 in regime and method must be a flag value, named, and explained by outside_domain."""
    from faultslip.fault.spring_slider_cells import output_attrs

    plain = output_attrs("regime", "fault")
    assert -1 not in plain["flag_values"] and "outside_domain" not in plain["long_name"]
    flagged = output_attrs("method", "fault", outside_domain=True)
    assert -1 in flagged["flag_values"]
    assert flagged["flag_meanings"].split()[list(flagged["flag_values"]).index(-1)] == "no_prediction"
    assert "outside_domain" in flagged["long_name"]


def test_run_time_is_an_elapsed_time_not_a_dateless_time_axis(cli, tmp_path):
    import xarray as xr

    assert cli("simulate", "lab_glass_dry.toml", "--cycles", "3", "-o", tmp_path / "g.nc").code == 0
    with xr.open_dataset(tmp_path / "g.nc") as dataset:
        attrs = dataset["time"].attrs
    assert attrs["units"] == "s" and "axis" not in attrs  # CF: a time axis needs "since"; a duration does not
    assert np.issubdtype(dataset["time"].dtype, np.floating)


def test_dopri5_starts_from_a_state_far_beyond_its_scale():
    """A mutated rate-and-state map (fuzzer seed 2611) overflowed the first-step estimate's squares."""
    from faultslip.dynamics.rate_state.slider import dopri5
    from faultslip.errors import SolverError

    def rhs(t, y):
        return (1e200 * y[1], -y[0])

    from faultslip.dynamics.rate_state.slider import _StepCollapse

    # the state's own scale is reached: dopri5 says where the solution stops being finite (its callers name the
    # method and the scene); before, the first-step estimate raised OverflowError
    with pytest.raises((SolverError, _StepCollapse)):
        dopri5(rhs, 0.0, (1e200, 1e200), 1e-3, np.array([1e-3]), 1e-6, (1e-12, 1e-12), max_steps=2000)
