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

The area depends on the speed alone (the addendum's "simple interpolation on a fixed curve"), so this
is a kinetic law mu(u) and the slider runs on seed 003's engine: stick, break-away at
K x = W mu_s, slip under mu(u), through the method interface (``auto`` takes an event-driven
integrator for this nonlinear law). Chapter 5's earlier variant, where the surfaces stay apart
through the deceleration, depends on the slip's history, and is not built.
"""

from __future__ import annotations

import numpy as np

from pathlib import Path

from faultslip.dynamics.slider import SliderSystem
from faultslip.errors import InputError
from faultslip.fault.scene import read_text_file, resolve_path, scene_document
from faultslip.friction.laws import CallableKinetic, ConstantStatic
from faultslip.io.resources import check_toml_layout, parse_toml
from faultslip.lab.surfaces import Surface, gaussian_surface, read_surface, truncation_contact
from faultslip.units import to_si


def bearing_curve(surface: Surface, points: int = 80) -> tuple[np.ndarray, np.ndarray]:
    """(compression in m, real / nominal area) of the surface against its inverted copy, from first touch to
    the approach where a fifth of the area is in contact (the range a sliding contact visits)."""
    rms = float(np.std(surface.height))
    approaches = np.linspace(0.0, 6.0 * rms, points)
    contact = truncation_contact(surface, approaches)
    fraction = contact["area"] / contact["nominal_area"]
    return approaches, fraction


def rough_surface_law(surface: Surface, normal_load: float, hardness: float, shear_strength: float,
                      separation_coefficient: float, nominal_area: float = 1e-6):
    """(static law, kinetic law, details) of seed 000's model on ``surface`` (see the module)."""
    for label, value in (("normal load", normal_load), ("hardness", hardness), ("shear strength", shear_strength),
                         ("nominal area", nominal_area)):
        if not (np.isfinite(value) and value > 0):
            raise InputError(f"the {label} must be positive, got {value!r}")
    if not (np.isfinite(separation_coefficient) and separation_coefficient >= 0):
        raise InputError(f"the separation coefficient c must be >= 0 (s/m), got {separation_coefficient!r}")
    compression, fraction = bearing_curve(surface)
    needed = normal_load / (hardness * nominal_area)  # the real-area fraction that carries the load plastically
    if not fraction[-1] >= needed:
        raise InputError(f"the load needs {needed:.3g} of the nominal area in contact, more than the surface reaches "
                         f"({fraction[-1]:.3g}); raise the hardness or the nominal area")
    rising = np.maximum.accumulate(fraction)
    h0 = float(np.interp(needed, rising + 1e-15 * np.arange(rising.size), compression))  # H A(h0) = L
    rms = float(np.std(surface.height))
    scale = shear_strength * nominal_area / normal_load

    def friction(sliding_speed):
        compressed = h0 - separation_coefficient * rms * np.abs(np.asarray(sliding_speed, dtype=float))
        return scale * np.interp(compressed, compression, fraction, left=0.0)

    static = scale * needed  # = p_s / H: the area that carries the load, sheared
    details = {"compression_at_rest": h0, "area_fraction_at_rest": needed, "static_friction": static,
               "rms": rms, "separation_per_speed": separation_coefficient * rms}
    return ConstantStatic(static), CallableKinetic(friction, "rough surface (seed 000)"), details


def rough_surface_slider(surface: Surface, mass: float, stiffness: float, normal_load: float, platform_speed: float,
                         hardness: float, shear_strength: float, separation_coefficient: float,
                         nominal_area: float = 1e-6, name: str = "rough-surface slider") -> tuple[SliderSystem, dict]:
    """Seed 000's apparatus on seed 003's slider engine: mass M, spring K, load L, drive V0."""
    static, kinetic, details = rough_surface_law(surface, normal_load, hardness, shear_strength,
                                                 separation_coefficient, nominal_area)
    system = SliderSystem(mass=mass, stiffness=stiffness, normal_load=normal_load, platform_speed=platform_speed,
                          static_law=static, kinetic_law=kinetic, name=name)
    details["natural_frequency"] = float(np.sqrt(stiffness / mass) / (2 * np.pi))
    return system, details


_SLIDER = {"mass": "mass", "stiffness": "stiffness", "normal_load": "force", "platform_speed": "speed"}
_FRICTION = {"law": None, "surface": None, "synthetic": None, "synthetic_size": None, "synthetic_seed": None,
             "hardness": "pressure", "shear_strength": "pressure", "separation_coefficient": "slowness",
             "nominal_area": None}


def parse_rough_scene(text: str, source: str = "<scene>", base_dir=None) -> tuple[SliderSystem, dict, dict]:
    """(slider, details, settings) of a rough-surface scene::

        [slider]   mass, stiffness, normal_load, platform_speed (with units)
        [friction] law = "rough_surface"; surface = "map.csv" or synthetic = ["3.26 um", "60 um"]
                   (synthetic_size, synthetic_seed); hardness, shear_strength, separation_coefficient ("0.8 s/m"),
                   nominal_area ("1 mm^2")
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
                                           name=str(data.get("name", Path(source).stem)))
    cycles = data.get("simulation", {}).get("cycles", 8)
    if not isinstance(cycles, int) or isinstance(cycles, bool) or not 1 <= cycles <= 10_000:
        raise InputError(f"[simulation] cycles in {source} must be a whole number from 1 to 10000")
    return system, details, {"cycles": cycles}


def load_rough_scene(path):
    path, _ = resolve_path(path, "rough-surface scene")
    return parse_rough_scene(read_text_file(path, "rough-surface scene"), path.name, base_dir=path.parent)


def is_rough_scene(argument) -> bool:
    """Whether a scene argument names a rough-surface scene (``[friction] law = "rough_surface"``)."""
    friction = (scene_document(argument) or {}).get("friction")
    return isinstance(friction, dict) and friction.get("law") == "rough_surface"
