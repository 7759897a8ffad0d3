"""Fault-displacement hazard at a site on a map's fault (:mod:`faultslip.fault.displacement` for the equations).

The ruptures through the site are the map's own: each segment's characteristic event (rate 1 / T, faultslip's Mw,
its slip per event as the average displacement) or, for a map with a ``[rupture_set]``, the fault system's
ruptures through the site's section on faultslip's branch (their rates, magnitudes and area-weighted average
slips). The site's x / L along each rupture follows the rupture's sections in order.

Where the site's fault takes its friction from a saved fit (a segment's lithology that ``faultslip fit --name``
stored, with its bootstrap samples), each sample's slip per event is a draw: every rupture's average
displacement is scaled by draw / central slip, the curve is computed for each draw, and the result carries
their mean and percentiles (epistemic) beside the aleatory variability of the profile.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from faultslip.errors import InputError
from faultslip.fault import displacement as fdh
from faultslip.fault.scaling import Fault, fitted_draws
from faultslip.io.geo import densify, great_circle, trace_length
from faultslip.units import JULIAN_YEAR, takes_units
from faultslip.datasets import ToXarray

#: the displacement models (faultslip.fault.displacement), and those through fdhpy
MODELS = fdh.MODELS
FDHPY_MODELS = fdh.FDHPY_MODELS
#: how near a fault's trace a site must be for principal displacement (m)
ON_FAULT = 1e3
#: displacements a curve is drawn at by default (m): 1 cm to 30 m
DEFAULT_DISPLACEMENTS = np.logspace(-2, math.log10(30.0), 41)
#: the percentiles of the curve over a fit's draws
QUANTILES = (5.0, 16.0, 50.0, 84.0, 95.0)


@dataclass
class DisplacementHazard(ToXarray):
    """A site's annual rate of exceeding each displacement (m; 1/yr)."""

    site: tuple
    fault: str  # the segment (or section) the site is on
    model: str
    displacements: np.ndarray
    rate: np.ndarray  # mean over draws (the only curve without draws)
    quantiles: dict = field(default_factory=dict)  # percentile -> curve, over a fit's draws
    ruptures: int = 0
    draws: int = 0
    distance: float = 0.0  # m from the site to the trace
    notes: list = field(default_factory=list)
    style: str = "strike-slip"  # of the site's fault, from its rake
    branches: dict = field(default_factory=dict)  # a logic tree's: model -> (weight, curve)

    def as_dict(self) -> dict:
        return {"site": {"lon": self.site[0], "lat": self.site[1]}, "fault": self.fault, "model": self.model,
                "distance_to_trace": {"value": self.distance, "units": "m"}, "ruptures": self.ruptures,
                "draws": self.draws, "displacement": {"value": self.displacements.tolist(), "units": "m"},
                "annual_exceedance_rate": {"value": self.rate.tolist(), "units": "1/yr"},
                "quantiles": {f"{q:g}": {"value": curve.tolist(), "units": "1/yr"} for q, curve in self.quantiles.items()},
                "style": self.style,
                "branches": {name: {"weight": weight, "annual_exceedance_rate": {"value": curve.tolist(), "units": "1/yr"}}
                             for name, (weight, curve) in self.branches.items()},
                "notes": self.notes}

    def to_dataset(self):
        """The curve as an xarray Dataset on ``displacement`` (and ``percentile`` for the draws), CF units."""
        import xarray as xr  # heavy: imported where used

        data = {"annual_exceedance_rate": (("displacement",), self.rate,
                                           {"units": "1/yr", "long_name": "annual rate of exceeding the displacement"})}
        coords = {"displacement": ("displacement", self.displacements,
                                   {"units": "m", "long_name": "principal fault displacement at the site"})}
        if self.quantiles:
            coords["percentile"] = ("percentile", np.array(list(self.quantiles)), {"units": "percent"})
            data["annual_exceedance_rate_percentiles"] = (
                ("percentile", "displacement"), np.vstack(list(self.quantiles.values())),
                {"units": "1/yr", "long_name": "percentiles of the rate over the fit's draws"})
        if self.branches:
            names = list(self.branches)
            coords["branch"] = ("branch", np.array(names), {"long_name": "displacement model of the logic tree"})
            data["branch_weight"] = (("branch",), np.array([self.branches[n][0] for n in names]), {"units": "1"})
            data["branch_annual_exceedance_rate"] = (("branch", "displacement"),
                                                     np.vstack([self.branches[n][1] for n in names]),
                                                     {"units": "1/yr", "long_name": "each model's curve"})
        return xr.Dataset(data, coords=coords, attrs={"site_lon": self.site[0], "site_lat": self.site[1],
                                                      "fault": self.fault, "displacement_model": self.model,
                                                      "style_of_faulting": self.style})


def along_trace(trace, lon: float, lat: float) -> tuple[float, float]:
    """(distance from the site to the trace, how far along the trace its nearest point lies), both in m. Each
    stretch between vertices is densified every 50 m; the distance along is the geodetic length (WGS84, as the
    map measures its segments) to the stretch's first vertex plus the fraction of the stretch's, so a site on a
    vertex is exactly as far along as the trace up to it."""
    trace = np.asarray(trace, float)
    best = (math.inf, 0.0)
    travelled = 0.0
    for i in range(len(trace) - 1):
        points = densify(trace[i:i + 2], 50.0)
        distance = great_circle(points[:, 0], points[:, 1], lon, lat)
        nearest = int(np.argmin(distance))
        stretch = trace_length(trace[i:i + 2])
        if distance[nearest] < best[0]:
            best = (float(distance[nearest]), travelled + stretch * nearest / (len(points) - 1))
        travelled += stretch
    return best


def _nearest(traces, names, lon, lat, what: str) -> tuple[int, float, float]:
    """(index of the trace the site is on, its distance, how far along), or one sentence if it is on none."""
    found = [along_trace(trace, lon, lat) for trace in traces]
    index = int(np.argmin([distance for distance, _ in found]))
    distance, along = found[index]
    if distance > ON_FAULT:
        raise InputError(f"the site ({lon:g}, {lat:g}) is {distance / 1e3:.3g} km from the nearest {what} "
                         f"({names[index]}): principal fault displacement is for a site on a trace (within "
                         f"{ON_FAULT / 1e3:g} km)")
    return index, distance, along


def _segment_ruptures(spec, dataset, lon, lat) -> dict:
    """The site's segment's characteristic event as the one rupture through the site."""
    table = spec.segments
    index, distance, along = _nearest(table.traces, table.ids, lon, lat, "fault trace")
    recurrence = float(dataset["recurrence_period"].values[index])
    slip = float(dataset["slip_per_event"].values[index])
    if not (math.isfinite(recurrence) and recurrence > 0 and math.isfinite(slip) and slip > 0):
        raise InputError(f"segment {table.ids[index]} has no stick-slip on this map: no earthquakes to displace "
                         "the site")
    length = float(dataset["segment_length"].values[index])
    return {"fault": index, "name": str(table.ids[index]), "distance": distance,
            "rates": np.array([JULIAN_YEAR / recurrence]),
            "magnitudes": np.array([float(dataset["moment_magnitude"].values[index])]),
            "positions": np.array([min(max(along / length, 0.0), 1.0)]), "averages": np.array([slip]),
            "note": f"the site is {along / 1e3:.3g} km along segment {table.ids[index]} ({length / 1e3:.4g} km): its "
                    "characteristic event is the one rupture through it"}


def _system_ruptures(result, lon, lat) -> dict:
    """The fault system's ruptures through the site's section, with the site's x / L along each."""
    sections = result.sections
    s, distance, along = _nearest(sections.traces, sections.ids, lon, lat, "section")
    ends = [(np.asarray(t[0]), np.asarray(t[-1])) for t in sections.traces]
    rates, magnitudes, positions, averages = [], [], [], []
    for k in np.flatnonzero(result.rate > 0):
        members = list(result.ruptures[k])
        if s not in members:
            continue
        place = members.index(s)
        # the rupture enters the site's section by the end nearer the section before it (or leaves by the end
        # nearer the one after it)
        if place > 0:
            other = sections.traces[members[place - 1]]
            entry = int(along_trace(other, *ends[s][1])[0] < along_trace(other, *ends[s][0])[0])
        elif place + 1 < len(members):
            other = sections.traces[members[place + 1]]
            entry = int(along_trace(other, *ends[s][0])[0] < along_trace(other, *ends[s][1])[0])
        else:
            entry = 0
        within = along if entry == 0 else sections.length[s] - along
        before = float(sections.length[members[:place]].sum())
        total = float(sections.length[members].sum())
        area = sections.area[members]
        rates.append(result.rate[k])
        magnitudes.append(result.magnitude[k])
        positions.append(min(max((before + within) / total, 0.0), 1.0))
        averages.append(float(np.sum(area * result.slip[members, k]) / area.sum()))
    if not rates:
        raise InputError(f"no rupture of the fault system with a rate passes through section {sections.ids[s]}")
    return {"fault": int(sections.fault[s]), "name": sections.ids[s], "distance": distance, "rates": np.array(rates),
            "magnitudes": np.array(magnitudes), "positions": np.array(positions), "averages": np.array(averages),
            "note": f"{len(rates)} rupture(s) of the fault system ({result.relation}) pass through section "
                    f"{sections.ids[s]}"}


def fault_draws(spec, dataset, index: int):
    """Slip per event (m) of segment ``index`` for each draw of a saved fit that is its lithology, or None."""
    if spec.scene.rate_state:
        return None
    table = spec.segments
    inputs = dict(spec.scene.fault_inputs)
    inputs.update(lithology=table.lithology[index], slip_rate=f"{float(table.slip_rate[index])!r} m/s",
                  zone_width=f"{float(table.zone_width[index])!r} m",
                  seismogenic_depth=f"{float(table.seismogenic_depth[index])!r} m",
                  rupture_length=f"{float(dataset['segment_length'].values[index])!r} m", dip=float(table.dips[index]))
    for key in ("mu_so", "mu_m", "b", "d", "shear_modulus"):  # the lithology's own, as the map takes them
        inputs.pop(key, None)
    draws = fitted_draws(Fault(**inputs))
    return None if draws is None else draws[0]


@takes_units(displacements="length")
def displacement_hazard(spec, dataset, site, model: str = "faultslip", displacements=None, system=None,
                        surface_rupture: bool = True) -> DisplacementHazard:
    """The annual rate of exceeding each displacement at ``site`` (lon, lat in degrees) on a map's fault.

    Parameters
    ----------
    spec : MapSpec
        A segment map.
    dataset : xarray.Dataset
        Its predictions (:func:`faultslip.studies.maps.run_map`).
    site : tuple
        (lon, lat) in degrees, on a trace (within :data:`ON_FAULT`).
    model : str
        ``faultslip`` (its slip per event as the average displacement), ``petersen_2011``, one of fdhpy's models
        (:data:`faultslip.fault.displacement.FDHPY_MODELS`, for the rupture's style of faulting from the fault's
        rake), or ``logic_tree`` (every model that applies, equally weighted).
    displacements : array, optional
        Displacements (m); :data:`DEFAULT_DISPLACEMENTS` otherwise.
    system : RuptureSet, optional
        The map's fault system: its ruptures through the site instead of each segment's own event.
    surface_rupture : bool
        Weigh by Wells & Coppersmith's (1993) probability of surface rupture.

    Returns
    -------
    DisplacementHazard
    """
    if spec.segments is None:
        raise InputError("a displacement hazard needs fault segments ([segments]), not a raster map")
    lon, lat = site
    d = DEFAULT_DISPLACEMENTS if displacements is None else np.asarray(displacements, float)
    if model not in MODELS:
        raise InputError(f"the displacement model must be one of {', '.join(MODELS)}, got {model!r}")
    ruptures = _system_ruptures(system, lon, lat) if system is not None else _segment_ruptures(spec, dataset, lon, lat)
    notes = [ruptures["note"]]
    style = fdh.style_of(spec.segments.rakes[ruptures["fault"]])  # the site's fault (a section's, on a system)
    if model == "logic_tree":
        return _logic_tree(spec, dataset, (lon, lat), d, ruptures, style, surface_rupture, system, notes)
    if model in fdh.FDHPY_MODELS:
        probability, said = fdh.fdhpy_exceedance(model, d, ruptures["magnitudes"], ruptures["positions"], style)
        weight = ruptures["rates"] * (fdh.surface_rupture_probability(ruptures["magnitudes"]) if surface_rupture else 1.0)
        notes += said + [f"{model} (fdhpy) for a {style} rupture"
                         + ("; surface rupture by Wells & Coppersmith (1993)" if surface_rupture else "")]
        return DisplacementHazard((lon, lat), ruptures["name"], model, d, probability.T @ weight, {},
                                  len(ruptures["rates"]), 0, ruptures["distance"], notes, style)
    curve = fdh.displacement_hazard_curve(d, ruptures["rates"], ruptures["magnitudes"], ruptures["positions"],
                                          ruptures["averages"], model, surface_rupture)
    quantiles, count = {}, 0
    draws = fault_draws(spec, dataset, ruptures["fault"]) if model == "faultslip" else None
    if draws is not None:
        central = float(dataset["slip_per_event"].values[ruptures["fault"]])
        factors = draws / central
        factors = factors[np.isfinite(factors) & (factors > 0)]
        if factors.size:
            curves = fdh.displacement_hazard_curve(d, ruptures["rates"], ruptures["magnitudes"], ruptures["positions"],
                                                   factors[:, None] * ruptures["averages"][None, :], model,
                                                   surface_rupture)
            curve, count = curves.mean(axis=0), int(factors.size)
            quantiles = {q: value for q, value in zip(QUANTILES, np.percentile(curves, QUANTILES, axis=0))}
            notes.append(f"{count} draws of the fit {spec.segments.lithology[ruptures['fault']]!r} carried through: "
                         "the curve is their mean, with their percentiles")
    elif model == "faultslip":
        notes.append("a rate-and-state map carries no draws to the displacement hazard: the curve carries the "
                     "profile's aleatory variability alone" if spec.scene.rate_state else
                     "the site's fault takes its friction from a preset without draws: the curve carries the "
                     "profile's aleatory variability alone")
    notes.append("principal displacement: Petersen et al. (2011) elliptical profile and sigma (a regression on "
                 "strike-slip ruptures, used whatever the slip type)"
                 + (", its level faultslip's slip per event" if model == "faultslip" else ", its level from Mw")
                 + ("; surface rupture by Wells & Coppersmith (1993)" if surface_rupture else ""))
    return DisplacementHazard((lon, lat), ruptures["name"], model, d, curve, quantiles, len(ruptures["rates"]), count,
                              ruptures["distance"], notes, style)


def _logic_tree(spec, dataset, site, d, ruptures, style, surface_rupture, system, notes) -> DisplacementHazard:
    """Every model that applies to the rupture's style, equally weighted: the mean curve, each branch's, and the
    5-95 % spread across them (epistemic: the models' disagreement). A model fdhpy cannot give (not installed) is
    left out and said."""
    names = fdh.applicable_models(style)
    branches, said = {}, []
    for name in names:
        try:
            branch = displacement_hazard(spec, dataset, site, name, d, system, surface_rupture)
        except InputError as exc:
            if "fdhpy" not in str(exc):
                raise
            said.append(f"{name} left out: fdhpy is not installed (pip install 'faultslip[fdh]')")
            continue
        branches[name] = branch.rate
        said += [note for note in branch.notes if "outside its range" in note]
    weight = 1.0 / len(branches)
    curves = np.vstack(list(branches.values()))
    mean = curves.mean(axis=0)
    quantiles = {q: value for q, value in zip((5.0, 50.0, 95.0), np.percentile(curves, (5.0, 50.0, 95.0), axis=0))}
    notes = notes + said + [f"logic tree over the {len(branches)} models for a {style} rupture, equally weighted: "
                            f"{', '.join(branches)}; the percentiles are across the models"]
    return DisplacementHazard(site, ruptures["name"], "logic_tree", d, mean, quantiles, len(ruptures["rates"]), 0,
                              ruptures["distance"], notes, style,
                              {name: (weight, curve) for name, curve in branches.items()})
