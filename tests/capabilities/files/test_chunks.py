"""Parallel compression: chunks encoded by workers are the chunks netCDF4 itself would store."""

import zlib

import netCDF4
import numpy as np
import pytest
import xarray as xr
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from faultslip.errors import InputError
from faultslip.io.chunks import ChunkFile, encode_chunk, padded, shuffled, unshuffled
from faultslip.studies.grid import parse_study
from faultslip.studies.streaming import choose_execution, plan_blocks, run_study

h5py = pytest.importorskip("h5py")


def _netcdf_with(path, shape, chunks, dtype, compression=True, fill=None):
    with netCDF4.Dataset(path, "w") as nc:
        for i, n in enumerate(shape):
            nc.createDimension(f"d{i}", n)
        options = {"zlib": True, "complevel": 1, "shuffle": True} if compression else {}
        nc.createVariable("v", dtype, tuple(f"d{i}" for i in range(len(shape))), chunksizes=chunks,
                          fill_value=fill, **options)


@pytest.mark.parametrize("dtype, fill", [("f8", np.nan), ("i1", np.int8(-127))])
def test_encoded_chunk_is_the_chunk_netcdf4_stores(tmp_path, dtype, fill):
    rng = np.random.default_rng(3)
    values = (rng.normal(size=(6, 40)) * 1e3).astype(dtype)
    theirs = tmp_path / "theirs.nc"
    _netcdf_with(theirs, values.shape, (6, 40), dtype, fill=fill)
    with netCDF4.Dataset(theirs, "a") as nc:
        nc["v"][:] = values
    with h5py.File(theirs, "r") as f:
        mask, stored = f["v"].id.read_direct_chunk((0, 0))
    assert mask == 0
    # the compressed bytes may differ between zlib builds; what they decompress to may not
    assert zlib.decompress(stored) == zlib.decompress(encode_chunk(values)) == shuffled(values)
    assert np.array_equal(unshuffled(zlib.decompress(stored), dtype, values.shape), values)


def test_chunk_file_writes_an_ordinary_netcdf_file_with_edge_chunks(tmp_path):
    values = np.arange(7 * 11, dtype=float).reshape(7, 11) / 7.0
    path = tmp_path / "direct.nc"
    chunk = (3, 4)
    _netcdf_with(path, values.shape, chunk, "f8", fill=np.nan)
    with ChunkFile(path, ["v"], "zlib") as writer:
        for i in range(0, 7, 3):
            for j in range(0, 11, 4):
                block = values[i:i + 3, j:j + 4]  # the last row and column of chunks run past the edge
                writer.write("v", (i, j), encode_chunk(padded(block, chunk, np.nan)))
    with netCDF4.Dataset(path) as nc:
        assert np.array_equal(nc["v"][:].data, values)
    with xr.open_dataset(path) as ds:
        assert np.array_equal(ds["v"].values, values)


def test_chunk_file_refuses_a_variable_with_other_filters(tmp_path):
    path = tmp_path / "plain.nc"
    _netcdf_with(path, (4,), (2,), "f8", compression=False)
    with pytest.raises(InputError, match="not stored with the zlib filters"):
        ChunkFile(path, ["v"], "zlib")


@settings(max_examples=60, deadline=None)
@given(hnp.arrays(st.sampled_from([np.float64, np.float32, np.int8, np.int32]),
                  hnp.array_shapes(min_dims=1, max_dims=3, max_side=9)))
def test_shuffle_round_trips(values):
    assert np.array_equal(unshuffled(shuffled(values), values.dtype, values.shape), values, equal_nan=True)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.integers(1, 6), min_size=1, max_size=3), st.data())
def test_padding_keeps_the_values_in_the_corner(shape, data):
    chunk = tuple(n + data.draw(st.integers(0, 3)) for n in shape)
    values = np.arange(np.prod(shape), dtype=float).reshape(shape)
    whole = padded(values, chunk, -1.0)
    assert whole.shape == chunk and whole.flags.c_contiguous
    assert np.array_equal(whole[tuple(slice(0, n) for n in shape)], values)
    assert (whole == -1.0).sum() == np.prod(chunk) - np.prod(shape)


STUDY = """
[study]
name = "chunked"
base = "san_andreas_1906.toml"

[sweep]
slip_rate = { logspace = ["5 mm/yr", "50 mm/yr", 7] }
zone_width = ["10 km", "13 mi", "30 km"]
lithology = ["granodiorite", "black_marble"]
"""


@pytest.mark.parametrize("compression", ["zlib", "none"])
def test_workers_compressing_their_chunks_give_the_in_process_file(tmp_path, monkeypatch, compression):
    import faultslip.studies.streaming as streaming

    study = parse_study(STUDY)
    serial = tmp_path / "serial.nc"
    run_study(study, serial, chunk_cells=5, workers=1, compression=compression)
    monkeypatch.setattr(streaming, "POOL_WORTH_SECONDS", 0.0)  # a pool even for this small grid
    pooled = tmp_path / "pooled.nc"
    summary = run_study(study, pooled, chunk_cells=5, workers=2, compression=compression)
    assert summary["executor"].startswith("process pool")
    assert len(plan_blocks(study, 5)[1]) == summary["blocks"] > 2  # edge chunks included (7 % 5 != 0)
    with xr.open_dataset(serial) as a, xr.open_dataset(pooled) as b:
        xr.testing.assert_identical(a.drop_attrs(), b.drop_attrs())
        for name in a.data_vars:
            assert a[name].encoding.get("zlib", False) == (compression == "zlib")


def test_small_grids_run_in_process_and_large_ones_on_the_pool():
    small = parse_study(STUDY)
    workers, note = choose_execution(small, pending_blocks=4, workers=2)
    assert workers == 1 and "a pool would cost more than it saves" in note
    assert choose_execution(small, pending_blocks=1, workers=2) == (1, " (one block: a pool would only add start-up time)")
    large = parse_study(STUDY.replace("7] }", "70000] }"))
    assert choose_execution(large, pending_blocks=40, workers=2) == (2, "")
    assert choose_execution(small, pending_blocks=4, workers=2, scheduler="local") == (2, "")
