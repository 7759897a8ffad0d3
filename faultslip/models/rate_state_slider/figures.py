"""The rate-and-state slider's figures: a fault's cycles, and the one slider's model error against the 2-D fault."""

from __future__ import annotations

import numpy as np

from faultslip.constants import JULIAN_YEAR
from faultslip.plots.figures import _pyplot


def cycles_figure(dataset):
    """A rate-and-state fault's cycles: slip rate (log) and shear stress against time in years, events marked."""
    plt = _pyplot()
    year = JULIAN_YEAR
    years = dataset["time"].values / year
    figure, (rate, stress) = plt.subplots(2, 1, figsize=(9, 5.6), sharex=True, constrained_layout=True)
    rate.semilogy(years, dataset["slip_rate"].values, color="C0", lw=1)
    rate.axhline(1e-3, color="0.5", lw=0.8, ls="--", label="event threshold 1 mm/s")
    rate.axhline(float(dataset.attrs["plate_rate_m_per_s"]), color="C2", lw=0.8, ls=":", label="plate rate")
    rate.set(ylabel="slip rate (m/s)")
    rate.legend(fontsize=8, loc="center left")
    stress.plot(years, dataset["shear_stress"].values / 1e6, color="C3", lw=1)
    stress.set(xlabel="time (yr)", ylabel="shear stress (MPa)")
    for axis in (rate, stress):
        for start in dataset["event_time"].values / year:
            axis.axvline(start, color="0.8", lw=0.6, zorder=0)
        axis.grid(True, alpha=0.3)
    figure.suptitle(f"{dataset.attrs.get('title', 'rate-and-state cycles')} (K / K_c "
                    f"{float(dataset.attrs['stiffness_ratio']):.3g}, {dataset.attrs.get('method', '')})", fontsize=10)
    return figure


def model_error_figure(table: dict, tolerance: float | None = None, hierarchy: dict | None = None):
    """The model-error chart: the one slider's error against each calibrated 2-D fault over W / h*, the declared
    bound, the held-out faults (SEAS BP1 among them) against it, and where one slider suffices for a tolerance.

    Parameters
    ----------
    table : dict
        :func:`faultslip.models.rate_state_slider.one_slider.load_calibration`'s table.
    tolerance : float, optional
        A model error allowed.
    hierarchy : dict, optional
        ``data/fault_2d_hierarchy.json``: speed against accuracy on SEAS BP1, drawn as a third panel.

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    if hierarchy is None:
        figure, axes = plt.subplots(1, 2, figsize=(11, 4.6), constrained_layout=True, sharey=True)
    else:
        figure = plt.figure(figsize=(16, 4.8), constrained_layout=True)
        first = figure.add_subplot(1, 3, 1)
        axes = [first, figure.add_subplot(1, 3, 2, sharey=first)]
        hierarchy_figure(hierarchy, figure.add_subplot(1, 3, 3))
    for axis, key, title in zip(axes, ("geometric", "zone_width"),
                                ("K = c G / W (c = {c:.3g}, calibrated)", "the seed's K = G / D")):
        part = table[key]
        bound = part["rows"]
        ratios = np.array([row["width_over_nucleation"] for row in bound])
        declared = np.array([row["model_error"] for row in bound])
        # between two calibrated levels the larger of the two is declared; a level is its own
        grid = np.geomspace(ratios[0], ratios[-1], 400)
        upper = np.clip(np.searchsorted(ratios, grid), 0, ratios.size - 1)
        lower = np.where(np.isclose(ratios[upper], grid), upper, np.maximum(upper - 1, 0))
        axis.plot(grid, np.maximum(declared[lower], declared[upper]), color="k", lw=1.5, label="declared bound")
        calibration = part.get("calibration", [])
        shown = [(row["width_over_nucleation"], row["model_error"]) for row in calibration]
        if shown:
            x, y = np.array(shown, float).T
            axis.plot(x, np.minimum(y, 10), "o", color="C0", ms=4, alpha=0.7, label="calibration faults")
        held = part.get("held_out", [])
        for row in held:
            colour = "C2" if row["covered"] else "C3"
            marker = "*" if row["name"] == "SEAS BP1" else "D"
            axis.plot(row["width_over_nucleation"], min(row["model_error"], 10), marker, color=colour,
                      ms=12 if marker == "*" else 6)
        if held:
            axis.plot([], [], "D", color="C2", label=f"held out: {sum(r['covered'] for r in held)} of {len(held)} "
                                                     "within the bound")
            axis.plot([], [], "*", color="k", ms=10, label="SEAS BP1 (held out)")
        if tolerance is not None:
            axis.axhline(tolerance, color="C2", lw=1, ls="--", label=f"tolerance {tolerance:g}")
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set(xlabel="W / h* (seismogenic width over nucleation size)",
                 title=title.format(c=part.get("stiffness_factor", 1.0)))
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=7)
    axes[0].set_ylabel("model error of one slider against the 2-D fault")
    return figure



def hierarchy_figure(table: dict, axis=None):
    """Speed against accuracy up the model hierarchy on SEAS BP1: each method's error in recurrence against the
    converged 2-D answer, against its cost, with the error each declares (benchmarks/hierarchy_chart.py).

    Parameters
    ----------
    table : dict
        ``data/fault_2d_hierarchy.json``: ``points`` with ``method``, ``label``, ``seconds``, ``error``,
        ``declared`` and ``refused``.
    axis : matplotlib.axes.Axes, optional
        Where to draw (a new figure otherwise).

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = _pyplot()
    if axis is None:
        figure, axis = plt.subplots(figsize=(7.5, 5), constrained_layout=True)
    else:
        figure = axis.figure
    styles = {"one_slider": ("*", "C3", "one slider (declared: its model error)"),
              "fault_2d": ("o", "C0", "2-D fault, elements per L_b (declared: a-priori bound)"),
              "fault_2d_tolerance": ("s", "C1", "2-D fault at 39 m, rtol 1e-4 to 1e-9")}
    floor = 1e-7
    for method, (marker, colour, label) in styles.items():
        points = [p for p in table["points"] if p["method"] == method]
        for index, point in enumerate(points):
            error = max(point["error"], floor)
            face = "none" if point["refused"] else colour
            axis.plot(point["seconds"], error, marker, color=colour, mfc=face, ms=12 if method == "one_slider" else 7,
                      label=label if index == 0 else None)
            if point["declared"] is not None:  # the declared band: from the point up to what it declares
                axis.plot([point["seconds"]] * 2, [error, max(point["declared"], floor)], "-", color=colour,
                          alpha=0.5, lw=3)
            if method != "fault_2d_tolerance" and (point["refused"] or method == "one_slider"):
                axis.annotate("refused" if point["refused"] else "one slider", (point["seconds"], error),
                              textcoords="offset points", xytext=(6, 4), fontsize=7, color=colour)
    axis.set_xscale("log")
    axis.set_yscale("log")
    axis.set(xlabel="cost: wall time of the run (s)", ylabel="error in recurrence against BP1's converged 2-D answer",
             title="speed against accuracy, SEAS BP1 (bars: declared)")
    axis.grid(True, which="both", alpha=0.3)
    axis.legend(fontsize=7, loc="lower left")
    return figure
