"""Plots geophysicists and teachers expect, in plain matplotlib.

Functions take data or presets, draw on given axes (or make a figure) and
return the figure; saving goes through :func:`faultslip.io.atomic.save_figure`.
"""

from __future__ import annotations

import numpy as np

from faultslip.io.report import display_unit

from faultslip.dynamics.spring_slider import closed_form
from faultslip.friction.materials import Preset
from faultslip.dynamics.spring_slider.critical import critical
from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle, slip_trajectory
from faultslip.units import takes_units

#: Loading-rate range of the seed 003 apparatus (V = 1e-6 to 2 in/s, K = 1.94e4 lb/in, W 137.8-430.6 lb).
LAB_RATE_RANGE = (1e-5, 1e3)


@takes_units(rates="rate")
def rate_law_figure(presets: list[Preset], rates=None):
    """Static friction and stick-slip amplitude against log10 of the loading rate.

    Left: mu_s(theta_dot) of seed 003 eq. 2-18 with the kinetic level mu_m
    dashed (the style of the seed's odd-numbered Figs. 4-1 to 4-21). Right:
    amplitude alpha = A0 (mu_s - mu_m) with A0 = 2W/K on each preset's
    apparatus (the seed's even-numbered figures, Table I note).

    Parameters
    ----------
    presets : list of Preset
        The presets drawn.
    rates : array_like, optional
        Loading rates (1/s).

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    if rates is None:
        rates = np.logspace(np.log10(LAB_RATE_RANGE[0]), np.log10(LAB_RATE_RANGE[1]), 400)
    log_rate = np.log10(rates)
    figure, (ax_mu, ax_alpha) = plt.subplots(1, 2, figsize=(11, 4.6), constrained_layout=True)
    colours = plt.get_cmap("tab20")(np.linspace(0, 1, max(len(presets), 2)))
    for preset, colour in zip(presets, colours):
        law = preset.require_stick_slip()
        label = f"{preset.material}, {preset.condition}"
        ax_mu.plot(log_rate, law.static(rates), color=colour, label=label)
        ax_mu.axhline(law.mu_m, color=colour, lw=0.8, ls="--")
        amplitude = closed_form.rate_law_amplitude(
            rates, preset.normal_load, preset.stiffness, law.mu_so, law.mu_m, law.b, law.d, 0.0
        )
        ax_alpha.plot(log_rate, amplitude / 0.0254, color=colour, label=label)
    ax_mu.set_xlabel(r"$\log_{10}\,\dot\theta$  ($\dot\theta$ in 1/s)")
    ax_mu.set_ylabel(r"static friction $\mu_s$")
    ax_mu.set_title(r"$\mu_s = \mu_m + 1/(1/(\mu_{so}-\mu_m) + b\dot\theta^{d})$  (seed 003 eq. 2-18)")
    ax_alpha.set_xlabel(r"$\log_{10}\,\dot\theta$  ($\dot\theta$ in 1/s)")
    ax_alpha.set_ylabel(r"amplitude $\alpha$ (in)")
    ax_alpha.set_title(r"$\alpha = A_0(\mu_s-\mu_m)$, $A_0 = 2W/K$  (eq. 2-19, $\lambda \to 0$)")
    for axis in (ax_mu, ax_alpha):
        axis.grid(True, alpha=0.3)
    ax_alpha.legend(fontsize=7, loc="upper right")
    return figure


@takes_units(critical_rate="rate")
def phase_plane_figure(system, rate_factors=(0.3, 0.999, 1.5), critical_rate=None):
    """Phase-plane (x, x') trajectories below, at and above the critical loading rate.

    Like seed 003 Figs. 2-7, 2-8 and 4-24 to 4-27: below the critical rate the slip
    trajectory returns to the line x' = V and a stick segment closes the limit cycle; at it
    the trajectory only touches the line; above it the trajectory spirals into steady sliding.

    Parameters
    ----------
    system : SliderSystem
        The slider.
    rate_factors : tuple
        Loading rates as fractions of the critical one.
    critical_rate : float, optional
        theta_c (1/s).

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()

    if critical_rate is None:
        critical_rate = critical(system).critical_loading_rate
    figure, axes = plt.subplots(1, len(rate_factors), figsize=(4.2 * len(rate_factors), 4.2), constrained_layout=True)
    for axis, factor in zip(np.atleast_1d(axes), rate_factors):
        at_rate = system.at_loading_rate(critical_rate * factor) if np.isfinite(critical_rate) else system
        cycle = exact_cycle(at_rate)
        duration = None if cycle.regime != "steady_sliding" else 8 * 2 * np.pi / at_rate.natural_frequency
        _, x, v = slip_trajectory(at_rate, duration=duration, samples=1500)
        micron, mm_s = 1e6, 1e3
        axis.plot(x * micron, v * mm_s, color="C0", lw=1.3, label="slip")
        if cycle.regime != "steady_sliding":
            axis.plot([x[-1] * micron, x[0] * micron], [at_rate.platform_speed * mm_s] * 2, color="C3", lw=2.0,
                      label="stick (x' = V)")
        axis.axhline(at_rate.platform_speed * mm_s, color="C3", lw=0.8, ls=":")
        axis.axhline(0.0, color="0.6", lw=0.6)
        axis.set_xlabel("displacement x (µm)")
        axis.set_title(f"θ̇ = {factor:g} θ̇c: {cycle.regime.replace('_', ' ')}", fontsize=10)
        axis.grid(True, alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("velocity x' (mm/s)")
    np.atleast_1d(axes)[0].legend(fontsize=8, loc="lower left")
    figure.suptitle(f"Phase plane, {system.name} (ζ = {system.damping_ratio:.3g}, θ̇c = {critical_rate:.4g} 1/s)")
    return figure


def sawtooth_figure(dataset, cycles: int = 6):
    """Spring force and displacement against time: the sawtooth record of stick-slip.

    Parameters
    ----------
    dataset : xarray.Dataset
        A simulation's time series.
    cycles : int
        Cycles drawn.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    events = dataset["event_time"].values
    if events.size > 1:  # window on the limit cycle, not on the first loading from rest
        start = events[0] - 0.5 * (events[1] - events[0])
        end = events[min(cycles, events.size - 1)] + 0.5 * (events[1] - events[0])
    else:
        start, end = None, None
    part = dataset.sel(time=slice(start, end))
    fault = dataset.attrs.get("scale") == "fault"
    # axes a person reads: time from the window's start, in the unit its span calls for (a lab window 22 s
    # long at t = 55 s read "55000-77000 ms"), lengths likewise
    times = part["time"].values
    origin = float(times[0]) if times.size else 0.0
    time_unit, time_scale = display_unit([float(times[-1]) - origin if times.size else 0.0], "s")
    length_unit, length_scale = display_unit([float(np.nanmax(np.abs(part["displacement"].values)))
                                              if times.size else 0.0], "m")
    figure, (ax_force, ax_x) = plt.subplots(2, 1, figsize=(9, 5.5), sharex=True, constrained_layout=True)
    t = (times - origin) / time_scale
    force = part["spring_force"]
    ax_force.plot(t, force.values / (1e5 if fault else 1.0), color="C0", lw=1.2)
    ax_force.set_ylabel(f"spring force K x ({'bar' if fault else force.attrs['units']})")
    displacement = part["displacement"].values / length_scale
    ax_x.plot(t, displacement, color="C1", lw=1.2)
    slipping = part["phase"].values == 1
    ax_x.plot(t[slipping], displacement[slipping], ".", color="C3", ms=2, label="slip")
    ax_x.set_ylabel(f"displacement x ({length_unit})")
    start_unit, start_scale = display_unit([origin], "s")
    ax_x.set_xlabel(f"time ({time_unit}) since t = {origin / start_scale:.4g} {start_unit}".rstrip())
    ax_x.legend(fontsize=8)
    for axis in (ax_force, ax_x):
        axis.grid(True, alpha=0.3)
    figure.suptitle(f"Stick-slip record: {dataset.attrs.get('scene', '')} ({dataset.attrs.get('slip_solver', '')})")
    return figure


def critical_comparison_figure(dataset):
    """Exact against seed (eq. I-22) critical loading rate across damping ratios."""
    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(7, 4.8), constrained_layout=True)
    zeta = dataset["damping_ratio"].values
    for index, preset in enumerate(dataset["preset"].values):
        row = dataset.sel(preset=preset)
        axis.loglog(zeta, row["critical_loading_rate"].values, "-o", color=f"C{index}", label=f"{preset}: exact")
        axis.loglog(zeta, row["seed_appendix_I_loading_rate"].values, "--s", color=f"C{index}", mfc="none",
                    label=f"{preset}: seed eq. I-22")
    axis.set_xlabel("damping ratio ζ")
    axis.set_ylabel("critical loading rate θ̇c (1/s)")
    axis.set_title("Critical loading rate: exact tangency vs seed 003 Appendix I")
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=7, ncol=2)
    return figure


def _pyplot():
    """matplotlib.pyplot, headless by default (an interactive backend set by the user wins)."""
    import matplotlib  # heavy: imported where used

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt  # heavy: imported where used

    return plt


def classroom_figure(analysis):
    """The classroom record: acceleration along the pull with its slip phases shaded, and each slip's friction
    drop against time.

    Parameters
    ----------
    analysis : ClassroomAnalysis
        :func:`analyse_accelerometer`'s analysis.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, (trace, drops) = plt.subplots(2, 1, figsize=(10, 5.2), constrained_layout=True, sharex=True)
    record = analysis.record
    signal = record.acceleration[analysis.axis]
    trace.plot(record.time, signal - np.median(signal), color="C0", lw=0.7, label=f"acceleration {analysis.axis}")
    for index, (start, duration) in enumerate(zip(analysis.starts, analysis.durations)):
        trace.axvspan(start, start + duration, color="C3", alpha=0.25, label="slip" if index == 0 else None)
    trace.set(ylabel="acceleration (m/s^2)", title=f"{record.source}: stick and slip")
    trace.legend(fontsize=8, loc="upper right")
    drops.plot(analysis.starts, analysis.friction_drop, "o", color="C3")
    drops.set(xlabel="time (s)", ylabel="mu_s - mu_k", title="friction drop of each slip (a at break-away / g)")
    for axis in (trace, drops):
        axis.grid(True, alpha=0.3)
    return figure
