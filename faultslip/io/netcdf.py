"""Writing xarray datasets to netCDF4 files atomically, compressed, with units kept, and sealed with a checksum.

Every netCDF file faultslip writes is checked when it is read back. HDF5 checks the stored chunks of a variable
itself, on every read, where they carry a checksum: zlib's Adler-32 (deflate in zlib format) or the Fletcher-32
filter, which faultslip adds wherever a variable is not deflated. The rest (attributes, dimensions, the variables'
types, filters and layout, and the values of small uncompressed variables such as coordinates) is covered by a
SHA-256 that the writer stores as the global attribute ``faultslip_checksum``, beside ``faultslip_checksum_covers``,
which says what it covers (:func:`seal`), and that the reader recomputes (:func:`checksum_problem`, run where
:func:`faultslip.io.resources.probe_netcdf` reads the file). It covers HDF5's chunk index too (:func:`chunk_map`): a
chunk whose entry is lost would read as fill values, and no chunk checksum can see a chunk that is not there.
"""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path

import numpy as np

from faultslip.io.atomic import atomic_path
from faultslip.errors import InputError


#: The global attribute that holds the checksum of a netCDF file faultslip wrote (:func:`netcdf_checksum`).
CHECKSUM_ATTRIBUTE = "faultslip_checksum"
#: A second attribute, covered by the checksum, that says what it covers: a file that has it and lacks the checksum
#: lost its checksum (one edit), where a file of a faultslip before checksums lacks both.
COVERS_ATTRIBUTE = "faultslip_checksum_covers"
COVERS = ("SHA-256 of the attributes, dimensions, variables' layout and filters, uncompressed values and chunk "
          "index; HDF5 checks each chunk (Adler-32 of zlib, or Fletcher-32)")


def compression_encoding(dataset, level: int = 4, compress: bool = True) -> dict:
    """zlib compression for every numeric array (strings and coordinates of text are left alone); without
    ``compress``, the Fletcher-32 checksum filter instead, so that HDF5 still checks every chunk it reads."""
    encoding = {}
    for name, variable in dataset.variables.items():
        if np.issubdtype(variable.dtype, np.number) and variable.ndim > 0:
            encoding[name] = {"zlib": True, "complevel": level} if compress else {"fletcher32": True}
    return encoding


def _self_checked(variable) -> bool:
    """Whether HDF5 checks a variable's stored chunks on every read: deflated in zlib format (Adler-32), or
    filtered by Fletcher-32."""
    filters = variable.filters() or {}
    return bool(filters.get("zlib") or filters.get("fletcher32"))


def _canonical(value) -> bytes:
    """The bytes of an attribute's or a variable's value, its type and shape included."""
    if isinstance(value, str):
        return b"str:" + value.encode("utf-8", "surrogatepass")
    array = np.asarray(value)
    if array.dtype.kind in "OUS":
        text = "\x1f".join(str(item) for item in array.ravel().tolist())
        return f"text{array.shape}:".encode() + text.encode("utf-8", "surrogatepass")
    return f"{array.dtype.str}{array.shape}:".encode() + np.ascontiguousarray(array).tobytes()


def _read_as_stored(dataset, offset) -> tuple | None:
    """A chunk as a read finds it, by its position (its filter mask and stored length; None where the read's
    lookup misses it). Only the stored bytes are read, none decompressed."""
    try:
        mask, data = dataset.id.read_direct_chunk(offset)
    except (RuntimeError, ValueError, KeyError, OSError):
        return None
    return mask, len(data)


def chunk_map(path) -> str:
    """SHA-256 of HDF5's chunk index of the file at ``path``: for every chunked dataset, each stored chunk's
    position, filter mask, address and size as a pass over the index lists it, and what a read by its
    position finds (h5py). A chunk lost from the index, or one the index lists but a read misses (found by
    the fuzzer: one flipped bit), reads as fill values, with no error; this is what tells. It reads every
    stored chunk's bytes once, without decompressing them."""
    import h5py  # heavy: imported where used

    try:
        return _chunk_map(path, h5py)
    except (RuntimeError, OSError, KeyError, ValueError) as exc:  # HDF5's own structures damaged (found by the fuzzer)
        raise InputError(f"cannot read the chunk index of {Path(path).name}: {exc}") from None


def _chunk_map(path, h5py) -> str:
    digest = hashlib.sha256()
    with h5py.File(path, "r", locking=False) as handle:
        names = []
        handle.visititems(lambda name, item: names.append(name) if isinstance(item, h5py.Dataset) else None)
        for name in sorted(names):
            dataset = handle[name]
            if dataset.chunks is None:
                continue
            entries = []
            if hasattr(dataset.id, "chunk_iter"):  # HDF5 1.12.3 and later: one pass over the index
                dataset.id.chunk_iter(lambda info: entries.append(
                    (info.chunk_offset, info.filter_mask, info.byte_offset, info.size)))
            else:
                for index in range(dataset.id.get_num_chunks()):
                    info = dataset.id.get_chunk_info(index)
                    entries.append((info.chunk_offset, info.filter_mask, info.byte_offset, info.size))
            found = [entry + (_read_as_stored(dataset, entry[0]),) for entry in sorted(entries)]
            digest.update(f"{name}|{found}".encode())
    return digest.hexdigest()


def _file_digest(nc, chunks: str | None, layout_only: bool = False) -> str:
    """SHA-256 of an open netCDF4 file's parts (:func:`netcdf_checksum`, :func:`layout_checksum`), each fed with
    its length, so no two files' parts run together the same way."""
    digest = hashlib.sha256()

    def feed(*parts: bytes) -> None:
        for part in parts:
            digest.update(len(part).to_bytes(8, "little"))
            digest.update(part)

    def walk(group, path: str) -> None:
        for key in sorted(group.ncattrs()):
            if not (path == "/" and key == CHECKSUM_ATTRIBUTE):
                feed(b"attribute", f"{path}{key}".encode(), _canonical(group.getncattr(key)))
        for name, dimension in sorted(group.dimensions.items()):
            feed(b"dimension", f"{path}{name}|{len(dimension)}|{dimension.isunlimited()}".encode())
        for name, variable in sorted(group.variables.items()):
            filters = sorted((variable.filters() or {}).items())
            # a variable just created says "native" where the file reopened says the byte order it stored
            endian = sys.byteorder if variable.endian() == "native" else variable.endian()
            feed(b"variable", f"{path}{name}|{variable.dtype}|{variable.dimensions}|{variable.shape}|{filters}|"
                              f"{variable.chunking()}|{endian}".encode())
            for key in sorted(variable.ncattrs()):
                feed(b"attribute", f"{path}{name}:{key}".encode(), _canonical(variable.getncattr(key)))
            if (name in group.dimensions) if layout_only else not _self_checked(variable):
                variable.set_auto_maskandscale(False)  # the values as stored
                feed(b"values", _canonical(variable[...]))
        for name, child in sorted(group.groups.items()):
            walk(child, f"{path}{name}/")

    walk(nc, "/")
    if chunks is not None:
        feed(b"chunks", chunks.encode())
    return digest.hexdigest()


def netcdf_checksum(nc, chunks: str) -> str:
    """SHA-256 of what an open netCDF4 file's own filters leave unchecked, given its :func:`chunk_map`.

    Every group's attributes (the root's ``faultslip_checksum`` left out) and dimensions; every variable's name,
    type, dimensions, shape, filters, chunking and attributes; the raw values of each variable whose chunks
    carry no checksum of their own (:func:`_self_checked`); and the chunk index."""
    return _file_digest(nc, chunks)


def layout_checksum(nc) -> str:
    """SHA-256 of an open netCDF4 file's layout: what :func:`netcdf_checksum` covers but the chunk index and the
    data variables' values, and with every coordinate variable's values (a variable named after a dimension).

    A sweep records it when it creates its partial output and compares it before it resumes: the blocks written
    are checked by their digests, and everything else in the file by this."""
    return _file_digest(nc, None, layout_only=True)


def file_layout_checksum(path) -> str:
    """:func:`layout_checksum` of the netCDF file at ``path``, opened only to read; one sentence where it cannot
    be opened."""
    import netCDF4  # heavy: imported where used

    try:
        with netCDF4.Dataset(path, "r") as nc:
            return layout_checksum(nc)
    except OSError as exc:
        raise InputError(f"cannot open {Path(path).name}: {exc.strerror or exc}") from None


def seal(path) -> None:
    """Store the checksum of the netCDF file at ``path`` in it (:data:`CHECKSUM_ATTRIBUTE`): the last step of
    every netCDF file faultslip writes, before it is renamed into place. Adding an attribute moves no chunk,
    so the chunk index read first is the sealed file's."""
    import netCDF4  # heavy: imported where used

    chunks = chunk_map(path)
    with netCDF4.Dataset(path, "a") as nc:
        nc.setncattr(COVERS_ATTRIBUTE, COVERS)
        nc.setncattr(CHECKSUM_ATTRIBUTE, netcdf_checksum(nc, chunks))


def _written_by_faultslip(nc) -> bool:
    """A file faultslip wrote, by its global attributes: a ``faultslip_`` attribute, or faultslip in its
    ``source`` or ``history``."""
    names = nc.ncattrs()
    return any(name.startswith("faultslip_") for name in names) or any(
        isinstance(value, str) and "faultslip" in value
        for value in (nc.getncattr(key) for key in ("source", "history") if key in names))


def checksum_problem(nc, path) -> str | None:
    """What is wrong with the checksum of the netCDF file at ``path``, open as ``nc``, or None.

    ``"mismatch"``: it carries :data:`CHECKSUM_ATTRIBUTE` and its content does not match it. ``"damaged"``: the
    checksum is gone while :data:`COVERS_ATTRIBUTE` stays, or an attribute's name is one or two characters from
    the checksum's (the name itself was damaged). ``"unsealed"``: a file faultslip wrote
    (:func:`_written_by_faultslip`) with neither, as versions before the checksum wrote them. None for a sealed
    file that matches, and for a file of another program, which carries nothing to check."""
    names = nc.ncattrs()
    if CHECKSUM_ATTRIBUTE in names:
        stored = nc.getncattr(CHECKSUM_ATTRIBUTE)
        return None if isinstance(stored, str) and stored == netcdf_checksum(nc, chunk_map(path)) else "mismatch"
    if COVERS_ATTRIBUTE in names or any(
            len(name) == len(CHECKSUM_ATTRIBUTE) and sum(a != b for a, b in zip(name, CHECKSUM_ATTRIBUTE)) <= 2
            for name in names):
        return "damaged"
    return "unsealed" if _written_by_faultslip(nc) else None


#: A data variable larger than this is written a block of rows at a time (xarray would read it whole first).
STREAM_BYTES = 1 << 20


def write_dataset(dataset, path, *, compress: bool = True) -> None:
    """Write ``dataset`` to ``path`` (netCDF4 engine): temporary file, then rename.

    Data variables over :data:`STREAM_BYTES` of numbers (a long run's series, which may still be on
    disk unread) are written a block of leading-dimension rows at a time into the file xarray made for
    the rest, so that writing holds one block, not the variable."""
    if not str(path).endswith(".nc"):
        raise InputError(f"output file {str(path)!r} must end in .nc (netCDF4)")
    large = [name for name, variable in dataset.data_vars.items()
             if variable.ndim > 0 and variable.dtype.kind == "f" and variable.size * variable.dtype.itemsize > STREAM_BYTES
             and not variable.chunks and not variable.encoding]  # a variable read from a file keeps its encoding
    rest = dataset.drop_vars(large)
    with atomic_path(path) as temporary:
        rest.to_netcdf(temporary, engine="netcdf4", format="NETCDF4",
                       encoding=compression_encoding(rest, compress=compress))
        if large:
            _append_in_blocks(temporary, dataset, large, compress)
        seal(temporary)


def _append_in_blocks(path, dataset, names, compress: bool) -> None:
    """Each variable of ``names`` into the netCDF at ``path``, its rows read and written a block at a time, with
    the encoding xarray gives a float variable (NaN as the fill value; zlib level 4 if ``compress``, else the
    Fletcher-32 checksum)."""
    import netCDF4  # heavy: imported where used

    with netCDF4.Dataset(path, "a") as nc:
        for name in names:
            variable = dataset[name].variable
            for dim in variable.dims:
                if dim not in nc.dimensions:
                    nc.createDimension(dim, dataset.sizes[dim])
            filters = {"zlib": True, "complevel": 4} if compress else {"fletcher32": True}
            row_bytes = max(1, variable.size // max(1, variable.shape[0])) * variable.dtype.itemsize
            block = max(1, min(STREAM_BYTES // row_bytes, variable.shape[0]))
            # a block is one whole chunk, written once: HDF5's chunk cache (16 MiB a variable by default, kept to
            # the file's close) would only hold memory
            target = nc.createVariable(name, variable.dtype, variable.dims, fill_value=np.nan,
                                       chunksizes=(block,) + variable.shape[1:], **filters)
            target.set_var_chunk_cache(size=block * row_bytes + (1 << 16), nelems=1, preemption=1.0)
            for key, value in variable.attrs.items():
                target.setncattr(key, value)
            for start in range(0, variable.shape[0], block):
                target[start:start + block] = variable[start:start + block].values


def create_chunked(path, dims: dict, coords: dict, variables: dict, attrs: dict, chunks: dict,
                   compression: str = "zlib"):
    """An open, empty netCDF4 file laid out for chunk-by-chunk writing.

    ``dims`` maps each dimension to its size; ``coords`` maps a dimension to ``(values, attrs)``
    (text values make a string coordinate); ``variables`` maps a name to ``(dims, dtype, fill,
    attrs)`` with dtype ``"f8"`` or ``"i1"``; ``chunks`` gives the chunk size per dimension.
    Variables use ``compression`` at level 1 with the byte shuffle (netCDF4's default), the
    filters that :func:`faultslip.io.chunks.encode_chunk` applies in worker processes; where that is not
    zlib (zstd, or none), the Fletcher-32 checksum too, so that HDF5 checks every chunk it reads. The
    writer seals the finished file (:func:`seal`).
    """
    import netCDF4  # heavy: imported where used

    nc = netCDF4.Dataset(path, "w", format="NETCDF4")
    try:
        for name, size in dims.items():
            nc.createDimension(name, size)
        for name, (values, coordinate_attrs) in coords.items():
            values = np.asarray(values)
            if values.dtype.kind in "OUT":
                variable = nc.createVariable(name, str, (name,))
                variable[:] = np.array([str(v) for v in values], dtype=object)
            else:
                variable = nc.createVariable(name, "f8", (name,))
                variable[:] = values.astype(float)
            for key, value in coordinate_attrs.items():
                variable.setncattr(key, value)
        for name, (variable_dims, dtype, fill, variable_attrs) in variables.items():
            filters = {} if compression == "none" else {"compression": compression, "complevel": 1}
            if compression != "zlib":
                filters["fletcher32"] = True
            variable = nc.createVariable(name, dtype, tuple(variable_dims), **filters, fill_value=fill,
                                         chunksizes=tuple(chunks[d] for d in variable_dims) if variable_dims else None)
            for key, value in variable_attrs.items():
                variable.setncattr(key, value)
            # each chunk is written once, whole: HDF5's chunk cache would only hold memory
            variable.set_var_chunk_cache(size=1 << 20, nelems=1, preemption=1.0)
        for key, value in attrs.items():
            nc.setncattr(key, value)
    except BaseException:
        nc.close()
        raise
    return nc


def open_for_append(path):
    """An existing netCDF4 file (a sweep's partial output, this run's own) opened to write more chunks."""
    import netCDF4  # heavy: imported where used

    try:
        return netCDF4.Dataset(path, "a")
    except OSError as exc:
        raise InputError(f"cannot reopen {Path(path).name} to continue it: {exc.strerror or exc}") from None
