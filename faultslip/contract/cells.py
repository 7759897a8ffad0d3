"""A family's sweep: its parameters, outputs and methods, and a block of cells evaluated at once.

The sweep engine (:mod:`faultslip.studies.grid`) knows no family. It asks a family's ``cells`` (the
:class:`Cells` protocol) which parameters a scene sweeps, checks a study with it, and hands it a block of
cells: each swept parameter as a numpy array on the study's axes (size 1 along the others), or, for a lazy
study, as a labelled, dask-chunked DataArray. ``evaluate`` returns each output broadcastable to the block.

A family with a vectorised kernel (the seed law's closed form, rate-and-state K / K_c) evaluates a block in
one call; any other family is :class:`PerCell`: its own ``run`` on each cell's scene, the outputs read from
the :class:`~faultslip.models.Result` by their declared names and units.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from typing import Callable, Protocol

import numpy as np

from faultslip.contract.specs import Output, Parameter
from faultslip.errors import FaultslipError, InputError
from faultslip.units import is_quantity


class Cells(Protocol):
    """What the sweep engine asks of a family (``Family.cells``)."""

    #: what a study of this family is called in messages ("a vibration study")
    label: str
    #: each cell keeps a work folder (a checkpointed run) that a resumed study continues
    checkpoints: bool
    #: the [study] method of a study that names none, and its tolerance (None: the scene's or family's own)
    default_tolerance: float | None

    def parameters(self, scene) -> dict[str, Parameter]:
        """The parameters a study of ``scene`` may sweep."""

    def check(self, study, where: str) -> None:
        """Refuse, in one sentence, a study whose method, cycles or swept values this family cannot take."""

    def outputs(self, study) -> dict[str, Output] | None:
        """The outputs of every cell, declared (None: the engine computes one cell to learn them)."""

    def attrs(self, name: str, study, flagged: bool = False) -> dict:
        """CF attributes of output ``name``."""

    def seconds_per_cell(self, study) -> float:
        """Estimated wall time of one cell on one worker."""

    def evaluate(self, study, values: dict) -> dict:
        """Every output over the block whose swept values are ``values`` (name -> array on the study's axes)."""


def labelled(value) -> bool:
    """Whether ``value`` is an xarray DataArray, without importing xarray (nothing is one before it is imported)."""
    xarray = sys.modules.get("xarray")
    return xarray is not None and isinstance(value, xarray.DataArray)


@dataclass(frozen=True)
class PerCell:
    """A family's sweep by its own ``run`` on each cell: ``run(scene.with_values(**cell), method, tolerance)``.

    ``read`` reads a cell's scene without running it (the family's scene reader): a study is checked
    value by value, and at the corners of its grid, before any cell runs. ``outputs`` maps each output to its
    :class:`Output` (or is a function of the scene, for a family whose scenes differ in what they report).
    """

    label: str
    parameter_specs: dict
    output_specs: object  # dict of Output, or scene -> dict of Output
    run: Callable
    read: Callable
    methods: tuple = ("auto",)
    seconds: float = 0.1  # declared cost of one cell on one worker (what the budget and the block size use)
    default_tolerance: float | None = None
    checkpoints: bool = False

    def parameters(self, scene) -> dict:
        specs = self.parameter_specs(scene) if callable(self.parameter_specs) else self.parameter_specs
        return {name: spec for name, spec in specs.items() if spec.sweepable}

    def outputs(self, study) -> dict:
        return self.output_specs(study.scene) if callable(self.output_specs) else self.output_specs

    def attrs(self, name: str, study, flagged: bool = False) -> dict:
        return self.outputs(study)[name].attrs()

    def seconds_per_cell(self, study) -> float:
        return self.seconds

    def check(self, study, where: str) -> None:
        if study.method not in self.methods:
            raise InputError(f"{where} method of {self.label} is one of {', '.join(self.methods)}, got "
                             f"{study.method!r}")
        if study.cycles:
            raise InputError(f"{where} cycles applies to rate-and-state studies; {self.label} runs each cell as "
                             "its scene says")
        for name, values in study.dims.items():  # every value on its own, then the corners together
            for value in values:
                self.read(study.scene.with_values(**{name: value}))
        if study.dims:
            corners = np.array(np.meshgrid(*[[0, len(v) - 1] for v in study.dims.values()], indexing="ij"))
            for index in corners.reshape(len(study.dims), -1).T:
                self.read(study.scene.with_values(**{name: values[i]
                                                     for (name, values), i in zip(study.dims.items(), index)}))

    def evaluate(self, study, values: dict) -> dict:
        outputs = self.outputs(study)
        names = list(values)
        if any(labelled(v) for v in values.values()):
            import xarray as xr  # heavy: imported where used (a lazy study)

            def kernel(*arrays):
                block = self._block(study, dict(zip(names, arrays)), outputs)
                return tuple(block[name] for name in outputs)

            results = xr.apply_ufunc(kernel, *(values[n] for n in names), output_core_dims=[[]] * len(outputs),
                                     dask="parallelized", output_dtypes=[spec.dtype for spec in outputs.values()])
            results = results if isinstance(results, tuple) else (results,)
            return dict(zip(outputs, results))
        return self._block(study, values, outputs)

    def _block(self, study, values: dict, outputs: dict) -> dict:
        names = list(values)
        arrays = np.broadcast_arrays(*(np.asarray(values[n]) for n in names)) if names else []
        shape = arrays[0].shape if names else ()
        block = {name: np.full(shape, spec.fill, spec.dtype) for name, spec in outputs.items()}
        method = None if study.method == "auto" else study.method
        for index in np.ndindex(shape):
            cell = {name: array[index] for name, array in zip(names, arrays)}
            scene = study.scene.with_values(**{n: v if isinstance(v, str) else float(v) for n, v in cell.items()})
            try:
                result = self.run(scene, method=method, tolerance=study.tolerance)
            except FaultslipError as exc:
                where = ", ".join(f"{n} = {v:.6g}" if not isinstance(v, str) else f"{n} = {v}"
                                  for n, v in ((n, cell[n]) for n in names))
                raise type(exc)(f"the cell {where or '(the base scene)'} of {self.label}: {exc}") from None
            for name, spec in outputs.items():
                block[name][index] = cell_value(result, spec)
        return block


def cell_value(result, spec: Output):
    """One output of a cell's Result, in the declared units (a flag's code; the fill value where the result
    has none)."""
    try:
        value = result[spec.key or spec.name]
    except KeyError:
        return spec.fill
    if value is None:
        return spec.fill
    if spec.flags:
        return spec.code(value)
    if is_quantity(value):
        value = value.to("dimensionless" if spec.units == "1" else spec.units).magnitude
    if isinstance(value, str):
        raise ValueError(f"{spec.name} is {value!r}, not a number")
    value = float(value)
    return value if math.isfinite(value) or math.isinf(value) else spec.fill
