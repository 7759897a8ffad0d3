"""Seed 001's figure: a nanoscale run's swing, friction and charge."""

from __future__ import annotations


from faultslip.plots.figures import _pyplot


def nanoscale_figure(run):
    """Seed 001 Fig. 3: force against displacement, and displacement with deposited charge against time.

    Parameters
    ----------
    run : NanoscaleRun
        A nanoscale run.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    figure, (phase, series) = plt.subplots(1, 2, figsize=(10.5, 4.2), constrained_layout=True)
    half = run.time.size // 2
    phase.plot(run.displacement[half:], run.force[half:], color="C0", lw=0.8)
    phase.set(xlabel="displacement X", ylabel="force F", title=f"force against displacement (A = {run.model.damping:g})")
    phase.grid(True, alpha=0.3)
    window = slice(int(0.93 * run.time.size), None)  # a few events: the staircase of stick and slip
    series.plot(run.time[window], run.displacement[window], color="C0", label="displacement X")
    twin = series.twinx()
    twin.plot(run.time[window], run.deposited[window], color="C3", ls="--", label="deposited charge Sigma_d")
    series.set(xlabel="time (1/omega)", ylabel="X")
    twin.set_ylabel("Sigma_d")
    lines = series.get_legend_handles_labels()[0] + twin.get_legend_handles_labels()[0]
    series.legend(lines, [line.get_label() for line in lines], fontsize=8, loc="upper left")
    series.grid(True, alpha=0.3)
    figure.suptitle("seed 001 toy model: stick-slip and contact charging (eqs. 1-4)")
    return figure
