"""Quasi-harmonic vibration figures (seed 002): amplitude against driving speed beside the friction curve."""

from __future__ import annotations

import numpy as np

from faultslip.dynamics.vibration import ERROR_CONSTANT, HAND_OVER_MARGIN
from faultslip.plots.figures import _pyplot

INCH = 0.0254


def error_figure(table):
    """Averaging's measured error against direct integration over the small parameter, beside its declared
    ERROR_CONSTANT eps^2, one line per curve (:func:`faultslip.dynamics.vibration.error_against_eps`)."""
    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(6, 4.4), constrained_layout=True)
    for index, curve in enumerate(dict.fromkeys(table["curve"])):
        chosen = table["curve"] == curve
        order = np.argsort(table["small_parameter"][chosen])
        eps = table["small_parameter"][chosen][order]
        axis.loglog(eps, table["error"][chosen][order], "o-", color=f"C{index}", label=f"measured, {curve}")
        axis.loglog(eps, table["declared"][chosen][order], "--", color=f"C{index}", lw=0.8,
                    label=f"declared {ERROR_CONSTANT:g} eps^2" if index == 0 else None)
    axis.set(xlabel="small parameter eps = (r + W max|f'|) / (M omega)",
             ylabel="relative error of the amplitude", title="averaging (seed 002 eq. 20) against integration")
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=8)
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
    """Seed 002's (v, r) plane: steady sliding, quasi-harmonic vibration (amplitude contours), stick-slip, and
    the band within HAND_OVER_MARGIN eps of sticking where only integration can call it."""
    from matplotlib.colors import ListedColormap  # heavy: matplotlib, imported where used

    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(7, 4.6), constrained_layout=True)
    speeds, dampings = table["speed"] / INCH, table["damping"] / (4.4482216152605 / INCH)
    axis.pcolormesh(speeds, dampings, table["regime"],
                    cmap=ListedColormap(["#e3f2fd", "#fff3e0", "#ffcdd2", "#bdbdbd"]), vmin=-0.5, vmax=3.5,
                    shading="nearest")
    amplitude = np.ma.masked_where(table["regime"] != 1, table["amplitude"] / INCH)
    if amplitude.count() > 3:
        lines = axis.contour(speeds, dampings, amplitude, levels=np.linspace(0, float(amplitude.max()), 6)[1:-1],
                             colors="C3", linewidths=0.8)
        axis.clabel(lines, fontsize=7, fmt="%.3g in")
    axis.set(xlabel="driving speed v (in/s)", ylabel="damping coefficient r (lbf s/in)",
             title=f"steady sliding (blue), quasi-harmonic (orange, amplitude), stick-slip (red),\n"
                   f"within {HAND_OVER_MARGIN:g} eps of sticking: integration decides (grey)")
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
