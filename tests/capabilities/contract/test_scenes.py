"""Bundled scenes load, validate and run; scene files state their units."""

from pathlib import Path

import pytest

from faultslip.errors import InputError
from faultslip.fault.scene import read_slider_scene, parse_scene, run_scene
from faultslip.io.resources import bundled_scenes


def test_bundled_scenes_include_1906_granite_and_every_table_i_preset():
    names = set(bundled_scenes())
    assert {"san_andreas_1906.toml", "granite_inverse_1906.toml"} <= names
    from faultslip.friction.materials import table_i_presets

    assert {f"lab_{p.name}.toml" for p in table_i_presets()} <= names


@pytest.mark.parametrize("name", bundled_scenes())
def test_every_bundled_scene_runs(name):
    report = run_scene(read_slider_scene(name))
    data = report.to_dict()
    assert "slip_per_event" in data or "kinetic_friction" in data


def test_lab_scene_uses_the_preset_apparatus():
    scene = read_slider_scene("lab_pyrite_dry.toml")
    system = scene.slider()
    assert system.normal_load == pytest.approx(430.6 * 4.4482216152605)
    assert system.platform_speed == pytest.approx(1e-4 * 0.0254)


def test_scene_without_units_or_with_wrong_kind_is_rejected():
    with pytest.raises(InputError, match="must state its units"):
        parse_scene('[scene]\nkind = "fault"\n[fault]\nslip_rate = 2\n')
    with pytest.raises(InputError, match="slip_rate in <scene> must be a speed"):
        parse_scene('[scene]\nkind = "fault"\n[fault]\nslip_rate = "2 bar"\n')
    with pytest.raises(InputError, match="kind in <scene> must be one of fault, lab"):
        parse_scene('[scene]\nkind = "quake"\n')
    with pytest.raises(InputError, match=r"unknown table \[faults\]"):
        parse_scene('[scene]\nkind = "fault"\n[faults]\nx = 1\n')
    with pytest.raises(InputError, match="unknown key name outside any table"):  # not a 'table [name]'
        parse_scene('name = "x"\n[scene]\nkind = "fault"\n')
    with pytest.raises(InputError, match="not valid TOML"):
        parse_scene("[scene\n")


def test_scene_keeps_its_text_for_provenance():
    scene = read_slider_scene()
    assert scene.text.startswith("# The 1906 San Francisco earthquake")
    assert scene.sources["zone_width"].startswith("seed 003")


def test_a_fault_scene_with_rate_state_friction_runs_its_cycles_beside_the_seed_law(cli):
    """configs/san_andreas_1906_rate_state.toml: BP1 friction on the 1906 fault. The seed law beside is the
    1906 scene's with radiation damping (4.65 m, 91.5 yr, as the README's radiation row); measured here
    4.33 m every 87 yr for the rate-and-state fault, K / K_c = 0.050."""
    from faultslip.fault.scaling import Fault

    out = cli("run", "configs/san_andreas_1906_rate_state.toml", "--json").json
    k = 0.25e6 * 1e5 / (13 * 1609.344)
    sigma = 250e5 / 0.65
    assert out["stiffness_ratio"] == pytest.approx(k * 0.008 / (sigma * 0.005), rel=1e-12)
    assert out["regime"].startswith("stick_slip")
    seed = Fault(lithology="granodiorite_water", shear_modulus="0.25e6 bar", zone_width="13 mi",
                 shear_stress="250 bar", slip_rate="2 in/yr", mu_so=0.65, mu_m=0.55,
                 radiation_damping=True).estimate()
    assert out["seed_law_slip_per_event"]["value"] == pytest.approx(seed.slip_per_event, rel=1e-12)
    assert 0.5 < out["slip_ratio_rate_state_to_seed"] < 2.0


@pytest.mark.parametrize("extra, message", [
    ('law = "rate_state"\nb = 0.015\ncritical_slip = "8 mm"\n', "needs a"),
    ('law = "rate_state"\na = 0.01\nb = 0.015\ncritical_slip = "8 mm"\nstatic = "constant"\n', "one or the other"),
    ('law = "rate_state"\nfit = "granodiorite_water"\n', "not a rate-and-state fit"),
    ('law = "rate_state"\na = 0.01\nb = 0.015\ncritical_slip = "8 kg"\n', "critical_slip"),
    ('law = "friction"\n', "law"),
])
def test_rate_state_scenes_are_refused_in_one_sentence(tmp_path, cli, extra, message):
    from conftest import assert_clean_error

    text = Path("configs/san_andreas_1906.toml").read_text().split("[simulation]")[0] + "[friction]\n" + extra
    path = tmp_path / "scene.toml"
    path.write_text(text)
    assert_clean_error(cli("run", path), message)
    assert_clean_error(cli("simulate", path), message)  # simulate, sweep and map take such scenes: the same check
