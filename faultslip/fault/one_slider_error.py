"""The one slider's declared model error against the 2-D fault, from the shipped calibration (issue 42), for one
fault or for every cell of a study or map.

``data/fault_2d_model_error.json`` (``benchmarks/fault_2d_calibration.py``) holds, for each reduction of a fault to
one block (K = c G / W from the seismogenic width, or the seed's K = G / D from the elastic-zone width), the
largest relative error of the block against the 2-D fault at each calibrated W / h*, times a safety factor of 1.25;
h* = (pi / 2) G D_c b / [sigma_n (b - a)^2] is the nucleation size (Rubin & Ampuero 2005). The declared error at a
W / h* is the larger of the two calibrated levels that bracket it; outside the calibrated range it is unbounded.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from faultslip.errors import InputError
from faultslip.friction.rate_state import nucleation_ratio, nucleation_size
from faultslip.io.resources import read_bundled_table
from faultslip.units import takes_units

CALIBRATION_FILE = "fault_2d_model_error.json"
#: The reductions a scene may ask for, by the [fault] key that states its width.
REDUCTIONS = {"seismogenic_width": "geometric", "zone_width": "zone_width"}
#: What each reduction is called in a report.
DESCRIPTIONS = {"geometric": "K = c G / W from the seismogenic width W (c calibrated against the 2-D fault)",
                "zone_width": "the seed's section 5-2 reduction, K = G / D from the elastic-zone width D"}


@lru_cache(maxsize=1)
def load_calibration() -> dict:
    """The shipped calibration of one slider against the 2-D fault (``data/fault_2d_model_error.json``).

    Returns
    -------
    dict
        ``geometric`` and ``zone_width``: each with its ``stiffness_factor`` c, ``rows`` (W / h* and the declared
        model error, relative), and the ``held_out`` faults with their true and declared errors; ``provenance``.
    """
    table = read_bundled_table(CALIBRATION_FILE, "the model-error calibration", "benchmarks/fault_2d_calibration.py")
    if not all(isinstance(table.get(key), dict) and table[key].get("rows") for key in REDUCTIONS.values()):
        raise InputError(f"{CALIBRATION_FILE} lacks a reduction's rows; rerun benchmarks/fault_2d_calibration.py")
    return table


def _envelope(rows) -> tuple[np.ndarray, np.ndarray]:
    """The calibrated W / h* levels, ascending, and the declared error at each."""
    ratios = np.array([row["width_over_nucleation"] for row in rows], float)
    errors = np.array([row["model_error"] for row in rows], float)
    order = np.argsort(ratios)
    return ratios[order], errors[order]


def envelope_error(width_over_nucleation, rows) -> np.ndarray:
    """The declared model error at each W / h* (array-wise): the larger of the calibrated levels that bracket it.

    Parameters
    ----------
    width_over_nucleation : array_like
        W / h* (dimensionless); 0 where b <= a.
    rows : list of dict
        ``width_over_nucleation`` and ``model_error`` (already the bound: the largest error at that level times the
        safety factor).

    Returns
    -------
    numpy.ndarray
        The declared model error (relative): NaN where W / h* is not positive (the fault creeps: neither model has
        earthquakes), infinite outside the calibrated range (not known).
    """
    ratios, errors = _envelope(rows)
    ratio = np.asarray(width_over_nucleation, dtype=float)
    inside = (ratio >= ratios[0]) & (ratio <= ratios[-1])
    upper = np.clip(np.searchsorted(ratios, ratio), 0, ratios.size - 1)
    on_level = ratios[upper] == ratio
    lower = np.where(on_level, upper, np.maximum(upper - 1, 0))
    value = np.maximum(errors[lower], errors[upper])
    return np.where(ratio > 0, np.where(inside, value, np.inf), np.nan)


def declared_from_envelope(ratio: float, rows) -> tuple[float, float, str]:
    """The declared model error at W / h* = ``ratio`` from a calibration's envelope ``rows``, and how it was found.

    Returns
    -------
    tuple
        (declared model error, relative, as :func:`envelope_error`; W / h*; how it was found).
    """
    ratios, _ = _envelope(rows)
    value = float(envelope_error(ratio, rows))
    if not ratio > 0:
        return value, ratio, "b <= a: the fault creeps, neither model has earthquakes"
    if math.isinf(value):
        return value, ratio, (f"W / h* = {ratio:.3g} lies outside the calibration ({ratios[0]:.3g} to "
                              f"{ratios[-1]:.3g}): the one slider's error there is not known (unbounded); give a "
                              "tolerance, or --method fault_2d, for the 2-D fault")
    upper = min(int(np.searchsorted(ratios, ratio)), ratios.size - 1)
    lower = upper if ratios[upper] == ratio else max(upper - 1, 0)
    return value, ratio, (f"W / h* = {ratio:.3g}: the largest model error over the calibrated 2-D faults at W / h* "
                          f"{ratios[lower]:.3g} to {ratios[upper]:.3g} (surface-breaking, buried, with and without "
                          "a ramp and a deep strengthening zone), times 1.25")


def zone_width_model_error(shear_modulus, zone_width, normal_stress, a, b, critical_slip,
                           calibration: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """W / h* and the declared model error of the seed's reduction (K = G / D) for every cell (array-wise, SI).

    Parameters
    ----------
    shear_modulus, zone_width, normal_stress, a, b, critical_slip : array_like
        G (Pa), the elastic-zone width D (m), sigma_n (Pa), a, b and D_c (m); they broadcast.
    calibration : dict, optional
        The calibration table (the shipped one otherwise).

    Returns
    -------
    tuple of numpy.ndarray
        (D / h*, 0 where b <= a; the declared model error, relative, as :func:`envelope_error`).
    """
    table = calibration or load_calibration()
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.asarray(zone_width, float) / nucleation_size(shear_modulus, critical_slip, a, b, normal_stress)
    return ratio, envelope_error(ratio, table["zone_width"]["rows"])


def range_within(value: float, error: float) -> list | None:
    """Where the 2-D fault's answer lies, given one slider's ``value`` and its declared model error ``error``.

    The calibration bounds |value / answer - 1| <= e, so the answer lies in [value / (1 + e), value / (1 - e)];
    from e = 1 on, the block may stand any factor below the 2-D fault and the range has no upper end.

    Parameters
    ----------
    value : float
        The one slider's recurrence (s) or slip per event (m).
    error : float
        Its declared model error (relative).

    Returns
    -------
    list or None
        [low, high] in ``value``'s units, high None where unbounded; None where the error is not finite (nothing
        is known) or the value is not a positive number.
    """
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0
            and isinstance(error, (int, float)) and math.isfinite(error) and error >= 0):
        return None
    return [value / (1.0 + error), value / (1.0 - error) if error < 1 else None]


@takes_units(shear_modulus="pressure", normal_stress="pressure", width="length")
def declared_model_error(law, shear_modulus: float, normal_stress: float, width: float,
                         calibration: dict | None = None, reduction: str = "geometric") -> tuple[float, float, str]:
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
        W, the seismogenic (velocity-weakening) width, or D of the seed's reduction (m).
    calibration : dict, optional
        The calibration table (the shipped one otherwise).
    reduction : str
        ``"geometric"`` (K = c G / W) or ``"zone_width"`` (the seed's K = G / D).

    Returns
    -------
    tuple
        (model error, W / h*, how it was found): the bound on the relative error of one slider against the 2-D
        fault, in recurrence or slip, whichever is larger (dimensionless); infinite outside the calibration.
    """
    table = calibration or load_calibration()
    if reduction not in DESCRIPTIONS:
        raise InputError(f"the reduction must be one of {', '.join(DESCRIPTIONS)}, got {reduction!r}")
    ratio = nucleation_ratio(law, shear_modulus, normal_stress, width)
    error, ratio, how = declared_from_envelope(ratio, table[reduction]["rows"])
    return error, ratio, f"{DESCRIPTIONS[reduction]}; {how}"


def declare_model_error(result, error: float, ratio: float, how: str, stands_for: str) -> None:
    """Add to a one-slider ``result`` (a :class:`faultslip.contract.result.Result`) its model error against the
    2-D fault, its W / h*, the ranges that error gives the recurrence and slip in their own units, and which fault
    it stands for; where the model error dominates the cycles' own it becomes the declared error, the numerical one
    kept beside as ``numerical_error``. Every door to one rate-and-state block declares through here."""
    result.add("model_error", error if math.isfinite(error) else None,
               label="declared model error against the 2-D fault (relative, recurrence or slip; null: unbounded)")
    result.add("width_over_nucleation", ratio, label="W / h* (what governs the model error)")
    for key, name, units in (("recurrence_period", "recurrence", "s"), ("slip_per_event", "slip per event", "m")):
        if key in result:  # the bound read in the answer's own units, as issue 68 asks of every rung
            result.add(f"{key.removesuffix('_period')}_range", range_within(result.si(key), error), units,
                       also=("yr",) if units == "s" else (),
                       label=f"the 2-D fault's {name} by the model error e: value / (1 + e) to / (1 - e)")
    result.note(f"model error: {how}")
    result.note(stands_for)
    numerical = result.estimated_relative_error
    result.add("numerical_error", numerical, label="the cycles' own error (integrator scatter, plus the settling left)")
    if not math.isnan(error) and (numerical is None or error > numerical):  # lead with the error that dominates
        result.add("estimated_relative_error", error if math.isfinite(error) else None,
                   label="declared error (the model error, which dominates; null: unbounded, outside the calibration)")


__all__ = ["CALIBRATION_FILE", "DESCRIPTIONS", "REDUCTIONS", "declare_model_error", "declared_from_envelope",
           "declared_model_error", "envelope_error", "load_calibration", "range_within", "zone_width_model_error"]
