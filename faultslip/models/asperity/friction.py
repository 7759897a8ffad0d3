"""Asperity friction from deformation and adhesion (seed 004: Bengisu & Akay 1999, J. Acoust. Soc. Am. 105, 194).

Small pure functions of the paper's contact model; the six-state slider lives in
:mod:`faultslip.models.asperity.dynamics`. Symbols follow the paper: contact slope Z', its standard
deviation s, relative approach dh = h_max - h, the Hertz radius r, the slope radius rho of eq. (27),
the contact-density constant gamma of eq. (4) (contacts per unit real contact area), tau and beta of
the adhesion law (18). Lengths in m, forces in N, areas in m^2.

The OCR renders micrometres as "mm" in several places; the paper's own numbers fix which (the
approach example of Sec. IV.B works only in micrometres, with a 1 nm slope cut-off). Its numbers
also need rho = 120 um, twice the (r1 + r2)/2 = 60 um that eq. (26) defines; both are recorded in
docs/asperity.md and tested.
"""

from __future__ import annotations

import math

from faultslip.constants import STANDARD_GRAVITY
import numpy as np

#: Table I of seed 004 (steel on copper, composite modulus 77 800 MPa). C = 2 kg/s in the dynamic
#: runs and 200 kg/s for the averages; the loss factor eta printed in kg/(m^2 s) is used in N s/m (see
#: docs/asperity.md). Case 7's "31.9 Hz" is read as 31.6 Hz like case 4 (Table II lists 31.6).
TABLE_I = {
    1: {"slope_std": 0.3, "natural_frequency": 10.0, "shear_strength": 0.0, "pressure_coefficient": 0.0},
    2: {"slope_std": 0.2, "natural_frequency": 10.0, "shear_strength": 0.0, "pressure_coefficient": 0.0},
    3: {"slope_std": 0.1, "natural_frequency": 10.0, "shear_strength": 0.0, "pressure_coefficient": 0.0},
    4: {"slope_std": 0.1, "natural_frequency": 31.6, "shear_strength": 0.0, "pressure_coefficient": 0.0},
    5: {"slope_std": 0.1, "natural_frequency": 100.0, "shear_strength": 0.0, "pressure_coefficient": 0.0},
    6: {"slope_std": 0.1, "natural_frequency": 10.0, "shear_strength": 9.8e6, "pressure_coefficient": 0.075},
    7: {"slope_std": 0.1, "natural_frequency": 31.6, "shear_strength": 9.8e6, "pressure_coefficient": 0.075},
    8: {"slope_std": 0.1, "natural_frequency": 100.0, "shear_strength": 9.8e6, "pressure_coefficient": 0.075},
}
TABLE_I_COMMON = {"mass": 10.0, "asperity_radius": 60e-6, "loss_factor": 200.0, "composite_modulus": 77.8e9}
#: Table II (s = 0.1): platform speeds (m/s) of the m_D peaks, by natural frequency (Hz)
TABLE_II = {10.0: (3.6e-3, 1.8e-3, 1.2e-3), 31.6: (12.0e-3, 6.0e-3, 4.0e-3, 3.0e-3, 2.4e-3, 2.0e-3),
            100.0: (38.75e-3, 19.15e-3, 12.8e-3, 9.6e-3, 7.6e-3, 6.4e-3)}
#: Table III (f0 = 10 Hz): the same by slope standard deviation
TABLE_III = {0.1: (3.6e-3, 1.8e-3, 1.2e-3), 0.2: (7.3e-3, 3.65e-3, 2.43e-3, 1.83e-3),
             0.3: (11.0e-3, 5.5e-3, 3.66e-3, 2.75e-3)}
#: Sec. IV.D: speeds where m_D vanishes and "computations become unstable" (contact loss), by s
CONTACT_LOSS_SPEEDS = {0.1: 0.285, 0.2: 0.550, 0.3: 0.800}
#: the paper's slope cut-off ("0.001 mm" in the OCR; 1 nm is the reading that reproduces Sec. IV.B)
SLOPE_CUTOFF = 1e-9
#: the slope radius that reproduces the paper's wavelength example (see the module docstring)
SLOPE_RADIUS = 120e-6


def hertz_constant(composite_modulus, asperity_radius):
    """K = 4 E / (3 r pi^(3/2)) (seed 004 eq. 14): the Hertz force of one contact is K a^(3/2), a its area.

    From Hertz, P = (4/3) E r^(1/2) d^(3/2) with a = pi r d (eq. 5). Units: N/m^3.
    """
    return 4.0 * np.asarray(composite_modulus, float) / (3.0 * np.asarray(asperity_radius, float) * math.pi ** 1.5)


def composite_modulus(modulus_1, poisson_1, modulus_2, poisson_2):
    """1/E = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (seed 004 eq. 15), Pa."""
    return 1.0 / ((1.0 - poisson_1 ** 2) / modulus_1 + (1.0 - poisson_2 ** 2) / modulus_2)


def maximum_contact_slope(approach, slope_std, slope_radius=SLOPE_RADIUS):
    """Z'_max = sqrt(dh / rho) (seed 004 eq. 27), capped at 3 s as the paper does ("setting Z'_max to 3 s")."""
    approach = np.maximum(np.asarray(approach, float), 0.0)
    return np.minimum(np.sqrt(approach / slope_radius), 3.0 * np.asarray(slope_std, float))


def mean_contact_slope(approach, slope_std, slope_radius=SLOPE_RADIUS, cutoff=SLOPE_CUTOFF):
    """<Z'> = s sqrt(2/pi) (1 - exp(-Z'_max^2 / (2 s^2))) (seed 004 eq. 25 with eq. 27), 0 below the cut-off.

    The mean of the positive half of a Gaussian slope distribution truncated at Z'_max. For
    dh << 2 rho s^2 it is dh / (s rho sqrt(2 pi)): rougher (larger s) surfaces have *smaller* mean
    contact slopes at a given small approach, which is why the critical speeds rise with s (Table III).
    """
    zmax = maximum_contact_slope(approach, slope_std, slope_radius)
    s = np.asarray(slope_std, float)
    value = s * math.sqrt(2.0 / math.pi) * -np.expm1(-zmax * zmax / (2.0 * s * s))
    return np.where(np.asarray(approach, float) >= cutoff, value, 0.0)


def mean_contact_slope_derivative(approach, slope_std, slope_radius=SLOPE_RADIUS, cutoff=SLOPE_CUTOFF):
    """d<Z'>/d(dh), 1/m: (sqrt(2/pi) / (2 s rho)) exp(-dh / (2 rho s^2)) below the 3 s cap, 0 above and below the
    cut-off."""
    approach = np.asarray(approach, float)
    s = np.asarray(slope_std, float)
    inside = (approach >= cutoff) & (approach < 9.0 * s * s * slope_radius)
    value = math.sqrt(2.0 / math.pi) / (2.0 * s * slope_radius) * np.exp(-approach / (2.0 * slope_radius * s * s))
    return np.where(inside, value, 0.0)


def mean_square_contact_slope(approach, slope_std, slope_radius=SLOPE_RADIUS, cutoff=SLOPE_CUTOFF):
    """<Z'^2> of the truncated half-Gaussian (seed 004 eq. 24, m = 2, in closed form):
    s^2 [erf(Z'_max / (s sqrt 2)) - sqrt(2/pi) (Z'_max/s) exp(-Z'_max^2 / (2 s^2))]."""
    zmax = maximum_contact_slope(approach, slope_std, slope_radius)
    s = np.asarray(slope_std, float)
    ratio = zmax / s
    from scipy.special import erf  # heavy: imported where used (scipy.special costs 0.2 s to import)

    value = s * s * (erf(ratio / math.sqrt(2.0)) - math.sqrt(2.0 / math.pi) * ratio * np.exp(-0.5 * ratio * ratio))
    return np.where(np.asarray(approach, float) >= cutoff, value, 0.0)


def friction_wavelength(max_approach, slope_std, slope_radius=SLOPE_RADIUS, cutoff=SLOPE_CUTOFF):
    """lambda = 2 int_cutoff^dh_max d(dh) / <Z'> (seed 004 eq. 29), m, in closed form.

    The block slides lambda while its approach goes from the summits (the cut-off) to dh_max and
    back. With L = 2 rho s^2 and c = s sqrt(2/pi), int d(dh) / (c (1 - e^(-dh/L))) =
    (L/c) ln(e^(dh/L) - 1); beyond the 3 s cap (dh > 9 s^2 rho) <Z'> is constant.
    """
    s = np.asarray(slope_std, float)
    scale = 2.0 * slope_radius * s * s
    slope_scale = s * math.sqrt(2.0 / math.pi)
    cap = 9.0 * s * s * slope_radius
    top = np.minimum(np.asarray(max_approach, float), cap)
    low = np.minimum(cutoff, top)

    def antiderivative(h):  # (L/c) ln(e^(h/L) - 1), written to stay finite for large h/L
        x = h / scale
        return scale / slope_scale * (x + np.log(-np.expm1(-x)))

    inside = antiderivative(top) - antiderivative(low)
    beyond = np.maximum(np.asarray(max_approach, float) - cap, 0.0) / (slope_scale * -np.expm1(-4.5))
    return 2.0 * (inside + beyond)


def critical_speeds(natural_frequency, wavelength, orders=(1, 2, 3)):
    """v_cn = f0 lambda / n (seed 004 eq. 28 with n f_f = f0), m/s: stick-slip bands lie around them."""
    return np.asarray([natural_frequency * wavelength / n for n in orders], float)


def contact_loss_speed(max_approach, slope_std, slope_radius=SLOPE_RADIUS, gravity=STANDARD_GRAVITY):
    """The platform speed above which the block cannot follow the surface down off the summits, m/s.

    Leaving a summit the approach grows as dh ~ e^(c v t / L) (<Z'> ~ c dh / L for dh << L), so the
    normal acceleration needed is (c v / L)^2 dh; it reaches g at dh_max for v = (L / c) sqrt(g / dh_max).
    This is our estimate of the paper's "contact loss" limit (Sec. IV.D), where its computations fail.
    """
    s = np.asarray(slope_std, float)
    scale = 2.0 * slope_radius * s * s
    return scale / (s * math.sqrt(2.0 / math.pi)) * np.sqrt(gravity / np.asarray(max_approach, float))


def deformation_normal_force(normal_area, normal_area_rate, mean_square_slope, hertz, contact_density,
                             loss_factor, asperity_radius):
    """F_n = (K / sqrt(gamma)) A_n (1 + <Z'^2>/4) + (eta / (pi r)) dA_n/dt (1 + <Z'^2>/2) (seed 004 eq. 17), N.

    Every contact has the mean area a_n = 1/gamma (eq. 4 gives gamma A_n contacts), so the Hertz sum is
    K gamma^(-1/2) A_n (1 + Z'^2)^(1/4); the series is cut after the first even moment as the paper does.
    """
    return (hertz / np.sqrt(contact_density) * normal_area * (1.0 + 0.25 * mean_square_slope)
            + loss_factor / (math.pi * asperity_radius) * normal_area_rate * (1.0 + 0.5 * mean_square_slope))


def contact_forces(resisting_area, assisting_area, mean_slope, deformation_force, shear_strength,
                   pressure_coefficient, adhesion_direction):
    """(F_t, F_n, F_t deformation) of seed 004 eq. (20), N.

    A_t = <Z'>(A_r - A_a) (eq. 12); F_t = (A_t/A_n + beta) F_n + tau A_n and
    F_n(t) = (1 - beta A_t/A_n) F_n - tau A_t, with tau and beta carrying ``adhesion_direction``
    (+1 when the block outruns the platform, -1 when the platform outruns it, a fraction in stick):
    the paper's "negative for positive relative velocity".
    """
    normal_area = resisting_area + assisting_area
    tangential_area = mean_slope * (resisting_area - assisting_area)
    deformation_friction = tangential_area / normal_area * deformation_force
    tau = adhesion_direction * shear_strength
    beta = adhesion_direction * pressure_coefficient
    friction = deformation_friction + beta * deformation_force + tau * normal_area
    normal = deformation_force - beta * deformation_friction - tau * tangential_area
    return friction, normal, deformation_friction
