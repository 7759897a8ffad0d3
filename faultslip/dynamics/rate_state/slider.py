"""The spring-slider under rate-and-state friction: quasi-static, quasi-dynamic and inertial.

A slider of stiffness k is pulled through a spring by a load point moving at V_lp(t), against
friction sigma_n mu(V, psi) (:mod:`faultslip.friction.rate_state`). Work is per unit area at
fault scale (k = G / D in Pa/m, sigma_n in Pa, m = rho D in kg/m^2, eta = G / (2 c_s) in
Pa s/m) or in forces at lab scale (k in N/m, sigma_n the normal load in N, m in kg): the
equations are the same.

* **quasi-static** (m = 0, eta = 0) and **quasi-dynamic** (m = 0, radiation damper eta,
  Rice 1993): the time derivative of the force balance k (delta_lp - delta) - eta V = sigma_n mu
  gives the slip speed explicitly, in x = ln(V / V0):

      dx/dt = (k (V_lp - V) - sigma_n mu_psi dpsi/dt) / (sigma_n mu_x + eta V)               (1)

  with mu_x = dmu/dx (a for the standard law) and mu_psi = dmu/dpsi (b). States (x, psi[, psi2],
  slip). Without eta the quasi-static speed can diverge in finite time past an instability
  (k < k_c): the solver says so and names the quasi-dynamic model instead of returning inf.
* **inertial**: m dV/dt = tau - sigma_n mu(V, psi) - eta V, dtau/dt = k (V_lp - V), with the
  regularised law (finite through V = 0). States (tau, V, psi[, psi2], slip).

Solvers (all adaptive, all on the logarithmic states):

* ``"lsoda"``: ODEPACK's LSODA through ``scipy.integrate.odeint``, which switches between Adams
  and BDF as the problem turns stiff, given the analytic Jacobian of (1) and a right-hand side
  in scalar math. The cheapest at lab scale (velocity steps, slide-hold-slide): ``auto`` picks it.
* ``"dopri5"``: an embedded Dormand-Prince 5(4) pair with PI step control and its order-4
  dense output, written for a handful of scalar states. It stops at an accepted step, which is
  how fault-scale cycles find their events.
* ``"radau"`` and ``"bdf"``: scipy's implicit solvers with the same analytic Jacobian.

The load history is integrated segment by segment, restarting at every breakpoint (a velocity
step is a jump in V_lp).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

from faultslip.constants import JULIAN_YEAR
import numpy as np

from faultslip.errors import InputError, NoEventsError, SolverError, beside
from faultslip.dynamics.shared.dormand_prince import (A21, A31, A32, A41, A42, A43, A51, A52, A53, A54, A61, A62, A63, A64,
                                               A65, B1, B3, B4, B5, B6, E1, E3, E4, E5, E6, E7, _C, _P,
                                               continuous_state)
from faultslip.dynamics.rate_state import compiled as rate_state_compiled
from faultslip.dynamics.rate_state import native
from faultslip.dynamics.shared.settling import aitken, assess_settling, bifurcation_note, settled_error
from faultslip.dynamics.rate_state.methods import (CYCLE_METHODS, ERROR_MODEL, NEAR_CRITICAL_FROM, SECONDS_PER_STEP,
                                                   error_bound, near_critical_error, steps_per_cycle)
from faultslip.friction.rate_state import RateStateLaw
from faultslip.io.progress import reporter
from faultslip.datasets import ToXarray
from faultslip.units import takes_units

MODELS = ("quasi_static", "quasi_dynamic", "inertial")
METHODS = ("auto", "lsoda", "dopri5", "dopri5_compiled", "radau", "bdf")
#: Slip speed above which the slider is "in an event" (SEAS benchmark convention, 1 mm/s).
EVENT_SPEED = 1e-3
#: The relative tolerance fault cycles take unless told (a simulation's).
CYCLES_RTOL = 1e-7


_P_ARRAY = np.array(_P)


# --- load-point histories -------------------------------------------------------


@dataclass(frozen=True)
class LoadHistory(ToXarray):
    """The load point's speed V_lp(t) (m/s): piecewise constant (``steps``) or piecewise linear (``table``).

    ``times`` are the breakpoints (s, increasing, from 0); ``speeds`` the speed on each segment
    (steps: one per segment) or at each breakpoint (table).
    """
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'times': 's', 'speeds': 'm/s'}
    DIMENSIONS = {'times': 'step', 'speeds': 'step'}

    times: tuple
    speeds: tuple
    kind: str = "steps"

    def __post_init__(self):
        times, speeds = np.asarray(self.times, float), np.asarray(self.speeds, float)
        if times.ndim != 1 or times.size < 2 or times[0] != 0.0 or np.any(np.diff(times) <= 0):
            raise InputError("a load history needs increasing times starting at 0 s")
        expected = times.size - 1 if self.kind == "steps" else times.size
        if speeds.size != expected:
            raise InputError(f"a {self.kind} load history with {times.size} times needs {expected} speeds")
        if not np.all(np.isfinite(speeds)) or np.any(speeds < 0):
            raise InputError("load-point speeds must be finite and not negative")

    @property
    def duration(self) -> float:
        return float(self.times[-1])

    @classmethod
    def constant(cls, speed: float, duration: float) -> "LoadHistory":
        return cls((0.0, float(duration)), (float(speed),))

    @classmethod
    def velocity_steps(cls, steps, duration: float) -> "LoadHistory":
        """``steps`` = [(t_start, V), ...] with t_start of the first step 0; held until ``duration``."""
        starts = [float(t) for t, _ in steps] + [float(duration)]
        return cls(tuple(starts), tuple(float(v) for _, v in steps))

    @classmethod
    def slide_hold_slide(cls, speed: float, slide: float, holds) -> "LoadHistory":
        """Slide for ``slide`` s at ``speed``, then for each hold time: hold (V_lp = 0), slide again."""
        times, speeds, now = [0.0], [], 0.0
        for hold in [None, *holds]:
            if hold is not None:
                now += float(hold)
                times.append(now)
                speeds.append(0.0)
            now += float(slide)
            times.append(now)
            speeds.append(float(speed))
        return cls(tuple(times), tuple(speeds))

    @classmethod
    def table(cls, times, speeds) -> "LoadHistory":
        times = np.asarray(times, float)
        return cls(tuple(times - times[0]), tuple(np.asarray(speeds, float)), kind="table")

    def segments(self):
        """(t0, t1, V at t0, V at t1) for each segment; within a segment the speed is linear in t."""
        for i in range(len(self.times) - 1):
            if self.kind == "steps":
                yield self.times[i], self.times[i + 1], self.speeds[i], self.speeds[i]
            else:
                yield self.times[i], self.times[i + 1], self.speeds[i], self.speeds[i + 1]

    def displacement(self, t):
        """Load-point displacement (m) at times ``t`` (the integral of V_lp)."""
        t = np.asarray(t, float)
        total = np.zeros_like(t)
        for t0, t1, v0, v1 in self.segments():
            span = np.clip(t - t0, 0.0, t1 - t0)
            total += v0 * span + 0.5 * (v1 - v0) / (t1 - t0) * span * span
        return total


# --- the slider ----------------------------------------------------------------------


@dataclass(frozen=True)
class RateStateSlider:
    """A spring-slider with rate-and-state friction (see the module docstring for units)."""

    law: RateStateLaw
    stiffness: float
    normal_stress: float
    mass: float = 0.0
    damping: float = 0.0

    def __post_init__(self):
        for label, value in (("stiffness", self.stiffness), ("normal stress", self.normal_stress)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"the {label} must be a positive finite number, got {value!r}")
        for label, value in (("mass", self.mass), ("damping", self.damping)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value >= 0):
                raise InputError(f"the {label} must be a finite number >= 0, got {value!r}")

    @classmethod
    def at_fault(cls, law, shear_modulus, zone_width, normal_stress, density=2700.0, shear_wave_speed=None,
                 radiation_damping=True) -> "RateStateSlider":
        """K = G / D, m = rho D, eta = G / (2 c_s) with c_s = sqrt(G / rho) unless given (per unit area)."""
        wave_speed = shear_wave_speed or math.sqrt(shear_modulus / density)
        return cls(law=law, stiffness=shear_modulus / zone_width, normal_stress=normal_stress,
                   mass=density * zone_width,
                   damping=shear_modulus / (2.0 * wave_speed) if radiation_damping else 0.0)

    def critical_stiffness(self, speed=None, model="quasi_static"):
        """k_c for ``model`` at steady sliding speed ``speed`` (:func:`faultslip.friction.rate_state.critical_stiffness`)."""
        mass = self.mass if model == "inertial" else 0.0
        damping = self.damping if model in ("quasi_dynamic", "inertial") else 0.0
        return self.law.critical_stiffness(self.normal_stress, speed, mass, damping)


# --- right-hand sides -------------------------------------------------------------


def _friction_partials(law, x, psi, psi2):
    """(mu, dmu/dx, dmu/dpsi, dmu/dpsi2) at x = ln(V / V0)."""
    if law.regularized:
        z = 0.5 * math.exp(x + (law.mu0 + law.b * psi + law.b2 * psi2) / law.a)
        root = math.sqrt(1.0 + z * z)
        weight = z / root
        return law.a * math.asinh(z), law.a * weight, law.b * weight, law.b2 * weight
    return law.mu0 + law.a * x + law.b * psi + law.b2 * psi2, law.a, law.b, law.b2


def _psi_rate(law, speed, psi, critical_slip):
    if law.evolution == "aging":
        return (law.reference_speed * math.exp(-psi) - speed) / critical_slip
    return -(speed / critical_slip) * (math.log(speed / law.reference_speed) + psi)


def _quasi_rhs(slider, load, damping):
    """f(t, y) for y = (x, psi, slip) or (x, psi, psi2, slip); quasi-static when damping = 0."""
    law, k, sigma = slider.law, slider.stiffness, slider.normal_stress
    v0, dc, dc2 = law.reference_speed, law.critical_slip, law.critical_slip2
    exp = math.exp
    if not law.two_state and not law.regularized:  # the common case, in as few operations as possible
        sigma_a, sigma_b = sigma * law.a, sigma * law.b
        if law.evolution == "aging":
            def rhs(t, y):
                speed = v0 * exp(y[0])
                dpsi = (v0 * exp(-y[1]) - speed) / dc
                return ((k * (load.speed(t) - speed) - sigma_b * dpsi) / (sigma_a + damping * speed), dpsi, speed)
        else:
            def rhs(t, y):
                speed = v0 * exp(y[0])
                dpsi = -(speed / dc) * (y[0] + y[1])
                return ((k * (load.speed(t) - speed) - sigma_b * dpsi) / (sigma_a + damping * speed), dpsi, speed)
        return rhs
    two = law.two_state

    def rhs(t, y):
        x, psi = y[0], y[1]
        psi2 = y[2] if two else 0.0
        speed = v0 * exp(x)
        mu, mu_x, mu_psi, mu_psi2 = _friction_partials(law, x, psi, psi2)
        dpsi = _psi_rate(law, speed, psi, dc)
        dpsi2 = _psi_rate(law, speed, psi2, dc2) if two else 0.0
        dx = (k * (load.speed(t) - speed) - sigma * (mu_psi * dpsi + mu_psi2 * dpsi2)) / (sigma * mu_x + damping * speed)
        return (dx, dpsi, dpsi2, speed) if two else (dx, dpsi, speed)

    return rhs


def _inertial_rhs(slider, load):
    """f(t, y) for y = (tau, V, psi[, psi2], slip); the regularised law keeps V = 0 finite."""
    law, k, sigma, m, eta = slider.law, slider.stiffness, slider.normal_stress, slider.mass, slider.damping
    v0, dc, dc2, two = law.reference_speed, law.critical_slip, law.critical_slip2, law.two_state

    def rhs(t, y):
        tau, speed, psi = y[0], y[1], y[2]
        psi2 = y[3] if two else 0.0
        z = speed / (2.0 * v0) * math.exp((law.mu0 + law.b * psi + law.b2 * psi2) / law.a)
        mu = law.a * math.asinh(z)
        magnitude = max(abs(speed), 1e-300)
        dpsi = _psi_rate(law, magnitude, psi, dc)
        dv = (tau - sigma * mu - eta * speed) / m
        dtau = k * (load.speed(t) - speed)
        if two:
            return (dtau, dv, dpsi, _psi_rate(law, magnitude, psi2, dc2), speed)
        return (dtau, dv, dpsi, speed)

    return rhs


# --- the embedded solver ----------------------------------------------------------------


class _StepCollapse(Exception):
    """dopri5's step size fell below its floor: the problem is stiff (or singular) here."""

    def __init__(self, t, message):
        super().__init__(message)
        self.t = t



def _scaled_rms(values) -> float:
    """The root mean square of ``values``; infinity where a square overflows (a state far beyond its scale)."""
    try:
        return math.sqrt(sum(v * v for v in values) / len(values))
    except OverflowError:
        return math.inf


def dopri5(rhs, t0, y0, t_end, t_eval, rtol, atol, max_steps=2_000_000, h0=None, on_step=None, last_step=None,
           rebase=False):
    """Integrate y' = rhs(t, y) (tuples of floats) from t0 to t_end; return (values at t_eval, y_end, steps, nfev).

    Dormand-Prince 5(4) with a PI step controller (Hairer & Wanner II, IV.2) and the order-4
    dense output for ``t_eval`` (sorted, within [t0, t_end]). ``atol`` is a tuple per state.
    ``on_step(t, y, step)`` runs after each accepted step, ``step`` being (y at its start, its size, its stages
    k1, k3..k7) for :func:`~faultslip.dynamics.shared.dormand_prince.continuous_state`; if it returns True the
    integration stops there.
    ``last_step`` (a dict), if given, receives the next step size under ``"h"``, to restart with.
    Raises :class:`_StepCollapse` if the step size underflows. ``rebase``: where it falls below a few float
    spacings of t after steps were taken, return there instead (an autonomous system's caller restarts its clock
    at 0 and goes on: at t ~ 1e11 s a millisecond step is below the clock's resolution, not the solution's).
    """
    n = len(y0)
    y = tuple(float(v) for v in y0)
    t = float(t0)
    k1 = rhs(t, y)
    nfev = 1
    out = np.empty((len(t_eval), n))
    next_out = 0
    while next_out < len(t_eval) and t_eval[next_out] <= t:
        out[next_out] = y
        next_out += 1
    span = t_end - t
    if span <= 0:
        return out[:next_out], y, t, 0, nfev
    if h0 is None:  # Hairer, Norsett & Wanner I, II.4: a first step from the size of y, f and f'
        scales = [atol[i] + rtol * abs(y[i]) for i in range(n)]
        d0 = _scaled_rms([y[i] / scales[i] for i in range(n)])
        d1 = _scaled_rms([k1[i] / scales[i] for i in range(n)])
        h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
        h0 = min(h0, span)
        try:
            f1 = rhs(t + h0, tuple(y[i] + h0 * k1[i] for i in range(n)))
            nfev += 1
            d2 = math.sqrt(sum(((f1[i] - k1[i]) / scales[i]) ** 2 for i in range(n)) / n) / h0
        except (OverflowError, ValueError, ZeroDivisionError):
            d2 = math.inf
        h1 = (0.01 / max(d1, d2)) ** 0.2 if max(d1, d2) > 1e-15 else max(1e-6, h0 * 1e-3)
        h0 = min(100 * h0, h1, span)
        if not (math.isfinite(h0) and h0 > 0):  # a state far beyond its scale: start small, the control adapts
            h0 = 1e-6 * span
    h = max(h0, 1e-300)
    previous_error = 1e-4
    steps = 0
    floor = 1e-14 * max(abs(t0), abs(t), 1e-300)
    while t < t_end:
        if steps >= max_steps:
            raise SolverError(f"dopri5 took more than {max_steps} steps before t = {t_end:g} s")
        t_next = t + h
        if t_next >= t_end:  # the last step lands on t_end exactly (t + (t_end - t) may miss it by an ulp)
            h, t_next = t_end - t, t_end
        try:
            k2 = rhs(t + _C[1] * h, [yj + h * A21 * a1 for yj, a1 in zip(y, k1)])
            k3 = rhs(t + _C[2] * h, [yj + h * (A31 * a1 + A32 * a2) for yj, a1, a2 in zip(y, k1, k2)])
            k4 = rhs(t + _C[3] * h, [yj + h * (A41 * a1 + A42 * a2 + A43 * a3)
                                     for yj, a1, a2, a3 in zip(y, k1, k2, k3)])
            k5 = rhs(t + _C[4] * h, [yj + h * (A51 * a1 + A52 * a2 + A53 * a3 + A54 * a4)
                                     for yj, a1, a2, a3, a4 in zip(y, k1, k2, k3, k4)])
            k6 = rhs(t + h, [yj + h * (A61 * a1 + A62 * a2 + A63 * a3 + A64 * a4 + A65 * a5)
                             for yj, a1, a2, a3, a4, a5 in zip(y, k1, k2, k3, k4, k5)])
            y_new = [yj + h * (B1 * a1 + B3 * a3 + B4 * a4 + B5 * a5 + B6 * a6)
                     for yj, a1, a3, a4, a5, a6 in zip(y, k1, k3, k4, k5, k6)]
            k7 = rhs(t + h, y_new)
            nfev += 6
            error = 0.0
            for yj, yn, a1, a3, a4, a5, a6, a7, tol in zip(y, y_new, k1, k3, k4, k5, k6, k7, atol):
                e = h * (E1 * a1 + E3 * a3 + E4 * a4 + E5 * a5 + E6 * a6 + E7 * a7)
                error += (e / (tol + rtol * max(abs(yj), abs(yn)))) ** 2
            error = math.sqrt(error / n)
        except (OverflowError, ValueError, ZeroDivisionError):  # a trial stage left the domain: smaller step
            error = math.inf
        if not math.isfinite(error):
            h *= 0.1
            if h < floor:
                raise _StepCollapse(t, f"the solution stops being finite at t = {t:.6g} s")
            continue
        if error <= 1.0:
            # accepted: dense output for the requested times inside this step
            last = next_out
            while last < len(t_eval) and t_eval[last] <= t_next:
                last += 1
            if last > next_out:  # the order-4 continuous extension, vectorised over the times in this step
                fraction = (t_eval[next_out:last] - t) / h
                powers = np.stack([fraction, fraction ** 2, fraction ** 3, fraction ** 4])
                q = np.array((k1, k2, k3, k4, k5, k6, k7)).T @ _P_ARRAY  # (states, 4)
                out[next_out:last] = np.asarray(y) + h * (q @ powers).T
                next_out = last
            step = (y, h, (k1, k3, k4, k5, k6, k7))
            t = t_next
            y = y_new
            k1 = k7
            steps += 1
            factor = 0.9 * error ** -0.14 * previous_error ** 0.08 if error > 0 else 5.0
            h *= min(5.0, max(0.2, factor))
            previous_error = max(error, 1e-4)
            if on_step is not None and on_step(t, y, step):
                if last_step is not None:
                    last_step["h"] = h
                return out[:next_out], y, t, steps, nfev
        else:
            h *= max(0.2, 0.9 * error ** -0.2)
        floor = 4e-16 * max(abs(t), abs(t0), 1e-300) * 16  # a few float spacings of t
        if h < floor:
            if rebase and t > t0:
                if last_step is not None:
                    last_step["h"] = h
                return out[:next_out], y, t, steps, nfev
            raise _StepCollapse(t, f"the step size fell below {floor:.1e} s at t = {t:.6g} s")
    return out, y, t, steps, nfev


# --- simulation -------------------------------------------------------------------------


@dataclass
class RateStateRun(ToXarray):
    """A rate-and-state simulation: time series and how it was obtained."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'time': 's', 'slip_speed': 'm/s', 'friction': '1', 'psi': '1', 'slip': 'm', 'load_point': 'm', 'steps': '1', 'function_evaluations': '1', 'wall_time': 's'}
    DIMENSIONS = {'time': 'time', 'slip_speed': 'time', 'friction': 'time', 'psi': 'time', 'slip': 'time', 'load_point': 'time'}

    time: np.ndarray
    slip_speed: np.ndarray  # m/s
    friction: np.ndarray
    psi: np.ndarray  # ln(V0 theta / D_c)
    slip: np.ndarray  # m
    load_point: np.ndarray  # m
    model: str
    method: str
    method_reason: str
    steps: int
    function_evaluations: int
    wall_time: float
    notes: list = field(default_factory=list)


class _Load:
    """V_lp(t) on the current segment of a load history (the solvers restart at each breakpoint)."""

    __slots__ = ("start", "speed0", "slope")

    def __init__(self):
        self.start, self.speed0, self.slope = 0.0, 0.0, 0.0

    def enter(self, t0, t1, v0, v1):
        self.start, self.speed0, self.slope = t0, v0, (v1 - v0) / (t1 - t0)

    def speed(self, t):
        return self.speed0 + self.slope * (t - self.start)


def _initial_state(slider, history, model, initial_speed, initial_psi):
    law = slider.law
    speed = initial_speed if initial_speed is not None else (history.speeds[0] or law.reference_speed)
    if speed <= 0:
        raise InputError("the initial slip speed must be positive (rate-and-state friction needs V > 0)")
    psi = math.log(law.reference_speed / speed) if initial_psi is None else initial_psi  # steady state
    if model == "inertial":
        z = speed / (2 * law.reference_speed) * math.exp((law.mu0 + law.b * psi + law.b2 * psi) / law.a)
        tau = slider.normal_stress * law.a * math.asinh(z) + slider.damping * speed
        state = [tau, speed, psi] + ([psi] if law.two_state else []) + [0.0]
        return tuple(state)
    return tuple([math.log(speed / law.reference_speed), psi] + ([psi] if law.two_state else []) + [0.0])


def _tolerances(slider, model, rtol):
    """Absolute tolerances per state: the log states are O(1-30), so rtol serves as their atol."""
    law = slider.law
    slip_scale = law.critical_slip * rtol
    logs = [rtol] * (2 if law.two_state else 1)
    if model == "inertial":
        return tuple([slider.normal_stress * law.a * rtol, law.reference_speed * rtol] + logs + [slip_scale])
    return tuple([rtol] + logs + [slip_scale])


def _lsoda_two_states(slider, load, damping, history, t_eval, y0, rtol, atol, max_speed):
    """The common case on LSODA: one-state standard law, quasi-static or quasi-dynamic, states (x, psi) only.

    Slip follows from the force balance without integrating it: with the spring's stretch s,
    k s = sigma_n mu + eta V at every instant, so delta = delta_lp - (sigma_n (mu - mu(0)) +
    eta (V - V(0))) / k. Returns (values with a slip column, steps, evaluations).
    """
    law, k, sigma = slider.law, slider.stiffness, slider.normal_stress
    v0, dc, a, b = law.reference_speed, law.critical_slip, law.a, law.b
    sigma_a, sigma_b = sigma * a, sigma * b
    exp = math.exp
    aging = law.evolution == "aging"
    limit = math.log(max_speed / v0) if math.isfinite(max_speed) else math.inf

    def f(y, t):
        x, psi = y
        if x > limit:
            raise _Diverging(t)
        speed = v0 * exp(x)
        dpsi = (v0 * exp(-psi) - speed) / dc if aging else -(speed / dc) * (x + psi)
        return ((k * (load.speed(t) - speed) - sigma_b * dpsi) / (sigma_a + damping * speed), dpsi)

    full = _quasi_jacobian(slider, load, damping)  # (x, psi, slip); slip enters neither equation

    def jac(y, t):
        rows = full(t, y)
        return (rows[0][:2], rows[1][:2])

    states, steps, nfev = _odeint_by_segment(f, jac, history, load, y0[:2], t_eval, rtol, atol[:2], slider)
    return _with_slip(states, slider, damping, history.displacement(t_eval), y0), steps, nfev


def _with_slip(states, slider, damping, load_point, y0):
    """(x, psi) at t_eval with the slip column from the force balance (see :func:`_lsoda_two_states`)."""
    law, k, sigma = slider.law, slider.stiffness, slider.normal_stress
    speed = law.reference_speed * np.exp(states[:, 0])
    mu = law.mu0 + law.a * states[:, 0] + law.b * states[:, 1]
    mu_start = law.mu0 + law.a * y0[0] + law.b * y0[1]
    speed_start = law.reference_speed * math.exp(y0[0])
    slip = load_point - (sigma * (mu - mu_start) + damping * (speed - speed_start)) / k
    return np.column_stack([states, slip])


def _compiled_two_states(slider, damping, history, t_eval, load_point, y0, rtol, atol, max_speed, model):
    """The one-state slider on the compiled Dormand-Prince kernel (:mod:`faultslip.dynamics.rate_state.compiled`).

    Returns (values, steps, nfev), or None where the kernel gave up on a stiff problem (its step
    budget), so that the caller can hand over to LSODA.
    """
    states, steps, nfev, status, t_stop = rate_state_compiled.integrate(
        slider.law, slider.stiffness, slider.normal_stress, damping, history.segments(), history.duration, y0[:2],
        t_eval, rtol, atol[:2], max_speed)
    if status == rate_state_compiled.DIVERGED or (status == rate_state_compiled.STEP_COLLAPSE
                                                   and model == "quasi_static"):
        _diverged(slider, t_stop)
    if status != rate_state_compiled.OK:
        return None
    return _with_slip(states, slider, damping, load_point, y0), steps, nfev


def _implicit_by_segment(rhs, jacobian, history, load, y0, t_eval, rtol, atol, method):
    """scipy's Radau or BDF with the analytic Jacobian, restarted at each breakpoint of the load history."""
    from scipy.integrate import solve_ivp  # heavy: imported where used

    def f(t, y):
        return np.array(rhs(t, y))

    jac = None if jacobian is None else (lambda t, y: np.array(jacobian(t, y)))
    pieces, nfev, steps, y = [], 0, 0, np.asarray(y0, float)
    for t0, t1, v0, v1 in history.segments():
        load.enter(t0, t1, v0, v1)
        last = t1 == history.duration
        wanted = t_eval[(t_eval >= t0) & ((t_eval < t1) | (last & (t_eval <= t1)))]
        times = wanted if wanted.size and wanted[-1] == t1 else np.append(wanted, t1)
        result = solve_ivp(f, (t0, t1), y, method="Radau" if method == "radau" else "BDF", t_eval=times,
                           rtol=rtol, atol=np.asarray(atol), jac=jac)
        if not result.success:
            raise SolverError(f"{method} failed at t = {result.t[-1] if result.t.size else t0:.6g} s: {result.message}")
        nfev += result.nfev
        steps += result.nlu
        pieces.append(result.y.T[:wanted.size])
        y = result.y[:, -1]
    return np.concatenate(pieces), steps, nfev


def _quasi_jacobian(slider, load, damping):
    """The analytic Jacobian of (1) and the state equations, one-state standard law (LSODA, Radau, BDF)."""
    law, k, sigma = slider.law, slider.stiffness, slider.normal_stress
    v0, dc, a, b = law.reference_speed, law.critical_slip, law.a, law.b
    exp = math.exp
    aging = law.evolution == "aging"

    def jacobian(t, y):
        x, psi = y[0], y[1]
        speed = v0 * exp(x)
        if aging:
            recovery = v0 * exp(-psi)
            dpsi = (recovery - speed) / dc
            dpsi_dx, dpsi_dpsi = -speed / dc, -recovery / dc
        else:
            dpsi = -(speed / dc) * (x + psi)
            dpsi_dx, dpsi_dpsi = -(speed / dc) * (x + psi + 1.0), -speed / dc
        denominator = sigma * a + damping * speed
        numerator = k * (load.speed(t) - speed) - sigma * b * dpsi
        dx_dx = ((-k * speed - sigma * b * dpsi_dx) * denominator - numerator * damping * speed) / denominator ** 2
        return ((dx_dx, -sigma * b * dpsi_dpsi / denominator, 0.0), (dpsi_dx, dpsi_dpsi, 0.0), (speed, 0.0, 0.0))

    return jacobian


@takes_units(t_eval="time", max_speed="speed")
def simulate_rate_state(slider: RateStateSlider, history: LoadHistory, *, model: str = "quasi_static",
                        method: str = "auto", rtol: float = 1e-8, samples: int | None = None, t_eval=None,
                        initial_speed: float | None = None, initial_psi: float | None = None,
                        max_speed: float = 10.0) -> RateStateRun:
    """Simulate ``slider`` under the load history; friction, speed, state and slip at ``t_eval``.

    ``model`` is quasi_static, quasi_dynamic or inertial; ``method`` auto, lsoda, dopri5, dopri5_compiled,
    radau or bdf. ``auto`` takes dopri5_compiled (the numba-compiled kernel of
    :mod:`faultslip.dynamics.rate_state.compiled`) for one-state quasi-static and quasi-dynamic sliders
    where numba is installed, handing over to LSODA if it runs out of steps, and LSODA otherwise.
    The slider starts at steady state at ``initial_speed`` (default: the first load-point speed).
    A quasi-static slider whose speed passes ``max_speed`` (m/s) has met an instability it
    cannot follow: a :class:`SolverError` says so and names the quasi-dynamic model.

    Parameters
    ----------
    slider : RateStateSlider
        The slider.
    history : LoadHistory
        Load-point speeds (m/s) from times (s).
    model : str
        quasi_static, quasi_dynamic or inertial.
    method : str
        The integrator.
    rtol : float
        Relative tolerance.
    samples : int, optional
        Output samples.
    t_eval : array_like, optional
        Output times (s).
    initial_speed : float, optional
        m/s.
    initial_psi : float, optional
        The initial state.
    max_speed : float
        The largest slip speed allowed (m/s).

    Returns
    -------
    RateStateRun
        Friction (dimensionless), speed (m/s), state and slip (m) at the output times.
    """
    if model not in MODELS:
        raise InputError(f"model must be one of {', '.join(MODELS)}, got {model!r}")
    if method not in METHODS:
        raise InputError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    if not 1e-14 <= rtol <= 1e-2:
        raise InputError(f"rtol must be between 1e-14 and 1e-2, got {rtol:g}")
    if model == "inertial" and slider.mass <= 0:
        raise InputError("the inertial model needs a mass > 0")
    if model == "quasi_dynamic" and slider.damping <= 0:
        raise InputError("the quasi-dynamic model needs a radiation damper eta > 0 (RateStateSlider.at_fault sets "
                         "eta = G / (2 c_s))")
    law = slider.law
    if model == "inertial" and not law.regularized:  # V may reach 0: eq. (4) is finite there
        slider = RateStateSlider(replace(law, regularized=True), slider.stiffness, slider.normal_stress,
                                 slider.mass, slider.damping)
        law = slider.law
    duration = history.duration
    if t_eval is None:
        t_eval = np.linspace(0.0, duration, samples or 1001)
    t_eval = np.asarray(t_eval, dtype=float)
    if t_eval.ndim != 1 or np.any(np.diff(t_eval) < 0) or t_eval[0] < 0 or t_eval[-1] > duration:
        raise InputError("t_eval must be sorted times within the load history")
    load = _Load()
    load.enter(*next(history.segments()))
    damping = slider.damping if model == "quasi_dynamic" else 0.0
    rhs = _inertial_rhs(slider, load) if model == "inertial" else _quasi_rhs(slider, load, damping)
    y0 = _initial_state(slider, history, model, initial_speed, initial_psi)
    atol = _tolerances(slider, model, rtol)
    common = not (law.two_state or law.regularized or model == "inertial")  # (x, psi) alone
    if method == "dopri5_compiled" and not common:
        raise InputError("dopri5_compiled integrates one-state, unregularised, quasi-static or quasi-dynamic sliders; "
                         "use method auto")
    if method == "dopri5_compiled" and not rate_state_compiled.available():
        raise InputError("dopri5_compiled needs numba: pip install 'faultslip[fast]', or use method auto")
    if method == "auto" and common and rate_state_compiled.available():
        chosen, reason = "dopri5_compiled", ("Dormand-Prince 5(4) compiled by numba on the log states: the cheapest "
                                             "at this tolerance (benchmarks/run.py); LSODA takes over if it is stiff")
    else:
        chosen = "lsoda" if method == "auto" else method
        reason = ("LSODA with the analytic Jacobian: the cheapest at this tolerance without numba (benchmarks/run.py), "
                  "stiff or not" if method == "auto" else "requested")
    started = time.perf_counter()
    load_point = history.displacement(t_eval)
    notes = []

    def too_fast(t, y, step=None):
        speed = y[1] if model == "inertial" else law.reference_speed * math.exp(y[0])
        return abs(speed) > max_speed and model == "quasi_static"

    try:
        compiled = None
        if chosen == "dopri5_compiled":
            compiled = _compiled_two_states(slider, damping, history, t_eval, load_point, y0, rtol, atol,
                                            max_speed if model == "quasi_static" else math.inf, model)
            if compiled is None:
                if method != "auto":
                    raise SolverError("dopri5_compiled gave up (its step budget or step size ran out: the problem is "
                                      "stiff here); use method lsoda or radau")
                notes.append("the compiled dopri5 gave up (stiff): solved with LSODA instead")
                chosen, reason = "lsoda", "stiff: the compiled dopri5 ran out of steps"
        if compiled is not None:
            values, steps, nfev = compiled
        elif chosen == "lsoda" and common:
            values, steps, nfev = _lsoda_two_states(slider, load, damping, history, t_eval, y0, rtol, atol,
                                                    max_speed if model == "quasi_static" else math.inf)
        elif chosen == "lsoda":
            jacobian = None if law.two_state or model == "inertial" else _quasi_jacobian(slider, load, damping)
            values, steps, nfev = _lsoda_by_segment(rhs, jacobian, history, load, y0, t_eval, rtol, atol,
                                                    max_speed if model == "quasi_static" else math.inf, slider)
        elif chosen == "dopri5":
            values, steps, nfev = _dopri5_by_segment(rhs, history, load, y0, t_eval, rtol, atol, too_fast, slider)
        else:
            if law.two_state or model == "inertial":
                raise InputError(f"{chosen} is available for one-state quasi-static and quasi-dynamic sliders; "
                                 "use method dopri5 or auto")
            values, steps, nfev = _implicit_by_segment(rhs, _quasi_jacobian(slider, load, damping), history, load,
                                                       y0, t_eval, rtol, atol, chosen)
    except _StepCollapse as collapse:
        if model == "quasi_static" and collapse.t < duration:
            _diverged(slider, collapse.t)
        if method != "auto" or law.two_state or model == "inertial":
            raise SolverError(f"dopri5 failed ({collapse}); the problem is stiff here: use method radau") from None
        notes.append(f"dopri5's step size collapsed at t = {collapse.t:.6g} s (stiff): solved with radau instead")
        chosen, reason = "radau", "stiff: dopri5's step size collapsed"
        values, steps, nfev = _implicit_by_segment(rhs, _quasi_jacobian(slider, load, damping), history, load, y0,
                                                   t_eval, rtol, atol, chosen)
    wall = time.perf_counter() - started
    values = np.asarray(values)
    if model == "inertial":
        speed = values[:, 1]
        psi = values[:, 2]
        psi2 = values[:, 3] if law.two_state else 0.0
    else:
        speed = law.reference_speed * np.exp(values[:, 0])
        psi = values[:, 1]
        psi2 = values[:, 2] if law.two_state else 0.0
    mu = law.friction(speed, psi, psi2)
    if not (np.all(np.isfinite(mu)) and np.all(np.isfinite(speed))):
        raise SolverError(f"{chosen} returned non-finite values for the {model} slider; tighten rtol or use radau")
    return RateStateRun(time=t_eval, slip_speed=speed, friction=np.asarray(mu, float), psi=psi, slip=values[:, -1],
                        load_point=load_point, model=model, method=chosen, method_reason=reason,
                        steps=steps, function_evaluations=nfev, wall_time=wall, notes=notes)


def quasi_static_friction(law, stiffness: float, history: LoadHistory, t_eval, rtol: float = 1e-8) -> np.ndarray:
    """Friction of the quasi-static slider (unit normal stress, spring ``stiffness`` in friction per metre)
    at ``t_eval``: the likelihood's inner loop (fits, posteriors), so the one-state law goes straight to the
    compiled kernel when numba is installed, without the run's slip, load-point and bookkeeping;
    everything else, and a kernel that gives up, goes through :func:`simulate_rate_state`."""
    if not (law.two_state or law.regularized) and rate_state_compiled.available():
        slider = RateStateSlider(law, stiffness, 1.0)
        y0 = _initial_state(slider, history, "quasi_static", None, None)
        atol = _tolerances(slider, "quasi_static", rtol)
        states, _, _, status, t_stop = rate_state_compiled.integrate(
            law, stiffness, 1.0, 0.0, history.segments(), history.duration, y0[:2], t_eval, rtol, atol[:2], 10.0)
        if status == rate_state_compiled.OK:
            mu = law.friction(law.reference_speed * np.exp(states[:, 0]), states[:, 1], 0.0)
            if np.all(np.isfinite(mu)):
                return np.asarray(mu, dtype=float)
        elif status in (rate_state_compiled.DIVERGED, rate_state_compiled.STEP_COLLAPSE):
            _diverged(slider, t_stop)
    return simulate_rate_state(RateStateSlider(law, stiffness, 1.0), history, t_eval=t_eval, rtol=rtol).friction


class _Diverging(Exception):
    def __init__(self, t):
        super().__init__(t)
        self.t = t


def _lsoda_by_segment(rhs, jacobian, history, load, y0, t_eval, rtol, atol, max_speed, slider):
    """odeint (LSODA) restarted at each breakpoint of the load history; refuses a diverging quasi-static speed."""
    limit = math.log(max_speed / slider.law.reference_speed) if math.isfinite(max_speed) else math.inf

    def f(y, t):
        if y[0] > limit:
            raise _Diverging(t)
        return rhs(t, y)

    dfun = None if jacobian is None else (lambda y, t: jacobian(t, y))
    return _odeint_by_segment(f, dfun, history, load, y0, t_eval, rtol, atol, slider)


def _odeint_by_segment(f, dfun, history, load, y0, t_eval, rtol, atol, slider):
    """odeint restarted at each breakpoint of the load history, sampled at ``t_eval``.

    ``f(y, t)`` raises :class:`_Diverging` where the quasi-static speed runs away. Returns
    (states at t_eval, steps, function evaluations).
    """
    from scipy.integrate import odeint  # heavy: imported where used

    pieces, nfev, steps, y = [], 0, 0, np.asarray(y0, float)
    tolerances = np.asarray(atol)
    for t0, t1, v_start, v_end in history.segments():
        load.enter(t0, t1, v_start, v_end)
        last = t1 == history.duration
        wanted = t_eval[(t_eval >= t0) & ((t_eval < t1) | (last & (t_eval <= t1)))]
        interior = wanted[wanted > t0]
        times = np.concatenate([[t0], interior, [] if interior.size and interior[-1] == t1 else [t1]])
        try:
            solution, info = odeint(f, y, times, Dfun=dfun, rtol=rtol, atol=tolerances, full_output=True,
                                    mxstep=500_000)
        except _Diverging as stop:
            _diverged(slider, stop.t)
        except OverflowError:
            raise SolverError("LSODA's trial state overflowed; tighten rtol or use method 'radau'") from None
        if info["message"] != "Integration successful.":
            raise SolverError(f"LSODA failed between {t0:g} and {t1:g} s: {info['message']}; use method 'radau'")
        nfev += int(info["nfe"][-1])
        steps += int(info["nst"][-1])
        start_row = solution[:1] if wanted.size and wanted[0] == t0 else solution[:0]
        pieces.append(np.vstack([start_row, solution[1:1 + interior.size]]))
        y = solution[-1]
    return np.concatenate(pieces), steps, nfev


def _dopri5_by_segment(rhs, history, load, y0, t_eval, rtol, atol, stop, slider):
    """dopri5 restarted at each breakpoint of the load history: its speed jumps there (a velocity step)."""
    pieces, steps, nfev, y = [], 0, 0, y0
    for t0, t1, v0, v1 in history.segments():
        load.enter(t0, t1, v0, v1)
        last = t1 == history.duration
        inside = t_eval[(t_eval >= t0) & ((t_eval < t1) | last)]
        values, y, t_end, segment_steps, segment_nfev = dopri5(rhs, t0, y, t1, inside, rtol, atol, on_step=stop)
        steps, nfev = steps + segment_steps, nfev + segment_nfev
        if t_end < t1:
            _diverged(slider, t_end)
        pieces.append(values)
    return np.concatenate(pieces), steps, nfev


def _diverged(slider, t):
    """Refuse a quasi-static run whose slip speed diverged, naming the cause: linear instability below k_c,
    or above it a velocity step too large for the slip law (Gu, Rice, Ruina & Tse 1984: a finite step
    destabilises a slider that small disturbances cannot)."""
    k_c = slider.critical_stiffness()
    ratio = slider.stiffness / k_c if k_c > 0 else math.inf
    if ratio < 1:
        cause = (f"k / k_c = {ratio:.3g} < 1: steady sliding is linearly unstable, and without inertia or a radiation "
                 "damper nothing bounds the speed")
    elif slider.law.evolution == "slip":
        cause = (f"k / k_c = {beside(ratio, 1.0)} >= 1, so small disturbances decay; the velocity step is larger than the slip "
                 "law's critical step at this stiffness (Gu et al. 1984: faultslip.dynamics.rate_state.slider."
                 "critical_step_ratio), and a large enough step destabilises it")
    else:
        cause = f"k / k_c = {ratio:.3g}: the step drove the state past what the quasi-static balance can follow"
    raise SolverError(f"the quasi-static slider has no solution past t = {t:.6g} s: its slip speed diverges ({cause}). "
                      "Use model 'quasi_dynamic' (a radiation damper bounds the speed) or 'inertial'")


# --- fault-scale earthquake cycles ---------------------------------------------------------


@dataclass
class RateStateCycles(ToXarray):
    """Earthquake cycles of a quasi-dynamic (or quasi-static) rate-and-state fault, after spin-up.

    Events are the intervals with slip speed above ``event_speed``. Per-event arrays cover the
    recorded cycles; the scalar properties are their means.
    """
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'event_times': 's', 'slip_per_event': 'm', 'stress_drop': 'Pa', 'peak_slip_rate': 'm/s', 'cycle_slip': 'm', 'plate_rate': 'm/s', 'stiffness_ratio': '1', 'steps': '1', 'function_evaluations': '1', 'wall_time': 's', 'event_speed': 'm/s', 'spin_up': '1', 'restarts': '1', 'rtol': '1', 'next_event_time': 's', 'a_over_b': '1'}
    DIMENSIONS = {'event_times': 'event', 'slip_per_event': 'event', 'stress_drop': 'event', 'peak_slip_rate': 'event', 'cycle_slip': 'event'}

    event_times: np.ndarray  # s, event starts
    slip_per_event: np.ndarray  # m, slip while V > event_speed
    stress_drop: np.ndarray  # Pa, elastic stress before minus after
    peak_slip_rate: np.ndarray  # m/s
    cycle_slip: np.ndarray  # m, all slip from one event start to the next
    plate_rate: float
    stiffness_ratio: float  # K / K_c (quasi-static k_c)
    model: str
    steps: int
    function_evaluations: int
    wall_time: float
    event_speed: float = EVENT_SPEED
    method: str = "dopri5"
    #: with ``record=True``: every accepted step's time (s), slip rate (m/s), psi, slip (m) and elastic
    #: shear stress (Pa) from the first recorded cycle on (the solver's own steps crowd into the events)
    series: dict | None = None
    #: the verdict on the cycles before the measured ones (None: measured after a fixed spin-up)
    settling: object = None
    spin_up: int = 0
    restarts: int = 0
    rtol: float = 1e-7
    #: s, the start of the event after the last measured cycle: every cycle's interval, the last's too
    next_event_time: float = math.nan
    #: the law's a / (b + b2), on which the declared error near K_c depends (None: not known, the largest taken)
    a_over_b: float | None = None

    @property
    def recurrence(self) -> float:
        """The mean interval of the measured cycles, from each one's event start to the next's (the same
        intervals whose slip ``cycle_slip`` holds; one cycle has one)."""
        starts = self.event_times if math.isnan(self.next_event_time) else np.append(self.event_times,
                                                                                   self.next_event_time)
        return float(np.mean(np.diff(starts))) if starts.size > 1 else math.nan

    @property
    def estimated_relative_error(self) -> float:
        """The steady cycle's declared error: the integrator's own (its fitted c rtol^q, amplified near K_c;
        the cycle-to-cycle scatter for an integrator without a calibration) plus what settling left."""
        if self.method in ERROR_MODEL:
            noise = error_bound(self.method, self.rtol, self.stiffness_ratio, a_over_b=self.a_over_b)
        else:
            noise = max(CYCLE_NOISE * self.rtol, near_critical_error(self.rtol, self.stiffness_ratio,
                                                                     a_over_b=self.a_over_b))
        if self.settling is None:
            return math.inf if self.spin_up < 1 else noise  # a fixed spin-up declares nothing about settling
        return settled_error(noise, self.settling.remaining)

    def report_settling(self, report) -> None:
        """Add the settling verdict and the declared error to ``report`` (every cycles report shows them)."""
        verdict = self.settling
        report.add("settled", bool(verdict.settled) if verdict is not None else None,
                   label="the sequence settled before it was measured")
        report.add("spin_up_cycles", int(self.spin_up), label="cycles run before the measured ones")
        report.add("estimated_relative_error", self.estimated_relative_error,
                   label="estimated relative error (integrator scatter, plus the settling left)")
        if verdict is not None and not verdict.settled:
            report.note(f"the cycles were measured before they settled: {verdict.reason}")
        if self.restarts:
            report.note(f"the cycle map was restarted {self.restarts} times from its extrapolated fixed point "
                        "(Steffensen) to reach the steady cycle")
        near = bifurcation_note("the critical stiffness K_c", "K / K_c", self.stiffness_ratio, 1.0)
        if near:
            report.note(near)

    @property
    def regime(self) -> str:
        if self.stiffness_ratio >= 1:
            return "stable_sliding" if self.event_times.size == 0 else "stick_slip"
        return "stick_slip"

    def summary(self) -> dict:
        return {"recurrence_period": {"value": self.recurrence, "units": "s"},
                "slip_per_event": {"value": float(np.mean(self.slip_per_event)), "units": "m"},
                "stress_drop": {"value": float(np.mean(self.stress_drop)), "units": "Pa"},
                "peak_slip_rate": {"value": float(np.max(self.peak_slip_rate)), "units": "m/s"},
                "stiffness_ratio": self.stiffness_ratio, "cycles": int(self.slip_per_event.size),
                "model": self.model, "method": self.method, "function_evaluations": self.function_evaluations,
                "wall_time": {"value": self.wall_time, "units": "s"}}


def cycles_stiffness_ratio(slider: RateStateSlider) -> float:
    """K / K_c that fault cycles judge a slider by: the quasi-static k_c = sigma_n (b - a) / D_c; 0 for a
    two-state law (which takes dopri5 whatever its ratio), inf where k_c <= 0 (stable)."""
    k_c = slider.critical_stiffness() if not slider.law.two_state else math.inf
    return slider.stiffness / k_c if k_c > 0 else math.inf


def law_a_over_b(law: RateStateLaw) -> float:
    """a / (b + b2): the law's steady-state weakening, which sets how slowly its cycles forget a perturbation."""
    return float(law.a / (law.b + law.b2))


def cycle_method(method: str, stiffness_ratio: float, law: RateStateLaw, rtol: float = CYCLES_RTOL,
                 record: bool = False) -> str:
    """The method :func:`fault_cycles` uses: ``method``, or for "auto" the cheapest at ``rtol`` by the
    calibrated cost models (:mod:`faultslip.dynamics.rate_state.methods`) among those that take the law:
    dopri5_compiled where it was built (one-state, unregularised laws; not when the series is recorded),
    else LSODA where the rupture is stiff (below K / K_c of about 0.015 at rtol 1e-7) and dopri5 elsewhere.
    Two-state laws take dopri5."""
    if method != "auto":
        return method
    if law.two_state:
        return "dopri5"
    names = [name for name in CYCLE_METHODS if name != "dopri5_compiled"
             or (native.available() and not law.regularized and not record)]
    return min(names, key=lambda name: steps_per_cycle(name, rtol, stiffness_ratio) * SECONDS_PER_STEP[name])


def _refuse_compiled(law: RateStateLaw, record: bool) -> None:
    """dopri5_compiled asked for where it cannot serve: say why and what to use."""
    if not native.available():
        raise InputError("dopri5_compiled was not built with this install (no C compiler at install time); use "
                         "'dopri5', the same scheme in Python, or method 'auto'")
    if law.two_state or law.regularized:
        raise InputError("dopri5_compiled integrates one-state, unregularised laws; use 'dopri5'")
    if record:
        raise InputError("dopri5_compiled steps from event edge to event edge and records no time series; use "
                         "'dopri5', the same scheme, to record one")


#: The default settling tolerance of fault cycles (relative, on interval, slip and state per cycle).
SETTLE_TOLERANCE = 1e-6
#: Cycle-to-cycle scatter of event quantities in units of rtol (event edges interpolated within a step;
#: measured 5-9 rtol at BP1 friction near K_c with dopri5 at rtol 1e-7).
CYCLE_NOISE = 10.0
#: LSODA's scatter in units of rtol: its event edges (a cubic Hermite of its steps' ends) scatter by 40 to 182 rtol
#: at rtol 3e-10 to 1e-7 (24 random faults, K / K_c 1e-5 to 0.3, 20 cycles after 12 of spin-up).
LSODA_CYCLE_NOISE = 300.0
#: A contraction is learnt only from cycle-to-cycle changes this many times the scatter (noise) or more.
SCATTER_MARGIN = 10.0


def cycle_noise(method: str, rtol: float, stiffness_ratio: float) -> float:
    """The cycle-to-cycle scatter the settling test takes as the integrator's own, not the approach's: 10 rtol
    (:data:`CYCLE_NOISE`), and for LSODA away from K_c :data:`LSODA_CYCLE_NOISE` rtol.

    Judged against 10 rtol, 21 of 40 random LSODA faults at K / K_c 1e-5 to 1e-2 took 8 to 402 cycles to settle
    where 4 do, cycles the cost model does not count. From K / K_c 0.9 (methods.NEAR_CRITICAL_FROM) the cycles
    approach their fixed point slowly, and changes of that size are the approach, not scatter: there 10 rtol stays.
    The scatter is measured, not taken from the declared error model: that model is fitted on runs settled by this
    test, and a test that took it as scatter would move the data it is fitted on.

    Parameters
    ----------
    method : str
        The integrator ("lsoda", "dopri5", "dopri5_compiled").
    rtol : float
        Its relative tolerance.
    stiffness_ratio : float
        The fault's K / K_c.

    Returns
    -------
    float
        The relative change per cycle taken as the integrator's scatter.
    """
    if method == "lsoda" and stiffness_ratio < NEAR_CRITICAL_FROM:
        return LSODA_CYCLE_NOISE * rtol
    return CYCLE_NOISE * rtol


@takes_units(plate_rate="speed", event_speed="speed", max_time="time")
def fault_cycles(slider: RateStateSlider, plate_rate: float, *, cycles: int = 100, spin_up: int = 2,
                 model: str = "quasi_dynamic", rtol: float = CYCLES_RTOL, event_speed: float = EVENT_SPEED,
                 max_time: float | None = None, method: str = "auto", record: bool = False,
                 max_steps: int = 5_000_000, progress=None, settle: float | None = SETTLE_TOLERANCE,
                 max_settling_cycles: int = 400) -> RateStateCycles:
    """Run ``spin_up + cycles`` earthquake cycles of a fault loaded at ``plate_rate`` (m/s) and measure them.

    The fault starts at steady sliding at 1.01 times the plate rate (a small perturbation that an
    unstable fault, K < K_c, grows into cycles). Integration is dopri5 on (ln V/V0, psi, slip),
    stopping as soon as the last event has ended. A stable fault (K >= K_c, or b <= a) has no
    events: that is refused with the ratio K / K_c, as are cycles that do not appear within
    ``max_time`` (default: 1e5 loading times D_c / V_pl and at least a million years).

    ``method``: "lsoda" (stiff/non-stiff switching, analytic Jacobian; one-state laws), "dopri5" (explicit, any
    law), "dopri5_compiled" (the same scheme stepped in C), or "auto" (the cheapest by the calibrated costs,
    :func:`cycle_method`). Events are found at step ends by both. Measured, 100 cycles at SEAS BP1 (K / K_c 0.05):
    dopri5 0.94 s, LSODA 0.80 s, recurrence equal to 1.3e-6, plate balance 3e-8 against 1.3e-5. Five cycles with a
    lab D_c of 15 µm on a 20 km fault (K / K_c 2e-4): dopri5's steps are stability-limited (305,000, 4.1 s) where
    LSODA takes 8,000 (0.54 s), recurrence equal to 1.2e-6.

    ``record``: keep the time series of every step after spin-up in ``series`` (for plots and files).
    ``max_steps``: the step budget; past it the run stops with a SolverError saying so.
    ``progress``: True for a bar, or a callable (done, total) over events (:mod:`faultslip.io.progress`).
    ``settle``: the cycles are measured only once the sequence has settled to this relative tolerance
    (:func:`~faultslip.dynamics.shared.settling.assess_settling` on the interval, the slip and the state
    at each event start); ``spin_up`` is then the least spin-up. Near K_c, where the natural approach
    takes hundreds of cycles, the one-state cycle map (psi at the rising crossing of ``event_speed``)
    is restarted from its Aitken-extrapolated fixed point (Steffensen). A sequence still unsettled
    after ``max_settling_cycles`` is measured anyway, its remaining distance declared in ``settling``.
    ``None`` measures after exactly ``spin_up`` cycles (the benchmarks' fixed work).

    Parameters
    ----------
    slider : RateStateSlider
        The fault's spring-block (:meth:`RateStateSlider.at_fault`).
    plate_rate : float
        V_pl (m/s).
    cycles, spin_up : int
        Cycles measured, after ``spin_up`` more.
    model : str
        quasi_dynamic or quasi_static.
    rtol : float
        The integrator's relative tolerance.
    event_speed : float
        Slip rate above which the fault is in an event (m/s).
    max_time : float, optional
        The longest simulated time (s).
    method : str
        auto, lsoda, dopri5 or dopri5_compiled.
    record : bool
        Keep every step's time series.
    max_steps : int
        The step budget.
    progress : callable, optional
        ``(done, total)`` over events.
    settle : float, optional
        The settling tolerance of the cycle (None: no settling check).
    max_settling_cycles : int
        The most cycles run to settle.

    Returns
    -------
    RateStateCycles
        Recurrence (s), slip per event (m), stress drop (Pa), peak slip rate (m/s) per cycle, K / K_c, the
        regime and the settling.
    """
    progress = reporter(progress, "cycles", "event")
    if method not in ("auto", "lsoda", "dopri5", "dopri5_compiled"):
        raise InputError(f"method must be auto, lsoda, dopri5 or dopri5_compiled, got {method!r}")
    if model not in ("quasi_dynamic", "quasi_static"):
        raise InputError("fault cycles run the quasi_dynamic model (or quasi_static, which fails at the first event)")
    if not (plate_rate > 0 and math.isfinite(plate_rate)):
        raise InputError(f"the plate rate must be a positive speed, got {plate_rate!r}")
    if cycles < 1 or spin_up < 0:
        raise InputError("cycles must be at least 1 and spin_up at least 0")
    law = slider.law
    ratio = cycles_stiffness_ratio(slider)
    if ratio >= 1:
        raise InputError(f"K / K_c = {beside(ratio, 1.0)} >= 1: steady sliding is stable here (no earthquake cycles); "
                         "cycles need K < K_c = sigma_n (b - a) / D_c")
    damping = slider.damping if model == "quasi_dynamic" else 0.0
    load = _Load()
    load.enter(0.0, 1.0, plate_rate, plate_rate)
    rhs = _quasi_rhs(slider, load, damping)
    speed0 = 1.01 * plate_rate
    y0 = tuple([math.log(speed0 / law.reference_speed), math.log(law.reference_speed / plate_rate)]
               + ([math.log(law.reference_speed / plate_rate)] if law.two_state else []) + [0.0])
    atol = _tolerances(slider, "quasi_dynamic", rtol)
    horizon = max_time or max(1e5 * law.critical_slip / plate_rate, 1e6 * JULIAN_YEAR)
    threshold = math.log(event_speed / law.reference_speed)
    sigma, k, v0 = slider.normal_stress, slider.stiffness, law.reference_speed
    keep_series = bool(record)  # the events dict below takes the name
    record = {"start": [], "end": [], "peak": [], "slip_start": [], "slip_end": [], "tau_start": [], "tau_end": []}
    state = {"inside": False, "peak": 0.0}
    # settling: per event start since the last restart, (interval, slip, psi); None once settled
    settling = {"starts": [], "restart": None, "restarts": 0, "verdict": None, "done": settle is None,
                "spin_up": spin_up}

    def elastic_stress(y):
        psi2 = y[2] if law.two_state else 0.0
        speed = v0 * math.exp(y[0])
        return sigma * float(law.friction(speed, y[1], psi2)) + damping * speed

    clock = {"offset": 0.0}  # the ODE is autonomous: restart the local time at every crossing
    # oscillations' maxima of ln V / V0 since the last event start, and the swing the latest is in
    slow = {"peaks": [], "rising": True, "high": -math.inf, "low": math.inf}

    previous = {"t": None, "y": None}
    record_series = {"time": [], "state": []}

    def crossing(t, y, interpolant):
        """Time and state where ln V crosses the threshold within the last step, found by bisection on
        ``interpolant(fraction)``: dopri5's own continuous extension of order 4, accurate to the integration's
        error, or (``None``, LSODA) a cubic Hermite interpolant of the step's ends. A step end alone would put
        the event's edges off by a step's slip. The Hermite's O(h^4) error led dopri5's error in slip per event
        where a / b nears 1 (c rtol^0.8, 93 rtol at rtol 1e-10); LSODA keeps it because its own dense output
        (scipy's Nordsieck polynomial) scattered the state at the crossing by 1e-5 at rtol 1e-8, and its slip per
        event scattered as much with either interpolant (its error is its integration's)."""
        t_prev, y_prev = previous["t"], previous["y"]
        if t_prev is None or t == t_prev:
            return t, y
        h = t - t_prev
        if interpolant is None:
            slopes = [h * d for d in rhs(0.0, y_prev)], [h * d for d in rhs(0.0, y)]  # autonomous: any t

            def interpolant(u):
                h00, h10 = (1 + 2 * u) * (1 - u) ** 2, u * (1 - u) ** 2
                h01, h11 = u * u * (3 - 2 * u), u * u * (u - 1)
                return [h00 * p + h10 * dp + h01 * c + h11 * dc
                        for p, c, dp, dc in zip(y_prev, y, slopes[0], slopes[1])]

        at = interpolant
        low, high = 0.0, 1.0
        rising = y[0] > y_prev[0]
        for _ in range(60):  # bisection to ~1e-18 of the step
            middle = 0.5 * (low + high)
            if (at(middle)[0] > threshold) == rising:
                high = middle
            else:
                low = middle
        state = at(high)
        state[0] = threshold
        return t_prev + high * h, state

    def event_start(t_c, y_c, x_after):
        """An event begins at (t_c, y_c); x_after is ln(V / V0) at the end of the step that crossed."""
        state["inside"], state["peak"] = True, v0 * math.exp(x_after)
        slow["peaks"].clear()  # after the event, ln V falls: the next oscillation starts at its trough
        slow["rising"], slow["low"] = False, math.inf
        record["start"].append(t_c)
        record["slip_start"].append(y_c[-1])
        record["tau_start"].append(elastic_stress(y_c))
        if not settling["done"]:
            _settling_step(settling, record, y_c, spin_up, settle, law.two_state or chosen_method == "lsoda",
                           max_settling_cycles, cycle_noise(chosen_method, rtol, ratio))

    def event_end(t_c, y_c):
        state["inside"] = False
        record["end"].append(t_c)
        record["peak"].append(state["peak"])
        record["slip_end"].append(y_c[-1])
        record["tau_end"].append(elastic_stress(y_c))
        if progress:  # the total grows while the sequence settles: spin-up, then the measured cycles
            done = len(record["end"])
            progress(done, max(settling["spin_up"] + cycles + 1, done + (0 if settling["done"] else 1)))

    def running():
        return not settling["done"] or len(record["end"]) <= settling["spin_up"] + cycles

    def on_step(t, y, step):
        # y is the integrator's own new state (dopri5 makes a new list each step; LSODA's caller copies):
        # kept by reference, the interseismic fast path costs two assignments. ``step``: dopri5's (start, size,
        # stages), or None (LSODA)
        now = clock["offset"] + t
        stop = False
        if y[0] > threshold:
            if not state["inside"]:
                event_start(*crossing(now, y, _step_interpolant(step)), y[0])
                stop = True
            else:
                state["peak"] = max(state["peak"], v0 * math.exp(y[0]))
        elif state["inside"]:
            event_end(*crossing(now, y, _step_interpolant(step)))
            stop = True
        elif not law.two_state:
            _slow_oscillation(slow, y[0], slider, ratio, now, v0, event_speed)
        previous["t"] = now
        previous["y"] = y
        if keep_series and settling["done"] and len(record["start"]) > settling["spin_up"]:
            record_series["time"].append(now)
            record_series["state"].append(tuple(y))
        return stop

    started = time.perf_counter()
    steps = nfev = 0
    chosen_method = cycle_method(method, ratio, law, rtol, record=keep_series)
    if chosen_method == "lsoda" and law.two_state:
        raise InputError("method 'lsoda' for fault cycles takes a one-state law (its Jacobian); use 'dopri5'")
    if chosen_method == "dopri5_compiled":
        _refuse_compiled(law, keep_series)
    if chosen_method == "lsoda":
        steps, nfev, clock["offset"] = _lsoda_cycles(rhs, _quasi_jacobian(slider, load, damping), y0, rtol, atol,
                                                     horizon, on_step, running, slider, model, max_steps)
    elif chosen_method == "dopri5_compiled":  # the same scheme stepped in C from one event edge to the next
        y, h = y0, -1.0
        fixed = (law.evolution == "aging", v0, law.critical_slip, k, sigma * law.a, sigma * law.b, damping,
                 plate_rate)
        while running() and clock["offset"] < horizon:
            if settling["restart"] is not None:  # Steffensen: continue from the extrapolated fixed point
                y, settling["restart"], h = settling["restart"], None, -1.0
            status, t_local, x, psi, slip, run_steps, run_nfev, h, t_c, psi_c, slip_c, peak = native.run(
                *y, h, horizon - clock["offset"], rtol, *atol, *fixed, state["inside"], threshold, max_steps - steps)
            steps, nfev = steps + run_steps, nfev + run_nfev
            if status == native.STEP_COLLAPSE and model == "quasi_dynamic" and run_steps > 0 and t_local > 0:
                # the step fell below the resolution of the clock, not of the solution (a rupture's millisecond
                # steps at t ~ 1e11 s, rtol 1e-12): restart the autonomous system's clock there and go on
                clock["offset"] += t_local
                y = (x, psi, slip)
                continue
            if status == native.STEP_COLLAPSE:
                if model == "quasi_static":
                    _diverged(slider, clock["offset"] + t_local)
                raise SolverError(f"dopri5_compiled failed in the quasi-dynamic fault cycles (the step size fell to "
                                  f"{h:.1e} s at t = {clock['offset'] + t_local:.6g} s); tighten rtol")
            if status == native.TOO_MANY_STEPS:
                # the C stepper sees no oscillations: no event in a budget that holds 20 cycles' steps is slow slip
                if (not state["inside"] and math.isfinite(peak) and peak < threshold
                        and 20 * steps_per_cycle(chosen_method, rtol, ratio) < max_steps):
                    raise NoEventsError(_no_event_sentence(v0 * math.exp(peak), f"in {max_steps} steps", slider,
                                                           ratio, event_speed))
                raise SolverError(f"dopri5_compiled took more than {max_steps} steps (its budget) before "
                                  f"t = {clock['offset'] + t_local:.6g} s")
            if state["inside"] and math.isfinite(peak):
                state["peak"] = max(state["peak"], v0 * math.exp(peak))
            if status == native.CROSSED:
                if state["inside"]:
                    event_end(clock["offset"] + t_c, [threshold, psi_c, slip_c])
                else:
                    event_start(clock["offset"] + t_c, [threshold, psi_c, slip_c], x)
            clock["offset"] += t_local
            y = (x, psi, slip)
    else:
        y, step = y0, {"h": None}
        try:
            while running() and clock["offset"] < horizon:
                if settling["restart"] is not None:  # Steffensen: continue from the extrapolated fixed point
                    y, settling["restart"], step["h"] = settling["restart"], None, None
                _, y, t_local, run_steps, run_nfev = dopri5(rhs, 0.0, y, horizon - clock["offset"], np.empty(0), rtol,
                                                            atol, max_steps=max_steps - steps, h0=step["h"],
                                                            on_step=on_step,
                                                            last_step=step, rebase=model == "quasi_dynamic")
                clock["offset"] += t_local
                steps, nfev = steps + run_steps, nfev + run_nfev
        except NoEventsError:
            raise
        except _StepCollapse as collapse:
            if model == "quasi_static":
                _diverged(slider, clock["offset"] + collapse.t)
            raise SolverError(f"dopri5 failed in the quasi-dynamic fault cycles ({collapse}); tighten rtol") from None
        except SolverError:  # its step budget: dopri5 saw only what was left of it, so say the run's whole budget
            raise SolverError(f"dopri5 took more than {max_steps} steps (its budget) before t = "
                              f"{clock['offset']:.6g} s at K / K_c = {ratio:.3g}; its steps are stability-limited "
                              "where the rupture is stiff: use method 'lsoda' (or 'dopri5_compiled'), or raise "
                              "max_steps") from None
    t_end = clock["offset"]
    wall = time.perf_counter() - started
    ends = len(record["end"])
    spin_up = settling["spin_up"]
    wanted = spin_up + cycles
    if ends <= wanted:
        slow = "; this close to K_c the 1 % perturbation it starts from grows slowly" if ratio > 0.99 else ""
        raise NoEventsError(f"only {ends} events in {t_end / JULIAN_YEAR:.3g} years (K / K_c = {ratio:.3g}); the fault "
                          f"creeps or its cycles are longer than max_time{slow}; raise max_time or check a, b and D_c")
    chosen = slice(spin_up, spin_up + cycles)
    series = _series(record_series, record["start"][spin_up + cycles], elastic_stress, v0) if keep_series else None
    starts = np.array(record["start"][spin_up:spin_up + cycles + 1])
    slip_starts = np.array(record["slip_start"][spin_up:spin_up + cycles + 1])
    return RateStateCycles(event_times=starts[:-1] if starts.size > cycles else starts,
                           next_event_time=float(starts[-1]) if starts.size > cycles else math.nan,
                           slip_per_event=np.array(record["slip_end"][chosen]) - np.array(record["slip_start"][chosen]),
                           stress_drop=np.array(record["tau_start"][chosen]) - np.array(record["tau_end"][chosen]),
                           peak_slip_rate=np.array(record["peak"][chosen]), cycle_slip=np.diff(slip_starts),
                           plate_rate=plate_rate, stiffness_ratio=ratio, model=model, steps=steps,
                           function_evaluations=nfev, wall_time=wall, event_speed=event_speed, method=chosen_method,
                           series=series, settling=settling["verdict"], spin_up=spin_up,
                           restarts=settling["restarts"], rtol=rtol, a_over_b=law_a_over_b(law))


def _settling_step(settling: dict, record: dict, y_c, least_spin_up: int, tolerance: float, no_restart: bool,
                   max_settling_cycles: int, noise: float) -> None:
    """At an event start: judge the sequence since the last restart, settle it, or restart it (Steffensen)."""
    starts, slips = record["start"], record["slip_start"]
    if len(starts) >= 2:
        settling["starts"].append((starts[-1] - starts[-2], slips[-1] - slips[-2], float(y_c[1])))
    history = settling["starts"]
    events = len(starts)
    if len(history) < 4:
        return
    # psi is O(1) and may cross zero: its changes are measured against 1, not against itself
    verdict = assess_settling(history, max(tolerance, noise), floor=(0.0, 0.0, 1.0),
                              names=("interval", "slip per cycle", "state"), noise=noise,
                              contraction_hint=settling.get("rho", math.nan))
    # the contraction is learnt only from changes well above the integrator's scatter: a ratio of two changes at
    # the scatter says nothing of the map (it is near 1 by chance) and, kept as the hint, it would amplify the
    # declared error a million-fold far from any bifurcation (K / K_c = 0.13: 2.5 declared, 2e-8 true)
    rows = np.asarray(history[-2:], float)
    scale = np.maximum(np.abs(rows[-1]), (0.0, 0.0, 1.0))
    last_change = float(np.max(np.abs(rows[-1] - rows[-2]) / np.where(scale > 0, scale, 1.0)))
    if 0 < verdict.contraction < 1 and last_change > SCATTER_MARGIN * noise:
        settling["rho"] = max(verdict.contraction, settling.get("rho", 0.0))
    settling["verdict"] = verdict
    if verdict.settled and events - 1 >= least_spin_up:
        settling["spin_up"], settling["done"] = events - 1, True
        return
    if events - 1 >= least_spin_up + max_settling_cycles:
        settling["spin_up"], settling["done"] = events - 1, True  # measured unsettled: the verdict says how far
        return
    if not no_restart and verdict.contraction < 1 and settling["restarts"] < 12:
        psi = [row[2] for row in history[-3:]]
        target = float(aitken(*psi))
        if math.isfinite(target) and target != psi[-1]:
            restart = list(y_c)
            restart[1] = target
            settling["restart"] = restart
            settling["restarts"] += 1
            settling["starts"] = []


def _series(recorded, end, elastic_stress, reference_speed) -> dict:
    """The recorded steps up to the start of the event after the last measured cycle, as arrays."""
    times = np.array(recorded["time"])
    keep = times <= end
    states = [state for state, kept in zip(recorded["state"], keep) if kept]
    columns = np.array(states, dtype=float)
    return {"time": times[keep], "slip_rate": reference_speed * np.exp(columns[:, 0]), "psi": columns[:, 1],
            "slip": columns[:, -1], "shear_stress": np.array([elastic_stress(state) for state in states])}


def _step_interpolant(step):
    """The state at a fraction of the last step from dopri5's continuous extension (``step``: its start, size and
    stages), or None (LSODA's step: the crossing interpolates its ends)."""
    if step is None:
        return None
    start, size, stages = step
    return lambda fraction: continuous_state(start, size, stages, fraction)


#: Maxima of ln V compared, window against window, before cycles below the event speed are declared slow slip.
SLOW_WINDOW = 50
#: The fall (and rise) in ln V that makes a maximum an oscillation's, not an integrator's scatter.
SLOW_SWING = 0.1


def _no_event_sentence(peak_speed, where, slider, ratio, event_speed) -> str:
    law = slider.law
    return (f"no slip faster than the event speed {event_speed:g} m/s {where}: the slider's slip speed peaks at "
            f"{peak_speed:.4g} m/s, slow slip or creep, not earthquakes (K / K_c = {ratio:.4g}, a / b = "
            f"{law.a / law.b:.3g}; near K_c and with a / b near 1 the cycles' peak speed can stay below it)")


def _slow_oscillation(slow, x, slider, ratio, now, v0, event_speed) -> None:
    """Raise NoEventsError where the slider has settled into oscillations whose speed peaks below the event speed.

    A one-state quasi-dynamic slider is an autonomous flow in (ln V, psi), so by Poincare-Bendixson its cycles
    approach one closed orbit with peaks that grow or shrink monotonically toward it: once the highest of the
    last :data:`SLOW_WINDOW` maxima of ln V (each below the event speed: called between events only) is no
    higher than the highest of the window before, no event will come (seen at K / K_c 0.998, a / b 0.9: peaks at 0.996 mm/s, where 5 million
    steps were spent and reported as the step budget of a stiff rupture). A maximum counts once ln V has fallen
    :data:`SLOW_SWING` below it and risen as far from the trough before it: an integrator's step-to-step scatter
    in a long interseismic creep is not an oscillation."""
    if slow["rising"]:
        if x > slow["high"]:
            slow["high"] = x
        elif x < slow["high"] - SLOW_SWING:
            peaks = slow["peaks"]
            peaks.append(slow["high"])
            slow["rising"], slow["low"] = False, x
            if len(peaks) >= 2 * SLOW_WINDOW:
                del peaks[:-2 * SLOW_WINDOW]
                recent = max(peaks[SLOW_WINDOW:])
                if recent <= max(peaks[:SLOW_WINDOW]):
                    where = f"over its last {2 * SLOW_WINDOW} oscillations, to t = {now / JULIAN_YEAR:.4g} yr"
                    raise NoEventsError(_no_event_sentence(v0 * math.exp(recent), where, slider, ratio, event_speed))
    elif x < slow["low"]:
        slow["low"] = x
    elif x > slow["low"] + SLOW_SWING:
        slow["rising"], slow["high"] = True, x


def _lsoda_cycles(rhs, jacobian, y0, rtol, atol, horizon, on_step, running, slider, model, max_steps=5_000_000):
    """Step scipy's LSODA through the cycles, calling ``on_step`` at every step end (absolute time)."""
    from scipy.integrate import LSODA  # heavy: imported where used

    solver = LSODA(rhs, 0.0, np.asarray(y0, float), horizon, rtol=rtol, atol=np.asarray(atol), jac=jacobian)
    steps = 0
    with np.errstate(over="raise", invalid="raise"):
        while running() and solver.status == "running":
            try:
                message = solver.step()
            except (OverflowError, FloatingPointError):
                message = "the state overflowed"
            if solver.status == "failed" or message:
                if model == "quasi_static":
                    _diverged(slider, solver.t)
                raise SolverError(f"LSODA failed in the fault cycles at t = {solver.t:.6g} s ({message}); use method "
                                  "'dopri5' or tighten rtol")
            steps += 1
            on_step(solver.t, solver.y.copy(), None)  # y kept by reference there
            if steps > max_steps:
                raise SolverError(f"LSODA took more than {max_steps} steps (its budget) before t = {solver.t:.6g} s")
    return steps, solver.nfev, solver.t


def critical_step_ratio(law: RateStateLaw, stiffness_ratio: float, *, largest: float = 1e4, tolerance: float = 0.01,
                        relaxation_lengths: float = 200.0) -> float:
    """The smallest velocity-step ratio V2 / V1 that destabilises a quasi-static slider at k = ratio k_c.

    Found by bisection on log(V2/V1) with simulations (Gu, Rice, Ruina & Tse 1984 for the slip
    law). Returns inf if a step of ``largest`` is still stable (as for the aging law above k_c),
    and 1.0 below k_c, where any perturbation grows. A step is unstable when the quasi-static
    speed diverges within ``relaxation_lengths`` D_c of slip at the new speed.
    """
    if law.two_state:
        raise InputError("the critical step ratio is defined here for one-state laws")
    if stiffness_ratio <= 1.0:
        return 1.0
    speed = law.reference_speed
    slider = RateStateSlider(law, stiffness_ratio * law.critical_stiffness(1.0), 1.0)

    def unstable(ratio):
        settle = relaxation_lengths * law.critical_slip / (ratio * speed)
        history = LoadHistory.velocity_steps([(0.0, speed), (1.0, ratio * speed)], 1.0 + settle)
        try:
            simulate_rate_state(slider, history, samples=3, rtol=1e-9)
        except SolverError as error:
            if "diverges" not in str(error):  # a solver failure is not an instability: say so
                raise SolverError(f"the critical step search at V2/V1 = {ratio:.4g} failed: {error}") from None
            return True
        return False

    if not unstable(largest):
        return math.inf
    low, high = 0.0, math.log(largest)
    while high - low > tolerance:
        middle = 0.5 * (low + high)
        if unstable(math.exp(middle)):
            high = middle
        else:
            low = middle
    return math.exp(high)
