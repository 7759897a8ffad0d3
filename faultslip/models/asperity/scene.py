"""Asperity scenes (seed 004, Bengisu & Akay): ``[friction] law = "asperity"``.

::

    name = "seed 004 Table I case 6 at v_c1"
    [slider]
    mass = "10 kg"
    natural_frequency = "10 Hz"      # f0 = sqrt(K/M) / 2 pi
    dashpot = "2 kg/s"               # C (200 kg/s suppresses stick-slip)
    platform_speed = "3.6 mm/s"
    [friction]
    law = "asperity"
    slope_std = 0.1                  # s, rad
    shear_strength = "9.8 MPa"       # tau (0 with pressure_coefficient 0: no adhesion)
    pressure_coefficient = 0.075     # beta
    composite_modulus = "77.8 GPa"
    asperity_radius = "60 um"        # r: Hertz and the contact density
    slope_radius = "120 um"          # rho of eq. (27)
    loss_factor = "200 N*s/m"        # eta
    contact_length = "0.1 um"        # alpha = 1/(gamma pi r): the contact-density choice
    slope_cutoff = "1 nm"
    initial_approach = "0.3 um"
    summit_exchange = true
    [run]
    duration = "6 s"
    [method]
    name = "auto"                    # auto | asperity_wavelength | asperity_quasistatic | asperity_LSODA
    tolerance = 0.05

``table_case = 6`` in ``[friction]`` starts from a Table I case. Units are optional (SI otherwise).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from faultslip.models.asperity.dynamics import METHODS, AsperityModel
from faultslip import ranges
from faultslip.errors import InputError
from faultslip.fault.scene import has_friction_law, load_law_scene
from faultslip.io.resources import check_toml_layout, parse_toml
from faultslip.units import to_si_scalar

_SLIDER = {"mass": "mass", "natural_frequency": "frequency", "dashpot": "damping", "platform_speed": "speed"}
_FRICTION = {"slope_std": "dimensionless", "shear_strength": "pressure", "pressure_coefficient": "dimensionless",
             "composite_modulus": "pressure", "asperity_radius": "length", "slope_radius": "length",
             "loss_factor": "damping", "contact_length": "length", "slope_cutoff": "length",
             "initial_approach": "length"}
_DEFAULT_UNITS = {"mass": "kg", "frequency": "Hz", "damping": "N*s/m", "speed": "m/s", "pressure": "Pa",
                  "length": "m", "dimensionless": None, "time": "s"}


def parse_asperity_scene(text: str, source: str = "<scene>") -> tuple[AsperityModel, dict, dict]:
    """(model, run settings with the method, notes) from scene TOML."""
    data = parse_toml(text, source)
    check_toml_layout(data, {"slider": set(_SLIDER), "friction": {"law", "table_case", "summit_exchange", *_FRICTION},
                             "run": {"duration"}, "method": {"name", "tolerance"}, "sources": None},
                      source, "an asperity scene")
    friction = data.get("friction", {})
    if friction.get("law") != "asperity":
        raise InputError(f"[friction] in {source} needs law = \"asperity\" for an asperity scene, "
                         f"got {friction.get('law')!r}")
    case = friction.get("table_case")
    if case is not None and (isinstance(case, bool) or case not in range(1, 9)):
        raise InputError(f"[friction] table_case in {source} must be a Table I case from 1 to 8, got {case!r}")
    values = {}
    for table, keys in (("slider", _SLIDER), ("friction", _FRICTION)):
        for key, kind in keys.items():
            if key in data.get(table, {}):
                values[key] = to_si_scalar(data[table][key], kind, f"[{table}] {key} in {source}",
                                           _DEFAULT_UNITS[kind])
    exchange = friction.get("summit_exchange", True)
    if not isinstance(exchange, bool):
        raise InputError(f"[friction] summit_exchange in {source} must be true or false, got {exchange!r}")
    values["summit_exchange"] = exchange
    name = str(data.get("name", Path(source).stem))
    base = AsperityModel.table_case(case) if case is not None else AsperityModel()
    model = replace(base, name=name, **values)
    duration = to_si_scalar(data.get("run", {}).get("duration", 6.0), "time", f"[run] duration in {source}", "s")
    if not 0.01 <= duration <= 600:
        raise InputError(f"[run] duration in {source} must be from 0.01 s to 600 s, got {duration:g} s")
    method = data.get("method", {})
    name_ = method.get("name", "auto")
    if name_ not in ("auto", *METHODS):
        raise InputError(f"[method] name in {source} must be one of auto, {', '.join(METHODS)}, got {name_!r}")
    tolerance = ranges.check_tolerance(method.get("tolerance", 0.05), f"[method] in {source}")
    notes = {"name": name, "description": str(data.get("description", ""))}
    return model, {"duration": duration, "method": name_, "tolerance": float(tolerance)}, notes


def load_asperity_scene(path):
    return load_law_scene(path, "asperity scene", parse_asperity_scene)


def is_asperity_scene(argument) -> bool:
    """Whether a scene argument names a asperity scene (``[friction] law = "asperity"``); False for anything unreadable,
    which the seed-law scene reader then reports."""
    return has_friction_law(argument, "asperity")
