"""Exact stick-slip cycles for linear kinetic laws (seed 003 eqs. 2-7 to 2-11, solved exactly).

With the kinetic law :math:`\\mu = \\mu_m + \\beta(V - \\dot x)` the slip phase is the linear
oscillator of seed eq. 2-8. Measuring lengths in :math:`L = W(\\mu_s - \\mu_m)/K` from the
sliding equilibrium :math:`x_e = (W\\mu_m + (\\beta W + \\eta)V)/K` and time in :math:`1/\\omega_n`,
a slip phase that starts at break-away (:math:`K x_0 + C V = W\\mu_s`, :math:`\\dot x_0 = V`) is

.. math::

    U'' + 2\\zeta U' + U = 0,\\qquad U(0) = 1 - 2\\zeta\\epsilon,\\quad U'(0) = \\epsilon,\\quad U''(0) = -1,

with :math:`\\epsilon = \\dot\\theta / (\\omega_n(\\mu_s - \\mu_m))`. So every exact cycle is a function of
two numbers, :math:`(\\zeta, \\epsilon)`, and is vectorised over arrays of them. Displacement, velocity
and acceleration are damped sinusoids :math:`e^{-\\zeta s}(p\\cos\\omega s + q\\sin\\omega s)` whose
zeros are known in closed form; the only root-finding is the end of slip, :math:`U'(s) = \\epsilon`,
on a bracket where :math:`U'` is monotonic (between a velocity minimum and the next maximum),
by safeguarded Newton iteration. Nothing is time-stepped.

Stick starts again when the slider velocity returns to V; the force then needed to hold it,
:math:`K x + C V \\le W\\mu_m`, is always inside the static limit. Regimes:

* ``stick_slip``: the velocity returns to V in the first swing;
* ``steady_sliding``: :math:`\\zeta > 0` and the first velocity maximum stays below V; the
  oscillation decays to steady sliding (seed Fig. 2-8c);
* ``growing_oscillation``: :math:`\\zeta < 0`: the slip oscillation grows, so steady sliding is
  unstable and the velocity always returns to V (in the first swing from a break-away; later
  swings for other starting points). The cycle quantities are still exact.
"""

from __future__ import annotations

import numpy as np

from faultslip.dynamics.shared.cycle import GROWING_OSCILLATION, STEADY_SLIDING, STICK_SLIP, CycleResult
from faultslip.errors import InputError, MethodError

#: Regime codes in the vectorised arrays.
REGIME_CODES = {0: STICK_SLIP, 1: STEADY_SLIDING, 2: GROWING_OSCILLATION}
_MAX_SWINGS = 10**7


def _damped(p, q, zeta, omega, s):
    """e^{-zeta s} (p cos(omega s) + q sin(omega s))."""
    return np.exp(-zeta * s) * (p * np.cos(omega * s) + q * np.sin(omega * s))


def _first_zero(p, q, omega, include_zero: bool):
    """Smallest s > 0 (or >= 0) where p cos(omega s) + q sin(omega s) = 0."""
    phase = np.arctan2(q, p)
    k = np.ceil((-phase - np.pi / 2) / np.pi)
    s = (phase + np.pi / 2 + k * np.pi) / omega
    too_early = (s < 0) | ((s <= 0) if not include_zero else False)
    return np.where(too_early, s + np.pi / omega, s)


class _Oscillator:
    """Coefficients of U, U', U'' for U'' + 2 zeta U' + U = 0 from (U0, V0)."""

    def __init__(self, zeta, u0, v0):
        self.zeta = zeta
        self.omega = np.sqrt(1.0 - zeta * zeta)
        a0 = -2.0 * zeta * v0 - u0
        j0 = -2.0 * zeta * a0 - v0
        w = self.omega
        self.coef = {
            "u": (u0, (v0 + zeta * u0) / w),
            "v": (v0, (a0 + zeta * v0) / w),
            "a": (a0, (j0 + zeta * a0) / w),
        }

    def __call__(self, which, s):
        p, q = self.coef[which]
        return _damped(p, q, self.zeta, self.omega, s)

    def velocity_and_acceleration(self, s):
        """U'(s) and U''(s), sharing one exp, cos and sin (the Newton loop's hot path)."""
        decay = np.exp(-self.zeta * s)
        cos, sin = np.cos(self.omega * s), np.sin(self.omega * s)
        (pv, qv), (pa, qa) = self.coef["v"], self.coef["a"]
        return decay * (pv * cos + qv * sin), decay * (pa * cos + qa * sin)

    def first_zero(self, which, include_zero=False):
        p, q = self.coef[which]
        return _first_zero(p, q, self.omega, include_zero)


def _end_of_slip(osc, target, lo, hi, iterations=100):
    r"""Vectorised safeguarded Newton for U'(s) = target on [lo, hi], where U' increases.

    The unknown is delta = T - s, the time left to the end of the natural period T = 2 pi / omega,
    and the residual is written without cancellation:

    .. math::

        U'(s) - t = t\,(E\cos\omega\delta - 1) + (p_v - t) E\cos\omega\delta - q_v E\sin\omega\delta,
        \qquad E\cos\omega\delta - 1 = \mathrm{expm1}(\zeta(\delta - T))\cos\omega\delta
        - 2\sin^2(\omega\delta/2),

    with :math:`E = e^{-\zeta s}`. At a high loading rate and light damping the root lies within
    about 2/eps of T, where U' and t are both of order eps: evaluated as U'(s) - t and in s, the
    residual lost every digit and the end of slip was lost (issue 9: half the true stress drop at
    eps ~ 1e9). In delta the root keeps full relative precision. Returns ``(s, delta)``.
    """
    zeta, omega = osc.zeta, osc.omega
    period = 2.0 * np.pi / omega
    (pv, qv), (pa, qa) = osc.coef["v"], osc.coef["a"]
    offset = pv - target

    def residual_and_slope(delta):
        phase = omega * delta
        cos, sin = np.cos(phase), np.sin(phase)
        decay_minus_one = np.expm1(zeta * (delta - period))
        envelope = decay_minus_one + 1.0
        cos_minus_one = decay_minus_one * cos - 2.0 * np.sin(0.5 * phase) ** 2
        residual = target * cos_minus_one + offset * envelope * cos - qv * envelope * sin
        acceleration = envelope * (pa * cos - qa * sin)  # U''(s) > 0 on the bracket
        return residual, -acceleration  # d residual / d delta

    d_lo, d_hi = period - hi, period - lo  # residual(d_lo) >= 0 >= residual(d_hi)
    f_lo, _ = residual_and_slope(d_lo)
    f_hi, _ = residual_and_slope(d_hi)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = np.where(f_lo > f_hi, d_lo + f_lo * (d_hi - d_lo) / (f_lo - f_hi), 0.5 * (d_lo + d_hi))
    x = np.clip(np.nan_to_num(x, nan=0.0), d_lo, d_hi)
    active = np.isfinite(x) & np.isfinite(target)
    tiny = np.finfo(float).tiny
    for _ in range(iterations):
        f, slope = residual_and_slope(x)
        d_lo = np.where(active & (f > 0), x, d_lo)
        d_hi = np.where(active & (f <= 0), x, d_hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = x - f / slope
        inside = (newton >= d_lo) & (newton <= d_hi) & (slope < 0)
        x_new = np.where(inside, newton, 0.5 * (d_lo + d_hi))
        step = np.abs(x_new - x)
        x = np.where(active, x_new, x)
        # converged: a step or bracket at round-off level of delta itself (relative precision)
        scale = np.maximum(np.abs(x), tiny)
        active &= (step > 4 * np.finfo(float).eps * scale) & (d_hi - d_lo > 4 * np.finfo(float).eps * scale) & (f != 0)
        if not active.any():
            break
    return period - x, x


def slip_cycle(damping_ratio, dimensionless_rate, initial_offset=None):
    """Exact slip phase in dimensionless form, vectorised over ``(zeta, epsilon)``.

    Parameters
    ----------
    damping_ratio : array_like
        :math:`\\zeta`, ``|zeta| < 1``.
    dimensionless_rate : array_like
        :math:`\\epsilon = \\dot\\theta/(\\omega_n(\\mu_s-\\mu_m)) \\ge 0`.
    initial_offset : array_like, optional
        :math:`U(0)`; default :math:`1 - 2\\zeta\\epsilon` (break-away from a stick at
        the static limit). Other values describe slips that start elsewhere (simulator).

    Returns
    -------
    dict of arrays
        ``regime`` (codes of :data:`REGIME_CODES`), ``swings`` (velocity oscillations in the
        slip phase, 1 normally), ``slip_time`` :math:`s_{end}`, ``u_start``, ``u_end``,
        ``u_max``, ``u_min``, ``v_min`` (all in units of L, :math:`\\omega_n L`,
        :math:`1/\\omega_n`). NaN where the regime is steady sliding.
    """
    zeta, eps = np.broadcast_arrays(np.asarray(damping_ratio, float), np.asarray(dimensionless_rate, float))
    if np.any(np.abs(zeta) >= 1):
        raise MethodError(
            "exact cycle: damping ratio must satisfy |zeta| < 1 (oscillating slip phase); "
            "use event-driven integration (method='simulate') for an overdamped slider"
        )
    if np.any(eps < 0) or not np.all(np.isfinite(eps)):
        raise InputError("exact cycle: the dimensionless loading rate must be finite and non-negative")
    u0 = 1.0 - 2.0 * zeta * eps if initial_offset is None else np.broadcast_to(np.asarray(initial_offset, float), zeta.shape)
    osc = _Oscillator(zeta, u0, eps)
    omega = osc.omega

    s_vmin = osc.first_zero("a")  # acceleration zeros: velocity minimum, then maximum
    s_vmax = s_vmin + np.pi / omega
    v_max = osc("v", s_vmax)
    growth = np.exp(-2.0 * np.pi * zeta / omega)  # per swing: > 1 when zeta < 0

    returns_now = v_max >= eps
    with np.errstate(divide="ignore", invalid="ignore"):
        needed = np.ceil(np.log(eps / v_max) / np.log(growth))
    swings = np.where(returns_now, 0.0, np.where(zeta < 0, needed, np.nan))
    swings = np.where(swings > _MAX_SWINGS, np.nan, swings)
    steady = ~np.isfinite(swings)
    n = np.nan_to_num(swings)
    scale = growth**n  # every point of swing n is swing 0 scaled by growth**n
    target = np.where(steady, np.nan, eps / scale)
    s_end0, delta_end = _end_of_slip(osc, np.where(steady, 0.0, target), s_vmin, s_vmax)

    s_umax = osc.first_zero("v", include_zero=True)
    s_umin = s_umax + np.pi / omega
    period_shift = 2.0 * np.pi * n / omega
    nan_if_steady = lambda a: np.where(steady, np.nan, a)  # noqa: E731
    regime = np.where(steady, 1, np.where(zeta < 0, 2, 0))
    return {
        "regime": regime.astype(int),
        "swings": nan_if_steady(n + 1),
        "slip_time": nan_if_steady(s_end0 + period_shift),
        "u_start": u0 + 0.0 * zeta,
        "u_end": nan_if_steady(_displacement_at(osc, delta_end) * scale),
        "u_drop": nan_if_steady(_displacement_drop(osc, u0, delta_end, scale)),
        "u_max": nan_if_steady(osc("u", s_umax) * scale),
        "u_min": nan_if_steady(osc("u", s_umin) * scale),
        "v_min": nan_if_steady(osc("v", s_vmin) * scale),
    }


#: Round-off floor of the exact cycle's relative error, measured against a 50-digit mpmath
#: reference over the (zeta, eps) plane (tests/models/spring_slider/test_exact_cycle.py: at most 1.4e-15 away from
#: the critical rate, eps from 1e-12 to 1e15).
ROUND_OFF_ERROR = 1e-14


def exact_cycle_error(dimensionless_rate, critical_rate):
    """Stated relative error of :func:`slip_cycle` at ``eps`` with critical ``eps_c`` (inf without one).

    Round-off everywhere, amplified near the critical rate: there the end of slip is a near-double
    root of U'(s) = eps (the velocity maximum just reaches V), so an O(machine eps) residual moves
    it by O(machine eps / sqrt(1 - eps/eps_c)). The constant 64 bounds the mpmath measurements
    with a margin (largest ratio seen: 26, at zeta = 0.9, 1 - eps/eps_c = 1e-8).
    """
    eps, eps_c = np.asarray(dimensionless_rate, float), np.asarray(critical_rate, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        closeness = np.where(np.isfinite(eps_c), 1.0 - eps / eps_c, 1.0)
    closeness = np.maximum(closeness, np.finfo(float).eps)
    return ROUND_OFF_ERROR + 64.0 * np.finfo(float).eps / np.sqrt(closeness)


def _displacement_at(osc, delta):
    """U(T - delta), from delta (precise where delta is small)."""
    period = 2.0 * np.pi / osc.omega
    p, q = osc.coef["u"]
    envelope = np.exp(osc.zeta * (delta - period))
    return envelope * (p * np.cos(osc.omega * delta) - q * np.sin(osc.omega * delta))


def _displacement_drop(osc, u0, delta, scale):
    """U(0) - U(T - delta) * scale without cancellation (the stress drop / (K L)).

    With U(0) = p_u: p_u (1 - E cos) + E q_u sin, and 1 - E cos = -expm1 cos + 2 sin^2(half phase).
    """
    period = 2.0 * np.pi / osc.omega
    p, q = osc.coef["u"]
    phase = osc.omega * delta
    decay_minus_one = np.expm1(osc.zeta * (delta - period))
    envelope = decay_minus_one + 1.0
    one_minus = -decay_minus_one * np.cos(phase) + 2.0 * np.sin(0.5 * phase) ** 2
    same_start = u0 - p * scale  # 0 for a cycle from break-away (scale 1)
    return same_start + scale * (p * one_minus + q * envelope * np.sin(phase))


def exact_cycle_arrays(loading_rate, normal_load, stiffness, mass, static_excess, damping_ratio):
    """Dimensional exact-cycle quantities, vectorised (numpy broadcasting; SI).

    Returns a dict with ``regime`` codes, ``dimensionless_rate``, ``amplitude`` (peak-to-peak
    displacement), ``stick_duration``, ``slip_duration``, ``period``, ``slip_per_event``
    (= V T), ``peak_slip_speed`` (largest sliding speed V - x'), ``stress_drop`` (drop of
    K x + C V from break-away to re-stick) and ``swings``.
    """
    omega_n = np.sqrt(stiffness / mass)
    length = normal_load * static_excess / stiffness
    with np.errstate(divide="ignore", invalid="ignore"):
        eps = loading_rate / (omega_n * static_excess)
    cycle = slip_cycle(damping_ratio, eps)
    speed_scale = omega_n * length
    with np.errstate(divide="ignore", invalid="ignore"):
        stick_time = cycle["u_drop"] / (eps * omega_n)
    slip_time = cycle["slip_time"] / omega_n
    period = stick_time + slip_time
    platform_speed = eps * speed_scale
    return {
        "regime": cycle["regime"],
        "swings": cycle["swings"],
        "dimensionless_rate": eps,
        "amplitude": length * (cycle["u_max"] - cycle["u_min"]),
        "stick_duration": stick_time,
        "slip_duration": slip_time,
        "period": period,
        "slip_per_event": platform_speed * period,
        "peak_slip_speed": speed_scale * (eps - cycle["v_min"]),
        "stress_drop": stiffness * length * cycle["u_drop"],
    }


def _require_linear_rate_system(system, method="exact cycle"):
    if not system.is_linear:
        raise MethodError(
            f"{method}: the kinetic law of {system.name} is not linear in sliding speed; "
            "use event-driven integration (method='simulate')"
        )
    if system.static_excess is None:
        raise MethodError(
            f"{method}: the static law of {system.name} depends on the time of stick, so each cycle "
            "depends on the last; use event-driven integration (method='simulate')"
        )
    if system.static_excess <= 0:
        raise InputError(f"{method}: mu_s must exceed mu_m for stick-slip in {system.name}")


def exact_cycle(system) -> CycleResult:
    """The exact limit cycle of a :class:`~faultslip.dynamics.spring_slider.slider.SliderSystem` with a linear kinetic law.

    Parameters
    ----------
    system : SliderSystem
        A slider with a rate- or constant static law and a constant or linear kinetic law.

    Returns
    -------
    CycleResult
        Slip per event (m), period (s), stick and slip durations (s), static friction and the regime.
    """
    _require_linear_rate_system(system)
    q = exact_cycle_arrays(
        system.loading_rate, system.normal_load, system.stiffness, system.mass,
        system.static_excess, system.damping_ratio,
    )
    scalar = {key: float(np.asarray(value)) for key, value in q.items()}
    regime = REGIME_CODES[int(scalar["regime"])]
    result = CycleResult(
        method="exact_cycle",
        regime=regime,
        loading_rate=system.loading_rate,
        platform_speed=system.platform_speed,
        static_friction=system.mu_m + system.static_excess,
        damping_ratio=system.damping_ratio,
        dimensionless_rate=scalar["dimensionless_rate"],
        amplitude=scalar["amplitude"],
        slip_per_event=scalar["slip_per_event"],
        stick_duration=scalar["stick_duration"],
        slip_duration=scalar["slip_duration"],
        period=scalar["period"],
        peak_slip_speed=scalar["peak_slip_speed"],
        stress_drop=scalar["stress_drop"],
        scale=system.scale,
        stress_drop_slip=scalar["stress_drop"] / system.stiffness,
    )
    if regime == GROWING_OSCILLATION:
        result.extra["swings"] = (scalar["swings"], None, "velocity swings per slip phase")
    return result


def slip_trajectory(system, duration=None, samples=400, start=None):
    """Analytic slip-phase trajectory (t, x, x') from break-away, for phase-plane plots.

    ``duration`` defaults to the end of slip (or 6 natural periods if the slider slides on).
    ``start`` optionally overrides the initial displacement (default: the static limit).
    """
    _require_linear_rate_system(system, "slip trajectory")
    zeta, omega_n = system.damping_ratio, system.natural_frequency
    excess = system.static_excess
    length = system.normal_load * excess / system.stiffness
    eps = system.loading_rate / (omega_n * excess)
    x_eq = (system.normal_load * system.mu_m + (system.kinetic_slope * system.normal_load + system.radiation_damper)
            * system.platform_speed) / system.stiffness
    u0 = 1.0 - 2.0 * zeta * eps if start is None else (start - x_eq) / length
    cycle = slip_cycle(zeta, eps, u0)
    if duration is None:
        s_end = float(cycle["slip_time"]) if np.isfinite(cycle["slip_time"]) else 12 * np.pi
    else:
        s_end = duration * omega_n
    s = np.linspace(0.0, s_end, samples)
    osc = _Oscillator(np.float64(zeta), np.float64(u0), np.float64(eps))
    return s / omega_n, x_eq + length * osc("u", s), omega_n * length * osc("v", s)
