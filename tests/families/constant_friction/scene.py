"""The constant-friction scene: its reader, its sweepable parameters and its outputs."""

from __future__ import annotations

from faultslip.contract.scenes import scene_source
from faultslip.contract.specs import Output, Parameter
from faultslip.errors import InputError
from faultslip.io.resources import check_toml_layout, parse_toml
from faultslip.units import to_si_scalar

PARAMETERS = {name: Parameter(name, kind, unit, long_name, (table, key)) for name, table, key, kind, unit, long_name in (
    ("stiffness", "slider", "stiffness", "stiffness", "N/m", "stiffness K"),
    ("normal_load", "slider", "normal_load", "force", "N", "normal load W"),
    ("mass", "slider", "mass", "mass", "kg", "mass M"),
    ("platform_speed", "slider", "platform_speed", "speed", "m/s", "platform speed V"),
    ("static_friction", "friction", "static", "dimensionless", "1", "static friction mu_s"),
    ("kinetic_friction", "friction", "kinetic", "dimensionless", "1", "kinetic friction mu_k"),
)}
OUTPUTS = {spec.name: spec for spec in (
    Output("slip_per_event", "m", "slip per event 2 (mu_s - mu_k) W / K"),
    Output("recurrence_period", "s", "recurrence period (stick plus slip)"),
    Output("regime", "1", "regime", flags=("stick_slip",)),
)}


def read(scene) -> dict:
    """The scene's inputs in SI."""
    text, source, _, _ = scene_source(scene, "constant-friction scene")
    data = parse_toml(text, source)
    check_toml_layout(data, {"slider": {"stiffness", "normal_load", "mass", "platform_speed"},
                             "friction": {"static", "kinetic"}}, source, "a constant-friction scene")
    slider, friction = data.get("slider", {}), data.get("friction", {})
    values = {name: to_si_scalar(slider[name], kind, f"[slider] {name} in {source}")
              for name, kind in (("stiffness", "stiffness"), ("normal_load", "force"), ("mass", "mass"),
                                 ("platform_speed", "speed")) if name in slider}
    if len(values) < 4:
        raise InputError(f"[slider] in {source} needs stiffness, normal_load, mass and platform_speed")
    if any(not value > 0 for value in values.values()):
        raise InputError(f"[slider] in {source}: every value must be positive")
    static, kinetic = friction.get("static"), friction.get("kinetic")
    if not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (static, kinetic)) or \
            not 0 <= kinetic < static <= 2:
        raise InputError(f"[friction] in {source} needs numbers 0 <= kinetic < static <= 2")
    return {**values, "static": float(static), "kinetic": float(kinetic)}
