"""Figures of a 3-D fault run: the first event's rupture front and the slip of the last system-size event on the
fault plane, and the peak slip rate in time."""

from __future__ import annotations

import numpy as np

from faultslip.models.fault_2d.integrate import YEAR
from faultslip.models.fault_3d.bp5_outputs import rupture_times
from faultslip.plots.figures import _pyplot


def rupture_figure(run, title: str = ""):
    """Three panels: the rupture time of the first event (contours every 2 s, SEAS BP5's rupture-time plot), the
    slip of the last event on the fault plane, and log10 of the peak slip rate against time.

    Parameters
    ----------
    run : Fault2DRun
        A 3-D fault's run (its ``fault`` a :class:`faultslip.models.fault_3d.model.Fault3D`).
    title : str
        The figure's title.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    fault = run.fault
    figure, axes = plt.subplots(3, 1, figsize=(8.0, 9.0), constrained_layout=True)
    along = fault.grid(fault.strike_position)[:, 0] / 1e3
    down = fault.grid(fault.depth)[0] / 1e3
    extent = (along[0], along[-1], down[-1], down[0])
    if run.event_count:
        times = fault.grid(rupture_times(run, 0) - float(run.events["start"][0]))
        image = axes[0].imshow(times.T, extent=extent, aspect="auto", cmap="viridis")
        finite = times[np.isfinite(times)]
        if finite.size and finite.max() > finite.min():
            levels = np.arange(0.0, finite.max() + 2.0, 2.0)
            axes[0].contour(along, down, times.T, levels=levels, colors="white", linewidths=0.6)
        figure.colorbar(image, ax=axes[0], label="rupture time (s)")
        axes[0].set(title="first event: slip rate reaches 1 mm/s (contours every 2 s)")
        slip = fault.grid(np.asarray(run.events["slip"][-1], float))
        image = axes[1].imshow(slip.T, extent=extent, aspect="auto", cmap="magma_r", vmin=0.0)
        figure.colorbar(image, ax=axes[1], label="slip (m)")
        axes[1].set(title=f"slip in the last event (event {run.event_count})")
    else:
        for axis in axes[:2]:
            axis.text(0.5, 0.5, "no event in the run", ha="center", va="center", transform=axis.transAxes)
    for axis in axes[:2]:
        axis.set(xlabel="along strike (km)", ylabel="down dip (km)")
    axes[2].plot(np.asarray(run.profile_time) / YEAR, np.log10(np.asarray(run.profile_max_speed)), lw=0.8)
    axes[2].set(xlabel="time (yr)", ylabel="log10 peak slip rate (m/s)")
    figure.suptitle(title or f"{fault.name}: {run.event_count} events")
    return figure
