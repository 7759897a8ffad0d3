"""The 2-D fault's parameters in depth, its force balance and its rates.

Quasi-dynamic force balance on each element (Rice 1993; SEAS BP1, Erickson et al. 2020, SRL 91,
874, eqs. 1-6), with the regularised rate-and-state friction:

    tau_0 + K (delta - V_pl t) - eta V = sigma_n a asinh[V / (2 V_0) exp(psi / a)],   eta = G / (2 c_s),

    aging law:  d psi / dt = (b V_0 / D_c) [exp((f_0 - psi) / b) - V / V_0],
    slip law:   d psi / dt = -(V / D_c) [psi - f_0 + b ln(V / V_0)],

with psi = f_0 + b ln(V_0 theta / D_c). The slip rate is solved element by element in
u = asinh[V / (2 V_0) exp(psi / a)], so that V = 2 V_0 exp(-psi / a) sinh(u) and

    g(u) = sigma_n a u + 2 eta V_0 exp(-psi / a) sinh(u) - tau_qs = 0.

g is increasing and convex in u where tau_qs > 0 (concave where < 0), so Newton's method converges
from any start, after one step monotonically; u is ln(V / V_0) + psi / a for V well above
V_0 exp(-psi / a), the logarithm of the slip rate, which keeps the solve well conditioned from
1e-20 m/s to metres per second.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from faultslip.models.fault_2d import compiled as compiled_kernel
from faultslip.errors import InputError, SolverError
from faultslip.fault.ladder import FaultDescription
from faultslip.friction.rate_state import nucleation_size

#: Newton iterations allowed for the slip rate; more means the state is not finite.
NEWTON_ITERATIONS = 200  # safeguarded: bisection alone would need ~60 from a double's range
#: The force balance's share of the integrator's tolerance: an implicit solve is stopped once its error is a small
#: fraction kappa of the step's (Hairer & Wanner, Solving ODEs II, IV.8, eq. 8.10, with kappa 1e-1 to 1e-2); 1e-3
#: here. On SEAS BP1 (1024 elements, rtol 1e-4) most solves then stop after one Newton step instead of two,
#: a third of a run's time.
NEWTON_SHARE = 1e-3


def newton_tolerance(rtol: float) -> float:
    """The force balance's tolerance on u^2 for an integrator at ``rtol``: a Newton step du with
    du^2 <= NEWTON_SHARE rtol (1 + |u|) leaves an error in u, and so a relative error in V, of at most half that."""
    return NEWTON_SHARE * rtol


@dataclass
class Fault2D:
    """A planar fault from the surface down to ``width``, in N elements of ``element_size``.

    Every array holds one value per element, its centre a distance (i + 1/2) h down dip (``depth``: the depth itself
    on a vertical fault; :attr:`true_depth` on a dipping one). SI units.

    ``plane``: "antiplane" (a vertical strike-slip fault, slip along strike; Rice 1993, SEAS BP1) or "strain"
    (slip down dip in plane strain, a fault dipping ``dip`` degrees, with a free surface: SEAS BP3, whose normal
    stress changes with slip; :mod:`faultslip.models.fault_2d.plane_strain`). ``sense``: "thrust" or "normal" in
    plane strain (slip, slip rate and shear stress are kept positive; a normal fault's slip unclamps where a
    thrust's clamps).
    """

    element_size: float  # m
    a: np.ndarray
    b: np.ndarray
    critical_slip: np.ndarray  # m
    normal_stress: np.ndarray  # Pa
    shear_modulus: float  # Pa
    shear_wave_speed: float  # m/s
    plate_rate: float  # m/s, imposed below the fault
    reference_speed: float  # m/s, V_0
    reference_friction: float  # f_0
    initial_shear_stress: np.ndarray  # Pa (tau_0)
    initial_state: np.ndarray  # psi at t = 0
    evolution: str = "aging"
    name: str = "2-D fault"
    notes: list = field(default_factory=list)
    plane: str = "antiplane"
    dip: float = 90.0  # degrees
    sense: str = "thrust"  # plane strain only
    poisson_ratio: float = 0.25  # plane strain only

    #: the geometries this class holds (the 3-D fault, built on it, holds its own)
    PLANES = ("antiplane", "strain")
    KIND = "2-D fault"

    def __post_init__(self):
        arrays = ("a", "b", "critical_slip", "normal_stress", "initial_shear_stress", "initial_state")
        count = None
        for key in arrays:
            value = np.ascontiguousarray(getattr(self, key), dtype=float)
            if value.ndim != 1 or (count is not None and value.size != count):
                raise InputError(f"{self.KIND}: {key} must hold one value per element")
            if not np.all(np.isfinite(value)):
                raise InputError(f"{self.KIND}: {key} must be finite")
            count = value.size
            setattr(self, key, value)
        for key in ("a", "critical_slip", "normal_stress"):
            if np.any(getattr(self, key) <= 0):
                raise InputError(f"{self.KIND}: {key} must be positive everywhere")
        if np.any(self.b < 0):
            raise InputError(f"{self.KIND}: b must not be negative")
        for key in ("element_size", "shear_modulus", "shear_wave_speed", "plate_rate", "reference_speed"):
            value = getattr(self, key)
            if not (math.isfinite(value) and value > 0):
                raise InputError(f"{self.KIND}: {key} must be a positive number, got {value!r}")
        if self.evolution not in ("aging", "slip"):
            raise InputError(f"{self.KIND}: evolution must be aging or slip, got {self.evolution!r}")
        if self.plane not in self.PLANES:
            raise InputError(f"{self.KIND}: plane must be {' or '.join(self.PLANES)}, got {self.plane!r}")
        if not (isinstance(self.dip, (int, float)) and 0.0 < self.dip <= 90.0):
            raise InputError(f"{self.KIND}: the dip must lie in (0, 90] degrees, got {self.dip!r}")
        if self.plane == "antiplane" and self.dip != 90.0:
            raise InputError(f"{self.KIND}: an antiplane fault is vertical (dip 90 degrees), got {self.dip:g}; a "
                             "dipping fault slips in plane strain: set plane = \"strain\"")
        if self.sense not in ("thrust", "normal"):
            raise InputError(f"{self.KIND}: sense must be thrust or normal, got {self.sense!r}")
        if not (isinstance(self.poisson_ratio, (int, float)) and 0.0 <= self.poisson_ratio < 0.5):
            raise InputError(f"{self.KIND}: Poisson's ratio must lie in [0, 0.5), got {self.poisson_ratio!r}")

    @property
    def count(self) -> int:
        return self.a.size

    @property
    def width(self) -> float:
        return self.count * self.element_size

    @property
    def depth(self) -> np.ndarray:
        return (np.arange(self.count) + 0.5) * self.element_size

    @property
    def true_depth(self) -> np.ndarray:
        """The element centres' depth below the surface (m): their distance down dip times sin(dip)."""
        return self.depth * math.sin(math.radians(self.dip))

    @property
    def damping(self) -> float:
        """Radiation damping eta = G / (2 c_s) (Pa s/m)."""
        return self.shear_modulus / (2.0 * self.shear_wave_speed)

    def nucleation_size(self) -> float:
        """h* = (pi / 2) G D_c b / [sigma_n (b - a)^2] at the weakest element (Rubin & Ampuero 2005, eq. 42)."""
        return float(np.min(nucleation_size(self.shear_modulus, self.critical_slip, self.a, self.b,
                                            self.normal_stress)))

    def process_zone(self) -> float:
        """L_b = G D_c / (sigma_n b), the cohesive-zone scale an element must resolve (Day et al. 2005)."""
        with np.errstate(divide="ignore", over="ignore"):  # a vanishing sigma_n b gives an unbounded L_b, not a warning
            values = self.shear_modulus * self.critical_slip / (self.normal_stress * self.b)
        return float(np.min(values))

    def seismogenic_width(self) -> float:
        """Depth extent of the velocity-weakening part (b > a)."""
        return float(np.sum(self.b > self.a) * self.element_size)

    def description(self) -> FaultDescription:
        """The fault as every rung of the ladder reads it (:class:`faultslip.fault.ladder.FaultDescription`)."""
        return FaultDescription(self.depth, self.a, self.b, self.critical_slip, self.normal_stress, self.element_size,
                                self.shear_modulus, self.shear_wave_speed, self.plate_rate, self.reference_speed,
                                self.reference_friction, self.evolution, self.name, self.plane, self.dip, self.sense,
                                self.poisson_ratio)

    def state_to_theta(self, psi: np.ndarray) -> np.ndarray:
        """theta = (D_c / V_0) exp((psi - f_0) / b) (s); for b = 0 the state has no meaning (returns D_c / V_0)."""
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
            safe_b = np.where(self.b > 0, self.b, 1.0)
            return self.critical_slip / self.reference_speed * np.exp(np.where(self.b > 0,
                                                                              (psi - self.reference_friction) / safe_b, 0.0))


class ForceBalance:
    """The slip rate and the state rate of every element; keeps the last u as a warm start.

    ``compiled``: the numba kernel (:mod:`faultslip.models.fault_2d.compiled`) where numba is here
    (None: where available), else the same iteration vectorised in numpy.
    """

    def __init__(self, fault: Fault2D, kernel, compiled: bool | None = None):
        self.fault, self.kernel = fault, kernel
        self.sigma_a = fault.normal_stress * fault.a
        self.inverse_a = 1.0 / fault.a
        self.damping = fault.damping
        self.two_v0_eta = 2.0 * fault.reference_speed * fault.damping
        self.aging_rate = fault.b * fault.reference_speed / fault.critical_slip
        self.inverse_b = np.where(fault.b > 0, 1.0 / np.where(fault.b > 0, fault.b, 1.0), 0.0)
        self.aging = fault.evolution == "aging"
        self.compiled = compiled_kernel.available() if compiled is None else compiled
        self._balance = compiled_kernel.balance() if self.compiled else None
        self.u = None  # the last solution, a warm start (part of a checkpoint)
        self.tolerance = 0.0  # the Newton solve's, on u^2 (0: to round-off); a run sets newton_tolerance(rtol)

    def quasi_static_stress(self, time: float, slip: np.ndarray) -> np.ndarray:
        """tau_0 + K (delta - V_pl t): the stress without radiation damping (Pa)."""
        return self.fault.initial_shear_stress + self.kernel(slip - self.fault.plate_rate * time)

    def _failed(self, element: int):
        raise SolverError(f"{self.fault.KIND}: the force balance did not converge at element {element} (depth "
                          f"{self.fault.depth[element]:.4g} m) after {NEWTON_ITERATIONS} Newton steps; the state "
                          "is not finite there. Tighten rtol")

    def slip_rate(self, stress: np.ndarray, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(V, u) from the force balance at quasi-static stress ``stress`` and state ``psi`` (numpy); NaN where
        the state has no finite slip rate (|tau / (sigma_n a)| beyond 700), which the integrator rejects."""
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return self._slip_rate(stress, psi)

    def _slip_rate(self, stress, psi):
        coefficient = self.two_v0_eta * np.exp(-psi * self.inverse_a)
        bound = stress / self.sigma_a
        absurd = ~(np.abs(bound) < 700.0) | ~(coefficient > 0)  # V would overflow: a trial state to reject
        stress = np.where(absurd, 0.0, stress)
        coefficient = np.where(absurd, 1.0, coefficient)
        bound = np.where(absurd, 0.0, bound)
        low, high = np.minimum(0.0, bound), np.maximum(0.0, bound)  # the root lies between them (g is monotone)
        u = self.u.copy() if self.u is not None else bound.copy()
        outside = (u < low) | (u > high)
        u[outside] = bound[outside]
        # asinh(tau / c), where the friction term vanishes, is beyond the root too: a start past it moves there
        past = np.abs(coefficient * np.sinh(u)) > np.abs(stress)
        if np.any(past):
            u[past] = np.arcsinh(stress[past] / coefficient[past])
            high = np.where(past & (stress >= 0), u, high)
            low = np.where(past & (stress < 0), u, low)
        for _ in range(NEWTON_ITERATIONS):
            residual = self.sigma_a * u + coefficient * np.sinh(u) - stress
            overflow = ~np.isfinite(residual)  # no finite slip rate here: an absurd trial state
            if np.any(overflow):
                absurd |= overflow
                residual[overflow] = 0.0
            high = np.where(residual > 0, u, high)
            low = np.where(residual > 0, low, u)
            proposal = u - residual / (self.sigma_a + np.where(absurd, 0.0, coefficient * np.cosh(u)))
            leaves = ~((low <= proposal) & (proposal <= high))  # inclusive: at the root a step may land on a bound
            proposal[leaves] = 0.5 * (low + high)[leaves]  # a step leaving the bracket bisects it
            step = u - proposal
            u = proposal
            scale = 1.0 + np.abs(u)
            if np.all((~leaves & ((np.abs(step) <= 1e-10 * scale) | (step * step <= self.tolerance * scale)))
                      | (high - low <= 4e-16 * scale)):
                break
        else:
            self._failed(int(np.argmax(np.abs(step))))
        self.u = u
        return np.where(absurd, np.nan, coefficient * np.sinh(u) / self.damping), u

    def rates(self, time: float, slip: np.ndarray, psi: np.ndarray):
        """(V, d psi / dt, quasi-static stress)."""
        stress = self.quasi_static_stress(time, slip)
        fault = self.fault
        if self.compiled:
            if self.u is None:
                self.u = stress / self.sigma_a  # the bracket's outer end
            speed, psi_rate = np.empty_like(stress), np.empty_like(stress)
            self._balance(stress, stress, False, stress, psi, self.u, self.sigma_a, self.inverse_a, self.two_v0_eta,
                          1.0 / self.damping, self.aging, self.aging_rate, fault.reference_friction, self.inverse_b,
                          fault.reference_speed, fault.critical_slip, fault.b, speed, psi_rate, NEWTON_ITERATIONS,
                          self.tolerance)
            return speed, psi_rate, stress  # NaN where a trial state has no finite slip rate: the step is rejected
        speed, _ = self.slip_rate(stress, psi)
        with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
            return speed, self._psi_rate(speed, psi), stress

    def _psi_rate(self, speed, psi):
        fault = self.fault
        if self.aging:
            return self.aging_rate * (np.exp((fault.reference_friction - psi) * self.inverse_b)
                                      - speed / fault.reference_speed)
        return -(speed / fault.critical_slip) * (psi - fault.reference_friction
                                                 + fault.b * np.log(speed / fault.reference_speed))


def steady_initial_conditions(a, b, normal_stress, damping, initial_speed, reference_speed, reference_friction,
                              stress_a=None):
    """SEAS BP1's initial stress and state: sliding at ``initial_speed`` everywhere, in steady state
    where a = ``stress_a`` (BP1: a_max), the state set so that V = initial_speed at every depth.

        tau_0 = sigma_n a_max asinh[V_init / (2 V_0) exp((f_0 + b ln(V_0 / V_init)) / a_max)] + eta V_init,
        psi_0 = a ln[(2 V_0 / V_init) sinh((tau_0 - eta V_init) / (a sigma_n))]

    (Erickson et al. 2020, BP1 eqs. 8-9, with theta written as psi).
    """
    a = np.asarray(a, float)
    stress_a = a.max() if stress_a is None else stress_a
    tau0 = normal_stress * stress_a * np.arcsinh(initial_speed / (2 * reference_speed) * np.exp(
        (reference_friction + b * np.log(reference_speed / initial_speed)) / stress_a)) + damping * initial_speed
    # a ln(2 V0 / V sinh(x)) with x = (tau0 - eta V) / (a sigma): sinh(x) overflows past x ~ 710, so
    # ln sinh(x) = x + ln((1 - exp(-2x)) / 2) for large x
    x = (tau0 - damping * initial_speed) / (a * normal_stress)
    log_sinh = np.where(x > 20, x + np.log1p(-np.exp(-2 * np.minimum(x, 700))) - math.log(2.0),
                        np.log(np.sinh(np.minimum(x, 20))))
    psi0 = a * (np.log(2 * reference_speed / initial_speed) + log_sinh)
    return np.broadcast_to(tau0, a.shape).astype(float), np.asarray(psi0, float)
