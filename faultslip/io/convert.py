"""Zarr store to netCDF4 file, chunk by chunk: memory stays flat however large the store.

Every chunk of the store becomes one chunk of the file. Worker processes read their chunks from
the store and encode them (byte shuffle, zlib level 1); this process only stores the bytes
(:class:`faultslip.io.chunks.ChunkFile`), so the conversion runs on every core and holds at most
a few chunks at a time. Values, fill values, coordinates and attributes are copied as stored:
a sweep written to Zarr and converted is the file the same sweep writes to netCDF.
"""

from __future__ import annotations

import itertools
import os
import time
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import budget
from faultslip.io.chunks import ChunkFile, block_digest, encode_chunk, padded
from faultslip.io.netcdf import create_chunked, seal
from faultslip.io.atomic import partial_output
from faultslip.io.outputs import check_output, output_lock
from faultslip.io.processes import run_windowed, stop_pool, usable_workers, worker_pool
from faultslip.io.gate import decoding
from faultslip.io.zarr_store import CHECKSUM, COVERS, DIGESTS, block_digests, check_store_checksum, open_store, verify_store


def _grid(store):
    """``(dims, chunks)`` that every data variable of ``store`` shares, or an InputError."""
    grids = {(variable.dims, tuple(variable.encoding.get("chunks") or variable.shape))
             for variable in store.data_vars.values()}
    if not grids:
        raise InputError("the Zarr store holds no data variables to convert")
    if len(grids) > 1:
        raise InputError("the Zarr store's variables lie on different grids or chunks; "
                         "faultslip convert copies stores whose variables share one grid (as faultslip sweep writes)")
    dims, chunks = grids.pop()
    return dims, dict(zip(dims, chunks))


def _encode_region(path, names, region, chunk_shape, fills):
    """Worker task: read one chunk of each variable from the store and encode it as HDF5 stores it; with the
    block's digest (:func:`faultslip.io.chunks.block_digest`), which the client checks against the store's."""
    import zarr  # heavy: imported where used

    group = zarr.open_group(str(path), mode="r")
    index = tuple(slice(start, stop) for start, stop in region)
    encoded, arrays = {}, {}
    for name in names:
        try:
            values = np.asarray(group[name][index])
        except Exception as exc:  # noqa: BLE001  a checksum or decompression failure: the chunk is damaged
            where = ".".join(str(start // size) for (start, _), size in zip(region, chunk_shape)) or "0"
            raise InputError(f"the Zarr store {Path(path).name}: chunk {where} of {name!r} is damaged "
                             f"({' '.join(str(exc).split())[:100]})") from None
        encoded[name] = encode_chunk(padded(values, chunk_shape, fills[name]))
        arrays[name] = values
    return encoded, block_digest(arrays)


def _netcdf_attrs(attrs: dict, where: str) -> dict:
    """Attributes netCDF can hold (text, numbers, lists of one of them); anything else is one sentence."""
    checked = {}
    for key, value in attrs.items():
        if key == "_FillValue":
            continue
        values = value if isinstance(value, list) else [value]
        kinds = {type(v) for v in values}
        ok = bool(values) and (kinds <= {str} or kinds <= {int, float}) and not any(isinstance(v, bool) for v in values)
        if not isinstance(key, str) or not key or not ok:
            raise InputError(f"the Zarr store's attribute {key!r} of {where} is {json_kind(value)}, which a netCDF "
                             "attribute cannot hold; the store was not written by faultslip or has been edited")
        checked[key] = value
    return checked


def json_kind(value) -> str:
    return ("null" if value is None else "a table" if isinstance(value, dict) else "true/false"
            if isinstance(value, bool) else "an empty list" if value == [] else "a mixed list"
            if isinstance(value, list) else type(value).__name__)


def zarr_to_netcdf(store_path, output, *, workers: int = 2, overwrite: bool = False, progress=None,
                   allow_large: bool = False) -> dict:
    """Convert the Zarr store at ``store_path`` into the netCDF4 file ``output``; returns a summary."""
    store_path = Path(store_path)
    check_store_checksum(store_path)  # its metadata as written, before xarray reads a byte of it
    store = open_store(store_path)
    output = check_output(output, label="-o", suffixes=(".nc",), inputs=[store_path], overwrite=overwrite)
    dims, chunks = _grid(store)
    stored = sum(f.stat().st_size for f in store_path.rglob("*") if f.is_file())
    # the file holds the same chunks with the same filters: about the store's size
    budget.check(budget.Estimate(f"converting {store_path.name}", disk=stored * 1.1, output=output), allow_large)
    with decoding(store_path, "Zarr store", "a faultslip store"):
        coords = {name: (store[name].values, _netcdf_attrs(store[name].attrs, repr(name)))
                  for name in dims if name in store.coords}
    missing = [name for name in dims if name not in coords]
    if missing:
        raise InputError(f"the Zarr store has no coordinate for dimension {missing[0]!r}; faultslip convert "
                         "copies stores with a coordinate on every dimension")
    verify_store(store_path)  # every chunk present and checksummed, before a byte is written
    expected = block_digests(store_path)  # and each block's digest, checked as its chunks are copied
    variables, fills = {}, {}
    for name, variable in store.data_vars.items():
        fill = variable.attrs.get("_FillValue")
        with decoding(store_path, "Zarr store", f"a faultslip store (the fill value of {name!r})"):
            fills[name] = np.array(fill if fill is not None else 0, dtype=variable.dtype)[()]
        variables[name] = (dims, variable.dtype.str.lstrip("<>|="), fill, _netcdf_attrs(variable.attrs, repr(name)))
    sizes = {name: store.sizes[name] for name in dims}
    starts = [range(0, sizes[d], chunks[d]) for d in dims]
    regions = [tuple((start, min(start + chunks[d], sizes[d])) for d, start in zip(dims, corner))
               for corner in itertools.product(*starts)]
    workers, _ = usable_workers(workers, len(regions))
    started = time.perf_counter()
    names = list(variables)
    chunk_shape = tuple(chunks[d] for d in dims)
    with output_lock(output, "faultslip convert", overwrite=overwrite), partial_output(output) as partial:
        # the store's own checks, not the file's (the file is sealed with its own checksum)
        attrs = {key: value for key, value in store.attrs.items() if key not in (DIGESTS, CHECKSUM, COVERS)}
        create_chunked(partial, sizes, coords, variables, _netcdf_attrs(attrs, "the store"), chunks).close()
        pool = worker_pool(workers) if workers > 1 and len(regions) > 1 else None
        done = 0
        try:
            with ChunkFile(partial, names, "zlib") as writer:
                def store_chunks(region, result):
                    nonlocal done
                    encoded, digest = result
                    key = ",".join(str(start) for start, _ in region)
                    if expected.get(key) != digest:
                        raise InputError(f"the Zarr store {store_path.name}: the block at {key or 'its one cell'} "
                                         "does not match the digest written with it (a chunk changed, moved or "
                                         "swapped); nothing was written")
                    for name, data in encoded.items():
                        writer.write(name, tuple(start for start, _ in region), data)
                    done += 1
                    if progress:
                        progress(done, len(regions))

                run_windowed(pool, _encode_region,
                             ((region, (str(store_path.resolve()), names, region, chunk_shape, fills))
                              for region in regions), store_chunks, window=workers + 1)
        except BaseException:
            stop_pool(pool, interrupted=True)
            raise
        stop_pool(pool)
        seal(partial)
        os.replace(partial, output)
    return {"input": str(store_path), "output": str(output), "chunks": len(regions), "variables": len(names),
            "seconds": time.perf_counter() - started, "workers": workers}
