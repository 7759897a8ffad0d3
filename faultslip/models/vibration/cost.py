"""The quasi-harmonic family's cost model: a simulation's CPU time in periods of the oscillation (eq. 10 at rtol
1e-10), a run's integration (shooting) and averaging their overheads alone; fitted on seed 002's scene by
``benchmarks/family_costs.py``."""

from __future__ import annotations

from dataclasses import replace

from faultslip.dynamics.vibration import simulation_periods
from faultslip.io import budget
from faultslip.models.vibration.scene import read_vibration_scene


def work(scene, action: str = "run", method=None, tolerance=None, **_) -> tuple[str, float, str]:
    """(cost entry, units, what): a simulation's periods, from the averaged cycle's decay rate
    (:func:`~faultslip.dynamics.vibration.simulation_periods`); a run's shooting or averaging's root search."""
    system, _notes = read_vibration_scene(scene)
    result = system.analyse()
    if not result.valid and not result.marginal:  # the slider sticks: the run says so at once
        return f"{action}:averaging_sticks" if action == "run" else "simulate", 0.0, "the averaged equation alone"
    if result.marginal:  # too close to sticking to call: integrated from the cycle
        result = replace(result, amplitude=result.cycle_amplitude)
    if action == "simulate":
        periods = simulation_periods(system, result)
        return "simulate", periods, f"eq. (10) integrated over {periods:.3g} periods"
    integrating = result.amplitude > 0 and (method == "quasi_harmonic_integration" or result.marginal or (
        method in (None, "auto") and result.estimated_error > (tolerance or 1e-3)))
    if not integrating:
        # a limit cycle's amplitude is a root search of eq. (20), 6-9 ms; steady sliding (no growth) 0.6 ms and a
        # slider that would stick 3 ms: one overhead for all three had estimated a study's cells at 3x their CPU
        if result.amplitude > 0:
            return "run:averaging", 0.0, "the averaged amplitude (eq. 20)"
        return "run:averaging_steady", 0.0, "steady sliding by the averaged equation (eq. 20)"
    # the periodic orbit by shooting: 44-70 periods at two rtols on seed 002's scene, near the onset speed too
    # (faultslip.dynamics.vibration.periodic_orbit); its fallback, settling, is refused beyond FALLBACK_PERIODS
    return "run:shooting", 0.0, "eq. (10)'s periodic orbit by shooting (about 50 periods at two rtols)"


def estimate(scene, action: str = "run", **options) -> budget.Estimate:
    """What a run or simulation of a vibration scene needs, before it starts."""
    entry, units, what = work(scene, action, **options)
    # averaging is closed form; integration imports scipy's integrators, and a simulation builds a Dataset
    imports = {"run:averaging": (), "run:averaging_steady": (), "run:averaging_sticks": (),
               "run:shooting": budget.INTEGRATION_IMPORTS}.get(
        entry, (*budget.DATASET_IMPORTS, *budget.INTEGRATION_IMPORTS))
    return budget.fitted_estimate("vibration", entry, units, what, output=options.get("output"), imports=imports)
