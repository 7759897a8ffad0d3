"""Streams (miniSEED, SAC) and QuakeML catalogs faultslip writes carry a checksum of what they hold, checked where
faultslip reads them back (faultslip.io.waveforms, faultslip.io.catalogs): simulate -> record, simulate --events ->
catalog. Other programs read the files as before (the checksum is a SEED log record, SAC user header fields, a
QuakeML element in faultslip's own namespace)."""

from __future__ import annotations

import re
import warnings

import numpy as np
import obspy
from obspy.io.mseed.util import get_record_information
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from conftest import assert_clean_error
from faultslip.errors import InputError
from faultslip.io.catalogs import QUAKEML_NAMESPACE, quakeml_checksum, read_catalog, write_quakeml
from faultslip.io.waveforms import CHECKSUM_CHANNEL, build_stream, read_stream, write_stream

TIMES = np.array(["1857-01-09T16:00:00.123456789", "1906-04-18T13:12:21", "2004-09-28T17:15:24.25"],
                 dtype="datetime64[ns]")
RNG = np.random.default_rng(5)


def _stream(station="FSLIP"):
    return build_stream(123.456, {"D": RNG.normal(size=700).cumsum() * 1e-6, "N": 600 + RNG.normal(size=700)},
                        946684800.123456789, station=station)


def _content(stream) -> list:
    """What faultslip reads of a stream: ids, starts, rates, samples."""
    return [(t.id, t.stats.starttime.ns, t.stats.sampling_rate, np.asarray(t.data, float).tobytes()) for t in stream]


def _catalog_content(catalog) -> tuple:
    return (catalog.time.tobytes(), catalog.latitude.tobytes(), catalog.longitude.tobytes(), catalog.depth.tobytes(),
            catalog.magnitude.tobytes(), catalog.magnitude_type, catalog.name, catalog.source)


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("exchange")
    stream = _stream()
    write_stream(stream, folder / "run.mseed")
    write_stream(stream, folder / "run.sac")
    write_quakeml(TIMES, [36.0, 37.7, 35.8], [-120.0, -122.5, -120.4], [8e3, 1e4, 7.9e3], [7.9, 7.8, 6.0],
                  folder / "events.xml", names=["Fort Tejon", "San Francisco", "Parkfield"])
    return folder, stream


def test_a_stream_reads_back_as_written_without_its_checksum_record(written):
    folder, stream = written
    back = read_stream(folder / "run.mseed")
    assert [t.stats.channel for t in back] == [t.stats.channel for t in stream]  # no LOG trace
    for got, sent in zip(back, stream):
        np.testing.assert_array_equal(got.data, sent.data)
    assert CHECKSUM_CHANNEL in [t.stats.channel for t in obspy.read(str(folder / "run.mseed"))]  # others see it
    sac = read_stream(folder / "run.D.sac")[0]
    np.testing.assert_array_equal(sac.data, stream[0].data.astype(np.float32))
    assert sac.stats.sac.kuser0 == "fsha256"


@pytest.mark.parametrize("name", ["run.mseed", "run.D.sac", "events.xml"])
@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_one_flipped_bit_anywhere_is_refused_or_changes_nothing(written, tmp_path_factory, name, data):
    """A hypothesis property: flip any one bit of a file faultslip wrote, and reading it back either refuses it in
    one sentence or returns exactly what was written."""
    folder, _ = written
    raw = bytearray((folder / name).read_bytes())
    position = data.draw(st.integers(0, len(raw) - 1))
    raw[position] ^= 1 << data.draw(st.integers(0, 7))
    damaged = tmp_path_factory.mktemp("flip") / name
    damaged.write_bytes(bytes(raw))
    read, content = ((read_catalog, _catalog_content) if name.endswith(".xml") else (read_stream, _content))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a warning here would be a file read unchecked
            got = read(damaged)
    except InputError as exc:
        assert "\n" not in str(exc)
        return
    assert content(got) == content(read(folder / name))


def test_a_cut_stream_is_refused_since_its_checksum_comes_first(written, tmp_path):
    folder, _ = written
    raw = (folder / "run.mseed").read_bytes()
    (tmp_path / "cut.mseed").write_bytes(raw[: len(raw) // 2])
    with pytest.raises(InputError, match="does not match the checksum faultslip wrote"):
        read_stream(tmp_path / "cut.mseed")


def test_a_second_checksum_record_is_refused(written, tmp_path):
    folder, _ = written
    raw = (folder / "run.mseed").read_bytes()
    length = get_record_information(str(folder / "run.mseed"))["record_length"]  # the checksum record's
    (tmp_path / "twice.mseed").write_bytes(raw[:length] + raw)
    with pytest.raises(InputError, match="2 checksum records"):
        read_stream(tmp_path / "twice.mseed")


def test_an_edited_sac_checksum_is_refused(written, tmp_path):
    folder, _ = written
    with warnings.catch_warnings():  # obspy rounds a SAC file's sample spacing to the microsecond, and says so
        warnings.simplefilter("ignore")
        trace = obspy.read(str(folder / "run.D.sac"))[0]
    trace.stats.sac.kuser1 = "00000000"
    trace.write(str(tmp_path / "x.D.sac"), format="SAC")
    with pytest.raises(InputError, match="does not match"):
        read_stream(tmp_path / "x.D.sac")


def test_an_older_faultslip_stream_is_read_with_a_warning_and_another_programs_as_it_is(tmp_path):
    for station, warned in (("FSLIP", True), ("PKD", False)):
        stream = _stream(station)
        stream.write(str(tmp_path / f"{station}.mseed"), format="MSEED", encoding="FLOAT64")  # no checksum record
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            back = read_stream(tmp_path / f"{station}.mseed")
        assert _content(back) == _content(obspy.read(str(tmp_path / f"{station}.mseed")))
        assert any("read unchecked" in str(w.message) for w in caught) == warned


def test_an_edited_catalog_is_refused_and_its_checksum_cannot_be_removed(written, tmp_path):
    folder, _ = written
    text = (folder / "events.xml").read_text(encoding="utf-8")
    assert QUAKEML_NAMESPACE in text
    (tmp_path / "moved.xml").write_text(text.replace("<value>37.7</value>", "<value>37.8</value>"), encoding="utf-8")
    with pytest.raises(InputError, match="does not match the checksum faultslip wrote"):
        read_catalog(tmp_path / "moved.xml")
    stripped = re.sub(r"\s*<faultslip:checksum>[0-9a-f]+</faultslip:checksum>", "", text)
    (tmp_path / "stripped.xml").write_text(stripped, encoding="utf-8")
    with pytest.raises(InputError, match="checksum that is now missing"):
        read_catalog(tmp_path / "stripped.xml")


def test_the_checksum_is_of_what_quakeml_carries(written):
    """The checksum written (from the events in memory, times in ns) is the one the file's events give when
    read back (times to the microsecond, as QuakeML carries them)."""
    folder, _ = written
    events = obspy.read_events(str(folder / "events.xml"))
    assert events.extra["checksum"]["value"] == quakeml_checksum(events)
    catalog = read_catalog(folder / "events.xml")
    assert list(catalog.name) == ["Fort Tejon", "San Francisco", "Parkfield"]


def test_an_older_faultslip_catalog_warns_and_another_programs_is_read(tmp_path):
    from obspy.core import event as quakeml

    for description, warned in (("faultslip synthetic events", True), ("ComCat search", False)):
        catalog = quakeml.Catalog(description=description)
        origin = quakeml.Origin(time=obspy.UTCDateTime("1966-06-28T04:26:14"), latitude=35.955, longitude=-120.498,
                                depth=9e3)
        catalog.append(quakeml.Event(origins=[origin], magnitudes=[quakeml.Magnitude(mag=6.0, magnitude_type="Mw")]))
        catalog.write(str(tmp_path / "c.xml"), format="QUAKEML")
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            assert len(read_catalog(tmp_path / "c.xml")) == 1
        assert any("read unchecked" in str(w.message) for w in caught) == warned


def test_the_commands_refuse_a_tampered_record_and_catalog_in_one_sentence(cli, tmp_path):
    out = cli("simulate", "configs/lab_glass_dry.toml", "--cycles", "4", "--stream", tmp_path / "r.mseed", "--json")
    assert out.code == 0, out.err
    raw = bytearray((tmp_path / "r.mseed").read_bytes())
    raw[get_record_information(str(tmp_path / "r.mseed"))["record_length"] + 200] ^= 0x10  # a data record's samples
    (tmp_path / "r.mseed").write_bytes(bytes(raw))
    assert_clean_error(cli("record", tmp_path / "r.mseed", "--stiffness", "3.397e6 N/m", "--normal-load", "613 N"),
                       "r.mseed", "checksum")
    events = cli("simulate", "san_andreas_1906.toml", "--cycles", "3", "--events", tmp_path / "e.xml",
                 "--start-time", "1906-04-18", "--json")
    assert events.code == 0, events.err
    text = (tmp_path / "e.xml").read_text(encoding="utf-8")
    year = re.search(r"<value>(\d{4})-", text).group(1)  # the first event's origin time
    (tmp_path / "e.xml").write_text(text.replace(f"<value>{year}-", f"<value>{int(year) + 1}-", 1), encoding="utf-8")
    assert_clean_error(cli("catalog", tmp_path / "e.xml", "--fault", "configs/parkfield.toml"), "e.xml", "checksum")


def test_another_agencys_checksum_element_is_theirs_and_not_checked(tmp_path):
    """Only faultslip's namespace (or one a damaged byte away from it) holds faultslip's checksum: a catalog of
    another program with a "checksum" element of its own is read as it is."""
    from obspy.core import event as quakeml
    from obspy.core.util import AttribDict

    catalog = quakeml.Catalog(description="an agency's export")
    origin = quakeml.Origin(time=obspy.UTCDateTime("2004-09-28T17:15:24"), latitude=35.8, longitude=-120.4, depth=8e3)
    catalog.append(quakeml.Event(origins=[origin], magnitudes=[quakeml.Magnitude(mag=6.0, magnitude_type="Mw")]))
    catalog.extra = AttribDict({"checksum": AttribDict({"value": "md5:0123", "namespace": "https://agency.example/ns"})})
    catalog.write(str(tmp_path / "agency.xml"), format="QUAKEML")
    assert len(read_catalog(tmp_path / "agency.xml")) == 1
