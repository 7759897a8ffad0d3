"""The one slider's declared model error against the 2-D fault (issue 33), from the shipped calibration.

The one-slider model's error against the 2-D fault, calibrated and shipped (issue 33).

A rate-and-state fault reduced to one spring-block (K = G / D) stands for a fault whose friction is
uniform from the surface to D, loaded by steady slip below (:func:`from_one_slider`). How well the
block reproduces that fault is governed by W / h*, the width over the nucleation size
h* = (pi / 2) G D_c b / [sigma_n (b - a)^2] (Rubin & Ampuero 2005). Near 1 the whole fault slips
together, but more softly than the block: a surface-breaking fault slipping over D has the
stiffness 2 G / (pi D) (the mode III crack's mean slip), 0.64 of the block's G / D, so it slips
more and recurs less often. Well above 1, ruptures nucleate, grow and arrest in ways a block
cannot, and the sequence can alternate between partial and full ruptures.

:func:`faultslip.models.fault_2d.calibration.calibrate` runs both models over W / h* (changing D_c, the rest of SEAS BP1's friction on a
20 km fault) and measures the block's relative error in recurrence and in slip per event (the 2-D
slip averaged over the velocity-weakening width); the model error is the larger. The table
``data/fault_2d_model_error.json`` is that calibration, computed by
``python benchmarks/fault_2d_calibration.py`` and shipped with its provenance;
:func:`declared_model_error` interpolates it (linear in log W / h*) for a scene.
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.contract.result import Result
from faultslip.errors import InputError
from faultslip.fault.rate_state_scene import load_rate_state_scene
from faultslip.friction.rate_state import nucleation_ratio
from faultslip.io import gate
from faultslip.io.report import Report
from faultslip.io.resources import bundled_dir
from faultslip.models.rate_state_slider.figures import model_error_figure

CALIBRATION_FILE = "fault_2d_model_error.json"

def load_calibration() -> dict:
    """The shipped calibration of one slider against the 2-D fault (``data/model_error.json``).

    Returns
    -------
    dict
        ``rows``: W / h* and the model error (relative) of each calibrated fault; ``provenance``.
    """
    path = bundled_dir("data") / CALIBRATION_FILE
    try:
        return gate.read_json(path, "the model-error calibration")
    except InputError as exc:
        raise InputError(f"{exc}; reinstall faultslip or run benchmarks/fault_2d_calibration.py") from None


def declared_model_error(law, shear_modulus: float, normal_stress: float, width: float,
                         calibration: dict | None = None) -> tuple[float, float, str]:
    """(model error, W / h*, how it was found) of a one-slider fault, from the shipped calibration.

    Parameters
    ----------
    law : RateStateLaw
        The fault's friction.
    shear_modulus : float
        G (Pa).
    normal_stress : float
        sigma_n (Pa).
    width : float
        W, the width of the velocity-weakening zone (m; D of the one slider).
    calibration : dict, optional
        The calibration table (the shipped one otherwise).

    Returns
    -------
    tuple
        (model error, W / h*, how it was found): the relative error of one slider against the 2-D fault, in
        recurrence or slip, whichever is larger (dimensionless).
    """
    table = calibration or load_calibration()
    ratios = np.array([row["width_over_nucleation"] for row in table["rows"]])
    errors = np.array([row["model_error"] for row in table["rows"]])
    order = np.argsort(ratios)
    ratios, errors = ratios[order], errors[order]
    ratio = nucleation_ratio(law, shear_modulus, normal_stress, width)
    if ratio <= 0:
        return math.nan, ratio, "b <= a: the fault creeps, neither model has earthquakes"
    if ratio < ratios[0]:
        return float(errors[0]), ratio, (f"W / h* = {ratio:.3g} is below the calibration ({ratios[0]:.3g} to "
                                         f"{ratios[-1]:.3g}): its nearest value is declared; below about 1 a 2-D "
                                         "fault may creep where the block slips")
    if ratio > ratios[-1]:
        return float(errors.max()), ratio, (f"W / h* = {ratio:.3g} is beyond the calibration ({ratios[0]:.3g} to "
                                            f"{ratios[-1]:.3g}): its largest value is declared")
    value = float(np.interp(math.log(ratio), np.log(ratios), errors))
    return value, ratio, f"interpolated in the shipped calibration at W / h* = {ratio:.3g}"


def model_error_result(scene=None, tolerance: float | None = None):
    """The shipped calibration of one slider (K = G / D) against the 2-D fault over W / h*, and a scene's
    declared model error (``faultslip model-error``).

    Parameters
    ----------
    scene : str, path or RateStateScene, optional
        A rate-and-state fault scene: its W / h* and declared model error.
    tolerance : float, optional
        A model error allowed: whether one slider suffices.

    Returns
    -------
    Result
        The calibration's model error at each W / h* (relative), the scene's, and ``plot()`` the map.
    """
    if tolerance is not None and not tolerance > 0:
        raise InputError(f"--tolerance must be positive, got {tolerance}")
    table = load_calibration()
    report = Report("faultslip model error: one slider (K = G / D) against the 2-D fault")
    for row in table["rows"]:
        key = f"w_over_h_{row['width_over_nucleation']:.3g}".replace(".", "_")
        report.add(key, row["model_error"], label=f"W / h* = {row['width_over_nucleation']:.3g}: model error"
                   + ("" if "recurrence_error" not in row else
                      f" (recurrence {row['recurrence_error']:+.2f}, slip {row['slip_error']:+.2f})"))
    if scene is not None:
        loaded = load_rate_state_scene(scene)
        if loaded.kind != "fault":
            raise InputError(f"{scene} is a laboratory slider; the model error is a fault's ([fault] table)")
        error, ratio, how = declared_model_error(loaded.law, loaded.fault["shear_modulus"],
                                                 loaded.fault["normal_stress"], loaded.fault["zone_width"], table)
        report.add("width_over_nucleation", ratio, label=f"{loaded.name}: W / h*")
        report.add("model_error", error, label=f"{loaded.name}: declared model error")
        if tolerance is not None:
            report.add("one_slider_suffices", bool(error <= tolerance), label=f"one slider suffices at {tolerance:g}")
        report.note(how)
    provenance = table.get("provenance", {})
    report.note(f"calibration: {provenance.get('computed_by', '?')}, {provenance.get('date', '?')}; "
                f"{provenance.get('definition', '')}")
    return Result("rate_state_slider", report, figure=lambda: model_error_figure(table, tolerance))
