"""Synthetic records out as obspy Streams (miniSEED, SAC) and QuakeML; lab records back in through obspy."""

import numpy as np
import obspy
import pytest

from conftest import assert_clean_error
from faultslip.errors import InputError
from faultslip.io.waveforms import band_code, build_stream, channels_by_quantity, read_stream, write_stream


@pytest.mark.parametrize("rate, code", [(5000.0, "F"), (500.0, "C"), (100.0, "H"), (20.0, "B"), (5.0, "M"),
                                         (1.0, "L"), (0.1, "V"), (0.01, "U"), (5e-4, "R"), (5e-5, "P"), (5e-6, "T"),
                                         (1e-7, "Q")])
def test_seed_band_codes(rate, code):
    assert band_code(rate) == code


def test_streams_round_trip_through_obspy(tmp_path):
    samples = {"D": np.linspace(0, 1e-3, 101), "F": np.full(101, 0.6)}
    stream = build_stream(100.0, samples, start_seconds=0.0, station="TESTSTATION")
    written = write_stream(stream, tmp_path / "a.mseed")
    back = obspy.read(str(written[0]))  # as another program reads it: the checksum is a first, log record
    assert [t.stats.channel for t in back] == ["LOG", "HYD", "HYF"] and back[1].stats.station == "TESTS"
    assert back[0].data.tobytes().startswith(b"faultslip sha256 ")
    np.testing.assert_array_equal(back[1].data, samples["D"])  # float64, exact
    files = write_stream(stream, tmp_path / "b.sac")
    assert [f.name for f in files] == ["b.D.sac", "b.F.sac"]
    np.testing.assert_allclose(obspy.read(str(files[0]))[0].data, samples["D"], rtol=1e-7)  # SAC is float32
    time, found = channels_by_quantity(read_stream(written[0]), "a")
    assert time[-1] == pytest.approx(1.0) and set(found) == {"displacement", "friction_coefficient"}


def test_a_simulated_lab_record_goes_out_as_miniseed_and_back_through_record(cli, tmp_path):
    """Seed 003's dry glass: simulate -> miniSEED -> record recovers the exact cycle's static friction
    (0.74776), amplitude and period (measured: 0.74759, 1.002e-5 m, 3.957 s)."""
    exact = cli("run", "configs/lab_glass_dry.toml", "--json").json
    out = cli("simulate", "configs/lab_glass_dry.toml", "--cycles", "6", "--stream", tmp_path / "r.mseed", "--json")
    assert out.code == 0, out.err
    stream = [t for t in obspy.read(str(tmp_path / "r.mseed")) if t.stats.channel != "LOG"]  # not the checksum
    assert sorted(t.stats.channel[-1] for t in stream) == ["D", "F", "R", "S"]
    assert stream[0].stats.sampling_rate == pytest.approx(20 / exact["slip_duration"]["value"], rel=1e-3)
    analysed = cli("record", tmp_path / "r.mseed", "--stiffness", "3.397e6 N/m", "--normal-load", "613 N",
                   "--platform-speed", "1e-4 in/s", "--json").json
    assert analysed["static_friction"] == pytest.approx(exact["static_friction"], abs=5e-4)
    assert analysed["period"]["value"] == pytest.approx(exact["period"]["value"], rel=1e-3)
    sac = cli("simulate", "configs/lab_glass_dry.toml", "--cycles", "4", "--stream", tmp_path / "s.sac", "--json")
    assert sac.code == 0, sac.err
    again = cli("record", tmp_path / "s.D.sac", "--stiffness", "3.397e6 N/m", "--normal-load", "613 N",
                "--platform-speed", "1e-4 in/s", "--json").json  # the siblings come along
    assert again["static_friction"] == pytest.approx(exact["static_friction"], abs=5e-4)


def test_fault_events_as_quakeml_with_mw_from_m0(cli, tmp_path):
    out = cli("simulate", "san_andreas_1906.toml", "--cycles", "3", "--events", tmp_path / "e.xml",
              "--stream", tmp_path / "f.mseed", "--start-time", "1906-04-18", "--json")
    assert out.code == 0, out.err
    events = obspy.read_events(str(tmp_path / "e.xml"))
    run = cli("run", "--json").json
    assert len(events) == 3
    assert events[0].preferred_magnitude().mag == pytest.approx(run["moment_magnitude"], abs=1e-9)
    assert events[0].preferred_magnitude().magnitude_type == "Mw"
    stream = obspy.read(str(tmp_path / "f.mseed"))
    slip = [t for t in stream if t.stats.channel.endswith("S")][0].data
    assert slip[-1] == pytest.approx(3 * run["slip_per_event"]["value"], rel=1e-9)  # slip is conserved
    assert any("averaged over" in note for note in out.json["notes"])
    assert stream[0].stats.starttime == obspy.UTCDateTime("1906-04-18")


def test_bad_streams_and_options_are_refused(cli, tmp_path):
    junk = tmp_path / "junk.mseed"
    junk.write_bytes(b"not a miniseed record at all" * 40)
    with pytest.raises(InputError, match="miniSEED"):
        read_stream(junk)
    assert_clean_error(cli("record", junk, "--stiffness", "1 N/m", "--normal-load", "1 N"), "miniSEED")
    assert_clean_error(cli("simulate", "configs/lab_glass_dry.toml", "--stream", tmp_path / "x.wav"), "--stream")
    assert_clean_error(cli("simulate", "configs/lab_glass_dry.toml", "--events", tmp_path / "x.xml"), "fault scene")
    only_force = build_stream(10.0, {"N": np.ones(50)}, start_seconds=0.0)
    write_stream(only_force, tmp_path / "n.mseed")
    assert_clean_error(cli("record", tmp_path / "n.mseed", "--stiffness", "1 N/m", "--normal-load", "1 N"),
                       "no displacement channel")
