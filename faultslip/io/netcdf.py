"""Writing xarray datasets to netCDF4 files atomically, compressed, with units kept."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from faultslip.io.atomic import atomic_path
from faultslip.errors import InputError


def compression_encoding(dataset, level: int = 4) -> dict:
    """zlib compression for every numeric variable (strings and coordinates of text are left alone)."""
    encoding = {}
    for name, variable in dataset.variables.items():
        if np.issubdtype(variable.dtype, np.number) and variable.ndim > 0:
            encoding[name] = {"zlib": True, "complevel": level}
    return encoding


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
                       encoding=compression_encoding(rest) if compress else None)
        if large:
            _append_in_blocks(temporary, dataset, large, compress)


def _append_in_blocks(path, dataset, names, compress: bool) -> None:
    """Each variable of ``names`` into the netCDF at ``path``, its rows read and written a block at a time, with
    the encoding xarray gives a float variable (NaN as the fill value; zlib level 4 if ``compress``)."""
    import netCDF4  # heavy: imported where used

    with netCDF4.Dataset(path, "a") as nc:
        for name in names:
            variable = dataset[name].variable
            for dim in variable.dims:
                if dim not in nc.dimensions:
                    nc.createDimension(dim, dataset.sizes[dim])
            filters = {"zlib": True, "complevel": 4} if compress else {}
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
    filters that :func:`faultslip.io.chunks.encode_chunk` applies in worker processes.
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
