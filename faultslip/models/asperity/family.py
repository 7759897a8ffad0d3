"""Seed 004's asperity friction as a model family: critical speeds in closed form, the six-state response by
the cheapest accurate integrator."""

from __future__ import annotations

import math

from dataclasses import replace

import numpy as np

from faultslip.models.asperity.dynamics import choose_method
from faultslip.models.asperity.dynamics import report as asperity_report
from faultslip.models.asperity.dynamics import run_dataset
from faultslip.models.asperity.dynamics import simulate as integrate
from faultslip.contract.cells import PerCell
from faultslip.contract.scenes import toml_reader
from faultslip.contract.specs import Output, Parameter
from faultslip.models.asperity.dynamics import (CONVERGENCE_RTOLS, METHODS, QUASISTATIC_ERROR, converged_run,
                                                measured_wavelength, peak_speeds, speed_sweep)
from faultslip import ranges
from faultslip.errors import InputError, SolverError
from faultslip.models.asperity.scene import load_asperity_scene
from faultslip.models.common import note_origin
from faultslip.models.asperity import cost as asperity_cost
from faultslip.contract.registry import Example, Family, register
from faultslip.contract.result import Result
from faultslip.models.asperity.speed_map import OUTCOMES, asperity_map
from faultslip.models.asperity.figures import map_figure, response_figure, sweep_figure
from faultslip.units import to_si


def run(scene, method=None, tolerance=None) -> Result:
    """Critical speeds in closed form, the response where it is asked."""
    model, settings, notes = load_asperity_scene(scene)
    tolerance = tolerance or settings["tolerance"]
    choice = choose_method(model, ("response",), tolerance, method or settings["method"])
    response, numerical, met, measured = None, 0.0, True, None
    if choice.method == "asperity_measured_wavelength":  # its rtol change is measured too, and declared if larger
        measured = measured_wavelength(model)
        choice = replace(choice, estimated_error=max(choice.estimated_error, measured.numerical_error))
    elif choice.method != "asperity_wavelength":  # converge or declare: the integration's own error is measured
        response, numerical, met = converged_run(model, settings["duration"], choice.method, tolerance)
        model_error = QUASISTATIC_ERROR if choice.method == "asperity_quasistatic" else 0.0
        choice = replace(choice, estimated_error=max(model_error, numerical))
    report = asperity_report(model, response, choice, f"faultslip asperity scene (seed 004): {notes['name']}",
                             measured=measured)
    if response is not None:
        report.add("numerical_error", numerical if math.isfinite(numerical) else None,
                   label="the statistics' change from rtol to a tighter one (measured)")
        if not met:
            report.note(f"{choice.method} did not converge to the tolerance {tolerance:g} down to rtol "
                        f"{CONVERGENCE_RTOLS[-1]:g}: its measured change {numerical:.3g} is declared")
    note_origin(report, notes.get("origin"))
    return Result("asperity", report, tolerance=tolerance)


#: the integrator map's speeds (m/s) and slope spreads (rad): where each integrator works (about 30 s)
MAP_SPEEDS = (1e-3, 3.6e-3, 0.03, 0.1, 0.2, 0.3, 0.45, 0.7)
MAP_SLOPE_STDS = (0.1, 0.2, 0.3)


def speed_study(scene, low, high, points: int = 40, dashpot=None, method: str = "asperity_quasistatic",
                integrator_map: bool = False, progress=None, tolerance=None) -> Result:
    """The asperity slider swept over platform speed: m_D, stick and loops, its peaks against eqs. (28)-(29)
    (seed 004 Tables II-III; ``faultslip asperity``).

    Parameters
    ----------
    scene : str, path or TomlScene
        An asperity scene.
    low, high : str or Quantity
        The platform speeds swept, with units ("1 mm/s").
    points : int
        Speeds in the sweep, from 3 to 2000.
    dashpot : str or Quantity, optional
        The dashpot C replacing the scene's ("200 kg/s").
    method : str
        asperity_quasistatic or asperity_LSODA.
    integrator_map : bool
        Also map where each integrator works, over speed and slope spread (about 30 s).
    progress : callable, optional
        ``(done, total)`` over speeds (:mod:`faultslip.io.progress`).
    tolerance : float, optional
        Converge each speed to this relative change of its statistics between successive rtols (about 3-5
        times the cost); without it each speed runs once and the report says convergence is not tested.

    Returns
    -------
    Result
        The report (peak speeds in m/s, ...), the sweep's Dataset over platform speed, its figure, and
        ``extras["map"]`` the integrator map's Dataset where asked, ``extras["map_figure"]`` its figure.
    """
    model, settings, notes = load_asperity_scene(scene)
    low, high = (to_si(text, "speed", name, "m/s") for text, name in ((low, "--from"), (high, "--to")))
    if not (0 < low < high):
        raise InputError(f"--from must be below --to and positive, got {low:g} and {high:g} m/s")
    if isinstance(points, bool) or not isinstance(points, int) or not 3 <= points <= 2000:
        raise InputError(f"--points must be from 3 to 2000, got {points}")
    if dashpot is not None:
        model = replace(model, dashpot=to_si(dashpot, "damping", "--dashpot", "N*s/m"))
    if method not in ("asperity_quasistatic", "asperity_LSODA"):
        raise InputError(f"--method must be asperity_quasistatic or asperity_LSODA, got {method!r}")
    for speed in (low, high):  # the model refuses an out-of-range speed before any cell runs
        replace(model, platform_speed=speed)
    if tolerance is not None:
        tolerance = ranges.check_tolerance(tolerance, label="--tolerance")
    sweep = speed_sweep(model, np.linspace(low, high, points), duration=settings["duration"], method=method,
                        progress=progress, tolerance=tolerance)
    report = asperity_report(model, None, None, f"faultslip asperity speed sweep (seed 004): {notes['name']}")
    report.section("Sweep")
    report.add("method", method).add("points", points)
    report.add("peak_speeds", [float(p) for p in peak_speeds(sweep)], "m/s", label="local maxima of m_D (Tables II-III)")
    sticking = sweep["platform_speed"].values[sweep["stick_fraction"].fillna(0).values > 1e-3]
    report.add("stick_slip_speeds", [float(s) for s in sticking], "m/s", label="speeds with stick")
    failed = {str(v): int((sweep["status"].values == v).sum()) for v in set(sweep["status"].values) if v != "ok"}
    if failed:
        report.add("failed_cells", failed, label="cells without a result, by reason")
    report.add("computing_time", float(sweep["elapsed"].sum()), "s")
    if tolerance is not None:
        errors = sweep["numerical_error"].values
        report.add("numerical_error", float(np.nanmax(errors)) if np.isfinite(errors).any() else None,
                   label="the largest change of a speed's statistics between its last two rtols (measured)")
        missed = sweep["platform_speed"].values[sweep["converged"].values == 0]
        report.add("unconverged_speeds", [float(s) for s in missed], "m/s",
                   label=f"speeds whose statistics did not converge to {tolerance:g}")
    report.note(f"convergence {sweep.attrs['convergence']}")
    grid = None
    if integrator_map:
        grid = asperity_map(MAP_SPEEDS, MAP_SLOPE_STDS, replace(model, dashpot=200.0), duration=0.2)
        report.section("Integrator map (C = 200 kg/s)")
        for name in grid["method"].values:
            codes = grid["outcome"].sel({"method": name}).values.ravel()
            report.add(f"map_{name}", {OUTCOMES[c]: int((codes == c).sum()) for c in sorted(set(codes))},
                       label=f"{name}: cells by outcome")
    return Result("asperity", report, sweep, lambda: sweep_figure([sweep], [notes["name"]]), extras={"map": grid,
                  "map_figure": None if grid is None else (lambda: map_figure(grid))})


def simulate(scene) -> Result:
    """The six-state time series, its report and seed 004's response panels."""
    model, settings, notes = load_asperity_scene(scene)
    choice = choose_method(model, ("response", "time_series"), settings["tolerance"], settings["method"])
    if choice.method in ("asperity_wavelength", "asperity_measured_wavelength"):
        raise InputError(f"{choice.method} gives critical speeds only; a simulation needs asperity_quasistatic "
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
    ("contact_length", "friction", "length", "m", "contact length alpha = 1/(gamma pi r): sets the contact density"),
)}
OUTPUTS = {spec.name: spec for spec in (
    Output("regime", "1", "regime of the response", flags=("stick_slip", "sliding")),
    Output("wavelength", "m", "lambda, eq. (29) at the initial approach"),
    Output("run_wavelength", "m", "lambda_run, the slip per approach cycle of a run at v_c1 "
                                  "(asperity_measured_wavelength)"),
    Output("critical_speed_1", "m/s", "v_c1 = f0 lambda / n (eq. 28), lambda eq. (29)'s or a run's by the method"),
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
                         methods=lambda: list(METHODS.values()), estimate=asperity_cost.estimate,
                         example=Example('asperity_seed004.toml', "study_asperity.toml",
                                         {'platform_speed': ['2 mm/s', '3.6 mm/s']}, {})))
