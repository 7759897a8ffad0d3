"""Rough-surface figures (seed 000): the surface, its autocorrelation, its height density, its contact."""

from __future__ import annotations

import math

import numpy as np

from faultslip.lab.surfaces import autocorrelation
from faultslip.plots.figures import _pyplot


def surface_figure(surface, stats: dict, contact: dict | None = None):
    """The surface (profile or map), its autocorrelation, its height density and the contact curve.

    Parameters
    ----------
    surface : Surface
        The surface.
    stats : dict
        :func:`surface_statistics`'s statistics.
    contact : dict, optional
        :func:`truncation_contact`'s contact.

    Returns
    -------
    matplotlib.figure.Figure
    """
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


def separation_figure(records: dict, sweeps: dict):
    """Seed 000 chapter 5 in one figure: x(t) as c grows (its figs. 5.9-5.14), the friction-velocity loop
    (fig. 5.18) and the separation (fig. 5.20) with each memory, and the amplitude against c.

    ``records`` maps a label to (dataset, separation in m) for the time-series panels; labels starting
    with "c =" go to panel (a), the others to (b) and (c). ``sweeps`` maps a label to a
    :func:`~faultslip.models.rough_surface.scene.separation_sweep` dataset.
    """
    plt = _pyplot()
    fig, axes = plt.subplots(1, 4, figsize=(17, 3.8), constrained_layout=True)
    for label, (record, _) in records.items():
        if label.startswith("c ="):
            axes[0].plot(record["time"], record["displacement"] * 1e3, lw=0.8, label=label)
    axes[0].set(xlabel="t (s)", ylabel="x (mm)", title="(a) x vs t as c grows (figs. 5.9-5.14)")
    for label, (record, separation) in records.items():
        if label.startswith("c ="):
            continue
        slipping = record["phase"].values == 1
        axes[1].plot(record["sliding_speed"].values[slipping] * 1e3, record["friction_coefficient"].values[slipping],
                     ".", ms=2, label=label)
        axes[2].plot(record["time"], separation * 1e9, lw=0.8, label=label)
    axes[1].set(xlabel="sliding speed (mm/s)", ylabel="mu", title="(b) friction in slip (fig. 5.18)")
    axes[2].set(xlabel="t (s)", ylabel="separation (nm)", title="(c) separation (fig. 5.20)")
    for label, sweep in sweeps.items():
        for memory in sweep["memory"].values:
            axes[3].plot(sweep["separation_coefficient"] * 1e-3, sweep["relative_amplitude"].sel(memory=memory), "o-",
                         ms=3, label=f"{label}, {memory}")
    axes[3].axhline(1.0, color="0.5", ls=":")
    axes[3].set(xlabel="c (s/mm)", ylabel="amplitude / break-away x", title="(d) amplitude against c")
    for axis in axes:
        axis.grid(True, alpha=0.3)
        axis.legend(fontsize=7)
    return fig
