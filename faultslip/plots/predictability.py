"""The predictability exercise as QuakeCaster draws it (Linton & Stein 2012): a staircase of cumulative slip against
time with the time- and slip-predictable lines, and the two correlations."""

from __future__ import annotations

import numpy as np

from faultslip.plots.figures import _pyplot

YEAR = 365.25 * 86400.0


def predictability_figure(result):
    """Cumulative slip against time, and slip against the intervals after and before each event.

    Parameters
    ----------
    result : Predictability
        :func:`faultslip.fault.predictability.predictability`'s answer.

    Returns
    -------
    matplotlib.figure.Figure
        Left: the staircase of cumulative slip; the time-predictable line (every event starts on it: a fixed
        upper level loaded at the mean rate) and the slip-predictable line (every event ends on it). Right: s_k
        against the following interval and the preceding interval against s_k, each with its r.
    """
    plt = _pyplot()
    figure, (staircase, scatter) = plt.subplots(1, 2, figsize=(11, 4.3), constrained_layout=True)
    t = result.times / YEAR
    after = np.cumsum(result.slips)
    before = after - result.slips
    rate = (after[-1] - after[0]) / (t[-1] - t[0])  # the mean loading rate over the sequence
    steps_t = np.repeat(t, 2)
    steps_s = np.column_stack([before, after]).ravel()
    staircase.plot(steps_t, steps_s, color="k", lw=1.5, label="cumulative slip")
    span = np.array([t[0], t[-1]])
    staircase.plot(span, before[0] + rate * (span - t[0]), "--", color="C0",
                   label="time-predictable: events start on this line")
    staircase.plot(span, after[0] + rate * (span - t[0]), ":", color="C3",
                   label="slip-predictable: events end on this line")
    staircase.set(xlabel="time since the first event (yr)", ylabel=f"cumulative size ({result.slip_unit.split(' ')[0]})",
                  title="the sequence")
    staircase.legend(fontsize=7)
    staircase.grid(True, alpha=0.3)
    intervals = result.intervals / YEAR
    scatter.plot(result.slips[:-1], intervals, "o", color="C0",
                 label=f"interval after vs slip: r = {result.time_correlation:.2f} "
                       f"({result.time_range[0]:.2f} to {result.time_range[1]:.2f})")
    scatter.plot(result.slips[1:], intervals, "s", color="C3", mfc="none",
                 label=f"interval before vs slip: r = {result.slip_correlation:.2f} "
                       f"({result.slip_range[0]:.2f} to {result.slip_range[1]:.2f})")
    scatter.set(xlabel=f"slip ({result.slip_unit.split(' ')[0]})", ylabel="interval (yr)",
                title=f"coefficient of variation {result.aperiodicity:.2f} "
                      f"({result.aperiodicity_range[0]:.2f} to {result.aperiodicity_range[1]:.2f})")
    scatter.legend(fontsize=7)
    scatter.grid(True, alpha=0.3)
    return figure
