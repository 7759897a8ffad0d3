"""The spring slider's cost model: what a simulation of N cycles needs, before it runs (the family declares it)."""

from __future__ import annotations

import math

from faultslip.contract.registry import load
from faultslip.dynamics import methods
from faultslip.dynamics.methods import planned
from faultslip.dynamics.spring_slider.simulate import HORIZON_PERIODS, resolved_solver
from faultslip.fault.scaling import Fault
from faultslip.fault.scene import check_method, read_slider_scene
from faultslip.io import budget, machine
from faultslip.io.budget import Estimate


def _check_run_method(action: str, options: dict) -> None:
    """What run refuses, its estimate refuses: a method that is not one of the seed law's."""
    if action == "run" and options.get("method") is not None:
        check_method(options["method"])


#: A cycle's seconds where the slip phases are integrated, and where they are analytic (typed rates, measured on
#: the 2-core machine the families' costs were fitted on: carried to this one with them)
INTEGRATED_CYCLE_SECONDS, ANALYTIC_CYCLE_SECONDS = 2.5e-3, 2e-6
#: Such a phase, once its swing has decayed below the integrator's tolerance, takes about this many slip phases'
#: evaluations more (:func:`~faultslip.dynamics.methods.integrator_evaluations`) as its steps lengthen: 44, 39 and 15
#: were measured for DOP853, RK45 and LSODA at rtol 1e-10 on configs/lab_steel_dry_polynomial.toml at 0.01 m/s
#: (benchmarks/slider_simulation_cost.py). Before that it takes about two slip phases' a natural period.
HORIZON_PHASES = 50


def decay_periods(system, rtol: float) -> float:
    """Natural periods a phase that never re-sticks swings before its swing falls below the tolerance's scale
    (rtol x 1e-3 of it, simulate's atol): ln(1e3 / rtol) / (pi gamma), with gamma = (W mu'(V) + eta + C) omega / K
    the damping of the linearised motion about steady sliding at V (the slip phase's Jacobian); the whole horizon
    where gamma is not positive (a weakening law at V swings on) or the law gives no slope there."""
    try:
        slope = float(system.kinetic_law.derivative(system.platform_speed))
    except (AttributeError, TypeError, ValueError, ArithmeticError):
        return float(HORIZON_PERIODS)
    damping = (system.normal_load * slope + system.radiation_damper + system.dashpot) * \
        system.natural_frequency / system.stiffness
    if not damping > 0:
        return float(HORIZON_PERIODS)
    return min(float(HORIZON_PERIODS), math.log(1e3 / rtol) / (math.pi * damping))


def simulation_estimate(cycles: int, samples_per_slip: int, integrated: bool, output=None, system=None,
                        solver: str = "DOP853", rtol: float = 1e-10) -> Estimate:
    """Memory and time of ``simulate``: the time series holds about (samples + 2) rows per cycle.

    An explicit solver (DOP853, RK45, RK23) on a stiff slip phase takes the steps its stability allows, not its
    accuracy's: stages x 2 pi x eps / stability limit a natural period
    (:func:`~faultslip.dynamics.methods.stiff_evaluations`, eps from
    :func:`~faultslip.dynamics.methods.slip_stiffness`). With ``system``, each cycle's slip phase is counted as the
    event-driven method's run counts it (:func:`~faultslip.dynamics.methods.slip_phase_evaluations`: a curved law's
    phase takes more steps than a linear one's), and so is one phase that never re-sticks (steady or sustained
    sliding), integrated to :data:`HORIZON_PERIODS` before the run ends: two slip phases' accurate steps a period
    while it swings (:func:`decay_periods`), :data:`HORIZON_PHASES` more once it has decayed, and an explicit
    solver's stability steps throughout. A run cannot tell before it starts whether its slider re-sticks. A
    polynomial law at 100 m/s had been estimated at 7 ms and took 65 s (benchmarks/slider_simulation_cost.py
    measures it)."""
    rows = float(cycles) * (samples_per_slip + 2)
    memory = rows * 6 * 8.0 * 3  # six columns, about three copies while the dataset is built
    per_cycle, horizon = (INTEGRATED_CYCLE_SECONDS if integrated else ANALYTIC_CYCLE_SECONDS), 0.0
    if integrated and system is not None:
        # each cycle's slip phase as the event-driven method counts it (its run's cost model), at least the typed rate
        accurate, limited = methods.slip_phase_evaluations(system, solver, rtol)
        per_cycle = max(per_cycle, (accurate + limited) * methods.evaluation_time(solver))
        horizon = (HORIZON_PERIODS * limited + (2 * decay_periods(system, rtol) + HORIZON_PHASES) *
                   methods.integrator_evaluations(methods.nearest_calibrated(solver), rtol)) * \
            methods.evaluation_time(solver)
    reference = float(cycles) * per_cycle + horizon + rows * 1e-8
    seconds = machine.on_this_machine(reference, "families")
    # the time series' Dataset, and the integrator or the analytic phases' roots
    imports = (*budget.DATASET_IMPORTS, *(budget.INTEGRATION_IMPORTS if integrated else ("scipy.optimize",)))
    return Estimate(what=f"a simulation of {cycles:.3g} cycles", memory=memory, disk=rows * 6 * 8.0 if output else 0.0,
                    seconds=seconds, output=output, imports=imports)


def simulation_solver(system, settings: dict) -> tuple[bool, str]:
    """Whether ``simulate`` integrates the slip phases, and by which solver ("auto": analytic on a linear kinetic
    law, DOP853 otherwise, as :func:`~faultslip.dynamics.spring_slider.simulate.simulate` chooses)."""
    solver = resolved_solver(system, settings.get("slip_solver", "auto"))
    return solver != "analytic", solver


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
    if slip_solver is not None:
        settings["slip_solver"] = slip_solver
    system = loaded.slider()
    integrated, solver = simulation_solver(system, settings)
    return simulation_estimate(settings.get("cycles", 100), settings.get("samples_per_slip", 64), integrated, output,
                               system, solver, settings.get("rtol", 1e-10))
