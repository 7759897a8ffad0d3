"""Seed 004's asperity friction as a model family: critical speeds in closed form, the six-state response by
the cheapest accurate integrator."""

from __future__ import annotations

from faultslip.dynamics.asperity import choose_method
from faultslip.dynamics.asperity import report as asperity_report
from faultslip.dynamics.asperity import run_dataset
from faultslip.dynamics.asperity import simulate as integrate
from faultslip.errors import InputError, SolverError
from faultslip.models.asperity.scene import load_asperity_scene
from faultslip.models.common import note_origin
from faultslip.contract.registry import Family, register
from faultslip.models.result import Result
from faultslip.plots.asperity import response_figure


def run(scene, method=None, tolerance=None) -> Result:
    """Critical speeds in closed form, the response where it is asked."""
    model, settings, notes = load_asperity_scene(scene)
    choice = choose_method(model, ("response",), tolerance or settings["tolerance"], method or settings["method"])
    response = integrate(model, settings["duration"], choice.method) if choice.method != "asperity_wavelength" else None
    report = asperity_report(model, response, choice, f"faultslip asperity scene (seed 004): {notes['name']}")
    note_origin(report, notes.get("origin"))
    return Result("asperity", report)


def simulate(scene) -> Result:
    """The six-state time series, its report and seed 004's response panels."""
    model, settings, notes = load_asperity_scene(scene)
    choice = choose_method(model, ("response", "time_series"), settings["tolerance"], settings["method"])
    if choice.method == "asperity_wavelength":
        raise InputError("asperity_wavelength gives critical speeds only; a simulation needs asperity_quasistatic "
                         "or asperity_LSODA in [method] name")
    response = integrate(model, settings["duration"], choice.method)
    report = asperity_report(model, response, choice, f"faultslip asperity simulation (seed 004): {notes['name']}")
    note_origin(report, notes.get("origin"))
    if response.status != "ok":
        raise SolverError(f"{choice.method} did not finish {notes['name']}: {response.reason}")
    return Result("asperity", report, run_dataset(response), lambda: response_figure(response))


FAMILY = register(Family("asperity", "seed 004: a block on asperities, stick fraction and period", run, simulate,
                         why="an asperity scene sets its run in [run] duration and its method in [method]"))
