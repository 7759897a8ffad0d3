"""Bundled scenes load, validate and run; scene files state their units."""

import pytest

from faultslip.errors import InputError
from faultslip.fault.scene import bundled_scenes, load_scene, parse_scene, run_scene


def test_bundled_scenes_include_1906_granite_and_every_table_i_preset():
    names = set(bundled_scenes())
    assert {"san_andreas_1906.toml", "granite_inverse_1906.toml"} <= names
    from faultslip.friction.materials import table_i_presets

    assert {f"lab_{p.name}.toml" for p in table_i_presets()} <= names


@pytest.mark.parametrize("name", bundled_scenes())
def test_every_bundled_scene_runs(name):
    report = run_scene(load_scene(name))
    data = report.to_dict()
    assert "slip_per_event" in data or "kinetic_friction" in data


def test_lab_scene_uses_the_preset_apparatus():
    scene = load_scene("lab_pyrite_dry.toml")
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
    with pytest.raises(InputError, match="not valid TOML"):
        parse_scene("[scene\n")


def test_scene_keeps_its_text_for_provenance():
    scene = load_scene()
    assert scene.text.startswith("# The 1906 San Francisco earthquake")
    assert scene.sources["zone_width"].startswith("seed 003")
