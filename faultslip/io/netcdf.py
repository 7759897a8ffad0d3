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


def write_dataset(dataset, path, *, compress: bool = True) -> None:
    """Write ``dataset`` to ``path`` (netCDF4 engine): temporary file, then rename."""
    if not str(path).endswith(".nc"):
        raise InputError(f"output file {str(path)!r} must end in .nc (netCDF4)")
    with atomic_path(path) as temporary:
        dataset.to_netcdf(temporary, engine="netcdf4", format="NETCDF4",
                          encoding=compression_encoding(dataset) if compress else None)


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
