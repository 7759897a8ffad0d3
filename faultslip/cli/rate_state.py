"""Rate-and-state commands: simulate, stability, cycles (and fit --law rate-state in faultslip.cli.lab)."""

from __future__ import annotations

import math

from faultslip.cli.common import _emit, _locked, _outputs
from faultslip.dynamics.rate_state import fault_cycles, simulate_rate_state
from faultslip.errors import FaultslipError
from faultslip.fault.rate_state_fault import seed_law_fault
from faultslip.fault.rate_state_scene import load_rate_state_scene
from faultslip.io.netcdf import write_dataset
from faultslip.io.report import Report

YEAR = 365.25 * 86400.0


def cmd_missing_action(args) -> int:
    raise FaultslipError("faultslip rate-state needs an action: simulate, stability, cycles or bench")


def _scene_notes(report, scene):
    report.note(scene.law.describe())
    if scene.origin:
        report.note(f"scene: {scene.origin}")


def cmd_simulate(args) -> int:
    output = _outputs(args, {"output": ("-o", (".nc",))}, [args.scene])["output"]
    if not (isinstance(args.rtol, float) and 1e-14 <= args.rtol <= 1e-2):
        raise FaultslipError(f"--rtol must lie between 1e-14 and 1e-2, got {args.rtol}")
    scene = load_rate_state_scene(args.scene)
    if scene.history is None:
        raise FaultslipError(f"{args.scene} has no [load] table to simulate; for a fault's cycles use "
                             "'faultslip rate-state cycles'")
    run = simulate_rate_state(scene.slider, scene.history, model=scene.model, method=args.method, rtol=args.rtol,
                              samples=scene.samples)
    law = scene.law
    final_speed = scene.history.speeds[-1] if scene.history.kind == "steps" else None
    report = Report(f"faultslip rate-state simulate: {scene.name}")
    report.add("model", scene.model).add("method", run.method).add("method_reason", run.method_reason, label="why")
    report.add("duration", float(run.time[-1]), "s").add("samples", int(run.time.size))
    report.add("initial_friction", float(run.friction[0])).add("peak_friction", float(run.friction.max()))
    report.add("final_friction", float(run.friction[-1]))
    if final_speed:
        report.add("steady_state_friction_at_final_speed", float(law.steady_state(final_speed)),
                   label="mu_ss at the last load speed")
    report.add("slip", float(run.slip[-1]), "m").add("peak_slip_speed", float(run.slip_speed.max()), "m/s")
    report.add("steps", int(run.steps)).add("function_evaluations", int(run.function_evaluations))
    report.add("wall_time", run.wall_time, "s")
    for note in run.notes:
        report.note(note)
    _scene_notes(report, scene)
    if output:
        import xarray as xr  # heavy: imported where used

        dataset = xr.Dataset(
            {"friction": ("time", run.friction, {"units": "1", "long_name": "friction coefficient"}),
             "slip_speed": ("time", run.slip_speed, {"units": "m/s", "long_name": "slip speed V"}),
             "log_state": ("time", run.psi, {"units": "1", "long_name": "psi = ln(V0 theta / D_c)"}),
             "slip": ("time", run.slip, {"units": "m", "long_name": "slip since the start"}),
             "load_point_displacement": ("time", run.load_point, {"units": "m", "long_name": "load-point displacement"})},
            coords={"time": ("time", run.time, {"units": "s", "long_name": "time"})},
            attrs={"title": f"faultslip rate-state simulation: {scene.name}", "Conventions": "CF-1.8",
                   "model": scene.model, "method": run.method, "law": law.describe()})
        with _locked(output):
            write_dataset(dataset, output)
        report.note(f"time series written to {output}")
    return _emit(report, args.json)


def cmd_stability(args) -> int:
    scene = load_rate_state_scene(args.scene)
    slider, law = scene.slider, scene.law
    if law.two_state:
        raise FaultslipError("the critical stiffness of a two-state law has no closed form here; give one state variable")
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
    return _emit(report, args.json)


def cmd_cycles(args) -> int:
    if not 1 <= args.cycles <= 10_000:
        raise FaultslipError(f"--cycles must lie between 1 and 10000, got {args.cycles}")
    scene = load_rate_state_scene(args.scene)
    if scene.kind != "fault":
        raise FaultslipError(f"{args.scene} describes a laboratory slider; fault cycles need a [fault] table with "
                             "shear_modulus, zone_width, normal_stress and plate_rate")
    result = fault_cycles(scene.slider, scene.plate_rate, cycles=args.cycles,
                          model="quasi_dynamic" if scene.model != "quasi_static" else "quasi_static")
    report = Report(f"faultslip rate-state cycles: {scene.name}")
    report.add("recurrence_period", result.recurrence, "s", also=("yr",))
    report.add("slip_per_event", float(result.slip_per_event.mean()), "m")
    report.add("stress_drop", float(result.stress_drop.mean()), "Pa", also=("MPa",))
    report.add("peak_slip_rate", float(result.peak_slip_rate.max()), "m/s")
    report.add("stiffness_ratio", result.stiffness_ratio, label="K / K_c (quasi-static k_c)")
    report.add("regime", result.regime).add("cycles", int(result.slip_per_event.size))
    report.add("plate_slip_balance", float((result.cycle_slip / (result.plate_rate * result.recurrence)).mean()),
               label="slip per cycle / (V_pl T)")
    report.add("model", result.model).add("steps", int(result.steps)).add("wall_time", result.wall_time, "s")
    report.note(f"events: slip speed above {result.event_speed:g} m/s (the SEAS convention)")
    if args.seed_law:
        seed = seed_law_fault(args.seed_law, slip_rate=scene.plate_rate, **scene.fault).estimate()
        report.add("seed_law_slip_per_event", seed.slip_per_event, "m",
                   label=f"seed law ({args.seed_law}) slip per event on the same fault")
        report.add("seed_law_recurrence_period", seed.recurrence_period, "s", also=("yr",),
                   label=f"seed law ({args.seed_law}) recurrence on the same fault")
        report.add("slip_ratio_rate_state_to_seed", float(result.slip_per_event.mean()) / seed.slip_per_event)
    _scene_notes(report, scene)
    return _emit(report, args.json)
