"""Seed 001's nanoscale stick-slip with contact charging as a model family: the damping threshold A_c in
closed form, the LSODA run only where the swing needs it."""

from __future__ import annotations

from faultslip.dynamics.nanoscale import choose_method
from faultslip.dynamics.nanoscale import report as nanoscale_report
from faultslip.dynamics.nanoscale import run_dataset
from faultslip.models.nanoscale.scene import load_nanoscale_scene
from faultslip.models.common import note_origin
from faultslip.contract.registry import Family, register
from faultslip.models.result import Result
from faultslip.plots.vibration import nanoscale_figure


def run(scene, method=None, tolerance=None, allow_large: bool = False) -> Result:
    """The regime in closed form; the force swing integrated where it is asked."""
    model, settings, notes = load_nanoscale_scene(scene)
    method = method or settings["method"]
    # the closed form, when asked for by name, answers the regime alone
    wanted = ("regime",) if method == "nanoscale_linear_stability" else ("regime", "force_swing")
    choice = choose_method(model, wanted, method, tolerance or settings["tolerance"])
    # the steady quantities come from a cycle shown to have settled, not from a fixed duration
    cycle = (model.settled_cycle(tolerance or settings["tolerance"], rtol=choice.rtol, allow_large=allow_large)
             if choice.method == "nanoscale_LSODA" else None)
    report = nanoscale_report(model, None, choice, f"faultslip nanoscale scene: {notes['name']}", cycle=cycle)
    note_origin(report, notes.get("origin"))
    return Result("nanoscale", report)


def simulate(scene, allow_large: bool = False) -> Result:
    """The time series (LSODA), its report and seed 001's Fig. 3."""
    model, settings, notes = load_nanoscale_scene(scene)
    choice = choose_method(model, ("regime", "force_swing", "time_series"), "auto", settings["tolerance"])
    integrated = model.simulate(settings["duration"], settings["samples"], rtol=choice.rtol, allow_large=allow_large)
    cycle = (model.settled_cycle(settings["tolerance"], rtol=choice.rtol, allow_large=allow_large)
             if model.stick_slip else None)
    report = nanoscale_report(model, integrated, choice, f"faultslip nanoscale simulation: {notes['name']}",
                              cycle=cycle)
    note_origin(report, notes.get("origin"))
    return Result("nanoscale", report, run_dataset(integrated), lambda: nanoscale_figure(integrated))


FAMILY = register(Family("nanoscale", "seed 001: nanoscale stick-slip with contact charging", run, simulate,
                         simulate_options=("allow_large",), run_options=("allow_large",),
                         why="a nanoscale scene sets its run in [run] and its accuracy in [method] tolerance"))
