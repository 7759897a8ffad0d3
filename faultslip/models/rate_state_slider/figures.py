"""The rate-and-state slider's figures: a fault's cycles, and the one slider's model error against the 2-D fault."""

from __future__ import annotations

import numpy as np

from faultslip.constants import JULIAN_YEAR
from faultslip.plots.figures import _pyplot


def cycles_figure(dataset):
    """A rate-and-state fault's cycles: slip rate (log) and shear stress against time in years, events marked."""
    plt = _pyplot()
    year = JULIAN_YEAR
    years = dataset["time"].values / year
    figure, (rate, stress) = plt.subplots(2, 1, figsize=(9, 5.6), sharex=True, constrained_layout=True)
    rate.semilogy(years, dataset["slip_rate"].values, color="C0", lw=1)
    rate.axhline(1e-3, color="0.5", lw=0.8, ls="--", label="event threshold 1 mm/s")
    rate.axhline(float(dataset.attrs["plate_rate_m_per_s"]), color="C2", lw=0.8, ls=":", label="plate rate")
    rate.set(ylabel="slip rate (m/s)")
    rate.legend(fontsize=8, loc="center left")
    stress.plot(years, dataset["shear_stress"].values / 1e6, color="C3", lw=1)
    stress.set(xlabel="time (yr)", ylabel="shear stress (MPa)")
    for axis in (rate, stress):
        for start in dataset["event_time"].values / year:
            axis.axvline(start, color="0.8", lw=0.6, zorder=0)
        axis.grid(True, alpha=0.3)
    figure.suptitle(f"{dataset.attrs.get('title', 'rate-and-state cycles')} (K / K_c "
                    f"{float(dataset.attrs['stiffness_ratio']):.3g}, {dataset.attrs.get('method', '')})", fontsize=10)
    return figure


def model_error_figure(table: dict, tolerance: float | None = None):
    """The model-error map: the one slider's error against the 2-D fault over W / h* (the shipped
    calibration), its recurrence and slip apart, and where one slider suffices for a tolerance.

    Parameters
    ----------
    table : dict
        :func:`load_calibration`'s table.
    tolerance : float, optional
        A model error allowed.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    rows = [row for row in table["rows"]]
    ratio = np.array([row["width_over_nucleation"] for row in rows])
    total = np.array([row["model_error"] for row in rows])
    recurrence = np.array([row.get("recurrence_error", np.nan) for row in rows])
    slip = np.array([row.get("slip_error", np.nan) for row in rows])
    figure, axis = plt.subplots(figsize=(7.5, 4.6), constrained_layout=True)
    axis.plot(ratio, total, "o-", color="k", label="model error (the larger)")
    axis.plot(ratio, np.abs(recurrence), "s--", color="C0", label="|recurrence error|")
    axis.plot(ratio, np.abs(slip), "^--", color="C3", label="|slip-per-event error|")
    if tolerance is not None:
        axis.axhline(tolerance, color="C2", lw=1)
        good = total <= tolerance
        if np.any(good):
            axis.fill_between(ratio, 0, tolerance, where=good, color="C2", alpha=0.15,
                              label=f"one slider suffices (tolerance {tolerance:g})")
    axis.set_xscale("log")
    axis.set_xticks(ratio, [f"{value:g}" for value in ratio])
    axis.minorticks_off()
    axis.set(xlabel="W / h* (fault width over nucleation size)", ylabel="relative error of one slider (K = G / D)",
             title="where one slider suffices: its error against the 2-D fault")
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=8)
    return figure
