"""The spring slider's cost model: what a simulation of N cycles needs, before it runs (the family declares it)."""

from __future__ import annotations

from faultslip.contract.registry import load
from faultslip.dynamics.methods import planned
from faultslip.fault.scaling import Fault
from faultslip.fault.scene import check_method, read_slider_scene
from faultslip.io import budget, machine
from faultslip.io.budget import Estimate


def _check_run_method(action: str, options: dict) -> None:
    """What run refuses, its estimate refuses: a method that is not one of the seed law's."""
    if action == "run" and options.get("method") is not None:
        check_method(options["method"])


def simulation_estimate(cycles: int, samples_per_slip: int, integrated: bool, output=None) -> Estimate:
    """Memory and time of ``simulate``: the time series holds about (samples + 2) rows per cycle."""
    rows = float(cycles) * (samples_per_slip + 2)
    memory = rows * 6 * 8.0 * 3  # six columns, about three copies while the dataset is built
    # typed rates (measured on the 2-core machine the families' costs were fitted on): carried to this one with them
    seconds = machine.on_this_machine(float(cycles) * (2.5e-3 if integrated else 2e-6) + rows * 1e-8, "families")
    # the time series' Dataset, and the integrator or the analytic phases' roots
    imports = (*budget.DATASET_IMPORTS, *(budget.INTEGRATION_IMPORTS if integrated else ("scipy.optimize",)))
    return Estimate(what=f"a simulation of {cycles:.3g} cycles", memory=memory, disk=rows * 6 * 8.0 if output else 0.0,
                    seconds=seconds, output=output, imports=imports)


def estimate(scene, action: str = "run", cycles=None, slip_solver=None, output=None, **options) -> Estimate:
    """What a run or simulation of a seed-law scene needs, before it starts: a run's closed form or exact cycle
    at its fitted overhead (``benchmarks/family_costs.py``), a simulation from its rows
    (:func:`simulation_estimate`). A scene of one rate-and-state block is its own family's to estimate."""
    if isinstance(scene, Fault):
        _check_run_method(action, options)
        return budget.fitted_estimate("spring_slider", "run", 0.0, "the fault's estimate in closed form")
    loaded = read_slider_scene(scene)
    if loaded.rate_state:
        return load(loaded.family).estimate(loaded, action, cycles=cycles, slip_solver=slip_solver, output=output,
                                            **options)
    _check_run_method(action, options)
    if action == "run":
        closed = budget.fitted_estimate("spring_slider", "run", 0.0, f"the cycle of {loaded.name}")
        if loaded.kind != "lab":
            return closed
        # a lab slider's cycle by the method its run will take (faultslip.dynamics.methods.choose), at that
        # method's declared cost: an integrated cycle had been estimated at the closed form's 2 ms
        method, tolerance = options.get("method") or loaded.method, options.get("tolerance") or loaded.tolerance
        cycles = min(int(loaded.simulation.get("cycles", 200)), 1000)
        chosen, assessment = planned(loaded.slider(), method, tolerance=tolerance, cycles=cycles)
        seconds = machine.on_this_machine(assessment.estimated_cost or 0.0, "families") if assessment.applicable \
            else 0.0
        return Estimate(what=f"the cycle of {loaded.name} by {chosen.name}", memory=closed.memory,
                        seconds=max(closed.seconds, seconds), imports=chosen.imports)
    settings = dict(loaded.simulation)
    if cycles is not None:
        settings["cycles"] = cycles
    solver = slip_solver or settings.get("slip_solver", "auto")
    integrated = not loaded.slider().is_linear or solver not in ("auto", "analytic")
    return simulation_estimate(settings.get("cycles", 100), settings.get("samples_per_slip", 64), integrated, output)
