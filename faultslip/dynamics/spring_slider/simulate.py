"""Event-driven time integration of stick and slip (any friction law, any scale).

The friction discontinuity is never smoothed. The simulation alternates:

* **stick**, analytic: x = x_s + V (t - t_s). It ends when the holding force K x + C V reaches
  W mu_s. For rate and constant laws the break-away displacement is explicit; for a
  time-of-stick law mu_s(t_stick) it is the single root of a convex function, located by
  Brent's method on an analytic bracket. A stick phase is never stepped through, so fault-scale
  interseismic periods (~1e9-1e10 s) cost nothing.
* **slip**, from (x_break, V): analytic for linear kinetic laws (see :mod:`faultslip.dynamics.spring_slider.exact_cycle`),
  otherwise integrated by a scipy method with dense output in scaled variables
  X = K x / W, Y = K x' / (W omega_n), s = omega_n t. The end of slip (x' returns to V,
  sliding speed 0) is a terminal event located by scipy's root finder to the integrator's
  tolerance; the force needed to stick is then checked against the static limit.

Failures are never silent: step-size collapse, an exhausted evaluation budget, a slip that
neither ends nor decays within the horizon, or a reverse slip raise :class:`SolverError`
naming the method, the scene and what to do instead.
"""

from __future__ import annotations

import math
import time as _time

import numpy as np

from faultslip.dynamics.shared.cycle import GROWING_OSCILLATION, STEADY_SLIDING, STICK_SLIP
from faultslip.dynamics.shared.settling import aitken, assess_settling
from faultslip.units import ELAPSED_TIME_ATTRS, takes_units
from faultslip.errors import EvaluationBudgetError, InputError, SolverError
from faultslip.dynamics.spring_slider.exact_cycle import _Oscillator, slip_cycle
from faultslip.io.report import Report

INTEGRATORS = ("RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA")
#: a slip phase is first integrated two periods of omega_n t (then on to its horizon): a graze, which only the
#: velocity's extrema show, ends the phase there instead of after the horizon
FIRST_STRETCH = 4.0 * math.pi
SUSTAINED_OSCILLATION = "sustained_oscillation"


class _BudgetExceeded(Exception):
    pass


class _BadFriction(Exception):
    def __init__(self, sliding, mu):
        super().__init__(sliding, mu)
        self.sliding, self.mu = sliding, mu


class SlipOutcome:
    """One slip phase: samples, end state and per-event quantities (SI, local time)."""

    __slots__ = ("times", "x", "v", "friction", "duration", "x_end", "x_max", "x_min", "v_min", "regime", "evaluations",
                 "fallback")

    def __init__(self, **kw):
        for key in self.__slots__:
            setattr(self, key, kw.get(key))


#: Event-driven slip phases' declared error, c rtol^q + floor (amplitude and period; event times that
#: per cycle), as (c, q, floor) by integrator: the tightest such model at least 1.5 x the largest error
#: measured on 369 calibration scenes at each rtol from 1e-3 to 1e-12 (the bench's stick-slip scenes
#: and faultslip.evaluation.bench's CALIBRATION_SEEDS' and LATER_CALIBRATION_SEEDS' random draws, 10 cycles a
#: run; benchmarks/event_driven_calibration.py fits it), checked on scenes drawn apart by faultslip bench.
#: Refitted once the position was integrated about the kinetic equilibrium (_integrated_slip): before, DOP853's
#: was (13, 0.99, 5e-12), set by weakening polynomial laws whose swing was a small difference of large positions,
#: RK45's (14, 1.07, 2e-12), Radau's (0.33, 0.94, 2e-12) and LSODA's (5.4, 0.86, 0). LSODA's error stays erratic in
#: rtol (its largest at 1e-12 is as large as at 1e-11, hence the floor). RK23 and BDF are not calibrated and take
#: LSODA's.
SOLVER_ERROR_MODEL = {"RK45": (8.8, 1.1, 0.0), "DOP853": (0.67, 0.9, 0.0), "Radau": (0.29, 1.02, 1e-12),
                      "LSODA": (1.6, 0.83, 1e-11)}
SOLVER_ERROR_MODEL["RK23"] = SOLVER_ERROR_MODEL["BDF"] = SOLVER_ERROR_MODEL["LSODA"]
#: RK45's longest step in a slip phase, in radians of the natural oscillation (omega t)
RK45_MAX_STEP = 1.0


def declared_slip_error(solver: str, rtol: float) -> float:
    """Declared relative error of event-driven slip phases integrated by ``solver`` at ``rtol``.

    error <= c rtol^q + floor (:data:`SOLVER_ERROR_MODEL`), relative, on the amplitude and the period;
    event times err by it per cycle, in periods. An integrator's error is not proportional to rtol
    everywhere: LSODA's grows faster as rtol shrinks (q < 1), and a floor is what round-off leaves.

    Parameters
    ----------
    solver : str
        scipy integrator of the slip phases (RK45, DOP853, Radau, LSODA; RK23 and BDF take LSODA's).
    rtol : float
        its relative tolerance.

    Returns
    -------
    float
        the declared relative error.
    """
    constant, power, floor = SOLVER_ERROR_MODEL.get(solver, SOLVER_ERROR_MODEL["LSODA"])
    return constant * rtol ** power + floor


def _stick_duration(system, x_start):
    """Time until K x + C V reaches W mu_s during a stick that starts at x_start."""
    from scipy.optimize import brentq  # heavy: imported where used

    law = system.static_law
    K, C, W, V = system.stiffness, system.dashpot, system.normal_load, system.platform_speed
    if not law.depends_on_stick_time:
        x_break = (W * float(law.limit(system.loading_rate)) - C * V) / K
        return max(0.0, (x_break - x_start) / V)

    def excess(tau):
        return K * (x_start + V * tau) + C * V - W * float(law.limit(system.loading_rate, tau))

    if excess(0.0) >= 0:
        return 0.0
    upper = getattr(law, "mu_upper", None)
    if upper is not None:  # mu_s <= mu_upper, so the force reaches the limit by then
        with np.errstate(over="ignore", divide="ignore"):
            hi = max((W * upper - C * V - K * x_start) / (K * V), 0.0) * (1 + 1e-12) + 1e-300
        if not np.isfinite(hi) or not np.isfinite(excess(hi)):
            raise SolverError(f"simulate: a stick of {system.name} would last longer than a double can count "
                              f"(platform speed {V:.3g} m/s); give a platform speed many orders of magnitude larger")
    else:
        hi = max(abs(x_start) / V, 1.0 / system.natural_frequency)
        while excess(hi) < 0:
            hi *= 2.0
            if hi > 1e30:
                raise SolverError(f"simulate: the static limit of {system.name} is never reached during stick")
    return brentq(excess, 0.0, hi, xtol=1e-15 * hi, rtol=4 * np.finfo(float).eps, maxiter=200)


def _equilibrium(system):
    """Sliding equilibrium of a linear slip phase: x_e = (W mu_m + (beta W + eta) V)/K."""
    return (system.normal_load * system.mu_m
            + (system.kinetic_slope * system.normal_load + system.radiation_damper) * system.platform_speed) / system.stiffness


def _analytic_slip(system, x_break, samples, horizon_periods):
    zeta, omega_n = system.damping_ratio, system.natural_frequency
    if not -1 < zeta < 1:
        raise SolverError(f"simulate (analytic slip): damping ratio {zeta:.3g} of {system.name} is not oscillatory; "
                          "use an integrator, e.g. slip_solver='Radau'")
    length = system.normal_load / system.stiffness
    x_eq = _equilibrium(system)
    eps = system.platform_speed / (omega_n * length)
    u0 = (x_break - x_eq) / length
    cycle = slip_cycle(zeta, eps, u0)
    osc = _Oscillator(np.float64(zeta), np.float64(u0), np.float64(eps))
    regime = {0: STICK_SLIP, 1: STEADY_SLIDING, 2: GROWING_OSCILLATION}[int(cycle["regime"])]
    if regime == STEADY_SLIDING:
        s = np.linspace(0.0, 2 * np.pi * horizon_periods, max(samples, 40 * horizon_periods))
        return SlipOutcome(times=s / omega_n, x=x_eq + length * osc("u", s), v=omega_n * length * osc("v", s),
                           duration=np.inf, regime=STEADY_SLIDING, evaluations=0)
    s_end = float(cycle["slip_time"])
    s = np.linspace(0.0, s_end, samples)
    x = x_eq + length * osc("u", s)
    v = omega_n * length * osc("v", s)
    v[-1] = system.platform_speed  # the event itself, exactly
    return SlipOutcome(
        times=s / omega_n, x=x, v=v, duration=s_end / omega_n,
        x_end=x_eq + length * float(cycle["u_end"]),
        x_max=x_eq + length * float(cycle["u_max"]), x_min=x_eq + length * float(cycle["u_min"]),
        v_min=omega_n * length * float(cycle["v_min"]), regime=regime, evaluations=0,
    )


def _integrated_slip(system, x_break, samples, solver, rtol, atol, horizon_periods, budget, counter):
    """One slip phase by a scipy integrator, in sub-phases when the kinetic law remembers the slip.

    A law with ``holds_peak`` (friction after the fastest moment depends on that peak, e.g. surfaces
    held apart through the deceleration) is integrated up to the first maximum of the sliding speed
    with mu(u), then with ``after_peak``; should the speed exceed the peak again, afresh.
    """
    from scipy.integrate import solve_ivp  # heavy: imported where used

    K, W, C, eta, V = system.stiffness, system.normal_load, system.dashpot, system.radiation_damper, system.platform_speed
    omega_n = system.natural_frequency
    speed_scale = omega_n * W / K  # velocity of one unit of Y
    kinetic = system.kinetic_law
    y_v = V / speed_scale
    memory = bool(getattr(kinetic, "holds_peak", False))

    def unheld(s, sliding):
        return kinetic(sliding)

    friction = [unheld]  # mu(s, sliding) of the current sub-phase
    peak = [math.inf]  # the sliding speed at which the current hold began

    def rhs(s, state):
        counter[0] += 1
        if budget is not None and counter[0] > budget:
            raise _BudgetExceeded
        velocity = state[1] * speed_scale
        sliding = V - velocity
        mu = friction[0](s, sliding)
        if not (mu >= 0 and np.isfinite(mu)):  # also catches a diverging solution (inf, NaN)
            raise _BadFriction(sliding, mu)
        return [state[1], (mu - centre) + (eta * sliding - C * velocity) / W - state[0]]

    def jacobian(s, state):
        sliding = V - state[1] * speed_scale
        if friction[0] is unheld:
            dmu = float(kinetic.derivative(sliding))
        else:  # the held friction, by a central difference
            step = 1e-7 * max(1.0, abs(sliding))
            dmu = float(friction[0](s, sliding + step) - friction[0](s, sliding - step)) / (2 * step)
        return [[0.0, 1.0], [-1.0, -(dmu * speed_scale) - (eta + C) * speed_scale / W]]

    def end_of_slip(s, state):
        return state[1] - y_v

    end_of_slip.terminal = True
    end_of_slip.direction = 1

    def at_rest(s, state):  # x extrema, for the peak-to-peak amplitude
        return state[1]

    def fastest(s, state):  # x'' = 0: the velocity extrema, for the peak sliding speed
        sliding = V - state[1] * speed_scale
        return float(friction[0](s, sliding)) - centre + (eta * sliding - C * state[1] * speed_scale) / W - state[0]

    def peaked(s, state):  # the sliding speed's maximum: the hold begins
        return fastest(s, state)

    peaked.terminal = True
    peaked.direction = 1

    def beyond_peak(s, state):  # clearly faster than the held peak: a new, higher peak is to be found
        # The peak's located position is off by the event tolerance, so the speed may creep past it; the held
        # law takes max(peak, u) and stays continuous, and only a rise of 1e-6 ends the hold.
        return V - state[1] * speed_scale - peak[0] * (1 + 1e-6)

    beyond_peak.terminal = True
    beyond_peak.direction = 1

    # The position is integrated about the kinetic equilibrium (steady sliding at V), so that rtol bounds the error
    # relative to the slip's swing: about the origin the swing is a small difference of positions several times
    # larger (a weakening polynomial law, x 7.5 times the swing: DOP853 2.4 times its declared amplitude error).
    centre = float(kinetic(V)) + eta * V / W
    if not math.isfinite(centre):
        centre = 0.0
    start = [K * x_break / W - centre, y_v]

    def position(centred):
        """Block position (m) of a centred, scaled state."""
        return (centred + centre) * W / K

    # atol is a small part of the swing's scale: the static excess, or the free oscillation's amplitude from the
    # start; a start at the equilibrium (mu_s = mu(0)) with atol alone took first steps too small to move the speed
    # at all, and scipy read the unchanged speed as the slip's end at once
    excess = system.static_excess if system.static_excess is not None else abs(float(kinetic(0.0)))
    scale = max(excess if excess else 0.0, math.hypot(start[0], y_v), 1e-6)
    options = dict(method=solver, rtol=rtol, atol=atol if atol is not None else rtol * 1e-3 * scale,
                   dense_output=True)
    if solver == "RK45":
        # a step of at most a sixth of a natural period: at rtol 1e-3 RK45's steps spanned much of a slip phase and its
        # interpolant put the slip's end 2.2 % off (fresh scene random_20261220_4, 5 times its declared error)
        options["max_step"] = RK45_MAX_STEP
    if solver in ("Radau", "BDF", "LSODA"):
        options["jac"] = jacobian
    horizon = 2 * np.pi * horizon_periods
    # a velocity peak that meets V within the integrator's declared error is a graze: the run cannot tell it from a
    # crossing, and a tolerance of atol alone left round-off to decide (mu independent of speed, as in seed 000 at
    # c = 0: every other graze missed, twice the slip per event, each found only after the whole horizon)
    graze = max(options["atol"], declared_slip_error(solver, rtol) * abs(y_v))

    pieces, rests, extrema = [], [], []  # (solution, friction) per sub-phase; x extrema; velocity extrema
    s_now, state_now, evaluations, ended, fallback, graze_note = 0.0, start, 0, False, None, None
    first = min(horizon, FIRST_STRETCH)
    while True:
        stretch_end = horizon if s_now >= first else first
        held = friction[0] is not unheld
        switches = [beyond_peak] if held else [peaked] if memory else []
        events = [end_of_slip, at_rest, fastest, *switches]
        try:
            try:
                solution = solve_ivp(rhs, (s_now, stretch_end), state_now, events=events, **options)
            except ValueError as error:
                if options["method"] == "DOP853":
                    raise SolverError(f"simulate (DOP853): scipy's event location failed in a slip phase of "
                                      f"{system.name} ({error}); try another rtol") from None
                # scipy locates an event on the step's dense output; LSODA's need not reproduce the step's end
                # states, and then no sign change brackets the event (brentq refuses). DOP853's interpolant passes
                # through them: that sub-phase is integrated by DOP853 (its stiff steps bounded by the run's
                # evaluation budget), at the loosest rtol whose declared error is within the failed solver's, so
                # that the run's declared error stands; the run says so.
                failed = options["method"]
                within = [level for level in (10.0 ** -k for k in range(3, 14))
                          if declared_slip_error("DOP853", level) <= declared_slip_error(failed, rtol)]
                fallback_rtol = within[0] if within else 1e-13
                bound = (f"whose declared error is within {failed}'s at rtol={rtol:g}" if within else
                         f"its tightest (its declared error {declared_slip_error('DOP853', 1e-13):.2g})")
                fallback = (f"a slip phase's event location failed under {failed} (scipy's dense output did not "
                            f"bracket the event: {error}); that phase was integrated by DOP853 at rtol="
                            f"{fallback_rtol:g}, {bound}")
                options = {key: value for key, value in options.items() if key != "jac"}
                options.update(method="DOP853", rtol=fallback_rtol, atol=options["atol"] * fallback_rtol / rtol)
                try:
                    solution = solve_ivp(rhs, (s_now, stretch_end), state_now, events=events, **options)
                except ValueError as again:
                    raise SolverError(f"simulate ({failed}, then DOP853): scipy's event location failed in a slip "
                                      f"phase of {system.name} under both ({again}); try another rtol") from None
        except _BadFriction as bad:
            raise SolverError(
                f"simulate ({solver}): the kinetic law of {system.name} gives friction {float(bad.mu):.3g} at sliding "
                f"speed {float(bad.sliding):.3g} m/s; friction must stay finite and non-negative, so the law is used "
                "outside its valid speed range (the slip runs away); limit its velocity weakening or add damping"
            ) from None
        except _BudgetExceeded:
            raise EvaluationBudgetError(
                f"simulate ({solver}, rtol={rtol:g}): budget of {budget} function evaluations exceeded in a slip phase "
                f"of {system.name}; use the exact cycle for linear laws, a looser rtol, or a larger budget"
            ) from None
        if solution.status == -1:
            raise SolverError(
                f"simulate ({solver}, rtol={rtol:g}) failed in a slip phase of {system.name}: {solution.message} "
                "Try a stiff method (Radau, LSODA) or a looser rtol."
            )
        evaluations += solution.nfev
        ended = solution.status == 1 and solution.t_events[0].size > 0
        s_stop = float(solution.t_events[0][0]) if ended else float(solution.t[-1])
        end_state = solution.y_events[0][0] if ended else None
        missed = _missed_end(solution, s_now, y_v, graze)
        if missed is not None and missed < s_stop:
            ended, s_stop, end_state = True, missed, solution.sol(missed)
            if float(end_state[1]) < y_v:
                graze_note = graze_note or (
                    f"a slip phase ended where the sliding speed touched zero without crossing it, within "
                    f"{options['method']}'s declared error at rtol={options['rtol']:g} (a graze): counted as a stick "
                    "of no duration, the limit of the stick-slip on the weakening side; on the strengthening side "
                    "the slider would never stick again")
        before = [times <= s_stop for times in solution.t_events]
        rests.append(solution.y_events[1][before[1], 0] if solution.t_events[1].size else np.array([]))
        extrema.append(solution.y_events[2][before[2], 1] if solution.t_events[2].size else np.array([]))
        switch = solution.status == 1 and bool(switches) and solution.t_events[3].size > 0
        if ended:  # the phase's end: cut the dense output there
            pieces.append((solution, friction[0], s_now, s_stop))
            break
        pieces.append((solution, friction[0], s_now, float(solution.t[-1])))
        if not switch and solution.status == 0 and s_now < first <= float(solution.t[-1]) < horizon:
            s_now, state_now = float(solution.t[-1]), solution.y[:, -1]  # past the first stretch: to the horizon
            continue
        if not switch:
            break
        s_now, state_now = float(solution.t_events[3][0]), solution.y_events[3][0]
        if held:
            friction[0], peak[0] = unheld, math.inf
        else:
            top, since = V - state_now[1] * speed_scale, s_now

            def hold(s, sliding, top=top, since=since):
                return kinetic.after_peak(top, (s - since) / omega_n, sliding)

            friction[0], peak[0] = hold, top

    def sample(s):
        """States and friction at local times ``s`` across the sub-phases."""
        ends = np.array([piece[3] for piece in pieces])
        which = np.minimum(np.searchsorted(ends, s, side="left"), len(pieces) - 1)
        states = np.empty((2, s.size))
        mu = np.empty(s.size)
        for index, (solution, law, _, _) in enumerate(pieces):
            chosen = which == index
            if np.any(chosen):
                states[:, chosen] = solution.sol(s[chosen])
                mu[chosen] = [float(law(si, V - yi * speed_scale)) for si, yi in zip(s[chosen], states[1, chosen])] \
                    if law is not unheld else kinetic(V - states[1, chosen] * speed_scale)
        return states, mu

    if not ended:
        last_solution, last_law, _, s_last = pieces[-1]
        x_scaled, y_scaled = last_solution.y[:, -1]
        equilibrium = float(last_law(s_last, V)) + eta * V / W - centre
        initial = math.hypot(start[0] - equilibrium, start[1])
        final = math.hypot(x_scaled - equilibrium, y_scaled)
        # decaying (even slowly, e.g. zeta = 0.01 over the horizon) -> steady sliding; a limit
        # cycle that keeps its size without sticking -> sustained (quasi-harmonic) oscillation
        regime = STEADY_SLIDING if final < 0.1 * initial else SUSTAINED_OSCILLATION
        s = np.linspace(0.0, s_last, max(samples, 40 * horizon_periods))
        states, mu = sample(s)
        return SlipOutcome(times=s / omega_n, x=position(states[0]), v=states[1] * speed_scale, friction=mu,
                           duration=np.inf, regime=regime, evaluations=evaluations, fallback=fallback)
    s_end = pieces[-1][3]
    s = np.linspace(0.0, s_end, samples)
    states, mu = sample(s)
    x = position(states[0])
    v = states[1] * speed_scale
    x[-1], v[-1] = position(end_state[0]), V
    candidates = np.concatenate([x] + [position(r) for r in rests])
    velocity_min = float(min(np.min(states[1]), np.min(np.concatenate(extrema), initial=np.inf))) * speed_scale
    # negative net damping: the slip oscillation grows (same label as the exact cycle)
    regime = GROWING_OSCILLATION if system.damping_ratio < 0 else STICK_SLIP
    return SlipOutcome(times=s / omega_n, x=x, v=v, friction=mu, duration=s_end / omega_n,
                       x_end=float(x[-1]), x_max=float(candidates.max()), x_min=float(candidates.min()),
                       v_min=velocity_min, regime=regime, evaluations=evaluations,
                       fallback="; ".join(note for note in (fallback, graze_note) if note) or None)


def _missed_end(solution, s_from, y_v, tolerance):
    """The end of slip (x' back up to V) that the event search stepped over, or None.

    A sign change is looked for only between steps, so a crossing that is nearly a tangency (the
    velocity just touching V at its maximum, as when mu(0) = mu_s) can fall inside one step and be
    missed; the slip would then run on for whole extra periods. The velocity's extrema are found
    reliably (x'' changes sign transversally): the first maximum at or above V, to the integrator's
    tolerance, proves a crossing since the extremum before it, which is found on the dense output.
    """
    from scipy.optimize import brentq  # heavy: imported where used

    times, states = solution.t_events[2], solution.y_events[2]
    if times.size == 0:
        return None
    later = times > s_from + 1e-12 * max(1.0, abs(s_from))  # an extremum at the very start is the break-away itself
    above = np.flatnonzero(later & (states[:, 1] >= y_v - tolerance))
    if not above.size:
        return None
    s_top = float(times[above[0]])
    previous = times[later & (times < s_top)]
    s_low = float(previous[-1]) if previous.size else s_from

    def gap(s):
        return float(solution.sol(s)[1]) - y_v

    if gap(s_top) <= 0 or gap(s_low) >= 0:
        return s_top  # a tangency to within tolerance
    return brentq(gap, s_low, s_top, xtol=1e-14 * max(1.0, s_top), rtol=4 * np.finfo(float).eps)


#: The longest slip phase, in natural periods, before it is judged steady or sustained (``horizon_periods``)
HORIZON_PERIODS = 200


def resolved_solver(system, slip_solver: str = "auto") -> str:
    """The slip solver :func:`simulate` uses: "auto" is the analytic phase on a linear kinetic law, else DOP853."""
    if slip_solver == "auto":
        return "analytic" if system.is_linear else "DOP853"
    return slip_solver


@takes_units(initial_displacement="length")
def simulate(
    system,
    cycles: int = 100,
    *,
    slip_solver: str = "auto",
    rtol: float = 1e-10,
    atol: float | None = None,
    samples_per_slip: int = 64,
    initial_displacement: float = 0.0,
    horizon_periods: int = HORIZON_PERIODS,
    max_evaluations: int | None = None,
    scene: str | None = None,
    verify_regime: bool = True,
    stop_when_converged: float | None = None,
):
    """Simulate ``cycles`` stick-slip cycles of a :class:`~faultslip.dynamics.spring_slider.slider.SliderSystem`.

    Parameters
    ----------
    slip_solver : {"auto", "analytic", "RK45", "RK23", "DOP853", "Radau", "BDF", "LSODA"}
        "auto" uses the analytic slip phase for linear kinetic laws and DOP853 otherwise.
    rtol, atol : float
        Integrator tolerances (scaled variables); ignored by the analytic slip phase.
    initial_displacement : float
        Displacement (m) at t = 0, stuck to the platform. Default 0: spring unloaded.
    horizon_periods : int
        Longest slip phase, in natural periods, before it is judged steady or sustained.
    max_evaluations : int, optional
        Budget of right-hand-side evaluations for the whole run (integrators only).
    verify_regime : bool
        Before accepting that an integrated slip phase does not re-stick, integrate it again at a
        1000 times tighter tolerance (near the critical rate a loose tolerance can miss the
        tangency). ``False`` shows the raw integrator, as the benchmarks do.
    stop_when_converged : float, optional
        Stop once two successive events agree in amplitude and period to this relative
        tolerance (the limit cycle is reached); ``cycles`` is then an upper bound.

    Returns
    -------
    xarray.Dataset
        On ``time``: displacement, velocity, sliding_speed, spring_force, friction_force,
        friction_coefficient and phase (0 stick, 1 slip). On ``event``: break-away time,
        amplitude (peak-to-peak), stick and slip durations, period, peak sliding speed, stress
        drop, slip and static friction at break-away. Attributes carry the method, tolerance,
        regime and the system with units.
    """
    if cycles < 1:
        raise InputError(f"cycles must be at least 1, got {cycles}")
    if samples_per_slip < 3:
        raise InputError("samples_per_slip must be at least 3")
    solver = resolved_solver(system, slip_solver)
    if solver not in ("analytic",) + INTEGRATORS:
        raise InputError(f"unknown slip solver {slip_solver!r}; allowed: auto, analytic, {', '.join(INTEGRATORS)}")
    if solver == "analytic" and not system.is_linear:
        raise InputError(f"the analytic slip phase needs a linear kinetic law; {system.name} has "
                         f"{type(system.kinetic_law).__name__}: use an integrator such as DOP853")
    name = scene or system.name
    # With an analytic slip phase and a static limit that does not depend on the stick time, every
    # slip starts from the same break-away state: the motion is exactly periodic after the first
    # stick, so one slip phase is computed and the cycle is tiled.
    periodic = solver == "analytic" and not system.static_law.depends_on_stick_time
    started = _time.perf_counter()
    if periodic:
        run = _periodic_run(system, cycles, float(initial_displacement), samples_per_slip, horizon_periods, name)
    else:
        run = _stepped_run(system, cycles, float(initial_displacement), solver, rtol, atol, samples_per_slip,
                           horizon_periods, max_evaluations, verify_regime, stop_when_converged, name)
    elapsed = _time.perf_counter() - started
    settling = run.pop("settling", None)
    dataset = _dataset(system, name, solver, rtol, atol, elapsed, **run)
    if settling is not None:
        dataset.attrs.update(settled=int(settling.settled), settling_remaining=float(settling.remaining),
                             settling_contraction=float(settling.contraction), settling_reason=settling.reason)
    else:  # analytic and independent of the stick time: every cycle after the first is the steady one
        dataset.attrs.update(settled=1, settling_remaining=0.0, settling_contraction=0.0,
                             settling_reason="exactly periodic after the first stick")
    if run["notes"]:
        dataset.attrs["regime_verification"] = "\n".join(sorted(set(run["notes"])))  # notes hold "; " themselves
    return dataset


_EVENT_KEYS = ("event_time", "amplitude", "stick_duration", "slip_duration", "peak_slip_speed", "stress_drop",
               "slip", "static_friction")


def _stick_segment(system, t, x, stick):
    V, K, C = system.platform_speed, system.stiffness, system.dashpot
    x_break = x + V * stick
    return (np.array([t, t + stick]), np.array([x, x_break]), np.array([V, V]),
            np.array([K * x + C * V, K * x_break + C * V]), np.zeros(2, dtype=np.int8))


def _slip_segment(system, t, slip):
    sliding = system.platform_speed - slip.v[1:]
    mu = slip.friction[1:] if slip.friction is not None else system.kinetic_law(sliding)
    return (t + slip.times[1:], slip.x[1:], slip.v[1:], system.normal_load * np.asarray(mu, dtype=float),
            np.ones(len(slip.times) - 1, dtype=np.int8))


def _event(system, stick, x_break, slip, name, solver):
    K, C, W, V = system.stiffness, system.dashpot, system.normal_load, system.platform_speed
    holding = K * x_break + C * V
    restick = K * slip.x_end + C * V
    if restick < -W * float(system.static_law.limit(system.loading_rate, 0.0)):
        raise SolverError(
            f"simulate ({solver}): in {name} the slider overtakes the platform (reverse slip), "
            "which this model does not describe; reduce the velocity weakening or add damping"
        )
    return {"amplitude": slip.x_max - slip.x_min, "stick_duration": stick, "slip_duration": slip.duration,
            "peak_slip_speed": V - slip.v_min, "stress_drop": holding - restick,
            "slip": V * slip.duration + (x_break - slip.x_end), "static_friction": holding / W}


def _periodic_run(system, cycles, x_start, samples, horizon_periods, name):
    """Analytic, exactly periodic motion: first stick, then ``cycles`` identical cycles, tiled."""
    first_stick = _stick_duration(system, x_start)
    x_break = x_start + system.platform_speed * first_stick
    check_break_away(system, system.stiffness * x_break + system.dashpot * system.platform_speed)
    slip = _analytic_slip(system, x_break, samples, horizon_periods)
    head = [_stick_segment(system, 0.0, x_start, first_stick), _slip_segment(system, first_stick, slip)]
    if slip.regime not in (STICK_SLIP, GROWING_OSCILLATION):
        return _collect(head, {key: [] for key in _EVENT_KEYS}, slip.regime, 0, [])
    event = _event(system, first_stick, x_break, slip, name, "analytic")
    stick = _stick_duration(system, slip.x_end)  # every later stick starts where slip ends
    period = stick + slip.duration
    template = [_stick_segment(system, 0.0, slip.x_end, stick), _slip_segment(system, stick, slip)]
    t_template = np.concatenate([segment[0] for segment in template])
    start = first_stick + slip.duration
    copies = cycles - 1
    tiled_t = np.maximum.accumulate(np.add.outer(start + period * np.arange(copies), t_template).ravel())
    tiled = [(tiled_t,) + tuple(np.tile(np.concatenate([seg[i] for seg in template]), copies) for i in range(1, 5))]
    events = {key: np.full(cycles, value) for key, value in event.items()}
    events["stick_duration"][1:] = stick
    events["event_time"] = first_stick + period * np.arange(cycles)
    regime = GROWING_OSCILLATION if slip.regime == GROWING_OSCILLATION else STICK_SLIP
    return _collect(head + tiled, events, regime, 0, [])


def _relative_change(new: float, old: float) -> float:
    """|new / old - 1|, with 0 for two zeros and infinity for a change from zero."""
    if old == 0:
        return 0.0 if new == 0 else math.inf
    return abs(new / old - 1)


#: A break-away force this far (relative) below the kinetic friction at zero sliding speed is that friction to
#: round-off: a static limit equal to it (seed 000's slider at c = 0) grazes, as the slip phase's graze test handles.
BREAK_AWAY_ROUND_OFF = 1e-12


def check_break_away(system, force: float) -> None:
    """Refuse a break-away whose spring and dashpot force K x + C V is below the kinetic friction at zero sliding
    speed, W mu_k(0): the slider cannot start to slip, and seed 003's stick-slip needs mu_s > mu_k(0) (the exact
    cycle refuses it as well). Every integrator had returned something there: LSODA and Radau events of zero slip
    called a growing oscillation, DOP853 one event of 32 um and then steady sliding."""
    kinetic = system.normal_load * system.mu_m
    if force < kinetic * (1 - BREAK_AWAY_ROUND_OFF):
        raise InputError(
            f"the static friction of {system.name} at break-away ({force / system.normal_load:.5g}) is "
            f"below its kinetic friction at zero sliding speed, mu_k(0) = {system.mu_m:.5g}: the slider cannot "
            "start to slip, so there is no stick-slip (seed 003 needs mu_s > mu_k(0)); lower the kinetic law near "
            "zero speed, raise the static friction, or load more slowly")


def _stepped_run(system, cycles, x, solver, rtol, atol, samples, horizon_periods, max_evaluations, verify_regime,
                 stop_when_converged, name):
    """Cycle by cycle: integrated slip phases, or a static limit that depends on the stick time.

    Every cycle starts stuck at the re-stick position x, so the cycle is a one-dimensional map
    x -> F(x). When only the steady cycle is wanted (``stop_when_converged``), the run stops once
    :func:`~faultslip.dynamics.shared.settling.assess_settling` finds it settled, and restarts the map
    from Aitken's extrapolated fixed point (Steffensen) whenever four natural cycles have not settled:
    near V_c, where the natural approach takes thousands of cycles, a few rounds reach it.
    """
    V = system.platform_speed
    t = 0.0
    segments, notes = [], []
    events = {key: [] for key in _EVENT_KEYS}
    regime = STICK_SLIP
    counter = [0]
    history, resticks, restarts = [], [], 0
    scale = system.normal_load * _friction_scale(system)
    # relative to each quantity itself, down to tolerance x its natural scale: a stress drop that settles
    # to zero (above V_c) is settled once within that, not never
    floor = (stop_when_converged or 1e-6) * scale
    floors = [floor, 0.0, floor / system.stiffness, 0.0]
    # each cycle's own scatter: 1.5e-12 measured for the analytic map near V_c; an integrator's its tolerance
    noise, rho = (MAP_NOISE if solver == "analytic" else 10 * rtol), math.nan
    limit = cycles if stop_when_converged is None else max(cycles, SETTLING_CYCLES)
    verdict = None
    while len(events["event_time"]) < limit:
        stick = _stick_duration(system, x)
        x_break = x + V * stick
        check_break_away(system, system.stiffness * x_break + system.dashpot * V)
        segments.append(_stick_segment(system, t, x, stick))
        t += stick
        if solver == "analytic":
            slip = _analytic_slip(system, x_break, samples, horizon_periods)
        else:
            slip = _integrated_slip(system, x_break, samples, solver, rtol, atol, horizon_periods,
                                    max_evaluations, counter)
            if verify_regime and slip.regime != STICK_SLIP and rtol > 1e-13:
                tighter = max(rtol * 1e-3, 1e-13)
                # a missed tangency happens within the first velocity swings: check only those
                check = _integrated_slip(system, x_break, samples, solver, tighter,
                                         None if atol is None else atol * 1e-3, min(horizon_periods, 3),
                                         max_evaluations, counter)
                if check.regime == STICK_SLIP:
                    slip = check
                    notes.append(f"a slip phase missed its re-stick at rtol={rtol:g}; recomputed at rtol={tighter:g}")
        if slip.fallback and slip.fallback not in notes:  # the check's, where it replaced the phase
            notes.append(slip.fallback)
        segments.append(_slip_segment(system, t, slip))
        if slip.regime not in (STICK_SLIP, GROWING_OSCILLATION):
            regime = slip.regime
            break
        if slip.regime == GROWING_OSCILLATION:
            regime = GROWING_OSCILLATION
        event = _event(system, stick, x_break, slip, name, solver)
        for key, value in event.items():
            events[key].append(value)
        events["event_time"].append(t)
        t += slip.duration
        x = slip.x_end
        history.append([event["stress_drop"], stick + slip.duration, event["amplitude"], event["slip"]])
        resticks.append(x)
        if _decayed(system, events["stress_drop"]):
            regime = STEADY_SLIDING
            notes.append(f"the stress drop fell to round-off ({DECAY_FLOOR:g} of W dmu) after {len(events['stress_drop'])} "
                         "events: the stick-slip sequence decays to steady sliding (loading above the critical speed)")
            break
        if stop_when_converged is not None and len(history) >= SETTLING_WINDOW:
            verdict = assess_settling(history, stop_when_converged, floors, SETTLING_NAMES, noise=noise,
                                      contraction_hint=rho)
            if 0 < verdict.contraction < 1:
                rho = max(rho, verdict.contraction) if math.isfinite(rho) else verdict.contraction
            if verdict.settled:
                break
            if restarts < MAX_RESTARTS and verdict.contraction < 1:
                restart = float(aitken(*resticks[-3:]))
                if math.isfinite(restart) and restart != x:
                    x, restarts = restart, restarts + 1
                    history, resticks = [], []
    if history:
        verdict = assess_settling(history, stop_when_converged or 1e-6, floors, SETTLING_NAMES, noise=noise,
                                  contraction_hint=rho)
    if restarts:
        notes.append(f"the cycle map was restarted {restarts} times from its extrapolated fixed point (Steffensen) "
                     "to reach the steady cycle; the record between restarts is not one continuous motion")
    if regime == STICK_SLIP and verdict is not None and verdict.settled and \
            history[-1][0] <= (stop_when_converged or 1e-6) * scale:
        regime = STEADY_SLIDING
        notes.append("the cycle settles where the stress drop vanishes: the slider no longer sticks, it slides "
                     "steadily (the steady answer is no stick-slip)")
    if regime == STICK_SLIP and _decaying(system, events["stress_drop"]):
        regime = STEADY_SLIDING
        notes.append("the stress drop decays geometrically toward zero (Aitken extrapolation of the last events): "
                     "the sequence tends to steady sliding; there is no stick-slip limit cycle")
    run = _collect(segments, events, regime, counter[0], notes)
    run["settling"] = verdict
    return run


#: Cycles a steady-cycle run may take beyond the requested ones, and Steffensen restarts allowed.
SETTLING_CYCLES = 400
#: The cycles the settling test needs before it can find a run settled.
SETTLING_WINDOW = 4
MAX_RESTARTS = 12
SETTLING_NAMES = ("stress drop", "period", "swing", "slip")
#: Cycle-to-cycle scatter of the analytic map at its fixed point (1.5e-12 measured 0.36 % below V_c).
MAP_NOISE = 3e-12


#: Stress drops below this fraction of W (mu_s - mu_m) are round-off: no stick-slip is left.
DECAY_FLOOR = 1e-10


def _friction_scale(system) -> float:
    law = system.static_law
    upper = getattr(law, "mu_upper", None)
    if upper is not None:
        return max(upper - law.mu_lower, 1e-300)
    excess = system.static_excess
    return excess if excess else 1.0


def _decayed(system, drops) -> bool:
    return bool(drops) and drops[-1] <= DECAY_FLOOR * system.normal_load * _friction_scale(system)


def _decaying(system, drops) -> bool:
    """Strictly falling stress drops whose Aitken limit is (near) zero: a sequence decaying to steady sliding.

    Below the critical speed the drops may also fall monotonically from a large first event, but
    toward a positive limit cycle; the extrapolated limit tells the two apart.
    """
    if len(drops) < 6:
        return False
    last = np.asarray(drops[-6:], dtype=float)
    if not np.all(np.diff(last) < 0):
        return False
    x0, x1, x2 = last[-3:]
    curvature = (x2 - x1) - (x1 - x0)
    if curvature <= 0:
        return False
    limit = x2 - (x2 - x1) ** 2 / curvature
    return limit < 1e-3 * last[0]


def _collect(segments, events, regime, evaluations, notes):
    columns = [np.concatenate([segment[i] for segment in segments]) for i in range(5)]
    return {"times": columns[0], "xs": columns[1], "vs": columns[2], "forces": columns[3], "phases": columns[4],
            "events": {key: np.asarray(value, dtype=float) for key, value in events.items()}, "regime": regime,
            "evaluations": evaluations, "notes": notes}


def _dataset(system, name, solver, rtol, atol, elapsed, times, xs, vs, forces, phases, events, regime, evaluations,
             notes):
    import xarray as xr  # heavy: imported where used

    units = system.units
    V, W, K = system.platform_speed, system.normal_load, system.stiffness
    xs, vs, forces = np.asarray(xs), np.asarray(vs), np.asarray(forces)
    event_times = np.asarray(events["event_time"])
    period = np.full(event_times.shape, np.nan)
    period[1:] = np.diff(event_times)

    def var(dims, data, unit, long_name, **extra):
        return (dims, np.asarray(data, dtype=float), {"units": unit, "long_name": long_name, **extra})

    dataset = xr.Dataset(
        data_vars={
            "displacement": var("time", xs, "m", "slider displacement from the unloaded spring"),
            "velocity": var("time", vs, "m/s", "slider velocity"),
            "sliding_speed": var("time", V - vs, "m/s", "sliding speed V - x' (0 during stick)"),
            "spring_force": var("time", K * xs, units["force"], "spring force K x (what the strain ring records)"),
            "friction_force": var("time", forces, units["force"], "friction force on the slider"),
            "friction_coefficient": var("time", forces / W, "1", "friction force over normal load"),
            "phase": ("time", np.asarray(phases, dtype=np.int8),
                      {"long_name": "stick (0) or slip (1)", "flag_values": np.array([0, 1], dtype=np.int8),
                       "flag_meanings": "stick slip", "units": "1"}),
            "event_time": var("event", event_times, "s", "break-away time"),
            "amplitude": var("event", events["amplitude"], "m", "peak-to-peak swing x_max - x_min of the slip"),
            "stress_drop_slip": var("event", np.asarray(events["stress_drop"], dtype=float) / K, "m",
                                    "stress-drop slip x1 - x2 = stress drop / K (the seeds' alpha)"),
            "stick_duration": var("event", events["stick_duration"], "s", "duration of the stick before the event"),
            "slip_duration": var("event", events["slip_duration"], "s", "duration of the slip phase"),
            "period": var("event", period, "s", "time since the previous break-away"),
            "peak_slip_speed": var("event", events["peak_slip_speed"], "m/s", "largest sliding speed V - x'"),
            "stress_drop": var("event", events["stress_drop"], units["force"], "drop of K x + C V, break-away to re-stick"),
            "slip": var("event", events["slip"], "m", "slip per event: relative sliding, integral of V - x' over the slip"),
            "static_friction": var("event", events["static_friction"], "1", "holding force over W at break-away"),
        },
        coords={
            "time": ("time", np.asarray(times, dtype=float), ELAPSED_TIME_ATTRS),
            "event": ("event", np.arange(event_times.size), {"long_name": "event number", "units": "1"}),
        },
    )
    attrs = {
        "title": f"faultslip simulation: {name}",
        "method": "event_driven" if solver != "analytic" else "exact_cycle",
        "method_reason": ("linear kinetic law: analytic slip phases, analytic stick phases" if solver == "analytic"
                          else f"{solver} slip phases (rtol {rtol:g}) between analytic stick phases"),
        "estimated_relative_error": 1e-13 if solver == "analytic" else declared_slip_error(solver, rtol),
        "slip_solver": solver,
        "rtol": rtol if solver != "analytic" else 0.0,
        "atol": (atol if atol is not None else -1.0) if solver != "analytic" else 0.0,
        "regime": regime,
        "scene": name,
        "scale": system.scale,
        "function_evaluations": int(evaluations),
        "wall_time_s": float(elapsed),
        "static_law": type(system.static_law).__name__,
        "kinetic_law": type(system.kinetic_law).__name__,
        "Conventions": "CF-1.8",
    }
    for key, (value, unit) in system.describe().items():
        attrs[key] = float(value)
        attrs[f"{key}_units"] = unit
    dataset.attrs.update(attrs)
    return dataset


def summary_report(dataset, title: str | None = None):
    """A :class:`~faultslip.io.report.Report` of a simulation: regime, limit-cycle statistics, cost."""

    attrs = dataset.attrs
    fault = attrs.get("scale") == "fault"
    r = Report(title or attrs.get("title", "faultslip simulation"))
    r.section("Simulation")
    r.add("method", attrs["method"])
    r.add("slip_solver", attrs["slip_solver"])
    if attrs["slip_solver"] != "analytic":
        r.add("rtol", attrs["rtol"], label="relative tolerance")
    r.add("regime", attrs["regime"])
    r.add("events", int(dataset.sizes["event"]), label="stick-slip events")
    r.add("loading_rate", attrs["loading_rate"], "1/s", "loading rate theta_dot")
    r.add("platform_speed", attrs["platform_speed"], "m/s", "platform speed V", also=("mm/yr",) if fault else ("in/s",))
    r.add("damping_ratio", attrs["damping_ratio"], label="damping ratio zeta (at rest)")
    r.add("function_evaluations", attrs["function_evaluations"])
    r.add("wall_time", attrs["wall_time_s"], "s", "wall time")
    if dataset.sizes["event"]:
        last = dataset.isel(event=-1)
        r.section("Last cycle (the limit cycle once converged)" if attrs["regime"] != STEADY_SLIDING
                  else "Last event (the sequence decays to steady sliding)")
        length = ("ft",) if fault else ("in",)
        r.add("slip_per_event", float(last["slip"]), "m", "slip per event, integral of u dt", also=length)
        r.add("stress_drop_slip", float(last["stress_drop_slip"]), "m",
              "stress-drop slip alpha = x1 - x2 = drop / K", also=length)
        r.add("peak_to_peak_swing", float(last["amplitude"]), "m", "peak-to-peak swing x_max - x_min", also=length)
        r.add("period", float(last["period"]) if dataset.sizes["event"] > 1 else float("nan"), "s", "period",
              also=("yr",) if fault else ("ms",))
        r.add("stick_duration", float(last["stick_duration"]), "s", "stick duration", also=("yr",) if fault else ("ms",))
        r.add("slip_duration", float(last["slip_duration"]), "s", "slip duration")
        r.add("peak_slip_speed", float(last["peak_slip_speed"]), "m/s", "peak sliding speed")
        r.add("stress_drop", float(last["stress_drop"]), dataset["stress_drop"].attrs["units"],
              "stress drop" if fault else "force drop", also=("bar",) if fault else ())
        r.add("static_friction", float(last["static_friction"]), label="static friction at break-away")
        amplitudes = dataset["amplitude"].values
        if amplitudes.size > 2:
            spread = float(np.ptp(amplitudes[amplitudes.size // 2:]) / np.mean(amplitudes[amplitudes.size // 2:]))
            r.add("amplitude_spread", spread, label="amplitude spread, 2nd half (max-min)/mean")
    for note in filter(None, attrs.get("regime_verification", "").split("\n")):
        r.note(note)
    return r


def uniform_channels(dataset, sampling_rate: float | None = None, max_samples: int = 2_000_000,
                     samples_per_slip: int = 20) -> tuple[float, dict, str]:
    """A simulation on a uniform time grid, for a seismological Stream: (sampling rate in Hz, {component:
    samples}, note). Components (faultslip.io.waveforms): D the slider displacement x, S the cumulative slip
    s(t) = V t - (x(t) - x(0)), both exact between samples in stick and linear in slip; R the slip rate as
    the mean over each sample interval (slip is conserved); F the friction coefficient. The default rate puts ``samples_per_slip`` samples in a slip phase, lowered if
    the run would need more than ``max_samples`` (the note then says how the events are averaged)."""
    time = dataset["time"].values
    speed = float(dataset.attrs["platform_speed"])
    duration = float(time[-1] - time[0])
    if not duration > 0:
        raise InputError("the simulation has no duration to sample")
    note = ""
    if sampling_rate is None:
        slips = dataset["slip_duration"].values if "slip_duration" in dataset else np.array([])
        slips = slips[np.isfinite(slips) & (slips > 0)]
        sampling_rate = samples_per_slip / float(np.median(slips)) if slips.size else 1000 / duration
        if duration * sampling_rate > max_samples - 1:
            limited = (max_samples - 1) / duration
            note = (f"{max_samples:,} samples over {duration:.4g} s: {limited:.3g} Hz, so each slip phase "
                    f"({float(np.median(slips)) if slips.size else math.nan:.3g} s) is averaged over "
                    f"{1 / limited:.3g} s (slip is conserved; give a sampling rate and a shorter run to resolve it)")
            sampling_rate = limited
    count = int(math.floor(duration * sampling_rate)) + 1
    if count > max_samples:
        raise InputError(f"{count:,} samples at {sampling_rate:g} Hz exceed {max_samples:,}; lower the sampling rate "
                         "or the number of cycles")
    if count < 2:
        raise InputError(f"{sampling_rate:g} Hz gives fewer than 2 samples over {duration:.4g} s")
    grid = time[0] + np.arange(count) / sampling_rate
    x = dataset["displacement"].values
    slip = speed * (time - time[0]) - (x - x[0])
    on_grid = np.interp(grid, time, slip)
    rate = np.empty(count)
    rate[1:] = np.diff(on_grid) * sampling_rate
    rate[0] = rate[1] if count > 1 else 0.0
    friction = np.interp(grid, time, dataset["friction_coefficient"].values)
    return float(sampling_rate), {"D": np.interp(grid, time, x), "S": on_grid, "R": rate, "F": friction}, note
