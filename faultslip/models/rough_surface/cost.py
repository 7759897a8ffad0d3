"""The rough-surface family's cost model: CPU time in stick-slip cycles, fitted on seed 000's scene by
``benchmarks/family_costs.py``."""

from __future__ import annotations

from faultslip.dynamics.methods import check_lent_method
from faultslip.io import budget
from faultslip.models.rough_surface.scene import read_rough_scene


def work(scene, action: str = "run", cycles=None, **_) -> tuple[str, float, str]:
    """(cost entry, units, what): the cycles the run solves or the simulation integrates."""
    _system, _details, settings = read_rough_scene(scene)
    count = float(cycles or settings["cycles"])
    return action, count, f"{'a simulation' if action == 'simulate' else 'a run'} of {count:g} stick-slip cycles"


def estimate(scene, action: str = "run", **options) -> budget.Estimate:
    """What a run or simulation of a rough-surface scene needs, before it starts; a run's method that its solve
    refuses, refused here too."""
    if action == "run":
        check_lent_method(options.get("method") or "auto", "a rough-surface scene")
    entry, units, what = work(scene, action, **options)
    rows = units * 66.0  # about 64 samples a slip and two a stick, six columns
    return budget.fitted_estimate("rough_surface", entry, units, what, memory=rows * 6 * 8.0 * 3,
                                  output=options.get("output"),
                                  imports=(*budget.DATASET_IMPORTS, *budget.INTEGRATION_IMPORTS))
