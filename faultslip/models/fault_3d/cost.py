"""The 3-D fault's cost model: its steps from the events a run will see, its weakening patch's width over h* and
its columns along strike, each step's CPU from the operator's shape, and the memory of the operator and the
records; the family declares it.

Fitted by ``benchmarks/fault_3d_cost.py`` on 3-D faults of each kind the rung builds (SEAS BP5-QD, BP5's patches at
1/20 buried and breaking the surface, 2-D scenes read as 3-D faults, a dipping one among them), the operator's
assembly timed apart; ``tests/models/fault_3d/test_fault_3d.py`` refits it from that results file and holds the
held-out draw's estimates within 2x of the CPU each used.
"""

from __future__ import annotations

import math

from faultslip.fault.ladder import expected_recurrence as one_slider_recurrence
from faultslip.io import machine
from faultslip.io.budget import Estimate, with_one_off

#: Steps of a run: A events^p (W / h*)^q N_x^r exp(u B) (rtol / 1e-6)^rtol, least squares in ln steps over the fit
#: runs and the cells benchmarks/fault_3d_model_error.py records (their steps do not depend on the machine): more
#: events, more partial ruptures (W >> h*) and more columns along strike each cost steps; a buried patch (B, its
#: top's depth over its width, :func:`faultslip.fault.strike_error.groups_of`) costs fewer than the events its
#: middle column's one slider expects. The rtol power is the 2-D fault's (FAULT_2D_STEPS, -0.18); measured on the
#: 3-D fault (--part rtol: three faults at rtol 1e-5 to 1e-8) it is -0.155 pooled (-0.149 to -0.163 per fault), 6 %
#: a decade of rtol from it. A central estimate: the measured steps lie within 0.64-1.30x of the fit's (47 runs;
#: 0.70-1.49x without the burial). The burial is held to the fitted runs' largest, 0.375 (a patch buried deeper
#: would otherwise extrapolate the exponential past them). The events are counted by the recurrence the one slider
#: expects (outside its box, the correction at the box's nearest point: faultslip.fault.ladder.expected_recurrence).
#: Without the burial, and with a margin of 1.4 that put the estimate above all but the slowest runs, a second held-out
#: draw's small buried patch (2 x 400 m, 300 m deep, W / h* 1.03: one event where its one slider expects 20) was
#: estimated at 2.96x its CPU.
FAULT_3D_STEPS = {"scale": 44.55, "events": 1.077, "width_over_nucleation": 1.016, "strike_columns": 0.676,
                  "burial": -1.809, "burial_fitted": 0.375, "rtol": -0.18}
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


def steps(strike_count: int, events: float, width_over_nucleation: float, rtol: float, burial: float = 0.0) -> float:
    """Dormand-Prince steps of a run seeing ``events`` system-size events (at least one's worth) on a fault of
    ``strike_count`` columns whose weakening patch is ``width_over_nucleation`` h* wide and buried ``burial`` of
    its width (:data:`FAULT_3D_STEPS`, the burial held to the fitted range; a fault that does not weaken, NaN,
    creeps: W / h* 0.1, burial 0)."""
    model = FAULT_3D_STEPS
    burial = min(burial, model["burial_fitted"]) if math.isfinite(burial) and burial > 0.0 else 0.0
    return (model["scale"] * max(events, 1.0) ** model["events"]
            * (width_over_nucleation if width_over_nucleation > 0.1 else 0.1) ** model["width_over_nucleation"]
            * strike_count ** model["strike_columns"] * math.exp(model["burial"] * burial)
            * (rtol / 1e-6) ** model["rtol"])


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
             width_over_nucleation: float, rtol: float, burial: float = 0.0, products: int = 1,
             first_run: tuple = (0.0, "")) -> Estimate:
    """Time, memory and disk of a run (station rows every step, in memory and as SEAS text); ``burial``: the
    weakening patch's top over its width (:func:`steps`); ``products``: the spectral products a force balance makes
    (:func:`products`); ``first_run``: seconds its process spends before the first step, and on what."""
    count = steps(strike_count, events, width_over_nucleation, rtol, burial)
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
            f"exp({model['burial']:.3g} burial) (rtol / 1e-6)^{model['rtol']:g}; "
            f"each {c0:.2g} + {c1:.2g} N + {c2:.2g} k (N_x + 1) N_z^2 s of CPU "
            "(FFT along strike, dense down dip; k = 2 where the normal stress changes), and the assembly "
            f"{FAULT_3D_PAIR_SECONDS:.2g} s a dislocation pair; "
            "memory (N_x + 1) N_z^2 x 16 B a spectrum (two; three where the normal stress changes)")

