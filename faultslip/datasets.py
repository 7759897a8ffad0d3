"""``to_xarray()`` for faultslip's result dataclasses: one conversion, in the core layer, that every layer's
results take (a class that writes its own dataset keeps it)."""

from __future__ import annotations

import dataclasses
import numbers

import numpy as np


class ToXarray:
    """``to_xarray()`` for a result dataclass: every number a 0-d variable, every array a variable on its own
    dimension (or a shared one: :attr:`DIMENSIONS`), every mapping of numbers one variable a key, every string an
    attribute; each with its unit from :attr:`UNITS` (SI, udunits; "1" for a number without one). A class that
    writes its own dataset (``to_dataset``) hands that over instead."""

    #: field -> its unit (SI, udunits)
    UNITS: dict = {}
    #: field -> the dimension its array lies on (arrays of one length share one)
    DIMENSIONS: dict = {}

    def to_xarray(self):
        """The result as an xarray Dataset, each variable with its ``units``."""
        own = getattr(self, "to_dataset", None)
        if callable(own):
            return own()
        return dataclass_dataset(self, type(self).UNITS, type(self).DIMENSIONS)


def dataclass_dataset(obj, units: dict, dimensions: dict | None = None):
    """:class:`ToXarray`'s dataset of the dataclass ``obj`` (see there)."""
    import xarray as xr  # heavy: imported where used

    dimensions = dimensions or {}
    data, attrs = {}, {"title": f"faultslip {type(obj).__name__}", "Conventions": "CF-1.8"}

    def attributes(name):
        unit = units.get(name)
        return {"long_name": name.replace("_", " "), **({"units": unit} if unit is not None else {})}

    for spec in dataclasses.fields(obj):
        name, value = spec.name, getattr(obj, spec.name)
        if name.startswith("_") or value is None:
            continue
        if isinstance(value, bool) or isinstance(value, np.bool_):
            data[name] = ((), int(value), {"long_name": name.replace("_", " "), "units": "1",
                                           "flag_values": np.array([0, 1], dtype=np.int8),
                                           "flag_meanings": "false true"})
        elif isinstance(value, numbers.Number):
            data[name] = ((), float(value), attributes(name))
        elif isinstance(value, str):
            attrs[name] = value
        elif isinstance(value, (tuple, list, np.ndarray)) and len(value) and all(
                isinstance(v, numbers.Number) for v in np.ravel(np.asarray(value, dtype=object))):
            array = np.asarray(value, dtype=float)
            if array.ndim == 1:
                data[name] = ((dimensions.get(name, f"{name}_index"),), array, attributes(name))
            elif array.ndim == 2:
                data[name] = ((dimensions.get(name, f"{name}_index"), f"{name}_column"), array, attributes(name))
        elif isinstance(value, dict):
            for key, item in value.items():
                if isinstance(item, numbers.Number) and not isinstance(item, bool):
                    data[f"{name}_{key}"] = ((), float(item), attributes(name))
    return xr.Dataset({name: xr.Variable(*spec) for name, spec in data.items()}, attrs=attrs)
