"""xlook's binary data files (issue 46, item 1): the three layouts written and read back, a real Penn State biax
run read as pylook reads it, and every malformed file refused in one sentence."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import faultslip
from faultslip.errors import InputError
from faultslip.lab.look_files import LAYOUTS, parse_look, read_look

ROOT = Path(__file__).resolve().parents[3]
P655 = ROOT / "data" / "p655" / "p655intact100l"


def write_look(name: str, columns: dict, units: dict, layout=(32, 4, ">f4")) -> bytes:
    """An xlook data file's bytes, laid out as the module docstring says (the test's own writer)."""
    slots, width, dtype = layout
    records = len(next(iter(columns.values())))
    header = name.encode().ljust(20, b"\x00") + np.array([records, len(columns), 0, 0], ">i4").tobytes()
    blocks = []
    names = list(columns)
    for slot in range(slots):
        if slot < len(names):
            column = names[slot]
            blocks.append(column.encode().ljust(13, b"\x00") + units[column].encode().ljust(13, b"\x00")
                          + np.array([0], ">i4").tobytes() + b"\x00" * 50 + np.array([records], ">i4").tobytes())
        else:
            blocks.append(b"no_val".ljust(13, b"\x00") + b"".ljust(13, b"\x00") + np.zeros(1, ">i4").tobytes()
                          + b"\x00" * 50 + np.zeros(1, ">i4").tobytes())
    data = b"".join(np.asarray(columns[column], dtype).tobytes() for column in names)
    return header + b"".join(blocks) + data


@pytest.mark.parametrize("layout", LAYOUTS, ids=lambda layout: f"{layout[0]}ch-{layout[1]}B")
@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_every_layout_reads_back_what_was_written(layout, data):
    count = data.draw(st.integers(1, min(layout[0], 6)))
    records = data.draw(st.integers(1, 50))
    values = st.floats(width=32, allow_nan=False) if layout[1] == 4 else st.floats(allow_nan=False, allow_infinity=False)
    columns = {f"col{i}": np.array(data.draw(st.lists(values, min_size=records, max_size=records)))
               for i in range(count)}
    units = {name: f"u{i}" for i, name in enumerate(columns)}
    read = parse_look(write_look("exp1", columns, units, layout), "t.look")
    assert read.name == "exp1" and read.layout == layout and read.records == records
    assert list(read.columns) == list(columns) and read.units == units
    for name, column in columns.items():
        assert np.array_equal(read.columns[name], column.astype(layout[2]).astype(np.float64))


def test_the_p655_biax_run_reads_as_pylook_reads_it():
    """Penn State's p655 (2005, from pylook's repository, BSD-3): 86,814 records of five columns, 4-byte big-endian
    floats under 32 column headers; every column bit for bit what pylook's reader gives
    (benchmarks/look_against_pylook.py, run in pylook's own interpreter)."""
    look = faultslip.lab.read_look(P655)
    assert look.name == "p655intact100" and look.records == 86814 and look.layout == (32, 4, ">f4")
    assert list(look.columns) == ["Time", "Vert_Disp", "Vert_Load", "Hor_Disp", "Hor_Load."]
    assert look.units["Time"] == "sec" and look.units["Vert_Load"] == "bits"
    compared = json.loads((ROOT / "benchmarks" / "results" / "look_against_pylook.json").read_text())
    assert compared["records"] == [86814, 86814] and not compared["only_in_pylook"]
    assert [row["column"] for row in compared["columns"]] == list(look.columns)
    assert all(row["bit_identical"] for row in compared["columns"])
    assert (P655.parent / "LICENSE").read_text().startswith("BSD 3-Clause License")


@pytest.mark.parametrize("damage, message", [
    (lambda b: b[:30], "too short"),
    (lambda b: b[:-4], "fits no xlook layout"),
    (lambda b: b + b"\x00" * 3, "fits no xlook layout"),
    (lambda b: b[:24] + np.array([40], ">i4").tobytes() + b[28:], "1 to 32 columns"),
    (lambda b: b[:20] + np.array([-5], ">i4").tobytes() + b[24:], "records"),
])
def test_a_malformed_file_is_refused_in_one_sentence(damage, message):
    good = write_look("x", {"a": np.arange(10.0), "b": np.ones(10)}, {"a": "s", "b": "MPa"})
    with pytest.raises(InputError, match=message) as raised:
        parse_look(damage(good), "bad.look")
    assert "\n" not in str(raised.value)


def test_a_header_that_disagrees_with_its_columns_is_refused():
    good = write_look("x", {"a": np.arange(10.0), "b": np.ones(10)}, {"a": "s", "b": "MPa"})
    renamed = good[:36 + 84] + b"no_val".ljust(13, b"\x00") + good[36 + 84 + 13:]  # column b marked empty
    with pytest.raises(InputError, match="names 1 columns"):
        parse_look(renamed, "bad.look")
    start = 36 + 84 + 80  # the second column's record count
    short = good[:start] + np.array([9], ">i4").tobytes() + good[start + 4:]
    with pytest.raises(InputError, match="has 9 records"):
        parse_look(short, "bad.look")
    with pytest.raises(InputError, match="does not exist"):
        read_look(ROOT / "no_such.look")


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(0, 400))
def test_damaged_bytes_are_read_or_refused_never_a_traceback(seed, cut):
    """Any byte flipped anywhere, or any truncation, reads or is one InputError sentence."""
    good = bytearray(write_look("x", {"a": np.arange(20.0), "b": np.ones(20)}, {"a": "s", "b": "MPa"},
                                (16, 4, ">f4")))
    rng = np.random.default_rng(seed)
    for index in rng.integers(0, len(good), 3):
        good[index] = int(rng.integers(0, 256))
    try:
        parse_look(bytes(good[:len(good) - cut]), "fuzz.look")
    except InputError as exc:
        assert str(exc).strip() and "\n" not in str(exc)


# --- xlook's ASCII export (issue 46, item 1) ---------------------------------------------------------------

def _ascii_export(columns: dict, units: dict) -> str:
    """A run as xlook's 'type' command exports it (the layout Leeman's biaxread reads): the records, the column
    labels, names and units in 12-character fields after a margin of 5, each column's records, then the rows."""
    names = list(columns)
    records = len(next(iter(columns.values())))
    lines = [f"number of records = {records}", "     " + "".join(f"col {i + 1}".ljust(12) for i in range(len(names))),
             "     " + "".join(name.ljust(12) for name in names),
             "     " + "".join((units[name] or ".").ljust(12) for name in names),
             "     " + "".join(f"{records} recs".ljust(12) for _ in names)]
    table = np.column_stack([columns[name] for name in names])
    lines += [f"{row + 1:8d} " + " ".join(f"{value:.17g}" for value in values) for row, values in enumerate(table)]
    return "\n".join(lines) + "\n"


def test_an_ascii_export_of_p655_reads_as_its_binary_file(tmp_path):
    """The first 2,000 records of p655 exported as text read back bit for bit (17 significant digits), through the
    same read_look that an r-file's 'read' command uses."""
    look = faultslip.lab.read_look(P655)
    columns = {name: values[:2000] for name, values in look.columns.items()}
    path = tmp_path / "p655.txt"
    path.write_text(_ascii_export(columns, look.units), encoding="utf-8")
    read = read_look(path)
    assert read.layout == ("ascii",) and list(read.columns) == list(look.columns)
    assert read.units == look.units
    for name in columns:
        assert np.array_equal(read.columns[name], columns[name])


@settings(max_examples=60, deadline=None)
@given(data=st.data())
def test_ascii_exports_read_back_what_was_written(data):
    from faultslip.lab.look_files import parse_look_ascii

    count = data.draw(st.integers(1, 8))
    records = data.draw(st.integers(1, 30))
    values = st.floats(allow_nan=False, allow_infinity=False)
    columns = {f"c{i}": np.array(data.draw(st.lists(values, min_size=records, max_size=records)))
               for i in range(count)}
    units = {name: data.draw(st.sampled_from(["", "mm", "MPa", "sec"])) for name in columns}
    read = parse_look_ascii(_ascii_export(columns, units), "t.txt")
    assert read.units == units and all(np.array_equal(read.columns[n], columns[n]) for n in columns)


@pytest.mark.parametrize("spoil, message", [
    (lambda t: t.replace("number of records = 3", "records: 3"), "not an xlook ASCII export"),
    (lambda t: t.replace("number of records = 3", "number of records = three"), "number of records = N"),
    (lambda t: t.replace("number of records = 3", "number of records = 4"), "every one of its"),
    (lambda t: t.rsplit("\n", 2)[0] + "\n", "has 2 rows"),
    (lambda t: t.replace(" 1.5 ", " x ", 1), "data row 1"),
    (lambda t: "\n".join(t.splitlines()[:3]), "not an xlook ASCII export"),
])
def test_a_malformed_ascii_export_is_one_sentence(spoil, message):
    from faultslip.lab.look_files import parse_look_ascii

    good = _ascii_export({"a": np.array([1.5, 2.0, 3.0]), "b": np.array([1.5, 4.0, 5.0])}, {"a": "s", "b": "MPa"})
    with pytest.raises(InputError, match=message) as raised:
        parse_look_ascii(spoil(good), "bad.txt")
    assert "\n" not in str(raised.value)
