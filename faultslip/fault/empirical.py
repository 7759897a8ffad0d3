"""Empirical earthquake scaling: Wells & Coppersmith (1994) and Leonard (2010).

Wells, D. L. & Coppersmith, K. J. (1994), New empirical relationships among magnitude, rupture length,
rupture width, rupture area and surface displacement, BSSA 84(4), 974-1002, Tables 2A and 2B:
ordinary least squares of the form ``y = a + b x`` with x or y a log10 quantity (lengths in km, areas
in km^2, displacements in m) and ``sigma`` the standard deviation of y, by slip type. Where W&C call a
relation not significant at 95 % (reverse-fault displacements), it is still given and flagged.

Leonard, M. (2010), Earthquake fault scaling: self-consistent relating of rupture length, width,
average displacement and moment release, BSSA 100(5A), 1971-1988, Table 6: Mw = log10(A) + a
(A in km^2) for interplate strike-slip (3.99) and dip-slip (4.00) faults and stable continental
regions (4.19). His average displacement follows from M0 = mu A D with mu = 3.3e10 Pa and
M0 = 10^(1.5 Mw + 9.05) N m (his own constants). Leonard gives asymmetric ranges, not one sigma, so
only ratios are reported for his relations.

Functions take and return SI (m, m^2) and magnitudes. :func:`compare` puts a physical prediction
beside the empirical expectation as a ratio and a z-score, z = log10(predicted / expected) / sigma
(for magnitudes, z = (predicted - expected) / sigma).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from faultslip.errors import InputError

SLIP_TYPES = ("strike-slip", "reverse", "normal", "all")

#: W&C 1994 Tables 2A-2B: relation -> slip type -> (a, b, sigma); relations are named "Y_from_X"
WELLS_COPPERSMITH_1994 = {
    "magnitude_from_surface_length": {"strike-slip": (5.16, 1.12, 0.28), "reverse": (5.00, 1.22, 0.28),
                                      "normal": (4.86, 1.32, 0.34), "all": (5.08, 1.16, 0.28)},
    "surface_length_from_magnitude": {"strike-slip": (-3.55, 0.74, 0.23), "reverse": (-2.86, 0.63, 0.20),
                                      "normal": (-2.01, 0.50, 0.21), "all": (-3.22, 0.69, 0.22)},
    "magnitude_from_subsurface_length": {"strike-slip": (4.33, 1.49, 0.24), "reverse": (4.49, 1.49, 0.26),
                                         "normal": (4.34, 1.54, 0.31), "all": (4.38, 1.49, 0.26)},
    "subsurface_length_from_magnitude": {"strike-slip": (-2.57, 0.62, 0.15), "reverse": (-2.42, 0.58, 0.16),
                                         "normal": (-1.88, 0.50, 0.17), "all": (-2.44, 0.59, 0.16)},
    "magnitude_from_area": {"strike-slip": (3.98, 1.02, 0.23), "reverse": (4.33, 0.90, 0.25),
                            "normal": (3.93, 1.02, 0.25), "all": (4.07, 0.98, 0.24)},
    "area_from_magnitude": {"strike-slip": (-3.42, 0.90, 0.22), "reverse": (-3.99, 0.98, 0.26),
                            "normal": (-2.87, 0.82, 0.22), "all": (-3.49, 0.91, 0.24)},
    "width_from_magnitude": {"strike-slip": (-0.76, 0.27, 0.14), "reverse": (-1.61, 0.41, 0.15),
                             "normal": (-1.14, 0.35, 0.12), "all": (-1.01, 0.32, 0.15)},
    "average_displacement_from_magnitude": {"strike-slip": (-6.32, 0.90, 0.28), "reverse": (-0.74, 0.08, 0.38),
                                            "normal": (-4.45, 0.63, 0.33), "all": (-4.80, 0.69, 0.36)},
    "maximum_displacement_from_magnitude": {"strike-slip": (-7.03, 1.03, 0.34), "reverse": (-1.84, 0.29, 0.42),
                                            "normal": (-5.90, 0.89, 0.38), "all": (-5.46, 0.82, 0.42)},
}
#: W&C's relations not significant at the 95 % level (their Table 2B: reverse-fault displacements)
NOT_SIGNIFICANT = {("average_displacement_from_magnitude", "reverse"),
                   ("maximum_displacement_from_magnitude", "reverse")}
#: Leonard 2010 Table 6: Mw = log10(A / km^2) + a
LEONARD_2010_AREA = {"strike-slip": 3.99, "dip-slip": 4.00, "stable-continental": 4.19}
LEONARD_SHEAR_MODULUS = 3.3e10  # Pa, Leonard's (2010) rigidity
LEONARD_MOMENT_CONSTANT = 9.05  # M0 = 10^(1.5 Mw + 9.05) N m, Leonard's (2010) convention

KM, KM2 = 1e3, 1e6


def _coefficients(relation: str, slip_type: str):
    if slip_type not in SLIP_TYPES:
        raise InputError(f"slip type must be one of {', '.join(SLIP_TYPES)}, got {slip_type!r}")
    return WELLS_COPPERSMITH_1994[relation][slip_type]


def _positive(values, what: str):
    array = np.asarray(values, dtype=float)
    if not np.all(np.isfinite(array) & (array > 0)):
        raise InputError(f"the {what} must be positive and finite")
    return array


def magnitude_from_length(surface_length, slip_type: str = "all"):
    """Mw = a + b log10(SRL / km) (W&C 1994 Table 2A); returns (Mw, sigma)."""
    a, b, sigma = _coefficients("magnitude_from_surface_length", slip_type)
    return a + b * np.log10(_positive(surface_length, "rupture length") / KM), sigma


def magnitude_from_area(area, slip_type: str = "all"):
    """Mw = a + b log10(RA / km^2) (W&C 1994 Table 2A); returns (Mw, sigma)."""
    a, b, sigma = _coefficients("magnitude_from_area", slip_type)
    return a + b * np.log10(_positive(area, "rupture area") / KM2), sigma


def rupture_length(magnitude, slip_type: str = "all"):
    """Surface rupture length (m) from log10(SRL / km) = a + b Mw (W&C 1994 Table 2A); returns (m, sigma of log10)."""
    a, b, sigma = _coefficients("surface_length_from_magnitude", slip_type)
    return KM * 10.0 ** (a + b * np.asarray(magnitude, dtype=float)), sigma


def rupture_area(magnitude, slip_type: str = "all"):
    """Rupture area (m^2) from log10(RA / km^2) = a + b Mw (W&C 1994 Table 2A); returns (m^2, sigma of log10)."""
    a, b, sigma = _coefficients("area_from_magnitude", slip_type)
    return KM2 * 10.0 ** (a + b * np.asarray(magnitude, dtype=float)), sigma


def average_displacement(magnitude, slip_type: str = "all"):
    """Average surface displacement (m) from log10(AD / m) = a + b Mw (W&C 1994 Table 2B); (m, sigma of log10)."""
    a, b, sigma = _coefficients("average_displacement_from_magnitude", slip_type)
    return 10.0 ** (a + b * np.asarray(magnitude, dtype=float)), sigma


def maximum_displacement(magnitude, slip_type: str = "all"):
    """Maximum surface displacement (m) from log10(MD / m) = a + b Mw (W&C 1994 Table 2B); (m, sigma of log10)."""
    a, b, sigma = _coefficients("maximum_displacement_from_magnitude", slip_type)
    return 10.0 ** (a + b * np.asarray(magnitude, dtype=float)), sigma


def _leonard_constant(setting: str) -> float:
    if setting not in LEONARD_2010_AREA:
        raise InputError(f"Leonard (2010) setting must be one of {', '.join(LEONARD_2010_AREA)}, got {setting!r}")
    return LEONARD_2010_AREA[setting]


def leonard_magnitude_from_area(area, setting: str = "strike-slip"):
    """Mw = log10(A / km^2) + a (Leonard 2010 Table 6)."""
    return np.log10(_positive(area, "rupture area") / KM2) + _leonard_constant(setting)


def leonard_average_displacement(area, setting: str = "strike-slip"):
    """Average displacement (m) D = M0 / (mu A) implied by Leonard's Mw(A), with his mu and M0(Mw) constants."""
    area = _positive(area, "rupture area")
    moment = 10.0 ** (1.5 * leonard_magnitude_from_area(area, setting) + LEONARD_MOMENT_CONSTANT)
    return moment / (LEONARD_SHEAR_MODULUS * area)


@dataclass(frozen=True)
class Comparison:
    """A physical prediction beside an empirical expectation."""

    quantity: str
    relation: str
    predicted: float
    expected: float
    units: str | None
    sigma: float | None  # of log10 (displacements, lengths) or of Mw (magnitudes); None: not given
    is_magnitude: bool = False
    note: str = ""

    @property
    def ratio(self) -> float:
        # a rupture far outside the relations' range can put the expectation at 0 or beyond floating point
        if not (math.isfinite(self.expected) and self.expected > 0 and math.isfinite(self.predicted)):
            return math.nan
        return self.predicted / self.expected

    @property
    def z_score(self) -> float | None:
        if self.sigma is None:
            return None
        if self.is_magnitude:
            difference = self.predicted - self.expected
        else:
            ratio = self.ratio
            difference = math.log10(ratio) if ratio > 0 else math.nan
        return difference / self.sigma if math.isfinite(difference) else None

    def as_dict(self) -> dict:
        finite = lambda value: value if value is not None and math.isfinite(value) else None  # noqa: E731 (JSON)
        return {"quantity": self.quantity, "relation": self.relation,
                "predicted": {"value": finite(self.predicted), "units": self.units},
                "expected": {"value": finite(self.expected), "units": self.units}, "ratio": finite(self.ratio),
                "sigma": self.sigma, "z_score": self.z_score, "note": self.note}


def compare(slip_per_event: float, magnitude: float, rupture_length_m: float, seismogenic_depth: float,
            slip_type: str = "strike-slip") -> list[Comparison]:
    """The physical slip per event and Mw beside W&C 1994 and Leonard 2010 for the same rupture (L x H).

    The physical slip is an average over the fault; W&C's average displacement is measured at the surface,
    which is why a ratio near 1 and ``|z| < 2`` is agreement, not more."""
    area = rupture_length_m * seismogenic_depth
    leonard_setting = "strike-slip" if slip_type in ("strike-slip", "all") else "dip-slip"
    rows = []
    expected, sigma = average_displacement(magnitude, slip_type)
    note = "not significant at 95 % (W&C 1994)" if ("average_displacement_from_magnitude", slip_type) in \
        NOT_SIGNIFICANT else ""
    rows.append(Comparison("slip_per_event", f"W&C 1994 AD(Mw), {slip_type}", slip_per_event, float(expected), "m",
                           sigma, note=note))
    rows.append(Comparison("slip_per_event", f"Leonard 2010 D(A), {leonard_setting}", slip_per_event,
                           float(leonard_average_displacement(area, leonard_setting)), "m", None))
    expected, sigma = magnitude_from_length(rupture_length_m, slip_type)
    rows.append(Comparison("moment_magnitude", f"W&C 1994 Mw(SRL), {slip_type}", magnitude, float(expected), None,
                           sigma, is_magnitude=True))
    expected, sigma = magnitude_from_area(area, slip_type)
    rows.append(Comparison("moment_magnitude", f"W&C 1994 Mw(RA), {slip_type}", magnitude, float(expected), None,
                           sigma, is_magnitude=True))
    rows.append(Comparison("moment_magnitude", f"Leonard 2010 Mw(A), {leonard_setting}", magnitude,
                           float(leonard_magnitude_from_area(area, leonard_setting)), None, None, is_magnitude=True))
    return rows


def add_to_report(report, rows: list[Comparison]):
    """The comparison as a report section (``fault`` and ``run``)."""
    report.section("Empirical scaling beside the prediction (W&C 1994, Leonard 2010)")
    for index, row in enumerate(rows):
        z = "" if row.z_score is None else f", z = {row.z_score:+.2f}"
        if not math.isfinite(row.ratio if not row.is_magnitude else row.predicted - row.expected):
            shown = "outside the relation's range (no comparison)"
        else:
            shown = (f"expects {row.expected:.3g} {row.units}: ratio {row.ratio:.3g}{z}" if not row.is_magnitude
                     else f"expects Mw {row.expected:.2f}: difference {row.predicted - row.expected:+.2f}{z}")
        report.add(f"empirical_{index}", {**row.as_dict(), "summary": shown + (f" ({row.note})" if row.note else "")},
                   label=row.relation)
    report.note("z = log10(predicted / expected) / sigma for displacements, (predicted - expected) / sigma for Mw; "
                "Leonard (2010) gives ranges, not one sigma, so his rows have no z.")
    return report


#: study and map variables (:func:`gridded`): name -> (units, long_name)
GRIDDED_ATTRS = {
    "empirical_slip": ("m", "W&C 1994 strike-slip average displacement AD(Mw) at the predicted Mw"),
    "empirical_slip_ratio": ("1", "slip per event / W&C 1994 AD(Mw)"),
    "empirical_slip_z": ("1", "log10(slip per event / W&C 1994 AD(Mw)) / 0.28"),
    "empirical_magnitude": ("1", "W&C 1994 strike-slip Mw(SRL) from the rupture length"),
    "empirical_magnitude_z": ("1", "(Mw - W&C 1994 Mw(SRL)) / 0.28"),
}


def gridded(slip_per_event, magnitude, rupture_length_m):
    """The study/map form of :func:`compare` (strike-slip W&C 1994), elementwise on numpy or xarray arrays:
    NaN where there is no stick-slip (slip 0) or no magnitude."""
    a, b, sigma = WELLS_COPPERSMITH_1994["average_displacement_from_magnitude"]["strike-slip"]
    expected = 10.0 ** (a + b * magnitude)
    slides = slip_per_event > 0
    ratio = (slip_per_event / expected).where(slides) if hasattr(slip_per_event, "where") else \
        np.where(slides, slip_per_event / expected, np.nan)
    a_l, b_l, sigma_l = WELLS_COPPERSMITH_1994["magnitude_from_surface_length"]["strike-slip"]
    from_length = a_l + b_l * np.log10(rupture_length_m / KM)
    return {"empirical_slip": expected, "empirical_slip_ratio": ratio, "empirical_slip_z": np.log10(ratio) / sigma,
            "empirical_magnitude": from_length + 0 * magnitude,  # broadcast onto the grid
            "empirical_magnitude_z": (magnitude - from_length) / sigma_l}
