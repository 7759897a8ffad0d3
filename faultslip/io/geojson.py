"""Fault traces from GeoJSON in the GEM Global Active Faults schema (Styron & Pagani 2020, Earthquake Spectra
36(1_suppl), 160-180).

Each feature is a LineString, or a MultiLineString whose parts become separate sections (a
part's id is the feature's with ``:1``, ``:2``, ... appended; joining them would put a jump
into the trace and lengthen it). Two features with one ``catalog_id`` are refused: a hazard
engine needs one id per source. The GAF
schema gives a measured value with its range as the text ``"(preferred,min,max)"`` (a missing part
is left empty, e.g. ``"(12,,)"``); plain numbers are accepted too. Read here:

===================  ===================================================  ============
property             meaning                                              unit
===================  ===================================================  ============
name                 the fault's name                                     -
catalog_id           its identifier (else the feature's index)            -
slip_type            Dextral, Sinistral, Reverse, Normal, ... (GAF terms)  -
net_slip_rate        slip rate (preferred, min, max)                      mm/yr
strike_slip_rate     used where net_slip_rate is missing                   mm/yr
average_dip          dip (preferred, min, max)                            degrees
average_rake         rake (preferred, min, max)                           degrees
upper_seis_depth     top of the seismogenic zone                          km
lower_seis_depth     bottom of the seismogenic zone                       km
===================  ===================================================  ============

A feature without a slip rate is refused with its name. Missing dip, rake or depths take the
documented defaults of :func:`read_fault_geojson`'s caller (the map's base scene), and the notes say
which features used them.
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.io.geo import trace_from_vertices
from faultslip.units import JULIAN_YEAR

MM_PER_YEAR = 1e-3 / JULIAN_YEAR
#: GAF slip types (the GEM Global Active Faults vocabulary, and the spellings its contributing datasets
#: use) and the rake that represents each, Aki & Richards convention. Terms are compared after
#: :func:`slip_type_key` (case, and ``-``, ``_`` or space between words, do not matter). Where a
#: term names an oblique slip without its sense, the sense is dextral (rake 180 -+ 45); where it
#: names a strike-slip without its sense, dextral (180).
SLIP_TYPE_RAKE = {
    "Dextral": 180.0, "Sinistral": 0.0, "Reverse": 90.0, "Normal": -90.0, "Thrust": 90.0,
    "Dextral-Normal": -135.0, "Dextral-Reverse": 135.0, "Sinistral-Normal": -45.0, "Sinistral-Reverse": 45.0,
    "Normal-Dextral": -135.0, "Normal-Sinistral": -45.0, "Reverse-Dextral": 135.0, "Reverse-Sinistral": 45.0,
    "Thrust-Dextral": 135.0, "Thrust-Sinistral": 45.0, "Dextral-Thrust": 135.0, "Sinistral-Thrust": 45.0,
    "Blind-Thrust": 90.0, "Subduction-Thrust": 90.0, "Anticline": 90.0, "Syncline": 90.0,
    "Spreading-Ridge": -90.0, "Strike-Slip": 180.0, "Dextral-Transform": 180.0, "Sinistral-Transform": 0.0,
    "Transform": 180.0, "Dextral-Oblique": 180.0, "Sinistral-Oblique": 0.0,
    "Normal-Strike-Slip": -135.0, "Reverse-Strike-Slip": 135.0, "Strike-Slip-Normal": -135.0,
    "Strike-Slip-Reverse": 135.0, "Normal-Oblique": -135.0, "Reverse-Oblique": 135.0,
}


def slip_type_key(term: str) -> str:
    """A GAF slip type compared without case or separators: ``"Blind Thrust"`` -> ``"blind-thrust"``."""
    return "-".join(term.replace("_", " ").replace("-", " ").lower().split())


_RAKE_BY_KEY = {slip_type_key(term): rake for term, rake in SLIP_TYPE_RAKE.items()}


def slip_type_rake(term: str) -> float | None:
    """The rake of a GAF slip type, or None for a term outside the vocabulary."""
    return _RAKE_BY_KEY.get(slip_type_key(term))


@dataclass
class GeoJSONFaults:
    ids: list
    names: list
    traces: list  # (n, 2) arrays of (lon, lat)
    slip_rate: np.ndarray  # m/s, preferred
    slip_rate_range: np.ndarray  # (n, 2) m/s, NaN where not given
    slip_type: list
    dip: np.ndarray  # degrees
    rake: np.ndarray  # degrees
    upper_depth: np.ndarray  # m
    lower_depth: np.ndarray  # m
    notes: list = field(default_factory=list)


def _number(value, where: str) -> float:
    """A JSON number as a finite float (JSON integers can exceed any float)."""
    try:
        number = float(value)
    except OverflowError:
        raise InputError(f"{where}: the number {str(value)[:20]}... is too large") from None
    if not math.isfinite(number):
        raise InputError(f"{where}: {value!r} is not finite")
    return number


def parse_tuple(value, where: str) -> tuple:
    """GAF "(preferred,min,max)" text, or a number, as three floats (NaN where empty)."""
    if value is None:
        return (math.nan, math.nan, math.nan)
    if isinstance(value, bool):
        raise InputError(f"{where}: {value!r} is not a number or a '(preferred,min,max)' text")
    if isinstance(value, (int, float)):
        return (_number(value, where), math.nan, math.nan)
    if not isinstance(value, str):
        raise InputError(f"{where}: {value!r} is not a number or a '(preferred,min,max)' text")
    text = value.strip()
    if text.startswith("(") and text.endswith(")"):
        text = text[1:-1]
    parts = [part.strip() for part in text.split(",")] if text else []
    if len(parts) > 3:
        raise InputError(f"{where}: {value!r} has more than three parts (preferred,min,max)")
    numbers = []
    for part in parts + [""] * (3 - len(parts)):
        try:
            number = float(part) if part else math.nan
        except ValueError:
            raise InputError(f"{where}: {value!r} is not '(preferred,min,max)' numbers") from None
        if math.isinf(number):
            raise InputError(f"{where}: {value!r} is infinite")
        numbers.append(number)
    return tuple(numbers)


def _lines(geometry, where: str) -> list:
    """The traces of a LineString (one) or a MultiLineString (one per part)."""
    if not isinstance(geometry, dict):
        raise InputError(f"{where} has no geometry")
    kind, coordinates = geometry.get("type"), geometry.get("coordinates")
    if kind == "LineString":
        parts = [coordinates]
    elif kind == "MultiLineString" and isinstance(coordinates, list):
        parts = coordinates
    else:
        raise InputError(f"{where}: the geometry must be a LineString or MultiLineString, got {kind!r}")
    if not parts:
        raise InputError(f"{where}: the geometry has no coordinates")
    traces = []
    for number, part in enumerate(parts, start=1):
        if not isinstance(part, list):
            raise InputError(f"{where}: coordinates must be lists of [lon, lat]")
        vertices = []
        for point in part:
            if not (isinstance(point, list) and len(point) in (2, 3)
                    and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in point)):
                raise InputError(f"{where}: a vertex must be [lon, lat] numbers, got {str(point)[:40]}")
            vertices.append((_number(point[0], where), _number(point[1], where)))
        traces.append(trace_from_vertices(vertices, where if len(parts) == 1 else f"{where}, part {number}"))
    return traces


def read_fault_geojson(path) -> GeoJSONFaults:
    """Fault features of a GAF-schema GeoJSON FeatureCollection; one sentence for anything malformed."""
    path = Path(path)
    label = f"fault file {path.name}"
    data = gate.read_bytes(path, "fault file", "geojson")
    with gate.decoding(path, "fault file", "GeoJSON"):
        document = json.loads(data)
    if not isinstance(document, dict) or document.get("type") != "FeatureCollection":
        raise InputError(f"{label} must be a GeoJSON FeatureCollection")
    features = document.get("features")
    if not isinstance(features, list) or not features:
        raise InputError(f"{label} has no features")
    out = {key: [] for key in ("ids", "names", "traces", "slip_rate", "slip_rate_range", "slip_type", "dip", "rake",
                               "upper_depth", "lower_depth")}
    defaulted = {"dip": [], "rake": [], "depths": []}
    unknown_types = []
    first_with_id = {}
    for index, feature in enumerate(features):
        if not isinstance(feature, dict) or feature.get("type") != "Feature":
            raise InputError(f"{label}: item {index} is not a GeoJSON Feature")
        properties = feature.get("properties") or {}
        if not isinstance(properties, dict):
            raise InputError(f"{label}: feature {index} has properties that are not an object")
        name = str(properties.get("name") or f"feature {index}")
        where = f"{label}, {name!r}"
        identifier = str(properties.get("catalog_id") or index)
        if identifier in first_with_id:
            raise InputError(f"{label}: features {first_with_id[identifier]!r} and {name!r} share catalog_id "
                             f"{identifier!r}; each source needs its own id")
        first_with_id[identifier] = name
        traces = _lines(feature.get("geometry"), where)
        rate = parse_tuple(properties.get("net_slip_rate"), f"{where}, net_slip_rate")
        if math.isnan(rate[0]):
            rate = parse_tuple(properties.get("strike_slip_rate"), f"{where}, strike_slip_rate")
        if math.isnan(rate[0]) or rate[0] <= 0:
            raise InputError(f"{where} has no positive net_slip_rate (or strike_slip_rate) in mm/yr; a map needs each "
                             "fault's slip rate")
        slip_type = properties.get("slip_type")
        if slip_type is not None and not isinstance(slip_type, str):
            raise InputError(f"{where}: slip_type must be a GAF term such as 'Dextral', got {str(slip_type)[:40]}")
        slip_type = slip_type.strip() if slip_type else None
        type_rake = slip_type_rake(slip_type) if slip_type else None
        if slip_type and type_rake is None:
            unknown_types.append(f"{name!r} ({slip_type[:40]!r})")
            continue
        dip = parse_tuple(properties.get("average_dip"), f"{where}, average_dip")[0]
        rake = parse_tuple(properties.get("average_rake"), f"{where}, average_rake")[0]
        upper = parse_tuple(properties.get("upper_seis_depth"), f"{where}, upper_seis_depth")[0]
        lower = parse_tuple(properties.get("lower_seis_depth"), f"{where}, lower_seis_depth")[0]
        if math.isnan(dip):
            defaulted["dip"].append(name)
        elif not 0 < dip <= 90:
            raise InputError(f"{where}: average_dip {dip:g} must lie in (0, 90] degrees")
        if math.isnan(rake):
            rake = math.nan if type_rake is None else type_rake
            if math.isnan(rake):
                defaulted["rake"].append(name)
        elif not -180 <= rake <= 180:
            raise InputError(f"{where}: average_rake {rake:g} must lie in [-180, 180] degrees")
        if math.isnan(upper) or math.isnan(lower):
            defaulted["depths"].append(name)
        elif not 0 <= upper < lower <= 100:
            raise InputError(f"{where}: seismogenic depths must satisfy 0 <= upper < lower <= 100 km, got {upper:g} "
                             f"and {lower:g}")
        for number, trace in enumerate(traces, start=1):
            several = len(traces) > 1
            out["ids"].append(f"{identifier}:{number}" if several else identifier)
            out["names"].append(f"{name} (part {number} of {len(traces)})" if several else name)
            out["traces"].append(trace)
            out["slip_rate"].append(rate[0] * MM_PER_YEAR)
            out["slip_rate_range"].append((rate[1] * MM_PER_YEAR, rate[2] * MM_PER_YEAR))
            out["slip_type"].append(slip_type or "")
            out["dip"].append(dip)
            out["rake"].append(rake)
            out["upper_depth"].append(upper * 1e3)
            out["lower_depth"].append(lower * 1e3)
    if unknown_types:
        warnings.warn(f"{label}: {len(unknown_types)} feature(s) skipped, their slip_type outside the GAF vocabulary: "
                      f"{', '.join(unknown_types[:3])}{', ...' if len(unknown_types) > 3 else ''}", stacklevel=2)
    if not out["ids"]:
        raise InputError(f"{label}: no feature is left to map (every slip_type is outside the GAF vocabulary)")
    seen = {}
    for name, trace in zip(out["names"], out["traces"]):  # one fault twice would count its moment twice
        for key in (tuple(np.round(trace, 9).ravel()), tuple(np.round(trace[::-1], 9).ravel())):
            if key in seen:
                raise InputError(f"{label}: {seen[key]!r} and {name!r} have the same trace; a fault is mapped once")
        seen[tuple(np.round(trace, 9).ravel())] = name
    notes = [f"{label}: {len(names)} feature(s) without {what} take the default ({', '.join(names[:3])}"
             f"{', ...' if len(names) > 3 else ''})" for what, names in defaulted.items() if names]
    return GeoJSONFaults(out["ids"], out["names"], out["traces"], np.array(out["slip_rate"]),
                         np.array(out["slip_rate_range"], dtype=float).reshape(-1, 2), out["slip_type"],
                         np.array(out["dip"]), np.array(out["rake"]), np.array(out["upper_depth"]),
                         np.array(out["lower_depth"]), notes)
