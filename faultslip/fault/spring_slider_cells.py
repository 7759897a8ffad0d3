"""The spring-slider family's sweep: seed 003's closed form over a block of fault or laboratory cells, the
event-driven simulation where a friction law has no closed form, and rate-and-state K / K_c (and cycles)
where the scene's [friction] law is "rate_state"."""

from __future__ import annotations

import math
import sys

import numpy as np

from faultslip import ranges
from faultslip.contract.cells import aligned, evaluate_by_cell, labelled
from faultslip.contract.specs import Output, flags_attrs, parameters
from faultslip.dynamics.kernel import KERNEL_OUTPUTS, METHOD_CODES, REGIME_CODES, cell_kernel
from faultslip.dynamics.methods import solve
from faultslip.dynamics.spring_slider.critical import critical_dimensionless_rate, solve_rate_law_critical
from faultslip.errors import InputError
from faultslip.fault import empirical
from faultslip.fault.rate_state_cells import METHOD_CODES as RATE_STATE_METHOD_CODES
from faultslip.fault.rate_state_cells import OUTPUT_ATTRS as RATE_STATE_OUTPUT_ATTRS
from faultslip.fault.rate_state_cells import REGIME_CODES as RATE_STATE_REGIME_CODES
from faultslip.fault.rate_state_cells import (check_cycle_method, check_friction, estimated_seconds,
                                              evolution_codes, friction_ratio, output_names, rate_state_cells)
from faultslip.fault.scene import apply_friction, parse_scene
from faultslip.friction.materials import get_preset, resolve_material
from faultslip.friction.rate_state import EVOLUTION_LAWS
from faultslip.io import budget
from faultslip.units import STANDARD_GRAVITY, to_si, to_si_scalar

#: Sweepable parameters: name -> (unit kind, SI unit, long name). "category" is a string dimension.
FAULT_TABLE = {
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
FAULT_PARAMETERS = parameters(FAULT_TABLE, "fault")
LAB_PARAMETERS = parameters({
    "preset": ("category", None, "Table I preset"),
    "platform_speed": ("speed", "m/s", "platform speed V"),
    "loading_rate": ("rate", "1/s", "loading rate theta_dot = K V / W"),
    "damping_ratio": ("dimensionless", "1", "damping ratio of the dashpot"),
    "kinetic_slope": ("slowness", "s/m", "slope beta of the linear kinetic law"),
    "normal_load": ("force", "N", "normal load W"),
    "stiffness": ("stiffness", "N/m", "stiffness K"),
}, "lab")
#: a fault whose base scene has rate-and-state friction ([friction] law = "rate_state")
RATE_STATE_PARAMETERS = parameters({
    "fit": ("category", None, "saved rate-and-state fit (faultslip fit --law rate-state --name)"),
    "evolution": ("category", None, "state evolution law (aging or slip)"),
    "a": ("dimensionless", "1", "rate-and-state direct effect a"),
    "b": ("dimensionless", "1", "rate-and-state evolution effect b"),
    "critical_slip": ("length", "m", "critical slip distance D_c"),
    "mu0": ("dimensionless", "1", "reference friction mu0 at V0"),
    "reference_speed": ("speed", "m/s", "reference speed V0"),
    **{name: FAULT_TABLE[name] for name in ("shear_modulus", "zone_width", "normal_stress", "slip_rate",
                                                  "rupture_length", "seismogenic_depth", "density",
                                                  "shear_wave_speed")},
    "shear_stress": ("pressure", "Pa", "shear stress tau (sigma_n = tau / mu0)"),
})
#: [study] method: the seed law's methods, and the cycle methods of a rate-and-state study
SEED_METHODS = ("auto", "closed_form", "exact_cycle")


def _method_and_cycles(kind, method, cycles, where):
    """Validate [study] method and cycles (or sweep()'s) for a study of this kind."""
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


def _check_consistent(scene, dims, source):
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


def _labels(coordinate) -> list:
    """The category names along a categorical coordinate (labelled or aligned numpy)."""
    return [str(v) for v in np.ravel(np.asarray(coordinate, dtype=object))]


def _loaded_xarray():
    """xarray where this process has loaded it, else None: a labelled coordinate exists only where it has, and a
    streamed sweep's numpy blocks need no 0.3 s import to learn that they are not labelled."""
    return sys.modules.get("xarray")


def _category_table(coordinate, getter):
    """Values over a categorical dimension from a per-category lookup (None -> NaN), shaped like ``coordinate``."""
    xr = _loaded_xarray()
    values = [getter(name) for name in _labels(coordinate)]
    data = np.array([np.nan if v is None else v for v in values], dtype=float)
    if xr is None or not isinstance(coordinate, xr.DataArray):  # aligned numpy: the same axes as the coordinate
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
    xr = _loaded_xarray()
    data = np.array([getter(name) for name in _labels(coordinate)], dtype=object)
    if xr is None or not isinstance(coordinate, xr.DataArray):
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


#: a closed-form sweep computes its blocks in numpy and never needs xarray's 0.4 s import
_labelled = labelled


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
    always = outside == "flag_all"  # every block of a study with some such cells carries the flag
    if always:
        outside = "flag"
    if outside == "refuse":
        pair = xr.broadcast(xr.DataArray(mu_so), xr.DataArray(mu_m)) if labelled else (mu_so, mu_m)
        ranges.check_friction_drop(*(_small_values(v) for v in pair), "in some cells of the study")
    elif labelled:
        no_excess = ~(xr.DataArray(mu_so) > xr.DataArray(mu_m))
        if bool(no_excess.any()):
            mu_m = xr.where(no_excess, 0.5 * xr.DataArray(mu_so), mu_m)  # a stand-in, masked below
        elif not always:
            no_excess = None
    else:
        no_excess = ~np.greater(mu_so, mu_m)
        if no_excess.any():
            mu_m = np.where(no_excess, 0.5 * np.asarray(mu_so), mu_m)  # a stand-in, masked below
        elif not always:
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


#: The axes the seed law's friction pair (mu_so, mu_m) can vary on in a study.
FRICTION_AXES = ("lithology", "mu_so", "mu_m")


def _study_friction(study, kind: str):
    """(mu_so, mu_m) of every cell of a study, broadcast over the axes they vary on (:data:`FRICTION_AXES`)."""
    axes = [name for name in FRICTION_AXES if name in study.dims]
    coords = {}  # aligned numpy over the friction axes (xarray's constructors would import dask)
    for k, name in enumerate(axes):
        shape = [1] * len(axes)
        shape[k] = len(study.dims[name])
        coords[name] = np.array(study.dims[name], dtype=object if name == "lithology" else float).reshape(shape)
    inputs = (_fault_inputs if kind == "fault" else _lab_inputs)(study, coords)
    return tuple(np.broadcast_arrays(np.asarray(inputs["mu_so"], dtype=float), np.asarray(inputs["mu_m"], dtype=float)))


def _cells_without_excess(study, kind: str):
    """Whether a study's cells lack a static excess (mu_m >= mu_so): "all", "some" or None; computed once a
    study (it decides whether every block carries the outside_domain flag)."""
    cached = study.__dict__.get("_without_excess", ())
    if cached != ():
        return cached
    so, m = _study_friction(study, kind)
    bad = ~(so > m)
    answer = "all" if bad.all() else "some" if bad.any() else None
    study.__dict__["_without_excess"] = answer
    return answer


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


_flags = flags_attrs


def output_attrs(name: str, kind: str, outside_domain: bool = False) -> dict:
    """CF attributes of one study output (``kind`` is fault or lab).

    ``outside_domain``: the study has cells without a prediction, flagged -1 in regime and method
    and explained by the ``outside_domain`` variable; -1 is then one of the ``flag_values``."""
    if kind == "rate_state":
        return _rate_state_attrs(name)
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


class RateStateOutput(Output):
    """An output of :func:`rate_state_cells` as a study declares it: its flags keep their codes (solver_failed
    is -1), which :class:`Output`'s enumeration would renumber."""

    @property
    def dtype(self):
        return np.dtype(np.int8) if self.name in ("regime", "method") else np.dtype(float)

    def attrs(self) -> dict:
        return _rate_state_attrs(self.name)


def _rate_state_has_moment(study) -> bool:
    """Whether a rate-and-state study's cells have a rupture length and a seismogenic depth (so a moment)."""
    values, _ = study.scene.rate_state_fault_values(require_modulus=False)
    return all(key in study.dims or values.get(key) is not None for key in ("rupture_length", "seismogenic_depth"))


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
    values = aligned(study.dims, RATE_STATE_PARAMETERS, block)
    inputs = rate_state_inputs(study, values)
    ratio = rate_state_cells(**inputs)["stiffness_ratio"]
    return (estimated_seconds(ratio, friction_ratio(inputs, ratio.shape), study.cycles, study.tolerance,
                              study.method) / max(ratio.size, 1)
            + 1.0 / budget.STUDY_CELL_RATE)


def _needs_simulation(scene) -> bool:
    return bool(scene.tables.get("friction"))


#: what a simulated cell reports (friction laws without a closed form: one event-driven run per cell)
_SIMULATED = ("slip_per_event", "recurrence_period", "loading_rate", "static_friction", "stress_drop", "regime",
              "estimated_relative_error", "method")


def _simulated(study, values):
    """Cells whose friction has no closed form: one event-driven simulation per cell."""
    outputs = {name: Output(name, "1", name, flags=("x",) if name in ("regime", "method") else ())
               for name in _SIMULATED}  # types and fills only; the attributes are output_attrs'

    def cell(**inputs):
        system = _cell_system(study, inputs)
        solution = solve(system, tolerance=study.tolerance, cycles=400)
        c = solution.cycle
        method = ("quasi_harmonic_averaging" if solution.method == "quasi_harmonic_averaging" else "event_driven")
        slipping = c.regime != "steady_sliding"
        return dict(zip(_SIMULATED, (c.slip_per_event if slipping else 0.0, c.period, system.loading_rate,
                                     c.static_friction, c.stress_drop if slipping else 0.0,
                                     REGIME_CODES.get(c.regime, 3), solution.estimated_relative_error,
                                     METHOD_CODES[method])))

    return evaluate_by_cell(values, outputs, cell)


def _cell_system(study, values):
    """The SliderSystem of one grid cell (for friction laws that need simulation)."""
    scene = parse_scene(study.scene.text, source=study.scene.name)
    table = scene.tables[scene.kind]
    kinds = FAULT_PARAMETERS if scene.kind == "fault" else LAB_PARAMETERS
    for name, value in values.items():
        if kinds[name].is_category:
            table["lithology" if scene.kind == "fault" else "preset"] = str(value)
        else:
            table[name] = kinds[name].toml_value(value)
    if scene.kind == "lab" and "loading_rate" in values:
        table.pop("platform_speed", None)
    if scene.kind == "lab" and "platform_speed" in values:
        table.pop("loading_rate", None)
    system = scene.slider()
    return apply_friction(system, {}, scene.name)


def rate_state_outputs(inputs, study) -> dict:
    """:func:`rate_state_cells` through :func:`xarray.apply_ufunc`: labelled, and lazy where inputs are chunked; a
    streamed block's aligned numpy inputs straight through the kernel, as apply_ufunc would pass them."""
    inputs = {**inputs, "evolution": evolution_codes(inputs["evolution"])}
    keys = list(inputs)
    names = output_names(study.cycles, "rupture_length" in inputs and "seismogenic_depth" in inputs)
    options = dict(cycles=study.cycles, method=study.method, tolerance=study.tolerance)

    def kernel(*arrays):
        result = rate_state_cells(**dict(zip(keys, arrays)), **options)
        return tuple(result[name] for name in names)

    xr = _loaded_xarray()
    if xr is None or not any(isinstance(inputs[key], xr.DataArray) for key in keys):
        return dict(zip(names, kernel(*(inputs[key] for key in keys))))
    dtypes = [np.int8 if name in ("regime", "method") else float for name in names]
    results = xr.apply_ufunc(kernel, *(inputs[key] for key in keys), output_core_dims=[[]] * len(names),
                             dask="parallelized", output_dtypes=dtypes)
    return dict(zip(names, results))



def scene_kind(scene) -> str:
    """fault, lab, or rate_state (a fault scene with rate-and-state friction)."""
    return "rate_state" if scene.rate_state else scene.kind


class SpringSliderCells:
    """The seed law's sweep (:class:`faultslip.contract.cells.Cells`), vectorised over a block; and, as
    :data:`RATE_STATE_CELLS`, a fault scene's with ``[friction] law = "rate_state"`` (the older form of the
    rate-and-state slider's scenes): K / K_c in closed form and cycles where asked, vectorised too."""

    checkpoints = False
    default_tolerance = 1e-6

    def __init__(self, label: str = "a spring-slider study"):
        self.label = label

    def parameters(self, scene) -> dict:
        return {"fault": FAULT_PARAMETERS, "lab": LAB_PARAMETERS, "rate_state": RATE_STATE_PARAMETERS}[scene_kind(scene)]

    def category(self, scene, name: str, value: str, where: str) -> str:
        return _category_name(name, value, scene_kind(scene), where)

    def check(self, study, where: str, source: str) -> None:
        _method_and_cycles(scene_kind(study.scene), study.method, study.cycles, where)
        _check_consistent(study.scene, study.dims, source)
        kind = scene_kind(study.scene)
        if kind != "rate_state" and _cells_without_excess(study, kind) == "all":
            ranges.check_friction_drop(*_study_friction(study, kind), f"in every cell of {source}")

    def outputs(self, study):
        if scene_kind(study.scene) == "rate_state":  # declared, so a run to a file integrates no cell twice
            return {name: RateStateOutput(name, *RATE_STATE_OUTPUT_ATTRS.get(name, ("1", name)))
                    for name in output_names(study.cycles, _rate_state_has_moment(study))}
        return None  # the seed law's depend on its friction (flagged cells where some have no excess): a cell says

    def attrs(self, name: str, study, flagged: bool = False) -> dict:
        kind = scene_kind(study.scene)
        return _rate_state_attrs(name) if kind == "rate_state" else output_attrs(name, kind, flagged)

    def seconds_per_cell(self, study) -> float:
        if scene_kind(study.scene) == "rate_state" and study.cycles:
            return _rate_state_cell_seconds(study)
        simulated = scene_kind(study.scene) != "rate_state" and _needs_simulation(study.scene)
        return 1.0 / (budget.SIMULATED_CELL_RATE if simulated else budget.STUDY_CELL_RATE)

    def imports(self, study) -> tuple:
        """What its cells import where they run: a rate-and-state block's cycles their integrators (and the
        linear algebra of their implicit steps); a lab slider that is simulated, the integrators; the closed
        forms, nothing."""
        if scene_kind(study.scene) == "rate_state":
            return (*budget.INTEGRATION_IMPORTS, "scipy.linalg") if study.cycles else ()
        return budget.INTEGRATION_IMPORTS if _needs_simulation(study.scene) else ()

    def counted(self, study) -> bool:
        kind = scene_kind(study.scene)
        return (kind == "rate_state" or _needs_simulation(study.scene)
                or _cells_without_excess(study, kind) is not None)  # its flagged cells are said

    def evaluate(self, study, values: dict) -> dict:
        kind = scene_kind(study.scene)
        if kind == "rate_state":
            inputs = rate_state_inputs(study, values)
            if any(_labelled(v) for v in inputs.values()):
                return rate_state_outputs(inputs, study)
            return rate_state_cells(**inputs, cycles=study.cycles, method=study.method, tolerance=study.tolerance)
        if _needs_simulation(study.scene):
            return _simulated(study, values)
        inputs = (_fault_inputs if kind == "fault" else _lab_inputs)(study, values)
        # a study whose friction leaves some cells without a static excess flags those cells, every block alike
        outside = "flag_all" if _cells_without_excess(study, kind) else "refuse"
        return evaluate(inputs, kind, study.method, study.tolerance, outside=outside)


CELLS = SpringSliderCells()
#: the same engine on a rate-and-state fault scene of the older form (the rate-and-state slider's family)
RATE_STATE_CELLS = SpringSliderCells("a rate-and-state study")


def read_scene(text: str, source: str, path=None):
    """A seed-law or rate-and-state scene file, as a study's base."""
    return parse_scene(text, source=source, path=path)
