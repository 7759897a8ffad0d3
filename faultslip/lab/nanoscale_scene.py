"""Nanoscale scenes (seed 001's toy model): the dimensionless parameters and the run's length.

::

    [nanoscale]          # every key optional: the slides' values otherwise
    damping = 3.0        # A
    drive_speed = 0.02   # v_a
    peak_speed = 0.01    # v_m
    charging_time = 2.0  # tau
    charge_length = 1.57 # a
    charge_force = 2.56e-7
    [run]
    duration = 3000.0    # in 1/omega
    samples = 6001
"""

from __future__ import annotations

from pathlib import Path

from faultslip.dynamics.nanoscale import SLIDES, NanoscaleModel
from faultslip.errors import InputError
from faultslip.fault.scene import read_text_file, resolve_path
from faultslip.io.resources import check_toml_layout, parse_toml

_RUN = {"duration", "samples"}


def parse_nanoscale_scene(text: str, source: str = "<scene>") -> tuple[NanoscaleModel, dict, dict]:
    """(model, run settings, notes) from scene TOML."""
    data = parse_toml(text, source)
    check_toml_layout(data, {"nanoscale": set(SLIDES), "run": _RUN, "sources": None}, source, "a nanoscale scene")
    for table in ("nanoscale", "run"):
        for key, value in data.get(table, {}).items():
            if not isinstance(value, (int, float)) or isinstance(value, bool):
                raise InputError(f"[{table}] {key} in {source} must be a number (the model is dimensionless), "
                                 f"got {value!r}")
    run = dict(data.get("run", {}))
    if "samples" in run and run["samples"] != int(run["samples"]):
        raise InputError(f"[run] samples in {source} must be a whole number")
    settings = {"duration": float(run.get("duration", 3000.0)), "samples": int(run.get("samples", 6001))}
    model = NanoscaleModel(**{key: float(value) for key, value in data.get("nanoscale", {}).items()})
    notes = {"name": str(data.get("name", Path(source).stem)), "description": str(data.get("description", ""))}
    return model, settings, notes


def load_nanoscale_scene(path):
    path, origin = resolve_path(path, "nanoscale scene")
    model, settings, notes = parse_nanoscale_scene(read_text_file(path, "nanoscale scene"), path.name)
    if origin:
        notes["origin"] = origin
    return model, settings, notes
