"""Regional parameter maps: fault-segment tables and lon/lat rasters (``faultslip map``).

Two input forms:

* a **segment table** (CSV): each fault segment's trace as lon/lat vertices, its slip rate,
  lithology, seismogenic depth and elastic-zone width, and optionally observed slip per event
  and recurrence with their sources. Each segment is predicted with the study kernel along a
  ``segment`` dimension (slip, recurrence, Mw for its geodetic length); a lon/lat raster then
  carries each cell's nearest-segment prediction;
* a **raster** (netCDF or CSV) of inputs on longitude and latitude: a lithology category, or
  shear modulus, zone width, slip rate and normal stress directly; every cell is predicted.

Distances are geodetic through ``obspy.geodetics``: segment lengths on the WGS84 ellipsoid
(``gps2dist_azimuth``), nearest-segment distances as great circles on the sphere
(``locations2degrees``, vectorised) to traces densified every ~1 km.

Map files are TOML::

    [map]
    name = "San Andreas fault system"
    base = "san_andreas_1906.toml"     # parameters a segment or cell does not give
    [segments]
    file = "../data/san_andreas_segments.csv"
    [grid]
    lon = { linspace = [-125.0, -114.5, 106] }   # degrees east
    lat = { linspace = [32.5, 40.5, 81] }        # degrees north
    max_distance = "60 km"                       # cells farther than this from every segment stay empty
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field, replace
from pathlib import Path

from faultslip.constants import JULIAN_YEAR
import numpy as np

from faultslip.io.geo import _check_lon_lat, nearest_segment, parse_trace, trace_length  # noqa: F401 (re-exported)
from faultslip.io.geojson import read_fault_geojson
from faultslip.io.sherifs import read_sherifs_faults, read_sherifs_ruptures
from faultslip.errors import InputError, did_you_mean
from faultslip.io import budget
from faultslip.io.resources import bundled_dir, check_toml_kind, parse_toml, read_unit_csv
from faultslip.units import si_unit, to_si
from faultslip import __version__, ranges
from faultslip.fault.scene import Scene, read_slider_scene, parse_scene
from faultslip.io.resources import read_text_file, resolve_path
from faultslip.friction.materials import resolve_material
from faultslip.io.resources import open_netcdf
from faultslip.fault.one_slider_error import range_within
from faultslip.fault.rate_state_cells import (check_cycle_method, estimated_seconds, evolution_codes, friction_ratio,
                                              rate_state_cells)
from faultslip.fault.spring_slider_cells import SEED_METHODS, evaluate, normal_stress_input, rate_state_inputs, rate_state_outputs
from faultslip.studies.grid import Study, as_dataset
from faultslip.studies.rupture_sets import RULE_KEYS, parse_rules, rupture_set_estimate
from datetime import datetime, timezone

SEGMENT_COLUMNS = {  # name -> (unit kind, required)
    "segment": (None, True),
    "trace": ("degree", True),
    "slip_rate": ("speed", True),
    "lithology": (None, True),
    "seismogenic_depth": ("length", True),
    "zone_width": ("length", True),
    "name": (None, False),
    "observed_slip": ("length", False),
    "observed_slip_event": (None, False),
    "observed_recurrence": ("time", False),
    "dip": ("degree", False),  # degrees, 0 to 90 (default 90: vertical)
    "upper_depth": ("length", False),  # the seismogenic zone's top (default 0: the surface); H below it
    "rake": ("degree", False),  # degrees, Aki & Richards (default 180: dextral)
}
RASTER_VARIABLES = {
    "lithology": None, "shear_modulus": "pressure", "zone_width": "length", "slip_rate": "speed",
    "normal_stress": "pressure", "shear_stress": "pressure",
}
MAP_SCHEMA = {"map": {"name", "base", "description", "cycles", "method"},
              "segments": {"file", "format", "properties", "model", "faults"}, "raster": {"file"},
              "grid": {"lon", "lat", "max_distance"}, "rupture_set": set(RULE_KEYS)}


@dataclass
class MapSpec:
    name: str
    scene: object
    segments: object = None  # SegmentTable
    raster: object = None  # xarray.Dataset of inputs on (lat, lon)
    lon: np.ndarray | None = None
    lat: np.ndarray | None = None
    max_distance: float = 60e3
    text: str = ""
    description: str = ""
    source_files: list = field(default_factory=list)
    notes: list = field(default_factory=list)  # which bundled files were used, if any
    inputs: list = field(default_factory=list)  # every file read: the map, its scene, its table
    cycles: int = 5  # a rate-and-state base: cycles simulated per unstable segment or cell
    cycle_method: str = "auto"  # ... and their integrator (auto, lsoda, dopri5, dopri5_compiled)
    rupture_rules: object = None  # studies.rupture_sets.Rules, from a [rupture_set] table


@dataclass
class SegmentTable:
    ids: list
    names: list
    traces: list  # list of (n, 2) arrays of (lon, lat)
    slip_rate: np.ndarray
    lithology: list
    seismogenic_depth: np.ndarray
    zone_width: np.ndarray
    observed_slip: np.ndarray
    observed_recurrence: np.ndarray
    observed_event: list
    sources: dict  # column -> list of strings
    path: str = ""
    #: from GeoJSON (GEM GAF): slip_type, dip and rake (degrees), upper_depth (m); a CSV table takes the seed's
    #: vertical strike-slip defaults (dip 90, rake 180: dextral, upper depth 0)
    geometry: dict = field(default_factory=dict)

    @property
    def dips(self) -> np.ndarray:
        """Each segment's dip (degrees): the table's or GeoJSON's, else 90."""
        return np.asarray(self.geometry.get("dip", np.full(len(self.ids), 90.0)), dtype=float)

    @property
    def rakes(self) -> np.ndarray:
        """Each segment's rake (degrees, Aki & Richards): the table's or GeoJSON's, else 180 (dextral)."""
        return np.asarray(self.geometry.get("rake", np.full(len(self.ids), 180.0)), dtype=float)

    @property
    def down_dip_widths(self) -> np.ndarray:
        """The rupture's down-dip width H / sin(dip) (m): what a dipping fault's moment and area take."""
        return self.seismogenic_depth / np.sin(np.radians(self.dips))

    @property
    def lengths(self) -> np.ndarray:
        return np.array([trace_length(trace) for trace in self.traces])


def segments_from_geojson(path, scene) -> SegmentTable:
    """A GEM GAF GeoJSON fault file as a segment table. GeoJSON carries no lithology or elastic-zone width:
    each fault takes the base scene's (its [fault] lithology and zone_width), and its seismogenic depth is
    lower - upper, else the scene's; the notes say which faults took defaults."""
    return segments_from_faults(read_fault_geojson(path), scene, path)


def segments_from_sherifs(geometry, properties, scene, model=None, faults=None) -> SegmentTable:
    """SHERIFS's fault files (:func:`faultslip.io.sherifs.read_sherifs_faults`) as a segment table, as GeoJSON's
    (:func:`segments_from_faults`); ``faults`` keeps those named, in the files' order. A fault whose shear modulus
    differs from the base scene's is said in the notes: the rupture set's moments take the scene's."""
    table = read_sherifs_faults(geometry, properties, model)
    if faults is not None:
        unknown = [name for name in faults if name not in table.ids]
        if unknown:
            raise InputError(f"[segments] faults names {unknown[0]!r}, which {Path(properties).name} does not have "
                             f"for model {table.model} ({', '.join(table.ids)})")
        keep = [i for i, name in enumerate(table.ids) if name in faults]
        left = [name for name in table.ids if name not in faults]
        for key in ("ids", "names", "traces", "slip_type"):
            setattr(table, key, [getattr(table, key)[i] for i in keep])
        for key in ("slip_rate", "slip_rate_range", "dip", "rake", "upper_depth", "lower_depth", "shear_modulus"):
            setattr(table, key, getattr(table, key)[keep])
        table.notes.append(f"{Path(properties).name}: {', '.join(left)} left out ([segments] faults)")
    base = scene.fault().shear_modulus
    differing = [name for name, g in zip(table.ids, table.shear_modulus) if np.isfinite(g) and abs(g / base - 1) > 1e-9]
    if differing:
        table.notes.append(f"{', '.join(differing)}: SHERIFS's shear modulus differs from the base scene's "
                           f"{base / 1e9:.4g} GPa, which the rupture set's moments take")
    return segments_from_faults(table, scene, geometry)


def segments_from_faults(faults, scene, path) -> SegmentTable:
    """Faults read from GeoJSON or SHERIFS's files as a segment table: each takes the base scene's lithology and
    zone width, and its seismogenic depth is lower - upper, else the scene's."""
    given = scene.tables.get("fault", {})
    if "lithology" not in given:
        raise InputError(f"{Path(path).name} carries no lithology: the map's base scene needs a [fault] lithology")
    base = scene.fault()
    count = len(faults.ids)
    depth = np.where(np.isnan(faults.lower_depth), base.seismogenic_depth or np.nan,
                     faults.lower_depth - np.nan_to_num(faults.upper_depth))
    if np.isnan(depth).any():
        raise InputError(f"{Path(path).name}: a fault has no seismogenic depths and the base scene no "
                         "seismogenic_depth to fall back on")
    lithology = resolve_material(given["lithology"]).name
    notes = list(faults.notes) + [f"{Path(path).name}: lithology {lithology} and zone width "
                                  f"{base.zone_width / 1e3:.4g} km from the base scene for every fault"]
    nan = np.full(count, np.nan)
    return SegmentTable(ids=faults.ids, names=faults.names, traces=faults.traces, slip_rate=faults.slip_rate,
                        lithology=[lithology] * count, seismogenic_depth=depth,
                        zone_width=np.full(count, base.zone_width), observed_slip=nan, observed_recurrence=nan.copy(),
                        observed_event=[""] * count, sources={"notes": notes}, path=str(path),
                        geometry={"slip_type": faults.slip_type, "dip": np.where(np.isnan(faults.dip), 90.0, faults.dip),
                                  "rake": np.where(np.isnan(faults.rake), 180.0, faults.rake),
                                  "upper_depth": np.nan_to_num(faults.upper_depth)})


def segment_map(segments, lon, lat, scene=None, max_distance="60 km", name="map", description="",
                cycles: int = 5, cycle_method: str = "auto") -> MapSpec:
    """A segment map from Python objects, the same :class:`MapSpec` that :func:`read_map` reads.

    Parameters
    ----------
    segments : pandas.DataFrame or mapping of column name to sequence
        One row per segment, with the columns of a segment table (:data:`SEGMENT_COLUMNS`):
        ``segment``, ``trace`` (a sequence of (lon, lat) pairs in degrees, or ``"lon lat; ..."``),
        ``slip_rate``, ``lithology``, ``seismogenic_depth``, ``zone_width`` and optionally
        ``name``, ``observed_slip``, ``observed_recurrence``. Each quantity is a string with units
        (``"24 mm/yr"``), a pint Quantity (a column may be one Quantity array) or a float in SI.
    lon, lat : array_like
        The raster's axes in degrees east and north.
    scene : Scene, path or bundled name, optional
        Parameters a segment does not give (default: the 1906 scene).
    max_distance : str, Quantity or float (m)
        Cells farther than this from every segment stay empty.

    Returns
    -------
    MapSpec
    """
    if not isinstance(scene, Scene):
        scene = read_slider_scene(scene)
    if hasattr(segments, "to_dict") and hasattr(segments, "columns"):  # a pandas DataFrame
        columns = {str(column): list(segments[column]) for column in segments.columns}
    elif isinstance(segments, dict):
        columns = dict(segments)
    else:
        raise InputError(f"segments must be a pandas DataFrame or a mapping of column to values, got "
                         f"{type(segments).__name__}")
    for column in columns:
        if column not in SEGMENT_COLUMNS and not column.startswith("source"):
            raise InputError(f"segments: unknown column {column!r}{did_you_mean(column, SEGMENT_COLUMNS)}")
    for column, (kind, required) in SEGMENT_COLUMNS.items():
        if required and column not in columns:
            raise InputError(f"segments lack the column {column!r}")
    count = len(list(columns["segment"]))
    if count == 0:
        raise InputError("segments: the table has no segments")

    def values(column, kind, optional=False):
        raw = columns.get(column)
        if raw is None:
            return np.full(count, math.nan)
        if not isinstance(raw, str) and hasattr(raw, "units") and hasattr(raw, "magnitude"):  # one Quantity array
            out = np.atleast_1d(np.asarray(to_si(raw, kind, f"segments {column}"), dtype=float))
        else:
            raw = list(raw)
            if len(raw) != count:
                raise InputError(f"segments: column {column!r} has {len(raw)} values for {count} segments")
            out = np.array([math.nan if optional and (item is None or item == "" or
                                                      (isinstance(item, float) and math.isnan(item)))
                            else to_si(item, kind, f"segments {column}, row {row + 1}", default_unit=si_unit(kind))
                            for row, item in enumerate(raw)], dtype=float)
        if out.shape != (count,):
            raise InputError(f"segments: column {column!r} has {out.size} values for {count} segments")
        return out

    ids = [str(item) for item in columns["segment"]]
    if len(set(ids)) != count:
        raise InputError("segments list a segment twice")
    traces = []
    for row, trace in enumerate(columns["trace"]):
        where = f"segments, row {row + 1}, trace"
        text = trace if isinstance(trace, str) else "; ".join(f"{float(x)!r} {float(y)!r}" for x, y in
                                                               np.asarray(trace, dtype=float).reshape(-1, 2))
        traces.append(parse_trace(text, where))
    lithology = []
    for row, item in enumerate(columns["lithology"]):
        try:
            lithology.append(resolve_material(str(item)).name)
        except InputError as exc:
            raise InputError(f"segments, row {row + 1}: {exc}") from None
    table = SegmentTable(ids, [str(item) for item in columns.get("name", ids)], traces, values("slip_rate", "speed"),
                         lithology, values("seismogenic_depth", "length"), values("zone_width", "length"),
                         values("observed_slip", "length", True), values("observed_recurrence", "time", True),
                         [str(item or "") for item in columns.get("observed_slip_event", [""] * count)],
                         {column: [str(item) for item in columns[column]] for column in columns
                          if column.startswith("source")}, "<segments>",
                         geometry=segment_geometry(columns.get("dip", [None] * count), columns.get("rake", [None] * count),
                                                   "segments", values("upper_depth", "length", True)))
    for key in ("slip_rate", "seismogenic_depth", "zone_width"):
        if np.any(~(getattr(table, key) > 0)):
            raise InputError(f"segments: {key} must be positive (row {int(np.argmax(~(getattr(table, key) > 0))) + 1})")
    spec = MapSpec(name=name, scene=scene, segments=table, description=description, cycles=cycles,
                   cycle_method=cycle_method)
    spec.lon = _axis(np.asarray(lon, dtype=float).ravel().tolist(), "lon", "segment_map")
    spec.lat = _axis(np.asarray(lat, dtype=float).ravel().tolist(), "lat", "segment_map")
    _check_lon_lat(spec.lon, spec.lat, "segment_map")
    spec.max_distance = to_si(max_distance, "length", "max_distance", default_unit="m")
    if not spec.max_distance > 0:
        raise InputError(f"max_distance must be positive, got {max_distance!r}")
    if scene.rate_state:
        check_cycle_method(cycle_method, "cycle_method")
    return spec


def segment_geometry(dips, rakes, where: str, upper_depths=None) -> dict:
    """Dip and rake (degrees) of each segment as a table's ``geometry``: a blank is 90 (vertical) or 180
    (dextral); a dip outside (0, 90] or a rake outside [-180, 180] is one sentence naming the row."""
    geometry = {}
    for column, raw, default in (("dip", dips, 90.0), ("rake", rakes, 180.0)):
        values = []
        for row, item in enumerate(raw):
            text = "" if item is None or (isinstance(item, float) and math.isnan(item)) else str(item).strip()
            try:
                degrees = float(text) if text else default
            except ValueError:
                raise InputError(f"{where}, row {row + 1}: {column} {text!r} is not a number of degrees") from None
            fine = 0.0 < degrees <= 90.0 if column == "dip" else -180.0 <= degrees <= 180.0
            if not fine:
                limits = "above 0 and at most 90" if column == "dip" else "from -180 to 180"
                raise InputError(f"{where}, row {row + 1}: {column} must lie {limits} degrees, got {degrees:g}")
            values.append(degrees)
        geometry[column] = np.array(values, dtype=float)
    upper = np.zeros(len(geometry["dip"])) if upper_depths is None else np.nan_to_num(np.asarray(upper_depths, float))
    if np.any(upper < 0):
        raise InputError(f"{where}, row {int(np.argmax(upper < 0)) + 1}: upper_depth must be zero or below the surface")
    geometry["upper_depth"] = upper
    return geometry


def read_segments(path) -> SegmentTable:
    """Read and validate a segment table (CSV with ``name (unit)`` headers)."""
    path = Path(path)
    header, cells = read_unit_csv(path, f"segment table {path.name}")
    names = [name for name, _ in header]
    for name, _ in header:
        if name not in SEGMENT_COLUMNS and not name.startswith("source"):
            hint = did_you_mean(name, SEGMENT_COLUMNS)
            raise InputError(f"segment table {path.name}: unknown column {name!r}{hint}")
    for name, (kind, required) in SEGMENT_COLUMNS.items():
        if required and name not in names:
            raise InputError(f"segment table {path.name} lacks the column {name!r}")
    units = dict(header)
    rows = [(line, dict(zip(names, row))) for line, row in cells]
    if not rows:
        raise InputError(f"segment table {path.name} has no segments")

    def quantity(line, row, column, kind, optional=False):
        text = row.get(column, "")
        if text == "":
            if optional:
                return math.nan
            raise InputError(f"segment table {path.name}, row {line}: {column} is empty")
        unit = units.get(column)
        if unit is None:
            raise InputError(f"segment table {path.name}: column {column!r} needs a unit in its header, "
                             f"e.g. '{column} (mm/yr)'")
        try:
            return to_si(f"{text} {unit}", kind, f"segment table {path.name}, row {line}, {column}")
        except InputError:
            raise
        except Exception:
            raise InputError(f"segment table {path.name}, row {line}: {column} {text!r} is not a number") from None


    table = {key: [] for key in ("ids", "names", "traces", "slip_rate", "lithology", "seismogenic_depth", "zone_width",
                                 "observed_slip", "observed_recurrence", "observed_event", "dip", "rake", "upper_depth")}
    sources = {name: [] for name in names if name.startswith("source")}
    if units.get("trace") not in (None, "degree", "degrees"):
        raise InputError(f"segment table {path.name}: trace must be in degrees, header says {units['trace']!r}")
    for line, row in rows:
        where = f"segment table {path.name}, row {line}"
        if not row["segment"]:
            raise InputError(f"{where}: segment name is empty")
        table["ids"].append(row["segment"])
        table["names"].append(row.get("name") or row["segment"])
        table["traces"].append(parse_trace(row["trace"], f"{where}, trace"))
        table["slip_rate"].append(quantity(line, row, "slip_rate", "speed"))
        try:
            table["lithology"].append(resolve_material(row["lithology"]).name)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
        table["seismogenic_depth"].append(quantity(line, row, "seismogenic_depth", "length"))
        table["zone_width"].append(quantity(line, row, "zone_width", "length"))
        table["observed_slip"].append(quantity(line, row, "observed_slip", "length", optional=True))
        table["observed_recurrence"].append(quantity(line, row, "observed_recurrence", "time", optional=True))
        table["observed_event"].append(row.get("observed_slip_event", ""))
        table["upper_depth"].append(quantity(line, row, "upper_depth", "length", optional=True))
        for column in ("dip", "rake"):
            if row.get(column) and units.get(column) not in ("degree", "degrees", "deg"):
                raise InputError(f"segment table {path.name}: column {column!r} must be in degrees, e.g. "
                                 f"'{column} (degree)'")
            table[column].append(row.get(column, ""))
        for name in sources:
            sources[name].append(row.get(name, ""))
    if len(set(table["ids"])) != len(table["ids"]):
        raise InputError(f"segment table {path.name} lists a segment twice")
    for key in ("slip_rate", "seismogenic_depth", "zone_width"):
        values = np.array(table[key])
        if np.any(values <= 0):
            bad = int(np.argmax(values <= 0))
            raise InputError(f"segment table {path.name}, row {rows[bad][0]}: {key} must be positive")
    return SegmentTable(table["ids"], table["names"], table["traces"], np.array(table["slip_rate"]), table["lithology"],
                        np.array(table["seismogenic_depth"]), np.array(table["zone_width"]),
                        np.array(table["observed_slip"]), np.array(table["observed_recurrence"]),
                        table["observed_event"], sources, str(path),
                        geometry=segment_geometry(table["dip"], table["rake"], f"segment table {path.name}",
                                                  table["upper_depth"]))


def read_raster(path):
    """Inputs on (lat, lon) from netCDF (variables with units) or CSV (one row per cell)."""
    import xarray as xr  # heavy: imported where used

    path = Path(path)
    if not path.exists():
        raise InputError(f"raster file {str(path)!r} does not exist")
    if path.suffix == ".nc":

        data = open_netcdf(path, "raster")
        for coordinate in ("lon", "lat"):
            if coordinate not in data.coords:
                raise InputError(f"raster {path.name} needs coordinates lon and lat (degrees); it has {list(data.coords)}")
        out = xr.Dataset(coords={"lat": data["lat"].values.astype(float), "lon": data["lon"].values.astype(float)})
        for name, variable in data.data_vars.items():
            if name not in RASTER_VARIABLES:
                hint = did_you_mean(name, RASTER_VARIABLES)
                raise InputError(f"raster {path.name}: unknown variable {name!r}{hint}")
            variable = variable.transpose("lat", "lon")
            if RASTER_VARIABLES[name] is None:
                out[name] = (("lat", "lon"), variable.values.astype(str))
                continue
            unit = variable.attrs.get("units")
            if unit is None:
                raise InputError(f"raster {path.name}: variable {name!r} has no units attribute")
            values = variable.values.astype(float)
            if np.isnan(values).any():
                raise InputError(f"raster {path.name}: variable {name!r} contains NaN")
            factor = to_si(f"1 {unit}", RASTER_VARIABLES[name], f"raster {path.name}, variable {name}")
            out[name] = (("lat", "lon"), values * factor)
    elif path.suffix == ".csv":
        out = _raster_from_csv(path)
    else:
        raise InputError(f"raster {path.name} must be .nc or .csv")
    _check_lon_lat(out["lon"].values, out["lat"].values, f"raster {path.name}")
    if "lithology" not in out and not {"shear_modulus", "slip_rate"} <= set(out.data_vars):
        raise InputError(f"raster {path.name} needs a lithology, or shear_modulus and slip_rate (and zone_width, normal_stress)")
    return out


def _raster_from_csv(path):
    import xarray as xr  # heavy: imported where used

    header, rows = read_unit_csv(path, f"raster {path.name}")
    names = [n for n, _ in header]
    units = dict(header)
    for required in ("lon", "lat"):
        if required not in names:
            raise InputError(f"raster {path.name} needs columns lon and lat (degrees)")
    for name in names:
        if name not in ("lon", "lat") and name not in RASTER_VARIABLES:
            hint = did_you_mean(name, RASTER_VARIABLES)
            raise InputError(f"raster {path.name}: unknown column {name!r}{hint}")
    columns = {name: [] for name in names}
    for line, row in rows:
        for name, cell in zip(names, row):
            if name in ("lon", "lat"):
                try:
                    columns[name].append(float(cell))
                except ValueError:
                    raise InputError(f"raster {path.name}, row {line}: {name} {cell!r} is not a number") from None
            elif RASTER_VARIABLES[name] is None:
                columns[name].append(cell)
            else:
                if units.get(name) is None:
                    raise InputError(f"raster {path.name}: column {name!r} needs a unit in its header")
                columns[name].append(to_si(f"{cell} {units[name]}", RASTER_VARIABLES[name],
                                           f"raster {path.name}, row {line}, {name}"))
    lon = np.unique(columns["lon"])
    lat = np.unique(columns["lat"])
    out = xr.Dataset(coords={"lat": lat, "lon": lon})
    i = np.searchsorted(lat, columns["lat"])
    j = np.searchsorted(lon, columns["lon"])
    if len(set(zip(i, j))) != len(i) or len(i) != lat.size * lon.size:
        raise InputError(f"raster {path.name}: rows must cover every (lon, lat) pair of a regular grid exactly once")
    for name in names:
        if name in ("lon", "lat"):
            continue
        if RASTER_VARIABLES[name] is None:
            grid = np.empty((lat.size, lon.size), dtype=object)
        else:
            grid = np.full((lat.size, lon.size), np.nan)
        grid[i, j] = columns[name]
        out[name] = (("lat", "lon"), grid.astype(str) if RASTER_VARIABLES[name] is None else grid)
    return out


#: The largest raster axis: 1e5 x 1e5 cells already need 80 GB per output.
MAX_AXIS = 100_000


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _axis(spec, name, where):
    usage = f"{where} {name} must be a list of degrees or {{ linspace = [start, stop, count] }}"
    if isinstance(spec, dict):
        args = spec.get("linspace")
        if list(spec) != ["linspace"] or not isinstance(args, list) or len(args) != 3:
            raise InputError(usage)
        start, stop, count = args
        if not (_number(start) and _number(stop)) or not isinstance(count, int) or isinstance(count, bool):
            raise InputError(usage)
        if not 1 <= count <= MAX_AXIS:
            raise InputError(f"{where} {name} linspace count must lie between 1 and {MAX_AXIS}, got {count}")
        values = np.linspace(float(start), float(stop), count)
    elif isinstance(spec, list) and spec and all(_number(v) for v in spec):
        if len(spec) > MAX_AXIS:
            raise InputError(f"{where} {name} has more than {MAX_AXIS} values")
        values = np.asarray(spec, dtype=float)
    else:
        raise InputError(usage)
    if len(set(values.tolist())) != values.size:
        raise InputError(f"{where} {name} repeats a value")
    return values


def read_map(path) -> MapSpec:
    """Read a map file, its base scene and its input table or raster (paths relative to the file).

    Parameters
    ----------
    path : str or path
        A map file (TOML).

    Returns
    -------
    MapSpec
    """

    path, origin = resolve_path(path, "map file", kind="map")
    text = read_text_file(path, "map file")
    document = parse_toml(text, path.name)
    check_toml_kind(document, path.name, "map")
    for table, content in document.items():
        if table not in MAP_SCHEMA:
            raise InputError(f"unknown table [{table}] in {path.name} (allowed: {', '.join(MAP_SCHEMA)})")
        if not isinstance(content, dict):
            raise InputError(f"{table} in {path.name} must be a table [{table}], got a value")
        for key in content:
            if key not in MAP_SCHEMA[table]:
                hint = did_you_mean(key, MAP_SCHEMA[table])
                raise InputError(f"unknown key {key!r} in [{table}] of {path.name}{hint}")
    head = document.get("map", {})
    if ("segments" in document) == ("raster" in document):
        raise InputError(f"{path.name} needs exactly one input: a [segments] or a [raster] table")

    for key in ("name", "base", "description"):
        if key in head and not isinstance(head[key], str):
            raise InputError(f"[map] {key} in {path.name} must be a string, got {head[key]!r}")
    notes = [f"map: {origin}"] if origin else []

    def resolve(name):
        """Relative to the map file; a bare name with no such file there may mean a bundled data file."""
        if not isinstance(name, str) or not name.strip():
            raise InputError(f"{path.name}: file must name an input file, got {name!r}")
        candidate = Path(name)
        local = candidate if candidate.is_absolute() else path.parent / candidate
        if local.is_file():
            return local
        bundled = bundled_dir("data") / candidate.name
        if candidate.name == name and bundled.is_file():
            notes.append(f"input: bundled data file {bundled.name} (no file {name!r} beside {path.name})")
            return bundled
        raise InputError(f"{path.name}: input file {name!r} does not exist")

    base_path, base_origin = resolve_path(head.get("base", "san_andreas_1906.toml"), "scene", base_dir=path.parent)
    scene = parse_scene(read_text_file(base_path, "scene file"), source=base_path.name, path=base_path)
    if base_origin:
        notes.append(f"scene: {base_origin}")
    spec = MapSpec(name=head.get("name", path.stem), scene=scene, text=text, description=head.get("description", ""))
    if scene.rate_state:
        spec.cycles, spec.cycle_method = head.get("cycles", 5), head.get("method", "auto")
        if not isinstance(spec.cycles, int) or isinstance(spec.cycles, bool) or not 1 <= spec.cycles <= 1000:
            raise InputError(f"[map] cycles in {path.name} must be a whole number from 1 to 1000 (a map predicts slip "
                             f"and recurrence; a study gives K / K_c alone), got {spec.cycles!r}")
        check_cycle_method(spec.cycle_method, f"[map] method in {path.name}")
    elif {"cycles", "method"} & set(head):
        raise InputError(f"[map] cycles and method in {path.name} apply to a base scene with rate-and-state "
                         "friction; a seed-law map takes --method")
    spec.notes = notes
    if "segments" in document:
        table = document["segments"]
        source = resolve(table.get("file", ""))
        form = table.get("format", "sherifs" if "properties" in table else None)
        if form not in (None, "sherifs"):
            raise InputError(f"[segments] format in {path.name} must be sherifs (or absent: CSV or GeoJSON by the "
                             f"file's suffix), got {form!r}")
        if form != "sherifs" and {"properties", "model", "faults"} & set(table):
            raise InputError(f"[segments] properties, model and faults in {path.name} belong to SHERIFS's files "
                             "(format = \"sherifs\")")
        if form == "sherifs":
            if "properties" not in table:
                raise InputError(f"[segments] in {path.name}: SHERIFS's faults need properties = "
                                 "\"Faults_properties.txt\" beside file = \"Faults_geometry.txt\"")
            chosen = table.get("faults")
            if chosen is not None and not (isinstance(chosen, list) and chosen and
                                           all(isinstance(name, str) for name in chosen)):
                raise InputError(f"[segments] faults in {path.name} must be a list of fault names, got {chosen!r}")
            if not isinstance(table.get("model", ""), str):
                raise InputError(f"[segments] model in {path.name} must be a model name, got {table['model']!r}")
            properties = resolve(table["properties"])
            spec.segments = segments_from_sherifs(source, properties, scene, table.get("model"), chosen)
            spec.notes.extend(spec.segments.sources.pop("notes", []))
            spec.source_files.append(str(properties))
        elif source.suffix.lower() in (".geojson", ".json"):
            spec.segments = segments_from_geojson(source, scene)
            spec.notes.extend(spec.segments.sources.pop("notes", []))
        else:
            spec.segments = read_segments(source)
    else:
        source = resolve(document["raster"].get("file", ""))
        spec.raster = read_raster(source)
    spec.source_files.append(str(source))
    spec.inputs = [path, base_path, *map(Path, spec.source_files)]
    grid = document.get("grid", {})
    if spec.segments is not None:
        if "lon" not in grid or "lat" not in grid:
            raise InputError(f"{path.name}: a segment map needs [grid] lon and lat for its raster")
        spec.lon = _axis(grid["lon"], "lon", f"[grid] in {path.name}")
        spec.lat = _axis(grid["lat"], "lat", f"[grid] in {path.name}")
        _check_lon_lat(spec.lon, spec.lat[: spec.lon.size] if spec.lat.size >= spec.lon.size else spec.lat, f"[grid] in {path.name}")
        _check_lon_lat(spec.lon[:1], spec.lat, f"[grid] in {path.name}")
    if "rupture_set" in document:
        if spec.segments is None:
            raise InputError(f"[rupture_set] in {path.name} joins fault sections: it needs [segments], not a raster")
        rules = dict(document["rupture_set"])
        listed = rules.get("ruptures")
        if isinstance(listed, dict):  # SHERIFS's rupture file and the set to take from it
            if set(listed) != {"file", "set"} or not isinstance(listed.get("set"), str):
                raise InputError(f"[rupture_set] ruptures in {path.name} is a list of fault lists, or "
                                 "{ file = \"ruptures.txt\", set = \"NAME\" } (SHERIFS's), got {listed!r}")
            rupture_file = resolve(listed["file"])
            sets = read_sherifs_ruptures(rupture_file)
            if listed["set"] not in sets:
                raise InputError(f"{rupture_file.name} has no set {listed['set']!r} (it has {', '.join(sets)})")
            rules["ruptures"] = [list(rupture) for rupture in sets[listed["set"]]]
            spec.inputs.append(rupture_file)
            spec.notes.append(f"ruptures: set {listed['set']} of {rupture_file.name}")
        spec.rupture_rules = parse_rules(rules, f"[rupture_set] in {path.name}", spec.segments.ids)
    if "max_distance" in grid:
        spec.max_distance = to_si(grid["max_distance"], "length", f"[grid] max_distance in {path.name}")
        if not spec.max_distance > 0:
            raise InputError(f"[grid] max_distance in {path.name} must be positive, got {grid['max_distance']!r}")
    return spec


# --- predictions ------------------------------------------------------------


def _fault_inputs_along(spec, dims_coords, lithology, overrides):
    """Study-kernel inputs for per-segment or per-cell parameters (DataArrays on their dims)."""
    import xarray as xr  # heavy: imported where used


    fault = spec.scene.fault()
    given = spec.scene.tables.get("fault", {})
    inputs = {name: getattr(fault, name) for name in ("shear_modulus", "zone_width", "slip_rate", "mu_so", "mu_m", "b",
                                                       "d", "rupture_length", "seismogenic_depth", "damping_ratio",
                                                       "density", "shear_wave_speed")}
    if "shear_wave_speed" not in given:
        inputs["shear_wave_speed"] = None  # sqrt(G / rho) per segment or cell, as Fault derives it
    if lithology is not None:
        flat = np.asarray(lithology).ravel()
        choices = {name: resolve_material(name) for name in set(flat)}
        shape = np.shape(lithology)

        def table(getter):
            return xr.DataArray(np.array([getter(choices[n]) for n in flat], dtype=float).reshape(shape), **dims_coords)

        inputs["shear_modulus"] = table(lambda c: c.shear_modulus if c.shear_modulus is not None else np.nan)
        for key in ("mu_so", "mu_m", "b", "d"):
            inputs[key] = table(lambda c, k=key: getattr(c.rate_law, k) if c.rate_law is not None else np.nan)
        if np.isnan(inputs["shear_modulus"].values).any() or np.isnan(inputs["mu_so"].values).any():
            bad = [n for n, c in choices.items() if c.shear_modulus is None or c.rate_law is None][0]
            raise InputError(f"lithology {bad!r} lacks a shear modulus or friction preset; it cannot be mapped")
    for name, values in overrides.items():
        inputs[name] = xr.DataArray(values, **dims_coords)
    inputs["normal_stress"] = normal_stress_input(inputs, overrides, given, fault)
    inputs["radiation_damping"] = bool(fault.radiation_damping)
    return inputs


def _rate_state_along(spec, dims_coords, lithology, overrides, tolerance):
    """Rate-and-state outputs for per-segment or per-cell parameters (DataArrays on their dims).

    A lithology gives its shear modulus; one that names a saved rate-and-state fit also gives its
    friction, where other lithologies take the base scene's [friction].
    """
    study, inputs = _rate_state_map_inputs(spec, dims_coords, lithology, overrides, tolerance)
    return as_dataset(rate_state_outputs(inputs, study), study)


def _rate_state_map_inputs(spec, dims_coords, lithology, overrides, tolerance):
    """(study, inputs): what :func:`_rate_state_along` computes its cells from, before any cell runs."""
    import xarray as xr  # heavy: imported where used

    varying = {name: xr.DataArray(values, **dims_coords) for name, values in overrides.items()}
    if lithology is not None:
        flat = np.asarray(lithology).ravel()
        choices = {name: resolve_material(name) for name in set(flat)}

        def table(getter, dtype=float):
            """A per-lithology value on the segments' or cells' dims (``getter`` takes the lithology's name)."""
            return xr.DataArray(np.array([getter(n) for n in flat], dtype=dtype).reshape(np.shape(lithology)),
                                **dims_coords)

        if "shear_modulus" not in varying:
            missing = sorted(n for n, c in choices.items() if c.shear_modulus is None)
            if missing and "shear_modulus" not in spec.scene.tables.get("fault", {}):
                raise InputError(f"lithology {missing[0]!r} has no shear modulus; it cannot be mapped")
            if not missing:
                varying["shear_modulus"] = table(lambda n: choices[n].shear_modulus)
        if any(c.rate_state is not None for c in choices.values()):
            needs_base = any(c.rate_state is None for c in choices.values())
            base = spec.scene.rate_state_law()[0] if needs_base else None
            laws = {n: c.rate_state or base for n, c in choices.items()}
            if any(law.two_state for law in laws.values()):
                raise InputError("a mapped fit has two state variables; fault predictions take a one-state law")
            for key in ("a", "b", "critical_slip", "mu0", "reference_speed"):
                varying[key] = table(lambda n, k=key: getattr(laws[n], k))
            varying["evolution"] = table(lambda n: laws[n].evolution, dtype=object)
    study = Study(name=spec.name, scene=spec.scene, dims={}, method=spec.cycle_method, tolerance=tolerance,
                  cycles=spec.cycles)
    return study, rate_state_inputs(study, varying)


#: A raster's cells along each axis whose K / K_c the cost model reads (evenly strided: at most 64 x 64 of them):
#: the closed form is cheap, but a raster may hold millions of cells, and the sample is built alone.
COST_SAMPLE_AXIS = 64


def _model_seconds(spec, tolerance: float) -> float:
    """CPU seconds of the map's predictions, before any runs: a rate-and-state map's cycles in every unstable
    segment or raster cell, by the integrators' calibrated cost models over each one's K / K_c (closed form, on
    a raster's strided sample, :data:`COST_SAMPLE_AXIS` a side at most); the seed law's closed form is vectorised
    (the raster rate)."""
    if not spec.scene.rate_state or not spec.cycles:
        return 0.0
    if spec.segments is not None:
        table = spec.segments
        count = len(table.ids)
        dims_coords = {"dims": ("segment",), "coords": {"segment": np.arange(count)}}
        overrides = {"slip_rate": table.slip_rate, "seismogenic_depth": table.down_dip_widths,
                     "zone_width": table.zone_width, "rupture_length": table.lengths}
        lithology = table.lithology
    else:
        count = int(spec.raster["lat"].size * spec.raster["lon"].size)
        raster = spec.raster.isel({axis: slice(None, None, -(-spec.raster[axis].size // COST_SAMPLE_AXIS))
                                   for axis in ("lat", "lon")})
        dims_coords = {"dims": ("lat", "lon"), "coords": {"lat": raster["lat"].values, "lon": raster["lon"].values}}
        overrides = {name: raster[name].values for name in ("shear_modulus", "zone_width", "slip_rate",
                                                            "normal_stress", "shear_stress") if name in raster}
        lithology = raster["lithology"].values if "lithology" in raster else None
    _, inputs = _rate_state_map_inputs(spec, dims_coords, lithology, overrides, tolerance)
    shape = _shape(inputs)
    sample = {key: np.broadcast_to(np.asarray(getattr(value, "values", value)), shape).ravel()
              for key, value in inputs.items()}
    sample["evolution"] = evolution_codes(sample["evolution"])
    ratio = rate_state_cells(**sample)["stiffness_ratio"]
    return (estimated_seconds(ratio, friction_ratio(sample, ratio.shape), spec.cycles, tolerance, spec.cycle_method)
            * count / max(ratio.size, 1))


def _shape(inputs: dict) -> tuple:
    """The broadcast shape of a map's inputs (its segments or raster cells)."""
    return np.broadcast_shapes(*(np.shape(getattr(value, "values", value)) for value in inputs.values()))


def predict_segments(spec, method="auto", tolerance=1e-6):
    """Per-segment predictions (slip, recurrence, Mw for the segment's length) on dim ``segment``."""
    import xarray as xr  # heavy: imported where used


    table = spec.segments
    coords = {"segment": ("segment", np.array(table.ids, dtype=object), {"long_name": "fault segment"})}
    dims_coords = {"dims": ("segment",), "coords": coords}
    lengths = table.lengths
    # a dipping fault ruptures its down-dip width H / sin(dip): the moment G L W slip takes W. The block's
    # stiffness keeps the seed's choice, G / D with the elastic zone D, whatever the dip (map notes say so)
    along = {"slip_rate": table.slip_rate, "seismogenic_depth": table.down_dip_widths, "zone_width": table.zone_width,
             "rupture_length": lengths}
    if spec.scene.rate_state:
        dataset = _rate_state_along(spec, dims_coords, table.lithology, along, tolerance)
    else:
        inputs = _fault_inputs_along(spec, dims_coords, table.lithology, along)
        study = Study(name=spec.name, scene=spec.scene, dims={}, method=method, tolerance=tolerance)
        dataset = as_dataset(evaluate(inputs, "fault", method, tolerance, outside="flag"), study)
    extra = {
        "name": (np.array(table.names, dtype=object), None, "segment name"),
        "lithology": (np.array(table.lithology, dtype=object), None, "lithology or friction preset"),
        "slip_rate": (table.slip_rate, "m/s", "long-term slip rate"),
        "segment_length": (lengths, "m", "geodetic length of the trace (WGS84)"),
        "seismogenic_depth": (table.seismogenic_depth, "m", "seismogenic depth H"),
        "dip": (table.dips, "degree", "dip of the fault"),
        "down_dip_width": (table.down_dip_widths, "m", "rupture width down dip, H / sin(dip): the moment's width"),
        "zone_width": (table.zone_width, "m", "elastic-zone half-width D"),
        "observed_slip": (table.observed_slip, "m", "observed slip per event (where published)"),
        "observed_recurrence": (table.observed_recurrence, "s", "observed paleoseismic recurrence (where published)"),
        "observed_slip_event": (np.array(table.observed_event, dtype=object), None, "event of the observed slip"),
    }
    dipping = [str(i) for i, dip in zip(table.ids, table.dips) if dip < 90.0]
    if dipping and hasattr(spec, "notes"):
        spec.notes.append(f"dipping segments ({', '.join(dipping)}): the moment and the rupture area take the down-dip "
                          "width H / sin(dip); the block's stiffness G / D keeps the elastic-zone width D, the same "
                          "geometric choice as for a vertical fault")
    for name, (values, unit, long_name) in extra.items():
        attrs = {"long_name": long_name, **({"units": unit} if unit else {})}
        dataset[name] = xr.DataArray(values, dims=("segment",), coords=coords, attrs=attrs)
    with np.errstate(divide="ignore", invalid="ignore"):
        dataset["recurrence_ratio"] = xr.DataArray(dataset["recurrence_period"].values / table.observed_recurrence,
                                                   dims=("segment",), attrs={"units": "1", "long_name": "predicted / observed recurrence"})
        dataset["slip_ratio"] = xr.DataArray(dataset["slip_per_event"].values / table.observed_slip, dims=("segment",),
                                             attrs={"units": "1", "long_name": "predicted / observed slip per event"})
    for column, values in table.sources.items():
        dataset[column] = xr.DataArray(np.array(values, dtype=object), dims=("segment",), attrs={"long_name": column.replace("_", " ")})
    dataset["trace_vertices"] = xr.DataArray(np.array(["; ".join(f"{lon:.4f} {lat:.4f}" for lon, lat in trace)
                                                       for trace in table.traces], dtype=object), dims=("segment",),
                                             attrs={"long_name": "trace as 'lon lat; ...' in degrees"})
    return dataset


#: What a map imports beside its Dataset: the k-d tree of its traces' nearest points.
MAP_IMPORTS = ("scipy.spatial",)


def map_size_estimate(spec, output=None, tolerance: float = 1e-6, relations=()) -> budget.Estimate:
    """What a map needs, before any work (``faultslip map --estimate``; ``faultslip.hazard.map_estimate``): its
    raster and traces, its predictions' own cost (a rate-and-state map's cycles in every segment or cell,
    :func:`_model_seconds`), and, for a map with ``[rupture_set]`` rules, its fault system's rates on each of
    ``relations``' branches (:func:`faultslip.studies.rupture_sets.rupture_set_estimate`).

    Parameters
    ----------
    spec : str, path or MapSpec
        A map file, or :func:`read_map`'s map.
    output : path, optional
        Where the map's netCDF would go (its disk is counted).
    tolerance : float
        The relative error the map's predictions are asked (a rate-and-state map's integrators are chosen by it).
    relations : sequence of str
        The magnitude relations whose rupture sets the map solves (``faultslip map --nrml`` solves one per
        ``--scaling-relations`` branch; a displacement hazard or the traces figure, faultslip's); empty, none.

    Returns
    -------
    faultslip.io.budget.Estimate
        CPU seconds (with what the map imports, measured: :func:`faultslip.io.budget.with_imports`), memory
        and disk, before any work.
    """
    tolerance = ranges.check_tolerance(tolerance if tolerance is not None else 1e-6)
    if isinstance(spec, (str, os.PathLike)):
        spec = read_map(spec)
    if spec.segments is not None:
        cells = float(np.size(spec.lat)) * float(np.size(spec.lon))
        points = sum(trace_length(trace) for trace in spec.segments.traces) / 1000.0 + len(spec.segments.traces)
    else:
        cells, points = float(spec.raster["lat"].size) * float(spec.raster["lon"].size), 0.0
    estimate = budget.map_estimate(cells, points, output, model_seconds=_model_seconds(spec, tolerance))
    if spec.scene.rate_state and spec.cycles:
        where = f"{len(spec.segments.ids)} segments" if spec.segments is not None else "its raster cells"
        estimate.what += f", with {spec.cycles} rate-and-state cycles in each unstable one of {where}"
    if relations and spec.rupture_rules is not None:  # the rates come after the predictions, the map still held
        rates = rupture_set_estimate(spec, spec.rupture_rules, tuple(relations))
        estimate = replace(estimate, what=f"{estimate.what}, and {rates.what}", memory=estimate.memory + rates.memory,
                           seconds=estimate.seconds + rates.seconds, imports=(*estimate.imports, *rates.imports))
    # and the CPU of what the map imports where it runs (its Dataset, the netCDF it writes): measured
    estimate.imports = (*budget.DATASET_IMPORTS, *(budget.DATASET_WRITER_IMPORTS if output is not None else ()),
                        *MAP_IMPORTS, *estimate.imports)
    return budget.with_imports(estimate)


def check_map_size(spec, output=None, allow_large: bool = False, tolerance: float = 1e-6, relations=()) -> None:
    """Refuse, before any work, a map beyond the machine's memory, disk or time budget (with ``relations``, its
    rupture sets' rates too: :func:`map_size_estimate`)."""
    if not allow_large:  # lifted, the estimate (a sample of the map's cells) is not worked out at all
        budget.check(map_size_estimate(spec, output, tolerance, relations))


def regional_map(path, method="auto", tolerance=1e-6, allow_large: bool = False):
    """A map file's dataset: :func:`read_map` then :func:`run_map`, what ``faultslip map FILE -o OUT.nc``
    computes (``faultslip.map`` at the top level).

    Parameters
    ----------
    path : str or path
        A map file (TOML), as in ``configs/san_andreas_map.toml``.
    method, tolerance, allow_large
        As :func:`run_map`.

    Returns
    -------
    xarray.Dataset
        Per-segment predictions and the raster, CF with units.
    """
    return run_map(read_map(path), method=method, tolerance=tolerance, allow_large=allow_large)


def run_map(spec, method="auto", tolerance=1e-6, allow_large: bool = False):
    """The map's dataset: per-segment predictions and a nearest-segment raster, or a predicted raster.

    The map's size is checked against the budget first (``allow_large`` lifts it).

    Parameters
    ----------
    spec : MapSpec
        :func:`read_map`'s or :func:`segment_map`'s map.
    method : str
        The seed law's method.
    tolerance : float
        Relative error allowed.
    allow_large : bool
        Lift the budget.

    Returns
    -------
    xarray.Dataset
        Slip per event (m), recurrence (s), Mw and the empirical relations on segments or a raster.
    """
    import xarray as xr  # heavy: imported where used

    tolerance = ranges.check_tolerance(tolerance if tolerance is not None else 1e-6)  # "10 %" as the command
    check_map_size(spec, allow_large=allow_large, tolerance=tolerance)
    if spec.scene.rate_state:
        if method != "auto":  # its cells choose their integrator by K / K_c, as 'faultslip run' does
            raise InputError(f"--method {method!r}: a rate-and-state map's segments choose their cycle integrator "
                             "themselves; leave --method out (auto)")
    elif method not in SEED_METHODS:
        raise InputError(f"--method must be one of {', '.join(SEED_METHODS)} for a map, got {method!r}"
                         + did_you_mean(str(method), SEED_METHODS))

    if spec.segments is not None:
        segments = predict_segments(spec, method, tolerance)
        index, distance = nearest_segment(spec.lon, spec.lat, spec.segments.traces)
        near = distance <= spec.max_distance
        raster_coords = {"lat": ("lat", spec.lat, {"units": "degrees_north", "long_name": "latitude", "standard_name": "latitude"}),
                         "lon": ("lon", spec.lon, {"units": "degrees_east", "long_name": "longitude", "standard_name": "longitude"})}
        dataset = segments
        dataset["nearest_segment"] = xr.DataArray(np.where(near, index, -1).astype(np.int32), dims=("lat", "lon"),
                                                  coords=raster_coords, attrs={"long_name": "index of the nearest segment (-1: none within max_distance)", "units": "1"})
        dataset["distance_to_segment"] = xr.DataArray(distance, dims=("lat", "lon"), coords=raster_coords,
                                                      attrs={"units": "m", "long_name": "great-circle distance to the nearest trace"})
        for name in ("slip_per_event", "recurrence_period", "moment_magnitude", "slip_rate"):
            values = dataset[name].values[index]
            dataset[f"map_{name}"] = xr.DataArray(np.where(near, values, np.nan), dims=("lat", "lon"), coords=raster_coords,
                                                  attrs={**dataset[name].attrs, "long_name": f"nearest-segment {dataset[name].attrs.get('long_name', name)}"})
        dataset.attrs["max_distance_m"] = spec.max_distance
    else:
        raster = spec.raster
        coords = {"lat": ("lat", raster["lat"].values, {"units": "degrees_north", "standard_name": "latitude"}),
                  "lon": ("lon", raster["lon"].values, {"units": "degrees_east", "standard_name": "longitude"})}
        overrides = {name: raster[name].values for name in ("shear_modulus", "zone_width", "slip_rate", "normal_stress",
                                                            "shear_stress") if name in raster}
        lithology = raster["lithology"].values if "lithology" in raster else None
        dims_coords = {"dims": ("lat", "lon"), "coords": coords}
        if spec.scene.rate_state:
            dataset = _rate_state_along(spec, dims_coords, lithology, overrides, tolerance)
        else:
            inputs = _fault_inputs_along(spec, dims_coords, lithology, overrides)
            study = Study(name=spec.name, scene=spec.scene, dims={}, method=method, tolerance=tolerance)
            dataset = as_dataset(evaluate(inputs, "fault", method, tolerance, outside="flag"), study)
        for name, values in overrides.items():
            dataset[name] = xr.DataArray(values, dims=("lat", "lon"), coords=coords)
        if lithology is not None:
            dataset["lithology"] = xr.DataArray(lithology.astype(object), dims=("lat", "lon"), coords=coords)

    dataset.attrs["tolerance"] = float(tolerance)  # the relative error asked of every method
    dataset.attrs.update({
        "title": f"faultslip map: {spec.name}", "Conventions": "CF-1.8", "source": f"faultslip {__version__}",
        "history": f"{datetime.now(timezone.utc).isoformat(timespec='seconds')}: faultslip map",
        "faultslip_map": spec.text, "faultslip_base_scene": spec.scene.text,
        "input_files": "; ".join(Path(f).name for f in spec.source_files),
        "comment": "approximate inputs; distances: WGS84 lengths, great-circle nearest distances (obspy.geodetics)",
    })
    if spec.description:
        dataset.attrs["summary"] = spec.description
    return dataset


def segment_rows(dataset) -> list[dict]:
    """Each segment's predicted and observed values as plain floats (NaN where absent), read column-wise."""
    names = ("slip_rate", "slip_per_event", "recurrence_period", "moment_magnitude", "observed_slip",
             "observed_recurrence", "slip_ratio", "recurrence_ratio", "outside_domain", "model_error")
    columns = {name: (np.asarray(dataset[name].values, dtype=float) if name in dataset
                      else np.full(dataset.sizes["segment"], np.nan)) for name in names}
    return [{"segment": str(segment), **{name: float(columns[name][i]) for name in names}}
            for i, segment in enumerate(dataset["segment"].values)]


def observed_table(dataset, most: int | None = None) -> str:
    """Predicted against observed recurrence and slip, with ratios, as Markdown (the first ``most`` rows).

    Parameters
    ----------
    dataset : xarray.Dataset
        :func:`run_map`'s dataset with observations.
    most : int, optional
        Rows shown.

    Returns
    -------
    str
        Markdown.
    """
    year = JULIAN_YEAR
    declared = "model_error" in dataset  # one block per segment standing for a fault: its bound, in years
    lines = ["| segment | slip rate (mm/yr) | predicted slip (m) | observed slip (m) | ratio | predicted recurrence (yr) "
             "| observed recurrence (yr) | ratio |" + (" 2-D fault's recurrence by the model error (yr) |" if declared
                                                     else ""), "| --- " * (9 if declared else 8) + "|"]

    def fmt(value, scale=1.0, digits=3):
        return "" if not np.isfinite(value) else f"{value / scale:.{digits}g}"

    def bound(row):
        within = range_within(row["recurrence_period"], row["model_error"])
        if within is None:
            return "not known" if np.isfinite(row["recurrence_period"]) else ""
        return f"{fmt(within[0], year)} to " + ("no upper end" if within[1] is None else fmt(within[1], year))

    rows = segment_rows(dataset)
    for row in rows[:most]:
        outside = row["outside_domain"] == 1
        predicted = "none: mu_m is not below mu_so (no stick-slip)" if outside else fmt(row["slip_per_event"])
        lines.append(f"| {row['segment']} | {row['slip_rate'] * year * 1e3:.3g} | {predicted} | "
                     f"{fmt(row['observed_slip'])} | {fmt(row['slip_ratio'])} | {fmt(row['recurrence_period'], year)} | "
                     f"{fmt(row['observed_recurrence'], year)} | {fmt(row['recurrence_ratio'])} |"
                     + (f" {bound(row)} |" if declared else ""))
    if most is not None and len(rows) > most:
        lines.append(f"| ... {len(rows) - most} more segments in the netCDF file |" + " |" * (8 if declared else 7))
    return "\n".join(lines)


def has_observations(dataset) -> bool:
    """Whether any segment carries an observed slip or recurrence."""
    return any(name in dataset and bool(np.isfinite(np.asarray(dataset[name].values, dtype=float)).any())
               for name in ("observed_recurrence", "observed_slip"))


#: A field whose spread is within this fraction of its size draws as one colour (round-off is no signal).
CONSTANT_SPREAD = 1e-9


def colour_limits(values, spread: float = CONSTANT_SPREAD) -> tuple[tuple, float | None]:
    """``((vmin, vmax), constant)`` for a colour scale: a field constant to the relative ``spread`` (at least
    :data:`CONSTANT_SPREAD`; a map passes its methods' declared error, below which a difference is no
    signal) gets a window of +-1 % around its value, and ``constant`` is that value; otherwise its range."""
    spread = max(spread, CONSTANT_SPREAD)
    finite = np.asarray(values, dtype=float)
    finite = finite[np.isfinite(finite)]
    if finite.size == 0:
        return (None, None), None
    low, high = float(finite.min()), float(finite.max())
    if high - low <= spread * max(abs(low), abs(high)):
        middle = 0.5 * (low + high)
        half = 0.01 * abs(middle) or 1.0
        return (middle - half, middle + half), middle
    return (low, high), None


def map_figure(dataset):
    """Slip, recurrence and Mw maps with segment traces and unit-labelled colour bars.

    Parameters
    ----------
    dataset : xarray.Dataset
        :func:`run_map`'s dataset.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt  # heavy: imported where used

    year = JULIAN_YEAR
    prefix = "map_" if "map_slip_per_event" in dataset else ""
    panels = [(f"{prefix}slip_per_event", 1.0, "slip per event (m)", "viridis"),
              (f"{prefix}recurrence_period", year, "recurrence period (yr)", "magma_r"),
              (f"{prefix}moment_magnitude", 1.0, "moment magnitude Mw", "plasma")]
    panels = [p for p in panels if p[0] in dataset]
    figure, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 5.2), constrained_layout=True, squeeze=False)
    lat = dataset["lat"].values
    for axis, (name, scale, label, cmap) in zip(axes[0], panels):
        values = dataset[name].values / scale
        # a spread within the tolerance the map was computed to is no signal (Mw is absolute: not scaled)
        limits, constant = colour_limits(values, 0.0 if "moment_magnitude" in name
                                         else float(dataset.attrs.get("tolerance", CONSTANT_SPREAD)))
        mesh = axis.pcolormesh(dataset["lon"].values, lat, values, shading="auto", cmap=cmap,
                               vmin=limits[0], vmax=limits[1])
        bar = figure.colorbar(mesh, ax=axis, label=label, shrink=0.8)
        if constant is not None:  # one value: one tick, not a range of round-off
            bar.set_ticks([constant])
            bar.set_ticklabels([f"{constant:.6g}"])
            label = f"{label}: {constant:.6g} everywhere"
        if "trace_vertices" in dataset:
            for text in dataset["trace_vertices"].values:
                trace = np.array([[float(v) for v in pair.split()] for pair in str(text).split(";")])
                axis.plot(trace[:, 0], trace[:, 1], color="k", lw=1.2)
        axis.set_aspect(1.0 / math.cos(math.radians(float(np.mean(lat)))))
        axis.set_xlabel("longitude (°E)")
        axis.set_ylabel("latitude (°N)")
        axis.set_title(label, fontsize=10)
        axis.grid(True, alpha=0.2)
    figure.suptitle(dataset.attrs.get("title", "faultslip map"))
    return figure


def observed_figure(dataset):
    """Predicted against observed recurrence and slip per event (log axes, 1:1 line)."""
    import matplotlib.pyplot as plt  # heavy: imported where used

    year = JULIAN_YEAR
    figure, axes = plt.subplots(1, 2, figsize=(10, 4.6), constrained_layout=True)
    for axis, (pred, obs, scale, label) in zip(axes, [("recurrence_period", "observed_recurrence", year, "recurrence (yr)"),
                                                       ("slip_per_event", "observed_slip", 1.0, "slip per event (m)")]):
        p, o = dataset[pred].values / scale, dataset[obs].values / scale
        ok = np.isfinite(p) & np.isfinite(o) & (p > 0)
        axis.loglog(o[ok], p[ok], "o", color="C3")
        for k, (segment, x, y) in enumerate(zip(dataset["segment"].values[ok], o[ok], p[ok])):
            axis.annotate(f"{segment} ({y / x:.2g}x)", (x, y), fontsize=8, xytext=(4, 4 if k % 2 == 0 else -12),
                          textcoords="offset points")
        if ok.any():
            low, high = min(o[ok].min(), p[ok].min()) / 2, max(o[ok].max(), p[ok].max()) * 2
            axis.loglog([low, high], [low, high], "k--", lw=0.8, label="1:1")
        axis.set_xlabel(f"observed {label}")
        axis.set_ylabel(f"predicted {label}")
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=8)
    figure.suptitle(f"Predicted against observed: {dataset.attrs.get('title', '')}")
    return figure
