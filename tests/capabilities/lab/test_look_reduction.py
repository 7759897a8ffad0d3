"""xlook's r-files (issue 46, item 1): every command by hand, Penn State's p655 reduced end to end and slot by slot
against pylook (every difference traced to a command), and every malformed line refused in one sentence."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from faultslip.errors import InputError
from faultslip.lab.look_files import LookFile
from faultslip.lab.look_reduction import run_commands, run_r_file

ROOT = Path(__file__).resolve().parents[3]
P655 = ROOT / "data" / "p655" / "p655_r"


def _look():
    columns = {"t": np.arange(6.0), "disp": np.array([0.0, 1.0, 3.0, 6.0, 10.0, 15.0]),
               "load": np.array([2.0, 4.0, 4.0, 8.0, 8.0, 16.0])}
    return LookFile("x", columns, {"t": "s", "disp": "micron", "load": "MPa"})


def _run(text):
    return run_commands(text, "test_r", look=_look())


def test_every_command_by_hand():
    r = _run("math 2 / 3 : 4 ratio .\nmath 2 * 2 = 5 double micron")
    np.testing.assert_array_equal(r.column(4), [0, 0.25, 0.75, 0.75, 1.25, 0.9375])
    np.testing.assert_array_equal(r.column(5), 2 * _look().columns["disp"])
    assert r.names[4] == "ratio" and r.units[5] == "micron" and r.names[0] == "rec_num"
    # math_int: records 1 to 3, both included; -1 is the last record, included
    np.testing.assert_array_equal(_run("math_int 2 * 0 = 2 1 3 d micron").column(2), [0, 0, 0, 0, 10, 15])
    np.testing.assert_array_equal(_run("math_int 2 + 1 = 6 4 -1 d micron").column(6), [0, 1, 3, 6, 11, 16])
    np.testing.assert_array_equal(_run("summation 1 6 T s").column(6), [0, 1, 3, 6, 10, 15])
    np.testing.assert_array_equal(_run("power 2 1 6 t2 s^2").column(6), np.arange(6.0) ** 2)
    np.testing.assert_array_equal(_run("zero 2 3").column(2), [-6, -5, -3, 0, 4, 9])
    # offset_int: the step from record 2 to 4 removed from 4 on; y holds records 2 and 3 at record 2's value
    np.testing.assert_array_equal(_run("offset_int 2 2 4 y").column(2), [0, 1, 3, 3, 3, 8])
    np.testing.assert_array_equal(_run("offset_int 2 2 4 n").column(2), [0, 1, 3, 6, 3, 8])
    # ec: DISP - LOAD / SLOPE on records 1 to -1 (record 0 kept)
    np.testing.assert_array_equal(_run("ec 2 3 6 1 -1 2.0 ec micron").column(6), [0, -1, 1, 2, 6, 7])
    # strain: sum of d disp / thickness from record 1 (0 there), held after the range
    thick = "math 1 * 0 = 7 h micron\nmath 7 + 2 = 7 h micron\n"
    np.testing.assert_allclose(_run(thick + "strain 2 7 6 1 4 gamma .").column(6), [0, 0, 1, 2.5, 4.5, 4.5])
    # r_row removes records 2 to 3 from every column; r_col clears a slot
    removed = _run("r_row 2 3\nr_col 3")
    np.testing.assert_array_equal(removed.column(2), [0, 1, 10, 15])
    assert removed.column(3) is None and removed.names[3] is None
    assert "load" not in removed.as_dict() and removed.as_dict()["disp"][1] == "micron"


def test_p655_reduces_to_friction_and_agrees_with_pylook_where_pylook_reads_the_same():
    """Penn State's p655 (Ghost Rocks gouge, 2005): the r-file's 39 commands give shear and normal stress in MPa, the
    layer thickness and the friction mu = tau / sigma_n, about 0.50 while sliding. Against pylook's interpreter
    (benchmarks/rfile_against_pylook.py): the slots no range or ec touches are bit for bit pylook's; normal stress
    and mu differ only at the last record (pylook's -1 stops before it); the layer thickness and ec_disp differ from
    the first record its ec changes (pylook's ec leaves LOAD / SLOPE); strain is faultslip's alone."""
    r = run_r_file(P655)
    assert r.commands == 39 and r.column(6).size == 86813  # one record axed (r_row 86283 86283)
    assert [r.names[s] for s in (1, 2, 3, 4, 5, 6, 7, 8)] == ["LP_disp", "Shear_stress", "layer_thick.", "Nor_stress",
                                                               "Time", "mu", "shear_str", "ec_disp"]
    sliding = r.column(6)[5000:80000]
    assert 0.45 < float(np.median(sliding)) < 0.55  # measured 0.501
    compared = {row["slot"]: row for row in json.loads(
        (ROOT / "benchmarks" / "results" / "rfile_against_pylook.json").read_text())["slots"]}
    assert all(compared[slot]["identical"] for slot in (0, 1, 2, 5))
    for slot in (4, 6):
        assert compared[slot]["records_differing"] == 1 and compared[slot]["first_differing"] == [86812]
    assert compared[8]["first_differing"][0] == 1460 and compared[3]["first_differing"][0] == 43
    assert compared[7]["in_pylook"] is False


@pytest.mark.parametrize("line, words", [
    ("plot 1 2", "does not know the command 'plot'"),
    ("math 1 * 2 = 4 name", "takes 7 arguments"),
    ("math 40 * 2 = 4 n u", "slot number from 0 to 31"),
    ("math 9 * 2 = 4 n u", "column 9 holds no data"),
    ("math 1 ^ 2 = 4 n u", "one of * / + -"),
    ("math 1 * x = 4 n u", "not a number"),
    ("math 1 * 2 ? 4 n u", "':' (column with column)"),
    ("math_int 1 * 2 = 4 3 99 n u", "not within the data"),
    ("math_int 1 * 2 = 4 4 2 n u", "not within the data"),
    ("offset_int 2 1 3 maybe", "hold the records between"),
    ("ec 2 3 6 0 -1 0 n u", "must not be 0"),
    ("r_row a b", "two whole numbers"),
])
def test_a_malformed_line_is_one_sentence_naming_it(line, words):
    with pytest.raises(InputError, match=re.escape(words)) as raised:
        _run(line)
    assert "line 1" in str(raised.value) and "\n" not in str(raised.value)


def test_a_missing_data_file_is_one_sentence(tmp_path):
    (tmp_path / "r").write_text("begin\nread nowhere/p999\nmath 1 * 2 = 4 n u\nend\n")
    with pytest.raises(InputError, match="does not exist"):
        run_r_file(tmp_path / "r")
    with pytest.raises(InputError, match="holds no data"):
        run_commands("zero 1 0", "r")


@settings(max_examples=200, deadline=None)
@given(st.lists(st.text(alphabet="mathintzeroffsec_rolw 0123456789-.*/+=:yn#,", max_size=40), max_size=6))
def test_any_r_file_runs_or_is_refused_in_one_sentence(lines):
    try:
        _run("\n".join(lines))
    except InputError as exc:
        assert str(exc).strip() and "\n" not in str(exc)


def test_the_reduce_command_writes_cf_netcdf_with_the_r_files_units(cli, tmp_path):
    import xarray as xr

    out = cli("reduce", P655, "-o", tmp_path / "p655.nc", "--json")
    assert out.code == 0, out.err
    assert out.json["commands"] == 39
    with xr.open_dataset(tmp_path / "p655.nc") as data:
        assert data.sizes["record"] == 86813
        assert data["Shear_stress"].attrs["units"] == "MPa" and data["mu"].attrs["units"] == "1"
        assert data["mu"].attrs["xlook_units"] == "." and data["ec_disp"].attrs["units"] == "micron"
        np.testing.assert_array_equal(data["mu"].values, run_r_file(P655).column(6))
    from conftest import assert_clean_error

    (tmp_path / "bad_r").write_text("read p655intact100l\nplot 1 2\n")
    assert_clean_error(cli("reduce", tmp_path / "bad_r"), "does not know the command")


def test_a_second_read_of_another_length_replaces_the_data_set(tmp_path):
    """Two data files of different lengths: the second read replaces every slot, so no command mixes them."""
    from faultslip.lab import look_reduction

    short = LookFile("short", {"t": np.arange(3.0), "disp": np.arange(3.0), "load": np.ones(3)},
                     {"t": "s", "disp": "micron", "load": "MPa"})
    long = LookFile("long", {"t": np.arange(5.0), "disp": np.arange(5.0) * 2}, {"t": "s", "disp": "micron"})
    files = iter([short, long])
    original = look_reduction.read_look
    look_reduction.read_look = lambda path: next(files)
    try:
        reduced = run_commands("read a.dat\nread b.dat\nmath 1 + 2 : 4 s micron", "test_r", base_dir=tmp_path)
    finally:
        look_reduction.read_look = original
    np.testing.assert_array_equal(reduced.column(4), np.arange(5.0) * 3)
    assert reduced.column(3) is None  # the first file's load column went with it


# --- xlook's further data commands (issue 74, item 1): each against its source, src/array.c, func.c, cmds.c ----

def _xlook_deriv(x, y, first, last, out):
    """array.c's deriv() as written there: three records a, b, c sliding along, the first value also at FIRST,
    the last also at LAST (a loop, kept apart from faultslip's vectorised one)."""
    out = list(out)
    for i in range(first, last - 1):
        a, b, c = x[i], x[i + 1], x[i + 2]
        ya, yb, yc = y[i], y[i + 1], y[i + 2]
        denom = abs(c - b) * (b - a) * (b - a) + abs(b - a) * (c - b) * (c - b)
        dydx = ((b - a) * (b - a) * yc - (c - b) * (c - b) * ya - ((b - a) * (b - a) - (c - b) * (c - b)) * yb) / denom
        if i == first:
            out[first] = dydx
        out[i + 1] = dydx
    out[last] = dydx
    return out


def test_xlooks_column_functions_by_their_source():
    import math

    x = np.array([0.5, 1.0, 2.0, 3.5, 5.0, 7.5])
    look = LookFile("x", {"t": np.arange(6.0), "x": x, "p": np.array([1.0, 2.0, 0.5, 1.0, 2.0, 3.0])},
                    {"t": "s", "x": "mm", "p": "."})

    def run(line):
        return run_commands(line, "test_r", look=look)

    by_hand = {  # the formulas of src/func.c and src/array.c, a value at a time
        "exp 2 5 e .": [math.exp(v) for v in x], "ln 2 5 e .": [math.log(v) for v in x],
        "log 2 5 e .": [math.log10(v) for v in x], "recip 2 5 e .": [1 / v for v in x],
        "positive 2 5 e .": [1.0 if v > 0.0 else 0.0 for v in x],
        "trig 2 5 sin e .": [math.sin(v) for v in x], "cos 2 5 cos e .": [math.cos(v) for v in x],
        "trig 2 5 tan e .": [math.tan(v) for v in x], "trig 2 5 atan e .": [math.atan(v) for v in x],
        "col_power 3 2 5 e .": [v ** p for v, p in zip(x, [1.0, 2.0, 0.5, 1.0, 2.0, 3.0])],
        "Power1 2 5 1.5 2 e .": [v ** 1.5 + 2 for v in x], "Power2 2 5 3 1.5 2 e .": [3 * v ** 1.5 + 2 for v in x],
        "normal 2 5 2 1.5 e .": [math.exp(-((v - 2) / 1.5) ** 2 / 2) / math.sqrt(2 * math.pi) / 1.5 for v in x],
        "rclow 2 5 2 3 e .": [(1 / (v * 3)) * math.sqrt(1 + (v * 3 * 2) ** 2) for v in x],
        "rcph 2 5 2 3 e .": [-math.atan(1 / (v * 2 * 3)) for v in x],
        "genexp 2 5 2 0.3 0.1 1 e .": [2 * math.exp(0.3 * v + 0.1) + 1 for v in x],
        "gensin 2 5 2 0.3 0.1 1 e .": [2 * math.sin(0.3 * v + 0.1) + 1 for v in x],
        "ExpLin 2 5 2 -0.3 0.1 e .": [2 * (1 - math.exp(-0.3 * v)) + 0.1 * v for v in x],
        "Poly4 2 5 1 2 3 4 5 e .": [1 + 2 * v + 3 * v ** 2 + 4 * v ** 3 + 5 * v ** 4 for v in x],
        "chisqr 2 5 4 e .": [v ** 1 * math.exp(-v / 2) / (4 * math.gamma(2)) for v in x],
        "z_min 2 5 e .": list(x - x.min()), "z_max 2 5 e .": list(x - x.max()), "r_mean 2 5 e .": list(x - x.mean()),
    }
    for line, expected in by_hand.items():
        np.testing.assert_allclose(run(line).column(5), expected, rtol=1e-14, atol=1e-300, err_msg=line)
        assert run(line).names[5] == "e"
    np.testing.assert_array_equal(run("math 2 - 2 = 6 d .\npositive 6 5 e .").column(5), [0, 0, 0, 1, 1, 1])
    # deriv: records 1 to 4 by array.c's loop; the records outside keep a new slot's zeros
    derived = run("deriv 1 2 5 1 4 dxdt mm/s").column(5)
    np.testing.assert_allclose(derived, _xlook_deriv(np.arange(6.0), x, 1, 4, [0.0] * 6), rtol=1e-14)
    assert derived[0] == 0.0 and derived[5] == 0.0
    np.testing.assert_allclose(run("deriv 1 2 5 0 -1 d .").column(5)[1:5], [0.75, 1.25, 1.5, 2.0], rtol=1e-14)
    # r_spike: record 3 takes record 2's value; name renames a slot
    np.testing.assert_array_equal(run("r_spike 2 3").column(2), [0.5, 1.0, 2.0, 2.0, 5.0, 7.5])
    renamed = run("name 2 slip micron")
    assert renamed.names[2] == "slip" and renamed.units[2] == "micron"


def test_the_chi_square_density_integrates_to_one():
    """xlook's func.c takes exp(tgamma(k / 2)) where the older C library's gamma() gave ln Gamma; faultslip takes
    Gamma(k / 2), the density's own: it integrates to 1, which exp(Gamma) would not (k = 4: exp(1) = 2.72)."""
    x = np.linspace(1e-9, 80.0, 400_001)
    look = LookFile("x", {"x": x}, {"x": "."})
    for ndf in (3.0, 4.0, 7.5):
        density = run_commands(f"chisqr 1 2 {ndf} f .", "r", look=look).column(2)
        assert np.trapezoid(density, x) == pytest.approx(1.0, abs=1e-6)


def test_display_commands_are_skipped_and_the_reduction_says_which():
    r = _run("begin\nplotall 1 2\ntype 1 2 0 5\nmath 2 * 2 = 5 d micron\nstat 2 0 5\nkp 1\nend")
    assert r.ran == ["begin", "math"]
    assert [entry.split(": ")[1].split(" (")[0] for entry in r.skipped] == ["plotall", "type", "stat", "kp"]
    assert r.to_dataset().attrs["commands_skipped"].startswith("test_r line 2: plotall")
    with pytest.raises(InputError, match="does not know the command 'smoothish'.*skips xlook's display commands"):
        _run("smoothish 1 2")


def _xlook_smooth(x, start, end, window):
    """special.c's smooth(), transcribed line for line (its scratch in a list of its own)."""
    out = [0.0] * len(x)
    window = 2 * (window // 2) + 1
    half = window // 2
    total = 0.0
    for _ in range(half):
        total += x[start]
    k = 0
    for i in range(window):
        if i < half:
            total += x[start + i]
        else:
            total += x[start + i]
            out[start + k] = total / window
            total -= x[start]
            k += 1
    j = window - 1
    for i in range(start + window, end + 1):
        total += x[i]
        out[i - half] = total / window
        total -= x[i - j]
    for i in range(1, half + 1):
        total += x[end]
        out[end - half + i] = total / window
        total -= x[end - window]
    return out


def _xlook_slope(x, y, start, end, window):
    """special.c's o_slope(), transcribed line for line."""
    out = [0.0] * len(x)
    window = 2 * (window // 2) + 1
    half = window // 2
    xsum = ysum = 0.0
    for i in range(start, start + window - 1):
        xsum += x[i]
        ysum += y[i]
    k, j = start + half, start
    for i in range(start + window - 1, end + 1):
        xsum += x[i]
        ysum += y[i]
        x_mean, y_mean = xsum / window, ysum / window
        sumx2 = sumxy = 0.0
        for l in range(j, i + 1):
            sumx2 += (x[l] - x_mean) * (x[l] - x_mean)
            sumxy += (x[l] - x_mean) * (y[l] - y_mean)
        out[k] = sumxy / sumx2
        xsum -= x[j]
        ysum -= y[j]
        k += 1
        j += 1
    for i in range(half):
        out[i + start] = out[start + half]
    for i in range(half):
        out[end - i] = out[end - half - 1]
    return out


def test_xlooks_offset_and_window_commands_by_their_source():
    rng = np.random.default_rng(74)
    x = np.cumsum(rng.uniform(0.5, 1.5, 40))
    y = np.sin(x) + 0.1 * rng.standard_normal(40)
    look = LookFile("x", {"x": x, "y": y}, {"x": "s", "y": "mm"})

    def run(line):
        return run_commands(line, "test_r", look=look)

    np.testing.assert_allclose(run("offset 2 5 1 7").column(2), y + (x[7] - y[5]), rtol=1e-15)
    for first, last, window in ((0, 39, 5), (3, 30, 7), (2, 20, 4)):  # 4 is forced to 5, as special.c does
        smoothed = run(f"smooth 2 3 {first} {last} {window} s mm").column(3)
        np.testing.assert_allclose(smoothed[first:last + 1], _xlook_smooth(y, first, last, window)[first:last + 1],
                                   rtol=1e-13)
        slopes = run(f"slope 1 2 3 {first} {last} {window} s mm/s").column(3)
        np.testing.assert_allclose(slopes[first:last + 1], _xlook_slope(x, y, first, last, window)[first:last + 1],
                                   rtol=1e-12)
        median = run(f"ms 2 3 {first} {last} {window} m mm").column(3)
        odd = 2 * (window // 2) + 1
        for i in range(first + odd // 2, last - odd // 2):  # each window's median at its middle
            assert median[i] == np.median(y[i - odd // 2:i + odd // 2 + 1])
        # the half-windows at the ends keep the data, the last window's middle too (special.c copies from
        # LAST - WINDOW / 2 on, over the last median it wrote)
        np.testing.assert_array_equal(median[first:first + odd // 2], y[first:first + odd // 2])
        np.testing.assert_array_equal(median[last - odd // 2:last + 1], y[last - odd // 2:last + 1])
    with pytest.raises(InputError, match="does not fit"):
        run("smooth 2 3 0 3 9 s mm")


def test_xlooks_thinning_and_volume_corrections_by_their_source():
    """array.c's calc_geom_thin, geom_thin and vol_corr as written there (their parameters read as C floats, as
    sscanf's %f reads them)."""
    import struct

    def c_float(value):
        return struct.unpack("f", struct.pack("f", value))[0]

    rng = np.random.default_rng(7)
    d = np.cumsum(rng.uniform(0.0, 2.0, 30))
    thick = 3000.0 - np.cumsum(rng.uniform(0.0, 1.0, 30))
    tau = np.cumsum(rng.normal(0.0, 0.1, 30))
    look = LookFile("x", {"d": d, "h": thick, "tau": tau}, {"d": "micron", "h": "micron", "tau": "MPa"})

    def run(line):
        return run_commands(line, "r", look=look)

    length, initial = c_float(50000.1), c_float(3000.3)
    h, expected = initial, [initial]
    for i in range(1, 30):
        h -= (d[i] - d[i - 1]) * h / (length * 2.0)
        expected.append(h)
    np.testing.assert_array_equal(run("cgt 50000.1 3000.3 1 4 h micron").column(4), expected)
    change, expected = 0.0, [thick[0]]
    for i in range(1, 30):
        change += (d[i] - d[i - 1]) * thick[i - 1] / (length * 2.0)
        expected.append(thick[i - 1] + change)
    np.testing.assert_array_equal(run("rgt 50000.1 1 2 4 h micron").column(4), expected)
    factor = c_float(0.013)
    out = [0.0] * 30
    out[3] = d[3]
    for row in range(4, 21):
        out[row] = out[row - 1] + d[row] - d[row - 1] - (tau[row] - tau[row - 1]) * factor
    np.testing.assert_array_equal(run("vc 1 3 4 3 20 0.013 vs micron").column(4), out)
    with pytest.raises(InputError, match="must not be its displacement column"):
        run("rgt 50000 1 2 1 h micron")


def test_xlooks_trend_removal_sort_and_curvature_by_their_source():
    import struct

    rng = np.random.default_rng(11)
    t = np.arange(20.0)
    y = 3.0 + 0.5 * t + rng.normal(0.0, 0.2, 20)
    look = LookFile("x", {"t": t, "y": y, "s": np.array([0, 1, 3, 2, 4, 6, 5, 5, 7, 8, 9, 1, 10, 11, 12, 13, 2,
                                                          14, 15, 16], float)},
                    {"t": "s", "y": "mm", "s": "mm"})

    def run(line):
        return run_commands(line, "r", look=look)

    # r_trend: the least-squares line over records 2 to 15 by special.c's line(), removed from Y everywhere
    x_mean, y_mean = t[2:16].mean(), y[2:16].mean()
    slope = np.sum((y[2:16] - y_mean) * (t[2:16] - x_mean)) / np.sum((t[2:16] - x_mean) ** 2)
    intercept = y_mean - slope * x_mean
    np.testing.assert_allclose(run("r_trend Y c 1 2 4 2 15 d mm").column(4), y - (t * slope + intercept), rtol=1e-13)
    np.testing.assert_allclose(run("r_trend y i 1 2 4 0.5 3 d mm").column(4), y - (0.5 * t + 3), rtol=1e-15)
    np.testing.assert_allclose(run("r_trend x i 1 2 4 0.5 3 d mm").column(4), t - (y - 3) / 0.5, rtol=1e-13)
    offset = run("r_trend_o Y c 1 2 4 2 15 d mm").column(4)
    assert offset[2] == pytest.approx(y[2], rel=1e-14)  # then offset to Y at the fit's first record
    # sort: from record 1 to 17, the records that continue the order; the rest removed from every column
    sorted_run = run("sort 3 1 17")
    np.testing.assert_array_equal(sorted_run.column(3), [0, 1, 3, 4, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16])
    np.testing.assert_array_equal(sorted_run.column(0), [0, 1, 2, 4, 5, 8, 9, 10, 12, 13, 14, 15, 17, 18, 19])
    assert len(sorted_run.column(2)) == 15
    # curv: the fourth-order second difference, DX read as a C float
    dx = struct.unpack("f", struct.pack("f", 0.1))[0]
    curvature = run("curv 2 4 0.1 c mm").column(4)
    i = np.arange(2, 18)
    np.testing.assert_allclose(curvature[2:18], (-30 * y[i] + 16 * (y[i + 1] + y[i - 1]) - (y[i + 2] + y[i - 2]))
                               / (12 * dx ** 2), rtol=1e-13)
    assert curvature[0] == curvature[1] == curvature[18] == curvature[19] == 0.0


def test_xlooks_commands_that_change_a_columns_length_by_their_source(tmp_path):
    import struct

    x = np.array([0.0, 0.4, 1.1, 1.5, 2.6, 3.0, 3.9, 5.2, 6.0, 7.1])
    y = np.array([2.0, 0.0, 5.0, 0.0, 1.0, 9.0, 3.0, 0.0, 4.0, 8.0])
    look = LookFile("x", {"x": x, "y": y}, {"x": "s", "y": "mm"})

    def run(line):
        return run_commands(line, "r", look=look)

    # compress: the non-zero values, a column of 7 records
    compressed = run("compress 2 4 c mm")
    np.testing.assert_array_equal(compressed.column(4), [2, 5, 1, 9, 3, 4, 8])
    dataset = compressed.to_dataset()
    assert dataset["c"].attrs["xlook_records"] == 7 and np.isnan(dataset["c"].values[7:]).all()
    with pytest.raises(InputError, match="holds 7 records where the data set has 10"):
        run("compress 2 4 c mm\nmath 4 + 1 : 5 s mm")
    # r_row_col: records 2 to 4 from column 2 alone
    np.testing.assert_array_equal(run("rrc 2 2 4").column(2), [2, 0, 9, 3, 0, 4, 8])
    assert len(run("rrc 2 2 4").column(1)) == 10
    # decimat: every third record of 1 to 8 (y at 1, 4 and 7) from record 1 on; decimat_r ends the column there
    np.testing.assert_array_equal(run("decimat 1 4 3 1 8 d s").column(4), [0, 0.4, 2.6, 5.2, 0, 0, 0, 0, 0, 0])
    np.testing.assert_array_equal(run("decimat_r 1 4 3 1 8 d s").column(4), [0, 0.4, 2.6, 5.2])
    # peak: above both neighbours each side
    np.testing.assert_array_equal(run("peak 2 4 p mm").column(4), [0, 0, 5, 0, 0, 9, 0, 0, 0, 0])
    # interpolate: y at x = 0, 1, 2, ... (increment 1) by do_interpolate's walk, linear between records
    walked = run("interpolate 1 2 4 5 0 9 1 xi s yi mm")
    new_x, new_y = [x[0]], [y[0]]
    i, k = 0, 1
    while k <= 9:
        if new_x[i] + 1.0 > x[k]:
            k += 1
        else:
            new_y.append(y[k - 1] + (y[k] - y[k - 1]) * (new_x[i] + 1.0 - x[k - 1]) / (x[k] - x[k - 1]))
            new_x.append(new_x[i] + 1.0)
            i += 1
    np.testing.assert_allclose(walked.column(4)[:len(new_x)], new_x, rtol=1e-15)
    np.testing.assert_allclose(walked.column(5)[:len(new_y)], new_y, rtol=1e-15)
    trimmed = run("interpolate_r 1 2 4 5 0 9 1 xi s yi mm")
    assert len(trimmed.column(1)) == len(new_x) and trimmed.names[4] == "xi" and trimmed.units[5] == "mm"
    # pdf: 4 bins of y from 0 to 9, each value's bin truncated from a C float, scaled to a density
    density = run("pdf 2 4 6 4 9 0")
    index = [int(struct.unpack("f", struct.pack("f", 3 * v / 9))[0]) for v in y]
    counts = np.bincount(index, minlength=4)
    np.testing.assert_allclose(density.column(4), counts / (10 * 9 / 3), rtol=1e-15)
    np.testing.assert_allclose(density.column(6), 0 + (np.arange(4) + 0.5) / 3 * 9, rtol=1e-15)
    assert density.names[4] == "prob_dens" and density.units[6] == "mm"
    assert np.trapezoid(density.column(4), dx=3.0) > 0
    with pytest.raises(InputError, match="outside 0 to 5"):
        run("pdf 2 4 6 4 5 0")


def test_xlooks_polyfit_is_the_least_squares_polynomial():
    """A cubic recovered exactly from cubic data (any least-squares method must), and the fit on noisy data equal
    to numpy's polyfit; the modes write where do_polyfit writes."""
    rng = np.random.default_rng(3)
    x = np.linspace(0.0, 4.0, 30)
    cubic = 1.0 - 2.0 * x + 0.5 * x ** 2 + 0.25 * x ** 3
    noisy = cubic + rng.normal(0.0, 0.1, 30)
    look = LookFile("x", {"x": x, "c": cubic, "n": noisy}, {"x": "s", "c": "mm", "n": "mm"})

    def run(line):
        return run_commands(line, "r", look=look)

    np.testing.assert_allclose(run("polyfit 1 2 4 3 0 29 n f mm").column(4), cubic, rtol=1e-12, atol=1e-12)
    fitted = run("polyfit 1 3 4 2 5 24 n f mm").column(4)
    expected = np.polyval(np.polyfit(x[5:25], noisy[5:25], 2), x)
    np.testing.assert_allclose(fitted[5:25], expected[5:25], rtol=1e-10)
    assert fitted[4] == 0.0 and fitted[25] == 0.0  # n: the fitted records only
    np.testing.assert_allclose(run("polyfit 1 3 4 2 5 24 a f mm").column(4), expected, rtol=1e-10)
    extended = run("polyfit 1 3 4 2 5 24 y 27 f mm").column(4)
    np.testing.assert_allclose(extended[5:28], expected[5:28], rtol=1e-10)
    assert extended[28] == 0.0
    stepped = run("polyfit_i 1 2 4 3 0 9 0.05 f mm").column(4)
    np.testing.assert_allclose(stepped[:10], np.polyval([0.25, 0.5, -2.0, 1.0], 0.05 * np.arange(10)), rtol=1e-12,
                               atol=1e-12)
    with pytest.raises(InputError, match="needs more than 5 records"):
        run("polyfit 1 2 4 5 0 4 n f mm")


@pytest.mark.parametrize("command", ["qi 1 2 3", "simplex 1 2", "rsm 1 2 3 4", "cm 1 2"])
def test_xlooks_interactive_rate_and_state_tools_are_skipped_with_the_way_there(command):
    reduced = _run(f"math 2 * 2 = 4 d mm\n{command}")
    assert reduced.ran == ["math"]
    assert "interactive rate-and-state tool" in reduced.skipped[0]
    assert "faultslip fit --law rate-state" in reduced.skipped[0]


def test_append_and_doit_run_as_xlook_runs_them(tmp_path):
    """append adds a second file's records after the first's; doit runs a command file beside the r-file on the
    same data, and a loop of doit files is refused in one sentence."""
    from test_look_files import _ascii_export  # xlook's ASCII export, as its type command writes it

    (tmp_path / "run_a").write_text(_ascii_export({"t": np.arange(3.0), "d": np.array([0.0, 1.0, 2.0])},
                                                  {"t": "s", "d": "mm"}))
    (tmp_path / "run_b").write_text(_ascii_export({"t": np.arange(3.0, 5.0), "d": np.array([3.0, 5.0])},
                                                  {"t": "s", "d": "mm"}))
    (tmp_path / "double").write_text("begin\nmath 2 * 2 = 3 twice mm\nend\n")
    (tmp_path / "r").write_text("begin\nread run_a\nappend run_b\ndoit double\nend\n")
    reduced = run_r_file(tmp_path / "r")
    np.testing.assert_array_equal(reduced.column(2), [0, 1, 2, 3, 5])
    np.testing.assert_array_equal(reduced.column(0), np.arange(5.0))
    np.testing.assert_array_equal(reduced.column(3), [0, 2, 4, 6, 10])
    assert reduced.ran == ["begin", "read", "append", "begin", "math", "doit"]
    (tmp_path / "loop").write_text("doit loop\n")
    (tmp_path / "r2").write_text("read run_a\ndoit loop\n")
    with pytest.raises(InputError, match="more than 8 deep"):
        run_r_file(tmp_path / "r2")
