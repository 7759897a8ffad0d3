"""Plots geophysicists and teachers expect, in plain matplotlib.

Functions take data or presets, draw on given axes (or make a figure) and
return the figure; saving goes through :func:`faultslip.atomic.save_figure`.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg", force=False)  # headless by default; an interactive backend set by the user wins

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import closed_form  # noqa: E402
from .materials import Preset  # noqa: E402

#: Loading-rate range of the seed 003 apparatus (V = 1e-6 to 2 in/s, K = 1.94e4 lb/in, W 137.8-430.6 lb).
LAB_RATE_RANGE = (1e-5, 1e3)


def rate_law_figure(presets: list[Preset], rates=None):
    """Static friction and stick-slip amplitude against log10 of the loading rate.

    Left: mu_s(theta_dot) of seed 003 eq. 2-18 with the kinetic level mu_m
    dashed (the style of the seed's odd-numbered Figs. 4-1 to 4-21). Right:
    amplitude alpha = A0 (mu_s - mu_m) with A0 = 2W/K on each preset's
    apparatus (the seed's even-numbered figures, Table I note).
    """
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
