"""Figures of a spring-block chain: where each event slipped, its magnitude-frequency distribution with the
fitted Gutenberg-Richter line, and the intervals between system-size events."""

from __future__ import annotations

import numpy as np

from faultslip.plots.figures import _pyplot


def chain_figure(catalogue, stats: dict, title: str = ""):
    """Three panels: the events in block and time (each a bar from its first to its last block), the
    cumulative number N(>= M) against M with Aki's b-value line, and the system-size intervals.

    Parameters
    ----------
    catalogue : xarray.Dataset
        A chain's catalogue (:func:`faultslip.models.spring_chain.family.run`'s dataset).
    stats : dict
        Its statistics (b-value, system-size recurrence).
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, (events, frequency, intervals) = plt.subplots(1, 3, figsize=(12.5, 4.2), constrained_layout=True)
    start = catalogue["event_start"].values
    slip = catalogue["slip"].values
    slipped = slip > 0
    first = np.where(slipped.any(axis=1), slipped.argmax(axis=1), 0)
    last = np.where(slipped.any(axis=1), slip.shape[1] - 1 - slipped[:, ::-1].argmax(axis=1), 0)
    scale, unit = (365.25 * 86400.0, "yr") if start.size and start[-1] > 3e7 else (1.0, "s")
    events.vlines(start / scale, first - 0.4, last + 0.4, color="C3", lw=0.8)
    events.set(xlabel=f"time ({unit})", ylabel="block", title="events: the blocks each slipped")
    magnitude = np.sort(catalogue["magnitude"].values)
    count = np.arange(magnitude.size, 0, -1)
    frequency.semilogy(magnitude, count, ".", ms=3, color="C0", label="N(>= M)")
    b = stats.get("b")
    if b is not None:
        line = np.linspace(b["completeness"], magnitude.max(), 50)
        frequency.semilogy(line, 10 ** (b["a"] - b["b"] * line), color="C3",
                           label=f"b = {b['b']:.2f} ({b['interval'][0]:.2f}-{b['interval'][1]:.2f})")
    frequency.set(xlabel="moment magnitude M", ylabel="number of events with magnitude >= M",
                  title="magnitude-frequency")
    frequency.legend(fontsize=8)
    system = catalogue["blocks_slipped"].values >= stats.get("system_fraction", 0.5) * slip.shape[1]
    gaps = np.diff(start[system]) / scale
    if gaps.size:
        intervals.hist(gaps, bins=min(30, max(5, gaps.size // 3)), color="C2")
    intervals.set(xlabel=f"interval between system-size events ({unit})", ylabel="count",
                  title=f"recurrence (CV {stats.get('recurrence_cv', float('nan')):.2f})")
    if title:
        figure.suptitle(title)
    return figure
