"""The constant-friction family's declaration: closed-form run, a sampled simulation, its sweep and methods."""

from __future__ import annotations

import math

import numpy as np

from faultslip.contract.cells import PerCell
from faultslip.contract.registry import Family, register
from faultslip.contract.result import Result
from faultslip.contract.scenes import toml_reader
from faultslip.errors import InputError
from faultslip.io.budget import Estimate
from faultslip.io.report import Report

from families.constant_friction.figures import sawtooth_figure
from families.constant_friction.scene import OUTPUTS, PARAMETERS, read


def cycle(values: dict) -> tuple[float, float, float]:
    """(slip per event, recurrence period, slip duration) of the undamped cycle."""
    slip = 2 * (values["static"] - values["kinetic"]) * values["normal_load"] / values["stiffness"]
    slip_duration = math.pi * math.sqrt(values["mass"] / values["stiffness"])
    return slip, slip / values["platform_speed"] + slip_duration, slip_duration


def check_method(method) -> None:
    """Its one method (or auto): what run refuses, its estimate refuses (check_family asks both)."""
    if method not in (None, "auto", "closed_form"):
        raise InputError(f"a constant-friction scene runs closed_form, got {method!r}")


def run(scene, method=None, tolerance=None) -> Result:
    check_method(method)
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

    return Result("constant_friction", report, series, lambda: sawtooth_figure(time, ratio))


def estimate(scene, action="run", cycles=None, method=None, **_) -> Estimate:
    """The cost model: the closed form's overhead, or the simulation's 200 samples a cycle (a test family's
    round figures: its runs take milliseconds)."""
    if action == "run":
        check_method(method)
    read(scene)
    rows = 0 if action == "run" else 200 * (cycles or 3) + 1
    return Estimate(f"constant friction, {rows} samples", memory=rows * 8.0 * 3, seconds=1e-3 + rows * 1e-7)


METHODS = [{"name": "constant_friction_closed_form", "friction_laws": "constant static and kinetic friction",
            "domain": "an undamped slider: every loading rate", "cost_model": "O(1)",
            "declared_error": "round-off (the exact cycle)", "run_method": "closed_form"}]
CELLS = PerCell("a constant-friction study", PARAMETERS, OUTPUTS, run, read, methods=("auto", "closed_form"),
                seconds=1e-4)
FAMILY = register(Family("constant_friction", "a spring-slider with constant friction (a test family)", run,
                         simulate, simulate_options=("cycles",), read_scene=toml_reader("constant_friction",
                                                                                        PARAMETERS), cells=CELLS,
                         methods=lambda: METHODS, estimate=estimate))
