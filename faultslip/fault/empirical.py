"""Empirical earthquake scaling: Wells & Coppersmith (1994) and Leonard (2010), in all their published forms.

Wells, D. L. & Coppersmith, K. J. (1994), New empirical relationships among magnitude, rupture length,
rupture width, rupture area and surface displacement, BSSA 84(4), 974-1002, Tables 2A and 2B: ordinary
least squares of the form ``y = a + b x`` with x or y a log10 quantity (lengths in km, areas in km^2,
displacements in m) and ``sigma`` the standard deviation of y, by slip type, in both directions (W&C fit
y(x) and x(y) separately, so the two are not exact inverses). Where W&C call a relation not significant at
95 % (reverse-fault displacements), it is still given and flagged. Their Table 2C (displacement against
surface length) is not carried.

Leonard, M. (2010), Earthquake fault scaling: self-consistent relating of rupture length, width, average
displacement and moment release, BSSA 100(5A), 1971-1988. His relations follow from three statements
(his eqs. 3-6 and Table 5): the width W = L for small ruptures, then W = C1 L^(2/3) (L, W in m), and for
interplate strike-slip faults W stays at its value at L = 45 km beyond it; the average displacement
D = C2 sqrt(A); and M0 = mu A D with mu = 3.3e10 Pa. Table 5 gives C1 and C2 with ranges, by setting. Every
relation here is computed from those constants, and the magnitude from M0 with
Mw = (2/3)(log10 M0 - 9.1): that constant is the one that reproduces his Table 6 coefficients (a test
recomputes them), whereas 9.05 would shift them all by +0.03. His surface-rupture-length forms
(Table 6: Mw = 1.52 log10 SRL + 4.33 strike-slip, + 4.40 dip-slip) are regressions, carried as printed.
Leonard gives ranges from the ranges of C1 and C2, not one sigma, so his relations carry (low, high).

Functions return SI (m, m^2) and magnitudes; they take SI numbers, or lengths and areas with units (``"7 km"``,
a pint Quantity). :func:`compare` puts a physical prediction
beside the empirical expectation as a ratio and a z-score, z = log10(predicted / expected) / sigma
(for magnitudes, z = (predicted - expected) / sigma).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from faultslip.errors import InputError
from faultslip.units import si_unit, takes_units, to_si

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
    "magnitude_from_width": {"strike-slip": (3.80, 2.59, 0.45), "reverse": (4.37, 1.95, 0.32),
                             "normal": (4.04, 2.11, 0.31), "all": (4.06, 2.25, 0.41)},
    "width_from_magnitude": {"strike-slip": (-0.76, 0.27, 0.14), "reverse": (-1.61, 0.41, 0.15),
                             "normal": (-1.14, 0.35, 0.12), "all": (-1.01, 0.32, 0.15)},
    "magnitude_from_area": {"strike-slip": (3.98, 1.02, 0.23), "reverse": (4.33, 0.90, 0.25),
                            "normal": (3.93, 1.02, 0.25), "all": (4.07, 0.98, 0.24)},
    "area_from_magnitude": {"strike-slip": (-3.42, 0.90, 0.22), "reverse": (-3.99, 0.98, 0.26),
                            "normal": (-2.87, 0.82, 0.22), "all": (-3.49, 0.91, 0.24)},
    "magnitude_from_maximum_displacement": {"strike-slip": (6.81, 0.78, 0.29), "reverse": (6.52, 0.44, 0.52),
                                            "normal": (6.61, 0.71, 0.34), "all": (6.69, 0.74, 0.40)},
    "maximum_displacement_from_magnitude": {"strike-slip": (-7.03, 1.03, 0.34), "reverse": (-1.84, 0.29, 0.42),
                                            "normal": (-5.90, 0.89, 0.38), "all": (-5.46, 0.82, 0.42)},
    "magnitude_from_average_displacement": {"strike-slip": (7.04, 0.89, 0.28), "reverse": (6.64, 0.13, 0.50),
                                            "normal": (6.78, 0.65, 0.33), "all": (6.93, 0.82, 0.39)},
    "average_displacement_from_magnitude": {"strike-slip": (-6.32, 0.90, 0.28), "reverse": (-0.74, 0.08, 0.38),
                                            "normal": (-4.45, 0.63, 0.33), "all": (-4.80, 0.69, 0.36)},
}
#: W&C's relations not significant at the 95 % level (their Table 2B: reverse-fault displacements)
NOT_SIGNIFICANT = {(relation, "reverse") for relation in WELLS_COPPERSMITH_1994 if "displacement" in relation}
KM, KM2 = 1e3, 1e6
#: the quantity on the non-magnitude side of each W&C relation: its SI scale from W&C's units, and its name
_WC_QUANTITY = {"surface_length": (KM, "surface rupture length"), "subsurface_length": (KM, "subsurface rupture length"),
                "width": (KM, "rupture width"), "area": (KM2, "rupture area"),
                "maximum_displacement": (1.0, "maximum displacement"),
                "average_displacement": (1.0, "average displacement")}

LEONARD_SETTINGS = ("strike-slip", "dip-slip", "stable-continental")
#: Leonard 2010 Table 5: setting -> (C1 in m^(1/3), C2), each (preferred, low, high)
LEONARD_2010_CONSTANTS = {"strike-slip": ((15.0, 11.0, 20.0), (3.7e-5, 1.5e-5, 9.0e-5)),
                          "dip-slip": ((17.5, 12.0, 25.0), (3.8e-5, 1.5e-5, 12e-5)),
                          "stable-continental": ((13.5, 11.0, 17.0), (7.3e-5, 5.0e-5, 10e-5))}
#: Length (m) beyond which an interplate strike-slip rupture's width stays constant (Leonard 2010 §"width")
LEONARD_SATURATION_LENGTH = {"strike-slip": 45e3}
#: Leonard 2010 Table 6, surface rupture length: setting -> (slope, intercept) of Mw = slope log10(SRL/km) + intercept
LEONARD_2010_SURFACE_LENGTH = {"strike-slip": (1.52, 4.33), "dip-slip": (1.52, 4.40)}
LEONARD_SHEAR_MODULUS = 3.3e10  # Pa, Leonard's (2010) rigidity
#: M0 = 10^(1.5 Mw + 9.1) N m: the constant with which his Table 5 constants give his Table 6 (a test shows it)
LEONARD_MOMENT_CONSTANT = 9.1
_BOUNDS = {"preferred": 0, "low": 1, "high": 2}


def slip_type_from_rake(rake) -> str:
    """W&C's slip type from the rake (degrees, Aki & Richards): within 45 degrees of horizontal, strike-slip;
    otherwise reverse (rake > 0) or normal: the convention of OpenQuake's ``WC1994``."""
    rake = float(rake)
    if not math.isfinite(rake) or not -180.0 <= rake <= 180.0:
        raise InputError(f"the rake must be an angle from -180 to 180 degrees, got {rake!r}")
    if -45.0 <= rake <= 45.0 or rake >= 135.0 or rake <= -135.0:
        return "strike-slip"
    return "reverse" if rake > 0 else "normal"


def leonard_setting(slip_type: str, stable_continental: bool = False) -> str:
    """Leonard's setting for a W&C slip type: stable continental, else strike-slip or dip-slip."""
    if slip_type not in SLIP_TYPES:
        raise InputError(f"slip type must be one of {', '.join(SLIP_TYPES)}, got {slip_type!r}")
    if stable_continental:
        return "stable-continental"
    return "strike-slip" if slip_type in ("strike-slip", "all") else "dip-slip"


def _coefficients(relation: str, slip_type: str):
    if slip_type not in SLIP_TYPES:
        raise InputError(f"slip type must be one of {', '.join(SLIP_TYPES)}, got {slip_type!r}")
    if relation not in WELLS_COPPERSMITH_1994:
        raise InputError(f"W&C (1994) relation must be one of {', '.join(WELLS_COPPERSMITH_1994)}, got {relation!r}")
    return WELLS_COPPERSMITH_1994[relation][slip_type]


def _positive(values, what: str):
    """``values`` in SI as an array: a bare number is m (m^2 for an area), ``"7 km"`` or a pint Quantity is
    converted; positive and finite, or refused in one sentence."""
    kind = "area" if what.endswith("area") else "length"
    array = np.asarray(to_si(values, kind, f"the {what}", default_unit=si_unit(kind)), dtype=float)
    if not np.all(array > 0):
        raise InputError(f"the {what} must be positive and finite")
    return array


def _finite(values, what: str):
    return np.asarray(to_si(values, "dimensionless", f"the {what}"), dtype=float)


def wells_coppersmith_1994(relation: str, value, slip_type: str = "all"):
    """Any W&C (1994) Table 2A/2B relation by name, in SI: ``magnitude_from_X`` takes X in m (lengths,
    widths, displacements) or m^2 (area) and returns (Mw, sigma of Mw); ``X_from_magnitude`` takes Mw and
    returns (X in m or m^2, sigma of log10 X). X is surface_length, subsurface_length, width, area,
    maximum_displacement or average_displacement.

    Parameters
    ----------
    relation : str
        The relation's name.
    value : float, array_like, str or Quantity
        Its argument (m, m^2 or Mw).
    slip_type : str
        all, strike-slip, reverse or normal.

    Returns
    -------
    tuple
        The value and its sigma.
    """
    a, b, sigma = _coefficients(relation, slip_type)
    if relation.startswith("magnitude_from_"):
        scale, what = _WC_QUANTITY[relation.removeprefix("magnitude_from_")]
        return a + b * np.log10(_positive(value, what) / scale), sigma
    scale, _ = _WC_QUANTITY[relation.removesuffix("_from_magnitude")]
    return scale * 10.0 ** (a + b * _finite(value, "magnitude")), sigma


def magnitude_from_length(surface_length, slip_type: str = "all"):
    """Mw = a + b log10(SRL / km) (W&C 1994 Table 2A); returns (Mw, sigma).

    Parameters
    ----------
    surface_length : float, array_like, str or Quantity
        The surface rupture length (m).
    slip_type : str
        all, strike-slip, reverse or normal.

    Returns
    -------
    tuple
        Mw and its standard deviation.
    """
    return wells_coppersmith_1994("magnitude_from_surface_length", surface_length, slip_type)


def magnitude_from_subsurface_length(subsurface_length, slip_type: str = "all"):
    """Mw = a + b log10(RLD / km) (W&C 1994 Table 2A); returns (Mw, sigma)."""
    return wells_coppersmith_1994("magnitude_from_subsurface_length", subsurface_length, slip_type)


def magnitude_from_width(width, slip_type: str = "all"):
    """Mw = a + b log10(RW / km), RW the down-dip rupture width (W&C 1994 Table 2A); returns (Mw, sigma).

    Parameters
    ----------
    width : float, array_like, str or Quantity
        The down-dip rupture width (m).
    slip_type : str
        all, strike-slip, reverse or normal.

    Returns
    -------
    tuple
        Mw and its standard deviation.
    """
    return wells_coppersmith_1994("magnitude_from_width", width, slip_type)


def magnitude_from_area(area, slip_type: str = "all"):
    """Mw = a + b log10(RA / km^2) (W&C 1994 Table 2A); returns (Mw, sigma).

    Parameters
    ----------
    area : float, array_like, str or Quantity
        The rupture area (m^2).
    slip_type : str
        all, strike-slip, reverse or normal.

    Returns
    -------
    tuple
        Mw and its standard deviation.
    """
    return wells_coppersmith_1994("magnitude_from_area", area, slip_type)


def magnitude_from_displacement(displacement, slip_type: str = "all", kind: str = "average"):
    """Mw = a + b log10(D / m), D the average or maximum surface displacement (W&C 1994 Table 2B);
    returns (Mw, sigma).

    Parameters
    ----------
    displacement : float, array_like, str or Quantity
        The average or maximum surface displacement (m).
    slip_type : str
        all, strike-slip, reverse or normal.
    kind : str
        average or maximum.

    Returns
    -------
    tuple
        Mw and its standard deviation.
    """
    if kind not in ("average", "maximum"):
        raise InputError(f"the displacement kind must be average or maximum, got {kind!r}")
    return wells_coppersmith_1994(f"magnitude_from_{kind}_displacement", displacement, slip_type)


def rupture_length(magnitude, slip_type: str = "all"):
    """Surface rupture length (m) from log10(SRL / km) = a + b Mw (W&C 1994 Table 2A); returns (m, sigma of log10).

    Parameters
    ----------
    magnitude : float or array_like
        Moment magnitude Mw.
    slip_type : str
        all, strike-slip, reverse or normal (W&C 1994's regressions).

    Returns
    -------
    tuple
        The surface rupture length (m) and the standard deviation of its log10.
    """
    return wells_coppersmith_1994("surface_length_from_magnitude", magnitude, slip_type)


def subsurface_rupture_length(magnitude, slip_type: str = "all"):
    """Subsurface rupture length (m) from log10(RLD / km) = a + b Mw (W&C 1994 Table 2A); (m, sigma of log10)."""
    return wells_coppersmith_1994("subsurface_length_from_magnitude", magnitude, slip_type)


def rupture_width(magnitude, slip_type: str = "all"):
    """Down-dip rupture width (m) from log10(RW / km) = a + b Mw (W&C 1994 Table 2A); (m, sigma of log10).

    Parameters
    ----------
    magnitude : float or array_like
        Moment magnitude Mw.
    slip_type : str
        all, strike-slip, reverse or normal (W&C 1994's regressions).

    Returns
    -------
    tuple
        The down-dip rupture width (m) and the standard deviation of its log10.
    """
    return wells_coppersmith_1994("width_from_magnitude", magnitude, slip_type)


def rupture_area(magnitude, slip_type: str = "all"):
    """Rupture area (m^2) from log10(RA / km^2) = a + b Mw (W&C 1994 Table 2A); returns (m^2, sigma of log10).

    Parameters
    ----------
    magnitude : float or array_like
        Moment magnitude Mw.
    slip_type : str
        all, strike-slip, reverse or normal (W&C 1994's regressions).

    Returns
    -------
    tuple
        The rupture area (m^2) and the standard deviation of its log10.
    """
    return wells_coppersmith_1994("area_from_magnitude", magnitude, slip_type)


def average_displacement(magnitude, slip_type: str = "all"):
    """Average surface displacement (m) from log10(AD / m) = a + b Mw (W&C 1994 Table 2B); (m, sigma of log10).

    Parameters
    ----------
    magnitude : float or array_like
        Moment magnitude Mw.
    slip_type : str
        all, strike-slip, reverse or normal (W&C 1994's regressions).

    Returns
    -------
    tuple
        The average surface displacement (m) and the standard deviation of its log10.
    """
    return wells_coppersmith_1994("average_displacement_from_magnitude", magnitude, slip_type)


def maximum_displacement(magnitude, slip_type: str = "all"):
    """Maximum surface displacement (m) from log10(MD / m) = a + b Mw (W&C 1994 Table 2B); (m, sigma of log10).

    Parameters
    ----------
    magnitude : float or array_like
        Moment magnitude Mw.
    slip_type : str
        all, strike-slip, reverse or normal (W&C 1994's regressions).

    Returns
    -------
    tuple
        The maximum surface displacement (m) and the standard deviation of its log10.
    """
    return wells_coppersmith_1994("maximum_displacement_from_magnitude", magnitude, slip_type)


# --- Leonard (2010): every form from Table 5's C1 and C2 -------------------------------------------------------

def _leonard_constants(setting: str, bound: str):
    if setting not in LEONARD_2010_CONSTANTS:
        raise InputError(f"Leonard (2010) setting must be one of {', '.join(LEONARD_SETTINGS)}, got {setting!r}")
    if bound not in _BOUNDS:
        raise InputError(f"the bound must be one of {', '.join(_BOUNDS)}, got {bound!r}")
    c1, c2 = LEONARD_2010_CONSTANTS[setting]
    return c1[_BOUNDS[bound]], c2[_BOUNDS[bound]]


def _leonard_magnitude_to_moment(magnitude):
    return 10.0 ** (1.5 * np.asarray(magnitude, dtype=float) + LEONARD_MOMENT_CONSTANT)


def _leonard_corners(setting: str, c1: float):
    """(L1, L2, W2): W = L up to L1 = C1^3 (where C1 L^(2/3) = L); W = C1 L^(2/3) up to L2; W = W2 beyond."""
    first = c1 ** 3
    saturation = LEONARD_SATURATION_LENGTH.get(setting, math.inf)
    return first, saturation, c1 * saturation ** (2.0 / 3.0) if math.isfinite(saturation) else math.inf


def leonard_width(length, setting: str = "strike-slip", bound: str = "preferred"):
    """Rupture width W (m) for a length L (m): W = L for L <= C1^3, C1 L^(2/3) above, constant beyond 45 km for
    interplate strike-slip faults (Leonard 2010 eqs. 3-4, Table 5).

    Parameters
    ----------
    length : float, array_like, str or Quantity
        Rupture length L (m).
    setting : str
        strike-slip, dip-slip or stable-continental (Leonard 2010 Table 5).
    bound : str
        preferred, low or high: Table 5's constants.

    Returns
    -------
    float or ndarray
        Rupture width W (m).
    """
    c1, _ = _leonard_constants(setting, bound)
    length = _positive(length, "rupture length")
    first, saturation, saturated = _leonard_corners(setting, c1)
    return np.where(length <= first, length, np.where(length <= saturation, c1 * length ** (2.0 / 3.0), saturated))


def leonard_average_displacement(area, setting: str = "strike-slip", bound: str = "preferred"):
    """Average displacement D = C2 sqrt(A) (m) over a rupture of area A (m^2) (Leonard 2010 eq. 6, Table 5)."""
    _, c2 = _leonard_constants(setting, bound)
    return c2 * np.sqrt(_positive(area, "rupture area"))


def leonard_moment_from_area(area, setting: str = "strike-slip", bound: str = "preferred"):
    """M0 = mu A D = mu C2 A^(3/2) (N m), mu = 3.3e10 Pa (Leonard 2010)."""
    area = _positive(area, "rupture area")
    return LEONARD_SHEAR_MODULUS * area * leonard_average_displacement(area, setting, bound)


def leonard_magnitude_from_area(area, setting: str = "strike-slip", bound: str = "preferred"):
    """Mw from the area (m^2): log10(A / km^2) + 3.99 strike-slip, 4.00 dip-slip, 4.19 stable continental as
    Table 6 prints them, here computed from C2 (Leonard 2010).

    Parameters
    ----------
    area : float, array_like, str or Quantity
        Rupture area (m^2).
    setting : str
        strike-slip, dip-slip or stable-continental (Leonard 2010 Table 5).
    bound : str
        preferred, low or high: Table 5's constants.

    Returns
    -------
    float or ndarray
        Mw.
    """
    _, c2 = _leonard_constants(setting, bound)
    # in logarithms: a tiny rupture's moment would underflow to zero
    log_moment = math.log10(LEONARD_SHEAR_MODULUS * c2) + 1.5 * np.log10(_positive(area, "rupture area"))
    return (log_moment - LEONARD_MOMENT_CONSTANT) / 1.5


def leonard_magnitude_from_length(length, setting: str = "strike-slip", bound: str = "preferred"):
    """Mw from the rupture length (m) through W(L): 1.67 log10(L / km) + 4.17 strike-slip, 4.24 dip-slip,
    4.32 stable continental in Table 6's middle segment, here computed from C1 and C2 (Leonard 2010).

    Parameters
    ----------
    length : float, array_like, str or Quantity
        Rupture length (m).
    setting : str
        strike-slip, dip-slip or stable-continental (Leonard 2010 Table 5).
    bound : str
        preferred, low or high: Table 5's constants.

    Returns
    -------
    float or ndarray
        Mw.
    """
    length = _positive(length, "rupture length")
    return leonard_magnitude_from_area(length * leonard_width(length, setting, bound), setting, bound)


def leonard_magnitude_from_surface_length(surface_length, setting: str = "strike-slip"):
    """Mw = 1.52 log10(SRL / km) + 4.33 strike-slip, 4.40 dip-slip (Leonard 2010 Table 6, as printed)."""
    if setting not in LEONARD_2010_SURFACE_LENGTH:
        raise InputError(f"Leonard (2010) gives surface-length forms for {', '.join(LEONARD_2010_SURFACE_LENGTH)} "
                         f"only, not {setting!r}")
    slope, intercept = LEONARD_2010_SURFACE_LENGTH[setting]
    return slope * np.log10(_positive(surface_length, "surface rupture length") / KM) + intercept


def leonard_area_from_magnitude(magnitude, setting: str = "strike-slip", bound: str = "preferred"):
    """Rupture area A = (M0 / (mu C2))^(2/3) (m^2) for a magnitude (Leonard 2010).

    Parameters
    ----------
    magnitude : float or array_like
        Moment magnitude Mw.
    setting : str
        strike-slip, dip-slip or stable-continental (Leonard 2010 Table 5).
    bound : str
        preferred, low or high: Table 5's constants.

    Returns
    -------
    float or ndarray
        Rupture area (m^2).
    """
    _, c2 = _leonard_constants(setting, bound)
    moment = _leonard_magnitude_to_moment(_finite(magnitude, "magnitude"))
    return (moment / (LEONARD_SHEAR_MODULUS * c2)) ** (2.0 / 3.0)


def leonard_length_from_magnitude(magnitude, setting: str = "strike-slip", bound: str = "preferred"):
    """Rupture length (m) for a magnitude: A = L W(L) inverted segment by segment (L = sqrt(A), (A/C1)^(3/5),
    A / W_max) (Leonard 2010).

    Parameters
    ----------
    magnitude : float or array_like
        Moment magnitude Mw.
    setting : str
        strike-slip, dip-slip or stable-continental (Leonard 2010 Table 5).
    bound : str
        preferred, low or high: Table 5's constants.

    Returns
    -------
    float or ndarray
        Rupture length (m).
    """
    c1, _ = _leonard_constants(setting, bound)
    area = leonard_area_from_magnitude(magnitude, setting, bound)
    first, saturation, saturated = _leonard_corners(setting, c1)
    return np.where(area <= first ** 2, np.sqrt(area),
                    np.where(area <= saturation * saturated, (area / c1) ** 0.6, area / saturated))


def leonard_width_from_magnitude(magnitude, setting: str = "strike-slip", bound: str = "preferred"):
    """Rupture width (m) for a magnitude, W = A / L (Leonard 2010)."""
    return leonard_area_from_magnitude(magnitude, setting, bound) / leonard_length_from_magnitude(magnitude, setting,
                                                                                                   bound)


def leonard_displacement_from_magnitude(magnitude, setting: str = "strike-slip", bound: str = "preferred"):
    """Average displacement (m) for a magnitude, D = C2 sqrt(A) (Leonard 2010)."""
    return leonard_average_displacement(leonard_area_from_magnitude(magnitude, setting, bound), setting, bound)


def leonard_range(function, value, setting: str = "strike-slip"):
    """(low, high) of one of the Leonard functions above over Table 5's ranges of C1 and C2 (both bounds
    together, ordered): his uncertainty, which is a range, not a sigma.

    Parameters
    ----------
    function : callable
        One of the Leonard functions.
    value : float
        Its argument (SI).
    setting : str
        strike-slip, dip-slip or stable-continental.

    Returns
    -------
    tuple
        (low, high) in the function's units.
    """
    low, high = function(value, setting, "low"), function(value, setting, "high")
    return np.minimum(low, high), np.maximum(low, high)


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


@takes_units(slip_per_event="length", rupture_length_m="length", seismogenic_depth="length")
def compare(slip_per_event: float, magnitude: float, rupture_length_m: float, seismogenic_depth: float,
            slip_type: str = "strike-slip") -> list[Comparison]:
    """The physical slip per event and Mw beside W&C 1994 and Leonard 2010 for the same rupture (L x H).

    The physical slip is an average over the fault; W&C's average displacement is measured at the surface,
    which is why a ratio near 1 and ``|z| < 2`` is agreement, not more.

    Parameters
    ----------
    slip_per_event : float
        The physical slip per event (m).
    magnitude : float
        Its Mw.
    rupture_length_m : float
        Rupture length L (m).
    seismogenic_depth : float
        Seismogenic depth H (m).
    slip_type : str
        strike-slip, reverse, normal or all.

    Returns
    -------
    list of Comparison
        Each relation's expectation, its ratio to the physical value and the z-score.
    """
    area = rupture_length_m * seismogenic_depth
    setting = leonard_setting(slip_type)
    rows = []
    expected, sigma = average_displacement(magnitude, slip_type)
    note = "not significant at 95 % (W&C 1994)" if ("average_displacement_from_magnitude", slip_type) in \
        NOT_SIGNIFICANT else ""
    rows.append(Comparison("slip_per_event", f"W&C 1994 AD(Mw), {slip_type}", slip_per_event, float(expected), "m",
                           sigma, note=note))
    rows.append(Comparison("slip_per_event", f"Leonard 2010 D(A), {setting}", slip_per_event,
                           float(leonard_average_displacement(area, setting)), "m", None))
    expected, sigma = magnitude_from_length(rupture_length_m, slip_type)
    rows.append(Comparison("moment_magnitude", f"W&C 1994 Mw(SRL), {slip_type}", magnitude, float(expected), None,
                           sigma, is_magnitude=True))
    expected, sigma = magnitude_from_area(area, slip_type)
    rows.append(Comparison("moment_magnitude", f"W&C 1994 Mw(RA), {slip_type}", magnitude, float(expected), None,
                           sigma, is_magnitude=True))
    rows.append(Comparison("moment_magnitude", f"Leonard 2010 Mw(A), {setting}", magnitude,
                           float(leonard_magnitude_from_area(area, setting)), None, None, is_magnitude=True))
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
