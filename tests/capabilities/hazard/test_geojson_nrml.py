"""GeoJSON fault traces in (GEM Global Active Faults schema) and OpenQuake NRML sources out."""

import json
import math
import warnings
import xml.etree.ElementTree as ET

import pytest

from conftest import assert_clean_error
from faultslip.errors import InputError
from faultslip.io.geojson import MM_PER_YEAR, parse_tuple, read_fault_geojson
from faultslip.io.nrml import GML_NAMESPACE, NRML_NAMESPACE

NS = {"n": NRML_NAMESPACE, "gml": GML_NAMESPACE}


def test_gaf_tuples():
    assert parse_tuple("(33,30,36)", "x") == (33.0, 30.0, 36.0)
    assert parse_tuple("(12,,)", "x")[0] == 12.0 and math.isnan(parse_tuple("(12,,)", "x")[1])
    assert parse_tuple(7, "x")[0] == 7.0
    for bad in ("(a,b,c)", "(1,2,3,4)", True, [1]):
        with pytest.raises(InputError):
            parse_tuple(bad, "x")


def test_the_bundled_gaf_file_is_read_with_defaults_said():
    faults = read_fault_geojson("data/gem_faults_example.geojson")
    assert faults.names[0] == "San Andreas (Parkfield)" and len(faults.ids) == 6
    assert faults.slip_rate[0] == pytest.approx(33 * MM_PER_YEAR)
    assert faults.rake[faults.ids.index("GAR")] == 0.0  # sinistral, from the slip type
    assert any("Calaveras" in note for note in faults.notes)


def _feature(**properties):
    return {"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[-120, 36], [-119, 35]]},
            "properties": properties}


@pytest.mark.parametrize("document, message", [
    ({"type": "FeatureCollection", "features": [_feature(name="x")]}, "no positive net_slip_rate"),
    ({"type": "FeatureCollection", "features": [_feature(name="x", net_slip_rate="(5,,)", slip_type="Wobbly")]},
     "no feature is left"),
    ({"type": "FeatureCollection", "features": [_feature(name="x", net_slip_rate="(5,,)", slip_type={})]},
     "slip_type must be a GAF term"),
    ({"type": "FeatureCollection", "features": [_feature(name="x", net_slip_rate="(5,,)", catalog_id="A"),
                                                _feature(name="y", net_slip_rate="(5,,)", catalog_id="A")]},
     "share catalog_id 'A'"),
    ({"type": "FeatureCollection", "features": [_feature(name="x", net_slip_rate="(5,,)", average_dip="(120,,)")]},
     "average_dip"),
    ({"type": "FeatureCollection", "features": []}, "no features"),
    ({"type": "Feature"}, "FeatureCollection"),
    ({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {"net_slip_rate": 5},
                                                 "geometry": {"type": "Point", "coordinates": [0, 0]}}]},
     "LineString"),
])
def test_malformed_gaf_files_are_refused_in_one_sentence(tmp_path, document, message):
    path = tmp_path / "f.geojson"
    path.write_text(json.dumps(document), encoding="utf-8")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(InputError, match=message):
            read_fault_geojson(path)
    if message == "no feature is left":  # the skipped feature is named before the refusal
        assert any("'x' ('Wobbly')" in str(warning.message) for warning in caught)


@pytest.mark.parametrize("term, rake", [
    ("Dextral_Transform", 180.0), ("Sinistral_Transform", 0.0), ("Subduction_Thrust", 90.0),
    ("Normal-Strike-Slip", -135.0), ("Reverse-Strike-Slip", 135.0), ("Blind Thrust", 90.0),
    ("Dextral-Oblique", 180.0), ("dextral_normal", -135.0), ("Spreading_Ridge", -90.0), ("Anticline", 90.0),
])
def test_the_whole_gaf_vocabulary_maps_to_a_rake(tmp_path, term, rake):
    path = tmp_path / "f.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": [
        _feature(name="x", net_slip_rate="(5,,)", slip_type=term)]}), encoding="utf-8")
    assert read_fault_geojson(path).rake[0] == rake


def test_an_unknown_slip_type_skips_that_feature_with_a_warning_naming_it(tmp_path):
    path = tmp_path / "f.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": [
        _feature(name="kept", net_slip_rate="(5,,)", slip_type="Dextral", catalog_id="A"),
        _feature(name="odd", net_slip_rate="(5,,)", slip_type="Wobbly", catalog_id="B")]}), encoding="utf-8")
    with pytest.warns(UserWarning, match="'odd' \\('Wobbly'\\)"):
        faults = read_fault_geojson(path)
    assert faults.names == ["kept"]


def test_a_multilinestring_becomes_separate_sections_not_one_joined_trace(tmp_path):
    """Joining the parts would add the jump between them to the trace (the audit: Mw 7.19 -> 7.50)."""
    from faultslip.io.geo import trace_length

    parts = [[[-120.0, 36.0], [-120.0, 36.5]], [[-118.0, 35.0], [-118.0, 35.5]]]
    feature = {"type": "Feature", "geometry": {"type": "MultiLineString", "coordinates": parts},
               "properties": {"name": "split", "catalog_id": "S", "net_slip_rate": "(5,,)"}}
    path = tmp_path / "f.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": [feature]}), encoding="utf-8")
    faults = read_fault_geojson(path)
    assert faults.ids == ["S:1", "S:2"]
    lengths = [trace_length(trace) for trace in faults.traces]
    assert lengths == pytest.approx([55.5e3, 55.5e3], rel=0.01)  # half a degree of latitude each, no jump


@pytest.mark.parametrize("mfd", ["single_bin", "truncated_gr"])
def test_map_from_geojson_writes_an_nrml_source_model(cli, tmp_path, mfd):
    out = cli("map", "configs/california_faults_map.toml", "-o", tmp_path / "m.nc", "--nrml", tmp_path / "s.xml",
              "--mfd", mfd, "--json")
    assert out.code == 0, out.err
    root = ET.parse(tmp_path / "s.xml").getroot()
    assert root.tag == f"{{{NRML_NAMESPACE}}}nrml"
    sources = root.findall(".//n:simpleFaultSource", NS)
    assert [s.get("id") for s in sources] == ["SA-PKF", "SA-CAR", "HAY", "SJC", "GAR", "CAL"]
    parkfield = sources[0]
    positions = [float(v) for v in parkfield.find(".//gml:posList", NS).text.split()]
    assert positions[:2] == [-120.6, 36.0]
    assert float(parkfield.find(".//n:lowerSeismoDepth", NS).text) == 12.0
    row = out.json["segments"][0]
    if mfd == "single_bin":
        bins = parkfield.find("n:incrementalMFD", NS)
        assert float(bins.get("minMag")) == pytest.approx(row["moment_magnitude"], abs=1e-3)
        rate = float(bins.find("n:occurRates", NS).text)
        assert rate == pytest.approx(365.25 * 86400 / row["recurrence_period"]["value"], rel=1e-6)
    else:
        gr = parkfield.find("n:truncGutenbergRichterMFD", NS)
        # the upper bound is faultslip's Mw on the nearest bin edge
        assert float(gr.get("bValue")) == 1.0 and float(gr.get("maxMag")) == pytest.approx(
            round(row["moment_magnitude"] / 0.1) * 0.1, abs=1e-9)
    assert float(sources[4].find("n:rake", NS).text) == 0.0  # Garlock, sinistral


def test_nrml_refusals(cli, tmp_path):
    assert_clean_error(cli("map", "configs/california_faults_map.toml", "-o", tmp_path / "m.nc", "--nrml",
                           tmp_path / "s.txt"), "--nrml")
    assert_clean_error(cli("map", "configs/california_faults_map.toml", "-o", tmp_path / "m.nc", "--nrml",
                           tmp_path / "s.xml", "--mfd", "tapered"), "--mfd must be one of")


def test_openquake_parses_the_source_model_where_installed(cli, tmp_path):
    nrml = pytest.importorskip("openquake.hazardlib.nrml", reason="the OpenQuake engine is not installed")
    out = cli("map", "configs/california_faults_map.toml", "-o", tmp_path / "m.nc", "--nrml", tmp_path / "s.xml")
    assert out.code == 0, out.err
    from openquake.hazardlib.sourceconverter import SourceConverter

    model = nrml.to_python(str(tmp_path / "s.xml"), SourceConverter(50.0, 2.0, width_of_mfd_bin=0.1))
    sources = [source for group in model for source in group]
    assert len(sources) == 6 and sources[0].source_id == "SA-PKF"


def _collection(*features):
    return {"type": "FeatureCollection", "features": [
        {"type": "Feature", "geometry": {"type": "LineString", "coordinates": coordinates},
         "properties": {"name": name, "net_slip_rate": "(5,3,8)", "slip_type": "Dextral"}}
        for name, coordinates in features]}


@pytest.mark.parametrize("coordinates, message", [
    ([[-120.0, 36.0], [-119.0, 36.0], [-119.0, 36.5], [-119.5, 35.5]], "crosses itself"),
    ([[-120.0, 36.0], [-119.0, 36.0], [-119.8, 36.001]], "doubles back on itself"),
    ([[-120.0, 36.0], [-120.0, 36.0], [-119.0, 36.5]], "repeats a vertex"),
])
def test_a_trace_that_crosses_or_retraces_itself_is_refused(tmp_path, coordinates, message):
    """Such a trace counts part of its fault twice: a self-retracing trace raised a map's moment 1.4-fold."""
    path = tmp_path / "faults.geojson"
    path.write_text(json.dumps(_collection(("bent", coordinates))))
    with pytest.raises(InputError, match=message):
        read_fault_geojson(path)


def test_the_same_fault_twice_is_refused_in_either_direction(tmp_path):
    trace = [[-120.0, 36.0], [-119.5, 36.2], [-119.0, 36.5]]
    path = tmp_path / "faults.geojson"
    path.write_text(json.dumps(_collection(("one", trace), ("again", trace[::-1]))))
    with pytest.raises(InputError, match="'one' and 'again' have the same trace"):
        read_fault_geojson(path)
    path.write_text(json.dumps(_collection(("one", trace), ("other", [[-118.0, 35.0], [-117.5, 35.4]]))))
    assert len(read_fault_geojson(path).names) == 2
