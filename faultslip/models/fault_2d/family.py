"""The 2-D fault as a model family: quasi-dynamic earthquake cycles on a vertical strike-slip fault in
an elastic half-space (SEAS BP1), its SEAS station files, CF netCDF, event catalogue and figures."""

from __future__ import annotations

import contextlib
import math
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from faultslip import __version__
from faultslip.models.fault_2d.analysis import (DISCRETISATION_ORDER, METHODS, MIN_RESOLUTION,  # noqa: F401
                                                   discretisation_error, kind_change_error, kind_checked_resolution,
                                                   moment_magnitude, run_kind, same_kind, sequence_discretisation,
                                                   single_run_error, summarise)
from faultslip.fault import dip_error, strike_error
from faultslip.models.fault_2d import bp3_outputs
from faultslip.models.fault_2d.integrate import YEAR, Fault2DRun
from faultslip.dynamics.rate_state.slider import fault_cycles
from faultslip.dynamics.shared.settling import settled_error
from faultslip import ranges
from faultslip.errors import InputError
from faultslip.fault.ladder import (ONE_SLIDER_METHOD, declared_error, groups, ladder_report, one_slider_report,
                                   rung_of, with_model_error)
from faultslip.fault.starts import compare_starts, other_starts, start_note, starts_estimate
from faultslip.io import budget
from faultslip.io.atomic import write_text_atomic
from faultslip.io.netcdf import write_dataset
from faultslip.io.outputs import output_lock, prepare_run_folder
from faultslip.io.progress import duration as spoken_duration
from faultslip.io.records import lazy_data
from faultslip.io.report import Report
from faultslip.io.seas import station_file_name, write_profiles, write_station
from faultslip.models.common import note_origin
from faultslip.models.fault_2d.cells import CELLS, read_scene
from faultslip.models.fault_2d.scene import (RESOLVABLE_ELEMENTS, Fault2DScene, dividing_size, from_one_slider,
                                             read_fault_2d_scene)
from faultslip.contract.registry import RUNGS, Example, Family, declared_rows, load, register
from faultslip.contract.result import Result
from faultslip.models.fault_2d.figures import cumulative_slip_figure, ladder_figure, slip_rate_figure
from faultslip.units import ELAPSED_TIME_ATTRS

#: Relative spread of the last intervals within which a sequence is called settled (periodic).
SETTLE_TOLERANCE = 1e-3


def simulate_fault(scene, *, output_dir=None, resume: bool = False, rtol: float | None = None,
                   allow_large: bool = False, progress=None, overwrite: bool = False,
                   settle_tolerance: float = SETTLE_TOLERANCE, allow_underresolved: bool = False) -> Result:
    """Run a 2-D fault scene; with ``output_dir``, stream the run there (checkpointed: ``resume=True``
    continues a stopped run bit for bit) and write the SEAS station files, slip profiles, event
    catalogue and CF netCDF when it ends.

    Parameters
    ----------
    scene : str, path or Fault2DScene
        A 2-D fault scene.
    output_dir : str or path, optional
        Where the run streams and its files go.
    resume : bool
        Continue a stopped run.
    rtol : float, optional
        The integrator's tolerance.
    allow_large : bool
        Lift the budget.
    progress : callable, optional
        ``(done, total)``.
    overwrite : bool
        Replace earlier files.
    settle_tolerance : float
        The settling tolerance of the sequence.

    Returns
    -------
    Result
        Recurrence (s), slip per event (m), moment per length (N), the settling and the run's Dataset.
    """
    loaded = read_fault_2d_scene(scene, allow_large=allow_large)
    rtol = loaded.rtol if rtol is None else rtol
    loaded.require_resolution(allow_underresolved)  # before any work
    budget.check(loaded.estimate(rtol, output_dir, in_this_process=True), allow_large)
    limit = None if allow_large else 2 * budget.time_budget()  # an estimate can be far off: the run stops there
    folder = Path(output_dir) if output_dir is not None else None
    if folder is not None:
        created = prepare_run_folder(folder, resume=resume, overwrite=overwrite, what="a 2-D fault run")
        try:
            with output_lock(folder / "run", "faultslip simulate (2-D fault)", overwrite=True, label="--output-dir"):
                run = loaded.run(rtol, folder, resume, progress, time_limit=limit)
                result = _result(loaded, run, settle_tolerance)
                write_outputs(loaded, run, folder, result)
        except Exception:
            if created:  # a folder this run made and left empty goes too
                with contextlib.suppress(OSError):
                    folder.rmdir()
            raise
        written = ("SEAS BP3 on-fault and surface station files, slip and stress profiles (slip.dat, "
                   "shear_stress.dat, normal_stress.dat)" if loaded.fault.plane == "strain"
                   else "SEAS station files, slip profiles (devol.dat)")
        result.note(f"{written}, events.csv and fault_2d.nc written to {folder}")
        return result
    return _result(loaded, loaded.run(rtol, progress=progress, time_limit=limit), settle_tolerance)


def _result(loaded: Fault2DScene, run: Fault2DRun, settle_tolerance: float) -> Result:
    summary = summarise(run, settle_tolerance, unsettled_mean=True)
    fault = run.fault
    report = Report(f"faultslip 2-D fault: {loaded.name}")
    report.add("method", "fault_2d")
    report.add("method_reason", "a 2-D fault scene: quasi-dynamic boundary elements with the exact antiplane "
                                "half-space kernel, Dormand-Prince 5(4) stepping")
    report.add("elements", fault.count).add("element_size", fault.element_size, "m")
    report.add("fault_width", fault.width, "m", also=("km",), label="frictional width W_f")
    report.add("seismogenic_width", fault.seismogenic_width(), "m", also=("km",), label="velocity-weakening width")
    report.add("nucleation_size", fault.nucleation_size(), "m", label="h* = (pi/2) G D_c b / (sigma_n (b - a)^2)")
    report.add("process_zone", fault.process_zone(), "m", label="L_b = G D_c / (sigma_n b)")
    report.add("resolution", fault.process_zone() / fault.element_size, label="elements per L_b")
    report.add("events", summary.events).add("system_size_events", summary.system_events)
    sequence = summary.sequence
    report.add("sequence", sequence.kind if sequence.period <= 1 else f"period_{sequence.period}",
               label="the sequence: periodic, period_p (a supercycle of p events), aperiodic or unsettled")
    report.add("recurrence_interval", summary.recurrence_interval, "s", also=("yr",),
               label="mean interval between system-size events (over a supercycle, or the aperiodic run)")
    if sequence.period > 1:
        report.add("supercycle", float(sequence.intervals.sum()), "s", also=("yr",),
                   label=f"period of the {sequence.period}-event supercycle")
        report.add("intervals", [float(v) for v in sequence.intervals], "s", label="each interval of the supercycle")
        report.add("event_slips", list(summary.event_slips), "m", label="each event's surface slip")
        report.add("event_hypocentres", list(summary.event_hypocentres), "m", label="each event's hypocentre depth")
    report.add("settled", bool(summary.settled),
               label=f"periodic (of any period up to 8): each interval repeats a supercycle later to {settle_tolerance:g}")
    report.add("recurrence_spread", summary.recurrence_spread if math.isfinite(summary.recurrence_spread) else None,
               label=("coefficient of variation of the intervals" if sequence.kind == "aperiodic" else
                      "largest relative change of an interval over a supercycle"))
    if sequence.kind == "aperiodic":
        report.add("recurrence_sampling_error", sequence.mean_error,
                   label=f"95 % half-width of the mean interval over {sequence.intervals.size} intervals (Student's "
                         "t, their integrated autocorrelation time counted)")
    report.add("slip_per_event", summary.surface_slip_per_event, "m",
               label="surface slip per event (mean over the measured events)")
    report.add("mean_slip_per_event", summary.mean_slip_per_event, "m", label="slip per event, mean over the "
                                                                              "velocity-weakening width")
    report.add("moment_per_length", summary.moment_per_length, "N", label="seismic moment per metre along strike")
    if loaded.fault_length is not None and summary.moment_per_length > 0:
        report.add("moment_magnitude", moment_magnitude(summary.moment_per_length, loaded.fault_length),
                   label=f"Mw for a fault {loaded.fault_length / 1e3:g} km long")
    report.add("hypocentre_depth", summary.hypocentre_depth, "m", also=("km",))
    report.add("peak_slip_rate", summary.peak_slip_rate, "m/s")
    report.add("plate_slip_balance", summary.plate_slip_balance_surface,
               label="slip per cycle at the shallowest station / (V_pl T)")
    report.add("plate_slip_balance_range", list(summary.plate_slip_balance_range), "1",
               label="the same at every station (min, max)")
    report.add("deep_creep_rate", summary.creep_rate_deep, "m/s", label="slip rate at the bottom element at the end")
    resolution = fault.process_zone() / fault.element_size
    discretisation, per_interval = sequence_discretisation(resolution, sequence.period)
    if sequence.kind == "unsettled" and sequence.first_event == 1:  # read over the intervals after the spin-up
        window = sequence.intervals
        report.add("recurrence_range", [float(window.min()), float(window.max())], "s", also=("yr",),
                   label=f"range of the {window.size} intervals after the first (unsettled: not one interval)")
        report.note(f"unsettled: the recurrence is the mean of {window.size} intervals, "
                    f"{window.min() / YEAR:.4g} to {window.max() / YEAR:.4g} yr, and its declared error their spread "
                    "about it, the slip per event the mean of the events closing them; run longer for a settled "
                    "answer")
    sequence_error = sequence.mean_error
    report.add("sequence_error", sequence_error if math.isfinite(sequence_error) else None,
               label="the sequence's own error in recurrence: its settling, or an unsettled or aperiodic run's "
                     "intervals about their mean (relative; null: too few intervals)")
    if math.isfinite(discretisation):
        kind_term = kind_change_error(resolution)
        report.add("discretisation_error", discretisation,
                   label="element size's error in recurrence: a bound through the runs of 66 faults, at least the "
                         "error a change of kind of sequence with the element size can carry (kind_change_error)")
        report.add("kind_change_error", kind_term,
                   label="the error one run may carry where its element size changed the kind of sequence, which "
                         "one run cannot see (measured up to 115 % at 3 per L_b; --richardson checks two sizes)")
        if kind_term > discretisation_error(resolution):
            report.note(f"one run on {resolution:.3g} elements per L_b cannot tell whether the element size changed "
                        f"its kind of sequence (1 fault in 8 did between 3 and 6 per L_b): its declared error "
                        f"counts that, {kind_term:.2g}; --richardson checks two sizes and lifts it where they agree")
        declared = settled_error(discretisation + 10 * run.rtol, sequence_error)
        report.add("estimated_relative_error", declared if math.isfinite(declared) else None,
                   label="declared: the sequence's (settling, or an aperiodic mean's sampling error), the element "
                         "size's and 10 rtol, added (null: none can be declared, too few intervals)")
        if sequence.period > 1:
            report.add("interval_errors", [settled_error(per_interval + 10 * run.rtol, sequence_error)]
                       * sequence.period,
                       label="declared error of each interval of the supercycle (relative: a supercycle's intervals "
                             "move more with the element size than its mean)")
    else:  # run as asked below the resolution where sequences keep their character: no error to declare
        report.add("discretisation_error", None, label="element size's error in recurrence (none declared: "
                                                       "under-resolved)")
        report.add("estimated_relative_error", None, label="declared error (none: the answer is qualitative)")
        report.note(f"under-resolved: {resolution:.2g} elements per L_b, below {MIN_RESOLUTION:g}, where sequences "
                    "change character; the answer is qualitative (run as asked with allow_underresolved)")
    report.add("duration", run.duration, "s", also=("yr",))
    report.add("rtol", run.rtol).add("kernel", run.kernel)
    report.add("steps", run.steps).add("rejected_steps", run.rejected)
    report.add("min_step", run.min_step, "s").add("max_step", run.max_step, "s", also=("yr",))
    report.add("wall_time", run.wall_time, "s")
    if summary.note:
        report.note(summary.note)
    start = (loaded.settings or {}).get("initial_speed")
    if start is not None:
        report.note(start_note(start))
    for note in run.notes:
        report.note(note)
    if run.resumed_from is not None:
        report.note(f"continued from the checkpoint at {run.resumed_from / YEAR:.6g} yr")
    if loaded.fault_length is not None and fault.plane == "antiplane":
        report.note(length_note(loaded))
    note_origin(report, loaded.origin)
    return Result("fault_2d", report, to_dataset(loaded, run), lambda: cumulative_slip_figure(run),
                  extras={"run": run, "slip_rate_figure": lambda: slip_rate_figure(run)})


def run_variables(run, space: str, event_extras: dict, along: str = "") -> dict:
    """The variables every fault run records, for its Dataset: station series on (time, station), profiles and
    friction on ``space`` (the elements' dimension), and the events (``event_extras`` after their slip); ``along``
    names the slip's direction in the station series' long names (" along the rake")."""
    units = {"slip": ("m", f"slip{along}"), "log10_slip_rate": ("1", "log10 of the slip rate in m/s"),
             "shear_stress": ("Pa", f"shear stress{along} (frictional strength)"),
             "log10_state": ("1", "log10 of the state theta in s")}
    # a run with a folder hands its series over unread: xarray reads them when indexed, and write_dataset a block
    # at a time
    data = {f"station_{name}": (("time", "station"), lazy_data(values),
                                {"units": units[name][0], "long_name": units[name][1]})
            for name, values in run.stations.items()}
    data["profile_slip"] = (("profile_time", space), lazy_data(run.profiles),
                            {"units": "m", "long_name": "cumulative slip"})
    data["profile_log10_slip_rate"] = (("profile_time", space), lazy_data(run.profile_log10_slip_rate),
                                       {"units": "1", "long_name": "log10 of the slip rate in m/s"})
    data["profile_max_slip_rate"] = ("profile_time", run.profile_max_speed, {"units": "m/s"})
    data["event_start"] = ("event", run.events["start"], {"units": "s", "long_name": "peak slip rate above 1e-3 m/s"})
    data["event_end"] = ("event", run.events["end"], {"units": "s"})
    data["event_hypocentre_depth"] = ("event", run.events["hypocentre_depth"], {"units": "m"})
    data["event_peak_slip_rate"] = ("event", run.events["peak_slip_rate"], {"units": "m/s"})
    data["event_slip"] = (("event", space), run.events["slip"], {"units": "m", "long_name": "slip in the event"})
    data.update(event_extras)
    fault = run.fault
    for key, unit in (("a", "1"), ("b", "1"), ("critical_slip", "m"), ("normal_stress", "Pa")):
        data[key] = (space, getattr(fault, key), {"units": unit})
    return data


def to_dataset(loaded: Fault2DScene, run: Fault2DRun):
    """The run as CF netCDF: station series on (time, station), profiles on (profile_time, depth), events."""
    import xarray as xr  # heavy: imported where used

    strain = run.fault.plane == "strain"
    along = "distance down dip of" if strain else "depth of"
    depth = ("depth", run.fault.depth, {"units": "m", "long_name": f"{along} the element centre", "positive": "down"})
    station = ("station", run.station_depths, {"units": "m", "long_name": f"station {'distance down dip' if strain else 'depth'}",
                                               "positive": "down"})
    data = run_variables(run, "depth", {"event_moment_per_length": (
        "event", run.moments_per_length(), {"units": "N", "long_name": "seismic moment per metre"})})
    fault = run.fault
    coords = {"time": ("time", run.station_time, ELAPSED_TIME_ATTRS), "station": station, "depth": depth,
              "profile_time": ("profile_time", run.profile_time, ELAPSED_TIME_ATTRS),
              "event": ("event", np.arange(run.event_count), {"units": "1", "long_name": "event number"})}
    attrs = {"title": f"faultslip 2-D fault: {loaded.name}", "Conventions": "CF-1.8", "source": f"faultslip {__version__}",
             "shear_modulus_Pa": fault.shear_modulus, "shear_wave_speed_m_per_s": fault.shear_wave_speed,
             "plate_rate_m_per_s": fault.plate_rate, "evolution": fault.evolution, "rtol": run.rtol, "steps": run.steps}
    if strain:
        extra_data, extra_coords, extra_attrs = bp3_outputs.dataset_variables(run)
        data.update(extra_data)
        coords.update(extra_coords)
        attrs.update(extra_attrs)
    return xr.Dataset(data, coords=coords, attrs=attrs)


def write_outputs(loaded: Fault2DScene, run: Fault2DRun, folder: Path, result: Result) -> None:
    """The SEAS files, the event catalogue (CSV with units) and the netCDF in ``folder``, each atomic."""
    fault = run.fault
    problem = f"faultslip 2-D fault: {loaded.name}"  # the scene's own problem, BP1 or not
    if fault.plane == "strain":
        bp3_outputs.write_bp3(run, folder, __version__, loaded.name)
    for k, depth in enumerate(run.station_depths if fault.plane == "antiplane" else ()):  # a station's columns at a time: the run may be on disk
        write_station(folder / station_file_name(depth), run.station_time, run.stations["slip"][:, k],
                      run.stations["log10_slip_rate"][:, k], run.stations["shear_stress"][:, k] / 1e6,
                      run.stations["log10_state"][:, k], depth=float(depth), element_size=fault.element_size,
                      version=__version__, problem=problem)
    if fault.plane == "antiplane":
        write_profiles(folder / "devol.dat", run.profile_time, run.profile_max_speed, run.profiles, fault.depth,
                       element_size=fault.element_size, version=__version__, problem=problem)
    moment = run.moments_per_length()
    lines = ["start (s),end (s),hypocentre_depth (m),peak_slip_rate (m/s),surface_slip (m),moment_per_length (N)"
             + (",moment_magnitude" if loaded.fault_length else "")]
    for i in range(run.event_count):
        row = [run.events["start"][i], run.events["end"][i], run.events["hypocentre_depth"][i],
               run.events["peak_slip_rate"][i], run.events["slip"][i, 0], moment[i]]
        if loaded.fault_length:
            row.append(moment_magnitude(moment[i], loaded.fault_length) if moment[i] > 0 else float("nan"))
        lines.append(",".join(repr(float(value)) for value in row))  # full precision: times reach 1e10 s
    write_text_atomic(folder / "events.csv", "\n".join(lines) + "\n")
    write_dataset(result.to_xarray(), folder / "fault_2d.nc")


#: How many times an escalated run that ends unsettled is run again, twice as long, while the budget allows.
LONGER_RUNS = 2


def one_slider(scene, reason: str = "asked for by name") -> Result:
    """The one-slider rung of a fault scene: the block derived from the scene's own profile, corrected by the 2-D
    calibration, with 95 % ranges of recurrence and slip per event (:func:`faultslip.fault.ladder.one_slider_report`).

    Parameters
    ----------
    scene : str, path or Fault2DScene
        A fault scene (the one description every rung reads).
    reason : str
        Why this rung runs.

    Returns
    -------
    Result
        Recurrence (s) and slip per event (m), each with its 95 % range, and the declared model error.
    """
    loaded = read_fault_2d_scene(scene)
    report = one_slider_report(loaded.fault.description(), reason)
    note_origin(report, loaded.origin)
    return Result("fault_2d", report)


def run(scene, method=None, tolerance=None, allow_large: bool = False, allow_underresolved: bool = False,
        richardson: bool = False, check_starts: bool = False, progress=None) -> Result:
    """A fault scene on the rung asked for, or on the cheapest whose declared error meets ``tolerance``.

    Parameters
    ----------
    scene : str, path or Fault2DScene
        A fault scene.
    method : str, optional
        A rung of :data:`RUNGS` by name, or ``auto``. ``fault_3d`` reads the scene as a fault ``fault_length``
        long (:func:`faultslip.models.fault_3d.family.refine_two_d`); ``auto`` never does: a 2-D scene is a fault
        infinitely long along strike.
    tolerance : float, optional
        The relative error allowed. ``auto`` runs the one slider where its declared model error meets it, and
        the 2-D fault of the same scene otherwise; without it, ``auto`` runs the 2-D fault. The 2-D run's
        settling tolerance is the smaller of this and 1e-3.
    allow_large, allow_underresolved, richardson, check_starts : bool
        Lift the budget; run coarser than the sequences keep their character at; run again on elements half
        the size (:func:`richardson_run`); run again from other starts (:func:`starts_run`).
    progress : callable, optional
        ``(done, total)`` of the 2-D run.

    Returns
    -------
    Result
        The rung's answer and its declared error; an escalation names both rungs.
    """
    method, asked = checked_request(method, tolerance, richardson, check_starts)
    loaded = read_fault_2d_scene(scene, allow_large=allow_large)
    if method == "one_slider":
        return one_slider(loaded)
    if method == "fault_3d":  # the rung above, asked for by name: the scene read as a fault fault_length long
        return load("fault_3d").refine(loaded, "asked for by name", allow_large=allow_large, progress=progress)
    settle = min(SETTLE_TOLERANCE, tolerance) if tolerance is not None else SETTLE_TOLERANCE
    if tolerance is not None and method == "fault_2d" and not asked:
        refuse_unreachable(loaded, tolerance)
    if method == "fault_2d" or tolerance is None:
        if richardson:
            return richardson_run(loaded, allow_large=allow_large, settle_tolerance=settle)
        if check_starts:
            return starts_run(loaded, allow_large=allow_large, allow_underresolved=allow_underresolved,
                              settle_tolerance=settle)
        return simulate_fault(loaded, allow_large=allow_large, allow_underresolved=allow_underresolved,
                              settle_tolerance=settle, progress=progress)
    cheap = one_slider(loaded, f"auto: the cheapest rung whose declared error meets the tolerance {tolerance:g}")
    declared = cheap.estimated_relative_error
    if declared is not None and declared <= tolerance:
        return cheap
    refuse_unreachable(loaded, tolerance, tried_slider=True, slider_error=declared)
    why = (f"the one slider's declared model error {declared:.2g} exceeds the tolerance {tolerance:g}"
           if declared is not None else "the scene lies outside the one slider's calibration")
    result = escalate(loaded, why, settle, allow_large, allow_underresolved, progress, cheap)
    declared = result.estimated_relative_error
    if declared is None or declared > tolerance:
        result.note(f"the 2-D rung's declared error {'(none)' if declared is None else f'{declared:.2g}'} does not "
                    f"meet the tolerance {tolerance:g}: run longer ([run] duration, or --allow-large) or on finer "
                    "elements (the 2-D fault is the top rung of a fault infinitely long along strike)")
    return result


def checked_request(method, tolerance, richardson: bool, check_starts: bool) -> tuple[str, list]:
    """The rung asked for (``auto`` where none) and the reruns asked for (``--richardson``, ``--check-starts``),
    refused in one sentence where :func:`run` cannot honour them; :func:`estimate` refuses what run refuses."""
    method = method or "auto"
    if method not in ("auto",) + RUNGS:
        raise InputError(f"a fault scene runs on the rungs {', '.join(RUNGS)} (or auto), got {method!r}")
    checked_tolerance(tolerance)
    asked = [flag for flag, on in (("--richardson", richardson), ("--check-starts", check_starts)) if on]
    if len(asked) == 2:
        raise InputError("--richardson and --check-starts each run the scene again; ask for one at a time")
    if asked and (method in ("one_slider", "fault_3d") or (tolerance is not None and method == "auto")):
        raise InputError(f"{asked[0]} runs the 2-D fault itself again: ask for --model fault_2d"
                         + (" (a tolerance may stop at the one slider)" if method == "auto" else ""))
    return method, asked


def checked_tolerance(tolerance) -> None:
    """Refuse a tolerance that is not a relative error in (0, 1) (None: no tolerance); the 3-D family's runs too."""
    ranges.check_tolerance(tolerance)


def refuse_unreachable(loaded: Fault2DScene, tolerance: float, tried_slider: bool = False,
                       slider_error: float | None = None) -> None:
    """Refuse, before any work, a ``tolerance`` below what the 2-D run can declare (:func:`floor_error`) and,
    where the one slider was tried first, below what it declares too (``slider_error``; None: none declared):
    name what would meet it."""
    floor = floor_error(loaded)
    if floor <= tolerance or (slider_error is not None and slider_error <= tolerance):
        return
    resolution = loaded.resolution
    # the tolerance's share left to the elements once 10 rtol is counted (half of it where rtol takes more)
    rtol_binds = 10 * loaded.rtol >= tolerance / 2
    elements_share = tolerance / 2 if rtol_binds else tolerance - 10 * loaded.rtol
    fixes, reachable = ["a smaller rtol ([run] rtol)"] if rtol_binds else [], True
    if single_run_error(resolution) > elements_share:  # the elements that would meet it, kind-change term counted
        needed = kind_checked_resolution(elements_share)
        width = loaded.fault.element_size * loaded.fault.count
        count = width * needed / loaded.fault.process_zone()
        reachable = count <= RESOLVABLE_ELEMENTS  # False for inf or nan too
        if reachable:
            count, size = dividing_size(width, math.ceil(count))
            fixes.insert(0, f'element_size = "{size} m" ({count} elements, {needed:.3g} per L_b)')
            fixes[-1] += ", or --model fault_2d --richardson (two sizes, where they agree in kind)"
    declares = (f"declares at least {floor:.2g} in recurrence" if math.isfinite(floor) else
                f"declares no error (under-resolved: below {MIN_RESOLUTION:g} elements per L_b)")
    head = "no rung meets" if tried_slider else "the 2-D fault cannot meet"
    tail = (f"; use {' and '.join(fixes)}, or a looser tolerance" if reachable else
            "; no element size a run can hold declares it: use a looser tolerance")
    raise InputError(f"{loaded.name}: {head} the tolerance {tolerance:g}: the 2-D fault on elements resolving "
                     f"L_b {resolution:.3g} times at rtol {loaded.rtol:g} {declares}"
                     + (f", the one slider {slider_error:.2g}" if tried_slider and slider_error is not None else
                        ", and the one slider declares none (outside its calibration)" if tried_slider else "")
                     + tail)


def floor_error(loaded: Fault2DScene) -> float:
    """The least relative error a 2-D run of ``loaded`` can declare, known before it runs: the element size's
    (:func:`single_run_error` at its resolution, a period-1 sequence's, the smallest) plus 10 rtol; the
    sequence's own settling can only add to it."""
    return single_run_error(loaded.resolution) + 10 * loaded.rtol


def one_slider_estimate(what: str) -> budget.Estimate:
    """The one-slider rung's cost: its block's 5 earthquake cycles, by the rate-and-state slider's fitted model."""
    return budget.fitted_estimate("rate_state_slider", "run", 5.0, what)


def ladder_estimate(loaded: Fault2DScene, include_3d: bool = False) -> budget.Estimate:
    """What :func:`ladder` needs before any rung runs: its rungs one after another (the one slider's cycles, the
    antiplane fault where the scene dips, the 2-D fault, and with ``include_3d`` the 3-D fault its ``fault_length``
    states), each from its own cost model (``faultslip model-error SCENE --estimate``)."""
    if include_3d and not loaded.fault_length:
        raise InputError(f"{loaded.name} states no [run] fault_length: its ladder has no 3-D rung (a 2-D scene is a "
                         "fault infinitely long along strike)")
    rungs = {"the one slider": one_slider_estimate("5 earthquake cycles")}
    if loaded.fault.plane == "strain":
        flat = loaded.antiplane()
        rungs["the antiplane rung"] = flat.estimate(flat.rtol, None, in_this_process=True)
    rungs["the 2-D rung"] = loaded.estimate(loaded.rtol, None, in_this_process=True)
    if include_3d:
        rungs["the 3-D rung"] = load("fault_3d").estimate(loaded, "run")
    return budget.rungs_estimate(f"the ladder on {loaded.name}", rungs)


def ladder(scene, tolerance: float | None = None, allow_large: bool = False, include_3d: bool = False) -> Result:
    """Every rung of the ladder on one scene: its answer, its declared range and its cost, and the chart
    (``faultslip model-error SCENE --plot``).

    Parameters
    ----------
    scene : str, path or Fault2DScene
        A fault scene.
    tolerance : float, optional
        A relative error allowed: which rungs meet it.
    allow_large : bool
        Run the 2-D rung beyond the budget.
    include_3d : bool
        Add the rung above, the 3-D fault the scene's ``fault_length`` states (budgeted before it runs); the rungs
        then compare their slip averaged over the velocity-weakening zone, as the 3-D fault gives it.

    Returns
    -------
    Result
        Per rung, recurrence (s) and slip per event (m) with their ranges, the declared error and the CPU time (s);
        ``plot()`` the chart.
    """
    loaded = read_fault_2d_scene(scene, allow_large=allow_large)
    budget.check(ladder_estimate(loaded, include_3d), allow_large)  # the whole ladder, before any rung runs
    slip = "mean" if include_3d else "surface"
    rungs = []
    started = time.process_time()
    cheap = one_slider(loaded)
    rungs.append(rung_of("one_slider", cheap, time.process_time() - started, slip=slip))
    dipping = loaded.fault.plane == "strain"
    if dipping:  # the antiplane fault of the same description, its error against plane strain declared
        started = time.process_time()
        flat = rung_of("antiplane", simulate_fault(loaded.antiplane(), allow_large=allow_large),
                     time.process_time() - started, slip=slip)
        ratio = groups(loaded.fault.description())["width_over_nucleation"]
        rungs.append(with_model_error(flat, dip_error.declared(loaded.fault.dip, width_over_nucleation=ratio)))
        unmeasured = dip_error.why_undeclared(loaded.fault.dip, ratio)
    started = time.process_time()
    full = simulate_fault(loaded, allow_large=allow_large)
    rungs.append(rung_of("fault_2d", full, time.process_time() - started, slip=slip))
    if include_3d:
        started = time.process_time()
        three = load("fault_3d").refine(loaded, "the ladder's top rung", allow_large=allow_large)
        rungs.append(rung_of("fault_3d", three, time.process_time() - started, slip=slip))
    report = ladder_report(f"faultslip model error: the ladder on {loaded.name}", rungs, tolerance,
                           "3-D" if include_3d else "2-D",
                           "slip per event, mean over the velocity-weakening zone" if include_3d
                           else "surface slip per event")
    if dipping:
        report.note(f"the fault dips {loaded.fault.dip:g} degrees: the 2-D rung is plane strain (SEAS BP3's "
                    "mechanics), and the antiplane rung's declared error adds its model error on dip-slip faults "
                    "(benchmarks/dip_model_error.py); the one slider's range is calibrated against the antiplane fault"
                    + (f"; none is declared on this fault: {unmeasured}" if unmeasured else ""))
    if include_3d:
        report.note(f"the 3-D rung reads the scene as a fault {loaded.fault_length / 1e3:g} km long (strengthening "
                    "beyond its ends); the lower rungs' ranges are those of a fault infinitely long along strike, "
                    "so they hold the 3-D answer only where the fault's ends matter little")
    elif loaded.fault_length:
        three = load("fault_3d").estimate(loaded, "run")
        report.note(f"the rung above, this scene read as a fault {loaded.fault_length / 1e3:g} km long, is the 3-D "
                    f"fault ({three.describe()}): --include-3d adds it, and 'faultslip run SCENE --model fault_3d' "
                    "runs it alone")
    else:
        report.note("a fault finite along strike is a 3-D scene (family fault_3d, docs/fault_3d.md): model-error on "
                    "it adds the 3-D rung, and the 2-D fault's declared model error against it")
    return Result("fault_2d", report, figure=lambda: ladder_figure(rungs, report.title))


def rerun_note(loaded: Fault2DScene, rtol: float) -> str:
    """What an escalation's estimate leaves out: the longer runs :func:`escalate` makes, while the budget allows,
    only where a run ends unsettled (each estimated from the events it will see, as the first)."""
    durations = [loaded.duration * 2 ** (k + 1) for k in range(LONGER_RUNS)]
    costs = [replace(loaded, duration=d).estimate(rtol).seconds for d in durations]
    return (f"not counted above: a 2-D run that ends unsettled is run again, twice as long, up to {LONGER_RUNS} times "
            "while the time budget allows (" + ", then ".join(
                f"{d / YEAR:.6g} yr, about {spoken_duration(c)}" for d, c in zip(durations, costs)) + ")")


def escalate(loaded: Fault2DScene, why: str, settle: float, allow_large: bool, allow_underresolved: bool,
             progress, cheap: Result) -> Result:
    """The 2-D rung of the same scene, after the one slider's declared error fell short: estimated and budgeted
    before any work; a run that ends unsettled runs again twice as long while the budget allows
    (:data:`LONGER_RUNS`), and otherwise reports its intervals' range."""
    loaded.require_resolution(allow_underresolved)
    estimate = loaded.estimate(in_this_process=True)
    estimate.what = f"the 2-D rung of {loaded.name} ({why})"
    budget.check(estimate, allow_large)
    if progress is not None and hasattr(progress, "announce"):
        progress.announce(f"escalating to the 2-D fault: {estimate.describe()}")
    started = time.process_time()
    result = simulate_fault(loaded, allow_large=allow_large, allow_underresolved=allow_underresolved,
                            settle_tolerance=settle, progress=progress)
    scene, longer, estimated = loaded, 0, estimate.seconds
    while result.values["sequence"] == "unsettled" and longer < LONGER_RUNS:
        scene = replace(scene, duration=2 * scene.duration)
        # the run just done counted its steps, which the event model only estimated: one twice as long from the same
        # start takes about twice as many
        again = scene.estimate(in_this_process=True, steps=2.0 * result.values["steps"])
        spent = time.process_time() - started
        if not allow_large and spent + again.seconds > budget.time_budget():
            result.note(f"unsettled after {scene.duration / 2 / YEAR:.6g} yr; running {scene.duration / YEAR:.6g} yr "
                        f"({again.describe()}) would pass the time budget: pass --allow-large to run it")
            break
        estimated += again.seconds
        result = simulate_fault(scene, allow_large=allow_large, allow_underresolved=allow_underresolved,
                                settle_tolerance=settle, progress=progress)
        result.note(f"run again over {scene.duration / YEAR:.6g} yr: the shorter run had not settled")
        longer += 1
    cpu = time.process_time() - started
    result.set("method_reason", f"escalated from the one slider to the 2-D fault of the same scene: {why}")
    result.add("escalated_from", "one_slider", label="the rung escalated from")
    result.add("one_slider_model_error", cheap.estimated_relative_error,
               label="the one slider's declared model error (95 % range's half-width; null: outside its calibration)")
    result.add("estimated_seconds", estimated, "s", label="the 2-D runs' cost, each estimated before it started")
    result.add("cpu_time", cpu, "s", label="the CPU time the 2-D rung used")
    result.add("runs", longer + 1, label="2-D runs (a run that ends unsettled is run again, twice as long)")
    result.note("the 2-D rung's declared error is numerical (element size, settling, rtol): the scene is a fault "
                "infinitely long along strike, for which the 2-D fault is the top rung; "
                + ("--model fault_3d runs it as a fault its fault_length long" if loaded.fault_length else
                   "a fault finite along strike is a 3-D scene (family fault_3d), whose 2-D rung adds its model "
                   "error against 3-D"))
    return result


def length_note(loaded: Fault2DScene) -> str:
    """The sentence a 2-D scene with a ``fault_length`` gets: its answer is an infinitely long fault's, and the
    3-D fault that long differs by the declared model error, where one is declared
    (:func:`faultslip.fault.strike_error.length_note`)."""
    zone = groups(loaded.fault.description())
    return strike_error.length_note(loaded.fault_length, zone["width"], zone["burial"], zone["width_over_nucleation"])


def starts_run(scene, allow_large: bool = False, allow_underresolved: bool = False,
               settle_tolerance: float = SETTLE_TOLERANCE) -> Result:
    """The scene from its own start and from :data:`~faultslip.fault.starts.START_FACTORS` times its start's slip
    rate: does it settle to the same cycle? A multistable fault does not
    (:func:`faultslip.fault.starts.compare_starts`).

    Parameters
    ----------
    scene : str, path or Fault2DScene
        A 2-D fault scene.
    allow_large, allow_underresolved : bool
        Run the three beyond the budget; run coarser than the sequences keep their character at.
    settle_tolerance : float
        The sequences' settling tolerance.

    Returns
    -------
    Result
        The scene's own start's answer and declared error, with each start's speed, recurrence and sequence,
        ``start_change`` (the largest relative change of the recurrence) and ``multistable``.
    """
    loaded = read_fault_2d_scene(scene, allow_large=allow_large)
    loaded.require_resolution(allow_underresolved)
    speed, others = other_starts(loaded)
    budget.check(starts_estimate(loaded, others), allow_large)
    result = simulate_fault(loaded, allow_large=True, allow_underresolved=allow_underresolved,
                            settle_tolerance=settle_tolerance)
    runs = [simulate_fault(other, allow_large=True, allow_underresolved=allow_underresolved,
                           settle_tolerance=settle_tolerance) for other in others]
    return compare_starts(result, runs, speed)


def richardson_run(scene, allow_large: bool = False, settle_tolerance: float = SETTLE_TOLERANCE) -> Result:
    """The scene on its own elements and on elements half their size, and the recurrence extrapolated
    (Richardson, at the a-priori bound's order, :data:`DISCRETISATION_ORDER`): the discretisation error then
    declared is what the two runs show (twice the extrapolation's correction to the finer run, which covers the
    finer run's distance from the limit on a fault converging at order 0.36 or faster; the slowest measured
    converged at about 0.4), not the a-priori bound, where both sequences have the same period.

    Parameters
    ----------
    scene : str, path or Fault2DScene
        A 2-D fault scene, resolved (2 or more elements per L_b).
    allow_large : bool
        Run the two beyond the budget (the finer costs several times the scene's own).
    settle_tolerance : float
        The sequences' settling tolerance.

    Returns
    -------
    Result
        The finer run's answer, with ``recurrence_extrapolated`` (s), both runs' recurrences and the declared
        discretisation error.
    """
    loaded = read_fault_2d_scene(scene, allow_large=allow_large)
    loaded.require_resolution()
    finer = loaded.at_element_size(loaded.fault.element_size / 2)
    budget.check(budget.one_after_another(f"the two runs of {loaded.name} (Richardson)",
                                          [loaded.estimate(in_this_process=True), finer.estimate()]), allow_large)
    coarse = simulate_fault(loaded, allow_large=True, settle_tolerance=settle_tolerance)
    result = simulate_fault(finer, allow_large=True, settle_tolerance=settle_tolerance)
    t_coarse, t_fine = (r.values["recurrence_interval"].to("s").magnitude for r in (coarse, result))
    kinds = [run_kind(run.values["sequence"], run.values["events"], run.values["system_size_events"])
             for run in (coarse, result)]
    same = same_kind(*kinds) and math.isfinite(t_coarse) and math.isfinite(t_fine)
    result.add("recurrence_coarse", t_coarse, "s", also=("yr",), label="recurrence on the scene's own elements")
    if not same:
        if not (math.isfinite(t_coarse) and math.isfinite(t_fine)):
            result.note("Richardson: the two resolutions' sequences differ; the a-priori discretisation bound stands")
            return result
        # a change of kind with the element size (near a bifurcation: benchmarks/fault_2d_resolution_designs.py
        # measured up to 115 % between such runs): no bound of the a-priori form holds, so the two runs' own
        # difference is declared where it is the larger; the finer run's kind is itself unchecked
        shown = max(abs(t_fine / t_coarse - 1), single_run_error(finer.resolution))
        result.note(f"Richardson: the element size changes the kind of sequence ({describe_kind(kinds[0])} on "
                    f"{loaded.fault.element_size:g} m elements, {describe_kind(kinds[1])} on "
                    f"{finer.fault.element_size:g} m): the fault is near a bifurcation and the a-priori bound does "
                    f"not hold; declared the two runs' difference, {abs(t_fine / t_coarse - 1):.2g}, at least what "
                    "one run on the finer elements declares; run finer elements until two sizes agree in kind")
        label = "the two resolutions' difference (their sequences differ), at least what one finer run declares"
    else:
        correction = (t_fine - t_coarse) / (2 ** DISCRETISATION_ORDER - 1)
        extrapolated = t_fine + correction
        shown = 2 * abs(correction) / extrapolated
        result.add("recurrence_extrapolated", extrapolated, "s", also=("yr",),
                   label=f"recurrence extrapolated (Richardson, order {DISCRETISATION_ORDER:g})")
        label = "Richardson: twice the extrapolation's correction"
    if "recurrence_sampling_error" in result:  # the sequence's own error, as the single run declared it
        sequence_error = float(result.values["recurrence_sampling_error"])
    else:
        spread = result.values["recurrence_spread"]
        sequence_error = float(spread) if result.values["settled"] and spread is not None else math.inf
    result.add("discretisation_error", shown, label=f"element size's error in recurrence ({label})")
    declared = settled_error(shown + 10 * finer.rtol, sequence_error)
    result.add("estimated_relative_error", declared if math.isfinite(declared) else None,
               label="declared: the sequence's, the element size's (Richardson) and 10 rtol, added")
    if same:
        if "kind_change_error" in result:  # two sizes agreed in kind: the term is lifted
            result.set("kind_change_error", 0.0)
        result.note(f"Richardson: {loaded.fault.element_size:g} m and {finer.fault.element_size:g} m elements agree "
                    f"in kind ({describe_kind(kinds[1])}); one run would have declared "
                    f"{single_run_error(finer.resolution):.2g}")
    return result


def describe_kind(kind: tuple) -> str:
    """A run's kind of sequence (:func:`~faultslip.models.fault_2d.analysis.run_kind`) in words."""
    settled, period, interleaving = kind
    head = "unsettled or aperiodic" if not settled else "period 1" if period <= 1 else f"period {period}"
    return head + (", partial events interleaved" if interleaving else "")


def simulate(scene, output_dir=None, resume: bool = False, rtol=None, allow_large: bool = False,
             overwrite: bool = False, allow_underresolved: bool = False) -> Result:
    return simulate_fault(scene, output_dir=output_dir, resume=resume, rtol=rtol, allow_large=allow_large,
                          overwrite=overwrite, progress=True, allow_underresolved=allow_underresolved)


def one_slider_refinement(loaded, elements_per_process_zone: float = 8.0) -> Fault2DScene:
    """The 2-D fault a one-slider rate-and-state fault scene stands for (its friction from the surface to D, loaded
    below), over 24 of its block's recurrences: enough system-size events to tell a period up to 3 from the
    spin-up, where the block may recur up to its declared model error (0.75) sooner than the 2-D fault. The
    block's 3 cycles run to size it (milliseconds)."""
    block = fault_cycles(loaded.slider, loaded.plate_rate, cycles=3)
    return from_one_slider(loaded, duration=24 * block.recurrence, elements_per_process_zone=elements_per_process_zone)


def refine_one_slider(loaded, reason: str, elements_per_process_zone: float = 8.0, allow_large: bool = False,
                      progress=None) -> Result:
    """A one-slider rate-and-state fault run as the 2-D fault it stands for (its friction from the surface to D,
    loaded below): the run is estimated and checked against the budget before any work (above it,
    ``allow_large`` is needed), it reports progress, and its answer carries its own declared error.

    Parameters
    ----------
    loaded : RateStateScene
        A rate-and-state fault scene (one slider).
    reason : str
        Why the one slider was not enough (said in the result).
    elements_per_process_zone : float
        Elements per process zone L_b of the 2-D fault.
    allow_large : bool
        Run beyond the time and memory budget.
    progress : callable, optional
        ``(done, total)`` progress, with ``announce(text)`` if it has one.

    Returns
    -------
    Result
        The 2-D fault's answer, with ``method_reason`` naming the escalation.
    """
    scene = one_slider_refinement(loaded, elements_per_process_zone)
    estimate = scene.estimate(in_this_process=True)
    estimate.what = f"escalating {loaded.name} to the 2-D fault ({reason})"
    budget.check(estimate, allow_large)
    if progress is not None and hasattr(progress, "announce"):
        progress.announce(f"escalating to the 2-D fault: {estimate.describe()}")
    result = simulate_fault(scene, allow_large=allow_large, progress=progress)
    result.set("method_reason", f"the 2-D fault with the scene's friction from the surface to D: {reason}")
    result.note(f"escalated to the 2-D fault, estimated before it started at {estimate.describe()}; its declared "
                "error is the 2-D run's own (estimated_relative_error)")
    return result


def estimate(scene, action: str = "run", rtol=None, output_dir=None, method=None, tolerance=None,
             richardson: bool = False, check_starts: bool = False, include_3d: bool = False,
             **_) -> budget.Estimate:
    """What a run or simulation of a 2-D fault scene needs, before it starts: its Dormand-Prince steps from the
    events it will see, and its records (:meth:`Fault2DScene.estimate`, cost.py); the one-slider rung's block
    cycles (the rate-and-state slider's cost model); with ``richardson`` the run on half-size elements too, with
    ``check_starts`` the runs from the other starts too (a tolerance that may escalate counts the 2-D run); the
    ``fault_3d`` rung, the 3-D fault's cost model on the scene's 3-D fault; ``action="ladder"``, every rung of
    :func:`ladder` (with ``include_3d``, the 3-D one too). With a ``tolerance``, the rungs :func:`run` goes to:
    the one slider alone where its declared error, known before its block runs
    (:func:`faultslip.fault.ladder.declared_error`), meets it, else the one slider and the 2-D fault. What run
    refuses before any work (a rung it does not know, a tolerance no rung can meet) is refused here too.
    ``action="refine"``: a one-slider rate-and-state scene's escalation, the run :func:`refine_one_slider` makes."""
    if action == "refine":  # a one-slider rate-and-state scene's escalation: the 2-D fault it stands for
        estimate = one_slider_refinement(scene).estimate(in_this_process=True)
        estimate.what = f"the 2-D fault {scene.name} stands for: {estimate.what}"
        return estimate
    loaded = read_fault_2d_scene(scene, allow_large=True)
    if action == "ladder":
        return ladder_estimate(loaded, include_3d)
    chosen = rtol if rtol is not None else loaded.rtol
    if action == "run":  # the rungs run() goes to, from what it asks and what each rung declares before it runs
        method, asked = checked_request(method, tolerance, richardson, check_starts)
        slider = one_slider_estimate(f"the one slider derived from {loaded.name} (5 earthquake cycles)")
        if method == "one_slider":
            return slider
        if method == "fault_3d":  # the rung above: the scene read as a fault fault_length long
            return load("fault_3d").estimate(loaded, "run", rtol=rtol)
        if tolerance is not None and method == "auto":
            declared = declared_error(loaded.fault.description())
            if declared is not None and declared <= tolerance:
                slider.what += f": its declared error {declared:.2g} meets the tolerance {tolerance:g}"
                return slider
            refuse_unreachable(loaded, tolerance, tried_slider=True, slider_error=declared)
            why = ("outside its calibration" if declared is None else
                   f"its declared error {declared:.2g} exceeds the tolerance {tolerance:g}")
            escalated = budget.rungs_estimate(f"{loaded.name} to tolerance {tolerance:g}", {
                f"the one slider ({why})": slider,
                "then the 2-D fault of the same scene": loaded.estimate(chosen, output_dir, in_this_process=True)})
            escalated.notes = (rerun_note(loaded, chosen),)
            return escalated
        if tolerance is not None and not asked:
            refuse_unreachable(loaded, tolerance)
    if action == "run" and check_starts:
        return starts_estimate(loaded, other_starts(loaded)[1], chosen, output_dir)
    if action == "run" and richardson:
        return budget.one_after_another(f"2 runs of {loaded.name} (Richardson: its elements and half their size)", [
            loaded.estimate(chosen, output_dir, in_this_process=True),
            loaded.at_element_size(loaded.fault.element_size / 2).estimate(chosen, output_dir)])
    return loaded.estimate(chosen, output_dir, in_this_process=True)


FAMILY = register(Family("fault_2d", "quasi-dynamic cycles on a 2-D fault in an elastic half-space (SEAS BP1)",
                         run, simulate, simulate_options=("output_dir", "resume", "rtol", "allow_large", "overwrite",
                                                          "allow_underresolved"),
                         run_options=("allow_large", "allow_underresolved", "richardson", "check_starts", "progress"),
                         why="a 2-D fault scene sets its run in [run]; simulate takes --output-dir, --resume and --rtol",
                         read_scene=read_scene, cells=CELLS, methods=lambda: [ONE_SLIDER_METHOD, *METHODS.values(),
                                          *declared_rows("fault_3d", "fault_3d")],
                         refine=refine_one_slider, ladder=ladder, estimate=estimate,
                         example=Example('fault_2d_small.toml', "study_fault_2d.toml",
                                         {'critical_slip': ['24 mm', '30 mm']}, None)))
