"""Quasi-harmonic vibration scenes (seed 002's apparatus): a spring-mass-dashpot on a driven surface.

::

    [vibration]
    mass = "1.76 lb"               # equivalent mass M (seed 002 Appendix C)
    stiffness = "70.5 lbf/in"      # k (Appendix B)
    damping = "0.00368 lbf*s/in"   # r (Appendix C; the seed prints lb.in/sec)
    normal_load = "2 lbf"          # W
    speed = "12.5 in/s"            # driving speed v

    [friction]                     # the friction-velocity curve, increasing powers of the sliding speed
    polynomial = [0.5, -0.01, 0.0, 1.48e-5]
    polynomial_speed_unit = "in/s"

Unlike seed 003's slider, the mass is the beam's equivalent mass, not the normal load over g.
"""

from __future__ import annotations

from pathlib import Path

from faultslip.dynamics.averaging import QuasiHarmonic
from faultslip.errors import InputError
from faultslip.fault.scene import read_text_file, resolve_path
from faultslip.io.resources import check_toml_layout, parse_toml
from faultslip.units import to_si_scalar, unit_factor

_VIBRATION = {"mass": "mass", "stiffness": "stiffness", "damping": "damping", "normal_load": "force",
              "speed": "speed"}
_FRICTION = {"polynomial", "polynomial_speed_unit"}


def parse_vibration_scene(text: str, source: str = "<scene>") -> tuple[QuasiHarmonic, dict]:
    """(the averaged slider, the scene's [sources]) from scene TOML."""
    data = parse_toml(text, source)
    check_toml_layout(data, {"vibration": set(_VIBRATION), "friction": _FRICTION, "sources": None}, source,
                      "a vibration scene")
    for table in ("vibration", "friction"):
        if table not in data:
            raise InputError(f"{source} needs a [{table}] table")
    vibration = data["vibration"]
    missing = [key for key in _VIBRATION if key not in vibration and key != "damping"]
    if missing:
        raise InputError(f"[vibration] in {source} needs {', '.join(missing)}")
    values = {key: to_si_scalar(vibration.get(key, "0 N*s/m"), kind, f"[vibration] {key}")
              for key, kind in _VIBRATION.items()}
    friction = data["friction"]
    coefficients = friction.get("polynomial")
    if not isinstance(coefficients, list) or not coefficients or not all(
            isinstance(c, (int, float)) and not isinstance(c, bool) for c in coefficients):
        raise InputError(f"[friction] polynomial in {source} must be a list of numbers (increasing powers)")
    unit = friction.get("polynomial_speed_unit", "m/s")
    if not isinstance(unit, str):
        raise InputError(f"[friction] polynomial_speed_unit in {source} must be a speed unit such as \"in/s\"")
    scale = unit_factor(unit, "speed", "[friction] polynomial_speed_unit")  # m/s per unit
    si = tuple(float(c) / scale ** power for power, c in enumerate(coefficients))  # c_n (s/m)^n
    name = str(data.get("name", Path(source).stem))
    system = QuasiHarmonic(values["mass"], values["damping"], values["stiffness"], values["normal_load"],
                           values["speed"], coefficients=si, name=name)
    sources = data.get("sources", {})
    if not isinstance(sources, dict) or not all(isinstance(v, str) for v in sources.values()):
        raise InputError(f"[sources] in {source} must map names to citation strings")
    return system, {"description": str(data.get("description", "")), **sources}


def load_vibration_scene(path) -> tuple[QuasiHarmonic, dict]:
    path, origin = resolve_path(path, "vibration scene")
    system, notes = parse_vibration_scene(read_text_file(path, "vibration scene"), path.name)
    if origin:
        notes["origin"] = origin
    return system, notes
