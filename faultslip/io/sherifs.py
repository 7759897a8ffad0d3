"""SHERIFS's input files (Chartier, Scotti & Lyon-Caen 2019, Seismol. Res. Lett. 90(4), 1678-1688): a fault
system's traces, its faults' properties, and its rupture sets.

``Faults_geometry.txt`` (tab- or space-separated, one header line)::

    model_name  fault_name  longitude  latitude  type        # one row per trace vertex, in order

``Faults_properties.txt``::

    model_name  fault_name  dip  oriented  mechanism  upper_sismo_depth  lower_sismo_depth
    slip_rate_min  slip_rate_moy  slip_rate_max  [Domain  shear_modulus]

with dip in degrees, depths in km, slip rates in mm/yr and the shear modulus in GPa; ``mechanism`` is N (normal),
R or T (reverse) or S (strike-slip). ``ruptures.txt`` lists rupture sets: a line ``set NAME`` opens one, each
following line names the faults of one multi-fault rupture, ``#`` starts a comment.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.io.geo import trace_from_vertices
from faultslip.io.geojson import MM_PER_YEAR, GeoJSONFaults

#: SHERIFS's mechanisms, as GAF slip types (faultslip.io.geojson.SLIP_TYPE_RAKE gives their rakes).
MECHANISMS = {"N": ("Normal", -90.0), "R": ("Reverse", 90.0), "T": ("Reverse", 90.0), "S": ("Strike-Slip", 180.0)}
GEOMETRY_COLUMNS = ("model_name", "fault_name", "longitude", "latitude")
PROPERTY_COLUMNS = ("model_name", "fault_name", "dip", "oriented", "mechanism", "upper_sismo_depth",
                    "lower_sismo_depth", "slip_rate_min", "slip_rate_moy", "slip_rate_max")
#: More faults or rupture lines than this is refused before anything is built from them.
MAX_FAULTS, MAX_RUPTURES = 10_000, 100_000


@dataclass
class SherifsFaults(GeoJSONFaults):
    """A SHERIFS model's faults, as :func:`faultslip.io.geojson.read_fault_geojson` gives GeoJSON's (SI), with
    each fault's ``shear_modulus`` (Pa; NaN where the file gives none) and the ``model`` read."""

    shear_modulus: np.ndarray = field(default_factory=lambda: np.zeros(0))
    model: str = ""


def _rows(path: Path, label: str, columns: tuple) -> tuple[list, list]:
    """(header, rows) of a whitespace-separated table whose header holds ``columns``; one sentence otherwise."""
    data = gate.read_bytes(path, label, "table")
    with gate.decoding(path, label, "text"):
        text = data.decode("utf-8-sig")
    lines = [line.split() for line in text.splitlines() if line.strip() and not line.lstrip().startswith("#")]
    if not lines:
        raise InputError(f"{label} {path.name} is empty")
    header = lines[0]
    missing = [name for name in columns if name not in header]
    if missing:
        raise InputError(f"{label} {path.name} lacks the column{'s' if len(missing) > 1 else ''} "
                         f"{', '.join(missing)} in its header (SHERIFS's: {' '.join(columns)})")
    for number, row in enumerate(lines[1:], start=2):
        if len(row) < len(header):
            raise InputError(f"{label} {path.name}, row {number}: {len(row)} fields for the header's {len(header)}")
    return header, lines[1:]


def _number(text: str, what: str, low: float, high: float) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{what} must be a number, got {text!r}") from None
    if not (math.isfinite(value) and low <= value <= high):
        raise InputError(f"{what} must lie from {low:g} to {high:g}, got {text!r}")
    return value


def read_sherifs_faults(geometry, properties, model: str | None = None) -> SherifsFaults:
    """The faults of one model of SHERIFS's ``Faults_geometry.txt`` and ``Faults_properties.txt``.

    Parameters
    ----------
    geometry, properties : str or path
        The two files.
    model : str, optional
        The ``model_name`` to read (the files' only one where not given).

    Returns
    -------
    SherifsFaults
        Traces (lon, lat degrees), the mean slip rate (m/s) and its range, slip type, dip and rake (degrees),
        upper and lower seismogenic depths (m) and shear modulus (Pa), in the properties file's order.
    """
    geometry, properties = Path(geometry), Path(properties)
    g_header, g_rows = _rows(geometry, "SHERIFS geometry file", GEOMETRY_COLUMNS)
    p_header, p_rows = _rows(properties, "SHERIFS properties file", PROPERTY_COLUMNS)
    models = list(dict.fromkeys(row[p_header.index("model_name")] for row in p_rows))
    if model is None:
        if len(models) != 1:
            raise InputError(f"{properties.name} holds the models {', '.join(models)}: name one ([segments] model)")
        model = models[0]
    elif model not in models:
        raise InputError(f"{properties.name} has no model {model!r} (it has {', '.join(models) or 'none'})")
    column = {name: g_header.index(name) for name in GEOMETRY_COLUMNS}
    vertices: dict[str, list] = {}
    for number, row in enumerate(g_rows, start=2):
        if row[column["model_name"]] != model:
            continue
        where = f"{geometry.name}, row {number}"
        vertices.setdefault(row[column["fault_name"]], []).append(
            (_number(row[column["longitude"]], f"{where}: longitude", -180.0, 360.0),
             _number(row[column["latitude"]], f"{where}: latitude", -90.0, 90.0)))
        if len(vertices) > MAX_FAULTS:
            raise InputError(f"{geometry.name} has more than {MAX_FAULTS:,} faults")
    index = {name: p_header.index(name) for name in PROPERTY_COLUMNS}
    modulus_column = p_header.index("shear_modulus") if "shear_modulus" in p_header else None
    out = {key: [] for key in ("ids", "traces", "slip_rate", "slip_rate_range", "slip_type", "dip", "rake",
                               "upper_depth", "lower_depth", "shear_modulus")}
    for number, row in enumerate(p_rows, start=2):
        if row[index["model_name"]] != model:
            continue
        name = row[index["fault_name"]]
        where = f"{properties.name}, fault {name}"
        if name in out["ids"]:
            raise InputError(f"{where}: listed twice")
        if name not in vertices:
            raise InputError(f"{where}: no trace in {geometry.name} for model {model}")
        if len(vertices[name]) < 2:
            raise InputError(f"{geometry.name}: fault {name} has {len(vertices[name])} vertex; a trace needs two")
        mechanism = row[index["mechanism"]].upper()
        if mechanism not in MECHANISMS:
            raise InputError(f"{where}: mechanism must be one of {', '.join(MECHANISMS)}, got {mechanism!r}")
        dip = _number(row[index["dip"]], f"{where}: dip (degrees)", 1.0, 90.0)
        upper = _number(row[index["upper_sismo_depth"]], f"{where}: upper_sismo_depth (km)", 0.0, 100.0)
        lower = _number(row[index["lower_sismo_depth"]], f"{where}: lower_sismo_depth (km)", 0.0, 100.0)
        if not lower > upper:
            raise InputError(f"{where}: lower_sismo_depth ({lower:g} km) must lie below upper_sismo_depth ({upper:g} km)")
        rates = [_number(row[index[key]], f"{where}: {key} (mm/yr)", 0.0, 1000.0)
                 for key in ("slip_rate_min", "slip_rate_moy", "slip_rate_max")]
        if not rates[0] <= rates[1] <= rates[2]:
            raise InputError(f"{where}: slip rates must run min <= moy <= max, got {rates[0]:g}, {rates[1]:g}, "
                             f"{rates[2]:g} mm/yr")
        modulus = (_number(row[modulus_column], f"{where}: shear_modulus (GPa)", 1.0, 100.0) * 1e9
                   if modulus_column is not None else math.nan)
        trace = trace_from_vertices(np.array(vertices[name], float), f"{geometry.name}: fault {name}")
        slip_type, rake = MECHANISMS[mechanism]
        for key, value in (("ids", name), ("traces", trace), ("slip_rate", rates[1] * MM_PER_YEAR),
                           ("slip_rate_range", (rates[0] * MM_PER_YEAR, rates[2] * MM_PER_YEAR)),
                           ("slip_type", slip_type), ("dip", dip), ("rake", rake), ("upper_depth", upper * 1e3),
                           ("lower_depth", lower * 1e3), ("shear_modulus", modulus)):
            out[key].append(value)
    if not out["ids"]:
        raise InputError(f"{properties.name} has no fault of model {model}")
    unlisted = sorted(set(vertices) - set(out["ids"]))
    notes = [f"{geometry.name}: traces of {', '.join(unlisted)} have no properties and are left out"] if unlisted else []
    array = lambda key: np.array(out[key], float)  # noqa: E731
    return SherifsFaults(ids=out["ids"], names=list(out["ids"]), traces=out["traces"], slip_rate=array("slip_rate"),
                         slip_rate_range=np.array(out["slip_rate_range"], float), slip_type=out["slip_type"],
                         dip=array("dip"), rake=array("rake"), upper_depth=array("upper_depth"),
                         lower_depth=array("lower_depth"), notes=notes, shear_modulus=array("shear_modulus"),
                         model=model)


def read_sherifs_ruptures(path) -> dict[str, list[tuple[str, ...]]]:
    """SHERIFS's rupture sets: set name -> its multi-fault ruptures, each a tuple of fault names in order.

    Parameters
    ----------
    path : str or path
        A ``ruptures.txt``.

    Returns
    -------
    dict
        Every set, in the file's order (a set may be empty: single-fault ruptures only).
    """
    path = Path(path)
    data = gate.read_bytes(path, "SHERIFS rupture file", "config")
    with gate.decoding(path, "SHERIFS rupture file", "text"):
        text = data.decode("utf-8-sig")
    sets: dict[str, list] = {}
    current = None
    count = 0
    for number, line in enumerate(text.splitlines(), start=1):
        words = line.split("#", 1)[0].split()
        if not words:
            continue
        if words[0] == "set":
            if len(words) != 2:
                raise InputError(f"{path.name}, line {number}: a set line is 'set NAME', got {line.strip()!r}")
            if words[1] in sets:
                raise InputError(f"{path.name}, line {number}: set {words[1]!r} appears twice")
            current = sets[words[1]] = []
            continue
        if current is None:
            raise InputError(f"{path.name}, line {number}: a rupture before any 'set NAME' line")
        if len(words) < 2 or len(set(words)) != len(words):
            raise InputError(f"{path.name}, line {number}: a multi-fault rupture names two or more different faults, "
                             f"got {line.strip()!r}")
        count += 1
        if count > MAX_RUPTURES:
            raise InputError(f"{path.name} lists more than {MAX_RUPTURES:,} ruptures")
        current.append(tuple(words))
    if not sets:
        raise InputError(f"{path.name} has no 'set NAME' line: no rupture set")
    return sets
