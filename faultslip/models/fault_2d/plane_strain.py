"""Plane-strain elastic fields of slip on a planar dipping fault in a half-space, by complex potentials.

Coordinates follow SEAS BP3 (Erickson et al. 2023, BSSA 113, 499): x horizontal, z depth (positive down), the
free surface z = 0, the fault x = z cot(dip) from the surface down. A point is the complex number zeta = x + i z;
the fault point a distance s down dip is s exp(i dip).

Kolosov-Muskhelishvili (Muskhelishvili 1953, Some Basic Problems of the Mathematical Theory of Elasticity, sec.
32-41; Barber 2010, Elasticity, ch. 19), kappa = 3 - 4 nu in plane strain:

    sigma_xx + sigma_zz = 4 Re Phi,      sigma_zz - sigma_xx + 2 i sigma_xz = 2 (conj(zeta) Phi' + Psi),
    2 G (u + i w) = kappa phi - zeta conj(phi') - conj(psi),      Phi = phi', Psi = psi'.

An edge dislocation at zeta_0 with Burgers vector b (complex) in the whole plane has phi = gamma log(zeta - zeta_0),
gamma = G b / (i pi (kappa + 1)). The free surface is Muskhelishvili's analytic continuation across z = 0
(Phi(zeta) = -conj Phi(conj zeta) - zeta conj Phi'(conj zeta) - conj Psi(conj zeta) below it), which gives

    Phi = gamma / (zeta - zeta_0) - gamma / (zeta - zbar_0) + conj(gamma) (zbar_0 - zeta_0) / (zeta - zbar_0)^2,
    Psi = -Phibar - Phi - zeta Phi',   Phibar(zeta) = conj(Phi(conj(zeta)))

(the image construction of Dundurs 1969, in Mathematical Theory of Dislocations, ASME, 70-115). The logarithms'
cuts run up dip from zeta_0 and from its image, so a dislocation slips the fault from zeta_0 up to the surface,
and uniform slip s on the element [s_1, s_2] down dip is the dislocation at s_2 less the one at s_1.

Slip delta follows BP3 (eq. 6): the footwall's (-) displacement less the hanging wall's (+), along the down-dip
direction, positive for thrust. The shear traction (eq. 13a) is positive where it drives thrust, the normal
traction (eq. 13b) positive in compression. The tests check the surface is free of traction, the displacement
jumps by the slip across the element and nowhere else, Hooke's law between the two fields, and the deep limit
against the whole-plane edge dislocation (which is the antiplane screw dislocation's over 1 - nu).
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.errors import InputError
from faultslip.models.fault_2d.model import ForceBalance


def _kappa(poisson_ratio: float) -> float:
    if not 0.0 <= poisson_ratio < 0.5:
        raise InputError(f"Poisson's ratio must lie in [0, 0.5), got {poisson_ratio!r}")
    return 3.0 - 4.0 * poisson_ratio


def _gamma(burgers: complex, shear_modulus: float, kappa: float) -> complex:
    return shear_modulus * burgers / (1j * math.pi * (kappa + 1.0))


def _setting(points, source: complex, burgers: complex, shear_modulus: float, poisson_ratio: float) -> tuple:
    """(zeta, kappa, gamma, conj(gamma), the image point, zeta - zeta_0, zeta - the image) of one dislocation."""
    zeta = np.asarray(points, dtype=complex)
    kappa = _kappa(poisson_ratio)
    gamma = _gamma(burgers, shear_modulus, kappa)
    image = np.conj(source)
    return zeta, kappa, gamma, np.conj(gamma), image, zeta - source, zeta - image


def _log_cut(w: np.ndarray, angle: float) -> np.ndarray:
    """log(w) with its cut along the ray of direction ``angle`` (radians) from 0."""
    return np.log(-w * np.exp(-1j * angle)) + 1j * (angle - math.pi)


def dislocation_stress(points, source: complex, burgers: complex, shear_modulus: float,
                       poisson_ratio: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(sigma_xx, sigma_zz, sigma_xz) (Pa, tension positive) at ``points`` (complex x + i z, m) of an edge
    dislocation at ``source`` (z > 0) with Burgers vector ``burgers`` (complex, m) in the half-space z > 0."""
    zeta, kappa, gamma, gamma_bar, image, near, far = _setting(points, source, burgers, shear_modulus, poisson_ratio)
    phi = gamma / near - gamma / far + gamma_bar * (image - source) / far ** 2
    phi_prime = -gamma / near ** 2 + gamma / far ** 2 - 2.0 * gamma_bar * (image - source) / far ** 3
    phi_bar = gamma_bar / far - gamma_bar / near + gamma * (source - image) / near ** 2
    psi = -phi_bar - phi - zeta * phi_prime
    total = 4.0 * phi.real  # sigma_xx + sigma_zz
    deviator = 2.0 * (np.conj(zeta) * phi_prime + psi)  # sigma_zz - sigma_xx + 2 i sigma_xz
    return 0.5 * (total - deviator.real), 0.5 * (total + deviator.real), 0.5 * deviator.imag


def dislocation_displacement(points, source: complex, burgers: complex, shear_modulus: float,
                             poisson_ratio: float, cut_angle: float) -> np.ndarray:
    """u + i w (m) at ``points`` of the dislocation of :func:`dislocation_stress`, zero far away; the displacement
    jumps by ``burgers`` across the cut, which runs from ``source`` along ``cut_angle`` (radians, in the x-z plane)
    to the surface and from the image on out of the solid."""
    zeta, kappa, gamma, gamma_bar, image, near, far = _setting(points, source, burgers, shear_modulus, poisson_ratio)
    log_near, log_far = _log_cut(near, cut_angle), _log_cut(far, cut_angle)
    potential = gamma * (log_near - log_far) - gamma_bar * (image - source) / far
    phi = gamma / near - gamma / far + gamma_bar * (image - source) / far ** 2
    phi_bar_integral = gamma_bar * (log_far - log_near) - gamma * (source - image) / near
    psi = -phi_bar_integral - zeta * phi
    return (kappa * potential - zeta * np.conj(phi) - np.conj(psi)) / (2.0 * shear_modulus)


def fault_point(distance, dip: float) -> np.ndarray:
    """x + i z of the fault point ``distance`` (m) down dip from the surface, the fault dipping ``dip`` (degrees)."""
    return np.asarray(distance, float) * np.exp(1j * math.radians(dip))


def _slip_burgers(dip: float) -> complex:
    """The Burgers vector of unit BP3 slip (eq. 6: the footwall less the hanging wall, down dip) across a cut
    running up dip: the displacement on the footwall's side less that on the hanging wall's is the slip times the
    down-dip direction (the potentials' jump, checked in the tests)."""
    return np.exp(1j * math.radians(dip))


def _tractions(sxx, szz, sxz, dip: float) -> tuple[np.ndarray, np.ndarray]:
    """BP3 eq. 13: shear (positive driving thrust) and normal (positive in compression) traction on the fault."""
    sin, cos = math.sin(math.radians(dip)), math.cos(math.radians(dip))
    shear = sin * cos * (szz - sxx) + (cos * cos - sin * sin) * sxz
    normal = -sin * sin * sxx + 2.0 * sin * cos * sxz - cos * cos * szz
    return shear, normal


def traction_kernels(count: int, element_size: float, dip: float, shear_modulus: float,
                     poisson_ratio: float) -> tuple[np.ndarray, np.ndarray]:
    """(K_shear, K_normal) (Pa per m of slip), (count, count): the traction at the centre of element i from unit
    slip on element j, elements of ``element_size`` from the surface down dip."""
    if count < 2:
        raise InputError(f"a 2-D fault needs at least 2 elements, got {count}")
    if not 0.0 < dip <= 90.0:
        raise InputError(f"the dip must lie in (0, 90] degrees, got {dip!r}")
    centres = fault_point((np.arange(count) + 0.5) * element_size, dip)
    burgers = _slip_burgers(dip)
    # the dislocation at each element's lower end, and the differences of neighbours
    ends = [dislocation_stress(centres, complex(point), burgers, shear_modulus, poisson_ratio)
            for point in fault_point(np.arange(1, count + 1) * element_size, dip)]
    shear = np.empty((count, count))
    normal = np.empty((count, count))
    previous = None
    for j, fields in enumerate(ends):
        tau, sigma = _tractions(*fields, dip)
        if previous is None:  # the element from the surface: a dislocation at the free surface stresses nothing
            shear[:, j], normal[:, j] = tau, sigma
        else:
            shear[:, j], normal[:, j] = tau - previous[0], sigma - previous[1]
        previous = (tau, sigma)
    return shear, normal


def surface_kernel(positions, count: int, element_size: float, dip: float, shear_modulus: float,
                   poisson_ratio: float) -> np.ndarray:
    """(2, stations, count): horizontal u (positive in +x) and vertical w (positive down) displacement (m) at the
    surface points x = ``positions`` (m) from unit slip on each element. A station at the trace (x = 0) is taken on
    the hanging wall's side, at 0+ (SEAS's ``fn+00``), and one at -0.0 on the footwall's (``fn-00``): the slip of the
    first element breaks the surface there."""
    points = _off_trace(positions, element_size).astype(complex)
    burgers = _slip_burgers(dip)
    cut = math.radians(dip) + math.pi
    ends = [dislocation_displacement(points, complex(point), burgers, shear_modulus, poisson_ratio, cut)
            for point in fault_point(np.arange(count + 1) * element_size, dip)]
    out = np.empty((2, points.size, count))
    for j in range(count):
        field = ends[j + 1] - ends[j]
        out[0, :, j], out[1, :, j] = field.real, field.imag
    return out


def _off_trace(positions, element_size: float) -> np.ndarray:
    """Surface positions with the trace (x = 0) moved a hair to its side: 0.0 to 0+, -0.0 to 0-."""
    positions = np.asarray(positions, float)
    return np.where(positions == 0.0, np.copysign(1e-9 * element_size, positions), positions)


#: SEAS BP3's surface stations (m): fn-32 .. fn+32, the trace's two sides as -0.0 and 0.0.
BP3_SURFACE_STATIONS = (-32e3, -16e3, -8e3, -0.0, 0.0, 8e3, 16e3, 32e3)


def rigid_motion(positions, time: float, plate_rate: float, dip: float) -> np.ndarray:
    """(2, stations): BP3 eq. 4, each side's rigid translation at ``time``: -+ V_p t / 2 (cos dip, sin dip), the
    hanging wall (x > z cot dip, +) moving up dip for thrust; -0.0 is on the footwall's side."""
    side = np.where(np.signbit(np.asarray(positions, float)), -1.0, 1.0)
    angle = math.radians(dip)
    return np.stack([-side * plate_rate * time / 2.0 * math.cos(angle), -side * plate_rate * time / 2.0 * math.sin(angle)])


class PlaneStrainOperator:
    """The dense traction kernels of a plane-strain fault: ``operator(deficit)`` is the shear traction change
    K_shear (delta - V_p t), :meth:`normal` the normal one, both from one product with the stacked matrix. A normal
    fault's slip runs the other way (BP3's V_p < 0): with slip kept positive, its normal kernel changes sign."""

    method = "dense"

    def __init__(self, fault):
        shear, normal = traction_kernels(fault.count, fault.element_size, fault.dip, fault.shear_modulus,
                                         fault.poisson_ratio)
        self.count = fault.count
        self.matrix = np.ascontiguousarray(np.vstack([shear, normal if fault.sense == "thrust" else -normal]))
        self._last = np.zeros(2 * fault.count)

    def both(self, deficit: np.ndarray) -> np.ndarray:
        """(shear change, normal change) stacked, each N long (Pa)."""
        self._last = self.matrix @ deficit
        return self._last

    def __call__(self, deficit: np.ndarray) -> np.ndarray:
        return self.both(deficit)[: self.count]


class PlaneStrainBalance(ForceBalance):
    """The force balance of :class:`faultslip.models.fault_2d.model.ForceBalance` with the normal stress changing
    with slip (BP3 eq. 15): sigma_n = sigma_n0 + K_normal (delta - V_p t), set before each solve. A trial state
    that would open the fault (sigma_n <= 0) has no slip rate: NaN, which the integrator rejects."""

    def __init__(self, fault, operator: PlaneStrainOperator, compiled: bool | None = None):
        super().__init__(fault, operator, compiled)
        self.normal_stress = fault.normal_stress.copy()
        self._opened = np.zeros(fault.count, dtype=bool)

    def quasi_static_stress(self, time: float, slip: np.ndarray) -> np.ndarray:
        changes = self.kernel.both(slip - self.fault.plate_rate * time)
        count = self.fault.count
        self.normal_stress = self.fault.normal_stress + changes[count:]
        self._opened = ~(self.normal_stress > 0.0)
        self.sigma_a = np.where(self._opened, 1.0, self.normal_stress) * self.fault.a
        return self.fault.initial_shear_stress + changes[:count]

    def rates(self, time: float, slip: np.ndarray, psi: np.ndarray):
        speed, psi_rate, stress = super().rates(time, slip, psi)
        if np.any(self._opened):
            speed = np.where(self._opened, np.nan, speed)
        return speed, psi_rate, stress
