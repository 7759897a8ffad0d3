"""Posterior figures: a corner plot of the draws, and the record with its posterior-predictive band."""

from __future__ import annotations

import numpy as np

LABELS = {"mu0": r"$\mu_0$", "a": "$a$", "b": "$b$", "critical_slip": r"$D_c$ (µm)", "b2": "$b_2$",
          "critical_slip2": r"$D_{c2}$ (µm)", "stiffness": r"$k$ (1/mm)", "trend": r"$c$ (1/mm)"}
SCALES = {"critical_slip": 1e6, "critical_slip2": 1e6, "stiffness": 1e-3, "trend": 1e-3}


def _label(name: str) -> str:
    """A parameter's axis label: its symbol and unit where known, else its own name (a parameter a new law or
    option adds is drawn, never a KeyError)."""
    return LABELS.get(name, name.replace("_", " "))


def corner_figure(posterior, truths: dict | None = None, bins: int = 40):
    """Every parameter's marginal (with the median and 95 % credible interval) and every pair's joint
    density, as 2-D histograms; ``truths`` draws known values (synthetic records).

    Parameters
    ----------
    posterior : Posterior
        :func:`sample_posterior`'s draws.
    truths : dict, optional
        Known values by parameter (SI).
    bins : int
        Histogram bins.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt  # heavy: imported where used

    names = posterior.names
    count = len(names)
    values = np.column_stack([posterior.samples[:, i] * SCALES.get(n, 1.0) for i, n in enumerate(names)])
    figure, axes = plt.subplots(count, count, figsize=(2.2 * count + 1, 2.2 * count + 1), squeeze=False)
    intervals = posterior.intervals()
    for row in range(count):
        for column in range(count):
            axis = axes[row, column]
            if column > row:
                axis.set_visible(False)
                continue
            if row == column:
                axis.hist(values[:, row], bins=bins, color="C0", histtype="stepfilled", alpha=0.6)
                low, high = (v * SCALES.get(names[row], 1.0) for v in intervals[names[row]])
                for line in (low, float(np.median(values[:, row])), high):
                    axis.axvline(line, color="k", lw=0.8, ls="--" if line != low and line != high else ":")
                axis.set_yticks([])
                axis.set_title(f"{_label(names[row])}: {np.median(values[:, row]):.4g}\n"
                               f"[{low:.4g}, {high:.4g}]", fontsize=8)
            else:
                axis.hist2d(values[:, column], values[:, row], bins=bins, cmap="Blues")
            if truths and names[column] in truths:
                axis.axvline(truths[names[column]] * SCALES.get(names[column], 1.0), color="C3", lw=1)
                if row != column and names[row] in truths:
                    axis.axhline(truths[names[row]] * SCALES.get(names[row], 1.0), color="C3", lw=1)
            from matplotlib.ticker import MaxNLocator  # heavy: imported where used

            axis.xaxis.set_major_locator(MaxNLocator(3))
            axis.yaxis.set_major_locator(MaxNLocator(3))
            axis.ticklabel_format(useOffset=False, style="plain", axis="both") if row != column else \
                axis.ticklabel_format(useOffset=False, style="plain", axis="x")
            if row == count - 1:
                axis.set_xlabel(_label(names[column]))
                axis.tick_params(axis="x", labelrotation=45)
            else:
                axis.set_xticklabels([])
            if column == 0 and row > 0:
                axis.set_ylabel(_label(names[row]))
            elif column > 0:
                axis.set_yticklabels([])
            axis.tick_params(labelsize=7)
    figure.suptitle(f"Posterior ({posterior.samples.shape[0]} draws, {posterior.walkers} walkers; "
                    f"R-hat ≤ {max(posterior.r_hat.values()):.3f}, ESS ≥ "
                    f"{min(posterior.effective_sample_size.values()):.0f}); 95 % credible intervals", fontsize=9)
    figure.tight_layout()
    return figure


def record_fit_figure(record, law_friction, band: dict | None = None, title: str = "", raw_friction=None,
                      trend=None):
    """The record's friction, the fitted law over it and (with ``band`` from
    :meth:`faultslip.lab.posterior.Posterior.predictive`) the posterior bands; below, the load point's speed.

    Parameters
    ----------
    record : StepRecord
        The record.
    law_friction : array_like
        The fitted law's friction at the record's times.
    band : dict, optional
        The posterior predictive bands.
    title : str
        The figure's title.
    raw_friction, trend : array_like, optional
        The raw friction and the removed trend.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt  # heavy: imported where used

    figure, (top, bottom) = plt.subplots(2, 1, figsize=(10, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    if raw_friction is not None:
        top.plot(record.time, raw_friction, color="0.75", lw=0.6, label="raw friction (before detrending)")
    top.plot(record.time, record.friction, ".", color="0.35", ms=1.5, label="record")
    if band is not None:
        low, high = band["data"]
        top.fill_between(band["time"], low, high, color="C1", alpha=0.25, lw=0, label="95 % posterior predictive")
        low, median, high = band["model"]
        top.fill_between(band["time"], low, high, color="C0", alpha=0.5, lw=0, label="95 % credible band (model)")
    top.plot(record.time, law_friction, color="C0", lw=1.0, label="fitted law")
    top.set_ylabel("friction")
    top.legend(fontsize=7, loc="best")
    top.grid(True, alpha=0.3)
    history = record.history
    for start, end, speed in zip(history.times[:-1], history.times[1:], history.speeds):
        bottom.plot([start, end], [speed * 1e6] * 2, color="k")
    bottom.set_ylabel("load point (µm/s)")
    bottom.set_xlabel("time (s)")
    bottom.grid(True, alpha=0.3)
    figure.suptitle(title, fontsize=9)
    figure.tight_layout()
    return figure
