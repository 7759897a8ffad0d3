"""Fitting a declared error c rtol^q + floor to measured errors, with a margin (the integrators' calibrations).

An integrator declares its error as a function of its tolerance. The calibration scripts in benchmarks/ measure
the largest error over many random scenes at each rtol, and :func:`fit_power_law` gives the tightest model of
this form that stands a ``margin`` above every one of them; the held-out scenes are then checked against it.
"""

from __future__ import annotations

import math

import numpy as np

#: the powers of rtol the fit tries, and the floors round-off leaves
POWERS = tuple(float(p) for p in np.round(np.arange(0.50, 1.101, 0.01), 2))
FLOORS = (0.0, 1e-12, 2e-12, 5e-12, 1e-11)


def fit_power_law(rtols, largest, margin: float, powers=POWERS, floors=FLOORS) -> tuple:
    """The tightest (c, q, floor) with c rtol^q + floor >= ``margin`` x ``largest`` at every rtol.

    For each power and floor, c is the least that bounds every point; the model kept has the smallest sum of
    log declared error over the rtols (the tightest band overall), and c is rounded up to two significant
    figures. Points that are not finite (no run measured there) are left out.
    """
    rtols, need = np.asarray(rtols, dtype=float), margin * np.asarray(largest, dtype=float)
    keep = np.isfinite(need) & (need > 0)
    rtols, need = rtols[keep], need[keep]
    if not need.size:
        raise ValueError("no finite error to fit a declared error to")
    best = None
    for power in powers:
        for floor in floors:
            above = need - floor
            constant = float(np.max(np.where(above > 0, above / rtols ** power, 0.0)))
            if constant <= 0:
                continue
            digits = 10 ** (math.floor(math.log10(constant)) - 1)
            constant = math.ceil(constant / digits) * digits
            score = float(np.sum(np.log(constant * rtols ** power + floor)))
            if best is None or score < best[0]:
                best = (score, float(f"{constant:.2g}"), float(power), floor)
    return best[1:]


def worst_cell(error, declared, status) -> tuple:
    """Over the measured cells (``status`` 0) of error and declared-error arrays: the largest error / declared, its
    index (None where nothing was measured), and whether every measured error lies within what it declared."""
    error, declared, ok = np.asarray(error, float), np.asarray(declared, float), np.asarray(status) == 0
    if not ok.any():
        return math.nan, None, False
    ratio = np.where(ok, error / declared, -np.inf)
    worst = np.unravel_index(np.argmax(ratio), ratio.shape)
    return float(ratio[worst]), worst, bool(np.all(ratio[ok] <= 1.0))
