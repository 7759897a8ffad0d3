"""The ordinary least-squares correction and its prediction interval, shared by the one slider's calibrations
against the 2-D fault (:mod:`faultslip.fault.ladder`, antiplane; :mod:`faultslip.fault.dip_slider`, plane strain).

A calibration regresses y = ln(richer rung / block) on a row x of groups. The corrected answer is the block's
times exp(x . beta), and its range at level p is exp(+- t s sqrt(1 + x^T (X^T X)^-1 x)) about it: the prediction
interval of a new fault's y (e.g. Montgomery, Peck & Vining 2012, eq. 3.55), t the Student quantile at the
residual's degrees of freedom, s the residual standard deviation.
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.errors import InputError


def least_squares(rows: np.ndarray, targets: np.ndarray, level: float = 0.95) -> dict:
    """beta of ``targets`` on ``rows`` (one row per fault, constant first) by least squares, and what the
    prediction interval needs.

    Returns
    -------
    dict
        ``coefficients``, ``inverse_gram`` (X^T X)^+, ``residual_sd`` s, ``standardized_residuals``
        e_i / sqrt(1 - h_i) (h_i the leverage), ``dof`` (faults less the rank), ``t_quantile`` at ``level``, the
        median bias uncorrected (exp(median y) - 1) and corrected (of the residuals), and ``faults``.

    Raises
    ------
    InputError
        Where fewer than 5 degrees of freedom are left for the spread.
    """
    from scipy import stats  # heavy: imported where used

    x = np.asarray(rows, float)
    y = np.asarray(targets, float)
    beta, _, rank, _ = np.linalg.lstsq(x, y, rcond=None)
    residual = y - x @ beta
    dof = x.shape[0] - int(rank)  # a group constant over the faults drops out of the rank
    if dof < 5:
        raise InputError(f"{x.shape[0]} calibration faults cannot fit {x.shape[1]} coefficients with a spread")
    sd = float(math.sqrt(residual @ residual / dof))
    gram = np.linalg.pinv(x.T @ x)
    leverage = np.einsum("ij,jk,ik->i", x, gram, x)
    return {"coefficients": beta.tolist(), "inverse_gram": gram.tolist(), "residual_sd": sd,
            # e_i / sqrt(1 - h_i): each residual on the scale of a new fault's error (what a local spread averages)
            "standardized_residuals": (residual / np.sqrt(np.clip(1.0 - leverage, 1e-12, None))).tolist(),
            "dof": dof, "t_quantile": float(stats.t.ppf(0.5 + level / 2, dof)),
            "median_bias_uncorrected": float(math.exp(np.median(y)) - 1.0),
            "median_bias_corrected": float(math.exp(np.median(residual)) - 1.0), "faults": int(x.shape[0])}


def corrected(raw: float, row: np.ndarray, model: dict, scale: tuple[float, float] | None = None) -> dict:
    """The block's answer ``raw`` corrected by ``model`` (:func:`least_squares`) at the fault's ``row``, with its
    prediction interval.

    ``scale``: (t, s), a quantile and residual spread of the fault's own neighbourhood (:func:`local_scale`) in
    place of the fit's pooled t and s, where the residual's spread varies over the calibrated box.

    Returns
    -------
    dict
        ``value``, ``low``, ``high`` (raw's units) and ``half_width`` (relative: exp(t s sqrt(1 + h)) - 1).
    """
    x = np.asarray(row, float)
    centre = raw * math.exp(float(x @ np.asarray(model["coefficients"], float)))
    quantile, sd = scale if scale is not None else (model["t_quantile"], model["residual_sd"])
    spread = quantile * sd * math.sqrt(1.0 + float(x @ np.asarray(model["inverse_gram"], float) @ x))
    return {"value": centre, "low": centre * math.exp(-spread), "high": centre * math.exp(spread),
            "half_width": math.exp(spread) - 1.0}


def local_scale(residuals: list, level: float = 0.95) -> tuple[float, float]:
    """(t, s) of a fault's neighbourhood: s the root mean square of its calibration faults' standardized residuals
    (:func:`least_squares`), t the Student quantile at ``level`` on one fewer degrees of freedom than there are.

    Raises
    ------
    InputError
        With fewer than 3 residuals: no spread to read.
    """
    from scipy import stats  # heavy: imported where used

    values = np.asarray(residuals, float)
    if values.size < 3:
        raise InputError(f"{values.size} calibration faults nearby cannot give a spread")
    return float(stats.t.ppf(0.5 + level / 2, values.size - 1)), float(math.sqrt(np.mean(values ** 2)))
