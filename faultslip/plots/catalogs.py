"""Observed recurrence beside the prediction (``faultslip catalog --plot``)."""

from __future__ import annotations

import numpy as np

from faultslip.fault import recurrence
from faultslip.plots.figures import _pyplot

YEAR = recurrence.SECONDS_PER_YEAR


def catalog_figure(comparison, title: str):
    """Left: the events' magnitudes against time. Right: the observed intervals with the fitted renewal
    densities and the predicted recurrence.

    Parameters
    ----------
    comparison : CatalogComparison
        :func:`compare_catalog`'s comparison.
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, (timeline, density) = plt.subplots(1, 2, figsize=(11, 4.2), constrained_layout=True)
    events = comparison.selected
    years = 1970 + events.seconds() / YEAR
    timeline.vlines(years, 0, events.magnitude, color="C0")
    timeline.plot(years, events.magnitude, "o", color="C0", label="selected events")
    prediction = comparison.prediction
    if prediction.recurrence is not None:
        step = prediction.recurrence / YEAR
        marks = years[0] + step * np.arange(0, int((years[-1] - years[0]) / step) + 2)
        for index, mark in enumerate(marks):
            timeline.axvline(mark, color="C3", ls=":", lw=1, label="predicted recurrence from the first event"
                             if index == 0 else None)
    timeline.set(xlabel="year", ylabel="magnitude", title="events on the fault")
    timeline.legend(fontsize=8, loc="lower right")
    if comparison.summary is not None:
        gaps = np.diff(events.seconds()) / YEAR
        top = max(gaps.max(), (prediction.recurrence or 0) / YEAR) * 1.6
        density.hist(gaps, bins=max(4, gaps.size), range=(0, top), density=True, color="0.8", label="observed intervals")
        grid = np.linspace(top / 500, top, 500)
        for index, (model, fitted) in enumerate(comparison.fits.items()):
            law = recurrence.distribution(model, fitted.mean / YEAR, fitted.aperiodicity)
            density.plot(grid, law.pdf(grid), color=f"C{index + 1}",
                         label=f"{model}: mean {fitted.mean / YEAR:.1f} yr, aperiodicity {fitted.aperiodicity:.2f}")
        if prediction.recurrence is not None:
            density.axvline(prediction.recurrence / YEAR, color="C3", lw=2,
                            label=f"predicted ({'rate-and-state' if prediction.law == 'rate_state' else 'seed law'}): "
                                  f"{prediction.recurrence / YEAR:.1f} yr")
        density.set(xlabel="interval (yr)", ylabel="probability density", title="recurrence")
        density.legend(fontsize=7)
    else:
        density.text(0.5, 0.5, "too few events for intervals", ha="center", va="center", transform=density.transAxes)
        density.set_axis_off()
    for axis in (timeline, density):
        axis.grid(True, alpha=0.3)
    figure.suptitle(title, fontsize=10)
    return figure
