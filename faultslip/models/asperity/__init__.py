"""Seed 004's asperity friction as a model family: critical speeds in closed form, the six-state response by
the cheapest accurate integrator."""

from __future__ import annotations

from faultslip.dynamics.asperity import choose_method
from faultslip.dynamics.asperity import report as asperity_report
from faultslip.dynamics.asperity import run_dataset
from faultslip.dynamics.asperity import simulate as integrate
from faultslip.contract.cells import PerCell
from faultslip.contract.scenes import toml_reader
from faultslip.contract.specs import Output, Parameter
from faultslip.dynamics.asperity import METHODS
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


#: What an asperity study sweeps ([slider] and [friction] of seed 004's scene) and writes.
PARAMETERS = {name: Parameter(name, kind, unit, long_name, (table, name)) for name, table, kind, unit, long_name in (
    ("platform_speed", "slider", "speed", "m/s", "platform speed v"),
    ("mass", "slider", "mass", "kg", "mass M"),
    ("natural_frequency", "slider", "frequency", "Hz", "natural frequency f0"),
    ("dashpot", "slider", "damping", "N*s/m", "dashpot C"),
    ("slope_std", "friction", "dimensionless", "1", "standard deviation s of the asperity slopes (rad)"),
    ("shear_strength", "friction", "pressure", "Pa", "shear strength tau of the adhesion law"),
    ("pressure_coefficient", "friction", "dimensionless", "1", "pressure coefficient beta"),
    ("composite_modulus", "friction", "pressure", "Pa", "composite modulus E'"),
    ("asperity_radius", "friction", "length", "m", "asperity radius r"),
    ("loss_factor", "friction", "damping", "N*s/m", "loss factor eta"),
    ("initial_approach", "friction", "length", "m", "initial approach"),
)}
OUTPUTS = {spec.name: spec for spec in (
    Output("regime", "1", "regime of the response", flags=("stick_slip", "sliding")),
    Output("wavelength", "m", "lambda, eq. (29) at the initial approach"),
    Output("critical_speed_1", "m/s", "v_c1 = f0 lambda (eq. 28)"),
    Output("contact_loss_speed", "m/s", "speed where following the surface needs more than g"),
    Output("mean_friction", "1", "mean friction coefficient, last half of the run"),
    Output("mean_deformation_friction", "1", "mean deformation friction, last half of the run"),
    Output("stick_fraction", "1", "fraction of time stuck, last half of the run"),
    Output("dominant_frequency", "Hz", "dominant frequency of the block's speed"),
    Output("method", "1", "method of this cell", flags=tuple(METHODS)),
    Output("estimated_relative_error", "1", "declared error of the method", key="estimated_error"),
)}
CELLS = PerCell("an asperity study", PARAMETERS, OUTPUTS, run, load_asperity_scene, methods=("auto", *METHODS),
                seconds=0.5)

FAMILY = register(Family("asperity", "seed 004: a block on asperities, stick fraction and period", run, simulate,
                         why="an asperity scene sets its run in [run] duration and its method in [method]",
                         read_scene=toml_reader("asperity", PARAMETERS), cells=CELLS,
                         methods=lambda: list(METHODS.values())))
