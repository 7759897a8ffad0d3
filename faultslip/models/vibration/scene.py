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
    # or a measured curve: table = [[0, 0.5], [5, 0.45], ...] with table_speed_unit = "in/s"

Unlike seed 003's slider, the mass is the beam's equivalent mass, not the normal load over g.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from faultslip.dynamics.vibration import QuasiHarmonic
from faultslip.contract.scenes import scene_source
from faultslip.errors import InputError
from faultslip.io.resources import scene_document
from faultslip.io.resources import check_toml_layout, parse_toml
from faultslip.units import to_si_scalar, unit_factor

_VIBRATION = {"mass": "mass", "stiffness": "stiffness", "damping": "damping", "normal_load": "force",
              "speed": "speed"}
_FRICTION = {"polynomial", "polynomial_speed_unit", "table", "table_speed_unit"}


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
    if ("polynomial" in friction) == ("table" in friction):
        raise InputError(f"[friction] in {source} needs exactly one of polynomial (coefficients) and table "
                         "([[speed, friction], ...])")
    unit_key = "polynomial_speed_unit" if "polynomial" in friction else "table_speed_unit"
    unit = friction.get(unit_key, "m/s")
    if not isinstance(unit, str):
        raise InputError(f"[friction] {unit_key} in {source} must be a speed unit such as \"in/s\"")
    scale = unit_factor(unit, "speed", f"[friction] {unit_key}")  # m/s per unit
    si, curve = None, None
    if "polynomial" in friction:
        coefficients = friction["polynomial"]
        if not isinstance(coefficients, list) or not coefficients or not all(
                isinstance(c, (int, float)) and not isinstance(c, bool) for c in coefficients):
            raise InputError(f"[friction] polynomial in {source} must be a list of numbers (increasing powers)")
        with np.errstate(over="ignore", invalid="ignore"):
            si = tuple(float(c) / scale ** power for power, c in enumerate(coefficients))  # c_n (s/m)^n
            swept = np.linspace(0.0, 2.0 * values["speed"], 201)  # the sliding speeds a cycle can reach
            friction_swept = np.polynomial.polynomial.polyval(swept, np.array(si))
        worst = int(np.argmax(np.where(np.isfinite(friction_swept), np.abs(friction_swept), np.inf)))
        if not all(math.isfinite(c) for c in si) or not abs(friction_swept[worst]) <= MAX_FRICTION:
            raise InputError(f"[friction] polynomial in {source} gives friction {friction_swept[worst]:.3g} at "
                             f"{swept[worst] / scale:.3g} {unit}, within the speeds a cycle sweeps (0 to twice the "
                             f"driving speed); a friction coefficient lies within +-{MAX_FRICTION:g}")
    else:
        curve = tabulated_curve(friction["table"], scale, values["speed"], source)
    name = str(data.get("name", Path(source).stem))
    system = QuasiHarmonic(values["mass"], values["damping"], values["stiffness"], values["normal_load"],
                           values["speed"], coefficients=si, friction=curve, name=name)
    sources = data.get("sources", {})
    if not isinstance(sources, dict) or not all(isinstance(v, str) for v in sources.values()):
        raise InputError(f"[sources] in {source} must map names to citation strings")
    return system, {"description": str(data.get("description", "")), **sources}


#: Largest friction coefficient a law may give over its operating speeds. Rock and metal give 0.1-1; the
#: bound is wide (Rayleigh's curve as a test oscillator reaches 16) and stops what overflows the averaging.
MAX_FRICTION = 100.0


def tabulated_curve(rows, scale: float, speed: float, source: str):
    """A measured friction-velocity curve, ``[[speed, friction], ...]`` (speeds in the unit ``scale`` m/s),
    as a C1 monotone-preserving interpolant (PCHIP) in SI; friction is held at the end values outside the
    table. The table must start at 0 and reach twice the driving speed, the sliding speeds a cycle up to
    the no-stick bound sweeps."""
    from scipy.interpolate import PchipInterpolator  # heavy: imported where used

    if not isinstance(rows, list) or len(rows) < 3 or not all(
            isinstance(r, list) and len(r) == 2 and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                                        for v in r) for r in rows):
        raise InputError(f"[friction] table in {source} must list at least 3 [speed, friction] pairs of numbers")
    table = np.array(rows, dtype=float)
    speeds, values = table[:, 0] * scale, table[:, 1]
    if not (np.all(np.isfinite(table)) and np.all(np.diff(speeds) > 0)):
        raise InputError(f"[friction] table in {source}: speeds must be finite and strictly increasing")
    if np.any(values < 0):
        raise InputError(f"[friction] table in {source}: friction must not be negative")
    if speeds[0] > 0 or speeds[-1] < 2 * speed:
        raise InputError(f"[friction] table in {source} must cover sliding speeds from 0 to twice the driving speed "
                         f"({2 * speed:.4g} m/s), the range a cycle below the no-stick bound sweeps")
    interpolant = PchipInterpolator(speeds, values)

    def curve(sliding_speed):
        return interpolant(np.clip(sliding_speed, speeds[0], speeds[-1]))

    return curve


def read_vibration_scene(path) -> tuple[QuasiHarmonic, dict]:
    """A vibration scene (seed 002's apparatus, a ``[vibration]`` table).

    Parameters
    ----------
    path : str, path or TomlScene
        The scene.

    Returns
    -------
    tuple
        (the averaged slider, the scene's notes and sources).
    """
    text, source, _, origin = scene_source(path, "vibration scene")
    system, notes = parse_vibration_scene(text, source)
    if origin:
        notes["origin"] = origin
    return system, notes


def is_vibration_scene(argument) -> bool:
    """Whether a scene argument names a vibration scene (a ``[vibration]`` table); False for anything
    unreadable, which the seed-law scene reader then reports."""
    return isinstance((scene_document(argument) or {}).get("vibration"), dict)
