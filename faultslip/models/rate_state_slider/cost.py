"""The rate-and-state slider's cost model: a laboratory slider's load history at its overhead, a fault's one
slider in earthquake cycles; fitted by ``benchmarks/family_costs.py``. A run whose tolerance sends it to the 2-D
fault checks that rung's own estimate before it starts (faultslip.models.fault_2d)."""

from __future__ import annotations

import os

from faultslip.dynamics.rate_state.methods import SECONDS_PER_STEP, cycle_steps
from faultslip.dynamics.rate_state.slider import CYCLES_RTOL, cycle_method, cycles_stiffness_ratio
from faultslip.fault.scene import Scene, has_friction_law
from faultslip.models.rate_state_slider.scene import read_rate_state_scene
from faultslip.io import budget

#: the cycles a fault's run and simulation take by default (the family's)
DEFAULT_CYCLES = 5


def _older_form(scene) -> bool:
    """A seed-law-form scene ([friction] law = "rate_state"), costed by its own entry."""
    return isinstance(scene, Scene) or (isinstance(scene, (str, os.PathLike))
                                        and has_friction_law(scene, "rate_state"))


def work(scene, action: str = "run", cycles=None, **_) -> tuple[str, float, str]:
    """(cost entry, units, what): earthquake cycles of a fault's slider; a laboratory slider's history or a
    seed-law-form scene at the entry's overhead."""
    count = float(DEFAULT_CYCLES if cycles is None else cycles)
    if _older_form(scene):
        return f"{action}:seed_law_form", count, f"{count:g} cycles of a rate-and-state fault (seed-law form)"
    loaded = read_rate_state_scene(scene)
    if loaded.kind == "lab":
        return f"{action}:lab", 0.0, "a laboratory slider's load history"
    count = float(DEFAULT_CYCLES if cycles is None or action == "run" else cycles)
    if action == "run":  # the one slider derived from the profile: closed form
        return action, count, f"{count:g} earthquake cycles of one slider"
    steps = simulation_steps(loaded.slider, count)
    return action, steps, f"{count:g} earthquake cycles of one slider (about {steps:.3g} dopri5 steps' work)"


def simulation_steps(slider, cycles: float) -> float:
    """A simulation's work in dopri5 steps: the steps its integrator takes to settle and record ``cycles``
    (:func:`~faultslip.dynamics.rate_state.methods.cycle_steps`), LSODA's weighted by its cost per step over
    dopri5's. A two-state law (dopri5, its K_c not the one-state one) counts the steps accuracy needs."""
    ratio = cycles_stiffness_ratio(slider)
    if not ratio < 1:  # stable: refused before any integration
        return 0.0
    method = cycle_method("auto", ratio, slider.law, record=True)
    if slider.law.two_state:
        ratio = 0.5  # the one-state stiff limit does not apply; accuracy's steps, settling far from K_c
    a_over_b = slider.law.a / slider.law.b if slider.law.b > 0 else 0.0
    return (cycle_steps(method, CYCLES_RTOL, ratio, a_over_b, cycles)
            * SECONDS_PER_STEP[method] / SECONDS_PER_STEP["dopri5"])


def cycles_imports(scene) -> tuple:
    """What a fault's recorded cycles import beside their Dataset: scipy's integrators where they are LSODA's (a
    stiff rupture, K / K_c below about 0.015: :func:`~faultslip.dynamics.rate_state.slider.cycle_method`, as
    the simulation chooses), nothing for dopri5 (0.1-0.2 s a small simulation's estimate had left out)."""
    ratio = cycles_stiffness_ratio(scene.slider)
    if not ratio < 1:  # stable: refused before any integration
        return ()
    return ("scipy.integrate",) if cycle_method("auto", ratio, scene.slider.law, record=True) == "lsoda" else ()


def estimate(scene, action: str = "run", **options) -> budget.Estimate:
    """What a run or simulation of a rate-and-state scene needs, before it starts."""
    scene = scene if _older_form(scene) else read_rate_state_scene(scene)  # read once, for work and imports
    entry, units, what = work(scene, action, **options)
    # a laboratory slider's history is integrated by the compiled Dormand-Prince (numba's extensions load with
    # it, and its LAPACK bindings from scipy.linalg) into a Dataset; a simulation's cycles are a Dataset too,
    # stepped by LSODA where the rupture is stiff; a fault's one-slider run is closed form
    imports = ((*budget.DATASET_IMPORTS, budget.NUMBA_EXTENSIONS, "scipy.linalg") if entry.endswith(":lab")
               else (*budget.DATASET_IMPORTS, *cycles_imports(scene))
               if entry == "simulate" else budget.DATASET_IMPORTS if action == "simulate" else ())
    return budget.fitted_estimate("rate_state_slider", entry, units, what, output=options.get("output"),
                                  imports=imports)
