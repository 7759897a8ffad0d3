"""The 3-D fault's cost model: its steps from the events a run will see and its squares' size, each step's CPU from
the operator's shape, and the memory of the operator and the records; the family declares it.

Fitted on the runs ``benchmarks/seas_bp5.py`` saves (SEAS BP5-QD at 2000 to 250 m, rtol 1e-6) and, for the
operator's assembly, on ``benchmarks/fault_3d_operator.py``'s; ``tests/models/fault_3d/test_fault_3d.py`` refits both from those
results files and holds each run's estimate within 2x of the CPU it used.
"""

from __future__ import annotations

from faultslip.fault.ladder import expected_recurrence as one_slider_recurrence
from faultslip.io.budget import Estimate, with_one_off

#: Steps per system-size event: scale (N_z / 20)^dip_rows (rtol / 1e-6)^rtol, times a margin so that the estimate
#: errs long; scale and dip_rows fitted on BP5's runs (benchmarks/seas_bp5.py), the rtol power the 2-D fault's
#: (FAULT_2D_STEPS, -0.18), not measured on the 3-D fault.
FAULT_3D_STEPS = {"scale": 663.6, "dip_rows": 0.851, "rtol": -0.18, "margin": 1.2}
#: CPU seconds per Dormand-Prince step: c0 + c1 N + c2 N_x N_z^2 (the element-wise work, and the per-frequency
#: N_z x N_z products of the FFT along strike): non-negative least squares, relative, over BP5's runs at 2000, 1000
#: and 500 m (within 0.76-1.19x of each; the element-wise term fits to zero beside the products).
FAULT_3D_STEP_SECONDS = (5.806e-4, 0.0, 2.674e-8)
#: CPU seconds per (triangle, observation point) pair of the half-space strain (cutde on one thread: its OpenMP
#: runtime is held to one, kernel._cutde), from the operator benchmark's assembly times.
FAULT_3D_PAIR_SECONDS = 8.1e-6


def expected_recurrence(fault) -> float:
    """The recurrence the one-slider rung expects of the fault's middle column (s): a rough count of the events a
    run will see (:func:`faultslip.fault.ladder.expected_recurrence`)."""
    return one_slider_recurrence(fault.description())


def steps(dip_count: int, events: float, rtol: float) -> float:
    """Dormand-Prince steps of a run seeing ``events`` system-size events (at least one's worth)."""
    model = FAULT_3D_STEPS
    return (model["margin"] * model["scale"] * max(events, 1.0) * (dip_count / 20.0) ** model["dip_rows"]
            * (rtol / 1e-6) ** model["rtol"])


def assembly_seconds(strike_count: int, dip_count: int) -> float:
    """CPU seconds to assemble the operator: every strike offset's dislocations, three triangles a square, at
    :data:`FAULT_3D_PAIR_SECONDS` a (source triangle, observation point) pair."""
    return 3.0 * (2 * strike_count - 1) * dip_count ** 2 * FAULT_3D_PAIR_SECONDS


def step_seconds(strike_count: int, dip_count: int) -> float:
    """CPU seconds per step on N_x x N_z squares."""
    c0, c1, c2 = FAULT_3D_STEP_SECONDS
    return c0 + c1 * strike_count * dip_count + c2 * strike_count * dip_count ** 2


def operator_bytes(strike_count: int, dip_count: int, normal_changes: bool = False) -> float:
    """The operator's spectra: (N_x + 1) complex N_z x N_z blocks each, for the shear, the cross-rake diagnostic and,
    on a fault whose normal stress changes, the normal stress."""
    return (3 if normal_changes else 2) * (strike_count + 1) * dip_count ** 2 * 16.0


def estimate(strike_count: int, dip_count: int, years: float, stations: int, output=None, *, events: float,
             rtol: float, first_run: tuple = (0.0, "")) -> Estimate:
    """Time, memory and disk of a run (station rows every step, in memory and as SEAS text); ``first_run``: seconds
    its process spends before the first step, and on what."""
    count = steps(dip_count, events, rtol)
    elements = strike_count * dip_count
    what, seconds = with_one_off(f"a 3-D fault run of {strike_count} x {dip_count} squares over {years:.4g} yr "
                                 f"(about {count:.3g} steps)", count * step_seconds(strike_count, dip_count)
                                 + assembly_seconds(strike_count, dip_count), first_run)
    return Estimate(what=what, seconds=seconds,
                    memory=operator_bytes(strike_count, dip_count) + count * (1 + 4 * stations) * 8.0 * 2
                    + 40 * elements * 8.0,
                    disk=count * stations * 100.0 + (years / 5 + 200 * max(events, 1.0)) * elements * 16.0
                    if output else 0.0, output=output)


def describe() -> str:
    """The cost model in words ('faultslip methods')."""
    c0, c1, c2 = FAULT_3D_STEP_SECONDS
    model = FAULT_3D_STEPS
    return (f"steps ~ {model['margin'] * model['scale']:g} per event (N_z / 20)^{model['dip_rows']:g} "
            f"(rtol / 1e-6)^{model['rtol']:g}; each {c0:.2g} + {c1:.2g} N + {c2:.2g} N_x N_z^2 s of CPU "
            f"(FFT along strike, dense down dip), and the assembly {FAULT_3D_PAIR_SECONDS:.2g} s a dislocation pair; "
            "memory (N_x + 1) N_z^2 x 16 B a spectrum (two; three where the normal stress changes)")

