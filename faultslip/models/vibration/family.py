"""Seed 002's quasi-harmonic vibration as a model family: the settled amplitude, averaged where accurate enough,
and eq. (10) integrated onto its cycle inside the averaged envelope."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from faultslip.dynamics.vibration import report as averaging_report
from faultslip.dynamics.vibration import (amplitude_against_speed, analyse_and_settle, simulate_vibration,
                                          vibration_dataset, vibration_report)
from faultslip.contract.cells import PerCell
from faultslip.contract.scenes import toml_reader
from faultslip.contract.specs import Output, parameters
from faultslip.dynamics.vibration import METHODS as DECLARED_METHODS
from faultslip.errors import InputError
from faultslip.units import to_si
from faultslip.models.vibration.scene import read_vibration_scene
from faultslip.models.vibration import cost as vibration_cost
from faultslip.contract.registry import Example, Family, register
from faultslip.contract.result import Result, judge_tolerance
from faultslip.models.common import note_origin, note_scene
from faultslip.models.vibration.figures import amplitude_speed_figure, vibration_series_figure

#: --method names of the CLI (the listed ones, faultslip.dynamics.vibration.METHODS) and their averaging methods
METHODS = {None: "auto", "auto": "auto", **{entry["name"]: short for short, entry in DECLARED_METHODS.items()}}


def averaging_method(method) -> str:
    """The averaging method a --method name asks for, refused in one sentence where it names none (run and
    estimate alike)."""
    chosen = METHODS.get(method)
    if chosen is None:
        raise InputError(f"a vibration scene takes --method auto, quasi_harmonic_averaging or "
                         f"quasi_harmonic_integration, got {method!r}")
    return chosen


def estimate(scene, action: str = "run", **options):
    """What a run or simulation of a vibration scene needs, before it starts (cost.py); a run's method that run
    refuses, refused here too."""
    if action == "run":
        averaging_method(options.get("method"))
    return vibration_cost.estimate(scene, action, **options)


def run(scene, method=None, tolerance=None) -> Result:
    """The settled amplitude of a vibration scene (seed 002): by averaging where it is accurate enough."""
    system, notes = read_vibration_scene(scene)
    chosen = averaging_method(method)
    analysis, settled = analyse_and_settle(system, chosen, tolerance or 1e-3)
    report = averaging_report(system, analysis, None, settled)
    note_origin(report, notes.get("origin"))
    return Result("vibration", report, tolerance=tolerance or 1e-3)


def amplitude_study(scene, speed=None, speeds=None, method: str = "auto", tolerance: float = 1e-3) -> Result:
    """The settled amplitude at one driving speed, and against speed (``faultslip quasi-harmonic``).

    Parameters
    ----------
    scene : str, path or TomlScene
        A vibration scene (seed 002's apparatus).
    speed : str or Quantity, optional
        A driving speed with units replacing the scene's ("12 in/s").
    speeds : tuple, optional
        ``(start, stop, count)``: the amplitude against driving speed over that many speeds (seed 002 Figs.
        10-11), in the report's JSON and the figure.
    method : str
        auto, quasi_harmonic_averaging or quasi_harmonic_integration (averaging or integration for short;
        ``faultslip quasi-harmonic --method``).
    tolerance : float
        The amplitude's relative error allowed.

    Returns
    -------
    Result
        The report (amplitude in m, growth rate in 1/s, ...), ``extras["sweep"]`` the arrays against speed, and
        ``plot()`` the amplitude against speed.
    """
    system, notes = read_vibration_scene(scene)
    if speed is not None:
        system = replace(system, speed=to_si(speed, "speed", "--speed"))
    sweep = None
    if speeds is not None:
        start, stop = (to_si(text, "speed", "--speeds") for text in speeds[:2])
        count = speeds[2]
        if not (0 < start < stop and isinstance(count, int) and 2 <= count <= 2000):
            raise InputError("--speeds needs START < STOP, both positive, and a count from 2 to 2000")
        sweep = amplitude_against_speed(system, np.linspace(start, stop, count))
    analysis, settled = analyse_and_settle(system, method, tolerance)
    report = averaging_report(system, analysis, sweep, settled)
    note_scene(report, notes)
    figure = (lambda: amplitude_speed_figure(system, sweep)) if sweep is not None else None
    # the tolerance chose the method (and the CLI's default 1e-3 too): judged as a run's is
    return judge_tolerance(Result("vibration", report, figure=figure, extras={"sweep": sweep, "system": system},
                                  tolerance=tolerance), None)


def simulate(scene) -> Result:
    """Eq. (10) from a small disturbance onto its limit cycle, beside the averaged envelope."""
    system, notes = read_vibration_scene(scene)
    integrated = simulate_vibration(system)
    report = vibration_report(integrated)
    note_origin(report, notes.get("origin"))
    return Result("vibration", report, vibration_dataset(integrated), lambda: vibration_series_figure(integrated))


#: What a vibration study sweeps ([vibration] of the scene) and writes.
PARAMETERS = parameters({
    "mass": ("mass", "kg", "equivalent mass M"),
    "stiffness": ("stiffness", "N/m", "stiffness k"),
    "damping": ("damping", "N*s/m", "damping r"),
    "normal_load": ("force", "N", "normal load W"),
    "speed": ("speed", "m/s", "driving speed v"),
}, "vibration")
OUTPUTS = {spec.name: spec for spec in (
    Output("regime", "1", "regime: quasi-harmonic vibration, steady sliding, or stick-slip (outside the averaging)",
           flags=("quasi_harmonic", "steady_sliding", "stick_slip")),
    Output("amplitude", "m", "limit-cycle amplitude A (NaN where the slider sticks)"),
    Output("peak_speed", "m/s", "A omega, the largest vibration speed"),
    Output("natural_frequency", "Hz", "omega / 2 pi"),
    Output("growth_rate", "1/s", "growth rate of small oscillations, -(r + W f'(v)) / 2M"),
    Output("small_parameter", "1", "eps = (r + W max|f'|) / (M omega), small where averaging holds"),
    Output("method", "1", "method of this cell", flags=("quasi_harmonic_averaging", "quasi_harmonic_integration")),
    Output("estimated_relative_error", "1", "estimated relative error of the amplitude"),
)}
CELLS = PerCell("a vibration study", PARAMETERS, OUTPUTS, run, read_vibration_scene,
                methods=("auto", "quasi_harmonic_averaging", "quasi_harmonic_integration"), seconds=0.15)

FAMILY = register(Family("vibration", "seed 002: friction-induced vibration without sticking (quasi-harmonic)",
                         run, simulate,
                         why="a vibration scene is integrated by DOP853 at rtol 1e-10 until its cycle settles",
                         read_scene=toml_reader("vibration", PARAMETERS), cells=CELLS,
                         methods=lambda: list(DECLARED_METHODS.values()), estimate=estimate,
                         example=Example('vibration_seed002.toml', "study_vibration.toml",
                                         {'speed': ['11 in/s', '12.5 in/s']}, {})))
