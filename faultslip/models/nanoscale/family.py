"""Seed 001's nanoscale stick-slip with contact charging as a model family: the damping threshold A_c in
closed form, the LSODA run only where the swing needs it."""

from __future__ import annotations

import dataclasses

from faultslip.models.nanoscale.dynamics import (HOPF_SAFETY, choose_method, reference_model, settle,
                                                 with_damping)
from faultslip.models.nanoscale.hopf import growth_rate, hopf_point
from faultslip.models.nanoscale.dynamics import report as nanoscale_report
from faultslip.models.nanoscale.dynamics import run_dataset
from faultslip.contract.cells import PerCell
from faultslip.contract.scenes import toml_reader
from faultslip.contract.specs import Output, Parameter
from faultslip.models.nanoscale.dynamics import METHODS as DECLARED_METHODS
from faultslip.models.nanoscale.dynamics import NANOSCALE_METHODS
from faultslip.models.nanoscale.scene import load_nanoscale_scene
from faultslip.models.nanoscale import cost as nanoscale_cost
from faultslip.io import budget
from faultslip.models.common import note_origin, note_scene
from faultslip.contract.registry import Example, Family, register
from faultslip.contract.result import Result, judge_tolerance
from faultslip.models.nanoscale.figures import nanoscale_figure


def run(scene, method=None, tolerance=None, allow_large: bool = False) -> Result:
    """The regime in closed form; the force swing integrated where it is asked."""
    model, settings, notes = load_nanoscale_scene(scene)
    method = method or settings["method"]
    # the closed form, when asked for by name, answers the regime alone
    wanted = ("regime",) if method == "nanoscale_linear_stability" else ("regime", "force_swing")
    tolerance = tolerance or settings["tolerance"]
    # the steady quantities come from a cycle shown to have settled (or the normal form's, its error measured),
    # not from a fixed duration
    choice, cycle = settle(model, choose_method(model, wanted, method, tolerance), tolerance, allow_large)
    report = nanoscale_report(model, None, choice, f"faultslip nanoscale scene: {notes['name']}", cycle=cycle)
    note_origin(report, notes.get("origin"))
    return Result("nanoscale", report, tolerance=tolerance)


def swing(scene, damping: float | None = None, integrate: bool = True, allow_large: bool = False) -> Result:
    """The regime, the threshold A_c and the settled force swing (``faultslip nanoscale``).

    Parameters
    ----------
    scene : str, path or TomlScene
        A nanoscale scene (seed 001's dimensionless toy model).
    damping : float, optional
        The damping A replacing the scene's.
    integrate : bool
        Run LSODA over the scene's [run] (False: the linear stability alone, ``--no-run``).
    allow_large : bool
        Run beyond the time and memory budget.

    Returns
    -------
    Result
        The report (dimensionless), the run's Dataset and seed 001's Fig. 3 where integrated.
    """
    model, settings, notes = load_nanoscale_scene(scene)
    if damping is not None:
        model = with_damping(model, damping)
    choice = choose_method(model, ("regime", "force_swing", "time_series"), "nanoscale_LSODA", settings["tolerance"])
    integrated = model.simulate(settings["duration"], settings["samples"], rtol=choice.rtol,
                                allow_large=allow_large) if integrate else None
    cycle = _settled(model, settings["tolerance"], allow_large) if integrated is not None else None
    report = nanoscale_report(model, integrated, choice if integrate else None, cycle=cycle)
    note_scene(report, notes)
    if integrated is None:
        return Result("nanoscale", report)
    return judge_tolerance(Result("nanoscale", report, run_dataset(integrated), lambda: nanoscale_figure(integrated),
                                  tolerance=settings["tolerance"]), None)


def _settled(model, tolerance: float, allow_large: bool):
    """The settled cycle beside a time series, as a run finds it (:func:`settle`: the Hopf normal form next to a
    supercritical A_c, LSODA from rest otherwise); None where steady sliding is the only answer."""
    return settle(model, choose_method(model, ("regime", "force_swing"), "auto", tolerance), tolerance,
                  allow_large)[1]


def simulate(scene, allow_large: bool = False) -> Result:
    """The time series (LSODA), its report and seed 001's Fig. 3."""
    model, settings, notes = load_nanoscale_scene(scene)
    choice = choose_method(model, ("regime", "force_swing", "time_series"), "auto", settings["tolerance"])
    integrated = model.simulate(settings["duration"], settings["samples"], rtol=choice.rtol, allow_large=allow_large)
    cycle = _settled(model, settings["tolerance"], allow_large)
    report = nanoscale_report(model, integrated, choice, f"faultslip nanoscale simulation: {notes['name']}",
                              cycle=cycle)
    note_origin(report, notes.get("origin"))
    return judge_tolerance(Result("nanoscale", report, run_dataset(integrated), lambda: nanoscale_figure(integrated),
                                  tolerance=settings["tolerance"]), None)


#: What a nanoscale study sweeps (seed 001's dimensionless inputs) and writes.
PARAMETERS = {name: Parameter(name, "dimensionless", "1", long_name, (table, name), number=True)
              for name, table, long_name in (
                  ("damping", "slider", "damping A"), ("drive_speed", "slider", "drive speed v_a"),
                  ("peak_speed", "friction", "peak speed v_m"), ("charging_time", "friction", "charging time tau"),
                  ("charge_length", "friction", "charge length a"), ("charge_force", "friction", "charge force f_ch"))}
OUTPUTS = {spec.name: spec for spec in (
    Output("regime", "1", "regime of the settled cycle (or, by linear stability, of steady sliding)",
           flags=("stick_slip", "oscillating_sliding", "unstable_sliding", "steady_sliding")),
    Output("critical_damping", "1", "A_c, the damping below which steady sliding is unstable (Routh-Hurwitz)"),
    Output("largest_growth_rate", "1", "largest Re(lambda) of small disturbances, in omega"),
    Output("force_swing", "1", "force peak-to-peak of the settled cycle"),
    Output("period", "1", "period of the settled cycle, in 1/omega"),
    Output("least_speed", "1", "least speed in the cycle (the tip sticks below v_m)"),
    Output("method", "1", "method of this cell", flags=("nanoscale_linear_stability", "nanoscale_LSODA")),
    Output("estimated_relative_error", "1", "estimated relative error of the force swing"),
)}
CELLS = PerCell("a nanoscale study", PARAMETERS, OUTPUTS, run, load_nanoscale_scene, methods=NANOSCALE_METHODS,
                seconds=0.5)


def estimate(scene, action: str = "run", method=None, tolerance=None, **_) -> budget.Estimate:
    """What a run or simulation of a nanoscale scene needs, before it starts: the closed form's overhead, a run's
    settled cycle (cost.settle_estimate: the chunks it is expected to take), or a simulation's LSODA over the
    scene's duration and its settled cycle."""
    model, settings, _notes = load_nanoscale_scene(scene)
    tolerance = tolerance or settings["tolerance"]
    if action == "run":
        method = method or settings["method"]
        wanted = ("regime",) if method == "nanoscale_linear_stability" else ("regime", "force_swing")
        cycle = _cycle_estimate(model, choose_method(model, wanted, method, tolerance).method, tolerance,
                                method == "auto")
        return cycle or budget.fitted_estimate("nanoscale", "closed_form", 0.0, "the regime in closed form")
    simulated = nanoscale_cost.nanoscale_estimate(settings["duration"], settings["samples"])
    # its settled cycle, found after the series as a run finds it (_settled)
    cycle = _cycle_estimate(model, choose_method(model, ("regime", "force_swing"), "auto",
                                                 settings["tolerance"]).method, settings["tolerance"], True)
    if cycle is None:
        return simulated
    return dataclasses.replace(simulated, seconds=simulated.seconds + cycle.seconds,
                               what=f"{simulated.what}, and its settled cycle")


#: The normal form's measured error at its reference over HOPF_REFERENCE: 0.07-6 on the check's random models, median
#: 1.5 (benchmarks/nanoscale_hopf_check.py). Before the run, an auto normal form is expected to hand over to LSODA
#: where HOPF_SAFETY times this slope times sigma / omega_0 exceeds the tolerance.
EXPECTED_HOPF_SLOPE = 1.5


def _cycle_estimate(model, method: str, tolerance: float, auto: bool) -> budget.Estimate | None:
    """What the settled cycle ``method`` finds needs: LSODA's from rest, or the normal form's one settled cycle at
    its reference damping (at A itself where A is farther off), and, for ``auto``, LSODA's too where the normal
    form is expected to declare more than ``tolerance``; None for the closed form."""
    if method == "nanoscale_hopf_normal_form":
        point = hopf_point(model)
        ratio = growth_rate(model) / point.frequency
        reference = nanoscale_cost.settle_estimate(reference_model(model, point))
        if not (auto and HOPF_SAFETY * EXPECTED_HOPF_SLOPE * ratio > tolerance):
            return reference
        integration = nanoscale_cost.settle_estimate(model)
        return dataclasses.replace(reference, seconds=reference.seconds + integration.seconds,
                                   what=f"{reference.what}, at the normal form's reference and at A")
    return nanoscale_cost.settle_estimate(model) if method == "nanoscale_LSODA" else None


FAMILY = register(Family("nanoscale", "seed 001: nanoscale stick-slip with contact charging", run, simulate,
                         simulate_options=("allow_large",), run_options=("allow_large",), estimate=estimate,
                         why="a nanoscale scene sets its run in [run] and its accuracy in [method] tolerance",
                         read_scene=toml_reader("nanoscale", PARAMETERS), cells=CELLS,
                         methods=lambda: list(DECLARED_METHODS.values()),
                         example=Example('nanoscale_seed001.toml', "study_nanoscale.toml",
                                         {'damping': [3.0, 13.0]}, {})))
