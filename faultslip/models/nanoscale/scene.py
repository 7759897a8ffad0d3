"""Nanoscale scenes (seed 001's toy model): a dimensionless slider with ``[friction] law = "nanoscale"``.

::

    name = "seed 001 toy model, A = 3"
    [slider]                 # dimensionless: mass = stiffness = 1, time in 1/omega, length in the slip scale
    damping = 3.0            # A
    drive_speed = 0.02       # v_a
    [friction]
    law = "nanoscale"
    peak_speed = 0.01        # v_m: velocity weakening above it
    charging_time = 2.0      # tau
    charge_length = 1.57     # a
    charge_force = 2.56e-7   # f_ch (0: the uncharged limit)
    [run]
    duration = 3000.0        # in 1/omega
    samples = 6001
    [method]
    name = "auto"            # auto | nanoscale_linear_stability | nanoscale_LSODA
    tolerance = 1e-6         # relative, of the force swing

Every number is optional (the slides' values otherwise) except ``law``. ``faultslip run``,
``simulate`` and ``nanoscale`` take such a scene.
"""

from __future__ import annotations

import math

from pathlib import Path

from faultslip.models.nanoscale.dynamics import NANOSCALE_METHODS, NanoscaleModel
from faultslip import ranges
from faultslip.errors import InputError
from faultslip.fault.scene import has_friction_law, load_law_scene
from faultslip.io.resources import check_toml_layout, parse_toml

_SLIDER = {"damping", "drive_speed"}
_FRICTION = {"law", "peak_speed", "charging_time", "charge_length", "charge_force"}
_RUN = {"duration", "samples"}
_METHOD = {"name", "tolerance"}


def parse_nanoscale_scene(text: str, source: str = "<scene>") -> tuple[NanoscaleModel, dict, dict]:
    """(model, run settings with the method, notes) from scene TOML."""
    data = parse_toml(text, source)
    check_toml_layout(data, {"slider": _SLIDER, "friction": _FRICTION, "run": _RUN, "method": _METHOD,
                             "sources": None}, source, "a nanoscale scene")
    law = data.get("friction", {}).get("law")
    if law != "nanoscale":
        raise InputError(f"[friction] in {source} needs law = \"nanoscale\" for a nanoscale scene, got {law!r}")
    for table in ("slider", "friction", "run"):
        for key, value in data.get(table, {}).items():
            if key != "law" and (not isinstance(value, (int, float)) or isinstance(value, bool)):
                raise InputError(f"[{table}] {key} in {source} must be a number (the model is dimensionless), "
                                 f"got {value!r}")
    run = dict(data.get("run", {}))
    samples = run.get("samples", 6001)
    if not (math.isfinite(samples) and samples == int(samples) and 2 <= samples <= 10_000_000):
        raise InputError(f"[run] samples in {source} must be a whole number from 2 to 10,000,000, got {samples!r}")
    duration = run.get("duration", 3000.0)
    if not (math.isfinite(duration) and duration > 0):
        raise InputError(f"[run] duration in {source} must be a positive number (in 1/omega), got {duration!r}")
    method = dict(data.get("method", {}))
    name = method.get("name", "auto")
    if name not in NANOSCALE_METHODS:
        raise InputError(f"[method] name in {source} must be one of {', '.join(NANOSCALE_METHODS)}, got {name!r}")
    tolerance = ranges.check_tolerance(method.get("tolerance", 1e-6), f"[method] in {source}")
    settings = {"duration": float(run.get("duration", 3000.0)), "samples": int(run.get("samples", 6001)),
                "method": name, "tolerance": float(tolerance)}
    values = {**data.get("slider", {}), **{k: v for k, v in data.get("friction", {}).items() if k != "law"}}
    model = NanoscaleModel(**{key: float(value) for key, value in values.items()})
    notes = {"name": str(data.get("name", Path(source).stem)), "description": str(data.get("description", ""))}
    return model, settings, notes


def load_nanoscale_scene(path):
    return load_law_scene(path, "nanoscale scene", parse_nanoscale_scene)


def is_nanoscale_scene(argument) -> bool:
    """Whether a scene argument names a nanoscale scene (``[friction] law = "nanoscale"``); False for anything unreadable,
    which the seed-law scene reader then reports."""
    return has_friction_law(argument, "nanoscale")
