"""The tables faultslip ships in data/ and reads back (calibrations, cost models, declared errors): each is written
by its benchmark sealed with a checksum (faultslip.io.resources.write_bundled_table), and read only where it matches.
An edited coefficient would otherwise change what faultslip declares with no other sign."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings, strategies as st

from faultslip.errors import InputError
from faultslip.io import gate, resources
from faultslip.io.resources import TABLE_CHECKSUM, bundled_dir, bundled_table_text, read_bundled_table, write_bundled_table

SHIPPED_DIR = bundled_dir("data")
SHIPPED = sorted(path.name for path in SHIPPED_DIR.glob("*.json"))
TABLE = {"provenance": {"computed_by": "benchmarks/example.py"}, "rows": [{"dip": 30.0, "model_error": 0.12}],
         "coefficients": [1.5, -0.25, 3e-9], "flag": True}


def _nested_numbers(value, where=()):
    """(path, number) for every number in a JSON value."""
    if isinstance(value, dict):
        for key, item in value.items():
            yield from _nested_numbers(item, where + (key,))
    elif isinstance(value, list):
        for index, item in enumerate(value):
            yield from _nested_numbers(item, where + (index,))
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        yield where, value


@pytest.fixture
def data_dir(tmp_path, monkeypatch):
    monkeypatch.setattr(resources, "bundled_dir", lambda kind: tmp_path)  # where read_bundled_table looks
    return tmp_path


@pytest.mark.parametrize("name", SHIPPED)
def test_every_shipped_table_matches_the_checksum_written_with_it(name):
    table = read_bundled_table(name, name, "its benchmark")
    assert TABLE_CHECKSUM not in table and table
    # the file is exactly what write_bundled_table writes of that content: nothing was added by hand
    assert (SHIPPED_DIR / name).read_text(encoding="utf-8") == bundled_table_text(table)


def test_a_written_table_reads_back_as_it_was_given(data_dir):
    write_bundled_table(data_dir / "example.json", TABLE)
    assert read_bundled_table("example.json", "the example", "benchmarks/example.py") == TABLE
    stored = json.loads((data_dir / "example.json").read_text(encoding="utf-8"))
    assert stored[TABLE_CHECKSUM] == gate.json_checksum(TABLE)


def test_a_table_with_its_own_checksum_key_is_not_written(data_dir):
    with pytest.raises(ValueError, match="checksum"):
        write_bundled_table(data_dir / "example.json", {**TABLE, TABLE_CHECKSUM: "0" * 64})
    assert not (data_dir / "example.json").exists()


@settings(max_examples=60, deadline=None)
@given(st.data())
def test_any_number_edited_after_writing_is_refused_in_one_sentence(tmp_path_factory, data):
    """A hypothesis property over the shipped tables themselves: change any one number in one of them and the
    reader refuses it, naming the table and the benchmark that writes it."""
    folder = tmp_path_factory.mktemp("data")
    name = data.draw(st.sampled_from(SHIPPED))
    table = read_bundled_table(name, name, "its benchmark")
    where, value = data.draw(st.sampled_from(list(_nested_numbers(table))))
    new = data.draw(st.one_of(st.floats(allow_nan=False, allow_infinity=False), st.integers(-10 ** 6, 10 ** 6))
                    .filter(lambda x: x != value))
    edited = json.loads(json.dumps(table))
    parent = edited
    for key in where[:-1]:
        parent = parent[key]
    parent[where[-1]] = new
    sealed = json.loads(bundled_table_text(table))
    (folder / name).write_text(json.dumps({**edited, TABLE_CHECKSUM: sealed[TABLE_CHECKSUM]}, indent=1),
                               encoding="utf-8")
    original = resources.bundled_dir
    resources.bundled_dir = lambda kind: folder
    try:
        with pytest.raises(InputError, match="does not match the checksum written with it") as caught:
            read_bundled_table(name, "the table", "benchmarks/producer.py")
    finally:
        resources.bundled_dir = original
    message = str(caught.value)
    assert "\n" not in message and name in message and "run benchmarks/producer.py" in message


def test_a_table_without_its_checksum_is_refused(data_dir):
    (data_dir / "example.json").write_text(json.dumps(TABLE), encoding="utf-8")
    with pytest.raises(InputError, match="carries no checksum.*run benchmarks/example.py"):
        read_bundled_table("example.json", "the example", "benchmarks/example.py")


def test_a_damaged_table_is_refused_in_one_sentence(data_dir):
    (data_dir / "example.json").write_bytes(bundled_table_text(TABLE).encode()[:40])
    with pytest.raises(InputError, match="reinstall faultslip or run benchmarks/example.py") as caught:
        read_bundled_table("example.json", "the example", "benchmarks/example.py")
    assert "\n" not in str(caught.value)


def test_an_edited_calibration_stops_the_one_slider_with_one_sentence(data_dir):
    """Through the library as a user meets it: the ladder's calibration edited in place (its recurrence
    coefficients scaled) is refused where the one slider reads it, not used."""
    from faultslip.fault import ladder

    shipped = json.loads((SHIPPED_DIR / ladder.CALIBRATION_FILE).read_text(encoding="utf-8"))
    shipped["recurrence"]["coefficients"][0] += 0.1
    (data_dir / ladder.CALIBRATION_FILE).write_text(json.dumps(shipped, indent=1), encoding="utf-8")
    ladder.load_calibration.cache_clear()
    try:
        with pytest.raises(InputError, match="ladder's calibration.*does not match the checksum"):
            ladder.load_calibration()
    finally:
        ladder.load_calibration.cache_clear()
