"""A fault's quasi-dynamic earthquake cycles on one rate-and-state spring-block: the report of
``faultslip rate-state cycles``.

Kept apart from :mod:`faultslip.models.rate_state_slider.family` so that a cycle run, often one short process,
loads no other model family, plotting or the 2-D fault (``benchmarks/spring_block_qdyn.py`` times it
whole against QDYN).
"""

from __future__ import annotations

from faultslip.dynamics.rate_state.slider import fault_cycles
from faultslip.errors import InputError
from faultslip.fault.one_slider_error import declare_model_error
from faultslip.models.rate_state_slider.scene import model_error_of, read_rate_state_scene, stands_for
from faultslip.fault.rate_state_series import cycles_series
from faultslip.io.report import Report
from faultslip.contract.result import Result


def _scene_notes(report, scene) -> None:
    report.note(scene.law.describe())
    if scene.origin:
        report.note(f"scene: {scene.origin}")


def earthquake_cycles(scene, count: int = 5, progress=None, record: bool = False) -> Result:
    """A fault's quasi-dynamic earthquake cycles ([fault]) on one spring-block (K = G / D); with the seed law
    beside them: :func:`faultslip.models.rate_state_slider.earthquake_cycles`.

    ``progress``: True for a bar, or a callable (done, total) over events (:mod:`faultslip.io.progress`).
    ``record``: keep every step's time series (``simulate``), as the Result's series and figure.

    Parameters
    ----------
    scene : str, path or RateStateScene
        A rate-and-state fault scene ([law] and [fault]).
    count : int
        Cycles measured after the spin-up, from 1 to 10000.
    progress : bool or callable, optional
        A progress bar, or ``(done, total)`` over events.
    record : bool
        Keep every step's time series.

    Returns
    -------
    Result
        Recurrence (s), slip per event (m), stress drop (Pa), peak slip rate (m/s), K / K_c and the settling.
    """
    scene = read_rate_state_scene(scene) if not hasattr(scene, "law") else scene
    if not 1 <= count <= 10_000:
        raise InputError(f"--cycles must lie between 1 and 10000, got {count}")
    if scene.kind != "fault":
        raise InputError(f"{scene.name} describes a laboratory slider; fault cycles need a [fault] table with "
                         "shear_modulus, zone_width, normal_stress and plate_rate")
    result = fault_cycles(scene.slider, scene.plate_rate, cycles=count,
                          model="quasi_dynamic" if scene.model != "quasi_static" else "quasi_static", progress=progress,
                          record=record)
    report = Report(f"faultslip rate-state cycles: {scene.name}")
    report.add("recurrence_period", result.recurrence, "s", also=("yr",))
    report.add("slip_per_event", float(result.slip_per_event.mean()), "m")
    report.add("stress_drop", float(result.stress_drop.mean()), "Pa", also=("MPa",))
    report.add("peak_slip_rate", float(result.peak_slip_rate.max()), "m/s")
    report.add("stiffness_ratio", result.stiffness_ratio, label="K / K_c (quasi-static k_c)")
    report.add("regime", result.regime).add("cycles", int(result.slip_per_event.size))
    report.add("plate_slip_balance", float((result.cycle_slip / (result.plate_rate * result.recurrence)).mean()),
               label="slip per cycle / (V_pl T)")
    report.add("model", result.model).add("integrator", result.method, label="integrator of the cycles")
    report.add("steps", int(result.steps)).add("wall_time", result.wall_time, "s")
    result.report_settling(report)
    report.note(f"events: slip speed above {result.event_speed:g} m/s (the SEAS convention)")
    _scene_notes(report, scene)
    series = cycles_series(result, scene.law, report.title) if record and result.series is not None else None
    answer = Result("rate_state_slider", report, series)  # a stably sliding fault records no cycles
    # one block standing for a fault: its model error against the 2-D fault, whichever door it came through
    declare_model_error(answer, *model_error_of(scene), stands_for(scene))
    return answer
