"""From a segment map to a hazard engine: moment-balanced sources, scaling-relation branches, an engine job.

Each mapped segment with stick-slip has faultslip's characteristic event (Mw, recurrence T) and a
moment rate, the seismic moment over T (= G L H V: slip per event = V T). :func:`hazard_sources` puts
beside faultslip's Mw the magnitudes that the empirical relations give for the same rupture (length L,
width H, area L H): Wells & Coppersmith (1994) Mw(RA) and Mw(SRL) with their sigmas, Leonard (2010) Mw(A)
and Mw(L) with his ranges (:mod:`faultslip.fault.empirical`).

:func:`source_models` turns them into one source model per magnitude-scaling relation, a logic-tree
branch each (``faultslip``, ``WC1994``, ``Leonard2010``): every branch releases the same moment rate,
spread by a magnitude-frequency distribution (:mod:`faultslip.fault.mfd`) around that relation's
magnitude. :func:`write_hazard_model` writes them as NRML (:mod:`faultslip.io.nrml`), and
:func:`write_engine_job` an OpenQuake classical job over them (sites, one GMPE, PGA).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.fault import empirical, mfd as mfds
from faultslip.io.atomic import write_text_atomic
from faultslip.fault.recurrence import conditional_probability
from faultslip.io.nrml import (write_logic_tree, write_multi_fault_model, write_nonparametric_model, write_sections,
                               write_source_model)
from faultslip.studies import rupture_sets
from faultslip.units import JULIAN_YEAR

#: branch name -> the engine's magnitude-scaling relation its sources carry (Leonard 2014's interplate
#: relations keep Leonard 2010's Mw(A) constants, 3.99 and 4.00; his stable-continental one is Leonard2010_SCR)
RELATIONS = {"faultslip": "WC1994", "WC1994": "WC1994", "Leonard2010": "Leonard2014_Interplate"}
#: an OpenQuake GMPE for active shallow crust (NGA-West2), and PGA levels in g
DEFAULT_GMPE = "BooreEtAl2014"
DEFAULT_LEVELS = (0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 1.5, 2.0)


@dataclass(frozen=True)
class HazardSource:
    """One segment's characteristic event and the empirical magnitudes for its rupture."""

    id: str
    name: str
    trace: np.ndarray
    dip: float
    rake: float
    upper_depth: float  # m
    lower_depth: float  # m
    length: float  # m, the rupture length faultslip used
    width: float  # m, the rupture's down-dip width H / sin(dip) (H for a vertical fault)
    slip_type: str
    magnitude: float  # faultslip's Mw
    recurrence: float  # s
    moment_rate: float  # N m per year
    empirical: dict  # relation label -> {"magnitude", "sigma" or "range"}

    @property
    def has_event(self) -> bool:
        return math.isfinite(self.magnitude) and math.isfinite(self.recurrence) and self.recurrence > 0

    def branch_magnitude(self, relation: str, stable_continental: bool = False) -> float:
        """The characteristic magnitude on a branch: faultslip's, W&C's Mw(RA) or Leonard's Mw(A)."""
        if relation == "faultslip":
            return self.magnitude
        area = self.length * self.width
        if relation == "WC1994":
            return float(empirical.magnitude_from_area(area, self.slip_type)[0])
        if relation == "Leonard2010":
            return float(empirical.leonard_magnitude_from_area(
                area, empirical.leonard_setting(self.slip_type, stable_continental)))
        raise InputError(f"scaling relation must be one of {', '.join(RELATIONS)}, got {relation!r}")

    def as_dict(self) -> dict:
        finite = lambda value: value if math.isfinite(value) else None  # noqa: E731 (JSON)
        return {"id": self.id, "name": self.name, "slip_type": self.slip_type,
                "magnitude": finite(self.magnitude), "recurrence": {"value": finite(self.recurrence), "units": "s"},
                "moment_rate": {"value": finite(self.moment_rate), "units": "N m/yr"},
                "rupture": {"length": {"value": self.length, "units": "m"}, "width": {"value": self.width, "units": "m"}},
                "empirical": self.empirical}


def _empirical_magnitudes(length: float, width: float, slip_type: str, stable_continental: bool) -> dict:
    area = length * width
    setting = empirical.leonard_setting(slip_type, stable_continental)
    rows = {}
    value, sigma = empirical.magnitude_from_area(area, slip_type)
    rows[f"W&C 1994 Mw(RA), {slip_type}"] = {"magnitude": float(value), "sigma": sigma}
    value, sigma = empirical.magnitude_from_length(length, slip_type)
    rows[f"W&C 1994 Mw(SRL), {slip_type}"] = {"magnitude": float(value), "sigma": sigma}
    low, high = empirical.leonard_range(empirical.leonard_magnitude_from_area, area, setting)
    rows[f"Leonard 2010 Mw(A), {setting}"] = {
        "magnitude": float(empirical.leonard_magnitude_from_area(area, setting)), "range": [float(low), float(high)]}
    low, high = empirical.leonard_range(empirical.leonard_magnitude_from_length, length, setting)
    rows[f"Leonard 2010 Mw(L), {setting}"] = {
        "magnitude": float(empirical.leonard_magnitude_from_length(length, setting)), "range": [float(low), float(high)]}
    return rows


def hazard_sources(spec, dataset, stable_continental: bool = False) -> list[HazardSource]:
    """Every mapped segment as a :class:`HazardSource`: geometry from the segment table (GeoJSON's dip, rake
    and upper depth, else vertical, dextral, from the surface), faultslip's event and moment rate from the
    map's ``dataset``, and the empirical magnitudes for the same rupture.

    Parameters
    ----------
    spec : MapSpec
        The map (:func:`read_map`).
    dataset : xarray.Dataset
        The map's predictions (:func:`run_map`).
    stable_continental : bool
        Use the stable-continental scaling relations.

    Returns
    -------
    list of HazardSource
        One per segment: geometry (degrees, km), event rate (1/yr), moment rate (N m/yr) and magnitudes.
    """
    table = spec.segments
    if table is None:
        raise InputError("hazard sources need fault segments ([segments]), not a raster map")
    count = len(table.ids)
    geometry = table.geometry or {}
    dip = geometry.get("dip", np.full(count, 90.0))
    rake = geometry.get("rake", np.full(count, 180.0))
    upper = geometry.get("upper_depth", np.zeros(count))
    magnitude = dataset["moment_magnitude"].values
    recurrence = dataset["recurrence_period"].values
    moment = dataset["seismic_moment"].values
    length = dataset["segment_length"].values
    # a dipping rupture's width is down dip, H / sin(dip): its area, moment and empirical magnitudes take it
    width = (dataset["down_dip_width"] if "down_dip_width" in dataset else dataset["seismogenic_depth"]).values
    sources = []
    for i in range(count):
        slip_type = empirical.slip_type_from_rake(float(rake[i]))
        event = math.isfinite(magnitude[i]) and math.isfinite(recurrence[i]) and recurrence[i] > 0
        sources.append(HazardSource(
            id=str(table.ids[i]), name=str(table.names[i]), trace=np.asarray(table.traces[i], dtype=float),
            dip=float(dip[i]), rake=float(rake[i]), upper_depth=float(upper[i]),
            lower_depth=float(upper[i] + table.seismogenic_depth[i]), length=float(length[i]), width=float(width[i]),
            slip_type=slip_type, magnitude=float(magnitude[i]), recurrence=float(recurrence[i]),
            moment_rate=float(moment[i] / recurrence[i] * JULIAN_YEAR) if event else math.nan,
            empirical=_empirical_magnitudes(float(length[i]), float(width[i]), slip_type, stable_continental)))
    return sources


def parse_relations(text: str | None) -> list[tuple[str, float]]:
    """``"faultslip,WC1994:0.3,Leonard2010"`` -> branches with weights; unweighted ones share what is left."""
    if text is None or not text.strip():
        return [("faultslip", 1.0)]
    branches, given = [], 0.0
    for part in text.split(","):
        name, _, weight = part.strip().partition(":")
        if name not in RELATIONS:
            raise InputError(f"scaling relation must be one of {', '.join(RELATIONS)}, got {name!r}")
        if name in [b[0] for b in branches]:
            raise InputError(f"scaling relation {name!r} is given twice")
        try:
            value = float(weight) if weight else math.nan
        except ValueError:
            raise InputError(f"the weight of {name!r} must be a number, got {weight!r}") from None
        if weight and not (math.isfinite(value) and 0 < value <= 1):
            raise InputError(f"the weight of {name!r} must be in (0, 1], got {weight!r}")
        given += value if weight else 0.0
        branches.append((name, value))
    unweighted = [name for name, value in branches if math.isnan(value)]
    rest = 1.0 - given
    if (unweighted and rest <= 1e-12) or (not unweighted and abs(rest) > 1e-9):
        raise InputError(f"the scaling relations' weights must sum to 1, got {given:g} for the weighted ones")
    return [(name, rest / len(unweighted) if math.isnan(value) else value) for name, value in branches]


def source_models(sources: list[HazardSource], relations: list[tuple[str, float]], kind: str = "characteristic",
                  min_magnitude: float = mfds.MIN_MAGNITUDE, b_value: float = mfds.B_VALUE,
                  bin_width: float = mfds.BIN_WIDTH, moment_constant: float = mfds.MOMENT_CONSTANT,
                  stable_continental: bool = False) -> dict:
    """relation -> list of NRML segment dicts, each with its moment-balanced ``mfd`` (None without stick-slip).

    Parameters
    ----------
    sources : list of HazardSource
        :func:`hazard_sources`'s sources.
    relations : list of tuple
        (relation, weight) pairs.
    kind : str
        characteristic, youngs_coppersmith or truncated_gr.
    min_magnitude, b_value, bin_width, moment_constant : float
        The distribution's parameters.
    stable_continental : bool
        Stable-continental relations.

    Returns
    -------
    dict
        Relation -> list of NRML segment dicts with their ``mfd`` (rates in 1/yr).
    """
    if kind not in mfds.KINDS:
        raise InputError(f"the magnitude-frequency distribution must be one of {', '.join(mfds.KINDS)}, got {kind!r}")
    models = {}
    for relation, _ in relations:
        engine_relation = "Leonard2010_SCR" if relation == "Leonard2010" and stable_continental else RELATIONS[relation]
        segments = []
        for source in sources:
            distribution = None
            if source.has_event:
                magnitude = source.branch_magnitude(relation, stable_continental)
                try:
                    distribution = mfds.build(kind, source.moment_rate, magnitude, min_magnitude, b_value, bin_width,
                                              moment_constant)
                except InputError as exc:
                    raise InputError(f"segment {source.id} ({relation} Mw {magnitude:.2f}): {exc}") from None
            segments.append({"id": source.id, "name": source.name, "trace": source.trace, "dip": source.dip,
                             "rake": source.rake, "upper_depth": source.upper_depth,
                             "lower_depth": source.lower_depth, "mfd": distribution,
                             "scaling_relation": engine_relation})
        models[relation] = segments
    return models


def sources_json(sources: list[HazardSource], models: dict) -> list[dict]:
    """Each source with its distribution on every branch (JSON-ready)."""
    by_id = {relation: {segment["id"]: segment["mfd"] for segment in segments} for relation, segments in models.items()}
    return [source.as_dict() | {"mfd": {relation: (None if by_id[relation][source.id] is None
                                                   else by_id[relation][source.id].as_dict())
                                        for relation in models}} for source in sources]


def magnitude_table(sources: list[HazardSource]) -> str:
    """faultslip's Mw beside the empirical magnitudes for the same rupture, as a Markdown table."""
    labels = list(sources[0].empirical) if sources else []
    short = [label.split(",")[0] for label in labels]
    lines = ["| segment | moment rate (N m/yr) | faultslip Mw | " + " | ".join(short) + " |",
             "| --- | --- | --- | " + " | ".join("---" for _ in labels) + " |"]
    for source in sources:
        cells = []
        for label in labels:
            row = source.empirical[label]
            spread = (f" ± {row['sigma']:.2f}" if "sigma" in row
                      else f" ({row['range'][0]:.2f}-{row['range'][1]:.2f})")
            cells.append(f"{row['magnitude']:.2f}{spread}")
        rate = f"{source.moment_rate:.3g}" if math.isfinite(source.moment_rate) else "no stick-slip"
        magnitude = f"{source.magnitude:.2f}" if math.isfinite(source.magnitude) else ""
        lines.append(f"| {source.id} | {rate} | {magnitude} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def branch_paths(path, relations: list[tuple[str, float]], system: bool = False) -> dict:
    """Where each source model goes: ``path`` itself for one relation without a rupture set; else ``path`` holds
    the logic tree and each branch's model sits beside it as ``<stem>_<relation>.xml``."""
    path = Path(path)
    if len(relations) == 1 and not system:
        return {relations[0][0]: path}
    return {name: path.with_name(f"{path.stem}_{name.lower()}{path.suffix}") for name, _ in relations}


def system_paths(path, relations: list[tuple[str, float]]) -> dict:
    """Where a rupture set's files go beside ``path``: ``sections`` (``<stem>_sections.xml``) and, per relation,
    its ``multiFaultSource`` (``<stem>_system_<relation>.xml``)."""
    path = Path(path)
    return {"sections": path.with_name(f"{path.stem}_sections{path.suffix}"),
            **{name: path.with_name(f"{path.stem}_system_{name.lower()}{path.suffix}") for name, _ in relations}}


def system_models(spec, dataset, relations: list[tuple[str, float]], stable_continental: bool = False,
                  bin_width: float = mfds.BIN_WIDTH, allow_large: bool = False) -> dict:
    """relation -> :class:`~faultslip.studies.rupture_sets.RuptureSet` of the map's ``[rupture_set]`` rules (each
    branch's rate problem checked against the budget before it is allocated, unless ``allow_large``)."""
    if spec.rupture_rules is None:
        return {}
    return {name: rupture_sets.rupture_set(spec, dataset, spec.rupture_rules, name, stable_continental, bin_width,
                                           allow_large) for name, _ in relations}


def write_hazard_model(path, models: dict, relations: list[tuple[str, float]], name: str, systems: dict | None = None,
                       bin_width: float = mfds.BIN_WIDTH, moment_constant: float = mfds.MOMENT_CONSTANT) -> dict:
    """Write the source models (and, for several relations or a rupture set, the logic tree at ``path``);
    returns {"files": [...], "sources": count per relation}.

    With ``systems`` (:func:`system_models`), each relation has a second branch, the fault system's
    ``multiFaultSource`` (and its background) over one sections file, weighted by the rules' ``weight``
    against the per-segment sources.

    Parameters
    ----------
    path : str or path
        The file (NRML).
    models : dict
        :func:`source_models`'s models.
    relations : list of tuple
        (relation, weight).
    name : str
        The model's name.

    Returns
    -------
    dict
        ``files`` written and ``sources`` per relation.
    """
    systems = systems or {}
    share = next(iter(systems.values())).rules.weight if systems else 0.0
    paths = branch_paths(path, relations, bool(systems))
    counts, files, branches = {}, [], []
    if share < 1.0:
        for relation, weight in relations:
            counts[relation] = write_source_model(paths[relation], models[relation], f"{name} ({relation})")
            files.append(str(paths[relation]))
            branches.append((relation, paths[relation].name, weight * (1.0 - share)))
    if systems:
        where = system_paths(path, relations)
        write_sections(where["sections"], rupture_sets.nrml_sections(next(iter(systems.values()))),
                       f"{name}: fault sections")
        files.append(str(where["sections"]))
        for relation, weight in relations:
            result = systems[relation]
            counts[f"{relation}_system"] = write_multi_fault_model(
                where[relation], rupture_sets.nrml_ruptures(result), f"{name} (fault system, {relation})",
                rupture_sets.background_source(result, bin_width, moment_constant))
            files.append(str(where[relation]))
            branches.append((f"{relation}_system", f"{where[relation].name} {where['sections'].name}", weight * share))
    if len(branches) > 1 or systems:
        write_logic_tree(path, branches)
        files.insert(0, str(path))
    return {"files": files, "sources": counts}


#: renewal models a time-dependent source may take (faultslip.fault.recurrence)
RENEWAL_MODELS = ("bpt", "lognormal")


@dataclass(frozen=True)
class TimeDependentSource:
    """A segment's rupture with its probability in the investigation time, by a renewal model and by Poisson."""

    source: HazardSource
    model: str
    mean: float  # s, the renewal model's mean recurrence
    aperiodicity: float
    elapsed: float  # s since the last rupture
    investigation_time: float  # s
    probability: float  # P(a rupture within the investigation time | none for ``elapsed``), the renewal model's
    poisson_probability: float  # 1 - exp(-t / mean): the memoryless branch beside it

    def as_dict(self) -> dict:
        return {"id": self.source.id, "model": self.model, "mean": {"value": self.mean, "units": "s"},
                "aperiodicity": self.aperiodicity, "elapsed": {"value": self.elapsed, "units": "s"},
                "investigation_time": {"value": self.investigation_time, "units": "s"},
                "probability": self.probability, "poisson_probability": self.poisson_probability}


def time_dependent_sources(sources: list[HazardSource], elapsed: dict, model: str = "bpt", aperiodicity: float = 0.5,
                           investigation_time: float = 50 * JULIAN_YEAR, means: dict | None = None
                           ) -> list[TimeDependentSource]:
    """Each segment's rupture as a time-dependent source: a renewal model (BPT or lognormal) with the time since
    the last rupture gives the probability of a rupture within the investigation time,
    P = (F(e + t) - F(e)) / (1 - F(e)) (:func:`faultslip.fault.recurrence.conditional_probability`), beside the
    Poissonian 1 - exp(-t / T).

    Parameters
    ----------
    sources : list of HazardSource
        The map's sources (:func:`hazard_sources`); those without stick-slip are left out.
    elapsed : dict
        Source id -> time since its last rupture (s); every source with stick-slip needs one.
    model : str
        ``bpt`` (Brownian passage time) or ``lognormal``.
    aperiodicity : float
        The renewal model's coefficient of variation (WGCEP's BPT: 0.5).
    investigation_time : float
        The window (s).
    means : dict, optional
        Source id -> mean recurrence (s), e.g. a catalogue's renewal fit; faultslip's predicted recurrence
        otherwise.

    Returns
    -------
    list of TimeDependentSource
        One per source with stick-slip.
    """
    if model not in RENEWAL_MODELS:
        raise InputError(f"a time-dependent source's renewal model must be one of {', '.join(RENEWAL_MODELS)}, "
                         f"got {model!r}")
    if isinstance(aperiodicity, bool) or not (isinstance(aperiodicity, (int, float)) and 0 < aperiodicity <= 5):
        raise InputError(f"the aperiodicity (coefficient of variation) must lie above 0 and at most 5, got "
                         f"{aperiodicity!r}")
    if not (math.isfinite(investigation_time) and investigation_time > 0):
        raise InputError(f"the investigation time must be positive, got {investigation_time!r} s")
    means = means or {}
    known = {source.id for source in sources}
    strays = sorted((set(elapsed) | set(means)) - known)
    if strays:
        raise InputError(f"no segment {strays[0]!r} in the map (its segments: {', '.join(sorted(known))})")
    made = []
    for source in sources:
        if not source.has_event:
            continue
        if source.id not in elapsed:
            raise InputError(f"segment {source.id} has no time since its last rupture: give one for every segment "
                             "with stick-slip")
        since = float(elapsed[source.id])
        if not (math.isfinite(since) and since >= 0):
            raise InputError(f"segment {source.id}: the time since its last rupture must be zero or positive, got "
                             f"{since!r} s")
        mean = float(means.get(source.id, source.recurrence))
        if not (math.isfinite(mean) and mean > 0):
            raise InputError(f"segment {source.id}: the mean recurrence must be positive, got {mean!r} s")
        made.append(TimeDependentSource(
            source, model, mean, float(aperiodicity), since, float(investigation_time),
            conditional_probability(model, mean, float(aperiodicity), since, float(investigation_time)),
            -math.expm1(-investigation_time / mean)))
    if not made:
        raise InputError("no segment has stick-slip (a magnitude and a recurrence): nothing is time-dependent")
    return made


def parse_renewal(text: str) -> tuple[str, float]:
    """``"bpt:0.5"`` or ``"lognormal:0.6"``: a renewal model and its aperiodicity (default 0.5)."""
    name, _, value = str(text).strip().partition(":")
    if name not in RENEWAL_MODELS:
        raise InputError(f"--renewal is MODEL:APERIODICITY with MODEL one of {', '.join(RENEWAL_MODELS)}, got {text!r}")
    try:
        aperiodicity = float(value) if value.strip() else 0.5
    except ValueError:
        raise InputError(f"--renewal {text!r}: the aperiodicity after ':' must be a number") from None
    return name, aperiodicity


def parse_last_ruptures(text: str) -> dict:
    """``"SA-PKF=2004.74; SA-CAR=1857.02"``: each segment's last rupture as a decimal year."""
    years = {}
    for part in (text or "").split(";"):
        if not part.strip():
            continue
        key, sep, value = part.partition("=")
        try:
            year = float(value)
        except ValueError:
            year = math.nan
        if not sep or not key.strip() or not math.isfinite(year):
            raise InputError(f"--last-ruptures takes 'SEGMENT=YEAR' pairs separated by ';' (a decimal year), got "
                             f"{part.strip()!r}")
        if key.strip() in years:
            raise InputError(f"--last-ruptures names segment {key.strip()} twice")
        years[key.strip()] = year
    if not years:
        raise InputError("--last-ruptures needs at least one 'SEGMENT=YEAR'")
    return years


def write_time_dependent_model(path, sources: list[TimeDependentSource], name: str, renewal_weight: float = 0.5
                               ) -> dict:
    """The time-dependent sources and their Poissonian twins as two source models under one logic tree at
    ``path`` (``<stem>_poisson.xml`` and ``<stem>_<model>.xml`` beside it): the same whole-segment ruptures,
    non-parametric, with the renewal model's probability on one branch and 1 - exp(-t / T) on the other.

    Parameters
    ----------
    path : str or path
        The logic tree (NRML).
    sources : list of TimeDependentSource
        :func:`time_dependent_sources`'s sources (one model and investigation time).
    name : str
        The model's name.
    renewal_weight : float
        The renewal branch's weight (the Poissonian branch has the rest).

    Returns
    -------
    dict
        ``files`` written, and each branch's ``probabilities`` by source id.
    """
    if not sources:
        raise InputError("no time-dependent source to write")
    if not 0 < renewal_weight < 1:
        raise InputError(f"the renewal branch's weight must lie between 0 and 1, got {renewal_weight!r}")
    models, spans = {s.model for s in sources}, {s.investigation_time for s in sources}
    if len(models) > 1 or len(spans) > 1:
        raise InputError("time-dependent sources written together share one renewal model and investigation time")
    model, years = models.pop(), spans.pop() / JULIAN_YEAR
    path = Path(path)
    branches = {"poisson": path.with_name(f"{path.stem}_poisson{path.suffix}"),
                model: path.with_name(f"{path.stem}_{model}{path.suffix}")}
    probabilities = {"poisson": {s.source.id: s.poisson_probability for s in sources},
                     model: {s.source.id: s.probability for s in sources}}
    for branch, file in branches.items():
        ruptures = [{"id": s.source.id, "name": s.source.name, "trace": s.source.trace, "dip": s.source.dip,
                     "rake": s.source.rake, "upper_depth": s.source.upper_depth, "lower_depth": s.source.lower_depth,
                     "magnitude": s.source.magnitude, "probability": probabilities[branch][s.source.id]}
                    for s in sources]
        write_nonparametric_model(file, ruptures, f"{name} ({branch})", years)
    write_logic_tree(path, [("poisson", branches["poisson"].name, 1 - renewal_weight),
                            (model, branches[model].name, renewal_weight)])
    return {"files": [str(path)] + [str(p) for p in branches.values()], "probabilities": probabilities}


def parse_sites(text: str) -> list[tuple[float, float]]:
    """``"-122.42 37.77; -120.5 35.9"``: longitude and latitude in degrees, pairs separated by semicolons."""
    sites = []
    for part in (text or "").split(";"):
        if not part.strip():
            continue
        values = part.replace(",", " ").split()
        try:
            lon, lat = (float(v) for v in values)
        except ValueError:
            raise InputError(f"a site is 'longitude latitude' in degrees, got {part.strip()!r}") from None
        if not (-180 <= lon <= 180 and -90 <= lat <= 90):
            raise InputError(f"site {part.strip()!r} is not a longitude from -180 to 180 and a latitude from -90 to 90")
        sites.append((lon, lat))
    if not sites:
        raise InputError("give at least one site as 'longitude latitude' (degrees), sites separated by ';'")
    return sites


def write_engine_job(path, source_model: str, is_logic_tree: bool, sites: list[tuple[float, float]],
                     gmpe: str = DEFAULT_GMPE, levels=DEFAULT_LEVELS, investigation_time: float = 50.0,
                     bin_width: float = mfds.BIN_WIDTH, vs30: float = 760.0, description: str = "faultslip sources",
                     tectonic_region: str = "Active Shallow Crust", infer_occur_rates: bool = False) -> list[str]:
    """An OpenQuake classical-PSHA job (``oq engine --run FILE.ini``): the sites, one GMPE, PGA at ``levels``
    (g), Poissonian over ``investigation_time`` years, ``width_of_mfd_bin`` = the distributions' bin width.
    A single source model gets a one-branch logic tree beside the job. Returns the files written.

    Parameters
    ----------
    path : str or path
        The job file (.ini).
    source_model : str
        The source model or logic tree file.
    is_logic_tree : bool
        Whether it is a logic tree.
    sites : list of tuple
        (lon, lat) in degrees.
    gmpe : str
        The ground-motion model.
    levels : tuple
        PGA levels (g).
    investigation_time : float
        Years.
    bin_width : float
        The MFD bin width.
    vs30 : float
        m/s.
    description : str
        The job's description.
    tectonic_region : str
        The region type.
    infer_occur_rates : bool
        Read the occurrence probabilities of multi-fault ruptures as one-year Poisson rates (a fault system's
        ``multiFaultSource``, :func:`faultslip.io.nrml.write_multi_fault_model`).

    Returns
    -------
    list of str
        The files written.
    """
    path = Path(path)
    folder = path.parent
    written = []
    if not is_logic_tree:
        tree = path.with_name(f"{path.stem}_source_model_logic_tree.xml")
        write_logic_tree(tree, [("faultslip", os.path.relpath(source_model, folder), 1.0)])
        source_model, written = str(tree), [str(tree)]
    gmpe_tree = path.with_name(f"{path.stem}_gmpe_logic_tree.xml")
    write_text_atomic(gmpe_tree, f"""<?xml version='1.0' encoding='utf-8'?>
<nrml xmlns="http://openquake.org/xmlns/nrml/0.5">
  <logicTree logicTreeID="gmpe">
    <logicTreeBranchSet uncertaintyType="gmpeModel" branchSetID="gmpe" applyToTectonicRegionType="{tectonic_region}">
      <logicTreeBranch branchID="{gmpe}">
        <uncertaintyModel>{gmpe}</uncertaintyModel>
        <uncertaintyWeight>1.0</uncertaintyWeight>
      </logicTreeBranch>
    </logicTreeBranchSet>
  </logicTree>
</nrml>
""")
    site_text = ", ".join(f"{lon:.6f} {lat:.6f}" for lon, lat in sites)
    level_text = ", ".join(f"{level:g}" for level in levels)
    write_text_atomic(path, f"""# written by faultslip: a classical PSHA over faultslip's fault sources
[general]
description = {description}
calculation_mode = classical
random_seed = 23

[geometry]
sites = {site_text}

[logic_tree]
number_of_logic_tree_samples = 0

[erf]
rupture_mesh_spacing = 2.0
width_of_mfd_bin = {bin_width:g}
area_source_discretization = 10.0

[site_params]
reference_vs30_type = measured
reference_vs30_value = {vs30:g}
reference_depth_to_1pt0km_per_sec = 40.0
reference_depth_to_2pt5km_per_sec = 1.0

[calculation]
source_model_logic_tree_file = {os.path.relpath(source_model, folder)}
gsim_logic_tree_file = {gmpe_tree.name}
investigation_time = {investigation_time:g}
intensity_measure_types_and_levels = {{"PGA": [{level_text}]}}
truncation_level = 3
maximum_distance = 300.0
{"infer_occur_rates = true" if infer_occur_rates else ""}

[output]
export_dir = .
mean = true
""")
    return written + [str(gmpe_tree), str(path)]
