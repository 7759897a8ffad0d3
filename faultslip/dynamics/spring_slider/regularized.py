"""The naive baseline: friction regularised across zero sliding speed and integrated straight through.

Most codes avoid the stick/slip switch by smoothing friction through u = 0:

.. math:: \\mu_w(u) = \\tanh(u/w)\\,\\bigl[\\mu_k(|u|) + \\Delta'\\,e^{-|u|/(k w)}\\bigr],

odd in the sliding speed u = V - x'. The tanh replaces sticking by a steep viscous branch of
width w; the second term is a Stribeck peak of width k w (k = 10) whose height :math:`\\Delta'`
is calibrated so that the maximum of :math:`\\mu_w` equals the static limit mu_s. As w -> 0 it
converges to the discontinuous law, but:

* it never truly sticks: during "stick" the slider creeps at a sliding speed of order w, so the
  spring loads at K(V - u) and the cycle is distorted unless w << V;
* it is stiff: the viscous branch has a time constant ~ M w / (W mu_s), and the integrator must
  step through every stick phase. At fault scale (V ~ 1e-9 m/s, stick ~ 4e9 s) that is hopeless
  for explicit methods.

This module exists to be measured against (``faultslip bench`` and ``faultslip stability``); the
project's own methods are the closed form, the exact cycle and the event-driven simulator.
"""

from __future__ import annotations

import numpy as np

from faultslip.errors import SolverError
from faultslip.dynamics.spring_slider.simulate import _BudgetExceeded
from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle

STRIBECK_FACTOR = 10.0


class RegularizedFriction:
    """The odd, smooth friction curve :math:`\\mu_w(u)` of a slider (see module docstring)."""

    def __init__(self, system, width: float, stribeck_factor: float = STRIBECK_FACTOR):
        if not width > 0:
            raise SolverError(f"regularised friction: width must be positive, got {width}")
        excess = system.static_excess
        if excess is None:
            raise SolverError("regularised friction: the time-of-stick law has no fixed static limit; "
                              "use the event-driven simulator")
        if getattr(system.kinetic_law, "holds_peak", False):
            raise SolverError("regularised friction: the kinetic law remembers the slip's peak speed (surfaces held "
                              "apart through the deceleration), which a smooth mu(u) cannot; use the event-driven "
                              "simulator")
        self.kinetic = system.kinetic_law
        self.width = width
        self.decay = stribeck_factor * width
        self.mu_s = system.mu_m + excess
        self.peak_height = self._calibrate(excess)

    def _shape(self, u, height):
        u = np.abs(u)
        return np.tanh(u / self.width) * (self.kinetic(u) + height * np.exp(-u / self.decay))

    def _peak(self, height):
        from scipy.optimize import minimize_scalar  # heavy: imported where used
        result = minimize_scalar(lambda x: -self._shape(x * self.width, height), bounds=(0.0, 20 * STRIBECK_FACTOR),
                                 method="bounded", options={"xatol": 1e-12})
        return -result.fun

    def _calibrate(self, excess):
        from scipy.optimize import brentq  # heavy: imported where used
        if excess <= 0:
            return 0.0
        return brentq(lambda h: self._peak(h) - self.mu_s, 0.0, 50.0 * excess + 1.0, xtol=1e-14, rtol=1e-13)

    def __call__(self, u):
        return np.sign(u) * self._shape(u, self.peak_height)

    def derivative(self, u, step=None):
        h = 1e-6 * self.width if step is None else step
        return (self(u + h) - self(u - h)) / (2 * h)


def simulate_regularized(system, cycles: int, width: float, solver: str = "Radau", rtol: float = 1e-8,
                         atol: float | None = None, max_evaluations: int = 10**6, duration: float | None = None):
    """Integrate the regularised model from rest through ``cycles`` stick-slip cycles.

    Break-aways are detected as downward crossings of x' = V/2; the amplitude of each cycle is
    the peak-to-peak displacement between break-aways. Returns a dict with ``event_time``,
    ``amplitude``, ``period``, ``creep`` (smallest sliding speed over V inside stick phases:
    never zero), ``evaluations`` and ``regime``. Raises :class:`SolverError` when the budget of
    right-hand-side evaluations is exhausted or the step size collapses.
    """
    from scipy.integrate import solve_ivp  # heavy: imported where used
    friction = RegularizedFriction(system, width)
    K, W, C, eta, V = system.stiffness, system.normal_load, system.dashpot, system.radiation_damper, system.platform_speed
    omega_n = system.natural_frequency
    speed_scale = omega_n * W / K
    counter = [0]

    def rhs(s, state):
        counter[0] += 1
        if counter[0] > max_evaluations:
            raise _BudgetExceeded
        velocity = state[1] * speed_scale
        sliding = V - velocity
        return [state[1], friction(sliding) + (eta * sliding - C * velocity) / W - state[0]]

    def jacobian(s, state):
        sliding = V - state[1] * speed_scale
        return [[0.0, 1.0], [-1.0, -float(friction.derivative(sliding)) * speed_scale - (eta + C) * speed_scale / W]]

    def break_away(s, state):
        return state[1] - 0.5 * V / speed_scale

    break_away.direction = -1

    def at_rest(s, state):
        return state[1]

    if duration is None:

        reference = exact_cycle(system)
        first = (system.normal_load * friction.mu_s - C * V) / K / V  # loading from rest to the first break
        period = reference.period if np.isfinite(reference.period) else 2 * np.pi / omega_n
        duration = first + (cycles + 0.5) * period
    options = dict(method=solver, rtol=rtol, atol=atol if atol is not None else rtol * 1e-3 * max(system.static_excess, 1e-6),
                   events=[break_away, at_rest], dense_output=False)
    if solver in ("Radau", "BDF", "LSODA"):
        options["jac"] = jacobian
    label = f"regularised friction ({solver}, w = {width:.3g} m/s, rtol = {rtol:g})"
    try:
        solution = solve_ivp(rhs, (0.0, duration * omega_n), [0.0, V / speed_scale], **options)
    except _BudgetExceeded:
        raise SolverError(f"{label}: budget of {max_evaluations} function evaluations exceeded in {system.name}; "
                          "the regularised model must step through every stick phase; use the event-driven "
                          "simulator or the exact cycle") from None
    if solution.status == -1:
        raise SolverError(f"{label} failed in {system.name}: {solution.message} Use the event-driven simulator.")
    breaks = solution.t_events[0] / omega_n
    rests_t = solution.t_events[1] / omega_n
    rests_x = solution.y_events[1][:, 0] * W / K if solution.t_events[1].size else np.array([])
    amplitudes = []
    for start, end in zip(breaks[:-1], breaks[1:]):
        inside = (rests_t > start) & (rests_t < end)
        amplitudes.append(np.ptp(rests_x[inside]) if inside.sum() >= 2 else np.nan)
    sliding = V - solution.y[1] * speed_scale
    # creep: time-averaged sliding speed over V while "stuck" (|u| < V/2); exactly 0 for true stick
    sticking = (np.abs(sliding) < 0.5 * V).astype(float)
    dt = np.diff(solution.t) / omega_n
    stuck_time = np.sum(dt * sticking[1:])
    creep = float(np.sum(dt * (np.abs(sliding[1:]) * sticking[1:])) / (V * stuck_time)) if stuck_time > 0 else np.nan
    return {
        "event_time": breaks,
        "amplitude": np.asarray(amplitudes),
        "period": np.diff(breaks),
        "creep": creep,
        "evaluations": counter[0],
        "regime": "stick_slip" if breaks.size >= 2 else "steady_sliding",
    }
