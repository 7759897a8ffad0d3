"""The 3-D fault's cost model: its steps from the events a run will see, its weakening patch's width over h* and
its columns along strike, each step's CPU from the operator's shape, and the memory of the operator and the
records; the family declares it.

Fitted by ``benchmarks/fault_3d_cost.py`` on 3-D faults of each kind the rung builds (SEAS BP5-QD, BP5's patches at
1/20 buried and breaking the surface, 2-D scenes read as 3-D faults, a dipping one among them), the operator's
assembly timed apart; ``tests/models/fault_3d/test_fault_3d.py`` refits it from that results file and holds the
held-out draw's estimates within 2x of the CPU each used, and 95 % of the fresh draws' (one of 70 is at 2.15x: a
patch at W / h* 1.03 that ruptured once where the estimate expected 19.7 events).
"""

from __future__ import annotations

import math

from faultslip.fault.ladder import expected_recurrence as one_slider_recurrence
from faultslip.io import machine
from faultslip.io.budget import Estimate, with_one_off

#: Steps of a run: A events^p (W / h*)^q N_x^r exp(u B) R^s (rtol / 1e-6)^rtol, least squares in ln steps over the
#: fit runs, the cells benchmarks/fault_3d_model_error.py records and the runs of benchmarks/fault_3d_resolution.py's
#: draw (eight patches at 100, 50 and 25 m; their steps do not depend on the machine): more events, more partial
#: ruptures (W >> h*) and more columns along strike each cost steps; a buried patch (B, its top's depth over its
#: width, :func:`faultslip.fault.strike_error.groups_of`) costs fewer than the events its middle column's one slider
#: expects; finer squares (R squares per L_b) resolve faster ruptures, in shorter steps. Without R the steps of 25 m
#: squares were 0.55-1.01x of the model's. The rtol power is the 2-D fault's (FAULT_2D_STEPS, -0.18); measured on
#: the 3-D fault (--part rtol: three faults at rtol 1e-5 to 1e-8) it is -0.155 pooled (-0.149 to -0.163 per fault),
#: 6 % a decade of rtol from it. A central estimate: the measured steps lie within 0.62-1.40x of the fit's (71 runs;
#: 0.66-1.57x without R); on the resolution benchmark's five held-out patches (15 runs at 100-25 m), 0.82-1.20x
#: (0.73-1.18x and a wider spread without R). The burial and R are held to the fitted runs' ranges (a patch buried
#: deeper, or squares finer, would otherwise extrapolate past them). The events are counted by the recurrence the one
#: slider expects (outside its box, the correction at the box's nearest point:
#: faultslip.fault.ladder.expected_recurrence). Without the burial, and with a margin of 1.4 that put the estimate
#: above all but the slowest runs, a second held-out draw's small buried patch (2 x 400 m, 300 m deep, W / h* 1.03:
#: one event where its one slider expects 20) was estimated at 2.96x its CPU.
FAULT_3D_STEPS = {"scale": 38.64, "events": 1.084, "width_over_nucleation": 1.023, "strike_columns": 0.660,
                  "burial": -1.630, "burial_fitted": 0.4375, "resolution": 0.163, "resolution_fitted": [2.294, 13.39],
                  "rtol": -0.18}
#: CPU seconds per Dormand-Prince step: c0 + c1 N + c2 k (N_x + 1) N_z^2 (the element-wise work, and the
#: per-frequency N_z x N_z products of the FFT along strike, k of them a force balance: 2 where the normal stress
#: changes), relative non-negative least squares over the fit runs' steps, their operator's assembly timed apart
#: (benchmarks/fault_3d_cost.py: 12 runs, 792-22,560 squares, within 0.72-1.15x of each).
FAULT_3D_STEP_SECONDS = (2.214e-4, 1.577e-7, 9.734e-9)
#: CPU seconds per (triangle, observation point) pair of the half-space strain (cutde on one thread: its OpenMP
#: runtime is held to one, kernel._cutde): the median over benchmarks/fault_3d_cost.py's fit runs that spent a second
#: or more assembling (3.3-4.0e-6 s; strike-slip and dipping). The operator benchmark's assemblies, timed in wall
#: time on a busier machine, gave 8.1e-6.
FAULT_3D_PAIR_SECONDS = 3.315e-6


def expected_recurrence(fault) -> float:
    """The recurrence the one-slider rung expects of the fault's middle column (s): a rough count of the events a
    run will see (:func:`faultslip.fault.ladder.expected_recurrence`)."""
    return one_slider_recurrence(fault.description())


def products(fault) -> int:
    """The spectral products each force balance makes: the shear's, and the normal stress's where slip changes it
    (a dipping fault, or a rake other than along strike:
    :class:`~faultslip.models.fault_3d.kernel.StrikeConvolution`)."""
    return 1 if (fault.dip == 90.0 and fault.rake == "strike") else 2


def steps(strike_count: int, events: float, width_over_nucleation: float, rtol: float, burial: float = 0.0,
          resolution: float = math.nan, model: dict | None = None) -> float:
    """Dormand-Prince steps of a run seeing ``events`` system-size events (at least one's worth) on a fault of
    ``strike_count`` columns whose weakening patch is ``width_over_nucleation`` h* wide and buried ``burial`` of
    its width, on ``resolution`` squares per L_b (:data:`FAULT_3D_STEPS`, or ``model``, a fit of the same form;
    the burial and the resolution held to the fitted ranges; a fault that does not weaken, NaN, creeps: W / h*
    0.1, burial 0; an unknown resolution, NaN, is the fitted range's lowest)."""
    model = FAULT_3D_STEPS if model is None else model
    burial = min(burial, model["burial_fitted"]) if math.isfinite(burial) and burial > 0.0 else 0.0
    lowest, highest = model["resolution_fitted"]
    resolution = min(max(resolution, lowest), highest) if math.isfinite(resolution) else lowest
    return (model["scale"] * max(events, 1.0) ** model["events"]
            * (width_over_nucleation if width_over_nucleation > 0.1 else 0.1) ** model["width_over_nucleation"]
            * strike_count ** model["strike_columns"] * math.exp(model["burial"] * burial)
            * resolution ** model["resolution"] * (rtol / 1e-6) ** model["rtol"])


def assembly_pairs(strike_count: int, dip_count: int) -> int:
    """(Source triangle, observation point) pairs the operator's assembly evaluates: every strike offset's
    dislocations, three triangles a square."""
    return 3 * (2 * strike_count - 1) * dip_count ** 2


def assembly_seconds(strike_count: int, dip_count: int) -> float:
    """CPU seconds to assemble the operator, at :data:`FAULT_3D_PAIR_SECONDS` a pair (:func:`assembly_pairs`), on
    this machine now (:mod:`faultslip.io.machine`)."""
    return machine.on_this_machine(assembly_pairs(strike_count, dip_count) * FAULT_3D_PAIR_SECONDS, "fault_3d")


def step_seconds(strike_count: int, dip_count: int, products: int = 1) -> float:
    """CPU seconds per step on N_x x N_z squares, ``products`` spectral products a force balance (:func:`products`),
    on this machine now (:mod:`faultslip.io.machine`)."""
    c0, c1, c2 = FAULT_3D_STEP_SECONDS
    return machine.on_this_machine(c0 + c1 * strike_count * dip_count
                                   + c2 * products * (strike_count + 1) * dip_count ** 2, "fault_3d")


def operator_bytes(strike_count: int, dip_count: int, normal_changes: bool = False) -> float:
    """The operator's spectra: (N_x + 1) complex N_z x N_z blocks each, for the shear, the cross-rake diagnostic and,
    on a fault whose normal stress changes, the normal stress."""
    return (3 if normal_changes else 2) * (strike_count + 1) * dip_count ** 2 * 16.0


def estimate(strike_count: int, dip_count: int, years: float, stations: int, output=None, *, events: float,
             width_over_nucleation: float, rtol: float, burial: float = 0.0, resolution: float = math.nan,
             products: int = 1, first_run: tuple = (0.0, "")) -> Estimate:
    """Time, memory and disk of a run (station rows every step, in memory and as SEAS text); ``burial``: the
    weakening patch's top over its width, ``resolution``: squares per L_b (:func:`steps`); ``products``: the spectral
    products a force balance makes (:func:`products`); ``first_run``: seconds its process spends before the first
    step, and on what."""
    count = steps(strike_count, events, width_over_nucleation, rtol, burial, resolution)
    elements = strike_count * dip_count
    what, seconds = with_one_off(f"a 3-D fault run of {strike_count} x {dip_count} squares over {years:.4g} yr "
                                 f"(about {count:.3g} steps)", count * step_seconds(strike_count, dip_count, products)
                                 + assembly_seconds(strike_count, dip_count), first_run)
    return Estimate(what=what, seconds=seconds,
                    memory=operator_bytes(strike_count, dip_count, products > 1) + count * (1 + 4 * stations) * 8.0 * 2
                    + 40 * elements * 8.0,
                    disk=count * stations * 100.0 + (years / 5 + 200 * max(events, 1.0)) * elements * 16.0
                    if output else 0.0, output=output)


def describe() -> str:
    """The cost model in words ('faultslip methods')."""
    c0, c1, c2 = FAULT_3D_STEP_SECONDS
    model = FAULT_3D_STEPS
    return (f"steps ~ {model['scale']:.3g} events^{model['events']:.3g} "
            f"(W / h*)^{model['width_over_nucleation']:.3g} N_x^{model['strike_columns']:.3g} "
            f"exp({model['burial']:.3g} burial) (squares per L_b)^{model['resolution']:.3g} "
            f"(rtol / 1e-6)^{model['rtol']:g}; "
            f"each {c0:.2g} + {c1:.2g} N + {c2:.2g} k (N_x + 1) N_z^2 s of CPU "
            "(FFT along strike, dense down dip; k = 2 where the normal stress changes), and the assembly "
            f"{FAULT_3D_PAIR_SECONDS:.2g} s a dislocation pair; "
            "memory (N_x + 1) N_z^2 x 16 B a spectrum (two; three where the normal stress changes)")

