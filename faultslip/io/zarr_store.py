"""Zarr stores written region by region, each region by the process that computed it.

A Zarr store is a folder with one file per chunk, so many processes on many machines can write
their own chunks at once, and nothing passes through the process that started the run. The
layout (dimensions, coordinates, every variable's type, fill value, chunks and attributes) is
written first from a description (:func:`create_store`); the regions are written after
(:func:`write_region`); the consolidated metadata is written last (:func:`finish_store`).

Stores use Zarr format 2 with the netCDF4 output's filters (byte shuffle, zlib level 1):
zarr-python, xarray and netCDF-C's NCZarr all read it.

What a finished store holds is checked where it is read back (``convert``, ``--resume``,
``--retry-failed``): each chunk by its CRC-32C, each block's values by its digest
(:data:`DIGESTS`), and its metadata (every ``.zgroup``, ``.zarray`` and ``.zattrs``: types, fill
values, codecs, units, the study) by a SHA-256 sealed into its root attributes
(:func:`seal_store`, :func:`check_store_checksum`), which the consolidated ``.zmetadata`` must
repeat.
"""

from __future__ import annotations

import asyncio
import hashlib
import itertools
import json
import os
import shutil
import sys
import warnings
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io.chunks import block_digest, deflate_compress
from faultslip.io import gate
from faultslip.io.gate import decoding
from faultslip.io.outputs import is_store  # noqa: F401  (defined with the output checks; used here too)

ZARR_FORMAT = 2


def require_zarr() -> None:
    """Refuse, in one sentence, a Zarr run where zarr or dask is not installed."""
    try:
        import dask.array  # noqa: F401  heavy: imported where used
        import zarr  # noqa: F401  heavy: imported where used
    except ImportError:
        raise InputError("Zarr output needs zarr and dask: pip install 'faultslip[zarr]'") from None


_FAST_ZLIB = {}


def _fast_zlib():
    """numcodecs' Zlib codec with ISA-L's encoder (see :mod:`faultslip.io.chunks`), registered as "zlib".

    Its id stays "zlib", so the store's metadata names the standard codec and every reader
    decodes with its own zlib; only the writing is faster. It is registered in this process's
    numcodecs registry (the workers read the codec from the store's metadata): zlib streams
    written here by numcodecs then come from ISA-L, and decoding is unchanged.
    """
    if "codec" not in _FAST_ZLIB:
        import numcodecs  # heavy: imported where used
        from numcodecs.compat import ensure_contiguous_ndarray  # heavy: imported where used

        class FastZlib(numcodecs.Zlib):
            def encode(self, buf):
                return deflate_compress(memoryview(ensure_contiguous_ndarray(buf)).cast("B"), self.level)

        numcodecs.register_codec(FastZlib, codec_id="zlib")
        _FAST_ZLIB["codec"] = FastZlib
    return _FAST_ZLIB["codec"](level=1)


def _codecs(dtype: str, compression: str) -> dict:
    """Filters and compressor of one array: byte shuffle, a CRC-32C checksum, then zlib or zstd.

    The checksum (numcodecs' ``crc32c``) is the last filter, so it covers every byte the chunk
    decodes to: a bit flip in the stored chunk either breaks the decompression or fails the
    checksum, and is refused by name, never read as a wrong value (zarr format 2 has no place
    for a checksum after the compressor).
    """
    import numcodecs  # heavy: imported where used

    itemsize = np.dtype(dtype).itemsize if np.dtype(dtype).kind not in "OUT" else 1
    filters = ([numcodecs.Shuffle(elementsize=itemsize)] if itemsize > 1 and compression != "none" else [])
    filters.append(numcodecs.CRC32C())
    if compression == "none":
        return {"compressors": None, "filters": filters}
    codec = _fast_zlib() if compression == "zlib" else numcodecs.Zstd(level=1)
    return {"compressors": [codec], "filters": filters}


def create_store(path, dims: dict, coords: dict, variables: dict, attrs: dict, chunks: dict,
                 compression: str = "zlib") -> None:
    """Write a store's layout (no data) from the description of :func:`faultslip.io.netcdf.create_chunked`."""
    require_zarr()
    import dask.array as da  # heavy: imported where used
    import xarray as xr  # heavy: imported where used

    data_vars = {}
    encoding = {}
    for name, (variable_dims, dtype, fill, variable_attrs) in variables.items():
        shape = tuple(dims[d] for d in variable_dims)
        chunk_shape = tuple(chunks[d] for d in variable_dims)
        data_vars[name] = (variable_dims, da.empty(shape, chunks=chunk_shape or (), dtype=dtype), variable_attrs)
        encoding[name] = {"chunks": chunk_shape, "_FillValue": fill, **_codecs(dtype, compression)}
    coordinates = {}
    for name, (values, coordinate_attrs) in coords.items():
        values = np.asarray(values)
        coordinates[name] = (name, values.astype(str) if values.dtype.kind in "OUT" else values.astype(float),
                             coordinate_attrs)
        # a coordinate has no missing values; text or numbers, it is checksummed too
        encoding[name] = {**({} if values.dtype.kind in "OUT" else {"_FillValue": None}),
                          **_codecs("U" if values.dtype.kind in "OUT" else "f8", compression)}
    dataset = xr.Dataset(data_vars, coords=coordinates, attrs=attrs)
    try:
        dataset.to_zarr(path, mode="w", compute=False, encoding=encoding, zarr_format=ZARR_FORMAT,
                        consolidated=False, write_empty_chunks=True)
    except OSError as exc:
        raise InputError(f"cannot write the Zarr store {path}: {exc.strerror or exc}") from None


def write_region(path, dataset, region: dict) -> None:
    """Write ``dataset``'s data variables into ``region`` (dimension -> slice) of the store at ``path``."""
    _fast_zlib()  # this process (a worker, perhaps on another machine) encodes with ISA-L too
    dataset = dataset.drop_vars(list(dataset.coords))
    # every chunk is written, fill or not: a chunk missing from a finished store is then damage
    dataset.to_zarr(path, region=region, mode="r+", zarr_format=ZARR_FORMAT, consolidated=False,
                    write_empty_chunks=True)


def finish_store(partial, output) -> None:
    """Consolidate ``partial``'s metadata and put it under ``output``, replacing an older store there.

    The old store is renamed aside first, so ``output`` names either the old store or the new
    one at every moment; the old one is deleted last.
    """
    import zarr  # heavy: imported where used

    seal_store(partial)
    zarr.consolidate_metadata(str(partial), zarr_format=ZARR_FORMAT)
    partial, output = Path(partial), Path(output)
    aside = None
    if output.exists():
        if not is_store(output):  # checked before the run too; never delete a folder that is not a store
            raise InputError(f"{output} exists and is not a Zarr store; refusing to replace it")
        aside = output.with_name(f".{output.name}.old-{os.getpid()}")
        os.replace(output, aside)
    os.replace(partial, output)
    if aside is not None:
        shutil.rmtree(aside, ignore_errors=True)


#: The store attribute holding each block's digest (:func:`faultslip.io.chunks.block_digest`), keyed by the block's
#: first index on each dimension ("0,30"): a chunk swapped with another is valid by its own CRC-32C, not by this.
DIGESTS = "faultslip_block_digests"


def set_block_digests(path, digests: dict) -> None:
    """Record the blocks' digests in the store at ``path`` (before it is finished)."""
    import zarr  # heavy: imported where used

    group = zarr.open_group(str(path), mode="r+", zarr_format=ZARR_FORMAT)
    group.attrs[DIGESTS] = json.dumps(digests, sort_keys=True)


def block_digests(path, group=None) -> dict:
    """The digests a finished store was written with; one sentence where it has none."""
    import zarr  # heavy: imported where used

    group = group if group is not None else zarr.open_group(str(path), mode="r")
    text = group.attrs.get(DIGESTS)
    try:
        digests = json.loads(text) if isinstance(text, str) else None
    except ValueError:
        digests = None
    if not isinstance(digests, dict):
        raise InputError(f"the Zarr store {Path(path).name} carries no digests of its blocks, so a chunk moved or "
                         "swapped could not be told; write it again with this faultslip (sweep -o OUT.zarr)")
    return digests


#: The root attributes that seal a finished store: the SHA-256 of its metadata, and what it covers (itself covered,
#: so that a store whose checksum was deleted is not taken for an older faultslip's).
CHECKSUM, COVERS = "faultslip_checksum", "faultslip_checksum_covers"
COVERS_TEXT = ("SHA-256 of the store's metadata: every .zgroup, .zarray and .zattrs by its path, keys sorted, this "
               "attribute left out; values are covered by faultslip_block_digests and each chunk's CRC-32C")
_METADATA_FILES = (".zgroup", ".zarray", ".zattrs")


def store_metadata(path) -> dict:
    """{path in the store: parsed JSON} of every ``.zgroup``, ``.zarray`` and ``.zattrs`` of a format 2 store,
    each read through the gate; one sentence where one is not JSON."""
    path = Path(path)
    found = {}
    for file in sorted(path.rglob(".z*")):
        if file.name in _METADATA_FILES:
            key = file.relative_to(path).as_posix()
            found[key] = gate.read_json(file, f"the Zarr store {path.name}'s metadata {key}")
    return found


def metadata_checksum(metadata: dict) -> str:
    """SHA-256 of a store's metadata (:func:`store_metadata`), the root's :data:`CHECKSUM` left out."""
    root = {key: value for key, value in metadata.get(".zattrs", {}).items() if key != CHECKSUM}
    return gate.json_checksum({**metadata, ".zattrs": root})


def seal_store(path) -> None:
    """Record the SHA-256 of the store's metadata in its root attributes (before it is consolidated)."""
    import zarr  # heavy: imported where used

    group = zarr.open_group(str(path), mode="r+", zarr_format=ZARR_FORMAT)
    group.attrs[COVERS] = COVERS_TEXT
    group.attrs[CHECKSUM] = metadata_checksum(store_metadata(path))


def layout_checksum(path) -> str:
    """SHA-256 of a (partial) store's layout: its metadata (:func:`store_metadata`) less the attributes written when
    it is finished (block digests, checksum), and every coordinate array's values (an array named after its one
    dimension). A sweep records it when it lays the store out and compares it before it resumes: the blocks
    written are checked by their digests, and everything else in the store by this."""
    import zarr  # heavy: imported where used

    metadata = store_metadata(path)
    root = {key: value for key, value in metadata.get(".zattrs", {}).items() if key not in (CHECKSUM, COVERS, DIGESTS)}
    group = zarr.open_group(str(path), mode="r", zarr_format=ZARR_FORMAT)
    coordinates = {}
    for name in sorted(group.array_keys()):
        if group[name].attrs.get("_ARRAY_DIMENSIONS") == [name]:
            values = np.asarray(group[name][...])
            coordinates[name] = [str(item) for item in values.tolist()] if values.dtype.kind in "OUS" else \
                hashlib.sha256(np.ascontiguousarray(values).tobytes()).hexdigest() + values.dtype.str
    return gate.json_checksum({"metadata": {**metadata, ".zattrs": root}, "coordinates": coordinates})


def require_store(path) -> Path:
    """``path`` as a Path, once its markers say it is a Zarr store; one sentence where it is missing or is not.

    Parameters
    ----------
    path : str or Path
        The store's folder.

    Returns
    -------
    Path
        The store's folder.
    """
    path = Path(path)
    if not path.exists():
        raise InputError(f"{str(path)!r} does not exist")
    if not is_store(path):
        raise InputError(f"{str(path)!r} is not a Zarr store (no .zgroup, .zmetadata or zarr.json inside)")
    return path


def check_store_checksum(path) -> None:
    """Refuse, in one sentence, a store whose metadata no longer matches the checksum sealed into it, whose
    checksum was removed, or whose consolidated metadata (``.zmetadata``, what readers take first) differs from
    its arrays' own; a store of an older faultslip (its block digests, neither attribute) is read with a warning,
    and another program's (none of them) as it is. A folder that is not a store is refused by its markers first,
    before its tree is walked (``faultslip convert /`` walked the whole file system)."""
    path = require_store(path)
    metadata = store_metadata(path)
    if (path / ".zmetadata").is_file():
        try:
            consolidated = json.loads(gate.read_bytes(path / ".zmetadata", f"the Zarr store {path.name}'s metadata",
                                                      "config"))["metadata"]
        except (ValueError, UnicodeDecodeError, KeyError, TypeError) as exc:
            raise InputError(f"the Zarr store {path.name}: its consolidated metadata (.zmetadata) is damaged "
                             f"({type(exc).__name__})") from None
        if consolidated != metadata:
            raise InputError(f"the Zarr store {path.name}: its consolidated metadata (.zmetadata) differs from its "
                             "arrays' own, so it was edited or damaged after it was written; write it again")
    root = metadata.get(".zattrs", {})
    if CHECKSUM not in root:
        if COVERS in root:
            raise InputError(f"the Zarr store {path.name} has lost the checksum of its metadata, so an edit of its "
                             "attributes could not be told; write it again")
        if DIGESTS in root:  # an older faultslip's store; another program's carries nothing of faultslip's to check
            warnings.warn(f"the Zarr store {path.name} was written by a faultslip that did not yet seal its metadata "
                          "with a checksum: its attributes are read unchecked", stacklevel=2)
    elif root[CHECKSUM] != metadata_checksum(metadata):
        raise InputError(f"the Zarr store {path.name}: its metadata (types, fill values, units, attributes) does not "
                         "match the checksum written with it: it was edited or damaged since; write it again")


def _grid_of(group):
    """(data variable names, shape, chunk shape) the store's data variables share."""
    names = [name for name in group.array_keys() if group[name].attrs.get("_ARRAY_DIMENSIONS") is not None
             and len(group[name].attrs["_ARRAY_DIMENSIONS"]) == len(group[name].shape)]
    grids = {(tuple(group[name].attrs["_ARRAY_DIMENSIONS"]), group[name].shape, group[name].chunks)
             for name in names}
    dims = max(grids, key=lambda grid: len(grid[0]))[0] if grids else ()
    data = [name for name in names if tuple(group[name].attrs["_ARRAY_DIMENSIONS"]) == dims and name not in dims]
    return data, group[data[0]].shape if data else (), group[data[0]].chunks if data else ()


def region_digest(group, names, starts, chunk_shape, shape) -> str:
    """The digest of the block starting at ``starts``, from the store's values as written."""
    index = tuple(slice(start, min(start + size, extent)) for start, size, extent in zip(starts, chunk_shape, shape))
    return block_digest({name: np.asarray(group[name][index]) for name in names})


def check_block_digests(path) -> None:
    """Refuse, naming the first, a block of a finished store whose values do not match its recorded digest."""
    import zarr  # heavy: imported where used

    group = zarr.open_group(str(path), mode="r")
    digests = block_digests(path, group)
    names, shape, chunks = _grid_of(group)
    for key, digest in digests.items():
        starts = [int(v) for v in key.split(",")] if key else []
        if region_digest(group, names, starts, chunks, shape) != digest:
            raise InputError(f"the Zarr store {Path(path).name}: the block at {key or 'its one cell'} does not match "
                             "the digest written with it (a chunk changed, moved or swapped); write it again")


def update_block_digests(path, cells: list) -> None:
    """Renew the digests of the blocks holding ``cells`` ({dimension: index} each) from the store's values."""
    import zarr  # heavy: imported where used

    group = zarr.open_group(str(path), mode="r+", zarr_format=ZARR_FORMAT)
    digests = block_digests(path, group)
    names, shape, chunks = _grid_of(group)
    dims = tuple(group[names[0]].attrs["_ARRAY_DIMENSIONS"]) if names else ()
    for cell in cells:
        starts = [cell[name] // size * size for name, size in zip(dims, chunks)]
        digests[",".join(map(str, starts))] = region_digest(group, names, starts, chunks, shape)
    group.attrs[DIGESTS] = json.dumps(digests, sort_keys=True)


def settle_background_writes(timeout: float = 30.0) -> None:
    """Wait for the writes zarr still has under way on its own event loop, and take their errors.

    When one of a store's concurrent writes fails (a full disk), zarr raises its error while the others run on;
    deleting the folder under them makes them fail too, and asyncio prints each such error at exit ("Task
    exception was never retrieved"): a traceback after the one sentence. zarr 3 keeps its loop in
    ``zarr.core.sync.loop``; with none running there is nothing to wait for."""
    holder = getattr(sys.modules.get("zarr.core.sync"), "loop", None)
    running = holder[0] if holder else None
    if running is None or not running.is_running():
        return

    async def settle():
        tasks = [task for task in asyncio.all_tasks() if task is not asyncio.current_task()]
        if tasks:
            await asyncio.wait(tasks, timeout=timeout)
        for task in tasks:
            if task.done() and not task.cancelled():
                task.exception()  # taken: asyncio no longer reports it

    asyncio.run_coroutine_threadsafe(settle(), running).result(timeout + 5.0)


def remove_store(path) -> None:
    """Delete a (partial) store folder, if it is one, once zarr's writes into it have ended."""
    settle_background_writes()
    path = Path(path)
    if path.is_dir():
        shutil.rmtree(path)
    elif path.exists():
        path.unlink()


def open_store(path):
    """The store at ``path`` as a lazy Dataset with its raw values and attributes (no CF decoding)."""
    require_zarr()
    import xarray as xr  # heavy: imported where used

    path = require_store(path)
    with decoding(path, "Zarr store", "Zarr", silence=True):  # no metadata consolidated: xarray warns, needlessly
        return xr.open_zarr(path, decode_cf=False, consolidated=None)


def chunk_keys(shape, chunks, separator: str = ".") -> list[str]:
    """The keys of every chunk of a zarr format 2 array of ``shape`` in ``chunks``."""
    if not shape:
        return ["0"]
    counts = [max(-(-size // chunk), 1) if size else 0 for size, chunk in zip(shape, chunks)]
    return [separator.join(str(i) for i in index) for index in itertools.product(*(range(n) for n in counts))]


def verify_store(path) -> None:
    """Refuse, naming the first one, a store with a missing chunk or an array without a checksum.

    Every array of a store faultslip writes has every chunk on disk (written whole, fill or
    not) and a CRC-32C filter; the bytes themselves are checked as each chunk is decoded.
    """

    path = Path(path)
    for meta in sorted(path.rglob(".zarray")):
        name = meta.parent.relative_to(path).as_posix()
        try:
            array = json.loads(meta.read_text(encoding="utf-8"))
            shape, chunks = tuple(array["shape"]), tuple(array["chunks"])
            separator = array.get("dimension_separator") or "."
            filters = array.get("filters") or []
            if not all(isinstance(n, int) and n >= 0 for n in shape + chunks) or len(shape) != len(chunks):
                raise ValueError("shape or chunks are not whole numbers")
        except (OSError, ValueError, KeyError, TypeError, AttributeError) as exc:
            raise InputError(f"the Zarr store {path.name}: the metadata of {name!r} is damaged ({exc})") from None
        if not any(isinstance(f, dict) and f.get("id") == "crc32c" for f in filters):
            raise InputError(f"the Zarr store {path.name}: array {name!r} has no checksum, so its chunks cannot be "
                             "verified; write it again with this faultslip (sweep -o OUT.zarr)")
        if 0 in shape:
            continue
        for key in chunk_keys(shape, chunks, separator):
            if not (meta.parent / key).is_file():
                raise InputError(f"the Zarr store {path.name} is missing chunk {key} of {name!r}; it is damaged "
                                 "or unfinished, and a missing chunk is never filled in")
