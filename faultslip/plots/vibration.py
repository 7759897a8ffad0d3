"""Quasi-harmonic vibration figures (seed 002): amplitude against driving speed beside the friction curve."""

from __future__ import annotations

import numpy as np

from faultslip.dynamics.vibration import ERROR_CONSTANT
from faultslip.plots.figures import _pyplot

INCH = 0.0254


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
    sticks = sweep["sticks"]
    if sticks.any():
        low, high = speeds[sticks].min() / INCH, speeds[sticks].max() / INCH
        amplitude.axvspan(low, high, color="0.85", label="stick-slip (A omega would reach v)")
    amplitude.set(xlabel="driving speed v (in/s)", ylabel="amplitude (in)",
                  title="averaged limit cycle (seed 002 eq. 20)")
    amplitude.legend(fontsize=8)
    amplitude.grid(True, alpha=0.3)
    figure.suptitle(system.name)
    return figure


def error_figure(table):
    """Averaging's measured error against direct integration over the small parameter, beside its declared
    ERROR_CONSTANT eps^2 (Rayleigh curves with and without an even term)."""
    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(6, 4.4), constrained_layout=True)
    for index, quadratic in enumerate(np.unique(table["even_term"])):
        chosen = table["even_term"] == quadratic
        eps = table["small_parameter"][chosen]
        axis.loglog(eps, table["error"][chosen], "o-", color=f"C{index}", label=f"measured, even term q = {quadratic:g}")
        axis.loglog(eps, table["declared"][chosen], "--", color=f"C{index}", lw=0.8,
                    label=f"declared {ERROR_CONSTANT:g} eps^2" if index == 0 else None)
    axis.set(xlabel="small parameter eps = (r + W max|f'|) / (M omega)",
             ylabel="relative error of the amplitude", title="averaging (seed 002 eq. 20) against integration")
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=8)
    return figure


def nanoscale_figure(run):
    """Seed 001 Fig. 3: force against displacement, and displacement with deposited charge against time.

    Parameters
    ----------
    run : NanoscaleRun
        A nanoscale run.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, (phase, series) = plt.subplots(1, 2, figsize=(10.5, 4.2), constrained_layout=True)
    half = run.time.size // 2
    phase.plot(run.displacement[half:], run.force[half:], color="C0", lw=0.8)
    phase.set(xlabel="displacement X", ylabel="force F", title=f"force against displacement (A = {run.model.damping:g})")
    phase.grid(True, alpha=0.3)
    window = slice(int(0.93 * run.time.size), None)  # a few events: the staircase of stick and slip
    series.plot(run.time[window], run.displacement[window], color="C0", label="displacement X")
    twin = series.twinx()
    twin.plot(run.time[window], run.deposited[window], color="C3", ls="--", label="deposited charge Sigma_d")
    series.set(xlabel="time (1/omega)", ylabel="X")
    twin.set_ylabel("Sigma_d")
    lines = series.get_legend_handles_labels()[0] + twin.get_legend_handles_labels()[0]
    series.legend(lines, [line.get_label() for line in lines], fontsize=8, loc="upper left")
    series.grid(True, alpha=0.3)
    figure.suptitle("seed 001 toy model: stick-slip and contact charging (eqs. 1-4)")
    return figure


def hand_over_figure(table):
    """Averaging's call after break-away against the event-driven simulation, per driving speed."""
    plt = _pyplot()
    speeds = np.unique(table["speed"])
    figure, axes = plt.subplots(1, speeds.size, figsize=(3.3 * speeds.size, 3.6), constrained_layout=True,
                                squeeze=False, sharey=True)
    styles = {"stick-slip, agreed": ("s", "C3"), "quasi-harmonic, agreed": ("o", "C0"),
              "declined (within 0.15 eps)": ("D", "0.6"), "wrong": ("X", "k")}
    for axis, speed in zip(axes[0], speeds):
        chosen = table["speed"] == speed
        eps, excess = table["eps"][chosen], table["excess"][chosen]
        predicted, simulated, marginal = (table[k][chosen] for k in ("predicted_sticks", "simulated_sticks", "marginal"))
        groups = {"stick-slip, agreed": ~marginal & predicted & simulated,
                  "quasi-harmonic, agreed": ~marginal & ~predicted & ~simulated,
                  "declined (within 0.15 eps)": marginal, "wrong": ~marginal & (predicted != simulated)}
        for label, mask in groups.items():
            if mask.any():
                marker, colour = styles[label]
                axis.scatter(eps[mask], excess[mask] + 1e-3, marker=marker, color=colour, s=40, label=label)
        axis.set(xscale="log", yscale="symlog", title=f"V = {speed:g} (A* omega = 2)", xlabel="e (curve's eps)")
        axis.grid(True, alpha=0.3)
    axes[0][0].set_ylabel("static excess mu_s - f(V)")
    ticks = sorted(set(np.round(table["excess"], 6)))
    for axis in axes[0]:
        axis.set_yticks([t + 1e-3 for t in ticks], [f"{t:g}" for t in ticks])
    handles = {}
    for axis in axes[0]:
        for handle, label in zip(*axis.get_legend_handles_labels()):
            handles.setdefault(label, handle)
    axes[0][-1].legend(handles.values(), handles.keys(), fontsize=7, loc="upper left", framealpha=0.9)
    figure.suptitle("after break-away: averaging's hand-over against event-driven simulation")
    return figure


def regions_figure(system, table):
    """Seed 002's (v, r) plane: steady sliding, quasi-harmonic vibration (amplitude contours) and stick-slip."""
    from matplotlib.colors import ListedColormap  # heavy: matplotlib, imported where used

    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(7, 4.6), constrained_layout=True)
    speeds, dampings = table["speed"] / INCH, table["damping"] / (4.4482216152605 / INCH)
    axis.pcolormesh(speeds, dampings, table["regime"], cmap=ListedColormap(["#e3f2fd", "#fff3e0", "#ffcdd2"]),
                    vmin=-0.5, vmax=2.5, shading="nearest")
    amplitude = np.ma.masked_where(table["regime"] != 1, table["amplitude"] / INCH)
    if amplitude.count() > 3:
        lines = axis.contour(speeds, dampings, amplitude, levels=np.linspace(0, float(amplitude.max()), 6)[1:-1],
                             colors="C3", linewidths=0.8)
        axis.clabel(lines, fontsize=7, fmt="%.3g in")
    axis.set(xlabel="driving speed v (in/s)", ylabel="damping coefficient r (lbf s/in)",
             title="steady sliding (blue), quasi-harmonic (orange, amplitude), stick-slip (red)")
    figure.suptitle(system.name, fontsize=10)
    return figure


def seed002_figures(table):
    """Seed 002 Figs. 9-11 in kind: the four friction curves, each curve's averaged amplitude against the
    driving speed, and curve (A) at several dampings; the no-stick bound A = v / omega dashed (above it the
    slider would stick)."""
    plt = _pyplot()
    figure, (curves, branches, damped) = plt.subplots(1, 3, figsize=(15, 4.4), constrained_layout=True)
    speeds = table["speeds"] / INCH
    grid = np.linspace(0.0, speeds.max() * 1.25, 400)
    for index, (name, curve) in enumerate(table["curves"].items()):
        curves.plot(grid, curve(grid * INCH), color=f"C{index}", label=f"({name}) {curve.description}")
    curves.set(xlabel="sliding speed (in/s)", ylabel="friction coefficient f", title="Fig. 9: friction curves")
    curves.legend(fontsize=7)
    omega = None
    for index, (name, branch) in enumerate(table["branches"].items()):
        alive = branch["amplitude"] > 0
        omega = branch["peak_speed"][alive][0] / branch["amplitude"][alive][0] if alive.any() else omega
        style = "--" if name == "B" else "o-"
        branches.plot(speeds, branch["amplitude"] / INCH, style, color=f"C{index}", ms=3, label=f"({name})")
    for index, (factor, branch) in enumerate(table["damped"].items()):
        damped.plot(speeds, branch["amplitude"] / INCH, "o-", color=f"C{index}", ms=3, label=f"damping x {factor:g}")
    for axis, title in ((branches, "Fig. 10: amplitude against speed"), (damped, "Fig. 11: curve (A), damping")):
        if omega:
            axis.plot(speeds, speeds / omega, ":", color="0.4", label="A omega = v (no-stick bound)")
        axis.set(xlabel="driving speed v (in/s)", ylabel="amplitude A (in)", title=title)
        axis.legend(fontsize=7)
    for axis in (curves, branches, damped):
        axis.grid(True, alpha=0.3)
    figure.suptitle("seed 002 theoretical curves in kind (illustrative curves; above the dotted line the slider "
                    "would stick)", fontsize=10)
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
