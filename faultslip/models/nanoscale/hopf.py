"""Seed 001's toy model at its Hopf point: the first Lyapunov coefficient and the small cycle's normal form.

Steady sliding loses stability at A = A_c through a Hopf bifurcation of the three-variable system (u = X',
F, Sigma) of eqs. (1), (2), (4). With x the deviation from steady sliding, x' = J x + B(x, x)/2 + C(x, x, x)/6
and, from phi's Taylor series and the exact quadratic terms of the charge,

    B_u(p, q) = -phi''(v_a) p_u q_u - 2 f_ch p_S q_S,   B_F = 0,   B_S(p, q) = -(p_u q_S + p_S q_u) / a
    C_u(p, q, r) = -phi'''(v_a) p_u q_u r_u,            C_F = C_S = 0.

At A_c, J q = i omega_0 q, J^T p = -i omega_0 p, <p, q> = 1, and the first Lyapunov coefficient is
(Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., 2004, §5.4: the projection formula)

    l_1 = Re[<p, C(q, q, q*)> - 2 <p, B(q, J^-1 B(q, q*))> + <p, B(q*, (2 i omega_0 - J)^-1 B(q, q))>] / (2 omega_0).

l_1 < 0 (supercritical): below A_c a small stable cycle grows as sqrt(A_c - A). Its normal form
z' = (sigma + i omega_0) z + omega_0 l_1 z |z|^2, with sigma the largest growth rate of small disturbances at A,
settles on |z|^2 = -sigma / (omega_0 l_1); x = z q + conj(z q), so the force swings 4 |z| |q_F| peak to peak,
the least speed is v_a - 2 |z| |q_u| and the period 2 pi / omega_0, each to a relative O(sigma / omega_0).

l_1 > 0 (subcritical): the small cycle is unstable and exists above A_c; steady sliding there is stable to small
disturbances only, and a tip started from rest can settle on a large stick-slip cycle (bistability).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class HopfPoint:
    """The Hopf point of a model: omega_0 at A_c, l_1 and the critical eigenvectors (u, F, Sigma)."""

    critical_damping: float
    frequency: float  # omega_0, in omega
    lyapunov: float  # l_1, for q normalised as numpy's eigenvector (the cycle's size does not depend on it)
    right: np.ndarray  # q
    left: np.ndarray  # p, with <p, q> = 1

    @property
    def supercritical(self) -> bool:
        return self.lyapunov < 0


def weakening_derivatives(model) -> tuple[float, float, float]:
    """phi', phi'' and phi''' at v_a, for phi(u) = r / (1 + r^2), r = u / v_m:

    phi' = (1 - r^2) / (v_m (1 + r^2)^2), phi'' = 2 r (r^2 - 3) / (v_m^2 (1 + r^2)^3),
    phi''' = -6 (r^4 - 6 r^2 + 1) / (v_m^3 (1 + r^2)^4)."""
    r, v_m = model.drive_speed / model.peak_speed, model.peak_speed
    s = 1.0 + r * r
    return ((1.0 - r * r) / (v_m * s * s), 2.0 * r * (r * r - 3.0) / (v_m ** 2 * s ** 3),
            -6.0 * (r ** 4 - 6.0 * r * r + 1.0) / (v_m ** 3 * s ** 4))


def jacobian(model) -> np.ndarray:
    """J of (u, F, Sigma) about steady sliding: rows u' = F - A u - phi(u) - f_ch Sigma^2, F' = v_a - u,
    Sigma' = (1 - Sigma) / tau - u Sigma / a."""
    slope = weakening_derivatives(model)[0]
    charge, a = model.steady_charge, model.charge_length
    return np.array([[-(model.damping + slope), 1.0, -2.0 * model.charge_force * charge],
                     [-1.0, 0.0, 0.0],
                     [-charge / a, 0.0, -(1.0 / model.charging_time + model.drive_speed / a)]])


def taylor_forms(model):
    """B and C of the module docstring at the model's steady sliding, as functions of (u, F, Sigma) vectors
    (complex allowed): x' = J x + B(x, x) / 2 + C(x, x, x) / 6 + O(|x|^4)."""
    _slope, curvature, third = weakening_derivatives(model)
    f_ch, a = model.charge_force, model.charge_length

    def quadratic(x, y):
        return np.array([-curvature * x[0] * y[0] - 2.0 * f_ch * x[2] * y[2], 0.0, -(x[0] * y[2] + x[2] * y[0]) / a])

    def cubic(x, y, z):
        return np.array([-third * x[0] * y[0] * z[0], 0.0, 0.0])

    return quadratic, cubic


def hopf_point(model) -> HopfPoint | None:
    """The Hopf point of ``model``'s parameters (at its A_c); None where A_c has no purely imaginary pair
    (no oscillatory loss of stability: A_c <= 0 or a real root crossing)."""
    critical = model.critical_damping
    if not (math.isfinite(critical) and critical > 0):
        return None
    at = replace(model, damping=critical)
    matrix = jacobian(at)
    values, vectors = np.linalg.eig(matrix)
    k = int(np.argmax(values.imag))
    frequency = float(values[k].imag)
    if not frequency > 0 or abs(values[k].real) > 1e-8 * frequency:
        return None
    right = vectors[:, k]
    left_values, left_vectors = np.linalg.eig(matrix.T)
    left = left_vectors[:, int(np.argmin(np.abs(left_values + 1j * frequency)))]
    left = left / np.conj(np.vdot(left, right))  # <p, q> = conj(p) . q = 1
    quadratic, cubic = taylor_forms(at)
    conjugate = np.conj(right)
    total = (np.vdot(left, cubic(right, right, conjugate))
             - 2.0 * np.vdot(left, quadratic(right, np.linalg.solve(matrix, quadratic(right, conjugate))))
             + np.vdot(left, quadratic(conjugate, np.linalg.solve(2j * frequency * np.eye(3) - matrix,
                                                                  quadratic(right, right)))))
    return HopfPoint(critical, frequency, float(total.real) / (2.0 * frequency), right, left)


def growth_rate(model) -> float:
    """sigma: the largest real part of the small disturbances' growth rates at the model's A."""
    return float(np.max(model.characteristic_roots().real))


def normal_form_cycle(model, point: HopfPoint) -> tuple[float, float, float]:
    """(force swing, period, least speed) of the small cycle below a supercritical A_c, to leading order in
    sigma / omega_0 (module docstring): 4 |z| |q_F|, 2 pi / omega_0 and v_a - 2 |z| |q_u|, |z|^2 =
    -sigma / (omega_0 l_1)."""
    sigma = growth_rate(model)
    radius = math.sqrt(max(-sigma / (point.frequency * point.lyapunov), 0.0))
    return (4.0 * radius * float(abs(point.right[1])), 2.0 * math.pi / point.frequency,
            model.drive_speed - 2.0 * radius * float(abs(point.right[0])))
