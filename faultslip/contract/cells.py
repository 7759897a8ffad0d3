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

import contextlib
import contextvars
import math
import sys
from dataclasses import dataclass
from typing import Callable, Protocol

import numpy as np

from faultslip.contract.specs import Output, Parameter
from faultslip.errors import FaultslipError, InputError
from faultslip.units import is_quantity


#: Values of one axis whose scenes a study's check builds: an axis's ends and an even spread between them. An axis
#: of 100,000 values built 100,000 scenes before any budget was checked; a value the spread skips that fails is
#: still caught, cell by cell, when the study runs (its cell is flagged and listed, not the study lost).
CHECKED_VALUES_PER_AXIS = 64


def checked_values(values) -> list:
    """The values of an axis a study's check reads scenes for: all of a short axis, else its ends and an even
    spread (:data:`CHECKED_VALUES_PER_AXIS` in all)."""
    values = list(values)
    if len(values) <= CHECKED_VALUES_PER_AXIS:
        return values
    picks = np.unique(np.linspace(0, len(values) - 1, CHECKED_VALUES_PER_AXIS).round().astype(int))
    return [values[i] for i in picks]


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

    def category(self, scene, name: str, value: str, where: str) -> str:
        """The canonical name of one value of a categorical parameter, or a sentence saying why it is refused."""

    def check(self, study, where: str, source: str) -> None:
        """Refuse, in one sentence, a study whose method, cycles or swept values this family cannot take
        (``where`` prefixes a message about the [study] table, ``source`` names the study)."""

    def outputs(self, study) -> dict[str, Output] | None:
        """The outputs of every cell, declared (None: the engine computes one cell to learn them)."""

    def attrs(self, name: str, study, flagged: bool = False) -> dict:
        """CF attributes of output ``name``."""

    def seconds_per_cell(self, study) -> float:
        """Estimated wall time of one cell on one worker."""

    def seconds_per_worker(self, study) -> float:
        """Optional: estimated time a worker spends once, before its first cell (a compiled step loaded, or compiled
        where numba's cache has none); a family without it spends none (:meth:`Study.seconds_per_worker`)."""

    def imports(self, study) -> tuple:
        """Optional: the modules a block's cells import where they run (faultslip.io.budget.Estimate.imports),
        which a sweep's estimate counts; a family without it declares none (:meth:`Study.imports`)."""

    def counted(self, study) -> bool:
        """Whether a finished sweep reports its cells counted by flag (cells simulated one by one, which differ
        in regime or may fail); a closed-form sweep skips the read-back."""

    def evaluate(self, study, values: dict) -> dict:
        """Every output over the block whose swept values are ``values`` (name -> array on the study's axes)."""


def corner_scenes(study) -> list:
    """The study's base scene moved to each corner of its grid (every swept dimension's first or last value)."""
    if not study.dims:
        return []
    corners = np.array(np.meshgrid(*[[0, len(v) - 1] for v in study.dims.values()], indexing="ij"))
    return [study.scene.with_values(**{name: values[i] for (name, values), i in zip(study.dims.items(), index)})
            for index in corners.reshape(len(study.dims), -1).T]


#: Cells inside a grid whose cost a per-cell estimate reads beside its corners: a grid whose corners are cheap
#: (closed form past a threshold) and whose inside integrates was estimated from its corners alone.
SAMPLED_CELLS = 8


def sampled_scenes(study, count: int = SAMPLED_CELLS) -> list:
    """The scenes of ``count`` cells of the study's grid, drawn without replacement by a fixed seed (every cell
    of a grid that has no more), so that an estimate is the same every time it is asked.

    Parameters
    ----------
    study : faultslip.studies.grid.Study
        The study whose grid is drawn from.
    count : int
        How many cells at most.

    Returns
    -------
    list
        The cells' scenes (the base scene moved to each cell's values).
    """
    if not study.dims:
        return []
    shape = tuple(len(values) for values in study.dims.values())
    size = math.prod(shape)
    picks = np.arange(size) if size <= count else np.sort(np.random.default_rng(0).choice(size, count, replace=False))
    return [study.scene.with_values(**{name: values[i] for (name, values), i in zip(study.dims.items(), index)})
            for index in zip(*np.unravel_index(picks, shape))]


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
        """The family's own cost model (``Family.estimate``) of the run of the base scene, of each corner of the
        grid and of cells drawn inside it (:func:`sampled_scenes`), averaged over those it estimates; :attr:`seconds`
        where the family declares none."""
        estimate = getattr(study.family, "estimate", None)
        if estimate is None:
            return self.seconds
        method = None if study.method == "auto" else study.method
        costs = []
        for scene in [study.scene, *corner_scenes(study), *sampled_scenes(study)]:
            try:
                costs.append(estimate(scene, "run", method=method, tolerance=study.tolerance).seconds)
            except InputError:  # a cell its run refuses fails alone, in the failure ledger, as before
                continue
        return float(np.mean(costs)) if costs else self.seconds

    def imports(self, study) -> tuple:
        """What the family's run of the base scene imports, as its cost model declares it (none where it has
        none, or refuses the base scene)."""
        estimate = getattr(study.family, "estimate", None)
        if estimate is None:
            return ()
        try:
            return tuple(estimate(study.scene, "run", method=None if study.method == "auto" else study.method,
                                  tolerance=study.tolerance).imports)
        except InputError:
            return ()

    def counted(self, study) -> bool:
        return True

    def check(self, study, where: str, source: str) -> None:
        if study.method not in self.methods:
            raise InputError(f"{where} method of {self.label} is one of {', '.join(self.methods)}, got "
                             f"{study.method!r}")
        if study.cycles:
            raise InputError(f"{where} cycles applies to rate-and-state studies; {self.label} runs each cell as "
                             "its scene says")
        self.read(study.scene)  # the base scene as it is
        for name, values in study.dims.items():  # values on their own (a long axis: a spread), then the corners
            for value in checked_values(values):
                self.read(study.scene.with_values(**{name: value}))
        for scene in corner_scenes(study):
            self.read(scene)

    def category(self, scene, name: str, value: str, where: str) -> str:
        return value  # read and checked with the cell's scene (check)

    def evaluate(self, study, values: dict) -> dict:
        method = None if study.method == "auto" else study.method
        names = list(values)

        def cell(**inputs):
            scene = study.scene.with_values(**inputs)
            try:
                result = self.run(scene, method=method, tolerance=study.tolerance)
            except FaultslipError as exc:
                where = ", ".join(f"{n} = {inputs[n]}" if isinstance(inputs[n], str) else f"{n} = {inputs[n]:.6g}"
                                  for n in names)
                raise type(exc)(f"the cell {where or '(the base scene)'} of {self.label}: {exc}") from None
            return {name: cell_value(result, spec) for name, spec in self.outputs(study).items()}

        return evaluate_by_cell(values, self.outputs(study), cell)


def aligned(dims: dict, parameters: dict, block: dict | None = None) -> dict:
    """Each swept parameter's values on the study's axes (size 1 along the others): numpy broadcasting then
    does what xarray's alignment would, without its cost. ``block`` (name -> slice) restricts each dimension."""
    values = {}
    for axis, (name, chosen) in enumerate(dims.items()):
        index = None if block is None else block.get(name, slice(None))
        chosen = chosen if index is None else chosen[index]
        data = np.array(chosen, dtype=object if parameters[name].is_category else float)
        values[name] = data.reshape([data.size if i == axis else 1 for i in range(len(dims))])
    return values


#: Where a study's engine collects the cells that failed (None: a failing cell fails its block, as in a notebook's
#: sweep). A context variable: each worker thread's block has its own list.
_FAILED_CELLS: contextvars.ContextVar = contextvars.ContextVar("faultslip_failed_cells", default=None)


@contextlib.contextmanager
def collect_cell_failures():
    """Within this context a cell whose run raises a :class:`FaultslipError` keeps its outputs' fill values and is
    listed, ``(index in its block, inputs, reason)``, in the list this yields, instead of failing its block: a
    long study on a cluster finishes, and its failure ledger says which cells to run again and why."""
    failures = []
    token = _FAILED_CELLS.set(failures)
    try:
        yield failures
    finally:
        _FAILED_CELLS.reset(token)


def evaluate_by_cell(values: dict, outputs: dict, cell: Callable) -> dict:
    """``cell(**inputs) -> {output: value}`` on every cell of a block: numpy arrays on the study's axes, or
    labelled (dask-chunked) DataArrays, each chunk then evaluated where dask runs it. ``outputs`` maps each
    output to its :class:`Output` (its type and its value where a cell has none). Inside
    :func:`collect_cell_failures` a failing cell keeps the fill values and is listed."""
    names = list(values)

    def block(*arrays):
        arrays = np.broadcast_arrays(*(np.asarray(a) for a in arrays)) if arrays else []
        shape = arrays[0].shape if arrays else ()
        result = {name: np.full(shape, spec.fill, spec.dtype) for name, spec in outputs.items()}
        failures = _FAILED_CELLS.get()
        for index in np.ndindex(shape):
            inputs = {n: (v if isinstance(v, str) else float(v))
                      for n, v in ((n, a[index]) for n, a in zip(names, arrays))}
            try:
                computed = cell(**inputs)
            except FaultslipError as exc:
                if failures is None:
                    raise
                failures.append((tuple(int(i) for i in index), inputs, str(exc)))
                continue
            for name, value in computed.items():
                result[name][index] = value
        return result

    if any(labelled(v) for v in values.values()):
        import xarray as xr  # heavy: imported where used (a lazy study)

        def kernel(*arrays):
            computed = block(*arrays)
            return tuple(computed[name] for name in outputs)

        results = xr.apply_ufunc(kernel, *(values[n] for n in names), output_core_dims=[[]] * len(outputs),
                                 dask="parallelized", output_dtypes=[spec.dtype for spec in outputs.values()])
        results = results if isinstance(results, tuple) else (results,)
        return dict(zip(outputs, results))
    return block(*(values[n] for n in names))


def cell_value(result, spec: Output):
    """One output of a cell's Result, in the declared units (a flag's code; the fill value where the result
    has none)."""
    key = spec.key or spec.name
    if hasattr(result, "number"):  # a Result: its stored number, pint only where the units differ
        value = result.number(key, spec.units) if key in result else None
    else:
        try:
            value = result[key]
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
