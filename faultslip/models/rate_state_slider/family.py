"""The rate-and-state slider as a model family: a laboratory slider's velocity steps and slide-hold-slides, and
a fault's quasi-dynamic earthquake cycles on one spring-block (Dieterich-Ruina friction)."""

from __future__ import annotations

import math
import os

from faultslip.dynamics.rate_state.methods import CYCLE_METHODS
from faultslip.dynamics.rate_state.slider import simulate_rate_state
from faultslip.contract.cells import PerCell
from faultslip.contract.scenes import toml_reader
from faultslip.contract.specs import Output, Parameter
from faultslip import ranges
from faultslip.errors import InputError
from faultslip.fault.ladder import ONE_SLIDER_METHOD
from faultslip.fault.one_slider_error import declare_model_error
from faultslip.fault.rate_state_fault import cycles_dataset
from faultslip.fault.scene import (Scene, estimate_scene_rate_state, has_friction_law, read_slider_scene,
                                   with_scene_notes)
from faultslip.fault.spring_slider_cells import RATE_STATE_CELLS
from faultslip.fault.spring_slider_cells import read_scene as read_seed_law_scene
from faultslip.io.resources import parse_toml
from faultslip.models.common import note_origin
from faultslip.io import budget
from faultslip.models.rate_state_slider.one_slider import DESCRIPTIONS
from faultslip.dynamics.rate_state.slider import RateStateSlider
from faultslip.models.rate_state_slider.scene import RateStateScene, model_error_of, read_rate_state_scene, stands_for
from faultslip.io.report import Report
from faultslip.fault.rate_state_fault import seed_law_fault
from faultslip.models.rate_state_slider import cycles as rate_state_cycles
from faultslip.models.rate_state_slider.cycles import _scene_notes
from faultslip.models.rate_state_slider import cost as rate_state_slider_cost
from faultslip.contract.registry import Example, Family, declared_rows, load, register
from faultslip.contract.result import Result
from faultslip.plots.figures import _pyplot
from faultslip.models.rate_state_slider.figures import cycles_figure
from faultslip.units import ELAPSED_TIME_ATTRS


def earthquake_cycles(scene, count: int = 5, seed_law: str | None = None, progress=None) -> Result:
    """A fault's quasi-dynamic earthquake cycles ([fault]), with the seed law on the same fault beside them
    (:func:`faultslip.models.rate_state_slider.cycles.earthquake_cycles`, then the seed law's estimate;
    ``faultslip rate-state cycles --seed-law``).

    Parameters
    ----------
    scene : str, path or RateStateScene
        A rate-and-state fault scene ([law] and [fault]).
    count : int
        Cycles measured after the spin-up.
    seed_law : str, optional
        A seed-law lithology or preset (``granodiorite``) estimated on the same fault (G, D, sigma_n, plate rate).
    progress : bool or callable, optional
        True for a bar, or a callable (done, total) over events (:mod:`faultslip.io.progress`).

    Returns
    -------
    Result
        The cycles' slip per event (m), recurrence (s) and their declared error; with ``seed_law``, the seed
        law's slip per event (m) and recurrence (s) beside them, and the ratio of the slips (dimensionless).
    """
    scene = read_rate_state_scene(scene) if not hasattr(scene, "law") else scene
    result = rate_state_cycles.earthquake_cycles(scene, count, progress)
    if seed_law:
        seed = seed_law_fault(seed_law, slip_rate=scene.plate_rate, **scene.fault).estimate()
        slip = result.values["slip_per_event"].to("m").magnitude
        result.add("seed_law_slip_per_event", seed.slip_per_event, "m",
                   label=f"seed law ({seed_law}) slip per event on the same fault")
        result.add("seed_law_recurrence_period", seed.recurrence_period, "s", also=("yr",),
                   label=f"seed law ({seed_law}) recurrence on the same fault")
        result.add("slip_ratio_rate_state_to_seed", slip / seed.slip_per_event)
    return result


def velocity_step(scene, method: str = "auto", rtol: float = 1e-8) -> Result:
    """A laboratory slider's friction through its load history ([load]: steps, slide-hold-slide or a speed).

    Parameters
    ----------
    scene : str, path or RateStateScene
        A laboratory rate-and-state scene.
    method : str
        The integrator (auto, lsoda, dopri5, dopri5_compiled, radau, bdf).
    rtol : float
        Relative tolerance.

    Returns
    -------
    Result
        Friction at the start, peak and end (dimensionless), slip (m), peak slip speed (m/s), the time series
        and figure.
    """
    scene = read_rate_state_scene(scene) if not hasattr(scene, "law") else scene
    if scene.history is None:
        raise InputError(f"{scene.name} has no [load] table to simulate; for a fault's cycles use "
                         "'faultslip rate-state cycles'")
    if not (isinstance(rtol, float) and 1e-14 <= rtol <= 1e-2):
        raise InputError(f"--rtol must lie between 1e-14 and 1e-2, got {rtol}")
    history = simulate_rate_state(scene.slider, scene.history, model=scene.model, method=method, rtol=rtol,
                                  samples=scene.samples)
    law = scene.law
    final_speed = scene.history.speeds[-1] if scene.history.kind == "steps" else None
    report = Report(f"faultslip rate-state simulate: {scene.name}")
    report.add("model", scene.model).add("method", history.method)
    report.add("method_reason", history.method_reason, label="why")
    report.add("duration", float(history.time[-1]), "s").add("samples", int(history.time.size))
    report.add("initial_friction", float(history.friction[0])).add("peak_friction", float(history.friction.max()))
    report.add("final_friction", float(history.friction[-1]))
    if final_speed:
        report.add("steady_state_friction_at_final_speed", float(law.steady_state(final_speed)),
                   label="mu_ss at the last load speed")
    report.add("slip", float(history.slip[-1]), "m").add("peak_slip_speed", float(history.slip_speed.max()), "m/s")
    report.add("steps", int(history.steps)).add("function_evaluations", int(history.function_evaluations))
    report.add("wall_time", history.wall_time, "s")
    for note in history.notes:
        report.note(note)
    _scene_notes(report, scene)

    import xarray as xr  # heavy: imported where used

    series = xr.Dataset(
        {"friction": ("time", history.friction, {"units": "1", "long_name": "friction coefficient"}),
         "slip_speed": ("time", history.slip_speed, {"units": "m/s", "long_name": "slip speed V"}),
         "log_state": ("time", history.psi, {"units": "1", "long_name": "psi = ln(V0 theta / D_c)"}),
         "slip": ("time", history.slip, {"units": "m", "long_name": "slip since the start"}),
         "load_point_displacement": ("time", history.load_point,
                                     {"units": "m", "long_name": "load-point displacement"})},
        coords={"time": ("time", history.time, ELAPSED_TIME_ATTRS)},
        attrs={"title": f"faultslip rate-state simulation: {scene.name}", "Conventions": "CF-1.8",
               "model": scene.model, "method": history.method, "law": law.describe()})

    def figure():
        plt = _pyplot()
        drawing, axes = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True, constrained_layout=True)
        axes[0].plot(history.time, history.friction, color="C0")
        axes[0].set_ylabel("friction")
        axes[1].semilogy(history.time, history.slip_speed, color="C3")
        axes[1].set_ylabel("slip speed (m/s)")
        axes[1].set_xlabel("time (s)")
        drawing.suptitle(report.title, fontsize=10)
        return drawing

    return Result("rate_state_slider", report, series, figure)


#: The methods of a fault scene: one slider (its stiffness from the fault's geometry, or the seed's K = G / D) or the
#: 2-D fault it stands for.
FAULT_METHODS = ("auto", "one_slider", "fault_2d")

#: What a scene of the older form is told (issue 40: one family, whatever the shape of its file).
OLDER_FORM = ("read as one rate-and-state block from the seed-law form of a fault scene ([fault] slip_rate with "
              "[friction] law = \"rate_state\"); the rate-and-state slider's own form is [law] with [fault] "
              "plate_rate (configs/rsf_block_bp1.toml)")


def _older_form(scene):
    """The seed-law :class:`~faultslip.fault.scene.Scene` of a scene in the older form, else None."""
    if isinstance(scene, Scene):
        return scene if scene.rate_state else None
    if isinstance(scene, (str, os.PathLike)) and has_friction_law(scene, "rate_state"):
        return read_slider_scene(scene)
    return None


def _run_older_form(scene, method, tolerance, allow_large: bool = False, progress=None) -> Result:
    """A fault scene of the seed-law form on the family's ladder (:func:`seed_law_form_on_the_ladder`)."""
    method = _fault_method(method, tolerance)
    estimate = estimate_scene_rate_state(scene)
    report = with_scene_notes(estimate.report(f"faultslip rate-and-state fault: {scene.name}"), scene)
    report.note(OLDER_FORM)
    return seed_law_form_on_the_ladder(estimate, report, scene.name, method, tolerance, allow_large, progress)


def _own_form(name: str, estimate) -> RateStateScene:
    """The family's own form of the one block a seed-law estimate ran: K = G / D (the seed's reduction, which the
    model-error calibration has a table for), its normal stress, plate rate, density and wave speed."""
    inputs = estimate.fault_inputs
    slider = RateStateSlider.at_fault(estimate.law, inputs["shear_modulus"], inputs["zone_width"],
                                      estimate.normal_stress, inputs["density"], inputs["shear_wave_speed"])
    return RateStateScene(name, "fault", estimate.law, slider, "quasi_dynamic", plate_rate=estimate.plate_rate,
                          fault={**inputs, "normal_stress": estimate.normal_stress}, reduction="zone_width",
                          width=inputs["zone_width"])


def seed_law_form_on_the_ladder(estimate, report, name: str, method: str = "auto", tolerance=None,
                                allow_large: bool = False, progress=None) -> Result:
    """A one-block rate-and-state fault of the seed-law form (a fault scene with ``[friction] law = "rate_state"``,
    or a saved fit through ``faultslip fault``) on the ladder the family's own form is on.

    It declares its model error against the 2-D fault it stands for (K = G / D, the calibration's zone-width
    table) and says which fault that is; a ``tolerance`` that error does not meet, or ``method="fault_2d"``, runs
    that 2-D fault instead (estimated and budgeted first).

    Parameters
    ----------
    estimate : RateStateFaultEstimate
        The block's estimate, with the fault it ran on (``fault_inputs``).
    report : Report
        Its report, as the seed-law form words it.
    name : str
        The fault's name.
    method : str
        ``auto``, ``one_slider`` or ``fault_2d``.
    tolerance : float, optional
        The relative error allowed, model error included.
    allow_large : bool
        Run the 2-D fault beyond the time budget.
    progress : callable, optional
        The 2-D run's progress.

    Returns
    -------
    Result
        The block with ``model_error`` and its dominant ``estimated_relative_error``, or the 2-D fault's answer.
    """
    loaded = _own_form(name, estimate)
    error, ratio, how = model_error_of(loaded)
    reason = _escalation(method, tolerance, error, ratio)
    if reason is not None:
        return _two_d(loaded, reason, allow_large=allow_large, progress=progress)
    result = Result("rate_state_slider", report)
    declare_model_error(result, error, ratio, how, stands_for(loaded))
    return result



def _rate_state_cycles(scene, cycles, slip_solver, rtol) -> Result:
    """A fault scene with rate-and-state friction: its quasi-dynamic cycles as a time series."""
    if slip_solver is not None or rtol is not None:
        raise InputError("--slip-solver and --rtol belong to the seed law's simulation; a rate-and-state fault's "
                         "cycles run at rtol 1e-7 with the method auto picks")
    cycles = 5 if cycles is None else cycles
    if not 1 <= cycles <= 1000:
        raise InputError(f"--cycles must be from 1 to 1000 for a rate-and-state fault, got {cycles}")
    estimate = estimate_scene_rate_state(scene, cycles=cycles, record=True)
    report = estimate.report(f"faultslip simulation (rate-and-state fault): {scene.name}")
    note_origin(report, scene.origin)
    report.note(OLDER_FORM)
    if estimate.cycles is None:
        report.note("steady sliding is stable here (K >= K_c): no cycles to record")
        return Result("rate_state_slider", report)
    dataset = cycles_dataset(estimate, f"faultslip rate-and-state cycles: {scene.name}")
    dataset.attrs["scene_text"] = scene.text
    report.add("samples", int(dataset.sizes["time"]), label="time samples (the integrator's steps)")
    result = Result("rate_state_slider", report, dataset, lambda: cycles_figure(dataset))
    loaded = _own_form(scene.name, estimate)  # the block stands for a fault: its model error, as run declares it
    declare_model_error(result, *model_error_of(loaded), stands_for(loaded))
    return result




def run(scene, method=None, tolerance=None, allow_large: bool = False, progress=None) -> Result:
    """A laboratory slider's load history, or a fault's cycles: what the scene describes.

    A fault scene's methods are ``one_slider`` (one quasi-dynamic spring-block, K = c G / W from the seismogenic
    width W, or the seed's K = G / D from the zone width D; :mod:`faultslip.models.rate_state_slider.one_slider`) and ``fault_2d``
    (the 2-D fault with the same friction from the surface to W, loaded below).
    ``tolerance`` is the model error allowed: ``auto`` takes one slider where its declared error
    against the 2-D fault (faultslip.models.rate_state_slider.model_error, from the shipped calibration) meets it,
    and the 2-D fault otherwise; without a tolerance it takes one slider and declares its error.
    """
    # the slider's own cost before any work; an escalation checks the 2-D fault's estimate before it starts
    budget.check(rate_state_slider_cost.estimate(scene, "run", method=method, tolerance=tolerance), allow_large)
    older = _older_form(scene)
    if older is not None:
        return _run_older_form(older, method, tolerance, allow_large, progress)
    loaded = read_rate_state_scene(scene)
    if loaded.kind == "lab":
        _lab_request(method, tolerance)
        return velocity_step(loaded)
    method = _fault_method(method, tolerance)
    error, ratio, how = model_error_of(loaded)
    reason = _escalation(method, tolerance, error, ratio)
    if reason is not None:
        return _two_d(loaded, reason, allow_large=allow_large, progress=progress)
    result = earthquake_cycles(loaded)
    result.add("method", "one_slider")
    if method == "one_slider":
        result.add("method_reason", "asked for by name")
    elif tolerance is None:
        result.add("method_reason", f"one spring-block, {DESCRIPTIONS[loaded.reduction]} (no model tolerance "
                                    "given: give one, or --method fault_2d, for the 2-D fault)")
    else:
        result.add("method_reason", f"one slider's declared model error {error:.2g} meets the tolerance {tolerance:g}")
    result.add("stiffness", loaded.slider.stiffness, "Pa/m", label=f"the block's stiffness ({DESCRIPTIONS[loaded.reduction]})")
    return result  # its model error declared by earthquake_cycles, as every door to one block does


def _lab_request(method, tolerance) -> None:
    """A laboratory scene takes no method or tolerance: refused in one sentence (run and estimate alike)."""
    if method not in (None, "auto") or tolerance is not None:
        raise InputError("a rate-and-state laboratory scene chooses its integrator and tolerance itself (rtol "
                         "1e-8); use 'faultslip rate-state simulate --method' to choose one")


def _fault_method(method, tolerance) -> str:
    """A fault's method (``auto`` where none), with its tolerance, refused in one sentence where run cannot take
    them (run and estimate alike)."""
    method = method or "auto"
    if method not in FAULT_METHODS:
        raise InputError(f"a rate-and-state fault runs one of {', '.join(FAULT_METHODS)}, got {method!r}")
    ranges.check_tolerance(tolerance, label="the tolerance of a fault's model error")
    return method


def estimate(scene, action: str = "run", method=None, tolerance=None, **options) -> budget.Estimate:
    """What a run or simulation of a rate-and-state scene needs, before it starts (cost.py's model of the slider's
    cycles or load history); a fault's run that its method or tolerance sends to the 2-D fault it stands for is
    estimated as that run (the richer family's cost model, as the escalation estimates it; the block's 3 cycles
    run first to size it, as they do there). What run refuses (an unknown method, a tolerance that is not a
    positive number, either on a laboratory scene) is refused here too."""
    def own() -> budget.Estimate:
        return rate_state_slider_cost.estimate(scene, action, method=method, tolerance=tolerance, **options)

    if action != "run":
        return own()
    older = _older_form(scene)
    loaded = read_rate_state_scene(scene) if older is None else None
    if loaded is not None and loaded.kind == "lab":
        _lab_request(method, tolerance)
        return own()
    chosen = _fault_method(method, tolerance)
    if chosen == "one_slider" or (chosen == "auto" and tolerance is None):
        return own()
    if older is not None:
        loaded = _own_form(older.name, estimate_scene_rate_state(older))
    error, ratio, _ = model_error_of(loaded)
    reason = _escalation(chosen, tolerance, error, ratio)
    if reason is None:
        return own()
    refined = load(RICHER).estimate(loaded, "refine")
    refined.what = f"{refined.what} ({reason})"
    return refined


def _two_d(loaded, reason: str, allow_large: bool = False, progress=None) -> Result:
    """Escalate to the richer model the family declares (:data:`RICHER`), through the contract: it builds the
    2-D fault this one slider stands for, estimates and budgets its run before any work, reports progress, and
    its answer carries its own declared error."""
    return load(RICHER).refine(loaded, reason, allow_large=allow_large, progress=progress)


def _escalation(method: str, tolerance, error: float, ratio: float) -> str | None:
    """Why one block gives way to the 2-D fault it stands for (asked for by name, or a model error the tolerance
    does not allow), or None where the block answers."""
    if method == "fault_2d":
        return "asked for by name"
    if method == "auto" and tolerance is not None and not error <= tolerance:
        return (f"one slider's declared model error {error:.2g} (W / h* = {ratio:.3g}) exceeds the tolerance "
                f"{tolerance:g}")
    return None


def stability(scene) -> Result:
    """The critical stiffness k_c of a rate-and-state slider or fault, quasi-static, with the radiation damper
    and with inertia, and k / k_c (``faultslip rate-state stability``; Ruina 1983, Rice and Ruina 1983).

    Parameters
    ----------
    scene : str, path or RateStateScene
        A rate-and-state scene (a laboratory slider or a fault) with one state variable.

    Returns
    -------
    Result
        k_c in the scene's stiffness unit (Pa/m on a fault; 1/m for friction per slip; N/m), k / k_c and the
        regime it implies.
    """
    scene = read_rate_state_scene(scene)
    slider, law = scene.slider, scene.law
    if law.two_state:
        raise InputError("the critical stiffness of a two-state law has no closed form here; give one state variable")
    speed = scene.plate_rate if scene.kind == "fault" else scene.history.speeds[0]
    report = Report(f"faultslip rate-state stability: {scene.name}")
    k_c = slider.critical_stiffness()
    unit = "Pa/m" if scene.kind == "fault" else ("1/m" if slider.normal_stress == 1.0 else "N/m")
    report.add("stiffness", slider.stiffness, unit)
    report.add("sliding_speed", speed, "m/s", label="steady sliding speed")
    report.add("critical_stiffness_quasi_static", k_c, unit, label="k_c = sigma_n (b - a) / D_c")
    ratio = slider.stiffness / k_c if k_c > 0 else math.inf
    report.add("stiffness_ratio", ratio if math.isfinite(ratio) else None, label="k / k_c (quasi-static)")
    if slider.damping > 0:
        report.add("critical_stiffness_quasi_dynamic", slider.critical_stiffness(speed, "quasi_dynamic"), unit,
                   label="k_c with the radiation damper")
    if slider.mass > 0:
        report.add("critical_stiffness_inertial", slider.critical_stiffness(speed, "inertial"), unit,
                   label="k_c with inertia (and damper)")
    if law.b <= law.a:
        regime = "velocity strengthening (b <= a): steady sliding is stable for every stiffness"
    elif ratio > 1:
        regime = "stable to small perturbations (k > k_c)"
        if law.evolution == "slip":
            regime += "; with the slip law a large enough velocity step still destabilises it (Gu et al. 1984)"
    else:
        regime = "unstable (k < k_c): stick-slip or earthquake cycles"
    report.add("regime", regime)
    _scene_notes(report, scene)
    return Result("rate_state_slider", report)


def simulate(scene, cycles=None, slip_solver=None, rtol=None) -> Result:
    """The same as :func:`run`; ``cycles`` sets a fault's number of earthquake cycles (default 5)."""
    older = _older_form(scene)
    if older is not None:
        return _rate_state_cycles(older, cycles, slip_solver, rtol)
    if slip_solver is not None or rtol is not None:
        raise InputError("--slip-solver and --rtol belong to the seed law's simulation; a rate-and-state slider's "
                         "integrator and tolerance are chosen for it")
    loaded = read_rate_state_scene(scene)
    if loaded.kind == "lab":
        if cycles is not None:
            raise InputError("--cycles counts a fault's earthquake cycles; a laboratory slider runs its [load] history")
        return velocity_step(loaded)
    result = rate_state_cycles.earthquake_cycles(loaded, 5 if cycles is None else cycles, record=True)
    if result.series is not None:
        result.figure = lambda: cycles_figure(result.series)
    return result


#: What a rate-and-state study sweeps: the law, and a fault's inputs ([law] and [fault] of the scene).
LAW_PARAMETERS = {name: Parameter(name, kind, unit, long_name, ("law", name)) for name, kind, unit, long_name in (
    ("a", "dimensionless", "1", "direct effect a"),
    ("b", "dimensionless", "1", "evolution effect b"),
    ("critical_slip", "length", "m", "critical slip distance D_c"),
    ("mu0", "dimensionless", "1", "reference friction mu0 at V0"),
    ("reference_speed", "speed", "m/s", "reference speed V0"),
    ("evolution", "category", None, "state evolution law (aging or slip)"),
)}
FAULT_PARAMETERS = {name: Parameter(name, kind, unit, long_name, ("fault", name)) for name, kind, unit, long_name in (
    ("shear_modulus", "pressure", "Pa", "shear modulus G"),
    ("seismogenic_width", "length", "m", "seismogenic width W (K = c G / W, c calibrated against the 2-D fault)"),
    ("zone_width", "length", "m", "elastic-zone width D (the seed's reduction, K = G / D)"),
    ("normal_stress", "pressure", "Pa", "effective normal stress"),
    ("plate_rate", "speed", "m/s", "plate rate V_pl"),
    ("density", "density", "kg/m^3", "rock density rho (m = rho G / K)"),
    ("shear_wave_speed", "speed", "m/s", "shear-wave speed c_s (radiation damper G / (2 c_s))"),
)}
PARAMETERS = {**LAW_PARAMETERS, **FAULT_PARAMETERS}
FAULT_OUTPUTS = {spec.name: spec for spec in (
    Output("regime", "1", "regime of the cycles",
           flags=("stick_slip", "stable_sliding", "velocity_strengthening", "slow_or_creeping")),
    Output("recurrence_period", "s", "recurrence period of the settled cycles"),
    Output("slip_per_event", "m", "slip per event"),
    Output("stress_drop", "Pa", "stress drop"),
    Output("peak_slip_rate", "m/s", "peak slip rate"),
    Output("stiffness_ratio", "1", "K / K_c (quasi-static K_c)"),
    Output("plate_slip_balance", "1", "slip per cycle / (V_pl T)"),
    Output("model_error", "1", "declared model error of one slider against the 2-D fault (relative)"),
    Output("width_over_nucleation", "1", "W / h*, what governs the model error"),
    Output("method", "1", "method of this cell", flags=("one_slider", "fault_2d")),
    Output("estimated_relative_error", "1", "declared relative error: the larger of model_error and numerical_error"),
    Output("numerical_error", "1", "the cycles' own error (integrator scatter, plus the settling left)"),
)}
LAB_OUTPUTS = {spec.name: spec for spec in (
    Output("initial_friction", "1", "friction at the start of the load history"),
    Output("peak_friction", "1", "largest friction in the run"),
    Output("final_friction", "1", "friction at the end of the run"),
    Output("steady_state_friction_at_final_speed", "1", "steady-state friction at the final load-point speed"),
    Output("slip", "m", "slip over the run"),
    Output("peak_slip_speed", "m/s", "largest slip speed"),
    Output("method", "1", "integrator of this cell", flags=("lsoda", "dopri5", "dopri5_compiled")),
)}


def _is_fault(scene) -> bool:
    return "fault" in scene.document()


def _cell(scene, method=None, tolerance=None) -> Result:
    """One cell of a study. A fault that can have no earthquake cycles (b <= a, or K >= K_c) is a cell flagged with
    its regime, not a refusal of the whole study: a study maps where the cycles are (as the seed law's does)."""
    loaded = read_rate_state_scene(scene)
    if loaded.kind == "fault":
        law, slider = loaded.law, loaded.slider
        ratio = slider.stiffness / slider.critical_stiffness() if law.b > law.a else math.inf
        if not ratio < 1:
            report = Report(f"faultslip rate-state cell: {loaded.name}")
            report.add("regime", "velocity_strengthening" if law.b <= law.a else "stable_sliding")
            report.add("stiffness_ratio", ratio if math.isfinite(ratio) else None)
            return Result("rate_state_slider", report)
    return run(loaded, method=method, tolerance=tolerance)


PER_CELL = PerCell("a rate-and-state study",
                   lambda scene: PARAMETERS if _is_fault(scene) else LAW_PARAMETERS,
                   lambda scene: FAULT_OUTPUTS if _is_fault(scene) else LAB_OUTPUTS,
                   _cell, read_rate_state_scene, methods=("auto", "one_slider"), seconds=0.05)
_READ_OWN = toml_reader("rate_state_slider", PARAMETERS)


def read_scene(text: str, source: str, path=None):
    """A study's base: the family's own form as a TomlScene, the older seed-law form as its Scene."""
    friction = parse_toml(text, source).get("friction")
    if isinstance(friction, dict) and friction.get("law") == "rate_state":
        return read_seed_law_scene(text, source, path)
    return _READ_OWN(text, source, path)


def cells(scene):
    """The older form sweeps vectorised (K / K_c in closed form, cycles where asked); the family's own form
    cell by cell, each a run."""
    return RATE_STATE_CELLS if isinstance(scene, Scene) else PER_CELL

#: The family a fault's cycles escalate to when one slider's model error is too large.
RICHER = "fault_2d"

FAMILY = register(Family("rate_state_slider", "the rate-and-state slider: velocity steps in the lab, quasi-dynamic "
                         "cycles of a fault on one spring-block", run, simulate,
                         simulate_options=("cycles", "slip_solver", "rtol"),
                         why="a rate-and-state slider's run is set by its [load] table, a fault's by --cycles",
                         run_options=("allow_large", "progress"), read_scene=read_scene, cells=cells,
                         adopt=seed_law_form_on_the_ladder,
                         methods=lambda: [*(method.describe() for method in CYCLE_METHODS.values()), ONE_SLIDER_METHOD,
                                          *declared_rows(RICHER, RICHER)], estimate=estimate,
                         example=Example('rsf_block_bp1.toml', "study_rate_state_slider.toml",
                                         {'critical_slip': ['4 mm', '8 mm']}, {'cycles': 2})))
