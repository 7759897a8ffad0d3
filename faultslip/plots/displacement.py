"""The fault-displacement hazard curve a site's engineer reads: annual rate of exceedance against displacement."""

from __future__ import annotations


def displacement_hazard_figure(hazard):
    """Annual rate of exceeding each displacement at the site (log-log), with the percentiles over a fit's draws
    shaded where there are draws, and the 475- and 2475-year return periods marked.

    Parameters
    ----------
    hazard : faultslip.studies.displacement_hazard.DisplacementHazard
        The curve.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure  # heavy: imported where used

    figure = Figure(figsize=(6.4, 4.6), layout="constrained")
    axes = figure.add_subplot()
    d = hazard.displacements
    if hazard.quantiles:
        low, high = hazard.quantiles[min(hazard.quantiles)], hazard.quantiles[max(hazard.quantiles)]
        axes.fill_between(d, low, high, color="0.85", label=f"{min(hazard.quantiles):g}-{max(hazard.quantiles):g} % "
                          f"over {hazard.draws} draws of the fit")
    positive = hazard.rate > 0
    axes.loglog(d[positive], hazard.rate[positive], color="C3", lw=2,
                label="mean" if hazard.quantiles else hazard.model.replace("_", " "))
    for years in (475, 2475):
        axes.axhline(1 / years, color="0.5", lw=0.8, ls=":")
        axes.text(d[0], 1 / years, f" {years} yr", va="bottom", fontsize=8, color="0.4")
    axes.set_xlabel("principal fault displacement at the site (m)")
    axes.set_ylabel("annual rate of exceedance (1/yr)")
    lon, lat = hazard.site
    axes.set_title(f"Fault-displacement hazard at {lon:.3f}, {lat:.3f} ({hazard.fault})", fontsize=10)
    axes.grid(True, which="both", alpha=0.3)
    axes.legend(fontsize=8, loc="lower left")
    return figure
