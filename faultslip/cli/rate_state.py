"""Rate-and-state commands: simulate, stability, cycles (and fit --law rate-state in faultslip.cli.lab)."""

from __future__ import annotations

import math

from faultslip.constants import JULIAN_YEAR
from faultslip.cli.common import _locked, _outputs
from faultslip.cli.printing import _emit, _progress
from faultslip.errors import FaultslipError
from faultslip.fault.rate_state_scene import load_rate_state_scene
from faultslip.io.netcdf import write_dataset
from faultslip.io.report import Report
from faultslip.models.rate_state_slider import earthquake_cycles, velocity_step

YEAR = JULIAN_YEAR


def cmd_missing_action(args) -> int:
    raise FaultslipError("faultslip rate-state needs an action: simulate, stability, cycles or bench")


def _scene_notes(report, scene):
    report.note(scene.law.describe())
    if scene.origin:
        report.note(f"scene: {scene.origin}")


def cmd_simulate(args) -> int:
    output = _outputs(args, {"output": ("-o", (".nc",))}, [args.scene])["output"]
    result = velocity_step(args.scene, method=args.method, rtol=args.rtol)
    report = result.report()
    if output:
        with _locked(output):
            write_dataset(result.time_series(), output)
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


def cmd_cycles_beside_seed_law(args) -> int:
    """rate-state cycles --seed-law: the cycles, and the seed law on the same fault (the parser routes here)."""
    return _emit(earthquake_cycles(args.scene, args.cycles, args.seed_law,
                                   progress=_progress("cycles", not args.json, "event")).report(), args.json)
