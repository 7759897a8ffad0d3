"""The 2-D fault's cost model: its steps from the events a run will see, each step's CPU (the FFT step, and the
plane-strain fault's dense one), and the scenes it was fitted on; the family declares it."""

from __future__ import annotations

import math

from faultslip.io import machine
from faultslip.io.budget import Estimate, with_one_off


#: A 2-D fault run's steps per simulated year (benchmarks/fault_2d_cost.py fits it to measured step counts,
#: which do not depend on the machine): A (V_pl / 1e-9 m/s) (W / h*) (rtol / 1e-7)^-0.18 g(h / L_b), where
#: W is the velocity-weakening width, h* the nucleation size, L_b the process zone and h the element size.
#: More cycles (a faster plate) and more partial ruptures (W >> h*) cost steps in proportion; an element
#: coarser than L_b makes the sequence irregular (g = (h / L_b)^0.31) and a finer one sharpens the fronts
#: (g grows as (L_b / h)^0.45 below h = L_b / 4, from BP1 at 50 and 25 m). Fitted over D_c 6-48 mm,
#: V_pl 1e-10 to 1e-8 m/s, h 250 m to 2 km, rtol 1e-7 and 1e-5, and BP1: within 0.75-1.4x of the measured
#: steps; the estimate takes twice the fit, so that it errs long.
FAULT_2D_STEPS = {"scale": 15.0, "plate_rate": 1.02, "width_over_nucleation": 0.99, "rtol": -0.18,
                  "coarse": 0.31, "fine": 0.45, "fine_below": 0.25, "margin": 2.0}
#: CPU seconds per Dormand-Prince step (six force balances and the stress kernel) on N elements with the whole step
#: compiled (numba and rocket-fft, the FFT kernel): c0 + c1 N, least squares in relative terms (each run's error
#: counts alike) over the twelve runs of benchmarks/ladder_escalations.py's first draw (seed 68000: 172-1,036
#: elements, rtol 1e-8, two runs at a time on the 2-core machine), within 0.88-1.08x of each
#: (tests/models/fault_2d/test_budget_fit.py refits it). Fitted on runs above 512 elements only, the line overstated
#: the smaller faults' steps by up to 1.6x. Another step path scales it by its measured cost
#: (:func:`faultslip.models.fault_2d.kernel.relative_step_cost`).
FAULT_2D_STEP_SECONDS = (2.031e-5, 2.702e-7, 1.0)
#: CPU seconds per step of a plane-strain (dipping) 2-D fault, whose kernels are dense: c0 + c2 N^2, fitted by
#: benchmarks/plane_strain_step.py (SEAS BP3-QD on 50-1,600 elements over 200 yr, within 1.29x of each;
#: tests/models/fault_2d/test_budget_fit.py refits it from benchmarks/results/plane_strain_step.json). Fitted on
#: 200-1,600 elements over 60 yr (100-700 steps a size), c0 had been 3x a small fault's step.
PLANE_STRAIN_STEP_SECONDS = (1.405e-4, 4.204e-9)
#: CPU seconds a process's first compiled 2-D run spends beyond its steps, per step path (the whole step fused, or the
#: force balance and stages compiled: a dense kernel's; a dipping or 3-D fault's step loads a part of them) and build
#: (one thread or several): "load", numba's cached step loaded into the process; "compile", compiled into an empty
#: cache (a fresh environment, or a new faultslip), once. Medians of benchmarks/first_run.py --part first-run (the
#: first run's CPU less a second run's, after the estimate that tells which applies); test_budget_fit.py checks them.
FAULT_2D_FIRST_RUN_SECONDS = {"fused serial": {"load": 0.998, "compile": 20.0},
                              "fused parallel": {"load": 1.1, "compile": 90.9},
                              "compiled serial": {"load": 0.967, "compile": 3.76},
                              "compiled parallel": {"load": 1.11, "compile": 9.46}}
#: Steps from the events a run will see (issue 68):
#:     steps = A events (W / h*)^q (W / L_b)^r (L_b / h / 3)^s (rtol / 1e-8)^-0.18 + 100,
#: events^1 since a settled sequence takes the same steps each cycle; A, q, r least squares over the 36 calibration
#: runs of benchmarks/ladder_designs.py (3 elements per L_b, rtol 1e-8), a run's events its duration over the
#: recurrence the one-slider rung expects; s over the first escalation draw's runs (3-5 per L_b), through the
#: calibration's level at 3 (benchmarks/fault_2d_event_steps.py fits it; tests/models/fault_2d/test_budget_fit.py
#: refits it). The earlier model, events^0.78 (W / h*)^0.51 N^0.58, fitted the events' power across faults, where it
#: stood in for the groups as well, and counted the elements whole, the creeping zone below included: on the 34
#: held-out designs it was 0.73-2.10x of the steps, this one 0.68-1.57x; on the 57 first runs of five later
#: escalation draws, 0.64-2.71x against 0.73-1.81x. FAULT_2D_STEPS' rtol factor carries it to other tolerances.
FAULT_2D_EVENT_STEPS = {"scale": math.exp(5.456), "width_over_nucleation": 0.345, "width_over_process_zone": 0.699,
                        "elements_per_process_zone": 0.496, "resolution": 3.0, "rtol": 1e-8}


#: The scenes the 2-D step models were fitted on: W / h* at the weakest element (FAULT_2D_STEPS' BP1 at D_c 6-48 mm
#: gives 0.55-4.4; the ladder designs 1.56-7.88) and the normal stress on the velocity-weakening part (BP1's
#: 50 MPa; the designs 25.1-99.0 MPa), each rounded outward (tests/models/fault_2d/test_budget_fit.py recomputes them). A scene
#: outside them (a sigma_n of 1e-6 MPa, or one falling to 0.01 MPa in the weakening zone) can step far more
#: often than either model knows: :func:`check` refuses it without --allow-large.
FAULT_2D_FITTED = {"width_over_nucleation": (0.5, 8.0), "normal_stress": (25e6, 100e6)}


def fault_2d_outside_fit(*, width_over_nucleation: float, normal_stress_low: float,
                         normal_stress_high: float) -> tuple:
    """Where a 2-D scene lies outside :data:`FAULT_2D_FITTED`, as sentences (empty: inside)."""
    low, high = FAULT_2D_FITTED["width_over_nucleation"]
    out = []
    if not low <= width_over_nucleation <= high:
        out.append(f"its W/h* is {width_over_nucleation:.3g}, fitted {low:g} to {high:g}")
    low, high = FAULT_2D_FITTED["normal_stress"]
    if normal_stress_low < low or normal_stress_high > high:
        out.append(f"its normal stress on the weakening part spans {normal_stress_low / 1e6:.3g} to "
                   f"{normal_stress_high / 1e6:.3g} MPa, fitted {low / 1e6:g} to {high / 1e6:g} MPa")
    return tuple(out)


def _resolution_factor(ratio: float) -> float:
    """How the steps grow with the element size h over L_b (:data:`FAULT_2D_STEPS`)."""
    c = FAULT_2D_STEPS
    ratio = min(max(ratio, 1e-6), 1e6)
    return ratio ** c["coarse"] * max(1.0, c["fine_below"] / ratio) ** c["fine"]


def event_step_groups(*, events: float, seismogenic_width: float, element_size: float, nucleation_size: float,
                      process_zone: float) -> dict:
    """The groups :data:`FAULT_2D_EVENT_STEPS` counts steps by: the events a run will see, the weakening width W
    over the nucleation size h* and over the process zone L_b (W at least one element)."""
    width = max(seismogenic_width, element_size)
    return {"events": events, "width_over_nucleation": width / nucleation_size,
            "width_over_process_zone": width / process_zone}


def fault_2d_steps(*, years: float, plate_rate: float, element_size: float, process_zone: float,
                   nucleation_size: float, seismogenic_width: float, rtol: float,
                   events: float | None = None) -> float:
    """Steps a 2-D fault run takes over ``years``: from the ``events`` it will see where they are known
    (:data:`FAULT_2D_EVENT_STEPS`, a central estimate), else an upper estimate from :data:`FAULT_2D_STEPS`."""
    c = FAULT_2D_STEPS
    # a fault without weakening (b = 0 everywhere: L_b infinite) creeps: its resolution costs nothing extra
    ratio = element_size / process_zone if 0 < process_zone < math.inf else 1.0
    resolution = _resolution_factor(ratio)
    partial = max(seismogenic_width, element_size) / nucleation_size if math.isfinite(nucleation_size) else 0.1
    if events is not None and events > 0 and math.isfinite(nucleation_size) and 0 < process_zone < math.inf:
        e = FAULT_2D_EVENT_STEPS
        groups = event_step_groups(events=events, seismogenic_width=seismogenic_width, element_size=element_size,
                                   nucleation_size=nucleation_size, process_zone=process_zone)
        return (e["scale"] * events * groups["width_over_nucleation"] ** e["width_over_nucleation"]
                * groups["width_over_process_zone"] ** e["width_over_process_zone"]
                * (process_zone / element_size / e["resolution"]) ** e["elements_per_process_zone"]
                * (rtol / e["rtol"]) ** c["rtol"]) + 100.0
    per_year = (c["scale"] * (plate_rate / 1e-9) ** c["plate_rate"] * partial ** c["width_over_nucleation"]
                * (rtol / 1e-7) ** c["rtol"] * resolution)
    return c["margin"] * per_year * years + 100.0


def fault_2d_first_run(*, fused: bool, threads: int, compile: bool) -> tuple[float, str]:
    """The first-run cost (:data:`FAULT_2D_FIRST_RUN_SECONDS`) of a process that does not hold the compiled step
    yet, and what it is spent on."""
    key = f"{'fused' if fused else 'compiled'} {'parallel' if threads > 1 else 'serial'}"
    seconds = FAULT_2D_FIRST_RUN_SECONDS[key]["compile" if compile else "load"]
    # measured the day the step's cost was (first_run.json, ladder_escalations.json): carried to this machine with it
    seconds = machine.on_this_machine(seconds, "fault_2d_step")
    if compile:
        return seconds, "to compile the 2-D step for this environment, once"
    return seconds, "to load the compiled 2-D step into this process"


def fault_2d_estimate(elements: int, years: float, stations: int, output=None, *, steps: float,
                      outside_fit: tuple = (), step_cost: float = 1.0, plane_strain: bool = False,
                      first_run: tuple = (0.0, "")) -> Estimate:
    """Time, memory and disk of a 2-D fault run of ``steps`` steps (:func:`fault_2d_steps`): station rows every
    step (in memory, and as SEAS text); its seconds this machine's now (:mod:`faultslip.io.machine`).
    ``plane_strain``: a dipping fault's dense step (:data:`PLANE_STRAIN_STEP_SECONDS`), and its two N x N kernels in
    memory. ``first_run``: seconds the process spends before its first step, and on what
    (:func:`fault_2d_first_run`)."""
    c0, c1, margin = FAULT_2D_STEP_SECONDS
    kernels = 0.0
    if plane_strain:
        dense0, dense2 = PLANE_STRAIN_STEP_SECONDS
        per_step = machine.on_this_machine(dense0 + dense2 * elements ** 2, "plane_strain_step")
        step_cost, kernels = 1.0, 2 * 8.0 * elements ** 2 * 2
    else:
        per_step = machine.on_this_machine(c0 + c1 * elements, "fault_2d_step")
    what, seconds = with_one_off(f"a 2-D fault run of {elements} elements over {years:.4g} yr (about {steps:.3g} steps)",
                                 margin * steps * per_step * step_cost, first_run)
    return Estimate(what=what, seconds=seconds,
                    memory=steps * (1 + 4 * stations) * 8.0 * 2 + kernels,
                    disk=steps * stations * 100.0 if output else 0.0, output=output, outside_fit=outside_fit)
