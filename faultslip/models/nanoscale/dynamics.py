"""Seed 001's nanoscale stick-slip toy model with contact charging (Ananthakrishna & Kumar, slides eqs. 1-4).

Dimensionless (displacement in units of the slip scale, time in 1/omega), the tip X is pulled by
a spring whose force F grows at the drive speed v_a, against viscous damping A X', a
velocity-weakening law with its maximum at v_m, and the electrostatic adhesion of the charge Sigma:

    X''      = F - A X' - phi(X') - f_ch Sigma^2,   phi(u) = (u / v_m) / (1 + (u / v_m)^2)   (1)
    Sigma'   = (1 - Sigma) / tau - X' Sigma / a                                             (2)
    Sigma_d' = X' Sigma / a            (charge deposited on the substrate)                   (3)
    F'       = v_a - X'                                                                     (4)

Steady sliding (X' = v_a) has Sigma* = 1 / (1 + tau v_a / a) and F* = A v_a + phi(v_a) + f_ch Sigma*^2.
Linearised about it, with d = A + phi'(v_a), c = 1/tau + v_a/a, g = 2 f_ch Sigma* and h = Sigma*/a,

    lambda^3 + (c + d) lambda^2 + (1 + c d - g h) lambda + c = 0,

and Routh-Hurwitz puts the boundary at (c + d)(1 + c d - g h) = c, i.e. at
d_c = [-(c^2 + 1 - g h) + sqrt((c^2 + 1 - g h)^2 + 4 c^2 g h)] / (2 c). The damping above which
stick-slip disappears is therefore

    A_c = -phi'(v_a) + d_c,   -phi'(v_a) = (1/v_m) ((v_a/v_m)^2 - 1) / (1 + (v_a/v_m)^2)^2,

which is 12 for the slides' v_a = 0.02, v_m = 0.01 without charge (velocity weakening needs
v_a > v_m); charging raises it by d_c ~ c g h / (1 + c^2) > 0 (1.26e-7 with the slides' f_ch).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from faultslip.dynamics.shared.settling import Settling, aitken, assess_settling, bifurcation_note, settled_error
from faultslip import ranges
from faultslip.errors import InputError, SolverError
from faultslip.io import budget
from faultslip.io.report import Report
from faultslip.models.nanoscale import cost as nanoscale_cost
from faultslip.models.nanoscale.cost import SETTLE_CHUNK, SETTLE_MAX_TIME
from faultslip.models.nanoscale.hopf import HopfPoint, growth_rate, hopf_point, normal_form_cycle

#: LSODA's tightest rtol here (the reference's); a settled cycle run again at a tighter rtol integrates this many
#: of its periods at a time: four cycles settle it from the cycle itself, the rest is margin
RTOL_FLOOR, REFINE_PERIODS = 1e-12, 8.0
#: a cycle whose force swings less than this many times LSODA's error in the force has decayed: steady sliding
DECAYED = 10.0
#: the tolerance of the settled cycle the Hopf normal form's error is measured against
REFERENCE_TOLERANCE = 1e-6

#: the slides' parameters ("The parameters used in the results reported here"), A = 3 in Fig. 3a
SLIDES = {"damping": 3.0, "drive_speed": 0.02, "peak_speed": 0.01, "charging_time": 2.0, "charge_length": 1.57,
          "charge_force": 2.56e-7}


@dataclass(frozen=True)
class NanoscaleModel:
    """Eqs. (1)-(4), dimensionless. ``charge_force`` f_ch = 0 is the uncharged limit.

    Parameters
    ----------
    damping : float
        A, the damping (dimensionless; stick-slip below A_c).
    drive_speed : float
        v_a, the drive speed (dimensionless).
    peak_speed : float
        v_m, the speed above which friction weakens (dimensionless).
    charging_time : float
        tau, the charging time (in 1/omega).
    charge_length : float
        a, the charge length (in the slip scale).
    charge_force : float
        f_ch, the force of the deposited charge (0: the uncharged limit).
    """

    damping: float = SLIDES["damping"]  # A
    drive_speed: float = SLIDES["drive_speed"]  # v_a
    peak_speed: float = SLIDES["peak_speed"]  # v_m
    charging_time: float = SLIDES["charging_time"]  # tau
    charge_length: float = SLIDES["charge_length"]  # a
    charge_force: float = SLIDES["charge_force"]  # f_ch

    def __post_init__(self):
        # dimensionless: values beyond 1e-9 to 1e9 (0 allowed for A and f_ch) describe no experiment and
        # overflow the model's squares
        for label, value in (("damping A", self.damping), ("charge force f_ch", self.charge_force)):
            if not (isinstance(value, (int, float)) and 0 <= value <= 1e9):
                raise InputError(f"the {label} must be a number from 0 to 1e9 (dimensionless), got {value!r}")
        for label, value in (("drive speed v_a", self.drive_speed), ("peak speed v_m", self.peak_speed),
                             ("charging time tau", self.charging_time), ("charge length a", self.charge_length)):
            if not (isinstance(value, (int, float)) and 1e-9 <= value <= 1e9):
                raise InputError(f"the {label} must be a positive number from 1e-9 to 1e9 (dimensionless), "
                                 f"got {value!r}")

    def weakening(self, speed):
        """phi(u) = (u / v_m) / (1 + (u / v_m)^2): rises to 1/2 at u = v_m and weakens beyond."""
        ratio = np.asarray(speed, dtype=float) / self.peak_speed
        return ratio / (1.0 + ratio * ratio)

    def weakening_slope(self, speed):
        """phi'(u) = (1 / v_m) (1 - (u/v_m)^2) / (1 + (u/v_m)^2)^2."""
        ratio = np.asarray(speed, dtype=float) / self.peak_speed
        return (1.0 - ratio * ratio) / (1.0 + ratio * ratio) ** 2 / self.peak_speed

    @property
    def steady_charge(self) -> float:
        return 1.0 / (1.0 + self.charging_time * self.drive_speed / self.charge_length)

    def _coupling(self):
        c = 1.0 / self.charging_time + self.drive_speed / self.charge_length
        sigma = self.steady_charge
        return c, 2.0 * self.charge_force * sigma, sigma / self.charge_length

    def characteristic_roots(self) -> np.ndarray:
        """Roots of the cubic above: growth rates of small disturbances of steady sliding."""
        c, g, h = self._coupling()
        d = self.damping + float(self.weakening_slope(self.drive_speed))
        return np.roots([1.0, c + d, 1.0 + c * d - g * h, c])

    @property
    def critical_damping(self) -> float:
        """A_c: steady sliding is stable above it, stick-slip below (Routh-Hurwitz on the cubic)."""
        c, g, h = self._coupling()
        p = c * c + 1.0 - g * h
        shift = (-p + math.sqrt(p * p + 4.0 * c * c * g * h)) / (2.0 * c)
        return -float(self.weakening_slope(self.drive_speed)) + shift

    @property
    def stick_slip(self) -> bool:
        return self.damping < self.critical_damping

    def simulate(self, duration: float = 3000.0, samples: int = 6001, perturbation: float = 1e-3,
                 rtol: float = 1e-8, allow_large: bool = False):
        """Eqs. (1)-(4) from steady sliding with X' raised by ``perturbation``: time, X, X', F, Sigma, Sigma_d.

        LSODA (the stuck phases are stiff: phi'(0) = 1 / v_m). Raises :class:`SolverError` naming the
        method if it fails."""
        from scipy.integrate import solve_ivp  # heavy: imported where used

        if not (duration > 0 and math.isfinite(duration)) or not 2 <= samples <= 10_000_000:
            raise InputError("duration must be positive and samples from 2 to 1e7")
        budget.check(nanoscale_cost.nanoscale_estimate(duration, samples), allow_large)  # before any work
        v_a, f_ch, damping = self.drive_speed, self.charge_force, self.damping
        sigma0 = self.steady_charge
        force0 = damping * v_a + float(self.weakening(v_a)) + f_ch * sigma0 ** 2
        rhs = self._rhs()

        start = [0.0, v_a * (1.0 + perturbation), force0, sigma0, 0.0]
        if not all(math.isfinite(value) for value in start):
            raise InputError(f"the steady-sliding force A v_a + phi(v_a) + f_ch Sigma*^2 = {force0:g} is not finite: "
                             "the damping A, drive speed v_a or charge force f_ch is too large")
        times = np.linspace(0.0, duration, samples)
        try:
            with np.errstate(over="ignore", invalid="ignore"):
                solution = solve_ivp(rhs, (0.0, duration), start, method="LSODA", t_eval=times, rtol=rtol, atol=1e-12,
                                     dense_output=True)
        except (ValueError, ArithmeticError) as exc:  # scipy refuses non-finite states mid-run the same way
            raise SolverError(f"LSODA failed on the nanoscale model ({exc}); the parameters drive the state to "
                              "overflow") from None
        if not solution.success:
            raise SolverError(f"LSODA failed on the nanoscale model: {solution.message}; tighten rtol or "
                              "shorten the duration")
        if not np.all(np.isfinite(solution.y)):
            raise SolverError("LSODA's state overflowed on the nanoscale model: the parameters (a large charge force "
                              "f_ch or damping A?) drive it beyond floating point")
        x, speed, force, charge, deposited = solution.y
        return NanoscaleRun(time=times, displacement=x, speed=speed, force=force, charge=charge,
                            deposited=deposited, model=self,
                            cycles=_cycles(_locate_events(solution, self._cycle_events(rhs)), self), rtol=rtol)

    def _rhs(self):
        v_a, a, tau, f_ch, damping, v_m = (self.drive_speed, self.charge_length, self.charging_time, self.charge_force,
                                           self.damping, self.peak_speed)

        def rhs(t, y):
            speed, charge, force = y[1], y[3], y[2]
            ratio = speed / v_m
            return (speed, force - damping * speed - ratio / (1.0 + ratio * ratio) - f_ch * charge * charge,
                    v_a - speed, (1.0 - charge) / tau - speed * charge / a, speed * charge / a)

        return rhs

    def _cycle_events(self, rhs):
        """Events located on the dense solution: X' through v_a upward (the force's maximum, F' = v_a - X'
        changing sign) and downward (its minimum), and X'' = 0 rising (the speed's minimum)."""
        v_a = self.drive_speed

        def up(t, y):
            return y[1] - v_a
        up.direction = 1.0

        def down(t, y):
            return y[1] - v_a
        down.direction = -1.0

        def slowest(t, y):
            return rhs(t, y)[1]
        slowest.direction = 1.0
        return [up, down, slowest]

    def settled_cycle(self, tolerance: float = 1e-6, rtol: float | None = None, max_cycles: int = 3000,
                      chunk: float = SETTLE_CHUNK, max_time: float = SETTLE_MAX_TIME,
                      allow_large: bool = False, start: tuple | None = None) -> "NanoscaleCycle":
        """The steady cycle below A_c, shown to have settled (issue 27).

        Starts stuck (X' = 0 at the steady-sliding force: a large disturbance, approached from above),
        integrates with LSODA and measures every cycle between upward crossings of X' = v_a: the force
        swing from the located extrema of the dense solution, the period and the least speed. The
        shared :func:`~faultslip.dynamics.shared.settling.assess_settling` judges the cycles; while
        unsettled, the map on the section X' = v_a is restarted from the Aitken-extrapolated (F, Sigma)
        (Steffensen), which reaches the cycle near A_c where the natural approach takes ~1 / (A_c - A)
        periods. The regime follows what the cycle does: it sticks (the least speed falls below
        STICK_FRACTION v_m), oscillates without sticking, or decays to steady sliding.

        LSODA's error in the swing scales with the force F*, not the swing: where F* / swing makes the settled
        cycle's error exceed ``tolerance`` at ``rtol``, the cycle is run again from its last crossing (``start``:
        time and state) at an rtol tightened by that ratio, to RTOL_FLOOR, and the tighter run is the answer.
        """
        from scipy.integrate import solve_ivp  # heavy: imported where used

        rtol = rtol if rtol is not None else min(1e-4, max(RTOL_FLOOR, tolerance / LSODA_ERROR_CONSTANT))
        # the worst case, integrating to max_time, within the budget before any work
        budget.check(nanoscale_cost.nanoscale_estimate(max_time, 2), allow_large)
        noise = LSODA_ERROR_CONSTANT * rtol
        rhs = self._rhs()
        events = self._cycle_events(rhs)
        sigma0 = self.steady_charge
        force0 = self.damping * self.drive_speed + float(self.weakening(self.drive_speed)) + \
            self.charge_force * sigma0 ** 2
        state = np.array([0.0, 0.0, force0, sigma0, 0.0]) if start is None else np.array(start[1], dtype=float)
        t = 0.0 if start is None else float(start[0])
        history, crossings, restarts, total, integrated = [], [], 0, 0, 0.0
        verdict, rho = None, math.nan
        floor = (self.drive_speed, 0.0, self.drive_speed)  # swing and least speed against v_a: both may vanish
        pending = {"top": None if start is None else (t, float(state[2])), "bottom": None, "slowest": math.inf}
        last_crossing = None
        while total < max_cycles and t < max_time:  # max_time: a run whose cycles never complete ends too
            with np.errstate(over="ignore", invalid="ignore"):
                solution = solve_ivp(rhs, (t, t + chunk), state, method="LSODA", rtol=rtol, atol=1e-12,
                                     dense_output=True)
            if not solution.success or not np.all(np.isfinite(solution.y[:, -1])):
                raise SolverError(f"LSODA failed on the nanoscale cycle at t = {t:g}: {solution.message}; tighten "
                                  "the tolerance")
            integrated += chunk
            located = _locate_events(solution, events)
            marks = sorted([(float(time), kind, state_at) for kind, (times, states) in
                            enumerate(zip(*located)) for time, state_at in zip(times, states)],
                           key=lambda item: item[0])
            restart = None
            for time, kind, at in marks:
                if kind == 2:
                    pending["slowest"] = min(pending["slowest"], float(at[1]))
                elif kind == 1:
                    pending["bottom"] = float(at[2])
                else:
                    if pending["top"] is not None and pending["bottom"] is not None:
                        # a cycle without a located speed minimum (a vanishing oscillation) is slowest where it
                        # crosses v_a going down, at most
                        history.append([pending["top"][1] - pending["bottom"], time - pending["top"][0],
                                        min(pending["slowest"], self.drive_speed)])
                        crossings.append(at.copy())
                        last_crossing = (time, at.copy())
                        total += 1
                        if history[-1][0] <= DECAYED * noise * abs(force0):
                            verdict = Settling(True, total, math.nan, 0.0, np.array(history[-1]),
                                               f"the oscillation decayed to a swing of {history[-1][0]:.2g}, below "
                                               f"LSODA's resolution of the force ({noise * abs(force0):.2g}): the "
                                               "tip slides steadily")
                            break
                    pending = {"top": (time, float(at[2])), "bottom": None, "slowest": math.inf}
                    if len(history) >= 4:
                        verdict = assess_settling(history, max(tolerance, noise), floor,
                                                  ("force swing", "period", "least speed"), noise=noise,
                                                  contraction_hint=rho)
                        if 0 < verdict.contraction < 1:
                            rho = max(rho, verdict.contraction) if math.isfinite(rho) else verdict.contraction
                        if verdict.settled:
                            break
                        if restarts < 12 and verdict.contraction < 1:
                            target = aitken(*[crossing[2:4] for crossing in crossings[-3:]])
                            if np.all(np.isfinite(target)):
                                restart = np.array([at[0], self.drive_speed, target[0], target[1], at[4]])
                                restart_time = time
                                break
            if verdict is not None and verdict.settled:
                break
            if restart is not None:
                state, t, restarts = restart, restart_time, restarts + 1
                history, crossings = [], []
                pending = {"top": (t, float(restart[2])), "bottom": None, "slowest": math.inf}
            else:
                state, t = solution.y[:, -1], float(solution.t[-1])
        if verdict is None:
            verdict = Settling(False, total, math.nan, math.inf, np.full(3, math.nan),
                               f"fewer than four cycles completed within {max_time:g} time units")
        swing, period, slowest = (history[-1] if history else (math.nan,) * 3)
        if verdict.settled and verdict.remaining == 0.0 and swing <= DECAYED * noise * abs(force0):
            # decayed to steady sliding (a start from rest above A_c, or a stable focus): swing 0, exactly
            return NanoscaleCycle(0.0, math.nan, self.drive_speed, verdict, total, restarts, rtol, 0.0, self,
                                  integrated)
        # the verdict is relative to max(swing, v_a): back to the swing's own scale. LSODA's error in the swing
        # scales with the force itself (~30 rtol F*, A = 3 and A = 0.994 A_c), so a small swing near A_c
        # carries it relative to F*, not to the swing
        scale = max(abs(swing), 1e-300)
        integration_error = noise * max(1.0, force0 / scale)
        remaining = settled_error(integration_error,
                                  float(verdict.remaining) * max(abs(swing), self.drive_speed) / scale)
        cycle = NanoscaleCycle(float(swing), float(period), float(slowest), verdict, total, restarts, rtol,
                               remaining, self, integrated)
        if (start is None and verdict.settled and integration_error > tolerance and rtol > RTOL_FLOOR
                and last_crossing is not None and math.isfinite(period)):
            # the rtol chosen for the tolerance met it in F*, not in this swing: once more from the cycle itself
            tighter = max(RTOL_FLOOR, rtol * tolerance / integration_error / 2.0)
            again = self.settled_cycle(tolerance, tighter, max_cycles, chunk=min(chunk, REFINE_PERIODS * period),
                                       max_time=max(max_time - integrated, chunk), allow_large=allow_large,
                                       start=last_crossing)
            if again.estimated_error < remaining:  # near A_c it may not settle again within its cycles
                cycle = replace(again, cycles=total + again.cycles, restarts=restarts + again.restarts,
                                integrated=integrated + again.integrated, refined_from=rtol)
            else:
                cycle = replace(cycle, integrated=integrated + again.integrated)
        return cycle


#: A cycle sticks when its least speed falls below this fraction of v_m: onto the rising, static-like branch
#: of phi (u < v_m, where friction grows with speed); above it the tip oscillates on the weakening branch.
STICK_FRACTION = 1.0
OSCILLATING = "oscillating_sliding"


def cycle_regime(model: "NanoscaleModel", swing: float, least_speed: float, settled: bool) -> str:
    """What the settled cycle does: sticks, oscillates without sticking, or slides steadily."""
    if not math.isfinite(swing) or swing <= 1e-9 * max(model.drive_speed, 1e-300):
        return "steady_sliding"
    if least_speed < STICK_FRACTION * model.peak_speed:
        return "stick_slip"
    return OSCILLATING


@dataclass
class NanoscaleCycle:
    """The settled cycle: its force swing (from the located extrema), period and least speed."""

    force_swing: float
    period: float
    least_speed: float
    settling: Settling
    cycles: int
    restarts: int
    rtol: float
    estimated_error: float  # relative, of the force swing: the integrator's plus what settling left
    model: "NanoscaleModel"
    integrated: float = math.nan  # model time integrated (1/omega): LSODA chunks, restarts and a tighter run included
    refined_from: float | None = None  # the rtol of a first run whose error in this swing missed the tolerance
    hopf: tuple | None = None  # the normal form's cycle: (omega_0, the reference's A, the error measured there)

    @property
    def regime(self) -> str:
        return cycle_regime(self.model, self.force_swing, self.least_speed, self.settling.settled)


def _locate_events(solution, events):
    """(times, states) per event function, located on the dense solution itself.

    scipy's own event location compares signs at the step ends from the integrator's states but
    root-finds on the interpolant, and near a tangency the two disagree ("f(a) and f(b) must have
    different signs"); here both come from the interpolant, so a bracket always holds a root.
    """
    from scipy.optimize import brentq  # heavy: imported where used

    steps = solution.t
    states = solution.sol(steps)
    found_times, found_states = [], []
    for event in events:
        values = np.array([event(t, states[:, i]) for i, t in enumerate(steps)])
        if event.direction > 0:
            crossings = np.flatnonzero((values[:-1] < 0) & (values[1:] >= 0))
        else:
            crossings = np.flatnonzero((values[:-1] > 0) & (values[1:] <= 0))
        times = [brentq(lambda t: event(t, solution.sol(t)), steps[i], steps[i + 1], xtol=1e-13, rtol=1e-15)
                 if values[i + 1] != 0 else steps[i + 1] for i in crossings]
        found_times.append(np.array(times, float))
        found_states.append(solution.sol(np.array(times)).T if times else np.empty((0, states.shape[0])))
    return found_times, found_states


def _cycles(located, model) -> np.ndarray:
    """Per cycle of a run (rows): force swing, period and least speed, from the located events."""
    (ups, downs, slow), (up_states, down_states, slow_states) = located
    up_force = up_states[:, 2] if ups.size else np.empty(0)
    down_force = down_states[:, 2] if downs.size else np.empty(0)
    slow_speed = slow_states[:, 1] if slow.size else np.empty(0)
    rows = []
    for i in range(ups.size - 1):
        inside = (downs > ups[i]) & (downs < ups[i + 1])
        if not inside.any():
            continue
        lowest = slow_speed[(slow > ups[i]) & (slow < ups[i + 1])]
        rows.append([up_force[i] - down_force[inside][-1], ups[i + 1] - ups[i],
                     float(lowest.min()) if lowest.size else math.inf])
    return np.array(rows, float).reshape(-1, 3)


@dataclass
class NanoscaleRun:
    time: np.ndarray
    displacement: np.ndarray
    speed: np.ndarray
    force: np.ndarray
    charge: np.ndarray
    deposited: np.ndarray
    model: NanoscaleModel
    cycles: np.ndarray = None  # rows: force swing, period, least speed per cycle (located on the dense solution)
    rtol: float = 1e-8

    def force_swing(self, last: float = 0.5) -> float:
        """Peak-to-peak force over the cycles in the last fraction of the run, from the located extrema of
        the dense solution (not the samples); 0 where no cycle completes (steady sliding)."""
        if self.cycles is None or not self.cycles.size:
            tail = self.force[int((1 - last) * self.force.size):]
            return float(tail.max() - tail.min()) if self.cycles is None else 0.0
        return float(self.cycles[-1, 0])

    def settling(self, tolerance: float = 1e-6) -> Settling:
        """Whether the run's cycles settled (the shared test), with the integrator's error as its noise."""
        noise = LSODA_ERROR_CONSTANT * self.rtol
        if self.cycles is None or self.cycles.shape[0] < 2:
            return Settling(False, 0 if self.cycles is None else self.cycles.shape[0], math.nan, math.inf,
                            np.full(3, math.nan), "fewer than two complete cycles in the run")
        return assess_settling(self.cycles, max(tolerance, noise), (self.model.drive_speed, 0.0,
                                                                    self.model.drive_speed),
                               ("force swing", "period", "least speed"), noise=noise)

    def slip_events(self, last: float = 0.5) -> int:
        """Slip events (X' rising through 2 v_a) over the last fraction of the run."""
        tail = self.speed[int((1 - last) * self.speed.size):]
        threshold = 2.0 * self.model.drive_speed
        return int(np.count_nonzero((tail[:-1] < threshold) & (tail[1:] >= threshold)))

    def charge_correlation(self) -> float:
        """Correlation coefficient of displacement and deposited charge (seed 001: 'both have the same slope')."""
        return float(np.corrcoef(self.displacement, self.deposited)[0, 1])


def hertz_radius(normal_force: float, radius: float, modulus: float) -> float:
    """Hertz contact radius a = (3 F_n R / (4 E*))^(1/3) (seed 001 eq. 5), m."""
    return (3.0 * normal_force * radius / (4.0 * modulus)) ** (1.0 / 3.0)


def jkr_radius(normal_force: float, radius: float, modulus: float, surface_energy: float) -> float:
    """JKR contact radius a^3 = 3R/(4E*) (F + 3 pi gamma R + sqrt(6 pi R gamma F + (3 pi R gamma)^2)) (eq. 6), m."""
    adhesion = 3.0 * math.pi * surface_energy * radius
    return (3.0 * radius / (4.0 * modulus) * (normal_force + adhesion + math.sqrt(
        6.0 * math.pi * radius * surface_energy * normal_force + adhesion ** 2))) ** (1.0 / 3.0)


def dipole_force(contact_radius: float, charge_density: float, permittivity: float = 3.5,
                 coefficient: float = 1.0) -> float:
    """Attraction of the contact's dipole layer F_c = mu pi a^2 sigma^2 / (2 eps_0 kappa), N (seed 001, 'Why doubt').

    The slides print sigma in the numerator once; the force of a charged layer goes as sigma^2 (their eq.
    in (e) and the full model's pi R z sigma^2 / 2 eps_0 kappa), which is used here."""
    return coefficient * math.pi * contact_radius ** 2 * charge_density ** 2 / (2.0 * 8.8541878128e-12 * permittivity)


#: The normal form answers within this sigma / omega_0 of a supercritical Hopf point. Its error, O(sigma), is measured
#: on the scene at this distance against a settled LSODA cycle and declared below it as HOPF_SAFETY times that,
#: scaled by sigma (measured: the error over sigma changes by 0.8-1.1x from here to 1e-4 of it, slides' model and a
#: strongly charged one); a measured error above HOPF_LIMIT says the expansion does not hold there
HOPF_REFERENCE, HOPF_SAFETY, HOPF_LIMIT = 3e-3, 2.0, 0.1
#: measured error of the LSODA force swing against rtol 1e-12: 27-30 rtol (slides' model, A = 3 and 7, rtol
#: 1e-4 to 1e-10; tests/models/nanoscale/test_nanoscale.py); declared 100 rtol
LSODA_ERROR_CONSTANT = 100.0
#: ``faultslip methods`` entries: the regime in closed form, the cycle by integration
METHODS = {
    "nanoscale_linear_stability": {
        "name": "nanoscale_linear_stability", "friction_laws": "nanoscale (seed 001 eqs. 1-4)",
        "domain": "the regime from small disturbances and the threshold A_c (Routh-Hurwitz); no swing or time series "
                  "where it sticks and slips; exact to round-off away from A = A_c",
        "cost_model": "a cubic's coefficients: about 1e-5 s",
        "declared_error": "round-off, away from A = A_c; the regime within 1e-9 of A_c is handed to LSODA"},
    "nanoscale_LSODA": {
        "name": "nanoscale_LSODA", "friction_laws": "nanoscale (seed 001 eqs. 1-4)",
        "domain": "any parameters; the force swing, slip events, charge and the time series",
        "cost_model": "LSODA (stiff stuck phases): 0.4 s at rtol 1e-4 to 1.7 s at 1e-10 for 3000 time units; "
                      f"error of the force swing {LSODA_ERROR_CONSTANT:g} rtol",
        "declared_error": f"{LSODA_ERROR_CONSTANT:g} rtol in the force swing (measured against rtol 1e-12), and the "
                          "settling left near the Hopf threshold"},
    "nanoscale_hopf_normal_form": {
        "name": "nanoscale_hopf_normal_form", "friction_laws": "nanoscale (seed 001 eqs. 1-4)",
        "domain": f"below a supercritical A_c (first Lyapunov coefficient l_1 < 0), within sigma / omega_0 = "
                  f"{HOPF_REFERENCE:g} of it: the small cycle's swing, period and least speed; no time series "
                  "(asked for by name farther off, it answers with its error measured at A itself)",
        "cost_model": "the Hopf point in closed form, and one settled LSODA cycle at sigma / omega_0 = "
                      f"{HOPF_REFERENCE:g}, where it settles in about a second",
        "declared_error": f"{HOPF_SAFETY:g} x the normal form's error measured on the scene at sigma / omega_0 = "
                          f"{HOPF_REFERENCE:g} (against that settled cycle), scaled by sigma: the error is O(sigma)"},
}
NANOSCALE_METHODS = ("auto", "nanoscale_linear_stability", "nanoscale_LSODA", "nanoscale_hopf_normal_form")
NANOSCALE_OUTPUTS = ("regime", "force_swing", "time_series")


@dataclass
class NanoscaleChoice:
    method: str
    reason: str
    estimated_error: float  # relative, of the force swing (0: exact)
    rtol: float | None = None


def choose_method(model: NanoscaleModel, outputs=("regime", "force_swing"), method: str = "auto",
                  tolerance: float = 1e-6) -> NanoscaleChoice:
    """The cheapest method that gives ``outputs`` within ``tolerance``: the closed form where the regime
    settles the question (or steady sliding, whose swing is 0), else LSODA at rtol = tolerance / 100."""
    if method not in NANOSCALE_METHODS:
        raise InputError(f"the nanoscale method must be one of {', '.join(NANOSCALE_METHODS)}, got {method!r}")
    unknown = [o for o in outputs if o not in NANOSCALE_OUTPUTS]
    if unknown:
        raise InputError(f"unknown output {unknown[0]!r}; allowed: {', '.join(NANOSCALE_OUTPUTS)}")
    tolerance = ranges.check_tolerance(tolerance)
    rtol = min(1e-4, max(RTOL_FLOOR, tolerance / LSODA_ERROR_CONSTANT))
    integration = NanoscaleChoice("nanoscale_LSODA", "", LSODA_ERROR_CONSTANT * rtol, rtol)
    point = hopf_point(model)
    bistable = bistable_above(model, point)
    closed_enough = "time_series" not in outputs and ("force_swing" not in outputs or not (model.stick_slip or
                                                                                         bistable))
    if method == "nanoscale_linear_stability":
        if not closed_enough:
            wanted = ("a time series" if "time_series" in outputs else "the stick-slip force swing" if
                      model.stick_slip else "the swing from rest (the Hopf point is subcritical: a tip started from "
                                            "rest may stick-slip above A_c)")
            raise InputError(f"nanoscale_linear_stability gives the regime and A_c, not {wanted}: use "
                             "nanoscale_LSODA or auto")
        return NanoscaleChoice(method, "requested", 0.0)
    if method == "nanoscale_LSODA":
        integration.reason = "requested"
        return integration
    outside = hopf_domain(model, point, outputs)
    if method == "nanoscale_hopf_normal_form":
        refused = hopf_domain(model, point, outputs, anywhere=True)
        if refused:
            raise InputError(f"nanoscale_hopf_normal_form {refused}: use nanoscale_LSODA or auto")
        return NanoscaleChoice(method, "requested", math.nan)
    if closed_enough:
        why = ("only the regime is asked" if "force_swing" not in outputs else
               f"A = {model.damping:g} >= A_c = {model.critical_damping:.6g}: small disturbances decay, the swing is 0"
               + ("" if point is None else " (a supercritical Hopf point: no small cycle above A_c)"))
        return NanoscaleChoice("nanoscale_linear_stability", f"closed form suffices: {why}", 0.0)
    if outside is None:
        ratio = growth_rate(model) / point.frequency
        return NanoscaleChoice("nanoscale_hopf_normal_form", f"sigma / omega_0 = {ratio:.3g} of a supercritical Hopf "
                               f"point, within {HOPF_REFERENCE:g}: the small cycle's normal form, its error measured "
                               "on the scene", math.nan)
    if bistable:
        integration.reason = (f"A = {model.damping:g} >= A_c = {model.critical_damping:.6g} at a subcritical Hopf "
                              "point (l_1 > 0): steady sliding is stable to small disturbances only, so what a tip "
                              f"started from rest does needs integration; rtol {rtol:g} for tolerance {tolerance:g}")
        return integration
    integration.reason = (("a time series is asked" if "time_series" in outputs else
                            f"A = {model.damping:g} < A_c = {model.critical_damping:.6g}: stick-slip, whose swing "
                            "needs integration") + f"; rtol {rtol:g} for tolerance {tolerance:g}")
    return integration


def bistable_above(model: NanoscaleModel, point: HopfPoint | None) -> bool:
    """At or above A_c of a subcritical Hopf point (l_1 > 0) steady sliding is stable to small disturbances only:
    a large stick-slip cycle can coexist with it (measured: from rest, up to 1-5 % above A_c of a strongly charged
    model)."""
    return point is not None and not point.supercritical and not model.stick_slip


def hopf_domain(model: NanoscaleModel, point: HopfPoint | None, outputs=("regime", "force_swing"),
                anywhere: bool = False) -> str | None:
    """None where the Hopf normal form answers ``outputs``, else why not (a clause after the method's name).
    ``anywhere``: below any supercritical A_c (asked for by name, it answers farther off too, its error measured at A
    itself)."""
    if "time_series" in outputs:
        return "gives no time series"
    if point is None:
        return "needs a Hopf point, and steady sliding here loses stability without an oscillatory pair of roots"
    if not point.supercritical:
        return "needs a supercritical Hopf point, and this one is subcritical (l_1 > 0: its small cycle is unstable)"
    if not model.stick_slip:
        return (f"gives the small cycle below A_c = {point.critical_damping:.6g}, and A = {model.damping:g} is "
                "above it (the swing is 0: nanoscale_linear_stability)")
    ratio = growth_rate(model) / point.frequency
    if not ratio <= HOPF_REFERENCE and not anywhere:
        return (f"holds within sigma / omega_0 = {HOPF_REFERENCE:g} of the Hopf point, and here sigma / omega_0 = "
                f"{ratio:.3g}")
    return None


def damping_at_growth(model: NanoscaleModel, point: HopfPoint, ratio: float) -> float:
    """The damping below A_c where sigma / omega_0 = ``ratio`` (0 where sigma never reaches it there)."""
    from scipy.optimize import brentq  # heavy: imported where used

    target = ratio * point.frequency
    excess = lambda damping: growth_rate(with_damping(model, damping)) - target  # noqa: E731
    if not excess(0.0) > 0:  # sigma never reaches the target: the whole range below A_c is nearer the point
        return 0.0
    return brentq(excess, 0.0, point.critical_damping, xtol=1e-13 * point.critical_damping, rtol=1e-13)


def reference_damping(model: NanoscaleModel, point: HopfPoint) -> float:
    """The damping below A_c where sigma / omega_0 = HOPF_REFERENCE: the normal form's error is measured there."""
    return damping_at_growth(model, point, HOPF_REFERENCE)


def reference_model(model: NanoscaleModel, point: HopfPoint) -> NanoscaleModel:
    """The model whose settled cycle measures the normal form's error: at :func:`reference_damping`, or ``model``
    itself where it is farther from A_c than that (the normal form asked for by name)."""
    if growth_rate(model) / point.frequency > HOPF_REFERENCE:
        return model
    return with_damping(model, reference_damping(model, point))


def normal_form(model: NanoscaleModel, allow_large: bool = False,
                anywhere: bool = False) -> tuple["NanoscaleCycle | None", str]:
    """The small cycle below a supercritical A_c by its normal form (:mod:`faultslip.models.nanoscale.hopf`), its
    declared error measured on the scene: at :func:`reference_damping` a settled LSODA cycle gives the expansion's
    relative error e_ref (the largest of swing, period and least speed, plus that cycle's own), and the error at A
    is declared HOPF_SAFETY e_ref sigma(A) / sigma_ref. ``anywhere`` (asked for by name): farther from A_c than
    the reference, the error is measured at A itself and declared as measured, however large. Returns (cycle, '')
    or (None, why not)."""
    point = hopf_point(model)
    outside = hopf_domain(model, point, anywhere=anywhere)
    if outside:
        return None, outside
    reference = reference_model(model, point)
    far = reference is model
    measured = reference.settled_cycle(REFERENCE_TOLERANCE, allow_large=allow_large)
    where = ("its cycle at A itself, measured by LSODA," if far else
             f"its reference cycle at A = {reference.damping:.6g} (sigma / omega_0 = {HOPF_REFERENCE:g})")
    if not measured.settling.settled or (measured.regime != OSCILLATING and not anywhere):
        return None, (f"{where} {'did not settle' if not measured.settling.settled else measured.regime + 's'}, so "
                      "its error cannot be measured")
    expected = normal_form_cycle(reference, point)
    found = (measured.force_swing, measured.period, measured.least_speed)
    error = max(abs(ours / theirs - 1.0) for ours, theirs in zip(expected, found)) + measured.estimated_error
    if not error <= HOPF_LIMIT and not anywhere:
        return None, f"{where} is {error:.2g} off the normal form: the expansion does not hold there"
    declared = error if far else HOPF_SAFETY * error * growth_rate(model) / growth_rate(reference)
    swing, period, least = normal_form_cycle(model, point)
    settling = Settling(True, 0, math.nan, declared, np.array([swing, period, least]),
                        "the normal form's cycle, no integration at A")
    return NanoscaleCycle(swing, period, least, settling, measured.cycles, measured.restarts, measured.rtol, declared,
                          model, measured.integrated, hopf=(point.frequency, reference.damping, error)), ""


def settle(model: NanoscaleModel, choice: NanoscaleChoice, tolerance: float,
           allow_large: bool = False) -> tuple[NanoscaleChoice, "NanoscaleCycle | None"]:
    """The settled cycle ``choice`` gives: LSODA's, or the normal form's. ``auto``'s normal form that declares more
    than ``tolerance``, or cannot measure its error, hands over to LSODA, and the cycle declaring the smaller error
    is the answer; the normal form asked for by name that cannot measure its error says why."""
    if choice.method == "nanoscale_LSODA":
        return choice, model.settled_cycle(tolerance, rtol=choice.rtol, allow_large=allow_large)
    if choice.method != "nanoscale_hopf_normal_form":
        return choice, None
    asked = choice.reason == "requested"
    cycle, why = normal_form(model, allow_large, anywhere=asked)
    if cycle is not None and (asked or cycle.estimated_error <= tolerance):
        return replace(choice, estimated_error=cycle.estimated_error), cycle
    if asked:
        raise SolverError(f"nanoscale_hopf_normal_form cannot declare its error: {why}; use nanoscale_LSODA")
    integration = choose_method(model, ("regime", "force_swing"), "nanoscale_LSODA", tolerance)
    integrated = model.settled_cycle(tolerance, rtol=integration.rtol, allow_large=allow_large)
    said = (f"the normal form declared {cycle.estimated_error:.2g}, above the tolerance {tolerance:g}"
            if cycle is not None else f"the normal form declined ({why})")
    if cycle is not None and cycle.estimated_error < integrated.estimated_error:
        return replace(choice, estimated_error=cycle.estimated_error,
                       reason=f"{choice.reason}; {said}, and LSODA's settled cycle more "
                              f"({integrated.estimated_error:.2g})"), cycle
    integration.reason = f"{said}: LSODA at rtol {integration.rtol:g} for tolerance {tolerance:g}"
    return integration, integrated


def with_damping(model: NanoscaleModel, damping: float) -> NanoscaleModel:
    return replace(model, damping=damping)


def report(model: NanoscaleModel, run: NanoscaleRun | None = None, choice: NanoscaleChoice | None = None,
           title: str = "faultslip nanoscale stick-slip with contact charging (seed 001, eqs. 1-4)",
           cycle: NanoscaleCycle | None = None):
    """The threshold analysis, the settled cycle and the run's time series, as a Report (``faultslip
    nanoscale``, ``run``). The regime is what the settled cycle does (it sticks, oscillates without
    sticking, or slides steadily); without one, only what linear stability says."""
    r = Report(title)
    r.add("damping", model.damping, label="A").add("drive_speed", model.drive_speed, label="v_a")
    r.add("peak_speed", model.peak_speed, label="v_m").add("charging_time", model.charging_time, label="tau")
    r.add("charge_length", model.charge_length, label="a").add("charge_force", model.charge_force, label="f_ch")
    r.add("critical_damping", model.critical_damping, label="A_c (Routh-Hurwitz)")
    r.add("critical_damping_uncharged", replace(model, charge_force=0.0).critical_damping,
          label="A_c without charge, -phi'(v_a)")
    bistable = bistable_above(model, hopf_point(model))
    if cycle is not None:
        where = ("A < A_c" if model.stick_slip else "A >= A_c, from rest" if bistable else "A >= A_c")
        r.add("regime", f"{cycle.regime} ({where}; what the settled cycle does)")
    elif model.stick_slip:
        r.add("regime", "unstable_sliding (A < A_c): steady sliding is unstable; whether the tip sticks needs the "
                        "cycle (integration)")
    else:
        r.add("regime", "steady_sliding (A >= A_c)" + (": stable to small disturbances" if bistable else ""))
    if bistable:
        r.note("the Hopf point is subcritical (first Lyapunov coefficient l_1 > 0): above A_c steady sliding is "
               "stable to small disturbances only, and a large stick-slip cycle can coexist with it; the settled "
               "cycle is run from rest (nanoscale_LSODA)")
    roots = model.characteristic_roots()
    r.add("largest_growth_rate", float(np.max(roots.real)), label="largest Re(lambda) of small disturbances")
    error = None
    if choice is not None:
        r.add("method", choice.method).add("method_reason", choice.reason, label="why this method")
        error = choice.estimated_error
        if run is None and cycle is None and not model.stick_slip and not bistable:
            r.add("force_swing", 0.0, label="force peak-to-peak (steady sliding)")
    if cycle is not None and cycle.hopf is not None:
        frequency, reference, measured = cycle.hopf
        r.add("force_swing", cycle.force_swing, label="force peak-to-peak of the small cycle (normal form)")
        r.add("period", cycle.period, label="period of the small cycle, 2 pi / omega_0")
        r.add("least_speed", cycle.least_speed, label="least speed X' in the cycle (sticks below v_m)")
        r.add("hopf_reference_damping", reference, label="A where the normal form's error was measured")
        r.add("hopf_reference_error", measured, label="the normal form's error measured there (against LSODA)")
        error = cycle.estimated_error if error is None else max(error, cycle.estimated_error)
        r.note(f"the normal form of the supercritical Hopf point (omega_0 = {frequency:.6g}): the cycle grows as "
               f"sqrt(sigma); its error, {measured:.2g} at A = {reference:.6g} against a settled LSODA cycle, is "
               f"O(sigma), and declared {HOPF_SAFETY:g} x that scaled by sigma")
    elif cycle is not None:
        r.add("force_swing", cycle.force_swing, label="force peak-to-peak of the settled cycle (located extrema)")
        r.add("period", cycle.period, label="period of the settled cycle")
        r.add("least_speed", cycle.least_speed, label="least speed X' in the cycle (sticks below v_m)")
        r.add("settled", bool(cycle.settling.settled), label="the cycle settled")
        r.add("cycles", int(cycle.cycles), label="cycles integrated to settle")
        r.add("settle_time", cycle.integrated, label="model time integrated to settle (chunks of LSODA, in 1/omega)")
        error = cycle.estimated_error if error is None else max(error, cycle.estimated_error)
        if not cycle.settling.settled:
            r.note(f"the cycle did not settle: {cycle.settling.reason}")
        if cycle.restarts:
            r.note(f"the cycle map was restarted {cycle.restarts} times from its extrapolated fixed point (Steffensen)")
        if cycle.refined_from is not None:
            r.note(f"LSODA's error in the swing scales with the force, not the swing: at rtol {cycle.refined_from:g} "
                   f"it missed the tolerance in this swing, so the settled cycle was run on at rtol {cycle.rtol:g}")
    if run is not None:
        r.add("duration", float(run.time[-1]))
        r.add("run_force_swing", run.force_swing(), label="force peak-to-peak of the run's last cycle")
        r.add("slip_events", run.slip_events(), label="slip events (X' through 2 v_a), last half")
        deposited = run.deposited[-1] / max(run.displacement[-1], 1e-300)
        r.add("deposited_per_displacement", float(deposited), label="Sigma_d / X at the end (Sigma*/a steady)")
        r.add("charge_correlation", run.charge_correlation(), label="corr(X, Sigma_d)")
        if cycle is None and not model.stick_slip:
            r.add("force_swing", 0.0, label="force peak-to-peak (steady sliding: disturbances decay, A >= A_c)")
        elif cycle is None:
            verdict = run.settling(choice.estimated_error if choice is not None and choice.estimated_error else 1e-6)
            r.add("force_swing", run.force_swing(), label="force peak-to-peak of the run's last cycle")
            r.add("settled", bool(verdict.settled), label="the run's cycles settled")
            if model.stick_slip:
                error = settled_error(error or 0.0, verdict.remaining) if verdict.cycles >= 2 else math.inf
                if not verdict.settled:
                    r.note(f"the run's cycles have not settled: {verdict.reason}; its swing is a transient")
    if error is not None:
        r.add("estimated_relative_error", error, label="estimated relative error (force swing)")
    near = bifurcation_note("the critical damping A_c", "A", model.damping, model.critical_damping)
    if near and (run is not None or (cycle is not None and cycle.hopf is None)):  # a note on integrated cycles
        r.note(near)
    r.note("dimensionless: displacement in the slip scale D, time in 1/omega; the slides' parameters unless set")
    return r


def run_dataset(run: NanoscaleRun):
    """The run as a CF dataset (dimensionless variables)."""
    import xarray as xr  # heavy: imported where used

    dims = ("time",)
    model = run.model
    return xr.Dataset(
        {"displacement": (dims, run.displacement, {"units": "1", "long_name": "tip displacement X (in D)"}),
         "speed": (dims, run.speed, {"units": "1", "long_name": "tip speed X'"}),
         "force": (dims, run.force, {"units": "1", "long_name": "spring force F"}),
         "charge": (dims, run.charge, {"units": "1", "long_name": "contact charge Sigma"}),
         "deposited_charge": (dims, run.deposited, {"units": "1", "long_name": "charge deposited Sigma_d"})},
        coords={"time": (dims, run.time, {"units": "1", "long_name": "time in 1/omega"})},
        attrs={"title": "faultslip nanoscale model (seed 001 eqs. 1-4)", "Conventions": "CF-1.8",
               **{key: float(getattr(model, key)) for key in SLIDES}})
