"""Closed-form stick-slip of the spring-slider (seed 003 eqs. 2-3, 2-8, 2-16 to 2-19).

The closed form assumes the slip phase starts from rest relative to the
ground (platform speed neglected during slip). It is exact only as the loading
rate tends to zero; its error grows with the dimensionless rate
``epsilon = theta_dot / (omega_n (mu_s - mu_m))`` (see
:mod:`faultslip.dynamics.spring_slider.exact_cycle`), and above the critical loading rate it predicts
stick-slip where there is none.

All functions are pure and vectorised (numpy, xarray). SI units throughout.
"""

from __future__ import annotations

import numpy as np

from faultslip.friction.laws import static_friction_excess
from faultslip.dynamics.spring_slider.critical import cached_critical_dimensionless_rate
from faultslip.dynamics.spring_slider.exact_cycle import slip_cycle
from faultslip.dynamics.shared.cycle import CycleResult, GROWING_OSCILLATION, STICK_SLIP
from faultslip.errors import MethodError, OutOfDomainWarning
from faultslip.ranges import NON_NEGATIVE
from faultslip.units import takes_units
import warnings


@takes_units(stiffness="stiffness|stress_per_length", platform_speed="speed", normal_load="force|pressure")
def loading_rate(stiffness, platform_speed, normal_load):
    r"""Loading rate :math:`\dot\theta = K V / W` in 1/s (seed 003 eq. 2-3).

    The rate of growth of shear force over normal load while the slider sticks.

    Parameters
    ----------
    stiffness : array_like
        K in N/m (lab) or Pa/m (per unit fault area).
    platform_speed : array_like
        V in m/s (for a fault, the tectonic slip rate).
    normal_load : array_like
        W in N (lab) or the effective normal stress in Pa (fault).

    Returns
    -------
    ndarray or float
        theta_dot (1/s).
    """
    return stiffness * platform_speed / normal_load


def platform_speed(stiffness, loading_rate, normal_load):
    r"""Platform speed :math:`V = \dot\theta W / K` in m/s: eq. 2-3 inverted."""
    return loading_rate * normal_load / stiffness


def natural_frequency(stiffness, mass):
    r"""Undamped natural frequency :math:`\omega_n = \sqrt{K/M}` in rad/s."""
    return np.sqrt(stiffness / mass)


def damping_ratio(stiffness, mass, dashpot=0.0, kinetic_slope=0.0, normal_load=0.0):
    r"""Damping ratio of the slip phase (seed 003, definitions under eq. 2-8).

    .. math:: \zeta = \frac{C + \beta W}{2\sqrt{K M}}

    ``kinetic_slope`` is :math:`\beta` of the linear kinetic law
    :math:`\mu = \mu_m + \beta (V - \dot x)` (eq. 2-7) in s/m; a friction that
    weakens with sliding speed has :math:`\beta < 0` and can make
    :math:`\zeta` negative (growing oscillation).
    """
    return (dashpot + kinetic_slope * normal_load) / (2.0 * np.sqrt(stiffness * mass))


def dashpot_for_damping_ratio(damping_ratio, stiffness, mass):
    r"""Dashpot :math:`C = 2\zeta\sqrt{K M}` giving damping ratio :math:`\zeta`."""
    return 2.0 * damping_ratio * np.sqrt(stiffness * mass)


def decay_parameter(damping_ratio):
    r""":math:`\lambda = \zeta / \sqrt{1 - \zeta^2}` (seed 003, under eq. 2-8).

    The envelope of the damped oscillation decays by :math:`e^{-\lambda\pi}`
    per half cycle. Defined for :math:`|\zeta| < 1`; NaN otherwise (no
    oscillation).
    """
    zeta = damping_ratio
    one_minus = 1.0 - zeta * zeta
    with np.errstate(invalid="ignore", divide="ignore"):
        root = np.sqrt(np.where(one_minus > 0, one_minus, np.nan))
    return zeta / root


def overshoot_factor(damping_ratio):
    r""":math:`1 + e^{-\lambda\pi}`: peak-to-peak swing of a damped half cycle per unit offset.

    Derived from seed 003 eq. 2-15: the slip starts at rest at
    :math:`x_1 = W\mu_s/K`, swings about :math:`W\mu_m/K`, and stops half a
    damped period later at :math:`x_2 = W\mu_m/K - e^{-\lambda\pi}(x_1 - W\mu_m/K)`.
    Hence :math:`\alpha = x_1 - x_2 = (W/K)(\mu_s - \mu_m)(1 + e^{-\lambda\pi})`.
    Seed eq. 2-17 prints a minus sign, which would give zero amplitude for an
    undamped slider; eq. 2-19 has the correct plus sign.
    """
    return 1.0 + np.exp(-np.pi * decay_parameter(damping_ratio))


@takes_units(normal_load="force|pressure", stiffness="stiffness|stress_per_length")
def slip_amplitude(normal_load, stiffness, static_excess, damping_ratio=0.0):
    r"""Peak-to-peak stick-slip amplitude (seed 003 eq. 2-16/2-17, sign corrected).

    .. math:: \alpha = \frac{W}{K}(\mu_s - \mu_m)(1 + e^{-\lambda\pi})

    Parameters
    ----------
    normal_load : array_like
        W in N, or normal stress in Pa for a fault.
    stiffness : array_like
        K in N/m, or Pa/m for a fault.
    static_excess : array_like
        :math:`\mu_s - \mu_m`.
    damping_ratio : array_like
        :math:`\zeta`, ``|zeta| < 1``.

    Returns
    -------
    alpha : array_like
        Amplitude in m.
    """
    return normal_load / stiffness * static_excess * overshoot_factor(damping_ratio)


@takes_units(domains={"loading_rate": NON_NEGATIVE}, loading_rate="rate", normal_load="force|pressure",
             stiffness="stiffness|stress_per_length")  # a loading rate of 0: the static friction mu_so
def rate_law_amplitude(loading_rate, normal_load, stiffness, mu_so, mu_m, b, d, damping_ratio=0.0):
    r"""Stick-slip amplitude with the static-friction rate law (seed 003 eq. 2-19).

    .. math::

        \alpha = \frac{W}{K}\,\frac{1}{1/(\mu_{so}-\mu_m) + b\dot\theta^d}\,(1 + e^{-\lambda\pi})

    Falls monotonically as the loading rate rises, tends to
    :math:`(W/K)(\mu_{so}-\mu_m)(1+e^{-\lambda\pi})` as it tends to 0, to 0 as
    it tends to infinity, and is 0 when :math:`\mu_{so} = \mu_m`.

    Parameters
    ----------
    loading_rate : array_like
        theta_dot (1/s).
    normal_load : array_like
        W (N or Pa).
    stiffness : array_like
        K (N/m or Pa/m).
    mu_so, mu_m, b, d : array_like
        The rate law of eq. 2-18.
    damping_ratio : array_like
        zeta.

    Returns
    -------
    ndarray or float
        alpha (m).
    """
    excess = static_friction_excess(loading_rate, mu_so, mu_m, b, d)
    return slip_amplitude(normal_load, stiffness, excess, damping_ratio)


def low_rate_amplitude(normal_load, stiffness, mu_so, mu_m):
    r"""Light-damping, low-rate limit :math:`\alpha = 2 (W/K)(\mu_{so} - \mu_m)` (seed 003 eq. 5-2)."""
    return 2.0 * normal_load / stiffness * (mu_so - mu_m)


def stick_duration(amplitude, platform_speed):
    r"""Stick duration :math:`\alpha / V` (closed form: the platform re-stretches the spring by :math:`\alpha`)."""
    return amplitude / platform_speed


def slip_duration(stiffness, mass, damping_ratio=0.0):
    r"""Slip duration of the closed form: half a damped period, :math:`\pi / \omega_d`.

    :math:`\omega_d = \omega_n\sqrt{1-\zeta^2}` (seed 003, under eq. 2-8).
    """
    one_minus = 1.0 - damping_ratio * damping_ratio
    with np.errstate(invalid="ignore"):
        omega_d = natural_frequency(stiffness, mass) * np.sqrt(np.where(one_minus > 0, one_minus, np.nan))
    return np.pi / omega_d


def cycle_period(amplitude, platform_speed, slip_time=0.0):
    r"""Cycle period :math:`T = \alpha/V + t_{slip}`.

    With ``slip_time = 0`` this is seed 003 eq. 5-5, the recurrence period
    :math:`T = \alpha / V`, used at fault scale where slip lasts seconds and
    stick lasts centuries.
    """
    return stick_duration(amplitude, platform_speed) + slip_time


def stress_drop(stiffness, amplitude):
    r"""Drop of spring force (lab, N) or shear stress (fault, Pa): :math:`K\alpha`."""
    return stiffness * amplitude


def dimensionless_rate(loading_rate, natural_frequency, static_excess):
    r"""The closed form's small parameter :math:`\epsilon = \dot\theta / (\omega_n (\mu_s - \mu_m))`.

    It is the platform speed over the slip speed scale
    :math:`\omega_n (W/K)(\mu_s-\mu_m)`. The closed form neglects terms of
    order :math:`\zeta\epsilon` and :math:`\epsilon^2`; stick duration over
    slip duration is about :math:`2/(\pi\epsilon)`.
    """
    return loading_rate / (natural_frequency * static_excess)


def peak_slip_speed(stiffness, mass, normal_load, static_excess, damping_ratio=0.0):
    r"""Peak sliding speed of a damped half cycle started from rest (closed form, V neglected).

    .. math:: u_{max} = \omega_n \frac{W}{K}(\mu_s - \mu_m)\, e^{-\lambda\varphi},
              \quad \varphi = \operatorname{atan2}(\sqrt{1-\zeta^2}, \zeta)
    """
    zeta = damping_ratio
    root = np.sqrt(np.maximum(1.0 - zeta * zeta, 0.0))
    phase = np.arctan2(root, zeta)
    return natural_frequency(stiffness, mass) * normal_load / stiffness * static_excess * np.exp(
        -decay_parameter(zeta) * phase
    )


def closed_form_cycle(system):
    """The seed's closed-form cycle for a :class:`faultslip.dynamics.spring_slider.slider.SliderSystem`.

    Requires a rate- or constant static law (the limit must not depend on the
    stick time) and uses the kinetic law's friction at rest as mu_m and its
    slope in the damping ratio.

    Parameters
    ----------
    system : SliderSystem
        A slider with a rate- or constant static law.

    Returns
    -------
    CycleResult
        Slip per event (m), period (s), static friction (dimensionless), stress drop (N or Pa) and the regime.
    """

    excess = system.static_excess
    if excess is None:
        raise MethodError(
            "closed form: a time-of-stick static law makes mu_s depend on the cycle itself; "
            "use method='simulate' (event-driven integration)"
        )
    zeta = system.damping_ratio
    if not -1.0 < zeta < 1.0:
        raise MethodError(f"closed form: damping ratio {zeta:.3g} is outside (-1, 1); the slip phase does not oscillate")
    amplitude = float(slip_amplitude(system.normal_load, system.stiffness, excess, zeta))
    slip_time = float(slip_duration(system.stiffness, system.mass, zeta))
    stick_time = float(stick_duration(amplitude, system.platform_speed))
    eps = float(dimensionless_rate(system.loading_rate, system.natural_frequency, excess))
    _warn_above_critical(system, eps, zeta)
    return CycleResult(
        method="closed_form",
        # negative net damping makes the slip oscillation grow: the same label as the exact cycle
        regime=GROWING_OSCILLATION if system.damping_ratio < 0 else STICK_SLIP,
        loading_rate=system.loading_rate,
        platform_speed=system.platform_speed,
        static_friction=system.mu_m + excess,
        damping_ratio=zeta,
        dimensionless_rate=eps,
        amplitude=amplitude,
        slip_per_event=system.platform_speed * (stick_time + slip_time),  # the integral of u dt is V T
        stress_drop_slip=amplitude,  # eq. 2-19's alpha approximates x1 - x2
        stick_duration=stick_time,
        slip_duration=slip_time,
        period=stick_time + slip_time,
        peak_slip_speed=float(peak_slip_speed(system.stiffness, system.mass, system.normal_load, excess, zeta)),
        stress_drop=float(stress_drop(system.stiffness, amplitude)),
        scale=system.scale,
    )


def _warn_above_critical(system, eps, zeta):
    """The closed form always reports stick-slip; above theta_c that is the wrong regime."""


    if zeta > 0 and eps >= cached_critical_dimensionless_rate(zeta):
        warnings.warn(
            f"closed form used above the critical loading rate in {system.name}: epsilon = {eps:.3g} >= "
            f"epsilon_c({zeta:.3g}) = {cached_critical_dimensionless_rate(zeta):.3g}; the exact cycle predicts "
            "steady sliding here, not stick-slip. Use the exact cycle (method='exact_cycle').",
            OutOfDomainWarning,
            stacklevel=3,
        )


def relative_error_against_exact(damping_ratio, dimensionless_rate) -> dict:
    r"""The closed form's relative errors against the exact cycle at (zeta, eps), dimensionless and vectorised.

    The stress-drop slip is :math:`1 + e^{-\lambda\pi}` (eq. 2-19, per unit offset) against the exact cycle's
    drop; the slip per event adds the slip during the slip phase, :math:`\epsilon \pi / \sqrt{1 - \zeta^2}`,
    against the exact drop plus :math:`\epsilon t_{slip}`. The period's error is the slip per event's (the plate
    balance: slip per event = V T). Returns ``slip_per_event`` and ``stress_drop_slip``, each
    closed / exact - 1 (NaN where the exact cycle slides steadily).
    """
    zeta, eps = np.asarray(damping_ratio, dtype=float), np.asarray(dimensionless_rate, dtype=float)
    cycle = slip_cycle(zeta, eps)
    drop = overshoot_factor(zeta)
    exact_slip = cycle["u_drop"] + eps * cycle["slip_time"]
    closed_slip = drop + eps * np.pi / np.sqrt(1 - zeta * zeta)
    return {"slip_per_event": closed_slip / exact_slip - 1, "stress_drop_slip": drop / cycle["u_drop"] - 1}
