"""The vibration family's figures: the settled amplitude against speed, and a run's series."""

from __future__ import annotations

import numpy as np

from faultslip.dynamics.vibration import HAND_OVER_MARGIN
from faultslip.plots.figures import _pyplot
from faultslip.plots.vibration import INCH


def amplitude_speed_figure(system, sweep):
    """Left: the friction-velocity curve (seed 002 Fig. 9). Right: the averaged limit-cycle amplitude against
    the driving speed (Figs. 10-11), stick-slip speeds shaded, both in the seed's inches.

    Parameters
    ----------
    system : QuasiHarmonic
        The averaged slider.
    sweep : dict
        :func:`amplitude_against_speed`'s arrays.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, (curve, amplitude) = plt.subplots(1, 2, figsize=(10, 4.2), constrained_layout=True)
    speeds = sweep["speed"]
    grid = np.linspace(0.0, 1.3 * speeds.max(), 400)
    curve.plot(grid / INCH, system.curve(grid), color="C0")
    curve.set(xlabel="sliding speed (in/s)", ylabel="friction coefficient f", title="friction-velocity curve")
    curve.grid(True, alpha=0.3)
    values = sweep["amplitude"] / INCH
    amplitude.plot(speeds / INCH, np.where(np.isnan(values), np.nan, values), "o-", color="C3", ms=3,
                   label="quasi-harmonic amplitude A")
    marginal = sweep["marginal"]  # the first-order call is not trusted here either way (HAND_OVER_MARGIN)
    sticks = sweep["sticks"] & ~marginal
    if sticks.any():
        low, high = speeds[sticks].min() / INCH, speeds[sticks].max() / INCH
        amplitude.axvspan(low, high, color="0.85", label="stick-slip (A omega would reach v)")
    for index, speed in enumerate(speeds[marginal]):
        amplitude.axvline(speed / INCH, color="k", ls="--", lw=0.8, label=None if index else
                          f"within {HAND_OVER_MARGIN:g} eps of sticking: integration decides")
    amplitude.set(xlabel="driving speed v (in/s)", ylabel="amplitude (in)",
                  title="averaged limit cycle (seed 002 eq. 20)")
    amplitude.legend(fontsize=8)
    amplitude.grid(True, alpha=0.3)
    figure.suptitle(system.name)
    return figure


def vibration_series_figure(run):
    """Seed 002 eq. (10) integrated: the displacement about the rest position inside eq. (20)'s envelope."""
    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(9, 3.8), constrained_layout=True)
    axis.plot(run["time"], run["displacement"] / INCH, color="C0", lw=0.5, label="Y (eq. 10, DOP853)")
    for sign in (1, -1):
        axis.plot(run["time"], sign * run["envelope"] / INCH, color="C3", lw=1.2,
                  label="averaged envelope (eq. 20)" if sign == 1 else None)
    axis.set(xlabel="time (s)", ylabel="displacement about rest (in)", title=run["system"].name)
    axis.legend(fontsize=8, loc="lower right")
    axis.grid(True, alpha=0.3)
    return figure
