"""Zarr stores: the same study as netCDF, atomic replacement, resume, refusals, and streaming conversion."""

import json

import numpy as np
import pytest
import xarray as xr

from faultslip.errors import InputError
from faultslip.io.convert import zarr_to_netcdf
from faultslip.io.zarr_store import is_store
from faultslip.studies.grid import parse_study
from faultslip.studies.streaming import compare_datasets, plan_blocks, run_study

pytest.importorskip("zarr")

STUDY = """
[study]
name = "zarr"
base = "san_andreas_1906.toml"

[sweep]
slip_rate = { logspace = ["5 mm/yr", "50 mm/yr", 9] }
zone_width = ["10 km", "13 mi", "30 km"]
lithology = ["granodiorite", "pyrite_dry"]
"""


@pytest.fixture
def study():
    return parse_study(STUDY)


def _same(a, b):
    comparison = compare_datasets(a, b)
    return (max(comparison["differences"].values()) == 0.0
            and not (comparison["missing"] or comparison["extra"] or comparison["attribute_differences"]))


def test_a_zarr_sweep_converts_to_the_netcdf_sweep(study, tmp_path):
    store, direct, converted = tmp_path / "s.zarr", tmp_path / "d.nc", tmp_path / "c.nc"
    run_study(study, store, chunk_cells=4, workers=1)
    run_study(study, direct, chunk_cells=4, workers=1)
    assert is_store(store) and (store / ".zmetadata").exists()  # consolidated, readable without listing
    summary = zarr_to_netcdf(store, converted, workers=2)
    # 12 predictions and the 5 empirical-scaling variables (W&C 1994 beside the slip and Mw)
    assert summary["chunks"] == len(plan_blocks(study, 4)[1]) == 18 and summary["variables"] == 17
    with xr.open_dataset(converted, decode_cf=False) as a, xr.open_dataset(direct, decode_cf=False) as b:
        assert _same(a, b)
        assert a["slip_per_event"].encoding["chunksizes"] == b["slip_per_event"].encoding["chunksizes"]
    with xr.open_zarr(store) as z, xr.open_dataset(direct) as n:
        assert _same(z, n)


def test_overwrite_replaces_a_store_and_never_a_plain_folder(study, tmp_path):
    store = tmp_path / "s.zarr"
    run_study(study, store, chunk_cells=50, workers=1)
    with pytest.raises(InputError, match="already exists; pass --overwrite"):
        run_study(study, store, chunk_cells=50, workers=1, overwrite=False)
    other = parse_study(STUDY.replace('"30 km"', '"25 km"'))
    run_study(other, store, chunk_cells=50, workers=1, overwrite=True)
    with xr.open_zarr(store) as z:
        assert float(z["zone_width"][-1]) == 25e3
    assert not list(tmp_path.glob(".s.zarr.old-*"))  # the replaced store is gone
    folder = tmp_path / "results.zarr"
    folder.mkdir()
    (folder / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match="is a folder but not a Zarr store"):
        run_study(study, folder, overwrite=True)
    assert (folder / "notes.txt").read_text() == "mine"


def test_format_and_suffix_must_agree(study, tmp_path):
    with pytest.raises(InputError, match="must end in .zarr"):
        run_study(study, tmp_path / "s.nc", file_format="zarr")
    with pytest.raises(InputError, match="--format must be one of netcdf, zarr"):
        run_study(study, tmp_path / "s.zarr", file_format="hdf")


def test_an_interrupted_zarr_run_resumes(study, tmp_path, monkeypatch):
    import faultslip.studies.streaming as streaming

    real, calls = streaming.compute_block, {"n": 0}

    def flaky(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 5:  # the layout's template comes from grid.template_block, not this name
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    store = tmp_path / "s.zarr"
    monkeypatch.setattr(streaming, "compute_block", flaky)
    with pytest.raises(KeyboardInterrupt):
        run_study(study, store, chunk_cells=6, workers=1)
    assert not store.exists() and is_store(tmp_path / "s.zarr.partial")
    assert len(json.loads((tmp_path / "s.zarr.progress.json").read_text())["done"]) == 4
    monkeypatch.setattr(streaming, "compute_block", real)
    summary = run_study(study, store, chunk_cells=6, workers=1, resume=True)
    assert summary["resumed_blocks"] == 4 and not (tmp_path / "s.zarr.partial").exists()
    fresh = tmp_path / "fresh.zarr"
    run_study(study, fresh, chunk_cells=6, workers=1)
    with xr.open_zarr(store, decode_cf=False) as a, xr.open_zarr(fresh, decode_cf=False) as b:
        for name in a.data_vars:
            assert a[name].values.tobytes() == b[name].values.tobytes()


def test_convert_refuses_what_it_cannot_copy(tmp_path):
    with pytest.raises(InputError, match="does not exist"):
        zarr_to_netcdf(tmp_path / "none.zarr", tmp_path / "o.nc")
    (tmp_path / "plain").mkdir()
    with pytest.raises(InputError, match="is not a Zarr store"):
        zarr_to_netcdf(tmp_path / "plain", tmp_path / "o.nc")
    ragged = tmp_path / "ragged.zarr"
    xr.Dataset({"a": ("x", np.arange(4.0)), "b": ("y", np.arange(3.0))},
               coords={"x": np.arange(4.0), "y": np.arange(3.0)}).to_zarr(ragged, zarr_format=2)
    with pytest.raises(InputError, match="different grids"):
        zarr_to_netcdf(ragged, tmp_path / "o.nc")
    assert not (tmp_path / "o.nc").exists()


def test_convert_cli_writes_nothing_on_refusal(cli, tmp_path):
    result = cli("convert", str(tmp_path / "none.zarr"), "-o", str(tmp_path / "o.nc"))
    assert result.code == 2 and "does not exist" in result.err and "Traceback" not in result.err
    assert not (tmp_path / "o.nc").exists()


def test_a_partial_store_is_deleted_only_after_zarrs_writes_into_it_have_ended(tmp_path):
    """A failed store write (a full disk) leaves zarr's other writes running on its event loop. remove_store waits
    for them and takes their errors, so none lands in the deleted folder or is printed at exit as "Task exception
    was never retrieved" (seen on a busy machine: a traceback after the one sentence)."""
    import asyncio
    import threading

    from zarr.core.sync import _get_loop

    from faultslip.io.zarr_store import remove_store

    partial = tmp_path / "s.zarr.partial"
    partial.mkdir()
    loop, started = _get_loop(), threading.Event()

    async def late_write():
        started.set()
        await asyncio.sleep(0.3)
        raise FileNotFoundError("the folder went")

    future = asyncio.run_coroutine_threadsafe(late_write(), loop)
    assert started.wait(10)
    remove_store(partial)
    assert future.done() and not partial.exists()
    assert isinstance(future.exception(), FileNotFoundError)


def test_a_finished_store_with_two_chunks_swapped_is_refused_not_converted(study, tmp_path):
    """Each chunk is valid by its own CRC-32C; the blocks' digests, written with the store, tell them apart."""
    import shutil

    store, converted = tmp_path / "s.zarr", tmp_path / "c.nc"
    run_study(study, store, chunk_cells=4, workers=1)
    chunks = sorted(path for path in (store / "slip_per_event").iterdir() if not path.name.startswith("."))
    first, second = chunks[0], chunks[1]
    assert first.read_bytes() != second.read_bytes()
    shutil.copyfile(first, tmp_path / "aside")
    shutil.copyfile(second, first)
    shutil.copyfile(tmp_path / "aside", second)
    with pytest.raises(InputError, match="does not match the digest written with it"):
        zarr_to_netcdf(store, converted, workers=1)
    assert not converted.exists()


def test_a_store_without_block_digests_is_refused_with_the_reason(study, tmp_path):
    import zarr

    store = tmp_path / "s.zarr"
    run_study(study, store, chunk_cells=4, workers=1)
    group = zarr.open_group(str(store), mode="r+")
    del group.attrs["faultslip_block_digests"]
    zarr.consolidate_metadata(str(store))
    with pytest.raises(InputError, match="carries no digests of its blocks"):
        zarr_to_netcdf(store, tmp_path / "c.nc", workers=1)
