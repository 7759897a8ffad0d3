"""The rough-surface family's cost model: CPU time fitted by ``benchmarks/family_costs.py`` on seed 000's scenes,
a run's in the seconds its method declares, a simulation's in stick-slip cycles."""

from __future__ import annotations

from faultslip.dynamics.methods import METHODS, check_lent_method, planned
from faultslip.io import budget
from faultslip.models.rough_surface.scene import read_rough_scene

#: A run's tolerance where none is given (the family's run and its estimate alike).
DEFAULT_TOLERANCE = 1e-6


def work(scene, action: str = "run", cycles=None, method=None, tolerance=None, **_) -> tuple[str, float, str]:
    """(cost entry, units, what). A run's units are the seconds its method declares on the calibration machine
    (:func:`faultslip.dynamics.methods.planned`: its rtol, its law's curvature and stiffness, the settling, and the
    refinement check's run at a hundredth of the rtol), which the fit carries to CPU seconds: the method and
    tolerance move a run's cost 30-fold, where its cycles alone had been counted. A simulation's are its cycles."""
    system, _details, settings = read_rough_scene(scene)
    return _work(system, float(cycles or settings["cycles"]), action, method, tolerance)


def _work(system, count: float, action: str, method, tolerance) -> tuple[str, float, str]:
    if action == "simulate":
        return action, count, f"a simulation of {count:g} stick-slip cycles"
    chosen, assessment = planned(system, method or "auto", tolerance=tolerance or DEFAULT_TOLERANCE,
                                 cycles=int(count), price=price)
    return _entry(assessment), float(assessment.estimated_cost), (f"a run of {count:g} stick-slip cycles by "
                                                                  f"{chosen.name} ({assessment.reason})")


def _entry(assessment) -> str:
    """Each integrator its own cost entry: on a table's kinks the integrators' shares of the evaluations the
    calibration counts differ, LSODA's tighter rtols costing it less than counted (each entry's seconds per unit
    in data/family_costs.json, fitted by benchmarks/family_costs.py)."""
    return f"run:{getattr(METHODS[assessment.method], 'solver', 'averaging')}"


def price(assessment) -> float:
    """What a run by ``assessment``'s method costs on a rough-surface law, in the fitted seconds of its entry: auto
    ranks the integrators by it (:func:`faultslip.dynamics.methods.choose`). By the calibration's seconds it takes
    DOP853, where LSODA costs less (benchmarks/rough_auto_choice.py)."""
    return budget.fitted_seconds("rough_surface", _entry(assessment), assessment.estimated_cost)


def estimate(scene, action: str = "run", **options) -> budget.Estimate:
    """What a run or simulation of a rough-surface scene needs, before it starts; a run's method that its solve
    refuses, refused here too."""
    if action == "run":
        check_lent_method(options.get("method") or "auto", "a rough-surface scene")
    system, _details, settings = read_rough_scene(scene)
    count = float(options.get("cycles") or settings["cycles"])
    entry, units, what = _work(system, count, action, options.get("method"), options.get("tolerance"))
    rows = count * 66.0  # about 64 samples a slip and two a stick
    return budget.fitted_estimate("rough_surface", entry, units, what, memory=rows * 6 * 8.0 * 3,
                                  output=options.get("output"),
                                  imports=(*budget.DATASET_IMPORTS, *budget.INTEGRATION_IMPORTS))
