"""Seed 004 figures: the response panels of its Figs. 8-14 and the m_D-against-speed curves of Figs. 6-7."""

from __future__ import annotations

import numpy as np

from faultslip.models.asperity.dynamics import STICK, analyse
from faultslip.models.asperity.speed_map import OUTCOMES
from faultslip.plots.figures import _pyplot


def response_figure(run):
    """Phase plane (x against x'), friction F_t/F_n against relative speed, and the spectrum of x' (Figs. 8-14).

    Parameters
    ----------
    run : AsperityRun
        :func:`simulate_asperity`'s run.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, (phase, friction, spectrum) = plt.subplots(1, 3, figsize=(13, 4.0), constrained_layout=True)
    half = run.time >= run.time[0] + 0.5 * (run.time[-1] - run.time[0])
    v = run.model.platform_speed
    phase.plot(run.displacement[half] * 1e3, run.speed[half] * 1e3, color="C0", lw=0.7)
    phase.axhline(v * 1e3, color="0.5", ls=":", label="platform speed")
    phase.set(xlabel="x (mm)", ylabel="x' (mm/s)", title="phase plane")
    phase.legend(fontsize=8)
    ratio = -run.friction[half] / run.normal_force[half]
    friction.plot((v - run.speed[half]) * 1e3, ratio, color="C3", lw=0.6)
    stuck = half & (run.mode == STICK)
    if stuck.any():
        friction.plot((v - run.speed[stuck]) * 1e3, -run.friction[stuck] / run.normal_force[stuck], ".", color="k",
                      ms=2, label="stuck")
        friction.legend(fontsize=8)
    friction.set(xlabel="relative speed v - x' (mm/s)", ylabel="F_t / F_n", title="instantaneous friction")
    t = run.time[half]
    uniform = np.linspace(t[0], t[-1], 4096)
    u = np.interp(uniform, run.time, run.speed)
    power = np.abs(np.fft.rfft((u - u.mean()) * np.hanning(u.size)))
    freqs = np.fft.rfftfreq(u.size, uniform[1] - uniform[0])
    spectrum.semilogy(freqs, power / max(power.max(), 1e-300), color="C2", lw=0.8)
    spectrum.axvline(run.model.natural_frequency, color="0.5", ls=":", label="f0")
    spectrum.set(xlim=(0, 6 * run.model.natural_frequency), xlabel="frequency (Hz)", ylabel="|X'(f)| (normalised)",
                 title="spectrum of x'")
    spectrum.legend(fontsize=8)
    for axis in (phase, friction, spectrum):
        axis.grid(True, alpha=0.3)
    response = analyse(run)
    regime = "stick-slip" if response.stick_slip else "no stick"
    figure.suptitle(f"{run.model.name}: v = {v * 1e3:.3g} mm/s, f0 = {run.model.natural_frequency:g} Hz "
                    f"({regime}, {response.loops or 'no'} loop period; {run.method})")
    return figure


def sweep_figure(sweeps, labels):
    """m_D and the stick fraction against platform speed, critical speeds v_c1/n marked (Figs. 6-7)."""
    plt = _pyplot()
    figure, (deformation, stick) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True, constrained_layout=True)
    for index, (sweep, label) in enumerate(zip(sweeps, labels)):
        colour = f"C{index}"
        speeds = sweep["platform_speed"].values * 1e3
        deformation.plot(speeds, sweep["mean_deformation_friction"].values, "o-", ms=2.5, color=colour, label=label)
        stick.plot(speeds, sweep["stick_fraction"].values, "o-", ms=2.5, color=colour, label=label)
        failed = sweep["status"].values != "ok"
        if failed.any():
            stick.plot(speeds[failed], np.zeros(failed.sum()), "x", color=colour, ms=6,
                       label=f"{label}: {', '.join(sorted(set(sweep['status'].values[failed])))}")
        if "converged" in sweep:  # a converged sweep rings the speeds whose statistics did not settle
            missed = sweep["converged"].values == 0
            if missed.any():
                deformation.plot(speeds[missed], sweep["mean_deformation_friction"].values[missed], "o", mfc="none",
                                 ms=8, color=colour, label=f"{label}: not converged to the tolerance")
        for n, speed in enumerate(sweep.attrs.get("critical_speeds_m_per_s", []), start=1):
            deformation.axvline(speed * 1e3, color=colour, ls=":", lw=0.8)
    deformation.set(ylabel="m_D (time-averaged deformation friction)",
                    title="deformation friction against platform speed; dotted: v_c1/n from eqs. (28)-(29)")
    stick.set(xlabel="platform speed v (mm/s)", ylabel="fraction of time stuck")
    for axis in (deformation, stick):
        axis.grid(True, alpha=0.3)
        axis.legend(fontsize=8)
    return figure


def map_figure(dataset, contact_loss_speeds=None):
    """One panel per method: the outcome of each (slope spread, speed) cell, failures named."""
    from matplotlib.colors import ListedColormap  # heavy: matplotlib is imported only when drawing

    plt = _pyplot()
    methods = list(dataset["method"].values)
    figure, axes = plt.subplots(1, len(methods), figsize=(5.2 * len(methods), 3.8), constrained_layout=True,
                                squeeze=False)
    colours = ListedColormap(["#2ca02c", "#9ecae1", "#d62728", "#bdbdbd", "#ff7f0e", "#9467bd"])
    speeds = dataset["platform_speed"].values
    spreads = dataset["slope_std"].values
    for axis, method in zip(axes[0], methods):
        codes = dataset["outcome"].sel({"method": method}).values
        axis.pcolormesh(np.arange(speeds.size + 1), np.arange(spreads.size + 1), codes, cmap=colours, vmin=-0.5,
                        vmax=len(OUTCOMES) - 0.5)
        axis.set_xticks(np.arange(speeds.size) + 0.5, [f"{v * 1e3:.3g}" for v in speeds], rotation=60, fontsize=7)
        axis.set_yticks(np.arange(spreads.size) + 0.5, [f"{s:g}" for s in spreads])
        axis.set(xlabel="platform speed (mm/s)", ylabel="slope standard deviation s", title=method)
    handles = [plt.Rectangle((0, 0), 1, 1, color=colours(i)) for i in range(len(OUTCOMES))]
    figure.legend(handles, OUTCOMES, loc="outside lower center", ncol=len(OUTCOMES), fontsize=8)
    figure.suptitle("seed 004: where each integrator works (red: contact lost, grey: declined)")
    return figure
