"""The one slider's declared model error against the 2-D fault, from the shipped calibration (issue 42).

A one-slider scene states its fault's seismogenic width W (the block's stiffness then K = c G / W, c calibrated),
or the elastic-zone width D of the seed's section 5-2 reduction (K = G / D). What it does not state (a
strengthening cap above a buried fault, the ramp below W, how deep the fault reaches before it creeps) the
calibration spans: ``benchmarks/fault_2d_calibration.py`` runs a designed set of 2-D faults over W / h*, the
width over the nucleation size h* = (pi / 2) G D_c b / [sigma_n (b - a)^2] (Rubin & Ampuero 2005), over a - b
and over those geometries, and the block beside each. The declared model error at a scene's W / h* is the
largest over the designs at the two calibrated levels that bracket it, times 1.25, a bound whose coverage the
calibration measures on faults held out of it, SEAS BP1 among them. Outside the calibrated range nothing is
known: the error is unbounded, and ``auto`` with a tolerance runs the 2-D fault.
"""

from __future__ import annotations

import math

from faultslip.contract.registry import family_of
from faultslip.contract.result import Result
from faultslip import ranges
from faultslip.errors import InputError
from faultslip.fault.one_slider_error import declared_from_envelope, declared_model_error, load_calibration
from faultslip.models.rate_state_slider.one_slider import DESCRIPTIONS, load_hierarchy
from faultslip.models.rate_state_slider.scene import read_rate_state_scene
from faultslip.io.report import Report
from faultslip.fault.dip_error import load_table as load_dip_table
from faultslip.models.rate_state_slider.figures import model_error_figure

__all__ = ["declared_from_envelope", "declared_model_error", "load_calibration", "model_error_result"]


def model_error_result(scene=None, tolerance: float | None = None, include_3d: bool = False):
    """The shipped calibration of one slider against the 2-D fault over W / h*, its held-out coverage, and a
    scene's declared model error (``faultslip model-error``).

    Parameters
    ----------
    scene : str, path or RateStateScene, optional
        A rate-and-state fault scene: its W / h* and declared model error.
    tolerance : float, optional
        A model error allowed: whether one slider suffices.
    include_3d : bool
        On a 2-D fault scene, add the rung above it: the 3-D fault its ``fault_length`` states (a 3-D scene's
        ladder has it already).

    Returns
    -------
    Result
        The declared model error at each calibrated W / h* (relative), the held-out coverage, the scene's, and
        ``plot()`` the chart.
    """
    tolerance = ranges.check_tolerance(tolerance, "--tolerance")
    if scene is not None:
        family = family_of(scene)
        if include_3d and family.name not in ("fault_2d", "fault_3d"):
            raise InputError(f"--include-3d adds the 3-D fault to a 2-D fault scene's ladder; {scene} is a "
                             f"{family.name} scene")
        if family.ladder is not None:  # a fault scene: every rung on it (the ladder)
            extra = {"include_3d": True} if include_3d and family.name == "fault_2d" else {}
            return family.ladder(scene, tolerance=tolerance, **extra)
        if family.name != "rate_state_slider":  # the one slider's model error is a rate-and-state fault's
            raise InputError(f"the model error is a fault's, against the rungs of its ladder: give a fault scene (a "
                             f"rate-and-state fault, a 2-D or a 3-D fault: configs/seas_bp1.toml); {scene} is a "
                             f"{family.name} scene")
    if include_3d:
        raise InputError("--include-3d adds the 3-D fault to a 2-D fault scene's ladder: give the scene")
    table = load_calibration()
    report = Report("faultslip model error: one slider against the 2-D fault")
    geometric = table["geometric"]
    report.add("stiffness_factor", geometric["stiffness_factor"],
               label="c of the block's stiffness K = c G / W (calibrated; 2 / pi = 0.637 is a surface-breaking crack's)")
    for row in geometric["rows"]:
        key = f"w_over_h_{row['width_over_nucleation']:.3g}".replace(".", "_")
        report.add(key, row["model_error"], label=f"W / h* = {row['width_over_nucleation']:.3g}: declared model error")
    for name, key in (("held_out_coverage", "geometric"), ("held_out_coverage_zone_width", "zone_width")):
        held = table[key]["held_out"]
        report.add(name, table[key]["coverage"], label=f"held-out faults within the declared error ({DESCRIPTIONS[key]}): "
                   f"{sum(row['covered'] for row in held)} of {len(held)}")
    dipping = load_dip_table()
    widths = [row["width_over_nucleation"] for row in dipping["faults"]]
    report.add("antiplane_on_dip_faults_measured", len(dipping["faults"]),
               label=f"the antiplane rung against plane strain: dipping faults measured (W / h* {min(widths):.3g}-"
                     f"{max(widths):.3g}); declared, the largest error at any W / h* up to a factor "
                     f"{math.exp(dipping['window']):.3g} above a fault's, times {dipping['margin']:g}")
    report.add("antiplane_on_dip_held_out_coverage", dipping["coverage"],
               label=f"held-out dipping faults within it: {sum(row['covered'] for row in dipping['held_out'])} of "
                     f"{len(dipping['held_out'])}")
    if scene is not None:
        loaded = read_rate_state_scene(scene)
        if loaded.kind != "fault":
            raise InputError(f"{scene} is a laboratory slider; the model error is a fault's ([fault] table)")
        error, ratio, how = declared_model_error(loaded.law, loaded.fault["shear_modulus"],
                                                 loaded.fault["normal_stress"], loaded.width, table, loaded.reduction)
        report.add("width_over_nucleation", ratio, label=f"{loaded.name}: W / h*")
        report.add("model_error", error if math.isfinite(error) else None,
                   label=f"{loaded.name}: declared model error (null: unbounded)")
        if tolerance is not None:
            report.add("one_slider_suffices", bool(error <= tolerance), label=f"one slider suffices at {tolerance:g}")
        report.note(how)
    provenance = table.get("provenance", {})
    report.note(f"calibration: {provenance.get('computed_by', '?')}, {provenance.get('date', '?')}; "
                f"{provenance.get('definition', '')}")
    return Result("rate_state_slider", report, figure=lambda: model_error_figure(table, tolerance, load_hierarchy()))
