"""Rough surfaces (seed 000): profiles and height maps, their statistics, and contact by truncation.

**Surfaces.** A profile (x, z) or a map z(x, y) on a regular grid, in SI, levelled by a least-squares
line or plane (seed 000 Appendix One: the Talysurf map was digitised with a tilt). Read from CSV
(``x (um), z (um)`` for a profile; ``x (um), y (um), z (um)`` rows for a map) or netCDF (a 2-D
``height`` with units on ``y, x``), or generated: a Gaussian surface with a given RMS and correlation
length (exponential autocorrelation, Whitehouse & Archard's model, seed 000 eq. 14), seeded.

**Statistics** (seed 000 §1.7, AD1.2): CLA (Ra, eq. 12), RMS (Rq), skewness and kurtosis of the heights;
the autocorrelation along x (eq. 13) and its correlation length beta* (where it falls to 1/e); the
summits (local maxima: 3-point on a profile, 8-neighbour on a map), their density, the spread of their
heights and their mean radius 1 / ``|curvature|`` (second differences); the height density by a Gaussian
kernel estimate (non-parametric, as the seed reads it off the map, fig. AD2.2).

**Contact by truncation** (seed 000 §5.3, after Pullen & Williamson): the surface is pressed against
its own inverted copy (the seed's squeezing of two maps) or a flat. At each approach the overlapping
cells are in contact: the real area A, the number of contacts (connected patches), and, with all
contacts plastic at flow pressure p_c, the load L = p_c A (eq. 23) and the mean pressure L / A = p_c.
The volume the truncated tips displace raises the whole surface evenly (Pullen & Williamson), which
the approach is corrected for.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from faultslip.errors import InputError
from faultslip.friction.contact import (contact_modulus, elastic_contact_hardness, greenwood_williamson,
                                        hirst_hollander_index, plasticity_index)
from faultslip.io.report import Report
from faultslip.io.resources import open_netcdf, read_numeric_csv
from faultslip.units import takes_units, to_si, unit_factor
from faultslip.datasets import ToXarray

#: a surface holds at most this many heights (a map of 4000 x 4000)
MAX_HEIGHTS = 16_000_000


@dataclass
class Surface(ToXarray):
    """Heights (m) on a regular grid: shape (n,) for a profile, (ny, nx) for a map; spacings in m."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'height': 'm', 'dx': 'm', 'dy': 'm'}

    height: np.ndarray
    dx: float
    dy: float | None = None
    source: str = ""

    def __post_init__(self):
        self.height = np.asarray(self.height, dtype=float)
        if self.height.ndim not in (1, 2) or min(self.height.shape) < 8:
            raise InputError(f"surface {self.source}: a profile or map needs at least 8 heights along each side")
        if self.height.size > MAX_HEIGHTS:
            raise InputError(f"surface {self.source}: {self.height.size:,} heights exceed {MAX_HEIGHTS:,}")
        if not np.all(np.isfinite(self.height)) or np.max(np.abs(self.height)) > 1.0:
            raise InputError(f"surface {self.source}: heights must be finite and within 1 m (a roughness, not a "
                             "landscape)")
        for name, value in (("dx", self.dx), ("dy", self.dy)):
            if value is not None and not (math.isfinite(value) and 1e-12 <= value <= 1.0):
                raise InputError(f"surface {self.source}: the grid spacing {name} must lie between 1 pm and 1 m")
        if self.height.ndim == 2 and self.dy is None:
            self.dy = self.dx

    @property
    def is_map(self) -> bool:
        return self.height.ndim == 2

    @property
    def cell_area(self) -> float:
        return self.dx * (self.dy if self.is_map else 1.0)

    def levelled(self) -> "Surface":
        """Minus its least-squares line (profile) or plane (map): seed 000 Appendix One."""
        z = self.height
        if not self.is_map:
            x = np.arange(z.size) * self.dx
            slope, intercept = np.polyfit(x, z, 1)
            return Surface(z - (slope * x + intercept), self.dx, None, self.source)
        ny, nx = z.shape
        y, x = np.meshgrid(np.arange(ny) * self.dy, np.arange(nx) * self.dx, indexing="ij")
        design = np.column_stack([x.ravel(), y.ravel(), np.ones(z.size)])
        coefficients, *_ = np.linalg.lstsq(design, z.ravel(), rcond=None)
        return Surface(z - (design @ coefficients).reshape(z.shape), self.dx, self.dy, self.source)


@takes_units(rms="length", correlation_length="length", spacing="length")
def gaussian_surface(rms: float, correlation_length: float, size: int = 256, spacing: float | None = None,
                     profile: bool = False, seed: int = 0) -> Surface:
    """A Gaussian random surface with exponential autocorrelation C(beta) = exp(-beta / beta*) (seed 000
    eq. 14): white noise filtered in Fourier space by the square root of the exponential's spectrum,
    rescaled to the exact RMS. ``spacing`` defaults to beta* / 8.

    Parameters
    ----------
    rms : float
        RMS height (m).
    correlation_length : float
        beta* (m).
    size : int
        Points a side.
    spacing : float, optional
        Sample spacing (m).
    profile : bool
        A profile rather than a map.
    seed : int
        The noise's seed.

    Returns
    -------
    Surface
    """
    if not (rms > 0 and correlation_length > 0 and 16 <= size <= 4096):
        raise InputError("a synthetic surface needs a positive RMS and correlation length and 16 to 4096 points a side")
    spacing = spacing or correlation_length / 8.0
    rng = np.random.default_rng(seed)
    shape = (size,) if profile else (size, size)
    noise = rng.standard_normal(shape)
    frequencies = [np.fft.fftfreq(n, d=spacing) * 2 * np.pi for n in shape]
    if profile:
        k2 = frequencies[0] ** 2
        spectrum = 2 * correlation_length / (1 + k2 * correlation_length ** 2)  # 1-D transform of e^(-|x|/b)
    else:
        ky, kx = np.meshgrid(*frequencies, indexing="ij")
        k2 = kx ** 2 + ky ** 2
        spectrum = 2 * np.pi * correlation_length ** 2 / (1 + k2 * correlation_length ** 2) ** 1.5  # 2-D transform
    height = np.real(np.fft.ifftn(np.fft.fftn(noise) * np.sqrt(spectrum)))
    height -= height.mean()
    height *= rms / height.std()
    return Surface(height, spacing, None if profile else spacing, f"Gaussian, RMS {rms:g} m, beta* {correlation_length:g} m")


def read_surface(path) -> Surface:
    """A profile or map from CSV or netCDF (see the module); heights and lengths with units.

    Parameters
    ----------
    path : str or path
        The surface file.

    Returns
    -------
    Surface
        Heights (m) on a grid of spacing (m).
    """
    path = Path(path)
    label = f"surface {path.name}" if path.name else "surface"  # "/" has no name
    if path.suffix.lower() == ".nc":
        data = open_netcdf(path, "surface")
        if "height" not in data:
            raise InputError(f"{label} needs a 'height' variable on (y, x) or (x)")
        height = data["height"]
        factor = unit_factor(height.attrs.get("units") or "", "length", f"{label}, height")
        spacings = []
        for dim in height.dims:
            coordinate = data[dim] if dim in data.coords else None
            if coordinate is None or coordinate.size < 2:
                raise InputError(f"{label}: the dimension {dim!r} needs a coordinate with units")
            step = np.diff(coordinate.values.astype(float))
            if not np.allclose(step, step[0], rtol=1e-6) or step[0] <= 0:
                raise InputError(f"{label}: {dim} must be evenly spaced and increasing")
            spacings.append(step[0] * unit_factor(coordinate.attrs.get("units") or "", "length", f"{label}, {dim}"))
        values = height.values * factor
        if values.ndim == 1:
            return Surface(values, spacings[0], None, path.name)
        return Surface(values, spacings[1], spacings[0], path.name)
    columns = read_numeric_csv(path, label)
    if "z" not in columns or "x" not in columns:
        raise InputError(f"{label} needs columns 'x (unit)' and 'z (unit)' (and 'y (unit)' for a map)")
    si = {}
    for name, (values, unit) in columns.items():
        if name not in ("x", "y", "z"):
            raise InputError(f"{label}: unknown column {name!r} (a surface has x, y and z)")
        if unit is None:
            raise InputError(f"{label}: column {name!r} needs a unit, e.g. '{name} (um)'")
        si[name] = values * unit_factor(unit, "length", f"{label}, {name}")
    if "y" not in si:
        step = np.diff(si["x"])
        if step.size < 7 or np.any(step <= 0) or not np.allclose(step, step[0], rtol=1e-6):
            raise InputError(f"{label}: x must increase in even steps (at least 8 points)")
        return Surface(si["z"], step[0], None, path.name)
    xs, ys = np.unique(si["x"]), np.unique(si["y"])
    if xs.size * ys.size != si["z"].size or xs.size < 8 or ys.size < 8:
        raise InputError(f"{label}: the x, y rows must fill a regular grid ({xs.size} x values and {ys.size} y values "
                         f"for {si['z'].size} heights)")
    grid = np.full((ys.size, xs.size), np.nan)
    grid[np.searchsorted(ys, si["y"]), np.searchsorted(xs, si["x"])] = si["z"]
    if np.isnan(grid).any():
        raise InputError(f"{label}: some (x, y) points repeat, so others are missing")
    dx, dy = np.diff(xs), np.diff(ys)
    if not (np.allclose(dx, dx[0], rtol=1e-6) and np.allclose(dy, dy[0], rtol=1e-6)):
        raise InputError(f"{label}: x and y must be evenly spaced")
    return Surface(grid, dx[0], dy[0], path.name)


def autocorrelation(surface: Surface, max_lag: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(lag in m, normalised autocorrelation C(beta) / C(0)) along x (seed 000 eq. 13), averaged over rows."""
    z = surface.height if surface.is_map else surface.height[None, :]
    z = z - z.mean()
    n = z.shape[1]
    max_lag = min(max_lag or n // 2, n - 1)
    spectrum = np.fft.rfft(z, n=2 * n, axis=1)
    correlation = np.fft.irfft(spectrum * np.conj(spectrum), axis=1)[:, : max_lag + 1].mean(axis=0)
    correlation /= (n - np.arange(max_lag + 1))  # unbiased: each lag over its own overlap
    return np.arange(max_lag + 1) * surface.dx, correlation / correlation[0]


def correlation_length(surface: Surface) -> float:
    """beta*: where the autocorrelation first falls to 1/e (linear interpolation), m; NaN if it never does."""
    lag, c = autocorrelation(surface)
    below = np.nonzero(c < math.exp(-1))[0]
    if below.size == 0:
        return math.nan
    i = below[0]
    return float(lag[i - 1] + (c[i - 1] - math.exp(-1)) / (c[i - 1] - c[i]) * (lag[i] - lag[i - 1]))


def summits(surface: Surface) -> dict:
    """Local maxima: their heights (m), curvature radii (m) and density (per m for a profile, per m^2 for a map)."""
    z = surface.height
    if not surface.is_map:
        centre = z[1:-1]
        peak = (centre > z[:-2]) & (centre > z[2:])
        curvature = (z[:-2] - 2 * centre + z[2:]) / surface.dx ** 2
        heights, curv = centre[peak], curvature[peak]
        extent = (z.size - 2) * surface.dx
    else:
        centre = z[1:-1, 1:-1]
        peak = np.ones_like(centre, dtype=bool)
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                if dx or dy:
                    peak &= centre > z[1 + dy: z.shape[0] - 1 + dy, 1 + dx: z.shape[1] - 1 + dx]
        z_xx = (z[1:-1, :-2] - 2 * centre + z[1:-1, 2:]) / surface.dx ** 2
        z_yy = (z[:-2, 1:-1] - 2 * centre + z[2:, 1:-1]) / surface.dy ** 2
        heights, curv = centre[peak], (0.5 * (z_xx + z_yy))[peak]  # the mean curvature of each summit
        extent = (z.shape[0] - 2) * (z.shape[1] - 2) * surface.dx * surface.dy
    radius = 1.0 / np.abs(curv[curv < 0])
    return {"heights": heights, "radii": radius, "density": heights.size / extent}


def statistics(surface: Surface) -> dict:
    """Seed 000's surface statistics (see the module), SI.

    Parameters
    ----------
    surface : Surface
        The surface.

    Returns
    -------
    dict
        RMS and CLA (m), skewness, kurtosis, correlation length (m), summit density (1/m^2), radius (m) and
        height spread (m).
    """
    from scipy import stats  # heavy: imported where used

    z = surface.height - surface.height.mean()
    rms = float(np.sqrt(np.mean(z ** 2)))
    if not rms > 1e-15:
        raise InputError(f"surface {surface.source} is flat once levelled: there is no roughness to describe")
    peaks = summits(surface)
    grid = np.linspace(z.min(), z.max(), 200)
    density = stats.gaussian_kde(z.ravel()[:: max(1, z.size // 200_000)])(grid)
    return {"cla": float(np.mean(np.abs(z))), "rms": rms, "skewness": float(np.mean(z ** 3) / rms ** 3),
            "kurtosis": float(np.mean(z ** 4) / rms ** 4), "correlation_length": correlation_length(surface),
            "summit_density": peaks["density"], "summit_count": int(peaks["heights"].size),
            "summit_sigma": float(np.std(peaks["heights"])) if peaks["heights"].size > 1 else math.nan,
            "summit_radius": float(np.mean(peaks["radii"])) if peaks["radii"].size else math.nan,
            "density_heights": grid, "density": density}


@takes_units(approaches="length", flow_pressure="pressure")
def truncation_contact(surface: Surface, approaches, counter: Surface | None = None,
                       flow_pressure: float | None = None, redistribute: bool = True) -> dict:
    """Contact of ``surface`` with ``counter`` at each approach (m) from first touch: real area (m^2), contacts
    (connected patches), displaced volume (m^3), and with ``flow_pressure`` (Pa) the load p_c A (N).

    ``counter`` is a surface as measured (heights up), turned over onto ``surface``: its heights then point
    down, mirrored. The default is a copy of ``surface`` itself (seed 000 §5.3); :func:`flat_like` gives a
    flat. With the gap g(x) = d - h(x) - h'(x) between the mean planes d apart, h' the turned-over
    counter's protrusion, the bodies first touch where h + h' is largest, and at an approach delta past
    first touch they overlap where delta > max(h + h') - (h + h'): the highest summits first (issue 27:
    this read min(h + h'), which touched the valleys first).

    Parameters
    ----------
    surface : Surface
        The surface.
    approaches : array_like
        Approaches from first touch (m).
    counter : Surface, optional
        The counter-surface.
    flow_pressure : float, optional
        p_c (Pa).
    redistribute : bool
        Redistribute the displaced volume.

    Returns
    -------
    dict
        Real area (m^2), contacts, displaced volume (m^3) and load (N) against approach.
    """
    from scipy import ndimage  # heavy: imported where used

    top = surface.height - surface.height.mean()
    facing = top if counter is None else counter.height - counter.height.mean()
    if facing.shape != top.shape:
        raise InputError("the two surfaces must share their grid")
    protrusion = facing[::-1, ::-1] if surface.is_map else facing[::-1]  # turned over: mirrored, pointing down
    reach = top + protrusion
    separation = float(reach.max()) - reach  # zero where they first touch
    approaches = np.atleast_1d(np.asarray(approaches, dtype=float))
    if np.any(approaches < 0):
        raise InputError("approaches are measured from first touch and must not be negative")
    area, contacts, volume = (np.empty(approaches.size) for _ in range(3))
    total = top.size * surface.cell_area
    for i, approach in enumerate(approaches):
        effective = approach
        for _ in range(20 if redistribute else 1):  # the displaced volume raises the surface evenly: less overlap
            overlap = np.maximum(effective - separation, 0.0)
            displaced = float(overlap.sum() * surface.cell_area)
            corrected = approach - displaced / total if redistribute else approach
            if abs(corrected - effective) <= 1e-12 * max(approach, 1e-30):
                break
            effective = corrected
        touching = overlap > 0
        area[i] = touching.sum() * surface.cell_area
        contacts[i] = ndimage.label(touching)[1] if surface.is_map else int(np.sum(np.diff(np.concatenate(
            [[False], touching, [False]]).astype(int)) == 1))
        volume[i] = displaced
    out = {"approach": approaches, "area": area, "contacts": contacts, "displaced_volume": volume,
           "nominal_area": total}
    if flow_pressure is not None:
        if not flow_pressure > 0:
            raise InputError("the flow pressure must be positive")
        out["load"] = flow_pressure * area
    return out


def flat_like(surface: Surface) -> Surface:
    """A smooth, rigid flat on the surface's grid (the counter-surface of the Greenwood-Williamson model)."""
    return Surface(np.zeros_like(surface.height), surface.dx, surface.dy, "flat")


@takes_units(load="force", flow_pressure="pressure")
def approach_for_load(surface: Surface, load: float, flow_pressure: float, counter: Surface | None = None) -> dict:
    """The approach where p_c A = L (seed 000 eq. 23), by bisection on the truncation contact.

    Parameters
    ----------
    surface : Surface
        The surface.
    load : float
        Normal load L (N).
    flow_pressure : float
        Flow pressure p_c (Pa).
    counter : Surface, optional
        The counter-surface (its own inverted copy otherwise).

    Returns
    -------
    dict
        The approach (m), real area (m^2), contacts and the load carried (N).
    """
    if not (load > 0 and flow_pressure > 0):
        raise InputError("the load and the flow pressure must be positive")
    needed = load / flow_pressure
    nominal = surface.height.size * surface.cell_area
    if needed >= nominal:
        raise InputError(f"a load of {load:g} N at {flow_pressure:g} Pa needs {needed:g} m^2 of contact, more than "
                         f"the {nominal:g} m^2 the surface covers")
    low, high = 0.0, float(np.ptp(surface.height)) * 2
    for _ in range(60):
        middle = 0.5 * (low + high)
        if truncation_contact(surface, [middle], counter, flow_pressure)["area"][0] < needed:
            low = middle
        else:
            high = middle
    return {key: (value[0] if isinstance(value, np.ndarray) else value)
            for key, value in truncation_contact(surface, [high], counter, flow_pressure).items()}


def report(surface: Surface, stats: dict, contact: dict | None = None, gw: dict | None = None,
           plasticity: dict | None = None, at_load: dict | None = None):
    """The statistics, plasticity and contact as a :class:`~faultslip.io.report.Report` (``faultslip surface``)."""
    r = Report(f"faultslip surface (seed 000): {surface.source}")
    r.add("kind", "map" if surface.is_map else "profile").add("points", int(surface.height.size))
    r.add("spacing", surface.dx, "m", also=("um",))
    r.section("Statistics (seed 000 §1.7)")
    r.add("cla", stats["cla"], "m", also=("um",), label="CLA (Ra)").add("rms", stats["rms"], "m", also=("um",),
                                                                         label="RMS (Rq)")
    r.add("skewness", stats["skewness"]).add("kurtosis", stats["kurtosis"])
    r.add("correlation_length", stats["correlation_length"], "m", also=("um",), label="correlation length beta* (1/e)")
    r.add("summit_density", stats["summit_density"], "1/m^2" if surface.is_map else "1/m", label="summit density")
    r.add("summit_sigma", stats["summit_sigma"], "m", also=("um",), label="spread of summit heights s")
    r.add("summit_radius", stats["summit_radius"], "m", also=("um",), label="mean summit radius R")
    if plasticity:
        r.section("Plasticity (Greenwood & Williamson; Hirst & Hollander)")
        for key, (value, label) in plasticity.items():
            r.add(key, value, label=label)
    if contact is not None:
        r.section("Contact by truncation (seed 000 §5.3)")
        points = [{"approach": {"value": float(a), "units": "m"}, "area": {"value": float(s), "units": "m^2"},
                   "contacts": int(n)} for a, s, n in zip(contact["approach"], contact["area"], contact["contacts"])]
        summary = "; ".join(f"{a * 1e6:.2g} um: {s / contact['nominal_area']:.3g} of the area, {int(n)} contacts"
                            for a, s, n in zip(contact["approach"][1::2], contact["area"][1::2],
                                               contact["contacts"][1::2]))
        r.add("contact_curve", {"points": points, "summary": summary}, label="approach: real area, contacts")
    if at_load is not None:
        r.add("approach_at_load", at_load["approach"], "m", also=("um",), label="approach where p_c A = L (eq. 23)")
        r.add("real_area_at_load", at_load["area"], "m^2", label="real area of contact")
        r.add("contacts_at_load", int(at_load["contacts"]), label="contacts")
        r.add("area_fraction_at_load", at_load["area"] / at_load["nominal_area"], label="real / nominal area")
    if gw is not None:
        points = [{"separation": {"value": float(d), "units": "m"}, "area": {"value": float(a), "units": "m^2"},
                   "load": {"value": float(p), "units": "N"}} for d, a, p in zip(gw["separation"], gw["area"], gw["load"])]
        summary = "; ".join(f"d {d * 1e6:.2g} um: {a / contact['nominal_area']:.3g} of the area at {p:.3g} N"
                            for d, a, p in zip(gw["separation"], gw["area"], gw["load"])) if contact else ""
        r.add("greenwood_williamson", {"points": points, "summary": summary},
              label="Greenwood-Williamson (elastic, Gaussian summits)")
    return r


@dataclass
class SurfaceAnalysis(ToXarray):
    """What ``faultslip surface`` computes: the surface, its statistics, its contact and the report."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {}

    surface: Surface
    stats: dict
    contact: dict
    report: Report


def analyze_surface(path=None, synthetic=None, size: int = 256, profile: bool = False, seed: int = 0, modulus=None,
                    poisson: float = 0.3, hardness=None, against: str = "inverted", flow_pressure=None,
                    load=None) -> SurfaceAnalysis:
    """A rough surface's statistics and its contact by truncation (seed 000; ``faultslip surface``).

    Parameters
    ----------
    path : str or path, optional
        A measured surface (a height map or profile file); or give ``synthetic``.
    synthetic : tuple, optional
        ``(rms, correlation_length)`` with units ("2 um", "20 um"): a Gaussian surface of ``size`` points a side
        (a profile if ``profile``), from ``seed``.
    modulus : str or Quantity, optional
        Young's modulus ("200 GPa"): the contact modulus, the elastic contact hardness, the Greenwood-Williamson
        contact and, with ``hardness``, the plasticity indices (seed 000 eqs. 15, 36-38).
    poisson : float
        Poisson's ratio.
    hardness : str or Quantity, optional
        The softer surface's hardness.
    against : str
        The counter-surface: ``inverted`` (its own inverted copy) or ``flat``.
    flow_pressure : str or Quantity, optional
        The flow pressure p_c of plastic contact (seed 000 eq. 23).
    load : str or Quantity, optional
        A normal load: the approach that carries it (needs ``flow_pressure``).

    Returns
    -------
    SurfaceAnalysis
        The surface, its statistics (m, 1/m^2, ...), its contact against approach, and the report.
    """
    if (path is None) == (synthetic is None):
        raise InputError("give a surface file, or --synthetic RMS CORRELATION_LENGTH (e.g. '2 um' '20 um')")
    if path is not None:
        surface = read_surface(path)
    else:
        rms, length = (to_si(text, "length", "--synthetic") for text in synthetic)
        surface = gaussian_surface(rms, length, size=size, profile=profile, seed=seed)
    surface = surface.levelled()
    stats = statistics(surface)
    plasticity = {}
    if modulus:
        contact_e = contact_modulus(to_si(modulus, "pressure", "--modulus"), poisson)
        plasticity["contact_modulus"] = (contact_e, "E' = E / (2 (1 - nu^2)), like surfaces (seed 000 eq. 37), Pa")
        plasticity["elastic_contact_hardness"] = (elastic_contact_hardness(contact_e, stats["summit_sigma"],
                                                                           stats["summit_radius"]),
                                                  "H' = 0.25 E' sqrt(s/R) (eq. 38), Pa")
        if hardness:
            softer = to_si(hardness, "pressure", "--hardness")
            plasticity["plasticity_index"] = (plasticity_index(contact_e, softer, stats["summit_sigma"],
                                                               stats["summit_radius"]),
                                                "plasticity index from the summits, psi = (E'/H) sqrt(s/R) (Greenwood "
                                                "& Williamson; eq. 36): s, R the summits' height spread and radius")
            plasticity["hirst_hollander_index"] = (hirst_hollander_index(contact_e, softer, stats["rms"],
                                                                         stats["correlation_length"]),
                                                   "plasticity index from the profile, psi = 0.6 (E'/H)(sigma/beta*) "
                                                   "(Hirst & Hollander; eq. 15): sigma, beta* the heights' rms and "
                                                   "correlation length; the two differ as summit and profile "
                                                   "statistics do, both > 1 means plastic contact")
    if against not in ("flat", "inverted"):
        raise InputError(f"--against must be flat or inverted, got {against!r}")
    counter = flat_like(surface) if against == "flat" else None
    flow = to_si(flow_pressure, "pressure", "--flow-pressure") if flow_pressure else None
    contact = truncation_contact(surface, np.linspace(0.0, 2.0 * stats["rms"], 9), counter, flow)
    at_load = None
    if load:
        if flow is None:
            raise InputError("--load needs --flow-pressure (all contacts plastic: L = p_c A, seed 000 eq. 23)")
        at_load = approach_for_load(surface, to_si(load, "force", "--load"), flow, counter)
    gw = None
    if modulus and surface.is_map and np.isfinite(stats["summit_radius"]):
        gw = greenwood_williamson(np.linspace(0.0, 2.0, 5) * stats["summit_sigma"], stats["summit_density"],
                                  stats["summit_radius"], stats["summit_sigma"], plasticity["contact_modulus"][0],
                                  contact["nominal_area"])
    return SurfaceAnalysis(surface, stats, contact, report(surface, stats, contact, gw, plasticity, at_load))
