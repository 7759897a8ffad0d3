"""Quasi-harmonic friction-induced vibration by Kryloff-Bogoliuboff averaging (seed 002, section 3).

The slider of seed 002 eq. (10), driven at speed v under a friction-velocity curve f,

    M X'' + r X' + k X = W f(v - X'),

oscillates about a shifted rest position without ever sticking while ``|X'| < v``. With
X - X_0 = A sin(omega t + Phi) and A, Phi slowly varying (omega^2 = k / M), averaging over a
period gives (seed 002 eqs. 20-21; the phase is unaffected since f depends on X' only)

    A' = -r A / (2 M) + W / (2 pi M omega) * integral_0^2pi f(v - A omega cos b) cos b db.  (eq. 20)

For a polynomial the integral is closed: expanding f about v, only the odd derivatives survive,

    integral = -pi sum_{m odd} w_m f^(m)(v) / m! (A omega)^m,
    w_m = 2 C(m + 1, (m + 1) / 2) / 2^(m + 1) = 1, 3/4, 5/8, 35/64, 63/128, ...

(from integral_0^2pi cos^(m+1) b db = 2 pi C(m + 1, (m + 1)/2) / 2^(m + 1)), so that

    A' = -(A / 2M) [r + W sum_{m odd} w_m f^(m)(v) / m! (A omega)^(m - 1)],

whose nonzero roots are seed 002 eq. (23)'s limit cycles. Any other curve (tabulated, callable)
goes by quadrature. Steady sliding (A = 0) is unstable where r + W f'(v) < 0; a limit cycle
A* is stable where dA'/dA < 0 there. A vertical shift of f changes nothing here (only
derivatives enter): the slider oscillates about another position with the same amplitude.

Validity: the first-order averaged amplitude is accurate to O(eps), ``eps = (r + W max|f'|) / (M omega)``,
the size of the nonlinear damping per radian (seed 002: "the nonlinear term is relatively small").
Where A omega reaches v the sliding speed v - X' touches zero: the slider would stick, and the
quasi-harmonic description ends; the stick-slip methods take over.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from faultslip.dynamics.spring_slider.simulate import simulate
from faultslip.dynamics.spring_slider.slider import SliderSystem
from faultslip.units import ELAPSED_TIME_ATTRS, takes_units
from faultslip.dynamics.shared.settling import assess_settling, settled_error
from faultslip import ranges
from faultslip.errors import InputError, SolverError
from faultslip.friction.laws import ConstantStatic, PolynomialKinetic
from faultslip.io.report import Report

#: quadrature nodes for curves without a closed form (the trapezoidal rule is spectrally accurate
#: for smooth periodic integrands); the estimate of its error compares with half as many
QUADRATURE_NODES = 512
#: measured error of the averaged limit-cycle amplitude against direct integration: 0.010 s^2 (Rayleigh's
#: curve), 0.026 s^2 (with an even term), 0.026-0.049 s^2 (configs/vibration_seed002.toml from 12.3 to
#: 13.4 in/s), s = small_parameter (tests/models/vibration/test_averaging.py): declared 0.1 s^2
ERROR_CONSTANT = 0.1
#: averaging declines to say whether the slider sticks again within this many eps of the no-stick bound
HAND_OVER_MARGIN = 0.15
#: the averaged envelope's integration tolerance (eq. 20 by LSODA)
ENVELOPE_RTOL = 1e-10
#: seed 002's apparatus in SI: equivalent mass 1.76 lb and r = 0.00368 lbf s/in (Appendix C, as printed),
#: k = 70.5 lbf/in (Appendix B); the normal load W = 2 lbf is illustrative (configs/vibration_seed002.toml)
SEED002_APPARATUS = {"mass": 1.76 * 0.45359237, "stiffness": 70.5 * 4.4482216152605 / 0.0254,
                     "damping": 0.00368 * 4.4482216152605 / 0.0254, "normal_load": 2 * 4.4482216152605}


def odd_weight(order: int) -> float:
    """w_m = 2 C(m + 1, (m + 1) / 2) / 2^(m + 1) for odd m: the averaged weight of the (A omega)^m term."""
    if order < 1 or order % 2 == 0:
        raise InputError(f"the averaging weights belong to odd orders, got {order}")
    return 2.0 * math.comb(order + 1, (order + 1) // 2) / 2.0 ** (order + 1)


def polynomial_integral(coefficients, speed: float, amplitude_speed) -> np.ndarray:
    """integral_0^2pi f(v - A omega cos b) cos b db for f(u) = sum c_n u^n (increasing powers), closed form.

    ``amplitude_speed`` is A omega (scalar or array, m/s)."""
    coefficients = np.asarray(coefficients, dtype=float)
    amplitude_speed = np.asarray(amplitude_speed, dtype=float)
    total = np.zeros_like(amplitude_speed)
    derivative = coefficients
    for order in range(1, coefficients.size):
        derivative = np.polynomial.polynomial.polyder(derivative)
        if order % 2:
            taylor = np.polynomial.polynomial.polyval(speed, derivative) / math.factorial(order)
            total = total - math.pi * odd_weight(order) * taylor * amplitude_speed ** order
    return total


def quadrature_integral(friction, speed: float, amplitude_speed, nodes: int = QUADRATURE_NODES):
    """The same integral for any vectorised curve ``friction(u)``, by the periodic trapezoidal rule;
    returns (values, estimated absolute error from halving the nodes)."""
    amplitude_speed = np.atleast_1d(np.asarray(amplitude_speed, dtype=float))

    def rule(count):
        angles = 2.0 * math.pi * np.arange(count) / count
        cosines = np.cos(angles)
        values = friction(speed - amplitude_speed[:, None] * cosines[None, :]) * cosines[None, :]
        return values.sum(axis=1) * (2.0 * math.pi / count)

    fine, coarse = rule(nodes), rule(nodes // 2)
    return fine, np.abs(fine - coarse)


@takes_units(mass="mass", damping="damping", stiffness="stiffness", normal_load="force", speed="speed")
@dataclass
class QuasiHarmonic:
    """The averaged slider of seed 002 eq. (10), SI: mass M (kg), damping r (N s/m), stiffness k (N/m),
    normal load W (N), driving speed v (m/s) and the friction curve, as polynomial coefficients in
    increasing powers of the sliding speed (``coefficients``) or any vectorised callable (``friction``).

    Parameters
    ----------
    mass : float
        Equivalent mass M (kg).
    damping : float
        Damping r (N s/m).
    stiffness : float
        Stiffness k (N/m).
    normal_load : float
        Normal load W (N).
    speed : float
        Driving speed v (m/s).
    coefficients : tuple, optional
        The friction curve's polynomial coefficients in increasing powers of the sliding speed ((s/m)^k).
    friction : callable, optional
        Or the friction curve as a vectorised callable of the sliding speed (m/s).
    name : str
        A name for reports.
    """

    mass: float
    damping: float
    stiffness: float
    normal_load: float
    speed: float
    coefficients: tuple | None = None
    friction: object = None
    name: str = "quasi-harmonic slider"

    def __post_init__(self):
        for label, value in (("mass", self.mass), ("stiffness", self.stiffness), ("normal load", self.normal_load),
                             ("driving speed", self.speed)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InputError(f"the {label} must be a positive finite number, got {value!r}")
        if not (math.isfinite(self.damping) and self.damping >= 0):
            raise InputError(f"the damping r must be a finite number >= 0, got {self.damping!r}")
        if (self.coefficients is None) == (self.friction is None):
            raise InputError("give the friction curve as polynomial coefficients or as a callable, one of them")
        if self.coefficients is not None:
            self.coefficients = tuple(float(c) for c in self.coefficients)
            if not self.coefficients or not all(math.isfinite(c) for c in self.coefficients):
                raise InputError("the friction polynomial needs finite coefficients")

    @property
    def angular_frequency(self) -> float:
        return math.sqrt(self.stiffness / self.mass)

    def curve(self, sliding_speed):
        """f(u): the friction coefficient at sliding speed u."""
        if self.coefficients is not None:
            return np.polynomial.polynomial.polyval(sliding_speed, self.coefficients)
        return np.asarray(self.friction(np.asarray(sliding_speed, dtype=float)), dtype=float)

    def slope(self, sliding_speed, step: float | None = None):
        """f'(u): exact for a polynomial, a central difference otherwise."""
        if self.coefficients is not None:
            return np.polynomial.polynomial.polyval(sliding_speed,
                                                    np.polynomial.polynomial.polyder(self.coefficients))
        h = step or 1e-6 * max(abs(self.speed), 1e-12)
        return (self.curve(np.asarray(sliding_speed) + h) - self.curve(np.asarray(sliding_speed) - h)) / (2 * h)

    def integral(self, amplitude):
        """integral_0^2pi f(v - A omega cos b) cos b db, and its estimated error (0 in closed form)."""
        amplitude_speed = np.asarray(amplitude, dtype=float) * self.angular_frequency
        if self.coefficients is not None:
            return polynomial_integral(self.coefficients, self.speed, amplitude_speed), np.zeros_like(amplitude_speed)
        values, error = quadrature_integral(self.curve, self.speed, amplitude_speed)
        return values.reshape(np.shape(amplitude_speed)), error.reshape(np.shape(amplitude_speed))

    def amplitude_rate(self, amplitude):
        """A' (m/s) from eq. (20)."""
        amplitude = np.asarray(amplitude, dtype=float)
        integral, _ = self.integral(amplitude)
        omega = self.angular_frequency
        return -self.damping * amplitude / (2 * self.mass) + self.normal_load * integral / (2 * math.pi * self.mass * omega)

    @property
    def steady_sliding_growth(self) -> float:
        """Growth rate (1/s) of small oscillations about steady sliding: -(r + W f'(v)) / (2 M)."""
        return -(self.damping + self.normal_load * float(self.slope(self.speed))) / (2 * self.mass)

    def small_parameter(self, amplitude: float = 0.0) -> float:
        """``eps = (r + W max|f'|) / (M omega)``, f' over the sliding speeds v +- A omega of an oscillation of
        amplitude A: the nonlinear damping per radian, whose smallness averaging assumes."""
        reach = amplitude * self.angular_frequency
        speeds = self.speed + np.linspace(-reach, reach, 201)
        return float((self.damping + self.normal_load * np.max(np.abs(self.slope(speeds))))
                     / (self.mass * self.angular_frequency))

    def limit_cycles(self, largest: float | None = None, samples: int = 4000) -> list:
        """Every nonzero root A* of A' = 0 up to ``largest`` (default: the no-stick limit v / omega, and
        twice it to show the roots beyond), with its stability, sorted by amplitude."""
        omega = self.angular_frequency
        top = largest or 2.0 * self.speed / omega
        grid = np.linspace(top / samples, top, samples)
        rates = self.amplitude_rate(grid) / grid  # A'/A: the roots without the trivial A = 0
        signs = np.sign(rates)
        cycles = []
        # a sign change between two nodes, or a root on a node itself (a sign change across a zero): A = 0.16 fell
        # on the node 32 x 0.005 for Rayleigh's oscillator at d = 0.0064, and the cycle went unseen
        between = np.nonzero(signs[:-1] * signs[1:] < 0)[0]
        on_node = [i for i in np.nonzero(signs == 0)[0] if 0 < i < samples - 1 and signs[i - 1] * signs[i + 1] < 0]
        for i in sorted(list(between) + on_node):
            if signs[i] == 0:
                root = float(grid[i])
            else:
                low, high = grid[i], grid[i + 1]
                for _ in range(80):
                    middle = 0.5 * (low + high)
                    if np.sign(self.amplitude_rate(middle) / middle) == signs[i]:
                        low = middle
                    else:
                        high = middle
                root = 0.5 * (low + high)
            step = 1e-6 * root
            derivative = float((self.amplitude_rate(root + step) - self.amplitude_rate(root - step)) / (2 * step))
            cycles.append(LimitCycle(amplitude=root, stable=derivative < 0, decay_rate=derivative,
                                     sticks=root * omega >= self.speed))
        return cycles

    def envelope(self, initial_amplitude: float, duration: float, samples: int = 401):
        """A(t) from eq. (20) by an adaptive integrator (LSODA): growth or decay toward a limit cycle.

        LSODA switches to a stiff method where the envelope collapses fast (a large eps, far outside averaging's
        domain: after break-away at 1 km/s on a polynomial curve, the explicit RK45 took 555,000 evaluations and
        24 s for one period; LSODA takes about 500 whatever the speed)."""
        from scipy.integrate import solve_ivp  # heavy: imported where used

        if not (initial_amplitude >= 0 and duration > 0):
            raise InputError("the envelope needs an initial amplitude >= 0 and a positive duration")
        times = np.linspace(0.0, duration, samples)
        solution = solve_ivp(lambda t, a: self.amplitude_rate(a), (0.0, duration), [initial_amplitude],
                             t_eval=times, rtol=ENVELOPE_RTOL, atol=1e-14 * max(initial_amplitude, 1e-12),
                             method="LSODA")
        if not solution.success:
            raise InputError(f"the amplitude equation failed to integrate: {solution.message}")
        return times, solution.y[0]

    def analyse(self, start: float | None = None) -> "QuasiHarmonicResult":
        """Steady sliding's stability, the limit cycles, which one the slider settles on, and validity.

        From small disturbances (``start`` None): steady sliding where it is stable (amplitude 0); else the
        smallest stable limit cycle. From an amplitude ``start`` (m; after break-away, say), where eq. (20)
        carries it: down to the largest cycle below, or steady sliding, where A' < 0 there; up to the smallest
        above where A' > 0. A subcritical slider, steady sliding stable, can so settle on a cycle. The motion is
        quasi-harmonic if that cycle's peak speed A omega stays below v; where there is no such cycle, or it
        would stick, the result is not valid (``valid`` False, amplitude NaN): the motion is stick-slip. Within
        HAND_OVER_MARGIN eps of that bound the first-order call is ``marginal``: integration decides.
        """
        growth = self.steady_sliding_growth
        cycles = self.limit_cycles()
        notes = []
        amplitude, valid, settled = 0.0, True, None
        if start is None or start <= 0:
            rising = growth > 0
            if rising:  # small oscillations grow to the first stable cycle above zero
                settled = next((c for c in cycles if c.stable), None)
        else:
            rising = float(self.amplitude_rate(start)) > 0
            if rising:
                settled = next((c for c in cycles if c.amplitude > start and c.stable), None)
            else:  # A' <= 0: down to the first stable cycle met below the start, or to steady sliding
                settled = next((c for c in reversed(cycles) if c.amplitude <= start and c.stable), None)
        if rising and settled is None:
            valid, amplitude = False, math.nan
            notes.append("no stable limit cycle below twice the no-stick amplitude v / omega: the oscillation "
                         "grows until the slider sticks (stick-slip); use the stick-slip methods")
        elif settled is not None and settled.sticks:
            valid, amplitude = False, math.nan
            notes.append(f"the limit cycle's peak speed A omega = {settled.amplitude * self.angular_frequency:.4g} "
                         f"m/s reaches the driving speed {self.speed:.4g} m/s: the slider would stick, so the "
                         "quasi-harmonic solution does not hold; use the stick-slip methods")
        elif settled is not None:
            amplitude = settled.amplitude
        elif any(c.stable and not c.sticks for c in cycles):
            notes.append("steady sliding is stable, but a large disturbance can reach a stable limit cycle "
                         f"(A = {next(c.amplitude for c in cycles if c.stable):.4g} m)")
        eps = self.small_parameter(amplitude if valid else self.speed / self.angular_frequency)
        marginal = False
        if settled is not None:
            # the peak speed differs from A omega by O(eps) (harmonics): within the margin of the bound the
            # first-order call is not trusted either way (benchmarks/averaging_check.py measures the wrong calls)
            distance = settled.amplitude * self.angular_frequency / self.speed - 1.0
            marginal = abs(distance) < HAND_OVER_MARGIN * self.small_parameter(settled.amplitude)
            if marginal:
                notes.append(f"the cycle's peak speed A omega is within {HAND_OVER_MARGIN:g} eps of the driving speed "
                             f"(A omega / v - 1 = {distance:.2g}): too close to call sticking at first order; "
                             "integration decides")
        if eps > 0.3:
            notes.append(f"eps = (r + W max|f'|) / (M omega) = {eps:.3g} is not small: averaging's error "
                         f"({ERROR_CONSTANT:g} eps^2 = {ERROR_CONSTANT * eps * eps:.2g}) is large")
        return QuasiHarmonicResult(steady_sliding_stable=growth < 0, growth_rate=growth, limit_cycles=cycles,
                                   amplitude=amplitude, small_parameter=eps, valid=valid, notes=notes,
                                   estimated_error=ERROR_CONSTANT * eps * eps if valid and amplitude > 0 else 0.0,
                                   marginal=marginal,
                                   cycle_amplitude=settled.amplitude if settled is not None else math.nan)


@dataclass
class LimitCycle:
    amplitude: float  # m
    stable: bool
    decay_rate: float  # dA'/dA at the root (1/s): negative for a stable cycle
    sticks: bool  # A omega >= v: outside the quasi-harmonic description


@dataclass
class QuasiHarmonicResult:
    steady_sliding_stable: bool
    growth_rate: float  # 1/s, of small oscillations about steady sliding
    limit_cycles: list
    amplitude: float  # m, the cycle the slider settles on from small disturbances (0: steady sliding)
    small_parameter: float
    valid: bool
    notes: list = field(default_factory=list)
    estimated_error: float = 0.0  # relative, of the amplitude (ERROR_CONSTANT eps^2)
    marginal: bool = False  # the settled cycle within HAND_OVER_MARGIN eps of sticking: integration decides
    cycle_amplitude: float = math.nan  # m, the cycle eq. (20) carries the slider to, whether or not it sticks


def from_slider(system, name: str | None = None) -> QuasiHarmonic:
    """The averaged model of a :class:`~faultslip.dynamics.spring_slider.slider.SliderSystem` in its slip phase,
    M x'' + C x' + K x = W mu(V - x') + eta (V - x'): r = C, and the radiation damper eta, which acts
    on the sliding speed, joins the curve as eta u / W."""
    law = system.kinetic_law
    coefficients = getattr(law, "coefficients", None)
    if coefficients is None and getattr(law, "is_linear", False):
        coefficients = (law.mu_m, law.slope)
    extra = system.radiation_damper / system.normal_load
    friction = None
    if coefficients is not None:
        coefficients = tuple(coefficients) + (0.0,) * max(0, 2 - len(coefficients))
        coefficients = (coefficients[0], coefficients[1] + extra) + coefficients[2:]
    else:
        friction = (lambda u, curve=law: np.asarray(curve(u), dtype=float) + extra * np.asarray(u)) if extra else law
    return QuasiHarmonic(mass=system.mass, damping=system.dashpot, stiffness=system.stiffness,
                         normal_load=system.normal_load, speed=system.platform_speed, coefficients=coefficients,
                         friction=friction, name=name or system.name)


def after_break_away(system, averaged: QuasiHarmonic | None = None) -> dict:
    """Whether the slider, released from stick at break-away, sticks again (seed 003's slider).

    At break-away x' = V and K x_b + C V = W mu_s, an offset Y_b = x_b - x_eq from steady sliding
    (K x_eq = W mu(V) + eta V): the oscillation starts with amplitude A0 = sqrt(Y_b^2 + (V/omega)^2),
    at the no-stick bound or above. It escapes sticking only if eq. (20) brings the amplitude below
    V / omega within about one period (when x' next reaches V); otherwise the motion is stick-slip.
    Returns A0, the amplitude after one period and ``sticks``."""
    averaged = averaged or from_slider(system)
    mu_s = system.rate_static_friction
    if mu_s is None:
        return {"sticks": True, "reason": "static friction depends on the time of stick: stick-slip methods"}
    speed, omega = system.platform_speed, averaged.angular_frequency
    offset = (system.normal_load * (mu_s - float(averaged.curve(speed))) - system.dashpot * speed) / system.stiffness
    start = math.hypot(offset, speed / omega)
    if float(averaged.amplitude_rate(start)) >= 0 and start * omega >= speed:  # grows from the bound: sticks
        return {"sticks": True, "marginal": False, "start": start, "after_one_period": start,
                "reason": f"after break-away the averaged amplitude {start:.4g} m grows (A' >= 0) from the no-stick "
                          f"bound V / omega = {speed / omega:.4g} m"}
    # break-away is at phase phi_b = acos(V / (A0 omega)) past a velocity peak; the next peak, where x'
    # would first exceed V again, comes 2 pi - phi_b later
    phase = math.acos(min(1.0, speed / (start * omega)))
    _, amplitude = averaged.envelope(start, (2 * math.pi - phase) / omega, samples=3)
    after = float(amplitude[-1])
    sticks = after * omega >= speed
    # the peak velocity differs from A omega by O(eps) (harmonics): closer to the bound than that, the
    # first-order answer cannot be trusted either way. Measured on hand_over_map's 100 Rayleigh sliders:
    # the first-order call was wrong only within 0.072 eps of the bound; 0.15 eps is declined
    # and never below the envelope's own tolerance (rtol 1e-10): at eps = 0 (mu independent of speed, no damper)
    # the amplitude stays on the bound, a graze every period, and round-off had called it "decays to steady sliding"
    margin = max(HAND_OVER_MARGIN * averaged.small_parameter(after), ENVELOPE_RTOL * 100)
    marginal = abs(after * omega / speed - 1.0) < margin
    reason = (f"after break-away the averaged amplitude goes from {start:.4g} to {after:.4g} m by the next velocity "
              f"peak, {'above' if sticks else 'below'} the no-stick bound V / omega = {speed / omega:.4g} m"
              + (f" by less than eps = {margin:.3g}: too close to call at first order" if marginal else ""))
    return {"sticks": sticks, "marginal": marginal, "start": start, "after_one_period": after, "reason": reason}


class SticksError(SolverError):
    """Eq. (10) reached a sliding speed of zero: the slider sticks, and the quasi-harmonic model ends there."""


def _equation_10(system: QuasiHarmonic):
    """Eq. (10) about the rest position, M Y'' + r Y' + k Y = W [f(v - Y') - f(v)], as (rhs, event): the event
    is terminal where the sliding speed v - Y' falls through zero (the slider would stick)."""
    m, r, k, w, v = system.mass, system.damping, system.stiffness, system.normal_load, system.speed
    base = float(system.curve(v))

    def rhs(t, y):
        return (y[1], (w * (float(system.curve(v - y[1])) - base) - r * y[1] - k * y[0]) / m)

    def sticks(t, y):
        return v - y[1]

    sticks.terminal, sticks.direction = True, -1
    return rhs, sticks


def integrate(system: QuasiHarmonic, initial_amplitude: float, periods: float = 400.0, record_periods: float = 6.0,
              rtol: float = 1e-10, extensions: int = 4) -> dict:
    """Eq. (10) integrated directly (DOP853) about the shifted rest position, Y = X - X_0:

        M Y'' + r Y' + k Y = W [f(v - Y') - f(v)],

    from Y = 0, Y' = A0 omega. The amplitude (half the peak-to-peak Y) is measured period by period
    over the last ``record_periods`` from the dense output (4096 samples a period, peaks to ~3e-7),
    and the shared settling test (:func:`~faultslip.dynamics.shared.settling.assess_settling`) judges
    them; an unsettled run is continued by ``periods`` up to ``extensions`` times, and what remains is
    returned as ``settling_error``. Raises :class:`SolverError` naming the time where the sliding speed
    v - Y' reaches zero (the slider would stick: eq. (10) with a kinetic curve no longer describes it)."""

    omega = system.angular_frequency
    rhs, sticks = _equation_10(system)
    period = 2 * math.pi / omega
    state, start, evaluations = [0.0, initial_amplitude * omega], 0.0, 0
    for _ in range(extensions + 1):
        end = start + periods * period
        solution = _dop853(rhs, sticks, (start, end), state, rtol, rtol * max(initial_amplitude, 1e-12) * omega)
        evaluations += int(solution.nfev)
        count = int(min(record_periods, periods))
        amplitudes = _cycle_amplitudes(solution, end, period, count)
        verdict = assess_settling(amplitudes, INTEGRATION_ERROR, floor=system.speed / omega * 1e-9,
                                  names=("amplitude",), noise=PEAK_SAMPLING_ERROR)
        state, start = solution.y[:, -1], end
        if verdict.settled:
            break
    return {"amplitude": amplitudes[-1], "time": end, "function_evaluations": evaluations, "settling": verdict,
            "settling_error": float(verdict.remaining), "state": [float(value) for value in state]}


#: the periodic orbit is solved at these two rtols (DOP853): the tighter answers, their difference declares
SHOOTING_RTOLS = (1e-11, 1e-13)
#: the declared error's floor, SHOOTING_ROUND_OFF / (1 - multiplier): one map's round-off at rtol 1e-13, carried
#: through the fixed point's conditioning; on Rayleigh's curve near the onset the rtol pair's difference fell
#: below the error (2.2e-11 against 1.5e-11) where the error times (1 - multiplier) reached 1.4e-12
SHOOTING_ROUND_OFF = 1e-11
#: the map is iterated this many times from the averaged minimum before the bracket is sought: at eps 0.75 with an
#: even term the orbit lay 99 % of the averaged amplitude from it, and its multiplier 0.09 brings it within 1e-3
SHOOTING_ITERATES = 3
#: the bracket's steps from the iterated guess, as fractions of the averaged amplitude
SHOOTING_SPREADS = (0.01, 0.03, 0.1, 0.3, 0.5)
#: halvings between a trial that sticks and the last that did not, before shooting gives up on a cycle that
#: close to sticking (2^-30 of the step: below the map's own resolution at rtol 1e-11)
SHOOTING_HALVINGS = 30
#: direct integration is the fallback where shooting finds no stable cycle, up to this many periods (about 40 s at
#: 2 ms a period); beyond, the run stops and says what to use
FALLBACK_PERIODS = 20000.0
#: the fallback starts at this fraction of the averaged amplitude, inside the cycle, where growth from small
#: disturbances comes from: started on it (Y' = A omega, about v near sticking), the transient stuck in its first
#: period at 12.889 in/s on seed 002's scene (damping x0.74, load x1.76), where the cycle slides
FALLBACK_START = 0.9


def _half_cycle(rhs, sticks, start_time, state, period, rtol, atol, direction):
    """Eq. (10) from ``state`` to the next extreme of Y (Y' through zero with ``direction``): (time, state,
    evaluations); SolverError where the slider would stick first or no extreme comes within 8 periods."""

    def extreme(t, y):
        return y[1]

    extreme.terminal, extreme.direction = True, direction
    solution = _dop853(rhs, sticks, (start_time, start_time + 8 * period), state, rtol, atol, until=extreme)
    if not solution.t_events[1].size:
        raise SolverError(f"DOP853 found no turning point of the oscillation within 8 periods ({solution.message})")
    return float(solution.t_events[1][0]), solution.y_events[1][0], int(solution.nfev)


def return_map(system: QuasiHarmonic, low: float, rtol: float) -> dict:
    """Eq. (10)'s Poincare map on the section Y' = 0, Y'' > 0 (a minimum of Y): from Y = ``low`` (m, < 0) at
    rest relative to the mean, through the maximum, to the next minimum. Returns the next minimum, the maximum
    between (both located by the integrator's event search), the time taken and the evaluations."""
    rhs, sticks = _equation_10(system)
    period = 2 * math.pi / system.angular_frequency
    atol = rtol * abs(low) * system.angular_frequency * 1e-3
    middle, top, up = _half_cycle(rhs, sticks, 0.0, [low, 0.0], period, rtol, atol, -1)
    end, bottom, down = _half_cycle(rhs, sticks, middle, top, period, rtol, atol, 1)
    return {"low": float(bottom[0]), "high": float(top[0]), "time": end, "evaluations": up + down}


def cycle_offset(system: QuasiHarmonic, amplitude: float, nodes: int = 256) -> float:
    """The mean of Y over a cycle of ``amplitude`` A (m), at first order: k <Y> = W <f(v - A omega cos b) - f(v)>
    over the phase b (eq. 10 averaged). Only the curve's even part shifts it (the odd part averages out): on
    Rayleigh's curve with an even term q at eps 0.5 and A = 1.41 it is -0.5 m, 35 % of A. The trapezoidal rule
    is spectrally accurate on the periodic integrand."""
    phases = np.linspace(0.0, 2 * math.pi, nodes, endpoint=False)
    mean = float(np.mean(system.curve(system.speed - amplitude * system.angular_frequency * np.cos(phases))))
    return system.normal_load * (mean - float(system.curve(system.speed))) / system.stiffness


def shoot(system: QuasiHarmonic, amplitude_guess: float, rtol: float) -> dict:
    """The periodic orbit of eq. (10) near ``amplitude_guess`` by shooting: the fixed point of
    :func:`return_map`, ``P(y) = y``, by Brent's method on a bracket (:func:`_bracket`) from the averaged
    minimum of Y (:func:`cycle_offset` less ``amplitude_guess``) after SHOOTING_ITERATES applications of the map.

    Its cost is a few dozen periods whatever the cycle's decay rate, where settling from the guess takes
    16 / (decay rate x period) periods: 6.6e5 at 1e-4 of the onset speed on seed 002's scene. Returns the
    amplitude (half of Y_max - Y_min), the multiplier P'(y*) (|P'| < 1: stable), the periods integrated and
    the evaluations; SolverError where no bracket is found, SticksError where every start sticks."""
    from scipy.optimize import brentq  # heavy: imported where used

    evaluations = periods = 0

    def gap(low):
        nonlocal evaluations, periods
        step = return_map(system, low, rtol)
        evaluations += step["evaluations"]
        periods += 1
        return step["low"] - low

    amplitude = abs(amplitude_guess)
    guess = cycle_offset(system, amplitude) - amplitude  # the minimum of Y about its shifted mean
    known = None  # the gap at guess, where already measured
    for _ in range(SHOOTING_ITERATES):  # the map attracts to a stable orbit: where eps is large, fast and far
        try:
            guess += gap(guess)
        except SticksError:  # within 1 % of sticking the averaged minimum can lie deeper than any cycle that slides
            guess, known = _shallower_start(gap, guess, amplitude)
            break
    ends = _bracket(gap, guess, amplitude, known)
    low = brentq(gap, min(ends), max(ends), xtol=1e-15 * amplitude, rtol=4 * np.finfo(float).eps, maxiter=200)
    cycle = return_map(system, low, rtol)
    step = 1e-4 * abs(low)
    shallower = return_map(system, low + step, rtol)
    try:
        deeper = return_map(system, low - step, rtol)
        multiplier = (shallower["low"] - deeper["low"]) / (2 * step)
    except SticksError:  # the orbit grazes sticking: a one-sided difference
        deeper = {"evaluations": 0}
        multiplier = (shallower["low"] - cycle["low"]) / step
    return {"amplitude": 0.5 * (cycle["high"] - low), "low": low, "multiplier": float(multiplier),
            "cycle_time": cycle["time"], "periods": periods + 3,
            "evaluations": evaluations + sum(leg["evaluations"] for leg in (cycle, deeper, shallower))}


def _shallower_start(gap, stuck: float, amplitude: float) -> tuple[float, float]:
    """The first minimum of Y above ``stuck`` (a start whose cycle sticks) by SHOOTING_SPREADS of the amplitude
    whose cycle slides, and its gap; SticksError where none within 50 % does."""
    for spread in SHOOTING_SPREADS:
        trial = stuck + spread * amplitude
        if trial >= 0:
            break
        try:
            return trial, gap(trial)
        except SticksError:
            continue
    raise SticksError(f"every start within 50 % of the averaged amplitude {amplitude:.4g} m above a cycle that "
                      "sticks sticks too")


def _bracket(gap, guess: float, amplitude: float, known: float | None = None) -> tuple[float, float]:
    """Two minima of Y about the return map's fixed point: ``gap`` (P(y) - y) changes sign between them.

    A stable fixed point has P' < 1, so the gap falls through zero there: its sign at ``guess`` says which way
    the orbit lies, and the search steps that way by SHOOTING_SPREADS of the amplitude. A deeper trial that
    sticks bounds the orbit (a deeper start swings wider): the step is halved between it and the last trial that
    did not, up to SHOOTING_HALVINGS times. SolverError where no sign change is found: within 50 % of the
    amplitude, or between the guess and the sticking bound (the orbit, if any, is that close to sticking).
    ``known``: the gap at ``guess`` where already measured."""
    last, last_gap = guess, gap(guess) if known is None else known
    if last_gap == 0:
        return guess, guess
    toward = math.copysign(1.0, last_gap)  # gap > 0: P(y) > y, the orbit's minimum lies above y (shallower)
    for spread in SHOOTING_SPREADS:
        trial = guess + toward * spread * amplitude
        if trial >= 0:
            break
        try:
            trial_gap = gap(trial)
        except SticksError:
            return _bracket_below_sticking(gap, last, last_gap, trial)
        if trial_gap * last_gap <= 0:
            return last, trial
        last, last_gap = trial, trial_gap
    raise SolverError(f"shooting found no periodic orbit within 50 % of the averaged amplitude {amplitude:.4g} m: "
                      f"the return map carries every start there toward {'smaller' if toward > 0 else 'larger'} "
                      "cycles (an unstable cycle repels them, or the stable one lies further)")


def _bracket_below_sticking(gap, last: float, last_gap: float, stuck: float) -> tuple[float, float]:
    """Halve the interval between ``last`` (its gap ``last_gap`` points deeper) and ``stuck`` (a start that sticks)
    until a trial's gap changes sign: the bracket for :func:`_bracket`."""
    for _ in range(SHOOTING_HALVINGS):
        trial = 0.5 * (last + stuck)
        try:
            trial_gap = gap(trial)
        except SticksError:
            stuck = trial
            continue
        if trial_gap * last_gap <= 0:
            return last, trial
        last, last_gap = trial, trial_gap
    raise SolverError(f"shooting found no periodic orbit short of sticking: starts deeper than "
                      f"{-stuck:.6g} m below the mean stick, and the map still points deeper at {-last:.6g} m")


def periodic_orbit(system: QuasiHarmonic, amplitude_guess: float) -> dict:
    """The stable periodic orbit of eq. (10) near ``amplitude_guess`` (m) by :func:`shoot` at the two
    SHOOTING_RTOLS: the tighter's amplitude, and as its declared error the two answers' relative difference
    (at least SHOOTING_ROUND_OFF / (1 - multiplier)). Near the onset speed the map's multiplier tends to 1 and
    the fixed point's conditioning 1 / (1 - P') grows: both grow with it, and say so. SolverError where the orbit
    found is unstable (|P'| >= 1: not the one the slider settles on)."""
    coarse, fine = (shoot(system, amplitude_guess, rtol) for rtol in SHOOTING_RTOLS)
    if not abs(fine["multiplier"]) < 1:
        raise SolverError(f"the periodic orbit shooting found ({fine['amplitude']:.4g} m) is unstable (multiplier "
                          f"{fine['multiplier']:.6g}): the slider does not settle on it")
    error = max(abs(coarse["amplitude"] / fine["amplitude"] - 1), SHOOTING_ROUND_OFF / (1 - fine["multiplier"]))
    return {**fine, "estimated_relative_error": error, "periods": coarse["periods"] + fine["periods"],
            "evaluations": coarse["evaluations"] + fine["evaluations"]}


def _cycle_amplitudes(solution, end: float, period: float, count: int) -> list:
    """Half the peak-to-peak Y of each of the last ``count`` whole cycles before ``end``, a cycle running from
    one minimum of Y to the next (Y' rising through zero), sampled 4096 times a nominal period 2 pi / omega.

    Far from harmonic (eps of order 1) a cycle lasts longer than 2 pi / omega, and a window of that length
    misses its peak: up to four nominal periods a cycle are searched. Where fewer cycles complete, those found
    are returned (the settling test then judges fewer)."""
    span = min(end - float(solution.t[0]), 4.0 * (count + 1) * period)
    times = np.linspace(end - span, end, int(4096 * span / period) + 1)
    displacement, velocity = solution.sol(times)
    minima = np.flatnonzero((velocity[:-1] < 0) & (velocity[1:] >= 0))[-(count + 1):]
    if minima.size < 2:  # not one whole cycle in the span: the span's own swing
        return [0.5 * float(displacement.max() - displacement.min())]
    return [0.5 * float(displacement[a:b + 1].max() - displacement[a:b + 1].min())
            for a, b in zip(minima[:-1], minima[1:])]


def _dop853(rhs, sticks, span, state, rtol, atol, times=None, until=None):
    """Eq. (10) by DOP853 with dense output, up to the terminal event ``until`` where one is given (its times and
    states are the solution's second event); refused where the slider would stick or the solver fails.

    The sliding speed v - Y' is least where Y' peaks (Y'' falls through zero). A cycle that grazes sticking dips
    below zero there for a fraction of one step, and the sign test at step ends misses it: seed 002's scene at
    12.886 in/s (damping x0.74, load x1.76) dips to -2.8e-4 m/s, unseen at rtol 1e-11, and was called sliding.
    Each peak of Y' is therefore located by the event search and its sliding speed checked."""
    from scipy.integrate import solve_ivp  # heavy: imported where used

    def peak(t, y):
        return rhs(t, y)[1]

    peak.direction = -1
    events = [sticks, peak] if until is None else [sticks, until, peak]
    solution = solve_ivp(rhs, span, state, method="DOP853", rtol=rtol, atol=atol, t_eval=times, events=events,
                         dense_output=until is None)
    dips = [t for t, y in zip(solution.t_events[-1], solution.y_events[-1]) if sticks(t, y) < 0]
    if solution.t_events[0].size or dips:
        time = min([*solution.t_events[0][:1], *dips[:1]])
        raise SticksError(f"the sliding speed reaches zero at t = {time:.6g} s: the slider sticks, "
                          "and the quasi-harmonic model ends there; use the stick-slip methods (faultslip simulate "
                          "on a seed-003 scene)")
    if not solution.success:
        raise SolverError(f"DOP853 failed on the quasi-harmonic slider: {solution.message}")
    return solution


#: Relative error of a peak read from 4096 samples a period: (pi / 4096)^2 / 2 ~ 3e-7.
PEAK_SAMPLING_ERROR = 3e-7


#: a simulation runs at most this many periods by default (128,000 samples of each series)
SIMULATED_PERIODS = 2000.0
#: a simulated time series is at most this many samples (about 48 MB of float64 over three series)
MAX_SERIES_SAMPLES = 2_000_000


def simulate_vibration(system: QuasiHarmonic, periods: float | None = None, samples_per_period: int = 64,
                       rtol: float = 1e-10) -> dict:
    """Eq. (10) integrated (DOP853) from a small disturbance, beside eq. (20)'s envelope from the same start.

    Where steady sliding is unstable the run starts at 5 % of the settled amplitude and shows the growth
    to the limit cycle; where it is stable, at half the no-stick bound v / omega, and shows the decay.
    ``periods`` defaults to the time the cycle takes to settle (:func:`settle_periods`). Returns time (s),
    displacement Y about the rest position (m), its velocity (m/s), the averaged envelope A(t) (m), the
    amplitude over the last two periods, the averaged one, and the evaluations. Raises
    :class:`SolverError` where the sliding speed reaches zero (the slider sticks)."""

    result = system.analyse()
    if not result.valid:
        raise SolverError(f"{system.name}: {result.notes[0] if result.notes else 'the slider sticks'}")
    omega = system.angular_frequency
    period = 2 * math.pi / omega
    periods = float(periods if periods is not None else simulation_periods(system, result))
    samples = int(periods * samples_per_period) + 1
    if not (0 < periods and 2 <= samples <= MAX_SERIES_SAMPLES):
        raise InputError(f"{periods:g} periods at {samples_per_period} samples each is outside 2 to "
                         f"{MAX_SERIES_SAMPLES:,} samples")
    start = 0.05 * result.amplitude if result.amplitude > 0 else 0.5 * system.speed / omega
    rhs, sticks = _equation_10(system)
    times = np.linspace(0.0, periods * period, samples)
    solution = _dop853(rhs, sticks, (0.0, times[-1]), [0.0, start * omega], rtol, rtol * max(start, 1e-12) * omega,
                       times)
    _, envelope = system.envelope(start, times[-1], samples=samples)
    # the peaks from the dense output, 4096 samples a period (to ~3e-7), not from the coarser series
    tail = solution.sol(np.linspace(times[-1] - 2 * period, times[-1], 8193))[0]
    # whether the series ends on its cycle: near the onset speed the growth takes ln 20 / sigma (2.5e5 periods at
    # 13.549 in/s on seed 002's scene), and the last periods' swing is the transient's, not the cycle's
    settling = assess_settling(_cycle_amplitudes(solution, times[-1], period, int(min(6, periods))),
                               INTEGRATION_ERROR, floor=system.speed / omega * 1e-9, names=("amplitude",),
                               noise=PEAK_SAMPLING_ERROR)
    return {"time": times, "displacement": solution.y[0], "velocity": solution.y[1], "envelope": envelope,
            "amplitude": 0.5 * float(tail.max() - tail.min()), "averaged_amplitude": result.amplitude,
            "initial_amplitude": start, "function_evaluations": int(solution.nfev), "system": system,
            "settling": settling}


def vibration_report(run: dict):
    """:func:`simulate_vibration`'s run as a :class:`~faultslip.io.report.Report` (``faultslip simulate``)."""
    report = Report(f"faultslip quasi-harmonic simulation (seed 002 eq. 10): {run['system'].name}")
    report.add("duration", float(run["time"][-1]), "s").add("samples", int(run["time"].size))
    report.add("initial_amplitude", run["initial_amplitude"], "m", also=("in",), label="disturbance at t = 0")
    report.add("amplitude", run["amplitude"], "m", also=("in",), label="amplitude over the last two periods")
    report.add("averaged_amplitude", run["averaged_amplitude"], "m", also=("in",), label="averaging (eq. 20)")
    settling = run["settling"]
    report.add("settled", bool(settling.settled), label="the series ends on its cycle")
    if run["averaged_amplitude"] > 0 and settling.settled:
        report.add("averaging_relative_error", abs(run["averaged_amplitude"] / run["amplitude"] - 1),
                   label="|averaged / integrated - 1|")
    elif not settling.settled:
        report.note(f"the series ends before its cycle has settled ({settling.reason}): its last swing is the "
                    "transient's, and averaging is not compared with it; the settled amplitude is faultslip run "
                    "SCENE --method quasi_harmonic_integration (the periodic orbit by shooting)")
    report.add("function_evaluations", run["function_evaluations"])
    return report


def vibration_dataset(run: dict):
    """:func:`simulate_vibration`'s run as a CF dataset."""
    import xarray as xr  # heavy: imported where used

    system = run["system"]
    dims = ("time",)
    return xr.Dataset(
        {"displacement": (dims, run["displacement"], {"units": "m", "long_name": "displacement Y about the rest position"}),
         "velocity": (dims, run["velocity"], {"units": "m/s", "long_name": "velocity Y'"}),
         "envelope": (dims, run["envelope"], {"units": "m", "long_name": "averaged amplitude A(t), seed 002 eq. (20)"})},
        coords={"time": (dims, run["time"], ELAPSED_TIME_ATTRS)},
        attrs={"title": f"faultslip quasi-harmonic vibration (seed 002 eq. 10): {system.name}", "Conventions": "CF-1.8",
               "mass_kg": system.mass, "stiffness_N_per_m": system.stiffness, "damping_N_s_per_m": system.damping,
               "normal_load_N": system.normal_load, "speed_m_per_s": system.speed,
               "settled_amplitude_m": run["amplitude"], "averaged_amplitude_m": run["averaged_amplitude"],
               "method": "DOP853 at rtol 1e-10 (eq. 10); envelope by eq. (20)"})


def estimated_error(system: QuasiHarmonic, amplitude: float) -> float:
    """The declared relative error of an averaged limit-cycle amplitude: ERROR_CONSTANT eps^2."""
    return ERROR_CONSTANT * system.small_parameter(amplitude) ** 2


@takes_units(speeds="speed")
def amplitude_against_speed(system: QuasiHarmonic, speeds) -> dict:
    """The settled amplitude at each driving speed (seed 002 Figs. 10-11): arrays of amplitude (m; 0 where
    steady sliding is stable, NaN where the oscillation would stick), steady sliding's growth rate, the small
    parameter, and where the first-order sticking call is marginal (within HAND_OVER_MARGIN eps: only
    integration can say whether the slider sticks there).

    Parameters
    ----------
    system : QuasiHarmonic
        The averaged slider.
    speeds : array_like
        Driving speeds (m/s).

    Returns
    -------
    dict
        ``speed`` (m/s), ``amplitude`` (m), ``growth_rate`` (1/s), ``small_parameter`` (dimensionless),
        ``sticks`` (bool, the first-order call) and ``marginal`` (bool), one value per speed.
    """
    speeds = np.asarray(speeds, dtype=float)
    amplitude, growth, eps, sticks, marginal = (np.empty(speeds.size) for _ in range(5))
    for i, speed in enumerate(speeds):
        at = QuasiHarmonic(system.mass, system.damping, system.stiffness, system.normal_load, float(speed),
                           system.coefficients, system.friction, system.name)
        result = at.analyse()
        amplitude[i] = result.amplitude
        growth[i], eps[i], sticks[i] = result.growth_rate, result.small_parameter, not result.valid
        marginal[i] = result.marginal
    return {"speed": speeds, "amplitude": amplitude, "growth_rate": growth, "small_parameter": eps,
            "sticks": sticks.astype(bool), "marginal": marginal.astype(bool)}


def report(system: QuasiHarmonic, result: QuasiHarmonicResult, sweep: dict | None = None,
           settled: dict | None = None):
    """The analysis as a :class:`~faultslip.io.report.Report` (``faultslip quasi-harmonic``); ``settled`` is
    :func:`settled_amplitude`'s answer, whose amplitude and method replace the averaged ones."""
    omega = system.angular_frequency
    r = Report(f"faultslip quasi-harmonic vibration (seed 002, averaging): {system.name}")
    r.add("mass", system.mass, "kg", also=("lb",)).add("stiffness", system.stiffness, "N/m", also=("lbf/in",))
    r.add("damping", system.damping, "N*s/m", also=("lbf*s/in",)).add("normal_load", system.normal_load, "N",
                                                                     also=("lbf",))
    r.add("speed", system.speed, "m/s", also=("in/s",), label="driving speed v")
    r.add("natural_frequency", omega / (2 * math.pi), "Hz", label="omega / 2 pi")
    r.add("friction_slope", float(system.slope(system.speed)), "s/m", label="f'(v)")
    r.add("growth_rate", result.growth_rate, "1/s", label="small oscillations grow at -(r + W f'(v)) / 2M")
    regime = ("steady_sliding" if result.valid and result.amplitude == 0 else
              "quasi_harmonic" if result.valid or settled else "stick_slip")
    r.add("regime", regime)
    if result.valid or settled:
        amplitude = settled["amplitude"] if settled else result.amplitude
        r.add("amplitude", amplitude, "m", also=("in",), label="limit-cycle amplitude A")
        r.add("peak_speed", amplitude * omega, "m/s", also=("in/s",), label="A omega (must stay below v)")
        r.add("method", method_name(settled["method"] if settled else "averaging"))  # what --method takes
        if settled:
            r.add("method_reason", settled["reason"], label="why this method")
        r.add("estimated_relative_error", settled["estimated_relative_error"] if settled else result.estimated_error,
              label="estimated relative error")
    r.add("small_parameter", result.small_parameter, label="eps = (r + W max|f'|) / (M omega)")
    r.add("limit_cycles", [{"amplitude": {"value": float(c.amplitude), "units": "m"}, "stable": bool(c.stable),
                            "sticks": bool(c.sticks)} for c in result.limit_cycles])
    if sweep is not None:
        r.add("amplitude_against_speed", [
            {"speed": {"value": float(v), "units": "m/s"},
             "amplitude": {"value": None if math.isnan(a) else float(a), "units": "m"}, "sticks": bool(s),
             "marginal": bool(m)}
            for v, a, s, m in zip(sweep["speed"], sweep["amplitude"], sweep["sticks"], sweep["marginal"])],
              in_text=False)  # the text shows it as amplitude_table
    for note in result.notes:
        r.note(note)
    r.note("method: Kryloff-Bogoliuboff averaging of seed 002 eq. (20); polynomial curves in closed form "
           "(weights 1, 3/4, 5/8, 35/64, ...)")
    return r


def amplitude_table(sweep: dict) -> str:
    """The amplitude against driving speed as a Markdown table (in the seed's inches); a marginal call says so."""
    inch = 0.0254
    lines = ["| driving speed (in/s) | amplitude (in) | regime |", "| --- | --- | --- |"]
    for speed, amplitude, sticks, marginal in zip(sweep["speed"], sweep["amplitude"], sweep["sticks"],
                                                  sweep["marginal"]):
        regime = "stick-slip" if sticks else "steady sliding" if amplitude == 0 else "quasi-harmonic"
        if marginal:
            regime += f" at first order, within {HAND_OVER_MARGIN:g} eps of sticking: integration decides"
        shown = "" if sticks else f"{amplitude / inch:.4g}"
        lines.append(f"| {speed / inch:.4g} | {shown} | {regime} |")
    return "\n".join(lines)


#: the two ways to the settled amplitude, with their declared error and cost (``faultslip methods``)
METHODS = {
    "averaging": {"name": "quasi_harmonic_averaging",
                  "friction_laws": "any friction-velocity curve (polynomials in closed form, others by quadrature); "
                                   "no sticking",
                  "domain": "small eps = (r + W max|f'|) / (M omega); A omega < v (else stick-slip: hand over)",
                  "cost_model": "a root search on the amplitude equation: about 1e-3 s",
                  "declared_error": "0.1 eps^2 relative (measured 0.010-0.049 eps^2 against integration)"},
    "integration": {"name": "quasi_harmonic_integration",
                    "friction_laws": "any friction-velocity curve; stops where the slider would stick",
                    "domain": "any eps, up to the onset (Hopf) speed: the stable periodic orbit by shooting "
                              "(Brent's method on the Poincare map at Y' = 0), whatever its decay rate",
                    "cost_model": "DOP853 at rtol 1e-11 and 1e-13 over 44-70 periods: about 0.15 s; where shooting "
                                  "finds no stable orbit, integrated until the cycle settles (16 / its decay rate "
                                  f"periods, refused beyond {FALLBACK_PERIODS:g})",
                    "declared_error": "the two rtols' difference, at least 1e-11 / (1 - multiplier) (both grow near "
                                      "the onset, as the multiplier tends to 1); settling's 1e-6 on the fallback"},
}
INTEGRATION_ERROR = 1e-6
#: a method by the name ``faultslip methods`` lists (what a report says) or by its short name
METHOD_ALIASES = {"auto": "auto", **{short: short for short in METHODS},
                  **{entry["name"]: short for short, entry in METHODS.items()}}


def method_name(method: str) -> str:
    """The listed name of a method given by either name (``averaging`` -> ``quasi_harmonic_averaging``)."""
    short = METHOD_ALIASES[method]
    return METHODS[short]["name"] if short in METHODS else short


def _short_method(method) -> str:
    if method not in METHOD_ALIASES:
        raise InputError(f"method must be auto, quasi_harmonic_averaging or quasi_harmonic_integration (averaging "
                         f"or integration for short), got {method!r}")
    return METHOD_ALIASES[method]


def settle_periods(system: QuasiHarmonic, result: QuasiHarmonicResult) -> float:
    """Periods for direct integration from the averaged amplitude to settle on the true cycle: 16 / (its
    decay rate x period), e^-16 of the start's offset, at least 60."""
    cycle = next((c for c in result.limit_cycles if c.stable and abs(c.amplitude - result.amplitude) == 0), None)
    rate = abs(cycle.decay_rate) if cycle is not None else abs(result.growth_rate)
    period = 2 * math.pi / system.angular_frequency
    return max(60.0, 16.0 / max(rate * period, 1e-12))


def simulation_periods(system: QuasiHarmonic, result: QuasiHarmonicResult) -> float:
    """Periods a simulation runs by default: where steady sliding is unstable, the growth from its start at 5 % of
    the cycle, ln 20 / (sigma x period), then :func:`settle_periods`; where it is stable, the decay alone; at
    most SIMULATED_PERIODS (the series' size). 594 periods had left seed 002's scene 4.5e-5 short of its cycle."""
    period = 2 * math.pi / system.angular_frequency
    growth = math.log(20.0) / (result.growth_rate * period) if result.amplitude > 0 and result.growth_rate > 0 else 0
    return min(growth + settle_periods(system, result), SIMULATED_PERIODS)


def analyse_and_settle(system: QuasiHarmonic, method: str = "auto", tolerance: float = 1e-3):
    """(analysis, settled): :meth:`QuasiHarmonic.analyse` and, where the slider vibrates or the call is
    marginal, :func:`settled_amplitude`. A marginal cycle that sticks when integrated comes back as not
    valid (stick-slip), with the integration's finding in its notes; ``settled`` is then None."""
    method = _short_method(method)
    analysis = system.analyse()
    if not (analysis.valid or analysis.marginal):
        return analysis, None
    try:
        return analysis, settled_amplitude(system, method, tolerance)
    except SticksError as error:  # only a cycle integrated to sticking decides stick-slip; other failures propagate
        if not analysis.marginal or method == "averaging":
            raise
        return replace(analysis, valid=False, amplitude=math.nan, estimated_error=0.0,
                       notes=[f"integrated, the slider sticks: {error}", *analysis.notes]), None


def settled_amplitude(system: QuasiHarmonic, method: str = "auto", tolerance: float = 1e-3) -> dict:
    """The amplitude the slider settles on from small disturbances, by ``method``: averaging, integration, or
    auto (averaging where its declared error ERROR_CONSTANT eps^2 meets ``tolerance`` and the cycle is not
    within HAND_OVER_MARGIN eps of sticking, else integration, which costs seconds). Returns the amplitude (m),
    the method, its declared error and why it was chosen; raises :class:`SolverError` where the oscillation
    sticks (the stick-slip methods apply there), or where averaging is asked for a cycle too close to call."""
    method = _short_method(method)
    tolerance = ranges.check_tolerance(tolerance)
    result = system.analyse()
    if not result.valid and not result.marginal:
        raise SolverError(f"{system.name}: {result.notes[0] if result.notes else 'the slider sticks'}")
    if result.marginal:
        if method == "averaging":
            raise SolverError(f"{system.name}: averaging cannot say whether this cycle sticks (its peak speed is "
                              f"within {HAND_OVER_MARGIN:g} eps of the driving speed); use the integration "
                              "(--method quasi_harmonic_integration)")
        method, reason = "integration", (f"the cycle's peak speed is within {HAND_OVER_MARGIN:g} eps of the driving "
                                         "speed, too close to call sticking at first order: integrated directly")
        result = replace(result, amplitude=result.cycle_amplitude)
    elif method == "auto":
        cheap = result.estimated_error <= tolerance
        method = "averaging" if cheap else "integration"
        reason = (f"averaging's declared error {result.estimated_error:.2g} meets the tolerance {tolerance:g}" if cheap
                  else f"averaging's declared error {result.estimated_error:.2g} exceeds the tolerance {tolerance:g} "
                       f"(eps = {result.small_parameter:.3g}): integrated directly")
    else:
        reason = "requested"
    if method == "averaging" or result.amplitude == 0.0:
        return {"amplitude": result.amplitude, "method": "averaging", "estimated_relative_error":
                result.estimated_error, "reason": reason if method == "averaging" else "steady sliding"}
    try:
        orbit = periodic_orbit(system, result.amplitude)
    except SolverError as failure:
        return _settled_by_integration(system, result, reason, failure)
    return {"amplitude": orbit["amplitude"], "method": "integration",
            "estimated_relative_error": orbit["estimated_relative_error"],
            "reason": f"{reason}: the periodic orbit by shooting (multiplier 1 - {1 - orbit['multiplier']:.3g})",
            "function_evaluations": orbit["evaluations"]}


def _settled_by_integration(system: QuasiHarmonic, result: QuasiHarmonicResult, reason: str,
                            failure: SolverError) -> dict:
    """Where shooting found no stable orbit: eq. (10) integrated from inside the cycle (FALLBACK_START of the
    averaged amplitude; steady sliding is unstable here, so the slider grows to its smallest stable cycle) until it
    settles, up to FALLBACK_PERIODS; beyond, SolverError naming both failures and what to use instead."""
    periods = settle_periods(system, result)
    if periods > FALLBACK_PERIODS:
        raise SolverError(f"{system.name}: shooting failed ({failure}), and integrating until the cycle settles "
                          f"would take {periods:.3g} periods; use --method quasi_harmonic_averaging (declared "
                          f"error {result.estimated_error:.2g}) or faultslip simulate") from failure
    run = integrate(system, FALLBACK_START * result.amplitude, periods=periods)
    error = settled_error(INTEGRATION_ERROR, run["settling_error"])
    reason = (f"{reason}: shooting failed ({failure}), integrated from {FALLBACK_START:g} of the averaged amplitude "
              "until the cycle settles")
    if not run["settling"].settled:
        reason = f"{reason}; {run['settling'].reason}"
    return {"amplitude": run["amplitude"], "method": "integration", "estimated_relative_error": error,
            "reason": reason, "function_evaluations": run["function_evaluations"]}


def averaging_error(system: QuasiHarmonic) -> dict:
    """Averaging's error on one slider, measured against eq. (10)'s periodic orbit (:func:`settled_amplitude` by
    integration: shooting, whose extremes are located, not sampled; settling from the averaged amplitude had
    read peaks to 3e-7 only, and took 4x the time over the error chart's rows).

    Returns
    -------
    dict
        ``small_parameter`` eps over the cycle, ``error`` |A_integrated / A_averaged - 1| and ``declared``,
        averaging's declared ERROR_CONSTANT eps^2.

    Raises
    ------
    SolverError
        Where there is no cycle to measure: the slider sticks, or steady sliding is stable.
    """
    result = system.analyse()
    if not result.valid or result.amplitude == 0.0:
        raise SolverError(f"{system.name} at {system.speed:.4g} m/s has no quasi-harmonic cycle to measure "
                          f"averaging's error on ({'it sticks' if not result.valid else 'steady sliding is stable'})")
    settled = settled_amplitude(system, "integration")
    return {"small_parameter": system.small_parameter(result.amplitude),
            "error": abs(settled["amplitude"] / result.amplitude - 1), "declared": result.estimated_error}


def quasi_harmonic_speeds(system: QuasiHarmonic, count: int = 5, search: int = 400) -> np.ndarray:
    """Up to ``count`` driving speeds at which ``system`` vibrates without sticking, found on ``search`` speeds
    from 0 to 2.5 times its own and taken from the 10th to the 80th percentile of those (integration slows
    without bound towards the onset, where the cycle's decay rate vanishes); each is a speed the analysis
    found vibrating, so a band with gaps gives no speed in a gap. Empty if it never vibrates."""
    grid = np.linspace(0.0, 2.5 * system.speed, search + 1)[1:]
    sweep = amplitude_against_speed(system, grid)
    vibrating = grid[(sweep["amplitude"] > 0) & ~sweep["sticks"]]
    if vibrating.size < 2:
        return np.empty(0)
    return np.unique(vibrating[np.round(np.linspace(0.1, 0.8, count) * (vibrating.size - 1)).astype(int)])


def error_against_eps(eps_values=(0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.4), even_terms=(0.0, 1.0),
                      scene: QuasiHarmonic | None = None) -> dict:
    """Averaging's measured error against direct integration over the small parameter, for Rayleigh's curve
    f = -e (u - v) + q e (u - v)^2 + e (u - v)^3 / 3 (M = k = W = 1, v = 10, limit cycle A = 2) with even
    terms q, and for a ``scene``'s slider at the speeds of :func:`quasi_harmonic_speeds`. Returns per row the
    ``curve`` it belongs to, eps (the small parameter over the cycle), the measured and the declared errors."""
    rows = []
    for quadratic in even_terms:
        for value in eps_values:
            p = np.polynomial.Polynomial([-10.0, 1.0])
            curve = -value * p + quadratic * value * p ** 2 + value / 3 * p ** 3
            system = QuasiHarmonic(1.0, 0.0, 1.0, 1.0, 10.0, coefficients=tuple(curve.coef))
            rows.append((f"Rayleigh, even term q = {quadratic:g}", averaging_error(system)))
    if scene is not None:
        rows += [(scene.name, averaging_error(replace(scene, speed=float(speed))))
                 for speed in quasi_harmonic_speeds(scene)]
    return {"curve": np.array([label for label, _ in rows]),
            **{key: np.array([row[key] for _, row in rows]) for key in ("small_parameter", "error", "declared")}}


def error_over_eps_squared(table: dict) -> dict:
    """Per curve of :func:`error_against_eps`: the measured error over eps^2, lowest and highest, and the
    range of eps it was measured over (what ERROR_CONSTANT bounds)."""
    summary = {}
    for curve in dict.fromkeys(table["curve"].tolist()):
        chosen = table["curve"] == curve
        ratio, eps = table["error"][chosen] / table["small_parameter"][chosen] ** 2, table["small_parameter"][chosen]
        summary[curve] = {"lowest": float(ratio.min()), "highest": float(ratio.max()),
                          "small_parameter": [float(eps.min()), float(eps.max())]}
    return summary


def hand_over_map(eps_values=(0.003, 0.01, 0.03, 0.1, 0.3), excess_values=(0.0, 0.1, 0.3, 1.0, 2.0),
                  speeds=(1.8, 2.05, 2.3, 3.0)):
    """Where averaging hands over, checked against the event-driven simulation of seed 003's slider.

    Rayleigh sliders (M = K = W = 1, f = 4 - e (u - V) + e (u - V)^3 / 3, limit cycle A = 2) with
    static friction f(V) + excess: for each (e, excess, V), whether averaging predicts a re-stick
    after break-away (:func:`after_break_away`) and whether the simulation (DOP853, rtol 1e-9, 3
    cycles) finds stick-slip; ``marginal`` marks where averaging declines to call it (within eps of the
    bound). Returns arrays over the flattened grid."""

    rows = []
    for speed in speeds:
        for value in eps_values:
            for excess in excess_values:
                p = np.polynomial.Polynomial([-speed, 1.0])
                curve = 4.0 - value * p + value / 3 * p ** 3
                system = SliderSystem(mass=1.0, stiffness=1.0, normal_load=1.0, platform_speed=speed,
                                      static_law=ConstantStatic(float(curve(speed)) + excess),
                                      kinetic_law=PolynomialKinetic(tuple(curve.coef)), name="rayleigh slider")
                verdict = after_break_away(system)
                predicted = -1 if verdict["marginal"] else int(verdict["sticks"])
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    regime = simulate(system, cycles=3, slip_solver="DOP853", rtol=1e-9).attrs["regime"]
                rows.append((speed, value, excess, predicted, regime == "stick_slip"))
    table = np.array(rows, dtype=float)
    return {"speed": table[:, 0], "eps": table[:, 1], "excess": table[:, 2], "predicted_sticks": table[:, 3] > 0,
            "marginal": table[:, 3] < 0, "simulated_sticks": table[:, 4] > 0}


#: regime codes of :func:`regions`
REGION_CODES = {"steady_sliding": 0, "quasi_harmonic": 1, "stick_slip": 2, "marginal": 3}


def regions(system: QuasiHarmonic, speeds, dampings) -> dict:
    """The (v, r) plane of seed 002's Figs. 10-11: at each driving speed and damping coefficient, steady
    sliding, a quasi-harmonic cycle (its amplitude) or stick-slip (the cycle would reach A omega = v), or
    marginal where the cycle's A omega is within HAND_OVER_MARGIN eps of v and the first order cannot call it.
    Returns ``regime`` codes (:data:`REGION_CODES`) and ``amplitude`` (m, NaN where it sticks) on
    (damping, speed)."""
    speeds, dampings = np.asarray(speeds, dtype=float), np.asarray(dampings, dtype=float)
    regime = np.empty((dampings.size, speeds.size), dtype=np.int8)
    amplitude = np.empty((dampings.size, speeds.size))
    for i, damping in enumerate(dampings):
        swept = amplitude_against_speed(QuasiHarmonic(system.mass, float(damping), system.stiffness,
                                                      system.normal_load, system.speed, system.coefficients,
                                                      system.friction, system.name), speeds)
        amplitude[i] = swept["amplitude"]
        # the first condition that holds names the cell: a marginal call before any the first order makes
        regime[i] = np.select([swept["marginal"], swept["sticks"], swept["amplitude"] > 0],
                              [REGION_CODES["marginal"], REGION_CODES["stick_slip"], REGION_CODES["quasi_harmonic"]],
                              default=REGION_CODES["steady_sliding"])
    return {"speed": speeds, "damping": dampings, "regime": regime, "amplitude": amplitude}
