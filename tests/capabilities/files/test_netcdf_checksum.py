"""Every netCDF file faultslip writes is sealed with a checksum and checked when it is read back.

HDF5 checks a variable's chunks itself where they carry a checksum (zlib's Adler-32, or Fletcher-32); the rest of
the file (attributes, layout, uncompressed coordinates) is covered by the SHA-256 in ``faultslip_checksum``.
"""

from __future__ import annotations

import shutil
import struct

import netCDF4
import numpy as np
import pytest
import xarray as xr
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from faultslip.errors import InputError
from faultslip.io.chunks import ChunkFile, encode_chunk, fletcher32, padded
from faultslip.io.netcdf import CHECKSUM_ATTRIBUTE, COVERS_ATTRIBUTE, create_chunked, seal, write_dataset
from faultslip.io.resources import open_netcdf

h5py = pytest.importorskip("h5py")


def _fletcher32_word_by_word(data: bytes) -> int:
    """H5_checksum_fletcher32 (HDF5's H5checksum.c) transcribed a word at a time, as C runs it in 32-bit sums."""
    sum1 = sum2 = 0
    words, index = len(data) // 2, 0
    while words:
        run = min(words, 360)
        words -= run
        for _ in range(run):
            sum1 = (sum1 + ((data[index] << 8) | data[index + 1])) & 0xFFFFFFFF
            sum2 = (sum2 + sum1) & 0xFFFFFFFF
            index += 2
        sum1 = (sum1 & 0xFFFF) + (sum1 >> 16)
        sum2 = (sum2 & 0xFFFF) + (sum2 >> 16)
    if len(data) % 2:
        sum1 += data[index] << 8
        sum2 += sum1
        sum1 = (sum1 & 0xFFFF) + (sum1 >> 16)
        sum2 = (sum2 & 0xFFFF) + (sum2 >> 16)
    sum1 = (sum1 & 0xFFFF) + (sum1 >> 16)
    sum2 = (sum2 & 0xFFFF) + (sum2 >> 16)
    return ((sum2 << 16) | sum1) & 0xFFFFFFFF


@settings(max_examples=60, deadline=None)
@given(st.binary(min_size=0, max_size=2000) | st.integers(0, 3000).map(lambda n: b"\xff" * n))
def test_fletcher32_is_hdf5s_algorithm(data):
    # all-ones bytes are the sums' worst case: the folds run at their largest values
    assert fletcher32(data) == _fletcher32_word_by_word(data)


@pytest.mark.parametrize("dtype, size", [("f8", 7), ("f8", 100_000), ("i1", 1), ("i1", 1001), ("i4", 721)])
def test_fletcher32_is_the_checksum_netcdf4_stores(tmp_path, dtype, size):
    rng = np.random.default_rng(size)
    values = rng.normal(size=size) * 1e300 if dtype == "f8" else rng.integers(-100, 100, size=size)
    values = values.astype(dtype)
    path = tmp_path / "theirs.nc"
    with netCDF4.Dataset(path, "w") as nc:
        nc.createDimension("d", size)
        nc.createVariable("v", dtype, ("d",), chunksizes=(size,), fletcher32=True)[:] = values
    with h5py.File(path, "r") as f:
        _, stored = f["v"].id.read_direct_chunk((0,))
    assert stored[:-4] == values.tobytes()
    assert struct.unpack("<I", stored[-4:])[0] == fletcher32(values.tobytes())
    assert encode_chunk(values, "none") == stored


def test_uncompressed_chunks_written_directly_are_checked_on_read(tmp_path):
    path = tmp_path / "direct.nc"
    values = np.arange(12.0).reshape(3, 4)
    create_chunked(path, {"x": 3, "y": 4}, {}, {"v": (("x", "y"), "f8", np.nan, {})}, {}, {"x": 3, "y": 2},
                   compression="none").close()
    with ChunkFile(path, ["v"], "none") as writer:
        for j in (0, 2):
            writer.write("v", (0, j), encode_chunk(padded(values[:, j:j + 2], (3, 2), np.nan), "none"))
    with netCDF4.Dataset(path) as nc:
        assert nc["v"].filters()["fletcher32"]
        assert np.array_equal(nc["v"][:].data, values)
    with h5py.File(path, "r") as f:
        offset = f["v"].id.get_chunk_info(1).byte_offset
    raw = bytearray(path.read_bytes())
    raw[offset + 3] ^= 0x10  # one bit of one value of the second chunk
    path.write_bytes(bytes(raw))
    with netCDF4.Dataset(path) as nc, pytest.raises(RuntimeError, match="HDF error"):
        nc["v"][:]


def _dataset():
    return xr.Dataset({"slip": (("fault", "time"), np.linspace(0.0, 3.0, 12).reshape(3, 4), {"units": "m"}),
                       "magnitude": ((), 7.1)},
                      coords={"fault": ["a", "b", "c"], "time": ("time", [0.0, 1.0, 2.0, 3.0], {"units": "s"})},
                      attrs={"title": "faultslip test", "source": "faultslip"})


@pytest.mark.parametrize("compress", [True, False])
def test_written_files_are_sealed_and_read_back_checked(tmp_path, compress):
    path = tmp_path / "out.nc"
    write_dataset(_dataset(), path, compress=compress)
    with netCDF4.Dataset(path) as nc:
        assert len(nc.getncattr(CHECKSUM_ATTRIBUTE)) == 64
        # every array's chunks carry a checksum HDF5 checks: deflate's, or Fletcher-32 where not compressed
        assert nc["slip"].filters()["zlib" if compress else "fletcher32"]
    back = open_netcdf(path, "result")
    assert np.array_equal(back["slip"].values, _dataset()["slip"].values)


@pytest.mark.parametrize("where, value", [("title", "faultslip test, edited"), ("units", "km"),
                                          (CHECKSUM_ATTRIBUTE, "0" * 64)])
def test_an_edited_attribute_is_refused(tmp_path, where, value):
    path = tmp_path / "out.nc"
    write_dataset(_dataset(), path)
    with netCDF4.Dataset(path, "a") as nc:
        (nc["slip"] if where == "units" else nc).setncattr(where, value)
    with pytest.raises(InputError, match="does not match the checksum faultslip wrote with it"):
        open_netcdf(path, "result")


def test_an_edited_coordinate_is_refused(tmp_path):
    path = tmp_path / "out.nc"
    write_dataset(_dataset(), path)
    with netCDF4.Dataset(path, "a") as nc:
        nc["fault"][1] = "z"  # a text coordinate: no filter of its own, covered by the checksum
    with pytest.raises(InputError, match="does not match the checksum"):
        open_netcdf(path, "result")


def test_a_lost_or_renamed_checksum_is_refused_and_an_older_file_is_said(tmp_path):
    path = tmp_path / "out.nc"
    write_dataset(_dataset(), path)
    renamed, lost, older = tmp_path / "renamed.nc", tmp_path / "lost.nc", tmp_path / "older.nc"
    for copy in (renamed, lost, older):
        shutil.copy(path, copy)
    with netCDF4.Dataset(renamed, "a") as nc:
        nc.renameAttribute(CHECKSUM_ATTRIBUTE, CHECKSUM_ATTRIBUTE[:-1] + "x")
    with netCDF4.Dataset(lost, "a") as nc:  # one edit: the attribute that says what the checksum covers stays
        nc.delncattr(CHECKSUM_ATTRIBUTE)
    for damaged in (renamed, lost):
        with pytest.raises(InputError, match="has lost its checksum, or its checksum attribute is damaged"):
            open_netcdf(damaged, "result")
    with netCDF4.Dataset(older, "a") as nc:  # as a faultslip before the checksum wrote it: neither attribute
        nc.delncattr(CHECKSUM_ATTRIBUTE)
        nc.delncattr(COVERS_ATTRIBUTE)
    with pytest.warns(UserWarning, match="read unchecked"):
        open_netcdf(older, "result")


def test_another_programs_file_is_read_as_it_is(tmp_path, recwarn):
    path = tmp_path / "theirs.nc"
    _dataset().assign_attrs(title="a rig's record", source="the rig").to_netcdf(path)
    assert open_netcdf(path, "record")["slip"].shape == (3, 4)
    assert not [w for w in recwarn if "checksum" in str(w.message)]


def test_sealing_is_idempotent_and_covers_every_part(tmp_path):
    path = tmp_path / "out.nc"
    write_dataset(_dataset(), path)
    with netCDF4.Dataset(path) as nc:
        first = nc.getncattr(CHECKSUM_ATTRIBUTE)
    seal(path)
    with netCDF4.Dataset(path) as nc:
        assert nc.getncattr(CHECKSUM_ATTRIBUTE) == first


@pytest.fixture(scope="module")
def sealed(tmp_path_factory):
    path = tmp_path_factory.mktemp("sealed") / "sealed.nc"
    write_dataset(_dataset(), path)
    return path, path.read_bytes(), open_netcdf(path, "result")


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(st.data())
def test_one_flipped_bit_is_refused_or_changes_nothing(sealed, tmp_path_factory, data):
    """A bit flipped anywhere in a sealed file: the read refuses it, or what it reads is what was written."""
    path, raw, original = sealed
    position = data.draw(st.integers(0, len(raw) - 1))
    damaged = bytearray(raw)
    damaged[position] ^= 1 << data.draw(st.integers(0, 7))
    target = tmp_path_factory.mktemp("flip") / "flipped.nc"
    target.write_bytes(bytes(damaged))
    try:
        back = open_netcdf(target, "result")
    except InputError:
        return
    xr.testing.assert_identical(back, original)
    for name in back.variables:
        assert back[name].attrs == original[name].attrs


STUDY = """[study]
name = "sealed"
base = "san_andreas_1906.toml"
method = "closed_form"
[sweep]
slip_rate = { logspace = ["1 mm/yr", "100 mm/yr", 7] }
lithology = ["granodiorite", "pyrite_dry"]
"""


@pytest.mark.parametrize("compression, workers", [("zlib", 1), ("zlib", 2), ("none", 2), ("zstd", 1)])
def test_a_sweep_seals_its_output_and_every_chunk_is_checked(tmp_path, compression, workers):
    from faultslip.studies.grid import parse_study
    from faultslip.studies.streaming import run_study

    if compression == "zstd" and not netCDF4.__has_zstandard_support__:
        pytest.skip("this netCDF4 has no zstd filter")
    path = tmp_path / "study.nc"
    # chunks of 3 cells: several chunks, written by the workers themselves where the codec allows
    run_study(parse_study(STUDY), path, chunk_cells=3, workers=workers, compression=compression)
    with netCDF4.Dataset(path) as nc:
        assert len(nc.getncattr(CHECKSUM_ATTRIBUTE)) == 64
        filters = nc["slip_per_event"].filters()
        assert filters["zlib"] if compression == "zlib" else filters["fletcher32"]
    assert open_netcdf(path, "study output")["slip_per_event"].shape == (7, 2)


def _two_chunks(path, write_second: bool) -> None:
    with netCDF4.Dataset(path, "w") as nc:
        nc.createDimension("cell", 8)
        variable = nc.createVariable("slip", "f8", ("cell",), chunksizes=(4,), zlib=True, fill_value=np.nan)
        variable.setncattr("units", "m")
        variable[0:4] = np.arange(4.0)
        if write_second:
            variable[4:8] = np.arange(4.0, 8.0)


def test_a_chunk_lost_from_the_index_is_refused(tmp_path):
    """A chunk missing from HDF5's index reads as fill values, with no error and no chunk checksum to fail: the
    checksum covers the index (a file identical in every attribute, type and stored chunk, but one)."""
    from faultslip.io.netcdf import chunk_map, netcdf_checksum

    whole, lost = tmp_path / "whole.nc", tmp_path / "lost.nc"
    _two_chunks(whole, True)
    seal(whole)
    _two_chunks(lost, False)
    with netCDF4.Dataset(whole) as nc:
        stored, covers = nc.getncattr(CHECKSUM_ATTRIBUTE), nc.getncattr(COVERS_ATTRIBUTE)
    with netCDF4.Dataset(lost, "a") as nc:
        nc.setncattr(COVERS_ATTRIBUTE, covers)
        nc.setncattr(CHECKSUM_ATTRIBUTE, stored)
        assert np.isnan(nc["slip"][4:].filled(np.nan)).all()  # read back as fill values, no error
        # every other part matches: only the index tells the two files apart
        assert netcdf_checksum(nc, chunk_map(whole)) == stored
    with pytest.raises(InputError, match="does not match the checksum"):
        open_netcdf(lost, "result")
    assert open_netcdf(whole, "result")["slip"].values.tolist() == list(np.arange(8.0))


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(where=st.floats(0.0, 1.0, exclude_max=True), damage=st.binary(min_size=1, max_size=16))
def test_a_damaged_files_chunk_index_is_one_sentence_never_an_hdf5_error(tmp_path, where, damage):
    """The fuzzer found a partial output whose damaged HDF5 object headers made h5py's visit raise a RuntimeError
    ('Object visitation failed') while the resumed sweep sealed it: a traceback. Reading the chunk index of any
    damaged file now either answers or says, in one InputError, that it cannot, and a resume checks it first."""
    from faultslip.io.netcdf import chunk_map

    path = tmp_path / f"damaged_{abs(hash((where, damage)))}.nc"
    _two_chunks(path, True)
    data = bytearray(path.read_bytes())
    start = int(where * len(data))
    data[start:start + len(damage)] = damage[: len(data) - start]
    path.write_bytes(bytes(data))
    try:
        assert len(chunk_map(path)) == 64
    except InputError as error:
        assert str(error).startswith(f"cannot read the chunk index of {path.name}")
