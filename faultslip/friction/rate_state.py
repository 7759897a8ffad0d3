"""Rate-and-state friction (Dieterich 1979; Ruina 1983): the law laboratories fit today.

Friction depends on the slip speed V and on state variables theta (s), which evolve with slip:

    mu = mu0 + a ln(V / V0) + b ln(V0 theta / D_c) [+ b2 ln(V0 theta2 / D_c2)]          (1)

    aging law (Dieterich):   d theta/dt = 1 - V theta / D_c                                (2a)
    slip law (Ruina):        d theta/dt = -(V theta / D_c) ln(V theta / D_c)              (2b)

At steady state theta = D_c / V and mu_ss = mu0 + (a - b - b2) ln(V / V0) (3): velocity
weakening where a < b (+ b2). The regularised form (Rice & Ben-Zion 1996; Lapusta et al. 2000)

    mu = a asinh[ V / (2 V0) exp((mu0 + b psi) / a) ]                                      (4)

equals (1) to within exp(-2 mu / a) (about 1e-100 at mu = 0.6, a = 0.005) for V well above
zero, and stays finite, odd and smooth through V = 0, as an inertial slider needs.

State is carried in logarithmic form, psi = ln(V0 theta / D_c), which spans the 10+ decades of
theta between ms slip and centuries of creep with uniform relative accuracy:

    aging:  d psi/dt = (V0 / D_c) exp(-psi) - V / D_c                                        (5a)
    slip:   d psi/dt = -(V / D_c) (ln(V / V0) + psi)                                         (5b)

Units: speeds in m/s, D_c in m, theta in s; a, b, mu0 dimensionless.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from faultslip.errors import InputError
from faultslip.units import to_si_scalar

EVOLUTION_LAWS = ("aging", "slip")


#: Largest reference friction mu0 accepted: rocks give 0.6-0.85 (Byerlee 1978), clean metals up to ~1.5.
MAX_MU0 = 2.0


def steady_state_friction(speed, a, b, mu0=0.6, reference_speed=1e-6, b2=0.0):
    """mu_ss = mu0 + (a - b - b2) ln(V / V0), eq. (3). ``speed`` and ``reference_speed`` in m/s."""
    return mu0 + (a - b - b2) * np.log(np.asarray(speed, dtype=float) / reference_speed)


def friction(speed, psi, a, b, mu0=0.6, reference_speed=1e-6, psi2=0.0, b2=0.0, regularized=False):
    """Friction from speed (m/s) and log-state psi = ln(V0 theta / D_c): eq. (1), or eq. (4) if ``regularized``."""
    speed = np.asarray(speed, dtype=float)
    if regularized:
        z = speed / (2.0 * reference_speed) * np.exp((mu0 + b * psi + b2 * psi2) / a)
        return a * np.arcsinh(z)
    return mu0 + a * np.log(speed / reference_speed) + b * psi + b2 * psi2


def log_state_rate(speed, psi, critical_slip, reference_speed=1e-6, evolution="aging"):
    """d psi / dt (1/s) for the aging (5a) or the slip (5b) law. ``speed`` is |V| (m/s)."""
    speed = np.abs(np.asarray(speed, dtype=float))
    if evolution == "aging":
        return (reference_speed * np.exp(-psi) - speed) / critical_slip
    if evolution == "slip":
        with np.errstate(divide="ignore"):
            return -(speed / critical_slip) * (np.log(speed / reference_speed) + psi)
    raise InputError(f"evolution law must be one of {', '.join(EVOLUTION_LAWS)}, got {evolution!r}")


def steady_state_psi(speed, reference_speed=1e-6):
    """psi at steady state: theta = D_c / V, so psi = ln(V0 / V)."""
    return np.log(reference_speed / np.asarray(speed, dtype=float))


def critical_stiffness(normal_stress, a, b, critical_slip, speed=None, mass=0.0, damping=0.0):
    """Critical stiffness k_c of a one-state slider at steady sliding speed V (same units as the stiffness).

    Linear stability of steady sliding (Ruina 1983; Rice & Ruina 1983), the same for the aging
    and the slip law. With the characteristic equation of the slider (mass m, damper eta, both
    per unit of the area that sigma_n acts on) linearised about steady sliding at speed V,
    lambda = V / D_c and P = m V lambda + eta V + sigma_n a:

        m V s^3 + P s^2 + (eta V lambda + k V + sigma_n lambda (a - b)) s + k V lambda = 0

    Routh-Hurwitz gives the Hopf boundary

        k_c = P lambda (sigma_n (b - a) - eta V) / (V (eta V + sigma_n a)),

    which is sigma_n (b - a) / D_c quasi-statically (m = eta = 0), sigma_n (b - a) / D_c
    [1 + m V^2 / (sigma_n a D_c)] with inertia (Rice & Ruina 1983, eq. 28), and
    (sigma_n (b - a) - eta V) / D_c quasi-dynamically (m = 0): radiation damping lowers it.
    Where b <= a (and so k_c <= 0) steady sliding is stable for every stiffness.
    """
    if mass == 0.0 and damping == 0.0:
        return normal_stress * (b - a) / critical_slip
    if speed is None:
        raise InputError("the critical stiffness with inertia or radiation damping depends on the sliding speed; "
                         "give speed")
    rate = speed / critical_slip
    p = mass * speed * rate + damping * speed + normal_stress * a
    return p * rate * (normal_stress * (b - a) - damping * speed) / (speed * (damping * speed + normal_stress * a))


def characteristic_roots(stiffness, normal_stress, a, b, critical_slip, speed, mass=0.0, damping=0.0):
    """Roots s (1/s) of the linearised slider's characteristic equation (see :func:`critical_stiffness`)."""
    rate = speed / critical_slip
    coefficients = [mass * speed,
                    mass * speed * rate + damping * speed + normal_stress * a,
                    damping * speed * rate + stiffness * speed + normal_stress * rate * (a - b),
                    stiffness * speed * rate]
    while coefficients and coefficients[0] == 0.0:
        coefficients.pop(0)
    return np.roots(coefficients)


@dataclass(frozen=True)
class RateStateLaw:
    """A rate-and-state law with one or two state variables, SI inside.

    ``a``, ``b``, ``critical_slip`` (D_c, m), ``mu0`` and ``reference_speed`` (V0, m/s);
    ``evolution`` is ``"aging"`` or ``"slip"``; ``b2`` and ``critical_slip2`` add a second state
    variable; ``regularized`` uses eq. (4). ``source`` says where the values come from.
    """

    a: float
    b: float
    critical_slip: float
    mu0: float = 0.6
    reference_speed: float = 1e-6
    evolution: str = "aging"
    b2: float = 0.0
    critical_slip2: float | None = None
    regularized: bool = False
    source: str = "given"
    name: str = field(default="rate_state", compare=False)

    def __post_init__(self):
        for label, value in (("a", self.a), ("b", self.b), ("D_c", self.critical_slip), ("mu0", self.mu0),
                             ("V0", self.reference_speed), ("b2", self.b2)):
            if not isinstance(value, (int, float)) or isinstance(value, bool) or not math.isfinite(value):
                raise InputError(f"rate-and-state {label} must be a finite number, got {value!r}")
        if not 0 < self.a < 1:
            raise InputError(f"rate-and-state a = {self.a:g} is outside (0, 1); laboratory values are about 0.001-0.02")
        if not 0 <= self.b < 1:
            raise InputError(f"rate-and-state b = {self.b:g} is outside [0, 1); laboratory values are about 0.001-0.02")
        if not 1e-9 <= self.critical_slip <= 10.0:
            raise InputError(f"D_c = {self.critical_slip:g} m is outside 1 nm - 10 m; laboratory values are 1-100 µm")
        if self.reference_speed <= 0:
            raise InputError(f"V0 must be a positive speed, got {self.reference_speed:g} m/s")
        if not 0 < self.mu0 < MAX_MU0:
            raise InputError(f"rate-and-state mu0 = {self.mu0:g} is outside (0, {MAX_MU0:g}); the friction of rock at the "
                             "reference speed is about 0.6 (Byerlee), of any solid well below 2")
        if self.evolution not in EVOLUTION_LAWS:
            raise InputError(f"evolution law must be one of {', '.join(EVOLUTION_LAWS)}, got {self.evolution!r}")
        if self.b2 and (self.critical_slip2 is None or not self.critical_slip2 > 0):
            raise InputError("a second state variable (b2) needs its own D_c2 > 0")

    @property
    def two_state(self) -> bool:
        return bool(self.b2)

    @classmethod
    def from_text(cls, a, b, critical_slip, mu0=0.6, reference_speed="1 um/s", evolution="aging", b2=0.0,
                  critical_slip2=None, regularized=False, source="given", name="rate_state") -> "RateStateLaw":
        """A law from quantity text: ``critical_slip="10 um"``, ``reference_speed="1 um/s"``."""
        return cls(a=to_si_scalar(a, "dimensionless", "a"), b=to_si_scalar(b, "dimensionless", "b"),
                   critical_slip=to_si_scalar(critical_slip, "length", "D_c"),
                   mu0=to_si_scalar(mu0, "dimensionless", "mu0"),
                   reference_speed=to_si_scalar(reference_speed, "speed", "V0"), evolution=evolution,
                   b2=to_si_scalar(b2, "dimensionless", "b2"),
                   critical_slip2=None if critical_slip2 is None else to_si_scalar(critical_slip2, "length", "D_c2"),
                   regularized=bool(regularized), source=source, name=name)

    def with_evolution(self, evolution: str) -> "RateStateLaw":
        return replace(self, evolution=evolution)

    def steady_state(self, speed):
        """mu_ss(V), eq. (3)."""
        return steady_state_friction(speed, self.a, self.b, self.mu0, self.reference_speed, self.b2)

    def friction(self, speed, psi, psi2=0.0):
        return friction(speed, psi, self.a, self.b, self.mu0, self.reference_speed, psi2, self.b2, self.regularized)

    def critical_stiffness(self, normal_stress, speed=None, mass=0.0, damping=0.0):
        """k_c of the one-state law (:func:`critical_stiffness`); two-state laws have no single closed form."""
        if self.two_state:
            raise InputError("the critical stiffness of a two-state law has no closed form here; use the one-state "
                             "law's b and D_c, or find the boundary by simulation (faultslip stability-rsf)")
        return critical_stiffness(normal_stress, self.a, self.b, self.critical_slip, speed, mass, damping)

    def describe(self) -> str:
        second = f", b2 {self.b2:g}, D_c2 {_length(self.critical_slip2)}" if self.two_state else ""
        return (f"rate-and-state ({self.evolution} law{', regularised' if self.regularized else ''}): a {self.a:g}, "
                f"b {self.b:g}, D_c {_length(self.critical_slip)}{second}, mu0 {self.mu0:g}, "
                f"V0 {self.reference_speed:g} m/s ({self.source})")


def _length(metres: float) -> str:
    return f"{metres * 1e3:g} mm" if metres >= 1e-3 else f"{metres * 1e6:g} µm"


#: Illustrative laboratory values. None of them is a fit to one experiment; each says so.
ILLUSTRATIVE = {
    "granite_illustrative": RateStateLaw(
        a=0.010, b=0.014, critical_slip=20e-6, mu0=0.70, reference_speed=1e-6, name="granite_illustrative",
        source="illustrative: velocity-weakening bare granite at room temperature, a and b about 0.01 and D_c of "
               "tens of µm, the ranges reviewed by Marone (1998, Annu. Rev. Earth Planet. Sci. 26, 643-696)"),
    "gouge_illustrative": RateStateLaw(
        a=0.012, b=0.010, critical_slip=50e-6, mu0=0.60, reference_speed=1e-6, name="gouge_illustrative",
        source="illustrative: velocity-strengthening clay-rich gouge (a > b), within the ranges reviewed by "
               "Marone (1998); not a measurement"),
    "step_example": RateStateLaw(
        a=0.005, b=0.010, critical_slip=10e-6, mu0=0.60, reference_speed=1e-6, name="step_example",
        source="the classic one-state velocity-step example (mu0 0.6, a 0.005, b 0.01, D_c 10 µm) used by "
               "rsfmodel's documentation; illustrative, not a measurement"),
}


def get_law(name: str) -> RateStateLaw:
    """One of the :data:`ILLUSTRATIVE` laws by name."""
    try:
        return ILLUSTRATIVE[name]
    except KeyError:
        raise InputError(f"unknown rate-and-state law {name!r}; bundled: {', '.join(ILLUSTRATIVE)}") from None


def nucleation_size(shear_modulus, critical_slip, a, b, normal_stress):
    """h* = (pi / 2) G D_c b / [sigma_n (b - a)^2] (Rubin & Ampuero 2005, eq. 42), array-wise.

    Parameters
    ----------
    shear_modulus, critical_slip, a, b, normal_stress : float or array_like
        G (Pa), D_c (m), a, b and sigma_n (Pa); they broadcast.

    Returns
    -------
    float or numpy.ndarray
        h* (m); infinite where b <= a (no weakening, nothing nucleates).
    """
    weakening = np.asarray(b, float) - np.asarray(a, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        size = np.where(weakening > 0, math.pi / 2 * np.asarray(shear_modulus, float) * critical_slip * b
                        / (normal_stress * weakening ** 2), np.inf)
    return float(size) if size.ndim == 0 else size


def nucleation_ratio(law, shear_modulus: float, normal_stress: float, width: float) -> float:
    """W / h*, h* of :func:`nucleation_size`; infinite h* (b <= a) gives 0."""
    return width / nucleation_size(shear_modulus, law.critical_slip, law.a, law.b, normal_stress)
