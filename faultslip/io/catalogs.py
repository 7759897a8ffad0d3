"""Earthquake catalogs in and out: QuakeML through obspy, and plain CSV.

A CSV catalog has ``name (unit)`` headers, one event per row::

    time,latitude (degree),longitude (degree),depth (km),magnitude,magnitude_type,name,source
    1966-06-28T04:26:14,35.955,-120.498,9,6.0,Mw,Parkfield 1966,Bakun & McEvilly (1984)

``time`` is ISO 8601 in UTC (a date alone is midnight); ``depth``, ``magnitude_type``, ``name`` and
any ``source...`` columns are optional. QuakeML (``.xml``, ``.quakeml``, ``.qml``) is read with
:func:`obspy.read_events`, each event's preferred (else first) origin and magnitude; events with
neither are counted and left out, never silently.

A QuakeML catalog faultslip writes carries a checksum of its events (:func:`quakeml_checksum`) in an element
of its own namespace (:data:`QUAKEML_NAMESPACE`), which other programs skip; read back, a catalog that does not
match it is refused, one of an older faultslip (no checksum) is read with a warning, and another program's
carries nothing to check.
"""

from __future__ import annotations

import hashlib
import io
import json
import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.io.atomic import atomic_path
from faultslip.io.resources import check_input_file, read_unit_csv
from faultslip.units import to_si
from faultslip.datasets import ToXarray

QUAKEML_SUFFIXES = (".xml", ".quakeml", ".qml")
#: The XML namespace of faultslip's own QuakeML element, the checksum of the events it wrote.
QUAKEML_NAMESPACE = "urn:x-faultslip:quakeml:1"
#: How a catalog faultslip wrote describes itself (write_quakeml): one without a checksum is an older faultslip's.
DESCRIPTION_START = "faultslip"
CATALOG_COLUMNS = {"time", "latitude", "longitude", "depth", "magnitude", "magnitude_type", "name"}


@dataclass
class Catalog(ToXarray):
    """Events sorted by time: UTC times as datetime64[ms], degrees, depth in m, magnitudes."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'time': 's', 'latitude': 'degree_north', 'longitude': 'degree_east', 'depth': 'm', 'magnitude': '1'}
    DIMENSIONS = {'time': 'event', 'latitude': 'event', 'longitude': 'event', 'depth': 'event', 'magnitude': 'event'}

    time: np.ndarray
    latitude: np.ndarray
    longitude: np.ndarray
    depth: np.ndarray
    magnitude: np.ndarray
    magnitude_type: list
    name: list
    source: list
    path: str = ""
    notes: list = field(default_factory=list)

    def __len__(self) -> int:
        return int(self.time.size)

    def subset(self, mask) -> "Catalog":
        mask = np.asarray(mask, dtype=bool)
        pick = lambda values: [v for v, keep in zip(values, mask) if keep]  # noqa: E731
        return Catalog(self.time[mask], self.latitude[mask], self.longitude[mask], self.depth[mask],
                       self.magnitude[mask], pick(self.magnitude_type), pick(self.name), pick(self.source),
                       self.path, list(self.notes))

    def seconds(self) -> np.ndarray:
        """Times as seconds since 1970-01-01 UTC (float)."""
        return self.time.astype("datetime64[ms]").astype(np.int64) / 1e3


def parse_time(text, where: str) -> np.datetime64:
    """An ISO 8601 UTC time (or date) as datetime64[ms]; one sentence if it is not one."""
    from obspy import UTCDateTime  # heavy: imported where used

    try:
        moment = UTCDateTime(str(text).strip())
    except Exception:  # obspy raises TypeError, ValueError or its own for bad strings
        raise InputError(f"{where}: {text!r} is not an ISO 8601 time such as 1966-06-28T04:26:14") from None
    return np.datetime64(int(round(moment.timestamp * 1e3)), "ms")


def _check_file(path: Path, what: str) -> None:
    check_input_file(path, what, "catalog")  # QuakeML is verbose: ~2 kB an event
    if path.stat().st_size == 0:
        raise InputError(f"{what} {path.name} is empty")


def read_catalog(path) -> Catalog:
    """A QuakeML or CSV catalog, sorted by time. Raises :class:`InputError` in one sentence.

    Parameters
    ----------
    path : str or path
        The catalog.

    Returns
    -------
    Catalog
        Times, coordinates (degrees), depths (m) and magnitudes.
    """
    path = Path(path)
    _check_file(path, "catalog")
    suffix = path.suffix.lower()
    if suffix in QUAKEML_SUFFIXES:
        catalog = _read_quakeml(path)
    elif suffix == ".csv":
        catalog = _read_csv(path)
    else:
        raise InputError(f"catalog {path.name}: unknown format {suffix or '(no suffix)'!r}; give QuakeML "
                         f"({', '.join(QUAKEML_SUFFIXES)}) or CSV (.csv)")
    if len(catalog) == 0:
        raise InputError(f"catalog {path.name} has no events with an origin time, location and magnitude")
    order = np.argsort(catalog.time, kind="stable")
    return catalog if np.all(order == np.arange(len(catalog))) else _reorder(catalog, order)


def _reorder(catalog: Catalog, order) -> Catalog:
    pick = lambda values: [values[i] for i in order]  # noqa: E731
    return Catalog(catalog.time[order], catalog.latitude[order], catalog.longitude[order], catalog.depth[order],
                   catalog.magnitude[order], pick(catalog.magnitude_type), pick(catalog.name), pick(catalog.source),
                   catalog.path, catalog.notes)


def quakeml_checksum(catalog) -> str:
    """SHA-256 of what an obspy Catalog says of its events, as QuakeML carries it (times to the microsecond):
    its description and comments, and for each event in order its origins (time, latitude, longitude, depth),
    magnitudes (value, type), which of them are preferred, descriptions, agency and comments.

    Parameters
    ----------
    catalog : obspy.core.event.Catalog
        The events.

    Returns
    -------
    str
        64 hex digits.
    """
    def text(value):
        return None if value is None else str(value)

    def number(value):
        return None if value is None else repr(float(value))

    def position(items, preferred):
        return next((index for index, item in enumerate(items) if item.resource_id == preferred), None)

    body = [text(catalog.description), [text(c.text) for c in catalog.comments]]
    for event in catalog:
        body.append([[[text(o.time), number(o.latitude), number(o.longitude), number(o.depth)] for o in event.origins],
                     [[number(m.mag), text(m.magnitude_type)] for m in event.magnitudes],
                     position(event.origins, event.preferred_origin_id),
                     position(event.magnitudes, event.preferred_magnitude_id),
                     [text(d.text) for d in event.event_descriptions],
                     text(event.creation_info.agency_id) if event.creation_info else None,
                     [text(c.text) for c in event.comments]])
    return hashlib.sha256(json.dumps(body).encode("utf-8")).hexdigest()


def _check_quakeml(events, data: bytes, path: Path) -> None:
    """Refuse, in one sentence, a catalog faultslip wrote that no longer matches the checksum written with it."""
    stated = (getattr(events, "extra", None) or {}).get("checksum") or {}
    namespace = str(stated.get("namespace", ""))
    # faultslip's namespace, or one a damaged byte away from it (its declaration in the file's header flipped): not
    # another agency's "checksum" element, which is theirs to check
    if len(namespace) == len(QUAKEML_NAMESPACE) and sum(a != b for a, b in zip(namespace, QUAKEML_NAMESPACE)) <= 2:
        if stated.get("value") != quakeml_checksum(events):
            raise InputError(f"catalog {path.name} does not match the checksum faultslip wrote with it: its events "
                             "were edited or damaged since; write it again (faultslip simulate --events)")
    elif QUAKEML_NAMESPACE.encode("ascii") in data or b"<faultslip:checksum" in data:  # its element or namespace
        raise InputError(f"catalog {path.name} was written by faultslip with a checksum that is now missing; write "
                         "it again (faultslip simulate --events)")
    elif str(events.description or "").startswith(DESCRIPTION_START):
        warnings.warn(f"catalog {path.name} was written by a faultslip that did not yet add a checksum to its "
                      "QuakeML: it is read unchecked", stacklevel=4)


def _read_quakeml(path: Path) -> Catalog:
    from obspy import read_events  # heavy: imported where used

    data = gate.read_bytes(path, "catalog", "catalog")
    with gate.decoding(path, "catalog", "QuakeML", silence=True):
        events = read_events(io.BytesIO(data), format="QUAKEML")
    _check_quakeml(events, data, path)
    rows, skipped = [], 0
    for event in events:
        origin = event.preferred_origin() or (event.origins[0] if event.origins else None)
        magnitude = event.preferred_magnitude() or (event.magnitudes[0] if event.magnitudes else None)
        if origin is None or magnitude is None or origin.time is None or origin.latitude is None \
                or origin.longitude is None or magnitude.mag is None:
            skipped += 1
            continue
        names = [d.text for d in event.event_descriptions if d.text]
        rows.append((np.datetime64(int(round(origin.time.timestamp * 1e3)), "ms"), float(origin.latitude),
                     float(origin.longitude), float(origin.depth) if origin.depth is not None else math.nan,
                     float(magnitude.mag), magnitude.magnitude_type or "", names[0] if names else str(event.resource_id),
                     (event.creation_info.agency_id if event.creation_info and event.creation_info.agency_id else "")))
    for row in rows:
        _check_depth(row[3], f"catalog {path.name}, event {row[6]!r}")
    catalog = _from_rows(rows, str(path))
    if skipped:
        catalog.notes.append(f"{skipped} event(s) in {path.name} had no origin time, location or magnitude and were "
                             "left out")
    _check_locations(catalog, path.name)
    return catalog


def _from_rows(rows, path: str) -> Catalog:
    columns = list(zip(*rows)) if rows else [[]] * 8
    return Catalog(np.array(columns[0], dtype="datetime64[ms]"), np.array(columns[1], float),
                   np.array(columns[2], float), np.array(columns[3], float), np.array(columns[4], float),
                   list(columns[5]), list(columns[6]), list(columns[7]), path)


#: Shallowest and deepest hypocentres accepted (m, positive down). Catalogs measure depth from sea
#: level, so an event under mountains can sit above it: ComCat's shallowest are about -3.5 km.
#: The deepest earthquakes are about 700 km down.
DEPTH_RANGE = (-4e3, 800e3)


def _check_depth(depth: float, where: str) -> None:
    """A hypocentre depth (m, positive down) within the Earth's seismogenic range; NaN (not given) passes."""
    if not math.isnan(depth) and not DEPTH_RANGE[0] <= depth <= DEPTH_RANGE[1]:
        raise InputError(f"{where}: depth {depth / 1e3:g} km is outside {DEPTH_RANGE[0] / 1e3:g} to "
                         f"{DEPTH_RANGE[1] / 1e3:g} km (positive down; a few km above sea level at most, as on land)")


def _check_locations(catalog: Catalog, name: str) -> None:
    bad = ~((np.abs(catalog.latitude) <= 90) & (np.abs(catalog.longitude) <= 180) & np.isfinite(catalog.magnitude))
    if bad.any():
        index = int(np.argmax(bad))
        raise InputError(f"catalog {name}: event {catalog.name[index]!r} has latitude {catalog.latitude[index]:g}, "
                         f"longitude {catalog.longitude[index]:g}, magnitude {catalog.magnitude[index]:g}: out of range")


def _read_csv(path: Path) -> Catalog:
    label = f"catalog {path.name}"
    header, cells = read_unit_csv(path, label)
    names = [name for name, _ in header]
    units = dict(header)
    for name in names:
        if name not in CATALOG_COLUMNS and not name.startswith("source"):
            raise InputError(f"{label}: unknown column {name!r}; a catalog has {', '.join(sorted(CATALOG_COLUMNS))} "
                             "and source columns")
    for required in ("time", "latitude", "longitude", "magnitude"):
        if required not in names:
            raise InputError(f"{label} lacks the column {required!r}")
    for column in ("latitude", "longitude"):
        if units.get(column) not in (None, "degree", "degrees"):
            raise InputError(f"{label}: {column} must be in degrees, the header says {units[column]!r}")
    depth_unit = units.get("depth")
    if "depth" in names and depth_unit is None:
        raise InputError(f"{label}: the depth column needs a unit in its header, e.g. 'depth (km)'")
    rows = []
    for line, values in cells:
        row = dict(zip(names, values))
        where = f"{label}, row {line}"

        def number(column):
            try:
                value = float(row[column])
            except ValueError:
                raise InputError(f"{where}: {column} {row[column]!r} is not a number") from None
            if not math.isfinite(value):
                raise InputError(f"{where}: {column} must be finite")
            return value

        depth = (to_si(f"{row['depth']} {depth_unit}", "length", f"{where}, depth")
                 if row.get("depth") else math.nan)
        _check_depth(depth, where)
        sources = "; ".join(row[c] for c in names if c.startswith("source") and row[c])
        rows.append((parse_time(row["time"], f"{where}, time"), number("latitude"), number("longitude"), depth,
                     number("magnitude"), row.get("magnitude_type", ""), row.get("name") or f"row {line}", sources))
    catalog = _from_rows(rows, str(path))
    _check_locations(catalog, path.name)
    return catalog


def write_quakeml(times, latitude, longitude, depth, magnitudes, path, names=None, magnitude_type: str = "Mw",
                  agency: str = "faultslip", comment: str = "") -> None:
    """Events as an obspy Catalog in QuakeML: UTC times as datetime64 or seconds since 1970, degrees,
    depth in m. Written through a temporary file and renamed (atomic).

    Parameters
    ----------
    times : array_like
        datetime64 or seconds since 1970.
    latitude, longitude : array_like
        Degrees.
    depth : array_like
        m.
    magnitudes : array_like
        Mw.
    path : str or path
        The file.
    names : list, optional
        Event names.
    magnitude_type : str
        Mw.
    agency : str
        The agency.
    comment : str
        A comment.

    Returns
    -------
    None
    """
    from obspy import UTCDateTime  # heavy: imported where used
    from obspy.core import event as quakeml  # heavy: imported where used

    catalog = quakeml.Catalog(description=comment or "faultslip synthetic events")
    count = len(magnitudes)
    for index in range(count):
        when = times[index]
        # full precision: a datetime64 by its nanoseconds (it was cut to milliseconds), seconds as they are
        moment = (UTCDateTime(ns=int(np.datetime64(when, "ns").astype(np.int64))) if isinstance(when, np.datetime64)
                  else UTCDateTime(float(when)))
        origin = quakeml.Origin(time=moment, latitude=float(latitude[index]), longitude=float(longitude[index]),
                        depth=float(depth[index]))
        magnitude = quakeml.Magnitude(mag=float(magnitudes[index]), magnitude_type=magnitude_type, origin_id=origin.resource_id)
        event = quakeml.Event(origins=[origin], magnitudes=[magnitude], creation_info=quakeml.CreationInfo(agency_id=agency),
                      event_descriptions=[quakeml.EventDescription(text=names[index] if names else f"event {index + 1}")])
        if comment:
            event.comments.append(quakeml.Comment(text=comment))
        event.preferred_origin_id = origin.resource_id
        event.preferred_magnitude_id = magnitude.resource_id
        catalog.append(event)
    from obspy.core.util import AttribDict  # heavy: imported where used

    catalog.extra = AttribDict({"checksum": AttribDict({"value": quakeml_checksum(catalog),
                                                        "namespace": QUAKEML_NAMESPACE})})
    with atomic_path(path) as temporary, gate.quiet():
        catalog.write(str(temporary), format="QUAKEML", nsmap={"faultslip": QUAKEML_NAMESPACE})
