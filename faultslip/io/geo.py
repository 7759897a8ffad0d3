"""Fault traces on the globe: parsing, lengths and distances (great circles through obspy.geodetics)."""

from __future__ import annotations

import math

import numpy as np

from faultslip.errors import InputError


def _check_lon_lat(lon, lat, where):
    lon, lat = np.asarray(lon, float), np.asarray(lat, float)
    if not (np.all(np.isfinite(lon)) and np.all(np.isfinite(lat))):
        raise InputError(f"{where}: longitude and latitude must be finite numbers")
    if np.any(np.abs(lon) > 180):
        raise InputError(f"{where}: longitude {lon[np.argmax(np.abs(lon))]:g} is out of range [-180, 180]")
    if np.any(np.abs(lat) > 90):
        raise InputError(f"{where}: latitude {lat[np.argmax(np.abs(lat))]:g} is out of range [-90, 90]")


def parse_trace(text: str, where: str) -> np.ndarray:
    """``"lon lat; lon lat; ..."`` (degrees) -> (n, 2) array, n >= 2."""
    vertices = []
    for part in str(text).split(";"):
        part = part.strip()
        if not part:
            continue
        fields = part.replace(",", " ").split()
        if len(fields) != 2:
            raise InputError(f"{where}: a trace vertex must be 'lon lat', got {part!r}")
        try:
            vertices.append((float(fields[0]), float(fields[1])))
        except ValueError:
            raise InputError(f"{where}: a trace vertex must be two numbers 'lon lat', got {part!r}") from None
    return trace_from_vertices(vertices, where, "a segment trace")


def trace_from_vertices(vertices, where: str, what: str = "a fault trace") -> np.ndarray:
    """(lon, lat) vertices as an (n, 2) trace: at least 2, in range; one sentence otherwise."""
    if len(vertices) < 2:
        raise InputError(f"{where}: {what} needs at least 2 vertices, got {len(vertices)}")
    trace = np.array(vertices)
    _check_lon_lat(trace[:, 0], trace[:, 1], where)
    _check_simple(trace, where, what)
    return trace


#: The sharpest turn a trace may take between two segments (degrees): a fault bends, it does not double back.
MAX_TURN = 170.0


def _check_simple(trace: np.ndarray, where: str, what: str) -> None:
    """Refuse a trace that repeats a vertex, doubles back on itself (a turn sharper than :data:`MAX_TURN`), or
    whose segments cross: each would count part of the fault twice, its length and moment with it (a self-retracing
    trace raised a map's moment 1.4-fold without a word). Planar in (lon cos lat, lat) about the trace's mean
    latitude: a fault's extent is small against the Earth's curvature."""
    scale = math.cos(math.radians(float(np.mean(trace[:, 1]))))
    points = np.column_stack([trace[:, 0] * scale, trace[:, 1]])
    steps = np.diff(points, axis=0)
    lengths = np.hypot(steps[:, 0], steps[:, 1])
    if np.any(lengths == 0):
        raise InputError(f"{where}: {what} repeats a vertex (vertex {int(np.argmax(lengths == 0)) + 2}); give each "
                         "vertex once")
    turns = np.einsum("ij,ij->i", steps[:-1], steps[1:]) / (lengths[:-1] * lengths[1:])
    back = np.flatnonzero(turns < math.cos(math.radians(MAX_TURN)))
    if back.size:
        raise InputError(f"{where}: {what} doubles back on itself at vertex {int(back[0]) + 2} (a turn sharper than "
                         f"{MAX_TURN:g} degrees): each part of a fault is traced once")
    count = steps.shape[0]
    for i in range(count - 2):  # each segment against every later one but its neighbour
        a, b = points[i], points[i + 1]
        c, d = points[i + 2:-1], points[i + 3:]
        cross = _segments_cross(a, b, c, d)
        if cross.any():
            j = i + 2 + int(np.argmax(cross))
            raise InputError(f"{where}: {what} crosses itself (segment {i + 1} and segment {j + 1}); a fault trace "
                             "never crosses itself")


def _orientation(p, q, r):
    """Sign of the turn p -> q -> r (broadcast over rows of ``r`` or ``q``)."""
    return np.sign((q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0]))


def _segments_cross(a, b, c, d) -> np.ndarray:
    """Whether segment a-b properly crosses each segment c[k]-d[k] (touching ends do not count)."""
    return ((_orientation(a, b, c) * _orientation(a, b, d) < 0)
            & (_orientation(c, d, np.broadcast_to(a, c.shape)) * _orientation(c, d, np.broadcast_to(b, c.shape)) < 0))


def trace_length(trace) -> float:
    """Geodetic length of a trace in m (WGS84 ellipsoid, obspy.geodetics.gps2dist_azimuth)."""
    from obspy.geodetics import gps2dist_azimuth  # heavy: imported where used

    return float(sum(gps2dist_azimuth(lat1, lon1, lat2, lon2)[0]
                     for (lon1, lat1), (lon2, lat2) in zip(trace[:-1], trace[1:])))


#: Mean Earth radius (m) of obspy's degrees2kilometers, so distances match obspy's spherical ones.
EARTH_RADIUS = 6371e3


def azimuth(start, end) -> float:
    """Initial great-circle azimuth from ``start`` to ``end`` (lon, lat in degrees), degrees clockwise from north."""
    lon1, lat1, lon2, lat2 = map(math.radians, (*start, *end))
    return math.degrees(math.atan2(math.sin(lon2 - lon1) * math.cos(lat2), math.cos(lat1) * math.sin(lat2)
                                   - math.sin(lat1) * math.cos(lat2) * math.cos(lon2 - lon1))) % 360.0


def great_circle(lon1, lat1, lon2, lat2):
    """Great-circle distance (m) between points given in degrees (haversine on a sphere of :data:`EARTH_RADIUS`),
    broadcast like numpy."""
    lon1, lat1, lon2, lat2 = (np.radians(np.asarray(v, float)) for v in (lon1, lat1, lon2, lat2))
    half = np.sin((lat2 - lat1) / 2) ** 2 + np.cos(lat1) * np.cos(lat2) * np.sin((lon2 - lon1) / 2) ** 2
    return 2 * EARTH_RADIUS * np.arcsin(np.sqrt(np.clip(half, 0.0, 1.0)))


def destination(lon: float, lat: float, bearing: float, distance: float) -> tuple[float, float]:
    """The point ``distance`` m from (lon, lat) along ``bearing`` degrees from north (a sphere of
    :data:`EARTH_RADIUS`)."""
    angle, course = distance / EARTH_RADIUS, math.radians(bearing)
    phi, lam = math.radians(lat), math.radians(lon)
    phi2 = math.asin(math.sin(phi) * math.cos(angle) + math.cos(phi) * math.sin(angle) * math.cos(course))
    lam2 = lam + math.atan2(math.sin(course) * math.sin(angle) * math.cos(phi),
                            math.cos(angle) - math.sin(phi) * math.sin(phi2))
    return math.degrees(lam2), math.degrees(phi2)


def _unit_vectors(lon, lat) -> np.ndarray:
    """(n, 3) unit vectors of points given in degrees."""
    lon, lat = np.radians(np.asarray(lon, float)), np.radians(np.asarray(lat, float))
    return np.stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)], axis=-1)


def _densified_vectors(traces, spacing: float = 1000.0):
    """Unit vectors of points every ~``spacing`` m along every trace (great circles), and each point's trace.

    Vectorised over all segments of all traces at once: a map of 60,000 faults densifies in
    seconds. Each segment gets ceil(length / spacing) intervals by spherical interpolation (slerp).
    """
    firsts, starts, ends, owners = [], [], [], []
    for number, trace in enumerate(traces):
        vectors = _unit_vectors(trace[:, 0], trace[:, 1])
        firsts.append(vectors[:1])
        starts.append(vectors[:-1])
        ends.append(vectors[1:])
        owners.append(np.full(len(vectors) - 1, number))
    p1, p2, owner = np.concatenate(starts), np.concatenate(ends), np.concatenate(owners)
    omega = np.arccos(np.clip(np.einsum("ij,ij->i", p1, p2), -1.0, 1.0))
    counts = np.maximum(1, np.ceil(omega * EARTH_RADIUS / spacing)).astype(np.int64)
    segment = np.repeat(np.arange(p1.shape[0]), counts)
    step = np.arange(segment.size) - np.repeat(np.cumsum(counts) - counts, counts) + 1
    fraction = step / counts[segment]
    angle = omega[segment]
    sine = np.sin(angle)
    tiny = sine < 1e-12  # coincident vertices: the point itself
    safe = np.where(tiny, 1.0, sine)
    a = np.where(tiny, 1.0 - fraction, np.sin((1.0 - fraction) * angle) / safe)
    b = np.where(tiny, fraction, np.sin(fraction * angle) / safe)
    points = a[:, None] * p1[segment] + b[:, None] * p2[segment]
    points /= np.linalg.norm(points, axis=1)[:, None]
    return (np.concatenate(firsts + [points]),
            np.concatenate([np.arange(len(traces)), owner[segment]]))


def densify(trace, spacing=1000.0):
    """Points along a trace every ~``spacing`` m (great-circle interpolation), as (lon, lat)."""
    vectors, _ = _densified_vectors([np.asarray(trace, float)], spacing)
    return np.column_stack([np.degrees(np.arctan2(vectors[:, 1], vectors[:, 0])),
                            np.degrees(np.arcsin(np.clip(vectors[:, 2], -1.0, 1.0)))])


def nearest_segment(lon, lat, traces, block=None, pairs=False):
    """Index of and distance (m) to the nearest trace for every (lat, lon) cell of the grid (great circles);
    with ``pairs``, for the points (lon[i], lat[i]) instead.

    The traces are densified every ~1 km and put in a k-d tree of unit vectors (the chord is
    monotonic in the great-circle angle), so the cost grows as (cells + points) log(points)
    rather than cells x points; the distance is the angle times obspy's mean Earth radius.
    """
    from scipy.spatial import cKDTree  # heavy: imported where used

    stacked, owner = _densified_vectors([np.asarray(t, float) for t in traces])
    if pairs:
        grid_lat, grid_lon = np.asarray(lat, float), np.asarray(lon, float)
    else:
        grid_lat, grid_lon = np.meshgrid(lat, lon, indexing="ij")
    queries = _unit_vectors(grid_lon.ravel(), grid_lat.ravel())
    chord, nearest = cKDTree(stacked).query(queries, k=1)
    angle = 2.0 * np.arcsin(np.clip(chord / 2.0, 0.0, 1.0))
    return owner[nearest].reshape(grid_lat.shape), (angle * EARTH_RADIUS).reshape(grid_lat.shape)


def distance_to_trace(lon, lat, trace) -> np.ndarray:
    """Great-circle distance (m) from each point to a trace (densified every ~1 km)."""
    _, distance = nearest_segment(np.asarray(lon, float).ravel(), np.asarray(lat, float).ravel(), [trace],
                                  pairs=True)
    return distance
