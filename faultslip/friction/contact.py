"""Contact of rough surfaces: the Greenwood-Williamson model and its plasticity index (seed 000, §1.7 and AD1.2).

Greenwood & Williamson (1966, Proc. R. Soc. A 295, 300-319): summits of one radius R, with density eta
per unit area and heights distributed as phi(z), pressed by a flat at separation d, each touching summit
a Hertz contact of interference w = z - d:

    n(d) = eta A_n int_d^inf phi(z) dz                                  contacts
    A(d) = pi eta A_n R int_d^inf (z - d) phi(z) dz                     real area
    P(d) = (4/3) E' sqrt(R) eta A_n int_d^inf (z - d)^(3/2) phi(z) dz   load

with E' the contact modulus. For exponential summit heights phi(z) = exp(-z/s)/s these are closed:
n = eta A_n e^(-d/s), A = pi eta A_n R s e^(-d/s), P = sqrt(pi) E' sqrt(R) eta A_n s^(3/2) e^(-d/s),
so the mean pressure P/A = E' sqrt(s/R) / sqrt(pi) does not depend on the load (tested). Gaussian
summit heights go by quadrature.

The plasticity index (GW eq. 36 in seed 000): psi = (E'/H) sqrt(s/R), s the standard deviation of the
summit heights; below about 0.6 the contact is elastic, above 1 plastic under all but the lightest
loads. GW's elastic contact hardness is H' = 0.25 E' sqrt(s/R) (seed 000 eq. 38). Seed 000 uses
E' = E / (2 (1 - nu^2)) for two like surfaces; Hirst & Hollander's form is psi = 0.6 (E'/H)(sigma/beta*)
with the correlation length beta* (seed 000 eq. 15).
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.errors import InputError

DISTRIBUTIONS = ("gaussian", "exponential")


def contact_modulus(youngs_modulus: float, poisson_ratio: float, like_surfaces: bool = True) -> float:
    """E' = E / (2 (1 - nu^2)) for two like surfaces (seed 000 eq. 37), E / (1 - nu^2) against a rigid one (eq. 16)."""
    if not (youngs_modulus > 0 and 0 <= poisson_ratio < 0.5):
        raise InputError("Young's modulus must be positive and Poisson's ratio in [0, 0.5)")
    return youngs_modulus / ((2.0 if like_surfaces else 1.0) * (1.0 - poisson_ratio ** 2))


def plasticity_index(contact_modulus_: float, hardness: float, summit_sigma: float, summit_radius: float) -> float:
    """Greenwood-Williamson psi = (E'/H) sqrt(s/R) (seed 000 eq. 36)."""
    if not (contact_modulus_ > 0 and hardness > 0 and summit_sigma > 0 and summit_radius > 0):
        raise InputError("the plasticity index needs a positive modulus, hardness, summit spread and radius")
    return contact_modulus_ / hardness * math.sqrt(summit_sigma / summit_radius)


def elastic_contact_hardness(contact_modulus_: float, summit_sigma: float, summit_radius: float) -> float:
    """GW's elastic contact hardness H' = 0.25 E' sqrt(s/R) (seed 000 eq. 38)."""
    return 0.25 * contact_modulus_ * math.sqrt(summit_sigma / summit_radius)


def hirst_hollander_index(contact_modulus_: float, hardness: float, sigma: float, correlation_length: float) -> float:
    """Hirst & Hollander's psi = 0.6 (E'/H)(sigma / beta*) (seed 000 eq. 15)."""
    return 0.6 * contact_modulus_ / hardness * sigma / correlation_length


def _moments(separation, summit_sigma, distribution, power):
    """int_d^inf (z - d)^power phi(z) dz for the summit-height density phi (mean 0, spread s)."""
    from scipy import integrate, special  # heavy: imported where used

    separation = np.atleast_1d(np.asarray(separation, dtype=float))
    if distribution == "exponential":  # phi = e^(-z/s)/s for z >= 0: closed form
        shifted = np.maximum(separation, 0.0)
        scale = np.exp(-shifted / summit_sigma) * summit_sigma ** power * special.gamma(power + 1)
        below = separation < 0  # a flat below every summit: the moments of (z - d) over z >= 0
        if below.any():
            for index in np.nonzero(below)[0]:
                d = separation[index]
                value, _ = integrate.quad(lambda z: (z - d) ** power * math.exp(-z / summit_sigma) / summit_sigma,
                                          0.0, np.inf, epsabs=0.0, epsrel=1e-10)
                scale[index] = value
        return scale
    if distribution == "gaussian":
        out = np.empty(separation.size)
        for index, d in enumerate(separation):
            low, high = max(d, -40 * summit_sigma), max(d, 0.0) + 40 * summit_sigma  # where phi has its mass
            inside = [0.0] if low < 0.0 < high else None
            value, _ = integrate.quad(lambda z: (z - d) ** power * math.exp(-0.5 * (z / summit_sigma) ** 2)
                                      / (summit_sigma * math.sqrt(2 * math.pi)), low, high, points=inside, limit=200,
                                      epsabs=0.0, epsrel=1e-10)  # moments are tiny in SI: relative accuracy
            out[index] = value
        return out
    raise InputError(f"summit heights must be one of {', '.join(DISTRIBUTIONS)}, got {distribution!r}")


def greenwood_williamson(separation, summit_density: float, summit_radius: float, summit_sigma: float,
                         contact_modulus_: float, nominal_area: float = 1.0, distribution: str = "gaussian") -> dict:
    """Contacts, real area (m^2) and load (N) against the separation d (m) of the flat from the summits'
    mean height, for ``nominal_area`` (m^2). Arrays over ``separation``."""
    if not (summit_density > 0 and summit_radius > 0 and summit_sigma > 0 and contact_modulus_ > 0
            and nominal_area > 0):
        raise InputError("the Greenwood-Williamson model needs positive summit density, radius, spread and modulus")
    scale = summit_density * nominal_area
    count = scale * _moments(separation, summit_sigma, distribution, 0.0)
    area = math.pi * scale * summit_radius * _moments(separation, summit_sigma, distribution, 1.0)
    load = 4.0 / 3.0 * contact_modulus_ * math.sqrt(summit_radius) * scale * _moments(separation, summit_sigma,
                                                                                       distribution, 1.5)
    return {"separation": np.atleast_1d(np.asarray(separation, dtype=float)), "contacts": count, "area": area,
            "load": load}
