"""Gridded parameter studies as labelled xarray datasets.

A study names a base scene and sweeps any of its parameters, each as a dimension::

    [study]
    name = "Slip and recurrence against slip rate and lithology"
    base = "san_andreas_1906.toml"
    method = "auto"          # or closed_form, exact_cycle
    tolerance = 1e-6

    [sweep]
    slip_rate = { logspace = ["1 mm/yr", "100 mm/yr", 41] }
    zone_width = ["5 km", "13 mi", "30 km"]
    lithology = ["granodiorite", "black_marble", "pyrite"]

Every value states its units. A swept ``lithology`` (fault) or ``preset`` (lab) is a categorical
dimension: each category supplies its shear modulus and friction law, unless those are swept too.

Evaluation is array arithmetic on labelled DataArrays: each intermediate carries only the
dimensions it depends on (the critical rate, for instance, is solved on the damping and
material dimensions only), and only the outputs span the whole grid. Kernels that are not
ufuncs go through :func:`xarray.apply_ufunc` with ``dask="parallelized"``, so a dask-chunked
study stays lazy. With ``method="auto"`` each cell uses the closed form where its error model
meets the tolerance and the exact cycle elsewhere; the regime comes from the exact criterion
eps < eps_c(zeta) in every cell. Friction laws without a closed form (polynomial kinetic,
time-of-stick static) are simulated cell by cell, in parallel chunks.
"""

from __future__ import annotations

import difflib
import hashlib
import itertools
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip import ranges
from faultslip.dynamics.kernel import KERNEL_OUTPUTS, METHOD_CODES, REGIME_CODES, cell_kernel
from faultslip.errors import InputError, did_you_mean
from faultslip.fault import empirical
from faultslip.io.resources import parse_toml
from faultslip.units import STANDARD_GRAVITY, to_si, to_si_scalar
from faultslip import __version__
from faultslip.dynamics.spring_slider.critical import critical_dimensionless_rate, solve_rate_law_critical
from faultslip.dynamics.methods import solve
from faultslip.dynamics.fault_2d.analysis import summarise as summarise_fault_2d
from faultslip.fault.fault_2d_scene import SWEEPABLE as FAULT_2D_PARAMETERS
from faultslip.fault.fault_2d_scene import Fault2DScene, is_fault_2d_document, load_fault_2d_scene, parse_fault_2d_scene
from faultslip.fault.scene import apply_friction, load_scene, parse_scene, Scene
from faultslip.io.resources import read_text_file, resolve_path, scene_document
from faultslip.fault.rate_state_cells import (check_cycle_method, check_friction, estimated_seconds, evolution_codes, output_names,
                                               rate_state_cells)
from faultslip.fault.rate_state_cells import OUTPUT_ATTRS as RATE_STATE_OUTPUT_ATTRS
from faultslip.fault.rate_state_cells import METHOD_CODES as RATE_STATE_METHOD_CODES
from faultslip.fault.rate_state_cells import REGIME_CODES as RATE_STATE_REGIME_CODES
from faultslip.friction.materials import get_preset, resolve_material
from faultslip.friction.rate_state import EVOLUTION_LAWS
from faultslip.io import budget
from faultslip.io.budget import MAX_DIMENSION_VALUES
from faultslip.units import is_quantity
from datetime import datetime, timezone

#: Sweepable parameters: name -> (unit kind, SI unit, long name). "category" is a string dimension.
FAULT_PARAMETERS = {
    "lithology": ("category", None, "lithology or friction preset"),
    "shear_modulus": ("pressure", "Pa", "shear modulus G"),
    "zone_width": ("length", "m", "elastic-zone half-width D"),
    "normal_stress": ("pressure", "Pa", "effective normal stress"),
    "shear_stress": ("pressure", "Pa", "shear stress tau (sigma_n = tau / mu_so)"),
    "slip_rate": ("speed", "m/s", "tectonic slip rate V"),
    "mu_so": ("dimensionless", "1", "static friction at vanishing loading rate"),
    "mu_m": ("dimensionless", "1", "kinetic friction"),
    "b": ("dimensionless", "1", "rate coefficient b of eq. 2-18 (in s^d)"),
    "d": ("dimensionless", "1", "rate exponent d of eq. 2-18"),
    "rupture_length": ("length", "m", "rupture length L"),
    "seismogenic_depth": ("length", "m", "seismogenic depth H"),
    "damping_ratio": ("dimensionless", "1", "damping ratio of the dashpot"),
    "density": ("density", "kg/m^3", "rock density rho (M = rho D)"),
    "shear_wave_speed": ("speed", "m/s", "shear-wave speed c_s (radiation damper G/(2 c_s))"),
}
LAB_PARAMETERS = {
    "preset": ("category", None, "Table I preset"),
    "platform_speed": ("speed", "m/s", "platform speed V"),
    "loading_rate": ("rate", "1/s", "loading rate theta_dot = K V / W"),
    "damping_ratio": ("dimensionless", "1", "damping ratio of the dashpot"),
    "kinetic_slope": ("slowness", "s/m", "slope beta of the linear kinetic law"),
    "normal_load": ("force", "N", "normal load W"),
    "stiffness": ("stiffness", "N/m", "stiffness K"),
}
#: a fault whose base scene has rate-and-state friction ([friction] law = "rate_state")
RATE_STATE_PARAMETERS = {
    "fit": ("category", None, "saved rate-and-state fit (faultslip fit --law rate-state --name)"),
    "evolution": ("category", None, "state evolution law (aging or slip)"),
    "a": ("dimensionless", "1", "rate-and-state direct effect a"),
    "b": ("dimensionless", "1", "rate-and-state evolution effect b"),
    "critical_slip": ("length", "m", "critical slip distance D_c"),
    "mu0": ("dimensionless", "1", "reference friction mu0 at V0"),
    "reference_speed": ("speed", "m/s", "reference speed V0"),
    **{name: FAULT_PARAMETERS[name] for name in ("shear_modulus", "zone_width", "normal_stress", "slip_rate",
                                                  "rupture_length", "seismogenic_depth", "density",
                                                  "shear_wave_speed")},
    "shear_stress": ("pressure", "Pa", "shear stress tau (sigma_n = tau / mu0)"),
}
STUDY_KEYS = {"name", "base", "method", "tolerance", "description", "cycles"}
#: [study] method: the seed law's methods, and the cycle methods of a rate-and-state study
SEED_METHODS = ("auto", "closed_form", "exact_cycle")


@dataclass
class Study:
    """A parsed study: base scene, swept dimensions (SI values or category names), method."""

    name: str
    scene: object  # faultslip.fault.scene.Scene
    dims: dict  # name -> list of SI floats or category strings
    method: str = "auto"
    tolerance: float = 1e-6
    text: str = ""  # the study file as read
    description: str = ""
    units_text: dict = field(default_factory=dict)
    base_name: str = ""  # the base scene as the study names it (stable across reproduction)

    cycles: int = 0  # rate-and-state studies: cycles simulated per unstable cell (0: K / K_c only)
    _cell_seconds: float | None = field(default=None, repr=False, compare=False)
    #: 2-D fault studies: the folder of per-cell checkpoints (set by the streaming runner; None: in memory)
    work_dir: object = field(default=None, compare=False)

    @property
    def kind(self) -> str:
        return study_kind(self.scene)

    @property
    def shape(self) -> tuple:
        return tuple(len(values) for values in self.dims.values())

    @property
    def size(self) -> int:
        return int(np.prod(self.shape)) if self.dims else 1

    def seconds_per_cell(self) -> float:
        """Estimated wall time per cell on one worker (for the budget and the block size)."""
        if self.kind == "fault_2d":
            if self._cell_seconds is None:
                self._cell_seconds = fault_2d_cell_seconds(self.scene, self.dims)
            return self._cell_seconds
        if self.kind == "rate_state" and self.cycles:
            if self._cell_seconds is None:
                self._cell_seconds = _rate_state_cell_seconds(self)
            return self._cell_seconds
        return 1.0 / (budget.SIMULATED_CELL_RATE if _needs_simulation(self) else budget.STUDY_CELL_RATE)

    def fingerprint(self) -> str:
        """Hash of everything that determines the result (for resuming)."""
        digest = hashlib.sha256()
        digest.update(self.text.encode())
        digest.update(self.scene.text.encode())
        digest.update(repr((self.method, self.tolerance, list(self.dims.items()))).encode())
        return digest.hexdigest()[:16]


def study_kind(scene) -> str:
    """fault, lab, rate_state (a fault scene with rate-and-state friction) or fault_2d (a 2-D fault scene)."""
    if isinstance(scene, Fault2DScene):
        return "fault_2d"
    return "rate_state" if scene.rate_state else scene.kind


def parameters_for(kind: str) -> dict:
    return {"fault": FAULT_PARAMETERS, "lab": LAB_PARAMETERS, "rate_state": RATE_STATE_PARAMETERS,
            "fault_2d": FAULT_2D_PARAMETERS}[kind]


def fault_2d_cell_seconds(scene, dims: dict | None = None) -> float:
    """A 2-D fault cell's mean run time over the study's cells (each cell's own element size, D_c, V_pl...):
    :meth:`Fault2DScene.estimate`. A grid of more than 256 cells is estimated from its corners and centre."""
    dims = dims or {}
    names = list(dims)
    if not names:
        return scene.estimate().seconds
    axes = [np.asarray(dims[name]) for name in names]
    if int(np.prod([axis.size for axis in axes])) <= 256:
        cells = itertools.product(*axes)
    else:
        cells = itertools.product(*[np.unique(axis[[0, axis.size // 2, -1]]) for axis in axes])
    seconds = [scene.with_values(**dict(zip(names, (float(v) for v in cell)))).estimate().seconds for cell in cells]
    return float(np.mean(seconds))


def _base_scene(text: str, source: str, path=None):
    """A study's base: a 2-D fault scene (family = "fault_2d") or a seed-law or rate-and-state scene."""
    if is_fault_2d_document(parse_toml(text, source)):
        scene = parse_fault_2d_scene(text, source)
        scene.path = path
        return scene
    return parse_scene(text, source=source, path=path)


def _method_and_cycles(kind, method, cycles, where):
    """Validate [study] method and cycles (or sweep()'s) for a study of this kind."""
    if kind == "fault_2d":
        if method not in ("auto", "fault_2d") or cycles:
            raise InputError(f"{where} a 2-D fault study runs the 2-D model for the base scene's [run] duration; "
                             "leave method and cycles out")
        return
    if kind == "rate_state":
        check_cycle_method(method, f"{where} method of a rate-and-state study")
        if not isinstance(cycles, int) or isinstance(cycles, bool) or not 0 <= cycles <= 1000:
            raise InputError(f"{where} cycles must be a whole number from 0 (K / K_c only) to 1000, got {cycles!r}")
        return
    if method not in SEED_METHODS:
        raise InputError(f"{where} method must be auto, closed_form or exact_cycle, got {method!r}")
    if cycles:
        raise InputError(f"{where} cycles applies to rate-and-state studies ([friction] law = \"rate_state\" in "
                         "the base scene); a seed-law study finds its limit cycle without it")


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


def _categories(name, spec, kind, where):

    if not isinstance(spec, list):
        spec = [spec]
    if not spec:
        raise InputError(f"{where} is empty: give at least one {name}")
    out = []
    for value in spec:
        if not isinstance(value, str):
            raise InputError(f"{where} must list names as strings, got {value!r}")
        out.append(_category_name(name, value, kind, where))
    if len(set(out)) != len(out):
        raise InputError(f"{where} lists a {name} twice")
    return out


def _category_name(name, value, kind, where) -> str:
    """The canonical name of one category, or a sentence saying why it is refused."""
    if kind == "lab":
        return get_preset(value).name
    if name == "evolution":
        if value not in EVOLUTION_LAWS:
            raise InputError(f"{where}: evolution law must be one of {', '.join(EVOLUTION_LAWS)}, got {value!r}")
        return value
    choice = resolve_material(value)
    if name == "fit":
        if choice.rate_state is None:
            raise InputError(f"{where}: {value!r} is not a rate-and-state fit (faultslip fit --law rate-state RECORD "
                             "--name NAME saves one; faultslip materials lists them)")
        if choice.rate_state.two_state:
            raise InputError(f"{where}: the fit {value!r} has two state variables; fault predictions take a "
                             "one-state law (K_c of a two-state law has no closed form)")
    return choice.name


def parse_study(text: str, source: str = "<study>", base_dir: Path | None = None, base_text: str | None = None) -> Study:
    """Parse and validate a study. ``base_text`` overrides reading the base scene (reproduction)."""

    document = parse_toml(text, source)
    for table in document:
        if table not in ("study", "sweep"):
            close = difflib.get_close_matches(table, ["study", "sweep"], n=1)
            hint = f"; did you mean [{close[0]}]?" if close else ""
            raise InputError(f"unknown table [{table}] in {source}{hint} (allowed: [study], [sweep])")
    head = document.get("study", {})
    for key in head:
        if key not in STUDY_KEYS:
            hint = did_you_mean(key, STUDY_KEYS)
            raise InputError(f"unknown key {key!r} in [study] of {source}{hint} (allowed: {', '.join(sorted(STUDY_KEYS))})")
    if not isinstance(head, dict):
        raise InputError(f"study in {source} must be a table [study], got a value")
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
        scene = _base_scene(base_text, str(head["base"]))
    else:  # relative to the study file; a bare name may also mean a bundled scene

        base, origin = resolve_path(head["base"], "scene", base_dir=base_dir)
        scene = _base_scene(read_text_file(base, "scene file"), base.name, path=base)
        scene.origin = origin
    kind = study_kind(scene)
    method = head.get("method", "auto")
    cycles = head.get("cycles", 0)
    _method_and_cycles(kind, method, cycles, f"[study] in {source}:")
    tolerance = head.get("tolerance", 1e-6)
    if not isinstance(tolerance, (int, float)) or isinstance(tolerance, bool) or not 0 < tolerance < 1:
        raise InputError(f"[study] tolerance in {source} must be a number between 0 and 1, got {tolerance!r}")
    allowed = parameters_for(kind)
    dims = {}
    units_text = {}
    for name, spec in document.get("sweep", {}).items():
        where = f"[sweep] {name} in {source}"
        if name not in allowed:
            hint = did_you_mean(name, allowed, n=3)
            raise InputError(f"unknown parameter {name!r} in [sweep] of {source}{hint} "
                             f"(a {kind.replace('_', '-')} study sweeps: {', '.join(allowed)})")
        unit_kind = allowed[name][0]
        dims[name] = (_categories(name, spec, kind, where) if unit_kind == "category"
                      else _values(name, spec, unit_kind, where))
        units_text[name] = spec
    _check_consistent(scene, dims, source)
    return Study(name=head.get("name", Path(source).stem), scene=scene, dims=dims, method=method,
                 tolerance=float(tolerance), text=text, description=head.get("description", ""), units_text=units_text,
                 base_name=Path(head["base"]).name, cycles=cycles)


def _check_consistent(scene, dims, source):
    if isinstance(scene, Fault2DScene):
        scene.with_values(**{name: values[0] for name, values in dims.items()})  # e.g. a ramp to sweep
        return
    if scene.rate_state:
        _check_rate_state(scene, dims, source)
    elif scene.kind == "fault":
        fault = scene.tables.get("fault", {})
        stress_in_base = "normal_stress" in fault or "shear_stress" in fault
        if "normal_stress" in dims and "shear_stress" in dims:
            raise InputError(f"{source} sweeps both normal_stress and shear_stress; sweep one (sigma_n = tau / mu_so)")
        if not stress_in_base and not {"normal_stress", "shear_stress"} & set(dims):
            raise InputError(f"{source}: the base scene gives no stress; sweep normal_stress or shear_stress")
        if scene.observed_slip is not None:
            raise InputError(f"{source}: the base scene is an inverse (observed_slip); a study needs a forward scene")
    else:
        if "platform_speed" in dims and "loading_rate" in dims:
            raise InputError(f"{source} sweeps both platform_speed and loading_rate; sweep one (theta_dot = K V / W)")


def _check_rate_state(scene, dims, source):
    """A rate-and-state study's base and sweep together give every input once, in range."""
    if scene.kind != "fault":
        raise InputError(f"{source}: [friction] law = \"rate_state\" applies to fault scenes; a laboratory slider "
                         "under rate-and-state friction is a rate-state scene (faultslip rate-state simulate)")
    if scene.observed_slip is not None:
        raise InputError(f"{source}: the base scene is an inverse (observed_slip); a study needs a forward scene")
    friction = scene.tables.get("friction", {})
    if "fit" not in dims and "fit" not in friction:
        missing = [key for key in ("a", "b", "critical_slip") if key not in friction and key not in dims]
        if missing:
            raise InputError(f"{source}: the base scene's [friction] needs {', '.join(missing)} (or sweep it, or "
                             "name a fit)")
    given = scene.tables.get("fault", {})
    if "normal_stress" in dims and "shear_stress" in dims:
        raise InputError(f"{source} sweeps both normal_stress and shear_stress; sweep one (sigma_n = tau / mu0)")
    if not ({"normal_stress", "shear_stress"} & (set(given) | set(dims))):
        raise InputError(f"{source}: the base scene gives no stress; sweep normal_stress or shear_stress")
    for key in ("zone_width", "slip_rate"):
        if key not in given and key not in dims:
            raise InputError(f"{source}: the base scene gives no {key}; give it in [fault] or sweep it")
    # each swept friction parameter in its range (b <= a is allowed: those cells slide stably)
    check_friction(dims.get("a", 0.5), dims.get("b", 0.5), dims.get("critical_slip", 1e-3), dims.get("mu0", 0.6),
                   dims.get("reference_speed", 1e-6), f"[sweep] in {source}")


def load_study(path) -> Study:

    path = Path(path)
    if not path.exists():
        raise InputError(f"study file {str(path)!r} does not exist")
    if path.is_dir():
        raise InputError(f"study file {str(path)!r} is a folder")
    return parse_study(read_text_file(path, "study file"), source=path.name, base_dir=path.parent)


# --- inputs as labelled arrays ---------------------------------------------


def _coordinate(study, name, values, index=None):
    import xarray as xr  # heavy: imported where used

    kind, unit, long_name = parameters_for(study.kind)[name]
    values = values if index is None else values[index]
    if kind == "category":
        data = np.array(values, dtype=object)
        attrs = {"long_name": long_name}
    else:
        data = np.asarray(values, dtype=float)
        attrs = {"units": unit, "long_name": long_name}
    # built from a variable of known numpy data: xarray's generic constructor would probe for
    # every duck-array library and import dask (about 0.4 s) even where nothing is chunked
    holder = xr.Dataset({"values": xr.Variable((name,), data, attrs, fastpath=True)},
                        coords={name: xr.IndexVariable((name,), data, attrs, fastpath=True)})
    return holder["values"].rename(name)


def study_inputs(study, block=None, chunks=None, aligned: bool = False) -> dict:
    """Every model input over only the dimensions it depends on (SI).

    ``block`` (name -> slice) restricts each swept dimension; ``chunks`` (name -> size)
    makes the swept coordinates dask-chunked, so everything downstream is lazy. Inputs are
    DataArrays, or with ``aligned`` numpy arrays on the study's axes (size 1 where an input does
    not vary), which is how a block in memory is computed: numpy's broadcasting does what
    xarray's alignment would, without its fixed cost (and without xarray's arithmetic, which
    imports dask wherever dask is installed).
    """
    coords = {}
    names = list(study.dims)
    for axis, (name, values) in enumerate(study.dims.items()):
        index = None if block is None else block.get(name, slice(None))
        if aligned:
            kind = parameters_for(study.kind)[name][0]
            chosen = values if index is None else values[index]
            data = np.array(chosen, dtype=object if kind == "category" else float)
            coords[name] = data.reshape([data.size if i == axis else 1 for i in range(len(names))])
            continue
        coords[name] = _coordinate(study, name, values, index)
        if chunks and name in chunks and parameters_for(study.kind)[name][0] != "category":
            coords[name] = coords[name].chunk({name: chunks[name]})
    builders = {"fault": _fault_inputs, "lab": _lab_inputs, "rate_state": rate_state_inputs}
    return builders[study.kind](study, coords)


def _labels(coordinate) -> list:
    """The category names along a categorical coordinate (labelled or aligned numpy)."""
    return [str(v) for v in np.ravel(np.asarray(coordinate, dtype=object))]


def _category_table(coordinate, getter):
    """Values over a categorical dimension from a per-category lookup (None -> NaN), shaped like ``coordinate``."""
    import xarray as xr  # heavy: imported where used

    values = [getter(name) for name in _labels(coordinate)]
    data = np.array([np.nan if v is None else v for v in values], dtype=float)
    if not isinstance(coordinate, xr.DataArray):  # aligned numpy: the same axes as the coordinate
        return data.reshape(np.shape(coordinate))
    # from a variable, as in _coordinate: the generic constructor would import dask
    holder = xr.Dataset({"values": xr.Variable(coordinate.dims, data, fastpath=True)}, coords=coordinate.coords)
    return holder["values"].rename(coordinate.name)


def _fault_inputs(study, coords):

    fault = study.scene.fault()  # the base, validated (lithology defaults applied)
    given = study.scene.tables.get("fault", {})
    inputs = {}
    for name in ("shear_modulus", "zone_width", "slip_rate", "mu_so", "mu_m", "b", "d", "rupture_length",
                 "seismogenic_depth", "damping_ratio", "density", "shear_wave_speed"):
        inputs[name] = coords[name] if name in coords else getattr(fault, name)
    if "shear_wave_speed" not in coords and "shear_wave_speed" not in given:
        inputs["shear_wave_speed"] = None  # sqrt(G / rho) of each cell, as Fault derives it
    if "lithology" in coords:  # each category supplies G and the friction law unless swept
        lith = coords["lithology"]
        choices = {name: resolve_material(name) for name in _labels(lith)}
        if "shear_modulus" not in coords:
            inputs["shear_modulus"] = _category_table(lith, lambda n: choices[n].shear_modulus)
            if np.isnan(np.asarray(inputs["shear_modulus"], dtype=float)).any():
                missing = [n for n in _labels(lith) if choices[n].shear_modulus is None]
                raise InputError(f"lithology {missing[0]!r} has no shear modulus; sweep shear_modulus as well")
        for key in ("mu_so", "mu_m", "b", "d"):
            if key not in coords:
                table = {n: (getattr(choices[n].rate_law, key) if choices[n].rate_law is not None else None)
                         for n in _labels(lith)}
                if any(v is None for v in table.values()):
                    missing = [n for n, v in table.items() if v is None]
                    raise InputError(f"lithology {missing[0]!r} has no friction preset; give {key} in the base "
                                     "scene or sweep it")
                inputs[key] = _category_table(lith, table.get)
    inputs["normal_stress"] = normal_stress_input(inputs, coords, given, fault)
    inputs["radiation_damping"] = bool(fault.radiation_damping)
    return inputs


def _category_names(coordinate, getter):
    """Names over a categorical dimension from a per-category lookup, shaped like ``coordinate``."""
    import xarray as xr  # heavy: imported where used

    data = np.array([getter(name) for name in _labels(coordinate)], dtype=object)
    if not isinstance(coordinate, xr.DataArray):
        return data.reshape(np.shape(coordinate))
    return xr.DataArray(data, dims=coordinate.dims, coords=coordinate.coords)


#: rate-and-state friction inputs of the cell kernel, and the defaults of a scene's [friction]
_RATE_STATE_FRICTION = {"a": None, "b": None, "critical_slip": None, "mu0": 0.6, "reference_speed": 1e-6,
                        "evolution": "aging"}


def rate_state_inputs(study, coords):
    """Keyword arguments of :func:`faultslip.fault.rate_state_cells.rate_state_cells` over the study's axes."""
    scene = study.scene
    friction = scene.tables.get("friction", {})
    values, _ = scene.rate_state_fault_values(require_modulus=False)
    if "fit" in friction:
        law, _ = scene.rate_state_law()
        if law.two_state:
            raise InputError(f"the fit {friction['fit']!r} in {scene.name} has two state variables; fault predictions "
                             "take a one-state law")
        base = {key: getattr(law, key) for key in _RATE_STATE_FRICTION}
        base_modulus = resolve_material(friction["fit"]).shear_modulus
    else:
        units = {"critical_slip": "length", "reference_speed": "speed"}
        base = {key: default if key not in friction else to_si_scalar(friction[key], units[key], key)
                if key in units else friction[key] if key == "evolution" else float(friction[key])
                for key, default in _RATE_STATE_FRICTION.items()}
        base_modulus = None
    inputs = {}
    fits = {name: resolve_material(name) for name in _labels(coords["fit"])} if "fit" in coords else {}
    for key in _RATE_STATE_FRICTION:
        if key in coords:
            inputs[key] = coords[key]
        elif fits and key == "evolution":
            inputs[key] = _category_names(coords["fit"], lambda n: fits[n].rate_state.evolution)
        elif fits:
            inputs[key] = _category_table(coords["fit"], lambda n, k=key: getattr(fits[n].rate_state, k))
        else:
            inputs[key] = base[key]
    for key in ("zone_width", "rupture_length", "seismogenic_depth", "density", "shear_wave_speed"):
        inputs[key] = coords.get(key, values.get(key, {"density": 2700.0}.get(key)))
    inputs["plate_rate"] = coords.get("slip_rate", values.get("slip_rate"))
    if "shear_modulus" in coords:
        inputs["shear_modulus"] = coords["shear_modulus"]
    elif fits and all(choice.shear_modulus is not None for choice in fits.values()):
        inputs["shear_modulus"] = _category_table(coords["fit"], lambda n: fits[n].shear_modulus)
    else:
        modulus = values.get("shear_modulus", base_modulus)
        if modulus is None:
            raise InputError(f"{scene.name} gives no shear modulus (nor does a fit or lithology); give "
                             "shear_modulus in [fault] or sweep it")
        inputs["shear_modulus"] = modulus
    if "normal_stress" in coords or "shear_stress" in coords:
        inputs["normal_stress"] = coords.get("normal_stress", coords.get("shear_stress") / inputs["mu0"]
                                             if "shear_stress" in coords else None)
    elif "normal_stress" in values:
        inputs["normal_stress"] = values["normal_stress"]
    else:
        inputs["normal_stress"] = values["shear_stress"] / inputs["mu0"]
    for key in ("rupture_length", "seismogenic_depth", "shear_wave_speed"):
        if inputs[key] is None:
            del inputs[key]
    return inputs


def normal_stress_input(inputs, varying, given, fault):
    """Effective normal stress: varying normal or shear stress (sigma_n = tau / mu_so), else the base scene's.

    ``varying`` maps swept (or per-segment, per-cell) names to their values; a shear stress is
    divided by ``inputs["mu_so"]``, which itself may vary by lithology.
    """
    if "normal_stress" in varying:
        return varying["normal_stress"]
    if "shear_stress" in varying:
        return varying["shear_stress"] / inputs["mu_so"]
    if "shear_stress" in given:
        return to_si(given["shear_stress"], "pressure", "shear stress") / inputs["mu_so"]
    return fault.effective_normal_stress


def _lab_inputs(study, coords):

    scene_lab = dict(study.scene.tables["lab"])
    base = get_preset(scene_lab["preset"])
    inputs = {}
    if "preset" in coords:
        chosen = {n: get_preset(n) for n in _labels(coords["preset"])}
        for key in ("mu_so", "mu_m", "b", "d"):
            inputs[key] = _category_table(coords["preset"], lambda n, k=key: getattr(chosen[n].require_stick_slip(), k))
        inputs["normal_load"] = coords.get("normal_load", _category_table(coords["preset"], lambda n: chosen[n].normal_load))
        inputs["stiffness"] = coords.get("stiffness", _category_table(coords["preset"], lambda n: chosen[n].stiffness))
    else:
        law = base.require_stick_slip()
        for key in ("mu_so", "mu_m", "b", "d"):
            inputs[key] = getattr(law, key)
        inputs["normal_load"] = coords.get("normal_load", to_si(scene_lab["normal_load"], "force", "normal load")
                                           if "normal_load" in scene_lab else base.normal_load)
        inputs["stiffness"] = coords.get("stiffness", to_si(scene_lab["stiffness"], "stiffness", "stiffness")
                                         if "stiffness" in scene_lab else base.stiffness)
    inputs["damping_ratio"] = coords.get("damping_ratio", to_si(scene_lab.get("damping_ratio", 0.0), "dimensionless", "damping ratio"))
    inputs["kinetic_slope"] = coords.get("kinetic_slope", to_si(scene_lab["kinetic_slope"], "slowness", "kinetic slope")
                                         if "kinetic_slope" in scene_lab else 0.0)
    if "loading_rate" in coords:
        inputs["loading_rate"] = coords["loading_rate"]
    elif "platform_speed" in coords:
        inputs["loading_rate"] = inputs["stiffness"] * coords["platform_speed"] / inputs["normal_load"]
    elif "loading_rate" in scene_lab:
        inputs["loading_rate"] = to_si(scene_lab["loading_rate"], "rate", "loading rate")
    else:
        inputs["loading_rate"] = inputs["stiffness"] * to_si(scene_lab["platform_speed"], "speed", "platform speed") \
            / inputs["normal_load"]
    return inputs


# --- evaluation ---------------------------------------------------------------


def _labelled(value) -> bool:
    """Whether ``value`` is an xarray DataArray, without importing xarray (nothing is one before it is
    imported): a closed-form sweep computes its blocks in numpy and never needs xarray's 0.4 s import."""
    xarray = sys.modules.get("xarray")
    return xarray is not None and isinstance(value, xarray.DataArray)


def _ufunc(function, *args, dtype=float):
    """apply_ufunc for an elementwise numpy kernel: labels kept, dask chunks processed in parallel."""
    if not any(_labelled(a) for a in args):
        return function(*args)
    import xarray as xr  # heavy: imported where used

    return xr.apply_ufunc(function, *args, dask="parallelized", output_dtypes=[dtype])


def _eps_c(zeta):

    return np.asarray(critical_dimensionless_rate(np.asarray(zeta, dtype=float)), dtype=float)


def _critical_rate(z_value, mu_so, mu_m, b, d):

    return np.asarray(solve_rate_law_critical(z_value, mu_so, mu_m, b, d), dtype=float)


def evaluate(inputs: dict, kind: str, method: str = "auto", tolerance: float = 1e-6, outside: str = "refuse"):
    """All study outputs from the inputs of :func:`study_inputs` (labelled; lazy if chunked).

    Cells with mu_m >= mu_so (no stick-slip to predict; ``faultslip fault`` refuses them) are
    refused with an :class:`InputError` (``outside="refuse"``, studies), or, with
    ``outside="flag"`` (maps, where one creeping segment must not stop the map), carry NaN
    outputs, regime and method -1, and the flag ``outside_domain`` = 1.

    Parameter-level quantities (stiffness, damping ratio, eps_c, the critical rate) are computed
    on the small dimensions they depend on; the grid-sized work is one call of :func:`cell_kernel`
    through :func:`xarray.apply_ufunc` (``dask="parallelized"``).
    """
    mu_so, mu_m, b, d = (inputs[k] for k in ("mu_so", "mu_m", "b", "d"))
    if kind == "fault":
        stiffness = inputs["shear_modulus"] / inputs["zone_width"]
        load = inputs["normal_stress"]
        drive = inputs["slip_rate"]
        mass = inputs["density"] * inputs["zone_width"]
        wave_speed = inputs["shear_wave_speed"]
        if wave_speed is None:  # the medium's own c_s = sqrt(G / rho) (faultslip.fault.scaling.shear_wave_speed)
            wave_speed = np.sqrt(inputs["shear_modulus"] / inputs["density"])
        radiation = (inputs["shear_modulus"] / (2 * wave_speed)) if inputs["radiation_damping"] else 0.0
        zeta = inputs["damping_ratio"] + radiation / (2 * np.sqrt(stiffness * mass))
        has_moment = not _is_nan(inputs["rupture_length"]) and not _is_nan(inputs["seismogenic_depth"])
        moment_factor = (inputs["shear_modulus"] * inputs["rupture_length"] * inputs["seismogenic_depth"]
                         if has_moment else np.nan)
    else:
        stiffness, load, drive = inputs["stiffness"], inputs["normal_load"], inputs["loading_rate"]
        mass = load / STANDARD_GRAVITY
        zeta = inputs["damping_ratio"] + inputs["kinetic_slope"] * load / (2 * np.sqrt(stiffness * mass))
        has_moment, moment_factor = False, np.nan
    # on the parameter dimensions only (small): refuse or flag the cells that fault would refuse
    # labelled inputs (maps, lazy studies) or numpy arrays already aligned on the study's axes
    # (``study_inputs(..., aligned=True)``, the in-memory fast path): the same arithmetic serves both
    labelled = any(_labelled(v) for v in inputs.values())
    if labelled:
        import xarray as xr  # heavy: imported where used (labelled inputs: maps and lazy studies)
    no_excess = None
    if outside == "refuse":
        pair = xr.broadcast(xr.DataArray(mu_so), xr.DataArray(mu_m)) if labelled else (mu_so, mu_m)
        ranges.check_friction_drop(*(_small_values(v) for v in pair), "in some cells of the study")
    elif labelled:
        no_excess = ~(xr.DataArray(mu_so) > xr.DataArray(mu_m))
        if bool(no_excess.any()):
            mu_m = xr.where(no_excess, 0.5 * xr.DataArray(mu_so), mu_m)  # a stand-in, masked below
        else:
            no_excess = None
    else:
        no_excess = ~np.greater(mu_so, mu_m)
        if no_excess.any():
            mu_m = np.where(no_excess, 0.5 * np.asarray(mu_so), mu_m)  # a stand-in, masked below
        else:
            no_excess = None
    zeta_values = _small_values(zeta)
    if np.any(np.abs(zeta_values) >= 1):
        raise InputError("the damping ratio of some cells reaches |zeta| >= 1 (no oscillating slip phase); "
                         "narrow the sweep of damping_ratio")
    omega_n = np.sqrt(stiffness / mass)
    eps_c = _ufunc(_eps_c, zeta)
    critical_rate = _ufunc(_critical_rate, omega_n * eps_c, mu_so, mu_m, b, d)
    args = [stiffness, load, drive, omega_n, zeta, eps_c, critical_rate, mu_so, mu_m, b, d, moment_factor]
    options = dict(drive_is_rate=kind == "lab", method=method, tolerance=tolerance)
    dtypes = [np.int8 if name in ("regime", "method") else float for name in KERNEL_OUTPUTS]
    if labelled and any(_labelled(a) for a in args):
        results = xr.apply_ufunc(cell_kernel, *args, kwargs=options, output_core_dims=[[]] * len(KERNEL_OUTPUTS),
                                 dask="parallelized", output_dtypes=dtypes)
    else:
        results = cell_kernel(*args, **options)
    outputs = dict(zip(KERNEL_OUTPUTS, results))
    if not has_moment:
        del outputs["seismic_moment"], outputs["moment_magnitude"]
    else:  # the empirical expectation beside the prediction (W&C 1994, strike-slip: the seed's faults)
        outputs.update(empirical.gridded(outputs["slip_per_event"], outputs["moment_magnitude"],
                                         inputs["rupture_length"]))
    if no_excess is not None:
        where = xr.where if labelled else np.where
        for name, value in outputs.items():
            fill = -1 if name in ("regime", "method") else np.nan
            outputs[name] = where(no_excess, fill, value).astype(value.dtype)
        flag = no_excess.astype(np.int8)
        outputs["outside_domain"] = (xr.broadcast(flag, outputs["regime"])[0] if labelled
                                     else np.broadcast_to(flag, np.shape(outputs["regime"])))
    return outputs


def _small_values(value):
    """The numpy values of a parameter-level quantity (computing it if dask-backed)."""
    if _labelled(value):
        return np.asarray(value.compute().values if _is_lazy(value) else value.values, dtype=float)
    return np.asarray(value, dtype=float)


def _is_lazy(value):
    return _labelled(value) and value.chunks is not None


def _is_nan(value):
    return value is None or (np.ndim(value) == 0 and isinstance(value, float) and math.isnan(value))


OUTPUT_ATTRS = {
    "slip_per_event": ("m", "slip per event: relative sliding in the event, integral of u dt = V T (0 without "
                       "stick-slip)"),
    "recurrence_period": ("s", "recurrence period (cycle period; NaN without stick-slip)"),
    "loading_rate": ("1/s", "loading rate theta_dot = K V / W"),
    "static_friction": ("1", "static friction mu_s at the loading rate (seed 003 eq. 2-18)"),
    "stress_drop": ("Pa", "stress drop (force drop in N for a lab study)"),
    "critical_loading_rate": ("1/s", "exact critical loading rate theta_c (inf without damping)"),
    "estimated_relative_error": ("1", "estimated relative error of the method used"),
    "dimensionless_rate": ("1", "eps = theta_dot / (omega_n (mu_s - mu_m))"),
    "seismic_moment": ("N m", "seismic moment M0 = G L H alpha"),
    "moment_magnitude": ("1", "moment magnitude Mw = (2/3)(log10 M0 - 9.1), M0 in N m"),
    **empirical.GRIDDED_ATTRS,
}


def _flags(codes: dict) -> dict:
    return {"flag_values": np.array(list(codes.values()), dtype=np.int8), "flag_meanings": " ".join(codes), "units": "1"}


def as_dataset(outputs: dict, study, block=None):
    """Outputs broadcast over every swept dimension of the study (or ``block``), with CF attributes.

    A swept parameter that no output depends on (the shear-wave speed without radiation damping)
    still labels every output, so the file has the grid the study asked for.
    """
    import xarray as xr  # heavy: imported where used

    arrays = {}
    for name, value in outputs.items():
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
    for name in dataset.data_vars:
        dataset[name].attrs = output_attrs(name, study.kind, "outside_domain" in dataset.data_vars)
    return dataset


def output_attrs(name: str, kind: str, outside_domain: bool = False) -> dict:
    """CF attributes of one study output (``kind`` is fault, lab, rate_state or fault_2d).

    ``outside_domain``: the study has cells without a prediction, flagged -1 in regime and method
    and explained by the ``outside_domain`` variable; -1 is then one of the ``flag_values``."""
    if kind == "rate_state":
        return _rate_state_attrs(name)
    if kind == "fault_2d":
        unit, long_name = FAULT_2D_OUTPUTS[name]
        return {"units": unit, "long_name": long_name}
    if name in ("regime", "method"):
        codes = {**({"no_prediction": -1} if outside_domain else {}),
                 **(REGIME_CODES if name == "regime" else METHOD_CODES)}
        long_name = ("regime (stick-slip, steady sliding, growing oscillation)" if name == "regime"
                     else "method used in this cell")
        if outside_domain:
            long_name += "; -1: no prediction, the variable outside_domain says why"
        return {"long_name": long_name, **_flags(codes)}
    if name == "outside_domain":
        return {"long_name": "cell outside the model's domain (no prediction)",
                **_flags({"predicted": 0, "no_static_excess_mu_m_not_below_mu_so": 1}),
                "comment": "faultslip fault refuses such inputs: with mu_m >= mu_so there is no "
                           "stick-slip to predict (seed 003 eq. 2-18)"}
    unit, long_name = OUTPUT_ATTRS[name]
    if name == "stress_drop" and kind == "lab":
        unit, long_name = "N", "force drop K (x_break - x_restick)"
    return {"units": unit, "long_name": long_name}


def _rate_state_attrs(name: str) -> dict:
    if name == "regime":
        return {"long_name": "regime: stick-slip (K < K_c), stable sliding (K >= K_c), velocity strengthening "
                             "(b <= a), or slow or creeping (K < K_c, yet no slip faster than 1 mm/s in the run)",
                **_flags(RATE_STATE_REGIME_CODES)}
    if name == "method":
        return {"long_name": "method of this cell: the closed form (K / K_c only), the cycles' integrator, or "
                             "solver_failed (outputs NaN; try method lsoda or dopri5, or a tighter tolerance)",
                **_flags(RATE_STATE_METHOD_CODES)}
    unit, long_name = RATE_STATE_OUTPUT_ATTRS[name]
    return {"units": unit, "long_name": long_name}


def _block_dataset(outputs: dict, study, block=None):
    """A Dataset from numpy outputs on the study's axes (``study_inputs(..., aligned=True)``), every output over every dimension.

    The same dataset :func:`as_dataset` builds from labelled outputs, built from variables
    directly: an output constant along a swept dimension is a broadcast view, not a copy.
    """
    import xarray as xr  # heavy: imported where used

    order = list(study.dims)
    coords = {name: _coordinate(study, name, values, None if block is None else block.get(name, slice(None)))
              for name, values in study.dims.items()}
    shape = tuple(coords[name].size for name in order)
    coords = {name: coordinate.variable for name, coordinate in coords.items()}
    variables = {}
    for name, value in outputs.items():
        if name in coords:  # a swept input that is also an output (loading_rate): the coordinate holds it
            coords[name].attrs = output_attrs(name, study.kind)
        else:
            variables[name] = xr.Variable(order, np.broadcast_to(value, shape),
                                          output_attrs(name, study.kind, "outside_domain" in outputs), fastpath=True)
    return xr.Dataset(variables, coords=coords)


def block_arrays(study, block) -> dict:
    """The data variables of :func:`compute_block` as numpy arrays over the block, dimensions in the study's
    order: what a sweep's worker encodes. The closed form skips the Dataset (its coordinates' indexes cost
    45 ms a block, a fifth of the block's work); an output constant over the block stays a broadcast view."""
    order = list(study.dims)
    if study.kind in ("rate_state", "fault_2d") or _needs_simulation(study):
        dataset = compute_block(study, block)
        return {name: dataset[name].transpose(*order).values for name in dataset.data_vars}
    outputs = evaluate(study_inputs(study, block, aligned=True), study.kind, study.method, study.tolerance)
    shape = tuple(len(study.dims[name][block.get(name, slice(None))]) for name in order)
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
    """The layout of the study's outputs, from one cell: computed, except for a 2-D fault, whose cell is
    minutes of work, so its layout is its variables' own. A closed-form study's needs no xarray."""
    first = {n: slice(0, 1) for n in study.dims}
    if study.kind == "fault_2d":
        outputs = {name: np.full((1,) * len(study.dims), np.nan) for name in FAULT_2D_OUTPUTS}
    elif study.kind == "rate_state" or _needs_simulation(study):
        dataset = compute_block(study, first)
        return StudyLayout({name: OutputLayout(variable.dtype, dict(variable.attrs))
                            for name, variable in dataset.data_vars.items()})
    else:
        outputs = evaluate(study_inputs(study, first, aligned=True), study.kind, study.method, study.tolerance)
    flagged = "outside_domain" in outputs
    return StudyLayout({name: OutputLayout(np.asarray(value).dtype, output_attrs(name, study.kind, flagged))
                        for name, value in outputs.items() if name not in study.dims})


#: A 2-D fault cell's outputs: name -> (units, long name).
FAULT_2D_OUTPUTS = {
    "recurrence_interval": ("s", "recurrence interval of system-size events (the last; NaN if fewer than two)"),
    "recurrence_spread": ("1", "relative spread of the last three intervals (settled where <= 1e-3)"),
    "settled": ("1", "1 where the sequence has settled (periodic to 1e-3), 0 where it has not"),
    "slip_per_event": ("m", "surface slip of the last system-size event"),
    "mean_slip_per_event": ("m", "slip of the last system-size event, mean over the velocity-weakening width"),
    "moment_per_length": ("N", "seismic moment per metre along strike of the last system-size event"),
    "events": ("1", "events in the run (peak slip rate above 1e-3 m/s)"),
    "peak_slip_rate": ("m/s", "largest slip rate in the run"),
    "nucleation_size": ("m", "h* = (pi/2) G D_c b / (sigma_n (b - a)^2)"),
    "plate_slip_balance": ("1", "slip per cycle at the shallowest station / (V_pl T)"),
    "steps": ("1", "Dormand-Prince steps taken"),
}


def _fault_2d_block(study, block):
    """One 2-D fault run per cell, each checkpointed in ``study.work_dir`` (a resumed study continues a
    cell where it stopped); the result of a cell does not depend on the block or the worker."""
    import xarray as xr  # heavy: imported where used

    coords = {name: _coordinate(study, name, values, None if block is None else block.get(name, slice(None)))
              for name, values in study.dims.items()}
    names = list(coords)
    grids = xr.broadcast(*coords.values()) if coords else []
    shape = grids[0].shape if coords else ()
    flat = [np.asarray(g.values).ravel() for g in grids]
    outputs = {name: np.full(int(np.prod(shape)) if shape else 1, np.nan) for name in FAULT_2D_OUTPUTS}
    for cell in range(flat[0].size if flat else 1):
        values = {name: flat[k][cell] for k, name in enumerate(names)}
        scene = study.scene.with_values(**values)
        folder = None
        if study.work_dir is not None:
            key = hashlib.sha256(repr(sorted((n, float(v)) for n, v in values.items())).encode()).hexdigest()[:16]
            folder = Path(study.work_dir) / key
        resume = folder is not None and (folder / "checkpoint.npz").is_file()
        run = scene.run(folder=folder, resume=resume)
        summary = summarise_fault_2d(run)
        row = {"recurrence_interval": summary.recurrence_interval, "recurrence_spread": summary.recurrence_spread,
               "settled": float(summary.settled), "slip_per_event": summary.surface_slip_per_event,
               "mean_slip_per_event": summary.mean_slip_per_event, "moment_per_length": summary.moment_per_length,
               "events": float(summary.events), "peak_slip_rate": summary.peak_slip_rate,
               "nucleation_size": scene.fault.nucleation_size(),
               "plate_slip_balance": summary.plate_slip_balance_surface, "steps": float(run.steps)}
        for name, value in row.items():
            outputs[name][cell] = value if value is not None and math.isfinite(value) else np.nan
    return _block_dataset({name: values.reshape(shape) for name, values in outputs.items()}, study, block)


def compute_block(study, block=None):
    """The study outputs on one block (name -> slice of each swept dimension), computed in memory."""
    if study.kind == "fault_2d":
        return _fault_2d_block(study, block)
    if study.kind == "rate_state":
        outputs = rate_state_cells(**study_inputs(study, block, aligned=True), cycles=study.cycles,
                                   method=study.method, tolerance=study.tolerance)
        return _block_dataset(outputs, study, block)
    if _needs_simulation(study):
        return _simulated_block(study, block)
    outputs = evaluate(study_inputs(study, block, aligned=True), study.kind, study.method, study.tolerance)
    return _block_dataset(outputs, study, block)


#: cells whose K / K_c a rate-and-state study's time estimate computes (a strided sample of the grid)
_COST_SAMPLE = 20_000


def _rate_state_cell_seconds(study) -> float:
    """Seconds per cell of a rate-and-state study: its unstable fraction (closed form, on a strided sample)
    times the cycles' measured cost."""
    steps = {name: 1 for name in study.dims}
    sizes = {name: len(values) for name, values in study.dims.items()}

    def sampled():
        return math.prod(-(-sizes[n] // steps[n]) for n in sizes)

    while sampled() > _COST_SAMPLE:
        widest = max(sizes, key=lambda n: -(-sizes[n] // steps[n]))
        steps[widest] *= 2
    block = {name: slice(None, None, step) for name, step in steps.items()}
    ratio = rate_state_cells(**study_inputs(study, block, aligned=True))["stiffness_ratio"]
    return (estimated_seconds(ratio, study.cycles, study.tolerance, study.method) / max(ratio.size, 1)
            + 1.0 / budget.STUDY_CELL_RATE)


def _needs_simulation(study) -> bool:
    return bool(study.scene.tables.get("friction"))


def _simulated_block(study, block):
    """Cells whose friction has no closed form: one event-driven simulation per cell (vectorize)."""
    import xarray as xr  # heavy: imported where used


    coords = {name: _coordinate(study, name, values, None if block is None else block.get(name, slice(None)))
              for name, values in study.dims.items()}
    names = list(coords)

    def cell(*values):
        system = _cell_system(study, dict(zip(names, values)))
        solution = solve(system, tolerance=study.tolerance, cycles=400)
        c = solution.cycle
        method = ("quasi_harmonic_averaging" if solution.method == "quasi_harmonic_averaging" else "event_driven")
        return (c.slip_per_event if c.regime != "steady_sliding" else 0.0, c.period, system.loading_rate,
                c.static_friction, c.stress_drop if c.regime != "steady_sliding" else 0.0,
                REGIME_CODES.get(c.regime, 3), solution.estimated_relative_error, METHOD_CODES[method])

    grids = xr.broadcast(*coords.values()) if coords else []
    results = np.vectorize(cell, otypes=[float] * 8)(*[g.values for g in grids]) if coords else cell()
    shape = grids[0].shape if coords else ()
    dims = grids[0].dims if coords else ()
    keys = ["slip_per_event", "recurrence_period", "loading_rate", "static_friction", "stress_drop", "regime",
            "estimated_relative_error", "method"]
    outputs = {k: xr.DataArray(np.asarray(v).reshape(shape), dims=dims, coords={n: coords[n] for n in dims})
               for k, v in zip(keys, results)}
    outputs["regime"] = outputs["regime"].astype(np.int8)
    outputs["method"] = outputs["method"].astype(np.int8)  # per cell: averaging where auto chose it
    return as_dataset(outputs, study)


def _cell_system(study, values):
    """The SliderSystem of one grid cell (for friction laws that need simulation)."""

    scene = parse_scene(study.scene.text, source=study.scene.name)
    table = scene.tables[scene.kind]
    kinds = parameters_for(study.kind)
    for name, value in values.items():
        if kinds[name][0] == "category":
            table["lithology" if study.kind == "fault" else "preset"] = str(value)
        else:
            table[name] = f"{float(value)!r} {kinds[name][1]}" if kinds[name][1] not in (None, "1") else float(value)
    if study.kind == "lab" and "loading_rate" in values:
        table.pop("platform_speed", None)
    if study.kind == "lab" and "platform_speed" in values:
        table.pop("loading_rate", None)
    system = scene.slider()
    return apply_friction(system, {}, scene.name)


def sweep(scene, method: str = "auto", tolerance: float = 1e-6, chunks: dict | None = None,
          allow_large: bool = False, cycles: int = 0, **dims):
    """Python API: sweep parameters of a scene; returns an xarray Dataset.

    ``scene`` is a Scene, a scene file or a bundled scene name; each keyword is a parameter name
    with a list of values with units (strings or pint Quantities), or category names. With
    ``chunks`` (dimension -> chunk size) the result is dask-backed and lazy. A scene with
    rate-and-state friction sweeps a, b, critical_slip, evolution, fit and the fault's quantities;
    ``cycles`` > 0 simulates that many cycles in every unstable cell (``method``: auto, lsoda, dopri5, dopri5_compiled).

    >>> sweep("san_andreas_1906.toml", slip_rate=["10 mm/yr", "35 mm/yr"], lithology=["granodiorite", "pyrite"])
    >>> sweep("san_andreas_1906_rate_state.toml", critical_slip=["10 um", "1 mm", "8 mm"], cycles=3)
    """

    if not isinstance(scene, (Scene, Fault2DScene)):
        document = scene_document(scene)
        scene = load_fault_2d_scene(scene) if is_fault_2d_document(document) else load_scene(scene)
    kind = study_kind(scene)
    allowed = parameters_for(kind)
    parsed = {}
    for name, values in dims.items():
        if name not in allowed:
            hint = did_you_mean(name, allowed, n=3)
            raise InputError(f"unknown parameter {name!r}{hint} (a {kind.replace('_', '-')} study sweeps: "
                             f"{', '.join(allowed)})")
        values = values if isinstance(values, dict) else list(values) if not isinstance(values, (str, bytes)) else [values]
        unit_kind = allowed[name][0]
        parsed[name] = (_categories(name, values, kind, name) if unit_kind == "category"
                        else _values(name, values, unit_kind, name))
    _check_consistent(scene, parsed, "sweep()")
    _method_and_cycles(kind, method, cycles, "sweep():")
    if not isinstance(tolerance, (int, float)) or isinstance(tolerance, bool) or not 0 < tolerance < 1:
        raise InputError(f"tolerance must be a number between 0 and 1, got {tolerance!r}")
    study = Study(name=scene.name, scene=scene, dims=parsed, method=method, tolerance=tolerance,
                  text=_study_text(scene, method, tolerance, dims, cycles), cycles=cycles)
    if chunks is None:  # everything in memory: refuse what will not fit (a chunked study stays lazy)

        estimate = budget.study_estimate(study, None, 1, study.size)
        budget.check(budget.Estimate(f"this in-memory sweep of {study.size:.3g} cells", memory=estimate.memory,
                                     seconds=estimate.seconds), allow_large)
        return finish(compute_block(study), study)
    if kind == "rate_state":
        return finish(as_dataset(rate_state_outputs(study_inputs(study, chunks=chunks), study), study), study)
    outputs = evaluate(study_inputs(study, chunks=chunks), study.kind, method, tolerance)
    return finish(as_dataset(outputs, study), study)


def rate_state_outputs(inputs, study) -> dict:
    """:func:`rate_state_cells` through :func:`xarray.apply_ufunc`: labelled, and lazy where inputs are chunked."""
    import xarray as xr  # heavy: imported where used

    inputs = {**inputs, "evolution": evolution_codes(inputs["evolution"])}
    keys = list(inputs)
    names = output_names(study.cycles, "rupture_length" in inputs and "seismogenic_depth" in inputs)
    options = dict(cycles=study.cycles, method=study.method, tolerance=study.tolerance)

    def kernel(*arrays):
        result = rate_state_cells(**dict(zip(keys, arrays)), **options)
        return tuple(result[name] for name in names)

    dtypes = [np.int8 if name in ("regime", "method") else float for name in names]
    results = xr.apply_ufunc(kernel, *(inputs[key] for key in keys), output_core_dims=[[]] * len(names),
                             dask="parallelized", output_dtypes=dtypes)
    return dict(zip(names, results))


def _study_text(scene, method, tolerance, dims, cycles: int = 0) -> str:

    def literal(value):
        if isinstance(value, str):
            return '"' + value.replace('"', '\\"') + '"'
        if is_quantity(value):
            return f'"{value.magnitude!r} {value.units:~}"'
        return repr(float(value))

    lines = ["[study]", f'name = {literal(scene.name)}', f'base = {literal(scene.path.name if scene.path else scene.name)}',
             f'method = "{method}"', f"tolerance = {tolerance!r}"] + ([f"cycles = {cycles}"] if cycles else []) + ["", "[sweep]"]
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
        "method_requested": study.method,
        "tolerance": study.tolerance,
        "comment": "regime and method are flags (see flag_meanings); categorical dimensions are strings",
    })
    if study.description:
        dataset.attrs["summary"] = study.description
    return dataset
