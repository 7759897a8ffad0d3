"""The 2-D runs behind the one slider's declared model error: the block against the 2-D fault it stands for,
over W / h* (``python benchmarks/fault_2d_calibration.py`` writes ``data/fault_2d_model_error.json``; the
one slider's family reads it, :mod:`faultslip.models.rate_state_slider.model_error`)."""

from __future__ import annotations

import math
from dataclasses import replace
from datetime import datetime, timezone

import numpy as np

from faultslip import __version__
from faultslip.dynamics.rate_state.slider import fault_cycles
from faultslip.errors import InputError
from faultslip.friction.rate_state import nucleation_ratio
from faultslip.models.fault_2d.analysis import summarise
from faultslip.models.fault_2d.integrate import YEAR
from faultslip.models.fault_2d.scene import from_one_slider

#: W / h* of the shipped calibration.
RATIOS = (1.25, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0)

def _scene_at_ratio(scene, ratio: float):
    law = scene.law
    current = nucleation_ratio(law, scene.fault["shear_modulus"], scene.fault["normal_stress"],
                               scene.fault["zone_width"])
    changed = replace(law, critical_slip=law.critical_slip * current / ratio)
    return replace(scene, law=changed, slider=replace(scene.slider, law=changed))


def compare(scene, elements_per_process_zone: float = 4.0, cycles: int = 10, rtol: float = 1e-7) -> dict:
    """One slider against the 2-D fault it stands for: recurrence and slip per event of both."""
    law, fault = scene.law, scene.fault
    width = fault["zone_width"]
    process = fault["shear_modulus"] * law.critical_slip / (fault["normal_stress"] * law.b)
    count = max(16, int(math.ceil(width / (process / elements_per_process_zone))))
    block = fault_cycles(scene.slider, scene.plate_rate, cycles=5)
    # long enough for the spin-up and ``cycles`` events at the block's recurrence (the 2-D one is shorter)
    duration = (cycles + 3) * block.recurrence
    two_d = from_one_slider(scene, element_size=width / count, duration=duration)
    run = two_d.run(rtol)
    summary = summarise(run, tolerance=0.01)
    starts, slip = run.events["start"], run.events["slip"]
    system = np.flatnonzero(slip[:, 0] >= 0.5 * slip[:, 0].max()) if starts.size else np.empty(0, int)
    later = system[1:]  # the first event follows the start-up, not a cycle
    if later.size < 2:
        raise InputError(f"the 2-D fault had {system.size} system-size events in {duration / YEAR:.4g} yr: too few to "
                         "compare (is W / h* below 1?)")
    weakening = two_d.fault.b > two_d.fault.a
    recurrence = float(np.mean(np.diff(starts[later])))
    mean_slip = float(np.mean(slip[later][:, weakening].mean(axis=1)))
    recurrence_error = block.recurrence / recurrence - 1
    slip_error = float(block.slip_per_event.mean()) / mean_slip - 1
    return {"width_over_nucleation": nucleation_ratio(law, fault["shear_modulus"], fault["normal_stress"], width),
            "critical_slip": law.critical_slip, "elements": count, "duration": duration,
            "recurrence_2d": recurrence, "recurrence_one_slider": block.recurrence,
            "recurrence_2d_spread": float(np.std(np.diff(starts[later])) / recurrence),
            "slip_2d": mean_slip, "slip_one_slider": float(block.slip_per_event.mean()),
            "recurrence_error": recurrence_error, "slip_error": slip_error,
            "model_error": max(abs(recurrence_error), abs(slip_error)), "events_2d": int(later.size),
            "settled_2d": bool(summary.settled), "steps_2d": run.steps, "wall_time_2d": run.wall_time}


def calibration_row(base_scene, ratio: float, elements_per_process_zone: float = 4.0) -> dict:
    """One row of the calibration; a 2-D fault without earthquakes (it creeps) is a model error of 1."""
    scene = _scene_at_ratio(base_scene, ratio)
    try:
        return compare(scene, elements_per_process_zone)
    except InputError as exc:
        return {"width_over_nucleation": ratio, "critical_slip": scene.law.critical_slip, "model_error": 1.0,
                "events_2d": 0, "note": f"{exc}: the block has earthquakes where the fault creeps"}


def calibrate(base_scene, ratios=RATIOS, elements_per_process_zone: float = 4.0, progress=None) -> dict:
    """The calibration table over ``ratios`` of W / h* (D_c changed, everything else of the base scene kept)."""
    rows = []
    for done, ratio in enumerate(ratios, start=1):
        rows.append(calibration_row(base_scene, ratio, elements_per_process_zone))
        if progress:
            progress(done, len(ratios))
    return {"provenance": {"computed_by": "benchmarks/fault_2d_calibration.py", "faultslip": __version__,
                           "date": datetime.now(timezone.utc).strftime("%Y-%m-%d"),
                           "base_scene": getattr(base_scene, "name", ""),
                           "elements_per_process_zone": elements_per_process_zone,
                           "definition": "model error = max(|T_block / T_2d - 1|, |slip_block / mean slip_2d - 1|); "
                                         "2-D: uniform friction from the surface to D, steady slip below; "
                                         "means over system-size events after the first"},
            "rows": rows}
