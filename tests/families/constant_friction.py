"""A test family: a spring-slider with constant static and kinetic friction (no rate effect, no damping).

It is the proof that a family is one module and one registry line (issue 40): ``tests/test_families.py``
declares it with :func:`faultslip.contract.declare`, and run, simulate, sweep, the CLI and the conformance
check take it with no edit anywhere in faultslip. Its physics is the undamped slider's exact cycle: the spring
loads to mu_s W, the block slides half an oscillation to the symmetric point about mu_k W, so

    slip per event = 2 (mu_s - mu_k) W / K,   recurrence = slip / V (the stick lasts slip / V, the slip pi / omega).

::

    family = "constant_friction"
    [slider]
    stiffness = "1e5 N/m"
    normal_load = "100 N"
    mass = "1 kg"
    platform_speed = "1 mm/s"
    [friction]
    static = 0.6
    kinetic = 0.5
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.contract.cells import PerCell
from faultslip.contract.registry import Family, register
from faultslip.contract.scenes import scene_source, toml_reader
from faultslip.contract.specs import Output, Parameter
from faultslip.errors import InputError
from faultslip.io.report import Report
from faultslip.io.resources import check_toml_layout, parse_toml
from faultslip.models.result import Result
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


def cycle(values: dict) -> tuple[float, float, float]:
    """(slip per event, recurrence period, slip duration) of the undamped cycle."""
    slip = 2 * (values["static"] - values["kinetic"]) * values["normal_load"] / values["stiffness"]
    slip_duration = math.pi * math.sqrt(values["mass"] / values["stiffness"])
    return slip, slip / values["platform_speed"] + slip_duration, slip_duration


def run(scene, method=None, tolerance=None) -> Result:
    if method not in (None, "auto", "closed_form"):
        raise InputError(f"a constant-friction scene runs closed_form, got {method!r}")
    values = read(scene)
    slip, period, _ = cycle(values)
    report = Report("constant friction")
    report.add("slip_per_event", slip, "m").add("recurrence_period", period, "s").add("regime", "stick_slip")
    report.add("method", "closed_form")
    return Result("constant_friction", report)


def simulate(scene, cycles=None) -> Result:
    """The sawtooth of the spring force over ``cycles`` cycles (default 3), sampled densely."""
    import xarray as xr  # heavy: imported where used

    values = read(scene)
    slip, period, slip_duration = cycle(values)
    count = cycles or 3
    time = np.linspace(0.0, count * period, 200 * count + 1)
    phase = np.mod(time, period)
    stick = period - slip_duration
    low = values["kinetic"] - (values["static"] - values["kinetic"])
    omega = math.pi / slip_duration
    ratio = np.where(phase < stick, low + (values["static"] - low) * phase / stick,
                     values["kinetic"] + (values["static"] - values["kinetic"]) * np.cos(omega * (phase - stick)))
    series = xr.Dataset({"friction": ("time", ratio, {"units": "1", "long_name": "spring force / W"})},
                        coords={"time": ("time", time, {"units": "s", "long_name": "time"})})
    report = Report("constant friction simulation")
    report.add("slip_per_event", slip, "m").add("recurrence_period", period, "s").add("cycles", count)

    def figure():
        import matplotlib.pyplot as plt  # heavy: imported where used

        fig, ax = plt.subplots()
        ax.plot(time, ratio)
        ax.set_xlabel("time (s)")
        ax.set_ylabel("spring force / W")
        return fig

    return Result("constant_friction", report, series, figure)


METHODS = [{"name": "constant_friction_closed_form", "friction_laws": "constant static and kinetic friction",
            "domain": "an undamped slider: every loading rate", "cost_model": "O(1)"}]
CELLS = PerCell("a constant-friction study", PARAMETERS, OUTPUTS, run, read, methods=("auto", "closed_form"),
                seconds=1e-4)
FAMILY = register(Family("constant_friction", "a spring-slider with constant friction (a test family)", run,
                         simulate, simulate_options=("cycles",), read_scene=toml_reader("constant_friction",
                                                                                        PARAMETERS), cells=CELLS,
                         methods=lambda: METHODS))
