"""Zarr stores: the same study as netCDF, atomic replacement, resume, refusals, and streaming conversion."""

import json
import shutil
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from faultslip.errors import InputError
from faultslip.io.convert import zarr_to_netcdf
from faultslip.io.zarr_store import CHECKSUM, COVERS, check_store_checksum, is_store, metadata_checksum, store_metadata
from faultslip.studies.grid import parse_study
from faultslip.studies.streaming import compare_datasets, failure_ledger, plan_blocks, retry_failed, run_study
from hypothesis import HealthCheck, given, settings, strategies as st

EXAMPLE = Path(__file__).resolve().parents[3] / "configs" / "example_lab_glass.zarr"

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


def _stopped_store(study, store, monkeypatch):
    """A Zarr run of ``study`` in blocks of 6 cells, stopped by Ctrl-C while it computes its fifth block."""
    import faultslip.studies.streaming as streaming

    real, calls = streaming.compute_block, {"n": 0}

    def flaky(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 5:  # the layout's template comes from grid.template_block, not this name
            raise KeyboardInterrupt
        return real(*args, **kwargs)

    monkeypatch.setattr(streaming, "compute_block", flaky)
    with pytest.raises(KeyboardInterrupt):
        run_study(study, store, chunk_cells=6, workers=1)
    monkeypatch.setattr(streaming, "compute_block", real)


def test_an_interrupted_zarr_run_resumes(study, tmp_path, monkeypatch):
    store = tmp_path / "s.zarr"
    _stopped_store(study, store, monkeypatch)
    assert not store.exists() and is_store(tmp_path / "s.zarr.partial")
    assert len(json.loads((tmp_path / "s.zarr.progress.json").read_text())["done"]) == 4
    summary = run_study(study, store, chunk_cells=6, workers=1, resume=True)
    assert summary["resumed_blocks"] == 4 and not (tmp_path / "s.zarr.partial").exists()
    fresh = tmp_path / "fresh.zarr"
    run_study(study, fresh, chunk_cells=6, workers=1)
    with xr.open_zarr(store, decode_cf=False) as a, xr.open_zarr(fresh, decode_cf=False) as b:
        for name in a.data_vars:
            assert a[name].values.tobytes() == b[name].values.tobytes()


@pytest.mark.parametrize("edit", ["a unit", "a global attribute", "a coordinate value", "a fill value"])
def test_a_layout_edited_in_the_partial_store_starts_the_run_over(study, tmp_path, monkeypatch, edit):
    """The block digests cover the values written; the layout recorded when the store was laid out covers the rest."""
    import zarr

    store = tmp_path / "s.zarr"
    _stopped_store(study, store, monkeypatch)
    group = zarr.open_group(str(tmp_path / "s.zarr.partial"), mode="r+", zarr_format=2)
    if edit == "a unit":
        group["slip_per_event"].attrs["units"] = "ft"
    elif edit == "a global attribute":
        group.attrs["title"] = "edited"
    elif edit == "a coordinate value":
        group["zone_width"][0] = 11000.0
    else:
        meta = tmp_path / "s.zarr.partial" / "slip_per_event" / ".zarray"
        text = meta.read_text()
        assert '"fill_value": "NaN"' in text
        meta.write_text(text.replace('"fill_value": "NaN"', '"fill_value": 0.0'))
    with pytest.warns(UserWarning, match="the layout of s.zarr.partial .* was edited since; starting over"):
        assert run_study(study, store, chunk_cells=6, workers=1, resume=True)["resumed_blocks"] == 0
    fresh = tmp_path / "fresh.zarr"
    run_study(study, fresh, chunk_cells=6, workers=1)
    with xr.open_zarr(store, decode_cf=False) as a, xr.open_zarr(fresh, decode_cf=False) as b:
        xr.testing.assert_identical(a.drop_attrs(deep=False), b.drop_attrs(deep=False))
        assert a.attrs.get("title") == b.attrs.get("title")


def test_convert_refuses_what_it_cannot_copy(tmp_path, monkeypatch):
    with pytest.raises(InputError, match="does not exist"):
        zarr_to_netcdf(tmp_path / "none.zarr", tmp_path / "o.nc")
    (tmp_path / "plain").mkdir()
    with pytest.raises(InputError, match="is not a Zarr store"):
        zarr_to_netcdf(tmp_path / "plain", tmp_path / "o.nc")
    # a folder is judged by its markers before its tree is walked: 'faultslip convert /' walked the whole file
    # system (11 s), and a /proc entry that vanished on the way ended it as a machine error (exit 1)
    deep = tmp_path / "deep"
    (deep / "a" / "b").mkdir(parents=True)
    (deep / "a" / "b" / ".zarray").write_text("{")
    walked = []
    monkeypatch.setattr(Path, "rglob", lambda self, pattern: walked.append(self) or iter(()))
    with pytest.raises(InputError, match="is not a Zarr store"):
        zarr_to_netcdf(deep, tmp_path / "o.nc")
    with pytest.raises(InputError, match="is not a Zarr store"):
        check_store_checksum(deep)
    assert walked == []
    monkeypatch.undo()
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
    for key in (CHECKSUM, COVERS):  # as a faultslip that digested its blocks but did not yet seal its metadata
        del group.attrs[key]
    zarr.consolidate_metadata(str(store))
    with pytest.warns(UserWarning, match="did not yet seal its metadata"):
        zarr_to_netcdf(store, tmp_path / "older.nc", workers=1)
    del group.attrs["faultslip_block_digests"]  # and as another program's store, with nothing of faultslip's
    zarr.consolidate_metadata(str(store))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # nothing of faultslip's to say it is an older faultslip's
        with pytest.raises(InputError, match="carries no digests of its blocks"):
            zarr_to_netcdf(store, tmp_path / "c.nc", workers=1)


def _edit_attribute(store, array, key, value, consolidate=True):
    import zarr

    zarr.open_group(str(store), mode="r+")[array].attrs[key] = value
    if consolidate:
        zarr.consolidate_metadata(str(store))


def test_a_finished_store_is_sealed_and_an_edited_attribute_is_refused(study, tmp_path):
    """Units, types and attributes are not in any chunk: the SHA-256 of the store's metadata, sealed into it, covers
    them. An edit made as zarr makes it (the metadata consolidated again) is refused before a byte is converted."""
    store = tmp_path / "s.zarr"
    run_study(study, store, chunk_cells=4, workers=2)
    check_store_checksum(store)  # a fresh store matches, its region writes included
    assert json.loads((store / ".zattrs").read_text())[CHECKSUM] == metadata_checksum(store_metadata(store))
    _edit_attribute(store, "slip_per_event", "units", "mm")
    with pytest.raises(InputError, match="does not match the checksum written with it"):
        zarr_to_netcdf(store, tmp_path / "c.nc", workers=1)
    assert not (tmp_path / "c.nc").exists()


def test_consolidated_metadata_that_differs_from_the_arrays_is_refused(study, tmp_path):
    """Readers take .zmetadata first: one edited there alone would be read while the arrays' own files match."""
    store = tmp_path / "s.zarr"
    run_study(study, store, chunk_cells=50, workers=1)
    consolidated = json.loads((store / ".zmetadata").read_text())
    consolidated["metadata"]["slip_per_event/.zattrs"]["units"] = "ft"
    (store / ".zmetadata").write_text(json.dumps(consolidated))
    with pytest.raises(InputError, match="consolidated metadata"):
        zarr_to_netcdf(store, tmp_path / "c.nc", workers=1)


def test_a_store_that_lost_its_checksum_is_refused(study, tmp_path):
    import zarr

    store = tmp_path / "s.zarr"
    run_study(study, store, chunk_cells=50, workers=1)
    del zarr.open_group(str(store), mode="r+").attrs[CHECKSUM]
    zarr.consolidate_metadata(str(store))
    with pytest.raises(InputError, match="lost the checksum of its metadata"):
        zarr_to_netcdf(store, tmp_path / "c.nc", workers=1)


def test_retry_failed_refuses_a_store_whose_metadata_was_edited(study, tmp_path):
    store = tmp_path / "s.zarr"
    run_study(study, store, chunk_cells=50, workers=1)
    _edit_attribute(store, "recurrence_period", "long_name", "something else")
    from faultslip.io import gate

    record = {"fingerprint": study.fingerprint(), "cells": [{"index": {name: 0 for name in study.dims}}]}
    failure_ledger(store).write_text(json.dumps({**record, "checksum": gate.json_checksum(record)}), encoding="utf-8")
    with pytest.raises(InputError, match="s.zarr: its metadata .* does not match the checksum"):
        retry_failed(study, store, workers=1)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_one_flipped_bit_in_the_metadata_is_refused_or_changes_nothing(tmp_path_factory, data):
    """A hypothesis property over the shipped example store: flip one bit of any of its metadata files, and
    convert either refuses it in one sentence or writes what the untouched store gives."""
    import shutil

    import xarray as xr

    folder = tmp_path_factory.mktemp("flip")
    store = folder / "s.zarr"
    shutil.copytree(EXAMPLE, store)
    files = sorted(p for p in store.rglob(".z*") if p.is_file())
    victim = data.draw(st.sampled_from(files))
    raw = bytearray(victim.read_bytes())
    raw[data.draw(st.integers(0, len(raw) - 1))] ^= 1 << data.draw(st.integers(0, 7))
    victim.write_bytes(bytes(raw))
    try:
        zarr_to_netcdf(store, folder / "c.nc", workers=1)
    except InputError as exc:
        assert "\n" not in str(exc)
        return
    zarr_to_netcdf(EXAMPLE, folder / "reference.nc", workers=1)
    with xr.open_dataset(folder / "c.nc", decode_cf=False) as got, \
            xr.open_dataset(folder / "reference.nc", decode_cf=False) as want:
        assert _same(got, want) and got.attrs.keys() == want.attrs.keys()


def test_reproduce_reads_a_zarr_sweep_whole_or_spot_checked_and_reports_what_changed(tmp_path, cli):
    """A cluster's sweep is a Zarr store: ``reproduce`` runs its embedded study again into a store and compares
    every variable, coordinate and attribute, or spot-checks drawn cells; its checksum is the sealed metadata and
    the blocks' digests, so a value changed in any chunk, or an edited attribute, is reported (exit 1), drawn or
    not; a folder that is not a store, or -o that is not one, is one sentence."""
    import zarr

    from conftest import assert_clean_error

    store, source = tmp_path / "s.zarr", tmp_path / "z.toml"
    source.write_text(STUDY, encoding="utf-8")
    assert cli("sweep", source, "-o", store, "--workers", "1").code == 0
    whole = cli("reproduce", store, "--json", "--workers", "1")
    assert whole.code == 0 and whole.json["matches"] and whole.json["checksum"] == "matches", whole.err
    assert whole.json["cells"] == 54 and not whole.json["attribute_differences"]
    spot = cli("reproduce", store, "--cells", "3", "--seed", "5", "--json")
    assert spot.code == 0 and spot.json["matches"] and (spot.json["cells"], spot.json["of_cells"]) == (3, 54)
    kept = tmp_path / "again.zarr"
    assert cli("reproduce", store, "-o", kept, "--json", "--workers", "1").code == 0 and is_store(kept)
    assert_clean_error(cli("reproduce", store, "-o", tmp_path / "again.nc"), "must end in .zarr")
    (tmp_path / "plain").mkdir()
    assert_clean_error(cli("reproduce", tmp_path / "plain"), "not a Zarr store")
    edited = tmp_path / "edited.zarr"
    shutil.copytree(store, edited)
    _edit_attribute(edited, "slip_per_event", "units", "mm")
    zarr.open_group(str(store), mode="r+")["recurrence_period"][0, 0, 0] = 1.0
    for path, words in ((store, ()), (store, ("--cells", "1", "--seed", "0")), (edited, ())):
        changed = cli("reproduce", path, "--json", "--workers", "1", *words)
        assert changed.code == 1 and changed.json["checksum"] == "differs" and not changed.json["matches"], words
