"""Gridded parameter studies of any model family, as labelled xarray datasets.

A study names a base scene and sweeps any of its family's sweepable parameters, each as a dimension::

    [study]
    name = "Slip and recurrence against slip rate and lithology"
    base = "san_andreas_1906.toml"
    method = "auto"          # one of the family's methods
    tolerance = 1e-6

    [sweep]
    slip_rate = { logspace = ["1 mm/yr", "100 mm/yr", 41] }
    zone_width = ["5 km", "13 mi", "30 km"]
    lithology = ["granodiorite", "black_marble", "pyrite"]

Every value states its units; a categorical parameter (a lithology, a preset, a fit) is a dimension of names.

This engine knows no family. The base scene's family (:mod:`faultslip.contract`) reads the scene, says which
parameters it sweeps, checks the study, and evaluates a block of cells (``Family.cells``): the seed law's
closed form in one vectorised call on numpy arrays aligned on the study's axes (each input over only the
dimensions it depends on), any family without such a kernel by its own run on each cell. A dask-chunked study
hands the family labelled, chunked coordinates and stays lazy.
"""

from __future__ import annotations

import difflib
import hashlib
import os
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from faultslip import __version__, ranges
from faultslip.contract.cells import aligned
from faultslip.contract.registry import DECLARATIONS, cells_of, family_of, load, read_scene, read_scene_text
from faultslip.errors import InputError, did_you_mean
from faultslip.io import budget
from faultslip.io.budget import MAX_DIMENSION_VALUES
from faultslip.io.resources import (check_toml_kind, parse_toml, read_text_file, resolve_path, scene_document,
                                    toml_kind)
from faultslip.units import is_quantity, to_si_scalar

STUDY_KEYS = {"name", "base", "method", "tolerance", "description", "cycles"}


@dataclass
class Study:
    """A parsed study: base scene, swept dimensions (SI values or category names), method.

    ``family`` is the base scene's model family (:class:`faultslip.contract.Family`); its ``cells`` evaluate
    the study.
    """

    name: str
    scene: object  # the family's scene object
    dims: dict  # name -> list of SI floats or category strings
    method: str = "auto"
    tolerance: float | None = 1e-6
    text: str = ""  # the study file as read
    description: str = ""
    units_text: dict = field(default_factory=dict)
    base_name: str = ""  # the base scene as the study names it (stable across reproduction)

    cycles: int = 0  # rate-and-state studies: cycles simulated per unstable cell (0: K / K_c only)
    _cell_seconds: float | None = field(default=None, repr=False, compare=False)
    _imports: tuple | None = field(default=None, repr=False, compare=False)
    #: studies whose cells checkpoint (a 2-D fault): the folder of per-cell work (set by the streaming runner)
    work_dir: object = field(default=None, compare=False)
    family: object = field(default=None, compare=False)

    def __post_init__(self):
        if self.family is None:
            self.family = family_of(self.scene)

    def __getstate__(self):
        """A worker gets the family by name and declaration (its functions stay in its module), so a family
        declared at run time reaches a pool's fresh processes too."""
        state = dict(self.__dict__)
        family = state.pop("family")
        state["family_declaration"] = (family.name, DECLARATIONS[family.name])
        return state

    def __setstate__(self, state):
        name, declaration = state.pop("family_declaration")
        DECLARATIONS.setdefault(name, declaration)
        self.__dict__.update(state)
        self.family = load(name)

    @property
    def cells(self):
        """The family's sweep (:class:`faultslip.contract.cells.Cells`)."""
        return cells_of(self.family, self.scene)

    @property
    def parameters(self) -> dict:
        """The parameters this study's base scene may sweep: name -> :class:`faultslip.contract.Parameter`."""
        return self.cells.parameters(self.scene)

    @property
    def shape(self) -> tuple:
        return tuple(len(values) for values in self.dims.values())

    @property
    def size(self) -> int:
        return int(np.prod(self.shape)) if self.dims else 1

    def seconds_per_cell(self) -> float:
        """Estimated wall time per cell on one worker (for the budget and the block size)."""
        if self._cell_seconds is None:
            self._cell_seconds = self.cells.seconds_per_cell(self)
        return self._cell_seconds

    def layout_seconds(self) -> float:
        """Estimated time a run to a file spends on the one cell it computes first to learn its outputs' layout
        (:func:`template_block`): a cell's, where the family does not declare its outputs, else 0."""
        return self.seconds_per_cell() if self.cells.outputs(self) is None else 0.0

    def imports(self) -> tuple:
        """The modules its cells import where they run (the family's ``Cells.imports``; none where it declares
        none): what a sweep's estimate counts beside its own (:func:`faultslip.io.budget.study_estimate`), and a
        process pool imports before its workers fork. Asked once per study: a family may read its cost model."""
        if self._imports is None:
            declared = getattr(self.cells, "imports", None)
            self._imports = tuple(declared(self)) if declared is not None else ()
        return self._imports

    def seconds_per_worker(self) -> float:
        """Estimated time each worker spends once, before its first cell (the family's
        ``Cells.seconds_per_worker``; 0 where it declares none)."""
        setup = getattr(self.cells, "seconds_per_worker", None)
        return float(setup(self)) if setup is not None else 0.0

    def fingerprint(self) -> str:
        """Hash of everything that determines the result (for resuming)."""
        digest = hashlib.sha256()
        digest.update(self.text.encode())
        digest.update(self.scene.text.encode())
        digest.update(repr((self.method, self.tolerance, list(self.dims.items()))).encode())
        return digest.hexdigest()[:16]


def _sweepable(study_or_cells, scene, name: str, where: str):
    """The :class:`~faultslip.contract.Parameter` ``name`` of the scene's family, or a sentence naming those it has."""
    allowed = study_or_cells.parameters(scene)
    if name not in allowed:
        hint = did_you_mean(name, allowed, n=3)
        label = study_or_cells.label
        raise InputError(f"unknown parameter {name!r}{where}{hint} ({label} sweeps: {', '.join(allowed)})")
    return allowed[name]


def _values(name, spec, kind, where):
    """SI values of one sweep dimension from a list, a linspace or a logspace."""
    if isinstance(spec, dict):
        if len(spec) != 1 or next(iter(spec)) not in ("linspace", "logspace"):
            raise InputError(f"{where} must be a list, or a table with one key linspace or logspace; got {spec!r}")
        rule, args = next(iter(spec.items()))
        if not isinstance(args, list) or len(args) != 3 or not isinstance(args[2], int) or isinstance(args[2], bool):
            raise InputError(f"{where} {rule} needs [start, stop, count], e.g. [\"1 mm/yr\", \"100 mm/yr\", 21]")
        start, stop = (to_si_scalar(v, kind, f"{where} {rule}") for v in args[:2])
        count = args[2]
        if count < 1:
            raise InputError(f"{where} is empty: {rule} count must be at least 1, got {count}")

        if count > MAX_DIMENSION_VALUES:  # checked before numpy allocates the coordinate
            raise InputError(f"{where} asks for {count:.3g} values; one dimension holds at most "
                             f"{MAX_DIMENSION_VALUES:.0e} (its coordinate alone would take {8 * count / 1e9:.3g} GB)")
        if rule == "logspace":
            if start <= 0 or stop <= 0:
                raise InputError(f"{where} logspace needs positive start and stop, got {args[0]!r} and {args[1]!r}")
            return list(ranges.check(name, np.geomspace(start, stop, count), where))
        return list(ranges.check(name, np.linspace(start, stop, count), where))
    if not isinstance(spec, list):
        spec = [spec]
    if not spec:
        raise InputError(f"{where} is empty: give at least one value")
    return [ranges.check(name, to_si_scalar(v, kind, where), where) for v in spec]


def _categories(name, spec, cells, scene, where):

    if not isinstance(spec, list):
        spec = [spec]
    if not spec:
        raise InputError(f"{where} is empty: give at least one {name}")
    out = []
    for value in spec:
        if not isinstance(value, str):
            raise InputError(f"{where} must list names as strings, got {value!r}")
        out.append(cells.category(scene, name, value, where))
    if len(set(out)) != len(out):
        raise InputError(f"{where} lists a {name} twice")
    return out



def _dimension(spec, parameter, cells, scene, where):
    """One swept dimension's values: category names, or SI numbers from a list, a linspace or a logspace."""
    if parameter.is_category:
        return _categories(parameter.name, spec, cells, scene, where)
    return _values(parameter.name, spec, parameter.kind, where)


def parse_study(text: str, source: str = "<study>", base_dir: Path | None = None, base_text: str | None = None) -> Study:
    """Parse and validate a study. ``base_text`` overrides reading the base scene (reproduction)."""

    document = parse_toml(text, source)
    check_toml_kind(document, source, "study")
    for table in document:
        if table not in ("study", "sweep"):
            close = difflib.get_close_matches(table, ["study", "sweep"], n=1)
            hint = f"; did you mean [{close[0]}]?" if close else ""
            what = f"table [{table}]" if isinstance(document[table], dict) else f"key {table} outside [study]"
            raise InputError(f"unknown {what} in {source}{hint} (allowed: [study], [sweep])")
    head = document.get("study", {})
    if not isinstance(head, dict):
        raise InputError(f"study in {source} must be a table [study], got a value")
    for key in head:
        if key not in STUDY_KEYS:
            hint = did_you_mean(key, STUDY_KEYS)
            raise InputError(f"unknown key {key!r} in [study] of {source}{hint} (allowed: {', '.join(sorted(STUDY_KEYS))})")
    for key in ("name", "description"):
        if key in head and not isinstance(head[key], str):
            raise InputError(f"[study] {key} in {source} must be a string, got {head[key]!r}")
    if not isinstance(document.get("sweep", {}), dict):
        raise InputError(f"sweep in {source} must be a table [sweep], got a value")
    if "base" not in head:
        raise InputError(f"[study] in {source} needs base = \"SCENE.toml\" (a scene file or a bundled scene name)")
    if not isinstance(head["base"], str):
        raise InputError(f"[study] base in {source} must be a file name string, got {head['base']!r}")
    if base_text is not None:
        scene, family = read_scene_text(base_text, str(head["base"]))
    else:  # relative to the study file; a bare name may also mean a bundled scene
        scene, family = read_scene(head["base"], base_dir=base_dir)
    cells = cells_of(family, scene)
    tolerance = ranges.check_tolerance(head.get("tolerance", cells.default_tolerance), f"[study] in {source}")
    dims, units_text = {}, {}
    for name, spec in document.get("sweep", {}).items():
        parameter = _sweepable(cells, scene, name, f" in [sweep] of {source}")
        dims[name] = _dimension(spec, parameter, cells, scene, f"[sweep] {name} in {source}")
        units_text[name] = spec
    study = Study(name=head.get("name", Path(source).stem), scene=scene, dims=dims, method=head.get("method", "auto"),
                  tolerance=tolerance, text=text, description=head.get("description", ""), units_text=units_text,
                  base_name=Path(head["base"]).name, cycles=head.get("cycles", 0), family=family)
    cells.check(study, f"[study] in {source}:", source)
    return study


def load_study(path) -> Study:
    """A study file, read: a path, or a bare name that is not here found among the bundled configs (as a scene's is:
    :func:`faultslip.io.resources.resolve_path`), so that ``faultslip sweep study_rate_state.toml`` runs anywhere.

    Parameters
    ----------
    path : str or path
        The study file.

    Returns
    -------
    Study
        Its base scene, grid, method, tolerance and cycles.
    """
    path, _ = resolve_path(path, "study file", kind="study")
    return parse_study(read_text_file(path, "study file"), source=path.name, base_dir=path.parent)


# --- inputs as labelled arrays ---------------------------------------------


def _coordinate(study, name, values, index=None):
    import xarray as xr  # heavy: imported where used

    parameter = study.parameters[name]
    values = values if index is None else values[index]
    data = np.array(values, dtype=object) if parameter.is_category else np.asarray(values, dtype=float)
    attrs = parameter.attrs()
    # built from a variable of known numpy data: xarray's generic constructor would probe for
    # every duck-array library and import dask (about 0.4 s) even where nothing is chunked
    holder = xr.Dataset({"values": xr.Variable((name,), data, attrs, fastpath=True)},
                        coords={name: xr.IndexVariable((name,), data, attrs, fastpath=True)})
    return holder["values"].rename(name)


def study_inputs(study, block=None, chunks=None, aligned_: bool = False) -> dict:
    """Each swept parameter's values over the block, as the family's ``evaluate`` takes them.

    ``block`` (name -> slice) restricts each swept dimension; ``chunks`` (name -> size) makes the swept
    coordinates dask-chunked, so everything downstream is lazy. Values are labelled DataArrays, or with
    ``aligned_`` numpy arrays on the study's axes (size 1 along the others), which is how a block in memory
    is computed: numpy's broadcasting does what xarray's alignment would, without its fixed cost (and
    without xarray's arithmetic, which imports dask wherever dask is installed).
    """
    if aligned_:
        return aligned(study.dims, study.parameters, block)
    coords = {}
    for name, values in study.dims.items():
        index = None if block is None else block.get(name, slice(None))
        coords[name] = _coordinate(study, name, values, index)
        if chunks and name in chunks and not study.parameters[name].is_category:
            coords[name] = coords[name].chunk({name: chunks[name]})
    return coords


def as_dataset(outputs: dict, study, block=None):
    """Outputs broadcast over every swept dimension of the study (or ``block``), with CF attributes.

    A swept parameter that no output depends on (the shear-wave speed without radiation damping)
    still labels every output, so the file has the grid the study asked for.
    """
    import xarray as xr  # heavy: imported where used

    arrays = {}
    for name, value in outputs.items():
        if name in study.dims:  # a swept input that is also an output (loading_rate): the coordinate holds it
            continue
        if not isinstance(value, xr.DataArray):
            value = xr.DataArray(value)
        arrays[name] = value
    dataset = xr.Dataset(arrays)
    for name, values in study.dims.items():
        if name not in dataset.dims:
            index = None if block is None else block.get(name, slice(None))
            dataset = dataset.expand_dims({name: _coordinate(study, name, values, index)})
    order = [d for d in study.dims if d in dataset.dims]
    dataset = dataset.transpose(*order) if order else dataset
    flagged = "outside_domain" in dataset.data_vars
    for name in dataset.data_vars:
        dataset[name].attrs = study.cells.attrs(name, study, flagged)
    return dataset


def _block_dataset(outputs: dict, study, block=None):
    """A Dataset from numpy outputs on the study's axes, every output over every dimension.

    The same dataset :func:`as_dataset` builds from labelled outputs, built from variables
    directly: an output constant along a swept dimension is a broadcast view, not a copy.
    """
    import xarray as xr  # heavy: imported where used

    order = list(study.dims)
    coords = {name: _coordinate(study, name, values, None if block is None else block.get(name, slice(None)))
              for name, values in study.dims.items()}
    shape = tuple(coords[name].size for name in order)
    coords = {name: coordinate.variable for name, coordinate in coords.items()}
    flagged = "outside_domain" in outputs
    variables = {}
    for name, value in outputs.items():
        if name in coords:  # a swept input that is also an output (loading_rate): the coordinate holds it
            coords[name].attrs = study.cells.attrs(name, study)
        else:
            variables[name] = xr.Variable(order, np.broadcast_to(value, shape), study.cells.attrs(name, study, flagged),
                                          fastpath=True)
    return xr.Dataset(variables, coords=coords)


def _evaluate_block(study, block):
    return study.cells.evaluate(study, study_inputs(study, block, aligned_=True))


def block_arrays(study, block) -> dict:
    """The data variables of :func:`compute_block` as numpy arrays over the block, dimensions in the study's
    order: what a sweep's worker encodes. No Dataset is built (its coordinates' indexes cost 45 ms a block,
    a fifth of a closed-form block's work); an output constant over the block stays a broadcast view."""
    outputs = _evaluate_block(study, block)
    shape = tuple(len(study.dims[name][block.get(name, slice(None))]) for name in study.dims)
    return {name: np.broadcast_to(value, shape) for name, value in outputs.items() if name not in study.dims}


@dataclass
class OutputLayout:
    """One output of a study as a file lays it out: its type and attributes, no values."""

    dtype: np.dtype
    attrs: dict


@dataclass
class StudyLayout:
    """A study's outputs (name -> :class:`OutputLayout`, as a Dataset's ``data_vars``) and global attributes."""

    data_vars: dict
    attrs: dict = field(default_factory=dict)

    def copy(self) -> "StudyLayout":
        return StudyLayout(dict(self.data_vars), dict(self.attrs))


def template_block(study) -> StudyLayout:
    """The layout of the study's outputs: the family's declared outputs, or else those of one cell computed
    (a family whose outputs depend on its scene). A closed-form study's needs no xarray."""
    declared = study.cells.outputs(study)
    if declared is not None:
        return StudyLayout({name: OutputLayout(spec.dtype, spec.attrs()) for name, spec in declared.items()
                            if name not in study.dims})
    outputs = _evaluate_block(study, {n: slice(0, 1) for n in study.dims})
    flagged = "outside_domain" in outputs
    return StudyLayout({name: OutputLayout(np.asarray(value).dtype, study.cells.attrs(name, study, flagged))
                        for name, value in outputs.items() if name not in study.dims})


def compute_block(study, block=None):
    """The study outputs on one block (name -> slice of each swept dimension), computed in memory."""
    return _block_dataset(_evaluate_block(study, block), study, block)


def sweep(scene, method: str = "auto", tolerance: float | None = None, chunks: dict | None = None,
          allow_large: bool = False, cycles: int = 0, **dims):
    """Python API: sweep parameters of any family's scene; returns an xarray Dataset.

    Parameters
    ----------
    scene : str, path or scene object
        A scene file, a bundled scene's name, or a scene object (a :func:`faultslip.models.read_slider_scene` Scene, a
        2-D fault scene, ...).
    method : str
        One of the family's methods, or ``"auto"`` (per cell, the cheapest that meets ``tolerance``).
    tolerance : float, optional
        The relative error allowed; None: the family's default (1e-6 for the seed law).
    chunks : dict, optional
        Dimension -> chunk size: the result is dask-backed and lazy.
    allow_large : bool
        Compute in memory beyond the time and memory budget.
    cycles : int
        Rate-and-state studies: cycles simulated in every unstable cell (0: K / K_c only).
    **dims
        Each a sweepable parameter of the scene's family, with a list of values with units (strings or pint
        Quantities), a ``{"logspace": [start, stop, count]}`` rule, or category names.

    Returns
    -------
    xarray.Dataset
        Every output over every swept dimension, with CF attributes (``units`` on every variable).

    A study file (``[study]`` and ``[sweep]``, what ``faultslip sweep STUDY -o OUT`` runs) is swept as it states,
    in memory (or lazily with ``chunks``): its grid, method, tolerance and cycles are its own.

    >>> sweep("san_andreas_1906.toml", slip_rate=["10 mm/yr", "35 mm/yr"], lithology=["granodiorite", "pyrite"])
    >>> sweep("vibration_seed002.toml", speed=["5 in/s", "10 in/s", "15 in/s"])
    >>> sweep("study_rate_state.toml")
    """
    if isinstance(scene, (str, os.PathLike)):
        document = scene_document(scene)
        if document is not None and toml_kind(document) == "study":
            stated = [name for name, given in (("method", method != "auto"), ("tolerance", tolerance is not None),
                                               ("cycles", cycles != 0), *((name, True) for name in dims)) if given]
            if stated:
                raise InputError(f"sweep(): {Path(scene).name} is a study, which states its own grid, method, "
                                 f"tolerance and cycles; give {', '.join(stated)} in its file, or sweep its base "
                                 "scene by keywords")
            return _computed(load_study(scene), chunks, allow_large)
    scene, family = read_scene(scene)
    cells = cells_of(family, scene)
    parsed = {}
    for name, values in dims.items():
        parameter = _sweepable(cells, scene, name, "")
        values = values if isinstance(values, dict) else list(values) if not isinstance(values, (str, bytes)) else [values]
        parsed[name] = _dimension(values, parameter, cells, scene, name)
    tolerance = ranges.check_tolerance(cells.default_tolerance if tolerance is None else tolerance, "sweep()")
    study = Study(name=scene.name, scene=scene, dims=parsed, method=method, tolerance=tolerance,
                  text=_study_text(scene, method, tolerance, dims, cycles), cycles=cycles, family=family)
    cells.check(study, "sweep():", "sweep()")
    return _computed(study, chunks, allow_large)


def _computed(study: Study, chunks: dict | None, allow_large: bool):
    """A study's Dataset: in memory, after refusing what will not fit, or lazy with ``chunks``."""
    if chunks is None:  # everything in memory: refuse what will not fit (a chunked study stays lazy)
        estimate = budget.study_estimate(study, None, 1, study.size)
        budget.check(budget.Estimate(f"this in-memory sweep of {study.size:.3g} cells", memory=estimate.memory,
                                     seconds=estimate.seconds), allow_large)
        return finish(compute_block(study), study)
    return finish(as_dataset(study.cells.evaluate(study, study_inputs(study, chunks=chunks)), study), study)


def _study_text(scene, method, tolerance, dims, cycles: int = 0) -> str:

    def literal(value):
        if isinstance(value, str):
            return '"' + value.replace('"', '\\"') + '"'
        if is_quantity(value):
            return f'"{value.magnitude!r} {value.units:~}"'
        return repr(float(value))

    lines = ["[study]", f'name = {literal(scene.name)}', f'base = {literal(scene.path.name if scene.path else scene.name)}',
             f'method = "{method}"'] + ([f"tolerance = {tolerance!r}"] if tolerance is not None else []) + ([f"cycles = {cycles}"] if cycles else []) + ["", "[sweep]"]
    for name, values in dims.items():
        if isinstance(values, dict):  # {"logspace": [start, stop, count]}
            (rule, args), = values.items()
            lines.append(f"{name} = {{ {rule} = [{', '.join(literal(v) if not isinstance(v, int) else str(v) for v in args)}] }}")
            continue
        values = list(values) if not isinstance(values, (str, bytes)) else [values]
        lines.append(f"{name} = [{', '.join(literal(v) for v in values)}]")
    return "\n".join(lines) + "\n"


def finish(dataset, study):
    """Global CF attributes and the embedded config that lets the file reproduce itself."""


    dataset.attrs.update({
        "title": f"faultslip study: {study.name}",
        "Conventions": "CF-1.8",
        "source": f"faultslip {__version__}",
        "history": f"{datetime.now(timezone.utc).isoformat(timespec='seconds')}: faultslip sweep",
        "faultslip_study": study.text,
        "faultslip_base_scene": study.scene.text,
        "faultslip_base_scene_name": study.base_name or (study.scene.path.name if study.scene.path else study.scene.name),
        "faultslip_family": study.family.name,
        "method_requested": study.method,
        **({"tolerance": study.tolerance} if study.tolerance is not None else {}),
        "comment": "regime and method are flags (see flag_meanings); categorical dimensions are strings",
    })
    if study.description:
        dataset.attrs["summary"] = study.description
    return dataset
