"""A long run's records stay on disk (issue 43, item 4): a finished record file indexed as numpy would index
it, a 2-D run with a folder equal through every output to the same run in memory, and a large variable
written to netCDF a block at a time equal to the variable written whole."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st

from faultslip.io import netcdf, records
from faultslip.io.netcdf import write_dataset
from faultslip.io.records import RecordColumns, RecordStream, lazy_data
from faultslip.models.fault_2d.family import to_dataset, write_outputs, _result
from faultslip.models.fault_2d.integrate import YEAR, run_cycles
from faultslip.models.fault_2d.scene import read_fault_2d_scene

from test_fault_2d import CONFIGS, STATIONS, small_fault


def _written(tmp_path, values: np.ndarray) -> RecordStream:
    stream = RecordStream(tmp_path / "rows.f8", values.shape[1])
    for row in values:
        stream.append(row)
    stream.sync()
    return stream


row_keys = st.one_of(
    st.integers(-40, 39),
    st.builds(slice, st.none() | st.integers(-45, 45), st.none() | st.integers(-45, 45),
              st.none() | st.integers(1, 7) | st.integers(-7, -1)),
    st.lists(st.booleans(), min_size=40, max_size=40).map(np.array),
    st.lists(st.integers(-40, 39), max_size=30).map(lambda v: np.array(v, dtype=int)),
)
column_keys = st.one_of(st.integers(-4, 3), st.builds(slice, st.none() | st.integers(-5, 5), st.none() | st.integers(-5, 5)))


@settings(max_examples=150, deadline=None)
@given(rows=row_keys, columns=column_keys, rows_per_block=st.sampled_from([1, 3, 1 << 20]))
def test_a_record_on_disk_is_indexed_as_numpy_indexes_it(tmp_path_factory, rows, columns, rows_per_block):
    folder = tmp_path_factory.mktemp("records")
    values = np.random.default_rng(7).normal(size=(40, 9))
    stream = _written(folder, values)
    old, records.BLOCK_BYTES = records.BLOCK_BYTES, rows_per_block * 9 * 8  # blocks of a row, a few, or all
    try:
        on_disk = stream.columns(slice(2, 6))
        assert isinstance(on_disk, RecordColumns) and on_disk.shape == (40, 4)
        expected = values[:, 2:6][rows, columns]
        got = on_disk[rows, columns]
        assert got.shape == expected.shape and np.array_equal(got, expected)
        assert np.array_equal(np.asarray(on_disk), values[:, 2:6])
    finally:
        records.BLOCK_BYTES = old
        stream.close()


def test_a_record_file_removed_after_the_run_is_one_sentence(tmp_path):
    stream = _written(tmp_path, np.ones((5, 3)))
    on_disk = stream.columns(slice(None))
    stream.remove()
    with pytest.raises(Exception, match="is gone"):
        on_disk[:, 0]


def test_a_2d_run_with_a_folder_equals_the_run_in_memory_in_every_output(tmp_path):
    fault = small_fault(element_size=1000.0)
    in_memory = run_cycles(fault, 200 * YEAR, rtol=1e-6, stations=STATIONS)
    on_disk = run_cycles(fault, 200 * YEAR, rtol=1e-6, stations=STATIONS, folder=tmp_path / "run")
    assert isinstance(on_disk.profiles, RecordColumns) and isinstance(on_disk.stations["slip"], RecordColumns)
    assert isinstance(in_memory.profiles, np.ndarray)
    for name in in_memory.stations:
        assert np.array_equal(np.asarray(on_disk.stations[name]), in_memory.stations[name])
    assert np.array_equal(on_disk.station_time, in_memory.station_time)
    assert np.array_equal(np.asarray(on_disk.profiles), in_memory.profiles)
    assert np.array_equal(np.asarray(on_disk.profile_log10_slip_rate), in_memory.profile_log10_slip_rate)
    # the files a run writes are byte for byte the same, and so is its netCDF's content
    loaded = read_fault_2d_scene(CONFIGS / "seas_bp1.toml")
    for run, folder in ((in_memory, tmp_path / "a"), (on_disk, tmp_path / "b")):
        folder.mkdir()
        write_outputs(loaded, run, folder, _result(loaded, run, 1e-3))
    for path in (tmp_path / "a").iterdir():
        if path.suffix != ".nc":
            assert path.read_bytes() == (tmp_path / "b" / path.name).read_bytes(), path.name
    with xr.open_dataset(tmp_path / "a" / "fault_2d.nc") as a, xr.open_dataset(tmp_path / "b" / "fault_2d.nc") as b:
        xr.testing.assert_identical(a, b)
    # the dataset the API returns reads the folder's records only when asked
    lazy = to_dataset(loaded, on_disk)
    assert not lazy["profile_slip"].variable._in_memory
    assert np.array_equal(lazy["profile_slip"][-3:, 5].values, in_memory.profiles[-3:, 5])


def test_a_large_variable_is_written_a_block_at_a_time_and_reads_back_equal(tmp_path, monkeypatch):
    values = np.random.default_rng(3).normal(size=(3001, 7))
    values[5, 2] = np.nan
    stream = _written(tmp_path, values)
    monkeypatch.setattr(netcdf, "STREAM_BYTES", 1000)  # blocks of 17 rows: many, and a partial last one
    lazy = xr.Dataset({"series": (("time", "station"), lazy_data(stream.columns(slice(None))),
                                  {"units": "m", "long_name": "slip"}),
                       "small": ("station", np.arange(7.0))},
                      coords={"time": np.arange(3001.0), "station": np.arange(7) * 2.5})
    eager = lazy.load()
    write_dataset(lazy, tmp_path / "streamed.nc")
    monkeypatch.setattr(netcdf, "STREAM_BYTES", 1 << 40)
    write_dataset(eager, tmp_path / "whole.nc")
    with xr.open_dataset(tmp_path / "streamed.nc") as a, xr.open_dataset(tmp_path / "whole.nc") as b:
        # the checksums differ with the layout (it covers the chunking); everything else is the same
        assert a.attrs[netcdf.CHECKSUM_ATTRIBUTE] != b.attrs[netcdf.CHECKSUM_ATTRIBUTE]
        xr.testing.assert_identical(a.drop_attrs(deep=False), b.drop_attrs(deep=False))
        assert set(a.attrs) == set(b.attrs) == {netcdf.CHECKSUM_ATTRIBUTE, netcdf.COVERS_ATTRIBUTE}
        assert a["series"].encoding["chunksizes"][0] == 17
    stream.close()
