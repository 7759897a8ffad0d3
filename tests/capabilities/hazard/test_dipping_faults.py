"""Dipping faults (issue 44, item 1): a 30-degree thrust and a 60-degree normal fault carry the down-dip width
L H / sin(dip) in their moment, moment rate, empirical magnitudes and NRML, checked by hand."""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from faultslip.errors import InputError
from faultslip.fault import empirical
from faultslip.studies import hazard
from faultslip.studies.maps import read_map, run_map
from faultslip.units import JULIAN_YEAR as YEAR

from conftest import assert_clean_error

ROOT = Path(__file__).resolve().parents[3]
NS = {"n": "http://openquake.org/xmlns/nrml/0.5"}
HEADER = ("segment,name,trace (degree),slip_rate (mm/yr),lithology,seismogenic_depth (km),zone_width (km),"
          "dip (degree),rake (degree)\n")
ROWS = ("thrust,a 30-degree thrust,-118.60 34.30; -118.20 34.35,5,granodiorite,15,20,30,90\n"
        "normal,a 60-degree normal fault,-117.00 36.50; -116.90 36.90,2,granodiorite,12,20,60,-90\n"
        "vertical,a vertical strike-slip fault,-120.00 36.00; -119.70 35.70,20,granodiorite,12,20,,\n")


def _map(tmp_path, rows=ROWS):
    (tmp_path / "segments.csv").write_text(HEADER + rows, encoding="utf-8")
    (tmp_path / "map.toml").write_text(
        f'[map]\nname = "dipping"\nbase = "{ROOT / "configs" / "san_andreas_1906.toml"}"\n\n'
        '[segments]\nfile = "segments.csv"\n\n[grid]\nlon = { linspace = [-121.0, -116.0, 11] }\n'
        'lat = { linspace = [34.0, 37.5, 8] }\nmax_distance = "40 km"\n', encoding="utf-8")
    return tmp_path / "map.toml"


def test_a_thrust_and_a_normal_fault_carry_the_down_dip_width_everywhere(tmp_path):
    spec = read_map(_map(tmp_path))
    data = run_map(spec)
    shear_modulus = spec.scene.fault().shear_modulus
    depth = np.array([15e3, 12e3, 12e3])
    dip = np.array([30.0, 60.0, 90.0])
    width = depth / np.sin(np.radians(dip))  # by hand: 30 km, 13.856 km, 12 km
    assert width[0] == pytest.approx(30e3, rel=1e-12)
    np.testing.assert_allclose(data["down_dip_width"].values, width, rtol=1e-12)
    np.testing.assert_allclose(data["dip"].values, dip)
    length = data["segment_length"].values
    slip = data["slip_per_event"].values
    moment = shear_modulus * length * width * slip  # M0 = G L W slip, W down dip
    np.testing.assert_allclose(data["seismic_moment"].values, moment, rtol=1e-9)
    np.testing.assert_allclose(data["moment_magnitude"].values, (2 / 3) * (np.log10(moment) - 9.1), atol=1e-9)
    assert any("down-dip width" in note for note in spec.notes)
    sources = hazard.hazard_sources(spec, data)
    for source, w, kind in zip(sources, width, ("reverse", "normal", "strike-slip")):
        assert source.slip_type == kind and source.width == pytest.approx(w, rel=1e-12)
        # the budget: G L W V per year, the moment over the recurrence
        rate = shear_modulus * source.length * w * data["slip_rate"].values[sources.index(source)] * YEAR
        assert source.moment_rate == pytest.approx(rate, rel=1e-9)
        area = source.length * w
        assert source.empirical[f"W&C 1994 Mw(RA), {kind}"]["magnitude"] == pytest.approx(
            float(empirical.magnitude_from_area(area, kind)[0]), abs=1e-12)
    models = hazard.source_models(sources, [("faultslip", 1.0)], "single_bin")
    hazard.write_hazard_model(tmp_path / "s.xml", models, [("faultslip", 1.0)], "dipping")
    written = ET.parse(tmp_path / "s.xml").getroot().findall(".//n:simpleFaultSource", NS)
    for node, d, h, rake in zip(written, dip, depth, (90, -90, 180)):
        geometry = node.find("n:simpleFaultGeometry", NS)
        assert float(geometry.find("n:dip", NS).text) == d
        assert float(geometry.find("n:lowerSeismoDepth", NS).text) == pytest.approx(h / 1e3)
        assert float(node.find("n:rake", NS).text) == rake


@pytest.mark.parametrize("row, words", [
    ("bad,x,-118.6 34.3; -118.2 34.35,5,granodiorite,15,20,0,90\n", "dip must lie above 0"),
    ("bad,x,-118.6 34.3; -118.2 34.35,5,granodiorite,15,20,95,90\n", "at most 90"),
    ("bad,x,-118.6 34.3; -118.2 34.35,5,granodiorite,15,20,45,270\n", "rake must lie from -180"),
    ("bad,x,-118.6 34.3; -118.2 34.35,5,granodiorite,15,20,steep,90\n", "not a number of degrees"),
])
def test_bad_dips_and_rakes_are_one_sentence(tmp_path, cli, row, words):
    assert_clean_error(cli("map", _map(tmp_path, row), "-o", tmp_path / "m.nc"), words)
    with pytest.raises(InputError):
        read_map(_map(tmp_path, row))


def test_the_geojson_dip_reaches_the_moment(tmp_path):
    """GEM GAF GeoJSON's average_dip reaches the moment like a table's (a fault rewritten to dip 45)."""
    import json

    document = json.loads((ROOT / "data" / "gem_faults_example.geojson").read_text(encoding="utf-8"))
    document["features"] = document["features"][:1]
    document["features"][0]["properties"]["average_dip"] = "(45,,)"
    (tmp_path / "one.geojson").write_text(json.dumps(document), encoding="utf-8")
    (tmp_path / "map.toml").write_text(
        f'[map]\nname = "one"\nbase = "{ROOT / "configs" / "san_andreas_1906.toml"}"\n\n'
        '[segments]\nfile = "one.geojson"\n\n[grid]\nlon = { linspace = [-121.0, -119.0, 5] }\n'
        'lat = { linspace = [35.0, 36.5, 4] }\nmax_distance = "40 km"\n', encoding="utf-8")
    data = run_map(read_map(tmp_path / "map.toml"))
    assert float(data["down_dip_width"].values[0]) == pytest.approx(12e3 * math.sqrt(2), rel=1e-12)


def test_a_single_dipping_fault_takes_its_down_dip_width(cli):
    """faultslip fault (and Fault) with --dip: M0 = G L (H / sin dip) slip by hand, the report names W and says the
    stiffness keeps the elastic-zone width; a vertical fault is unchanged."""
    from faultslip.fault.scaling import Fault

    base = dict(lithology="granodiorite", zone_width="13 mi", shear_stress="250 bar", slip_rate="2 in/yr",
                rupture_length="100 km", seismogenic_depth="15 km")
    vertical = Fault(**base).estimate()
    thrust = Fault(**base, dip=30, rake=90).estimate()
    assert thrust.slip_per_event == pytest.approx(vertical.slip_per_event, rel=1e-15)  # the slider does not change
    shear_modulus = Fault(**base).shear_modulus
    assert thrust.seismic_moment == pytest.approx(shear_modulus * 100e3 * 30e3 * thrust.slip_per_event, rel=1e-12)
    assert vertical.seismic_moment == pytest.approx(shear_modulus * 100e3 * 15e3 * vertical.slip_per_event,
                                                    rel=1e-12)
    rows = {row["relation"] if isinstance(row, dict) and "relation" in row else str(row): row
            for row in thrust.empirical()}
    assert any("reverse" in str(key) for key in rows), rows
    out = cli("fault", "--lithology", "granodiorite", "--zone-width", "13 mi", "--shear-stress", "250 bar",
              "--slip-rate", "2 in/yr", "--rupture-length", "100 km", "--depth", "15 km", "--dip", "30", "--rake", "90",
              "--json")
    assert out.code == 0, out.err
    assert out.json["rupture_width"]["value"] == pytest.approx(30e3, rel=1e-12)
    assert any("keeps the elastic-zone width" in note for note in out.json["notes"])
    assert_clean_error(cli("fault", "--lithology", "granodiorite", "--zone-width", "13 mi", "--shear-stress",
                           "250 bar", "--slip-rate", "2 in/yr", "--dip", "95"), "dip must lie")


def test_a_tables_upper_depth_reaches_the_nrml(tmp_path):
    """A segment table's upper_depth column: the seismogenic zone from 3 km down H = 15 km, so 3 to 18 km in NRML."""
    header = HEADER.replace("rake (degree)\n", "rake (degree),upper_depth (km)\n")
    rows = "thrust,a buried thrust,-118.60 34.30; -118.20 34.35,5,granodiorite,15,20,30,90,3\n"
    (tmp_path / "segments.csv").write_text(header + rows, encoding="utf-8")
    (tmp_path / "map.toml").write_text(
        f'[map]\nname = "buried"\nbase = "{ROOT / "configs" / "san_andreas_1906.toml"}"\n\n'
        '[segments]\nfile = "segments.csv"\n\n[grid]\nlon = { linspace = [-121.0, -116.0, 11] }\n'
        'lat = { linspace = [34.0, 37.5, 8] }\nmax_distance = "40 km"\n', encoding="utf-8")
    spec = read_map(tmp_path / "map.toml")
    sources = hazard.hazard_sources(spec, run_map(spec))
    assert sources[0].upper_depth == pytest.approx(3e3) and sources[0].lower_depth == pytest.approx(18e3)
    assert sources[0].width == pytest.approx(30e3, rel=1e-12)
