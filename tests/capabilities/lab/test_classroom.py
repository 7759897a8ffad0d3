"""The classroom experiment: phyphox accelerometer exports read directly, stick and slip recovered."""

import math

import numpy as np
import pytest

from conftest import assert_clean_error
from faultslip.errors import InputError
from faultslip.lab.classroom import analyse, is_accelerometer_csv, read_accelerometer, synthetic_record, \
    write_phyphox_csv

G = 9.80665

# phyphox's documented CSV export of "Acceleration without g" (header and number style as the app writes them)
PHYPHOX = ('"Time (s)","Linear Acceleration x (m/s^2)","Linear Acceleration y (m/s^2)",'
           '"Linear Acceleration z (m/s^2)","Absolute acceleration (m/s^2)"\n')


def test_the_reader_takes_phyphox_exports_in_each_csv_flavour(tmp_path):
    rows = [f"{0.01 * i:.9E},{0.0:.9E},{math.sin(i / 5):.9E},{0.0:.9E},{abs(math.sin(i / 5)):.9E}" for i in range(50)]
    comma = tmp_path / "Raw Data.csv"
    comma.write_text(PHYPHOX + "\n".join(rows) + "\n", encoding="utf-8")
    semicolon = tmp_path / "semicolon.csv"
    semicolon.write_text(PHYPHOX.replace(",", ";") + "\n".join(r.replace(",", ";").replace(".", ",") for r in rows)
                         + "\n", encoding="utf-8")
    tab = tmp_path / "tab.csv"
    tab.write_text(PHYPHOX.replace(",", "\t") + "\n".join(r.replace(",", "\t") for r in rows) + "\n", encoding="utf-8")
    for path in (comma, semicolon, tab):
        assert is_accelerometer_csv(path)
        record = read_accelerometer(path)
        assert record.kind == "phyphox" and set(record.acceleration) == {"x", "y", "z"}  # |a| is left out
        assert record.time[-1] == pytest.approx(0.49)
        np.testing.assert_allclose(record.acceleration["y"][:3], [0.0, math.sin(0.2), math.sin(0.4)], rtol=1e-8)
    generic = tmp_path / "generic.csv"
    generic.write_text("time (ms),a (g_0)\n" + "\n".join(f"{10 * i},{0.1 * math.sin(i / 5)}" for i in range(40)) + "\n",
                       encoding="utf-8")
    record = read_accelerometer(generic)
    assert record.kind == "generic" and record.time[1] == pytest.approx(0.01)
    assert record.acceleration["a"][5] == pytest.approx(0.1 * math.sin(1.0) * G)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_stick_and_slip_and_the_friction_drop_are_recovered(tmp_path, seed):
    """A phone of 0.2 kg on a band of 8 N/m pulled at 2 cm/s with mu_s 0.45 and mu_k 0.35 (seed 003's slider,
    sampled at 100 Hz with 0.03 m/s^2 noise): every slip found, mu_s - mu_k within 5 % (measured 1-2 %),
    omega = sqrt(k/m) = 6.32 within 5 %, the recurrence within 1 %."""
    time, acceleration = synthetic_record(duration=20.0, seed=seed)
    path = tmp_path / "phone.csv"
    write_phyphox_csv(path, time, acceleration, axis="x", decimal_comma=bool(seed % 2))
    result = analyse(read_accelerometer(path))
    assert result.axis == "x"
    period = 2 * 0.1 * 0.2 * G / (8.0 * 0.02)  # the stick: the band re-stretches by 2 dmu W / k at V ...
    assert result.starts.size in (6, 7)
    assert np.median(result.friction_drop) == pytest.approx(0.10, rel=0.05)
    assert np.median(result.omega) == pytest.approx(math.sqrt(8.0 / 0.2), rel=0.05)
    intervals = np.diff(result.starts)
    assert intervals.mean() == pytest.approx(2.99, rel=0.01) and intervals.mean() > period  # stick + slip
    assert np.median(result.slip_distance) == pytest.approx(np.median(result.model_distance), rel=0.1)


def test_a_steady_pull_has_no_slips(tmp_path):
    time = np.arange(0, 10, 0.01)
    path = tmp_path / "steady.csv"
    write_phyphox_csv(path, time, np.random.default_rng(1).normal(0, 0.03, time.size))
    result = analyse(read_accelerometer(path))
    assert result.starts.size == 0 and any("no slip" in note for note in result.notes)


def test_the_cli_and_its_refusals(cli, tmp_path):
    out = cli("record", "configs/example_phyphox.csv", "--plot", tmp_path / "c.png", "--json")
    assert out.code == 0, out.err
    assert out.json["events"] == 10 and out.json["friction_drop"] == pytest.approx(0.10, rel=0.05)
    assert (tmp_path / "c.png").stat().st_size > 20_000
    assert_clean_error(cli("record", "configs/example_phyphox.csv", "--axis", "w"), "--axis must be x, y or z")
    assert_clean_error(cli("record", "configs/example_record.csv"), "--stiffness and --normal-load")
    bad = tmp_path / "bad.csv"
    bad.write_text(PHYPHOX + "0,0,oops,0,0\n" * 30, encoding="utf-8")
    assert_clean_error(cli("record", bad), "is not a number")
    bad.write_text('"Time (s)","Linear Acceleration x (m/s^2)"\n' + "0,1\n" * 30, encoding="utf-8")
    assert_clean_error(cli("record", bad), "increase strictly")
    with pytest.raises(InputError, match="at least 20"):
        bad.write_text(PHYPHOX + "0,0,0,0,0\n", encoding="utf-8")
        read_accelerometer(bad)
