"""Writing xarray datasets to netCDF4 files atomically, compressed, with units kept."""

from __future__ import annotations

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
