"""Figures of a 2-D fault run: cumulative slip (the field's standard picture) and log10 V in space-time."""

from __future__ import annotations

import numpy as np

from faultslip.models.fault_2d.integrate import YEAR, Fault2DRun
from faultslip.plots.figures import _pyplot


def cumulative_slip_figure(run: Fault2DRun, title: str = ""):
    """Slip profiles against depth: blue every profile interval between events, red every coseismic
    interval within them (Lapusta et al. 2000, Fig. 3; SEAS BP1, Erickson et al. 2020, Fig. 4).

    Parameters
    ----------
    run : Fault2DRun
        A 2-D fault's run with its profiles.
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(7.5, 5.0), constrained_layout=True)
    depth_km = run.fault.depth / 1e3
    coseismic = run.profile_max_speed > 1e-3
    for rows, colour, width in ((~coseismic, "C0", 0.6), (coseismic, "C3", 0.5)):
        for profile in run.profiles[rows]:
            axis.plot(profile, depth_km, color=colour, lw=width)
    axis.invert_yaxis()
    axis.set(xlabel="cumulative slip (m)", ylabel="depth (km)",
             title=title or f"{run.fault.name}: cumulative slip ({run.event_count} events)")
    axis.plot([], [], color="C0", label="between events (every profile interval)")
    axis.plot([], [], color="C3", label="within events (every coseismic interval)")
    axis.legend(loc="lower right", fontsize=8)
    return figure


def slip_rate_figure(run: Fault2DRun, title: str = ""):
    """log10 slip rate on the fault against the profile index: time runs unevenly, a profile every
    few years between events and every second within them, so that both show (SEAS BP1's convention).

    Parameters
    ----------
    run : Fault2DRun
        A 2-D fault's run.
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(9, 4.6), constrained_layout=True)
    depth_km = run.fault.depth / 1e3
    values = np.clip(run.profile_log10_slip_rate, -12, 1)
    image = axis.pcolormesh(np.arange(values.shape[0]), depth_km, values.T, cmap="magma", shading="auto",
                            vmin=-12, vmax=1)
    axis.invert_yaxis()
    axis.set(xlabel="profile index (between events: every profile interval; within: every coseismic interval)",
             ylabel="depth (km)", title=title or f"{run.fault.name}: log10 slip rate in space and time")
    figure.colorbar(image, ax=axis, label="log10 V (m/s)")
    return figure


def station_figure(run: Fault2DRun, title: str = ""):
    """Slip rate at the stations against time (years)."""
    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(8, 4.2), constrained_layout=True)
    for k, depth in enumerate(run.station_depths):
        axis.plot(run.station_time / YEAR, run.stations["log10_slip_rate"][:, k], lw=0.7, label=f"{depth / 1e3:g} km")
    axis.set(xlabel="time (yr)", ylabel="log10 slip rate (m/s)", title=title or f"{run.fault.name}: stations")
    axis.legend(fontsize=7, ncol=2)
    return figure


def ladder_figure(rungs: list[dict], title: str = ""):
    """Each rung's answer for one scene with its declared range, against the CPU time it cost: recurrence and
    slip per event (the ladder chart, issue 68).

    Parameters
    ----------
    rungs : list of dict
        ``name``, ``cpu_time`` (s), ``recurrence`` and ``recurrence_range`` (s), ``slip`` and ``slip_range`` (m);
        a range may be None (none declared).
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, axes = plt.subplots(1, 2, figsize=(9.0, 4.0), constrained_layout=True)
    for axis, key, scale, label in ((axes[0], "recurrence", YEAR, "recurrence (yr)"),
                                    (axes[1], "slip", 1.0, "slip per event (m)")):
        for k, rung in enumerate(rungs):
            value = rung[key] / scale
            band = rung.get(f"{key}_range")
            cost = max(rung["cpu_time"], 1e-3)
            if band is not None:
                low, high = band[0] / scale, band[1] / scale
                axis.errorbar([cost], [value], yerr=[[value - low], [high - value]], fmt="o", color=f"C{k}",
                              capsize=4, label=rung["name"])
            else:
                axis.plot([cost], [value], "o", mfc="none", color=f"C{k}", label=f"{rung['name']} (no range)")
        axis.set_xscale("log")
        axis.set_xlabel("CPU time (s)")
        axis.set_ylabel(label)
        axis.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    figure.suptitle(title or "the ladder: each rung's answer and declared range against its cost", fontsize=10)
    return figure
