"""The nanoscale family's cost model: LSODA's CPU time per unit of nanoscale time (1/omega), fitted on seed 001's
scene by ``benchmarks/family_costs.py`` (``data/family_costs.json``), and the closed form's overhead."""

from __future__ import annotations

from faultslip.io import budget
from faultslip.io.budget import Estimate


def nanoscale_estimate(duration: float, samples: int) -> Estimate:
    """Time and memory of a nanoscale run over ``duration`` (in 1/omega) kept at ``samples`` points."""
    return budget.fitted_estimate("nanoscale", "lsoda", duration, f"a nanoscale run over {duration:.3g}/omega",
                                  memory=float(samples) * 6 * 8.0 * 3)
