"""Rough-surface figures (seed 000): the surface, its autocorrelation, its height density, its contact."""

from __future__ import annotations

import math

import numpy as np

from faultslip.lab.surfaces import autocorrelation
from faultslip.plots.figures import _pyplot


def surface_figure(surface, stats: dict, contact: dict | None = None):
    """The surface (profile or map), its autocorrelation, its height density and the contact curve."""
    plt = _pyplot()
    fig, axes = plt.subplots(1, 4 if contact is not None else 3, figsize=(15, 3.6), constrained_layout=True)
    if surface.is_map:
        image = axes[0].imshow(surface.height * 1e6, origin="lower", cmap="terrain",
                               extent=(0, surface.height.shape[1] * surface.dx * 1e3, 0,
                                       surface.height.shape[0] * surface.dy * 1e3))
        fig.colorbar(image, ax=axes[0], label="height (um)")
        axes[0].set(xlabel="x (mm)", ylabel="y (mm)", title="height map")
    else:
        axes[0].plot(np.arange(surface.height.size) * surface.dx * 1e3, surface.height * 1e6, lw=0.6)
        axes[0].set(xlabel="x (mm)", ylabel="height (um)", title="profile")
    lag, c = autocorrelation(surface)
    axes[1].plot(lag * 1e6, c)
    axes[1].axhline(math.exp(-1), color="0.5", ls=":")
    axes[1].set(xlabel="lag (um)", ylabel="C / C(0)", title=f"autocorrelation, beta* = {stats['correlation_length'] * 1e6:.3g} um")
    axes[2].plot(stats["density_heights"] * 1e6, stats["density"] / 1e6)
    axes[2].set(xlabel="height (um)", ylabel="density (1/um)", title="height density (kernel estimate)")
    if contact is not None:
        axes[3].plot(contact["approach"] * 1e6, contact["area"] / contact["nominal_area"], "o-", ms=3)
        axes[3].set(xlabel="approach (um)", ylabel="real / nominal area", title="contact by truncation")
    for axis in axes[1:]:
        axis.grid(True, alpha=0.3)
    return fig
