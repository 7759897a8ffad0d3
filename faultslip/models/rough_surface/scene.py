"""Seed 000's sliding model: friction from the real contact of two rough surfaces that separate as they slide.

The revised model of seed 000's addendum (AD1.3):

- The surfaces are pressed together until all-plastic contact carries the load,
  H A(h0) = L, where A(h) is the bearing area at compression h. A(h) comes from the surface map,
  truncated against its inverted copy (:func:`faultslip.lab.surfaces.truncation_contact`).
- Sliding at relative speed u separates them by c sigma u (sigma the RMS roughness; the seed's c has
  units of s/m, "the gradient when multiplied by the RMS surface roughness"). So the real area is
  A(h0 - c sigma u).
- Friction is the junctions' shear strength times the real area: mu(u) = p_s A(h0 - c sigma u) / L.
  At rest this is mu_s = p_s / H, and it falls with speed as the surfaces part. That velocity
  weakening drives the stick-slip.

With ``memory = "none"`` the area depends on the speed alone (the addendum's "simple interpolation
on a fixed curve"): a kinetic law mu(u) on seed 003's engine, stick, break-away at K x = W mu_s,
slip under mu(u), through the method interface (``auto`` takes an event-driven integrator).

Chapter 5's runs (its figs. 5.9-5.24) kept the surfaces apart through the deceleration until they
came to rest (``memory = "held"``), and there c scaled the static compression h0 instead of the RMS
(its eq. 27: ``separation_reference = "static_compression"``). Chapter 4 suggests the surfaces fall
back by inertia (``memory = "falling"`` at ``fall_acceleration``). Both depend on the slip's
history; the engine integrates them in sub-phases split at the peak sliding speed
(:class:`faultslip.friction.laws.SeparatingSurfacesKinetic`).
"""

from __future__ import annotations

import hashlib
import threading
from pathlib import Path

import numpy as np

from faultslip.dynamics.spring_slider.simulate import simulate
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.contract.scenes import scene_source
from faultslip.errors import InputError, SolverError
from faultslip.io.resources import resolve_path, scene_document
from faultslip.friction.laws import (SEPARATION_MEMORIES, STANDARD_GRAVITY, ConstantStatic,
                                     SeparatingSurfacesKinetic)
from faultslip.io.resources import check_toml_layout, parse_toml
from faultslip.lab.surfaces import Surface, gaussian_surface, read_surface, truncation_contact
from faultslip.units import takes_units, to_si


#: Bearing curves computed in this process, by their surface's heights, spacing and points: a study's cells share
#: one surface, and its truncation (80 labelled contact maps) cost each cell, and each cell's estimate, ~0.1 s.
_BEARING_CURVES: dict = {}
BEARING_CURVES_KEPT = 8
_BEARING_LOCK = threading.Lock()  # a lazy study's cells may run on dask's threads


def bearing_curve(surface: Surface, points: int = 80) -> tuple[np.ndarray, np.ndarray]:
    """(compression in m, real / nominal area) of the surface against its inverted copy, from first touch to
    the approach where a fifth of the area is in contact (the range a sliding contact visits).

    Parameters
    ----------
    surface : Surface
        The surface, heights in m.
    points : int
        Approaches from 0 to 6 RMS heights.

    Returns
    -------
    tuple of numpy.ndarray
        (compression in m, real / nominal area), read-only: a surface's curve is computed once per process.
    """
    height = np.ascontiguousarray(surface.height)
    key = (hashlib.blake2b(height.tobytes(), digest_size=16).hexdigest(), height.shape, surface.dx, surface.dy,
           int(points))
    with _BEARING_LOCK:
        kept = _BEARING_CURVES.get(key)
    if kept is not None:
        return kept
    rms = float(np.std(height))
    approaches = np.linspace(0.0, 6.0 * rms, points)
    contact = truncation_contact(surface, approaches)
    fraction = contact["area"] / contact["nominal_area"]
    for array in (approaches, fraction):
        array.setflags(write=False)
    with _BEARING_LOCK:
        while len(_BEARING_CURVES) >= BEARING_CURVES_KEPT:
            _BEARING_CURVES.pop(next(iter(_BEARING_CURVES)))
        _BEARING_CURVES[key] = (approaches, fraction)
    return approaches, fraction


SEPARATION_REFERENCES = ("rms", "static_compression")


def rough_surface_law(surface: Surface, normal_load: float, hardness: float, shear_strength: float,
                      separation_coefficient: float, nominal_area: float = 1e-6, memory: str = "none",
                      fall_acceleration: float = STANDARD_GRAVITY, separation_reference: str = "rms"):
    """(static law, kinetic law, details) of seed 000's model on ``surface`` (see the module).

    The separation per sliding speed is c times the RMS roughness (AD1.3, ``separation_reference =
    "rms"``) or c times the static compression h0 (chapter 5 eq. 27, ``"static_compression"``).
    """
    for label, value in (("normal load", normal_load), ("hardness", hardness), ("shear strength", shear_strength),
                         ("nominal area", nominal_area)):
        if not (np.isfinite(value) and value > 0):
            raise InputError(f"the {label} must be positive, got {value!r}")
    if not (np.isfinite(separation_coefficient) and separation_coefficient >= 0):
        raise InputError(f"the separation coefficient c must be >= 0 (s/m), got {separation_coefficient!r}")
    if separation_reference not in SEPARATION_REFERENCES:
        raise InputError(f"unknown separation reference {separation_reference!r}; allowed: "
                         f"{', '.join(SEPARATION_REFERENCES)}")
    if memory not in SEPARATION_MEMORIES:
        raise InputError(f"unknown separation memory {memory!r}; allowed: {', '.join(SEPARATION_MEMORIES)}")
    compression, fraction = bearing_curve(surface)
    needed = normal_load / (hardness * nominal_area)  # the real-area fraction that carries the load plastically
    if not fraction[-1] >= needed:
        raise InputError(f"the load needs {needed:.3g} of the nominal area in contact, more than the surface reaches "
                         f"({fraction[-1]:.3g}); raise the hardness or the nominal area")
    rising = np.maximum.accumulate(fraction)
    h0 = float(np.interp(needed, rising + 1e-15 * np.arange(rising.size), compression))  # H A(h0) = L
    rms = float(np.std(surface.height))
    scale = shear_strength * nominal_area / normal_load
    reference = rms if separation_reference == "rms" else h0

    def friction_at_separation(separation):
        return scale * np.interp(h0 - np.asarray(separation, dtype=float), compression, fraction, left=0.0)

    kinetic = SeparatingSurfacesKinetic(friction_at_separation, separation_coefficient * reference, memory,
                                        fall_acceleration, f"rough surface (seed 000, separation {memory})")
    static = scale * needed  # = p_s / H: the area that carries the load, sheared
    details = {"compression_at_rest": h0, "area_fraction_at_rest": needed, "static_friction": static,
               "rms": rms, "separation_per_speed": separation_coefficient * reference,
               "separation_memory": memory, "separation_reference": separation_reference}
    return ConstantStatic(static), kinetic, details


@takes_units(
    mass="mass", stiffness="stiffness", normal_load="force", platform_speed="speed", hardness="pressure",
    shear_strength="pressure", separation_coefficient="slowness", nominal_area="area",
    fall_acceleration="acceleration")
def rough_surface_slider(surface: Surface, mass: float, stiffness: float, normal_load: float, platform_speed: float,
                         hardness: float, shear_strength: float, separation_coefficient: float,
                         nominal_area: float = 1e-6, name: str = "rough-surface slider", *, memory: str = "none",
                         fall_acceleration: float = STANDARD_GRAVITY,
                         separation_reference: str = "rms") -> tuple[SliderSystem, dict]:
    """Seed 000's apparatus on seed 003's slider engine: mass M, spring K, load L, drive V0.

    Parameters
    ----------
    surface : Surface
        The surfaces' heights.
    mass : float
        M (kg).
    stiffness : float
        K (N/m).
    normal_load : float
        L (N).
    platform_speed : float
        V0 (m/s).
    hardness : float
        H (Pa).
    shear_strength : float
        Shear strength of the junctions (Pa).
    separation_coefficient : float
        c (s/m).
    nominal_area : float
        A_n (m^2).
    name : str
        A name for reports.
    memory : str
        none, held or falling: the separation after the fastest moment of a slip.
    fall_acceleration : float
        m/s^2, with ``memory = "falling"``.
    separation_reference : str
        rms or h0.

    Returns
    -------
    tuple
        (the SliderSystem, its details: static friction, area fraction, compression in m, ...).
    """
    static, kinetic, details = rough_surface_law(surface, normal_load, hardness, shear_strength,
                                                 separation_coefficient, nominal_area, memory, fall_acceleration,
                                                 separation_reference)
    system = SliderSystem(mass=mass, stiffness=stiffness, normal_load=normal_load, platform_speed=platform_speed,
                          static_law=static, kinetic_law=kinetic, name=name)
    details["natural_frequency"] = float(np.sqrt(stiffness / mass) / (2 * np.pi))
    return system, details


def separation_history(dataset, kinetic) -> np.ndarray:
    """The surfaces' separation h(t) (m) along a simulated record (seed 000's fig. 5.20).

    Zero while stuck; in each slip phase h = k_h abs(u) up to the phase's fastest moment so far, then
    as the law's memory says (:meth:`SeparatingSurfacesKinetic.separation_after_peak`), from the
    running peak of the sliding speed and the time since it.

    Parameters
    ----------
    dataset : xarray.Dataset
        A rough-surface simulation.
    kinetic : SeparatingSurfacesKinetic
        The slider's kinetic law.

    Returns
    -------
    ndarray
        h(t) (m).
    """
    sliding = np.abs(np.asarray(dataset["sliding_speed"].values, dtype=float))
    times = np.asarray(dataset["time"].values, dtype=float)
    slipping = np.asarray(dataset["phase"].values) == 1
    separation = np.zeros_like(sliding)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], slipping.astype(np.int8), [0]])))
    for start, stop in zip(edges[::2], edges[1::2]):
        speed = sliding[start:stop]
        peak = np.maximum.accumulate(speed)
        when = times[start:stop][np.maximum.accumulate(np.where(speed >= peak, np.arange(speed.size), 0))]
        if kinetic.memory == "none":
            separation[start:stop] = kinetic.separation(speed)
        else:
            separation[start:stop] = [kinetic.separation_after_peak(p, t - w, u)
                                      for p, t, w, u in zip(peak, times[start:stop], when, speed)]
    return separation


def separation_sweep(surface: Surface, *, mass: float, stiffness: float, normal_load: float, platform_speed: float,
                     hardness: float, shear_strength: float, coefficients, memories=("none", "held"),
                     separation_reference: str = "rms", fall_acceleration: float = STANDARD_GRAVITY,
                     nominal_area: float = 1e-6, cycles: int = 6, rtol: float = 1e-8):
    """Stick-slip against the separation coefficient c and the separation memory (seed 000 figs. 5.9-5.14).

    Returns an xarray Dataset on (memory, separation_coefficient): the limit cycle's peak-to-peak
    amplitude, that amplitude over the break-away displacement W mu_s / K ("almost equal to the
    total displacement", seed 000 §5.5), the lowest displacement (negative: the slider overshoots
    its unloaded position), slip duration, peak sliding speed, peak separation, the friction's lowest
    value in slip, and the regime. A cell the engine cannot finish holds NaN and its reason.
    """
    import xarray as xr  # heavy: imported where used

    coefficients = np.asarray(coefficients, dtype=float)
    if coefficients.ndim != 1 or coefficients.size == 0 or not np.all(np.isfinite(coefficients) & (coefficients >= 0)):
        raise InputError("the separation coefficients must be a non-empty list of numbers >= 0")
    memories = tuple(memories)
    names = ("amplitude", "relative_amplitude", "lowest_displacement", "slip_duration", "peak_slip_speed",
             "peak_separation", "lowest_friction")
    values = {name: np.full((len(memories), coefficients.size), np.nan) for name in names}
    regimes = np.full((len(memories), coefficients.size), "", dtype=object)
    for i, memory in enumerate(memories):
        for j, coefficient in enumerate(coefficients):
            system, details = rough_surface_slider(surface, mass, stiffness, normal_load, platform_speed, hardness,
                                                   shear_strength, float(coefficient), nominal_area, memory=memory,
                                                   fall_acceleration=fall_acceleration,
                                                   separation_reference=separation_reference)
            try:
                record = simulate(system, cycles=cycles, slip_solver="DOP853", rtol=rtol)
            except SolverError as error:
                regimes[i, j] = f"failed: {error}"
                continue
            regimes[i, j] = record.attrs["regime"]
            if record.sizes["event"] == 0:
                continue
            last = record.isel(event=-1)
            settled = record["time"] >= float(last["event_time"])  # the last cycle: break-away to its end
            cycle = record.where(settled, drop=True)
            breakaway = normal_load * details["static_friction"] / stiffness
            values["amplitude"][i, j] = float(last["amplitude"])
            values["relative_amplitude"][i, j] = float(last["amplitude"]) / breakaway
            values["lowest_displacement"][i, j] = float(cycle["displacement"].min())
            values["slip_duration"][i, j] = float(last["slip_duration"])
            values["peak_slip_speed"][i, j] = float(last["peak_slip_speed"])
            values["peak_separation"][i, j] = float(np.max(separation_history(record, system.kinetic_law)))
            values["lowest_friction"][i, j] = float(cycle["friction_coefficient"].where(cycle["phase"] == 1).min())
    units = {"amplitude": "m", "relative_amplitude": "1", "lowest_displacement": "m", "slip_duration": "s",
             "peak_slip_speed": "m s-1", "peak_separation": "m", "lowest_friction": "1"}
    coords = {"memory": list(memories),
              "separation_coefficient": ("separation_coefficient", coefficients,
                                         {"units": "s m-1", "long_name": f"c (separation = c {separation_reference} |u|)"})}
    data = {name: (("memory", "separation_coefficient"), values[name], {"units": units[name]}) for name in names}
    data["regime"] = (("memory", "separation_coefficient"), regimes.astype(str))
    return xr.Dataset(data, coords=coords, attrs={"source": "faultslip.models.rough_surface.scene.separation_sweep (seed 000 §5.5)",
                                                  "separation_reference": separation_reference})


_SLIDER = {"mass": "mass", "stiffness": "stiffness", "normal_load": "force", "platform_speed": "speed"}
_FRICTION = {"law": None, "surface": None, "synthetic": None, "synthetic_size": None, "synthetic_seed": None,
             "hardness": "pressure", "shear_strength": "pressure", "separation_coefficient": "slowness",
             "nominal_area": None, "separation_memory": None, "separation_reference": None,
             "fall_acceleration": "acceleration"}


def parse_rough_scene(text: str, source: str = "<scene>", base_dir=None) -> tuple[SliderSystem, dict, dict]:
    """(slider, details, settings) of a rough-surface scene::

        [slider]   mass, stiffness, normal_load, platform_speed (with units)
        [friction] law = "rough_surface"; surface = "map.csv" or synthetic = ["3.26 um", "60 um"]
                   (synthetic_size, synthetic_seed); hardness, shear_strength, separation_coefficient ("0.8 s/m"),
                   nominal_area ("1 mm^2"); separation_memory = "none" (AD1.3), "held" (chapter 5) or
                   "falling" (with fall_acceleration, default "9.80665 m/s^2"); separation_reference = "rms"
                   (AD1.3) or "static_compression" (chapter 5 eq. 27)
        [simulation] cycles
    """
    data = parse_toml(text, source)
    check_toml_layout(data, {"slider": set(_SLIDER), "friction": set(_FRICTION), "simulation": {"cycles"},
                             "sources": None}, source, "a rough-surface scene")
    friction = data.get("friction", {})
    if friction.get("law") != "rough_surface":
        raise InputError(f"[friction] in {source} needs law = \"rough_surface\"")
    slider = data.get("slider", {})
    missing = [key for key in _SLIDER if key not in slider] + [key for key in ("hardness", "shear_strength",
                                                                             "separation_coefficient")
                                                                if key not in friction]
    if missing:
        raise InputError(f"{source} needs {', '.join(missing)} (with units)")
    values = {key: to_si(slider[key], kind, f"[slider] {key}") for key, kind in _SLIDER.items()}
    law = {key: to_si(friction[key], _FRICTION[key], f"[friction] {key}")
           for key in ("hardness", "shear_strength", "separation_coefficient")}
    area = to_si(friction.get("nominal_area", "1 mm^2"), "area", "[friction] nominal_area")
    choices = {}
    for key, allowed in (("separation_memory", SEPARATION_MEMORIES), ("separation_reference", SEPARATION_REFERENCES)):
        value = friction.get(key, allowed[0])
        if value not in allowed:
            raise InputError(f"[friction] {key} in {source} must be one of {', '.join(map(repr, allowed))}, "
                             f"got {value!r}")
        choices[key] = value
    if "fall_acceleration" in friction and choices["separation_memory"] != "falling":
        raise InputError(f"[friction] fall_acceleration in {source} applies only with separation_memory = \"falling\"")
    fall = to_si(friction.get("fall_acceleration", f"{STANDARD_GRAVITY} m/s^2"), "acceleration",
                 "[friction] fall_acceleration")
    if ("surface" in friction) == ("synthetic" in friction):
        raise InputError(f"[friction] in {source} needs exactly one of surface (a map file) and synthetic "
                         "([rms, correlation length])")
    if "surface" in friction:
        path, _ = resolve_path(str(friction["surface"]), "surface", base_dir=base_dir)
        surface = read_surface(path).levelled()
    else:
        spec = friction["synthetic"]
        if not (isinstance(spec, list) and len(spec) == 2):
            raise InputError(f"[friction] synthetic in {source} must be [rms, correlation length], e.g. "
                             "[\"3.26 um\", \"60 um\"]")
        size, seed = friction.get("synthetic_size", 128), friction.get("synthetic_seed", 0)
        if not all(isinstance(v, int) and not isinstance(v, bool) for v in (size, seed)) or seed < 0:
            raise InputError(f"[friction] synthetic_size and synthetic_seed in {source} must be whole numbers >= 0")
        surface = gaussian_surface(to_si(spec[0], "length", "synthetic rms"), to_si(spec[1], "length",
                                                                                   "synthetic correlation length"),
                                   size=size, seed=seed)
    system, details = rough_surface_slider(surface, values["mass"], values["stiffness"], values["normal_load"],
                                           values["platform_speed"], law["hardness"], law["shear_strength"],
                                           law["separation_coefficient"], area,
                                           name=str(data.get("name", Path(source).stem)),
                                           memory=choices["separation_memory"], fall_acceleration=fall,
                                           separation_reference=choices["separation_reference"])
    cycles = data.get("simulation", {}).get("cycles", 8)
    if not isinstance(cycles, int) or isinstance(cycles, bool) or not 1 <= cycles <= 10_000:
        raise InputError(f"[simulation] cycles in {source} must be a whole number from 1 to 10000")
    return system, details, {"cycles": cycles}


def read_rough_scene(path):
    """A rough-surface scene (``[friction] law = "rough_surface"``).

    Parameters
    ----------
    path : str, path or TomlScene
        The scene.

    Returns
    -------
    tuple
        (the slider, its rough-surface details, the simulation settings).
    """
    text, source, folder, _ = scene_source(path, "rough-surface scene")
    return parse_rough_scene(text, source, base_dir=folder)


def is_rough_scene(argument) -> bool:
    """Whether a scene argument names a rough-surface scene (``[friction] law = "rough_surface"``)."""
    friction = (scene_document(argument) or {}).get("friction")
    return isinstance(friction, dict) and friction.get("law") == "rough_surface"
