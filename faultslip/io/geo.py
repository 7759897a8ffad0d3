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
    return trace


def trace_length(trace) -> float:
    """Geodetic length of a trace in m (WGS84 ellipsoid, obspy.geodetics.gps2dist_azimuth)."""
    from obspy.geodetics import gps2dist_azimuth  # heavy: imported where used

    return float(sum(gps2dist_azimuth(lat1, lon1, lat2, lon2)[0]
                     for (lon1, lat1), (lon2, lat2) in zip(trace[:-1], trace[1:])))


def densify(trace, spacing=1000.0):
    """Points along a trace every ~``spacing`` m (great-circle interpolation), as (lon, lat)."""
    from obspy.geodetics import gps2dist_azimuth  # heavy: imported where used

    points = [trace[0]]
    for (lon1, lat1), (lon2, lat2) in zip(trace[:-1], trace[1:]):
        distance = gps2dist_azimuth(lat1, lon1, lat2, lon2)[0]
        count = max(1, int(math.ceil(distance / spacing)))
        for fraction in np.arange(1, count + 1) / count:
            points.append(_interpolate(lon1, lat1, lon2, lat2, fraction))
    return np.array(points)


def _interpolate(lon1, lat1, lon2, lat2, fraction):
    """Point a fraction of the way along the great circle (spherical slerp)."""
    p1 = np.array(_unit(lon1, lat1))
    p2 = np.array(_unit(lon2, lat2))
    omega = math.acos(max(-1.0, min(1.0, float(p1 @ p2))))
    if omega < 1e-12:
        return lon1, lat1
    point = (math.sin((1 - fraction) * omega) * p1 + math.sin(fraction * omega) * p2) / math.sin(omega)
    return math.degrees(math.atan2(point[1], point[0])), math.degrees(math.asin(point[2] / np.linalg.norm(point)))


def _unit(lon, lat):
    lon, lat = math.radians(lon), math.radians(lat)
    return math.cos(lat) * math.cos(lon), math.cos(lat) * math.sin(lon), math.sin(lat)


def nearest_segment(lon, lat, traces, block=4096, pairs=False):
    """Index of and distance (m) to the nearest trace for every (lat, lon) cell of the grid (great circles);
    with ``pairs``, for the points (lon[i], lat[i]) instead."""
    from obspy.geodetics import degrees2kilometers, locations2degrees  # heavy: imported where used

    points = [densify(trace) for trace in traces]
    owner = np.concatenate([np.full(len(p), i) for i, p in enumerate(points)])
    stacked = np.concatenate(points)
    if pairs:
        grid_lat, grid_lon = np.asarray(lat, float), np.asarray(lon, float)
    else:
        grid_lat, grid_lon = np.meshgrid(lat, lon, indexing="ij")
    flat_lat, flat_lon = grid_lat.ravel(), grid_lon.ravel()
    index = np.empty(flat_lat.size, dtype=np.int64)
    distance = np.empty(flat_lat.size)
    for start in range(0, flat_lat.size, block):  # bounded memory: cells x points in blocks
        sl = slice(start, start + block)
        degrees = locations2degrees(flat_lat[sl, None], flat_lon[sl, None], stacked[None, :, 1], stacked[None, :, 0])
        nearest = np.argmin(degrees, axis=1)
        index[sl] = owner[nearest]
        distance[sl] = degrees2kilometers(degrees[np.arange(nearest.size), nearest]) * 1e3
    return index.reshape(grid_lat.shape), distance.reshape(grid_lat.shape)


def distance_to_trace(lon, lat, trace) -> np.ndarray:
    """Great-circle distance (m) from each point to a trace (densified every ~1 km)."""
    _, distance = nearest_segment(np.asarray(lon, float).ravel(), np.asarray(lat, float).ravel(), [trace],
                                  pairs=True)
    return distance
