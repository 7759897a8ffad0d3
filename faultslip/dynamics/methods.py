"""Solution methods behind one interface, and the automatic choice: model no more than a scene needs.

Every method declares its name, the friction laws it supports, its domain of validity, an error
model and a cost model. :func:`choose` ranks the applicable methods by estimated cost and picks the
cheapest whose estimated error meets the requested tolerance; :func:`solve` runs it and records the
method, the reason and the estimated error. Forcing a method outside its domain warns and names the
better one.

Error models (relative, leading order; checked against measurements in the tests):

* closed form: ``1.5 (2 |zeta| eps + eps^2)`` with ``eps = theta_dot / (omega_n (mu_s - mu_m))``, trusted
  only for ``eps <= 0.1 eps_c(zeta)``: the expansion breaks down near the critical rate and the
  closed form reports stick-slip above it;
* exact cycle: round-off (1e-14), amplified near the critical rate as ``machine eps / sqrt(1 - eps/eps_c)``;
* event-driven integration: ``c_solver * rtol``, with c measured by ``faultslip bench``
  (RK45 2, DOP853 1, Radau 1, LSODA 60; LSODA's error control is loose);
* regularised friction: not trusted (it never truly sticks); run only when forced.

Cost models (seconds, order of magnitude, from the benchmarks): closed form ~2e-5, exact cycle
~2e-4, event-driven ``cycles * nfev_per_slip(solver, rtol) * t_eval``, where the cycles of a steady-cycle run
are those it takes to settle (:func:`settling_cycles`).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass

import numpy as np

from faultslip.dynamics.shared.assessment import Assessment
from faultslip.dynamics.shared.settling import bifurcation_note, settled_error
from faultslip.dynamics import vibration as averaging
from faultslip.dynamics.spring_slider.closed_form import closed_form_cycle
from faultslip.dynamics.spring_slider.critical import cached_critical_dimensionless_rate
from faultslip.dynamics.shared.cycle import STEADY_SLIDING, CycleResult
from faultslip import ranges
from faultslip.errors import EvaluationBudgetError, InputError, MethodError, OutOfDomainWarning
from faultslip.io import budget
from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle, exact_cycle_error
from faultslip.dynamics.spring_slider.regularized import simulate_regularized
from faultslip.dynamics.spring_slider.simulate import (BREAK_AWAY_ROUND_OFF, SETTLING_CYCLES, SETTLING_WINDOW,
                                                       SUSTAINED_OSCILLATION, check_break_away, declared_slip_error,
                                                       simulate)

DEFAULT_TOLERANCE = 1e-6
OUTPUTS = ("amplitude", "period", "event_times", "time_series")
#: Event-driven integrators' right-hand-side evaluations per slip phase on a linear kinetic law at rtol = 1e-3, 1e-6,
#: 1e-9, 1e-12 (the declared error: simulate.declared_slip_error): the median over the 137 linear-law scenes of
#: bench.random_scenes' calibration seeds, 10 cycles a run, to two figures (benchmarks/integrator_evaluations.py;
#: test_methods holds it to benchmarks/results/integrator_evaluations.json). Re-derived once slip phases were integrated
#: about the kinetic equilibrium; LSODA's count at 1e-12 is bimodal (quartiles 216 and 609).
INTEGRATOR_EVALUATIONS = {
    "DOP853": (62, 92, 150, 300),
    "RK45": (38, 120, 400, 1600),
    "LSODA": (50, 100, 160, 320),
    "Radau": (58, 250, 1400, 7900),
}
INTEGRATOR_EVALUATION_TIME = {"DOP853": 2.0e-5, "RK45": 2.0e-5, "LSODA": 2.5e-5, "Radau": 5.0e-5}
#: An explicit solver's stages a step and its stability limit on the negative real axis (h |lambda| at most this;
#: Hairer & Wanner, Solving ODEs II, IV.2): where the slip phase is stiff its steps are these, not its accuracy's.
EXPLICIT_STABILITY = {"DOP853": (12, 6.0), "RK45": (6, 3.3), "RK23": (3, 2.5)}
RTOL_LEVELS = tuple(10.0 ** -k for k in range(3, 13))  # 1e-3 ... 1e-12


@dataclass
class Solution:
    """The answer of :func:`solve`: cycle quantities, event times and how they were obtained."""

    cycle: CycleResult
    event_times: np.ndarray
    method: str
    method_reason: str
    estimated_relative_error: float
    settings: dict
    dataset: object = None  # the time series, when requested or simulated
    function_evaluations: int = 0
    wall_time: float = 0.0

    def to_xarray(self):
        """The cycle's numbers with their units (:meth:`CycleResult.to_xarray`), the event times on ``event``, the
        method and its declared error as attributes, and the time series where the solve kept one."""
        import xarray as xr  # heavy: imported where used

        dataset = self.cycle.to_xarray()
        dataset["event_time"] = xr.Variable(("event",), np.asarray(self.event_times, float),
                                            {"long_name": "event time", "units": "s"})
        dataset.attrs.update(method=self.method, method_reason=self.method_reason,
                             estimated_relative_error=float(self.estimated_relative_error))
        if self.dataset is not None:
            dataset = xr.merge([dataset, self.dataset], combine_attrs="override")
        return dataset

    def report(self, title: str):
        report = self.cycle.report(title)
        report.items[0].value = self.method
        report.add("method_reason", self.method_reason, label="why this method")
        report.add("estimated_relative_error", self.estimated_relative_error, label="estimated relative error")
        if self.settings:
            report.add("method_settings", ", ".join(f"{k}={v}" for k, v in self.settings.items()), label="settings")
        # what the run itself found (a re-stick recomputed, a fallback integrator, Steffensen restarts)
        attrs = {} if self.dataset is None else self.dataset.attrs
        for note in filter(None, attrs.get("regime_verification", "").split("\n")):
            report.note(note)
        return report


def _linear_rate_system(system) -> str | None:
    """None if the closed form / exact cycle can describe the system, else why not."""
    if not system.is_linear:
        return f"kinetic law {type(system.kinetic_law).__name__} is not linear in sliding speed"
    if system.static_excess is None:
        return "static friction depends on the time of stick (each cycle depends on the last)"
    if system.static_excess <= 0:
        return "mu_s does not exceed mu_m: there is no stick-slip"
    if not -1 < system.damping_ratio < 1:
        return f"damping ratio {system.damping_ratio:.3g} is outside (-1, 1): the slip phase does not oscillate"
    return None


class Method:
    name = "method"
    friction_laws = ""
    domain = ""
    cost_model = ""
    declared_error = ""
    #: the modules its run imports where it runs (faultslip.io.budget.Estimate.imports): none, in closed form
    imports: tuple = ()

    def assess(self, system, outputs, tolerance, cycles) -> Assessment:  # pragma: no cover - interface
        raise NotImplementedError

    def run(self, system, cycles, settings):  # pragma: no cover - interface
        raise NotImplementedError

    #: how a method that ``faultslip run`` does not take is reached (None: run takes it by its name)
    selected_by: str | None = None

    def describe(self) -> dict:
        row = {"name": self.name, "friction_laws": self.friction_laws, "domain": self.domain,
               "cost_model": self.cost_model, "declared_error": self.declared_error}
        return row if self.selected_by is None else row | {"run_method": None, "selected_by": self.selected_by}


class ClosedForm(Method):
    name = "closed_form"
    friction_laws = "rate-law or constant static friction; constant or linear kinetic friction"
    domain = "|zeta| < 1 and eps <= 0.1 eps_c(zeta) (well below the critical loading rate); no time series"
    cost_model = "O(1): about 2e-5 s per scene, 1e-8 s per cell vectorised"
    declared_error = "1.5 (2 |zeta| eps + eps^2), the expansion's next order with a safety factor (measured below 1.5x)"

    #: The expansion is leading order; within eps <= 0.1 eps_c the true error stays below 1.5 times it.
    SAFETY = 1.5

    @staticmethod
    def error_model(damping_ratio, eps):
        """Relative error of amplitude and period to leading order: 2 |zeta| eps + eps^2."""
        return 2.0 * np.abs(damping_ratio) * eps + eps * eps

    def assess(self, system, outputs, tolerance, cycles):
        why_not = _linear_rate_system(system)
        if why_not:
            return Assessment(self.name, False, why_not)
        if "time_series" in outputs:
            return Assessment(self.name, False, "the closed form gives no time series")
        eps, zeta = system.dimensionless_rate, system.damping_ratio
        eps_c = cached_critical_dimensionless_rate(zeta) if zeta > 0 else math.inf
        if eps > 0.1 * eps_c:
            where = "above" if eps >= eps_c else "near"
            return Assessment(self.name, False, f"loading rate is {where} the critical rate (eps = {eps:.3g}, "
                              f"eps_c = {eps_c:.3g}): the closed form's expansion fails there")
        error = self.SAFETY * (2.0 * abs(zeta) * eps + eps * eps)  # error_model, on plain floats
        if "event_times" in outputs:
            error *= max(cycles, 1)  # the period error accumulates over the cycles
        where = f"far below eps_c = {eps_c:.3g}" if math.isfinite(eps_c) else "with no critical rate (zeta <= 0)"
        return Assessment(self.name, True, f"eps = theta_dot/(omega_n dmu_s) = {eps:.3g}, {where}; "
                          f"error model 1.5 (2|zeta| eps + eps^2) = {error:.2g}", error, 2e-5)

    def run(self, system, cycles, settings):
        cycle = closed_form_cycle(system)
        first = (system.normal_load * cycle.static_friction / system.stiffness) / system.platform_speed
        return cycle, first + cycle.period * np.arange(cycles), None, 0


class ExactCycle(Method):
    name = "exact_cycle"
    friction_laws = "rate-law or constant static friction; constant or linear kinetic friction"
    domain = "|zeta| < 1; any loading rate (reports steady sliding above the critical rate)"
    cost_model = "about 2e-4 s per scene (5e-3 s with a 100-cycle time series), 1-2 us per cell vectorised"
    declared_error = "round-off of the closed-form piecewise solution (about 1e-12), and the settling left where it settles"

    def assess(self, system, outputs, tolerance, cycles):
        why_not = _linear_rate_system(system)
        if why_not:
            return Assessment(self.name, False, why_not)

        cost = 2e-4 + (5e-5 * cycles if "time_series" in outputs else 0.0)
        zeta, eps = system.damping_ratio, system.dimensionless_rate
        eps_c = cached_critical_dimensionless_rate(zeta) if zeta > 0 else math.inf
        error = float(exact_cycle_error(eps, eps_c))
        return Assessment(self.name, True, "linear kinetic law: the slip phase is solved analytically",
                          error, cost)

    def run(self, system, cycles, settings):

        cycle = exact_cycle(system)
        if settings.get("time_series") or cycle.regime == STEADY_SLIDING:
            dataset = simulate(system, cycles=cycles, slip_solver="analytic")
            return cycle, dataset["event_time"].values, dataset, 0
        first = (system.normal_load * cycle.static_friction - system.dashpot * system.platform_speed) \
            / system.stiffness / system.platform_speed
        return cycle, first + cycle.period * np.arange(cycles), None, 0


class ExactMap(Method):
    """Analytic slip phases and a root-found stick for a static friction that grows with the time of
    stick (Cameron's law): each cycle is the one-dimensional map of the re-stick position, iterated
    with Steffensen restarts until :func:`~faultslip.dynamics.shared.settling.assess_settling` finds
    the steady cycle settled (issue 27: near V_c = c alpha_m the natural approach takes thousands of
    cycles)."""

    imports = (*budget.DATASET_IMPORTS, "scipy.optimize")  # the analytic simulation's Dataset, its roots
    name = "exact_map"
    friction_laws = "time-of-stick static friction; constant or linear kinetic friction"
    domain = "|zeta| < 1; any loading rate (the settled cycle decides stick-slip or steady sliding)"
    cost_model = "about 0.5 ms per cycle, 4-33 cycles to settle with Steffensen restarts (more as V nears V_c)"
    declared_error = "the distance to the settled cycle the settling test measures (geometric tail, or the scatter)"

    def assess(self, system, outputs, tolerance, cycles):
        if not system.is_linear:
            return Assessment(self.name, False, f"kinetic law {type(system.kinetic_law).__name__} is not linear "
                              "in sliding speed: the slip phase has no closed form")
        if not system.static_law.depends_on_stick_time:
            return Assessment(self.name, False, "static friction does not depend on the stick time: every cycle "
                              "is the same, the exact cycle solves it directly")
        if not -1 < system.damping_ratio < 1:
            return Assessment(self.name, False, f"damping ratio {system.damping_ratio:.3g} is outside (-1, 1)")
        reason = ("linear kinetic law with time-of-stick static friction: analytic slip phases, the steady cycle by "
                  "Steffensen iteration of the re-stick map")
        near = _near_cameron_critical_speed(system)
        # 0.5 ms a cycle and as much to start: benchmarks/lab_cycle_cost.py (it had been 1 ms and 1.5 ms a cycle)
        return Assessment(self.name, True, f"{reason}; {near}" if near else reason, SETTLED_ERROR,
                          5e-4 + 5e-4 * settling_cycles(system, outputs, cycles, steady_above_critical=True))

    def run(self, system, cycles, settings):
        dataset = simulate(system, cycles=cycles, slip_solver="analytic", stop_when_converged=settings.get("converge"))
        return _cycle_from_dataset(system, dataset, self.name), dataset["event_time"].values, dataset, 0


def _cameron_critical_speed(system) -> float | None:
    """Cameron's V_c = c alpha_m (seed 002 eq. 9 as alpha -> 0, alpha_m = 2 W (mu_u - mu_k) / K), m/s, where
    eq. 9 holds (undamped, constant kinetic friction); None elsewhere."""
    law, kinetic = system.static_law, system.kinetic_law
    if not all(hasattr(law, key) for key in ("mu_upper", "growth_rate")) or not hasattr(kinetic, "mu_m") or \
            system.damping_ratio != 0 or getattr(kinetic, "slope", 0.0):
        return None
    return law.growth_rate * 2 * system.normal_load * (law.mu_upper - kinetic.mu_m) / system.stiffness


def _near_cameron_critical_speed(system) -> str | None:
    """Cameron's V_c, named when the platform speed is within 10 % of it."""
    critical = _cameron_critical_speed(system)
    if critical is None:
        return None
    return bifurcation_note("Cameron's critical speed V_c = c alpha_m", "V", system.platform_speed, critical, "m/s")


#: Cycles a time-of-stick slider's steady-cycle run takes where Cameron's V_c is not known (4-8 measured on the
#: damped random Cameron scenes of faultslip.evaluation.bench.random_scenes, seeds 101-1203).
TIME_OF_STICK_CYCLES = 6
#: A curved kinetic law's slip phase takes (a + b min(eps, c)) times a linear law's evaluations at the same rtol:
#: fitted on the polynomial laws of bench.random_scenes seeds 101-606 (24 runs, 0.9-15 times), held out on 707-1203
#: (30 runs: 24 within 2x of the CPU used; a linear law's count is 0.74-1.1 times the calibration's). Past eps ~ 2
#: the phase is stiff: LSODA's count stops growing (500 a phase at eps 1,700), an explicit solver's is its stability.
CURVED_LAW_EVALUATIONS = (2.0, 2.0, 2.0)


def settling_cycles(system, outputs, cycles: int, steady_above_critical: bool = False) -> float:
    """The cycles a run of ``cycles`` takes: all of them where events or a time series are wanted; else those it
    takes to settle (:func:`~faultslip.dynamics.spring_slider.simulate.simulate`, ``stop_when_converged``).

    A static friction that does not depend on the stick time breaks away at the same stress every cycle: the
    settling test's first window (:data:`SETTLING_WINDOW` cycles) finds it settled. A time-of-stick law's re-stick
    map contracts more slowly as the speed nears Cameron's V_c; with Steffensen restarts its run takes
    ``4 (1 + log2 1 / |1 - V / V_c|)`` cycles (measured 4, 8, 16, 24, 32 at 0.05, 0.3, 0.8, 0.95, 0.99 V_c
    on configs/lab_steel_dry_time_of_stick.toml), :data:`TIME_OF_STICK_CYCLES` where V_c is not known (damped). Above
    V_c the exact map settles on steady sliding (9-33 cycles measured, the same rule); an integrator's slip
    phases graze re-stick there and do not settle (``steady_above_critical`` False): every cycle the run allows,
    :data:`SETTLING_CYCLES` at least.

    Parameters
    ----------
    system : SliderSystem
        The slider.
    outputs : iterable of str
        What is wanted (``event_times`` and ``time_series`` run every cycle).
    cycles : int
        The cycles asked for.
    steady_above_critical : bool
        Whether the method settles on steady sliding above V_c (the exact map does).

    Returns
    -------
    float
        Cycles.
    """
    if {"time_series", "event_times"} & set(outputs):
        return float(max(cycles, 1))
    if not system.static_law.depends_on_stick_time:
        return float(SETTLING_WINDOW)
    critical = _cameron_critical_speed(system)
    if critical is None:
        return float(TIME_OF_STICK_CYCLES)
    ratio = system.platform_speed / critical
    if ratio >= 1 and not steady_above_critical:
        return float(max(cycles, SETTLING_CYCLES))
    gap = max(abs(1 - ratio), 2.0 ** -(SETTLING_CYCLES / SETTLING_WINDOW))
    return float(min(SETTLING_WINDOW * (1 + max(math.log2(1 / gap), 0.0)), max(cycles, SETTLING_CYCLES)))


#: The exact map's own error once settled: its stick root is found to ~1e-12 relative.
SETTLED_ERROR = 1e-10


#: A law the event-driven calibration never drew (laws.py ``error_calibrated``) is run twice, at rtol and at
#: rtol / REFINEMENT, and declares at least REFINEMENT_FACTOR times their largest relative difference over
#: CHECKED_OUTPUTS. On rough-surface scenes (seed 000's tabulated law: kinks at its 80 knots, and stress drops a
#: fifth of the slip) the calibrated error had been exceeded up to 5.6x on the amplitude and period and 135x on
#: the stress drop. Twice the difference held on 480 runs of 24 such scenes (4 solvers, tolerances 1e-3 to 1e-7)
#: with the largest error 0.71 of it; three times it is the margin of 1.5 the calibrations keep
#: (benchmarks/refinement_check.py measures it, on a held-out draw too).
REFINEMENT = 100.0
REFINEMENT_FACTOR = 3.0
FINEST_RTOL = 1e-13
CHECKED_OUTPUTS = ("amplitude", "period", "stress_drop", "peak_slip_speed", "slip_per_event")


def refined_rtol(rtol: float) -> float:
    """The check run's rtol: a hundredth of the run's, no finer than 1e-13 (round-off)."""
    return max(rtol / REFINEMENT, FINEST_RTOL)


#: A stress drop under this share of the slip's swing is a graze (seed 000's slider at c = 0 touches zero speed
#: once a period, its drop zero): the drop is zero to within the solver's position error, which at a tangency is
#: of order sqrt(rtol), and has no relative error to declare; its difference is said in force units instead.
GRAZE_SHARE = 1e-3


def _grazes(cycle) -> bool:
    return abs(cycle.stress_drop_slip) < GRAZE_SHARE * abs(cycle.amplitude)


def refinement_difference(coarse, fine) -> tuple[float, float | None]:
    """Two runs' largest relative difference over CHECKED_OUTPUTS (inf where one is missing), and where both
    runs' stress drops are grazes (:data:`GRAZE_SHARE`), their absolute difference (N in the lab, Pa on a fault;
    else None)."""
    graze = _grazes(coarse) and _grazes(fine)
    worst = 0.0
    for name in CHECKED_OUTPUTS:
        if graze and name == "stress_drop":
            continue
        a, b = getattr(coarse, name), getattr(fine, name)
        if not (math.isfinite(a) and math.isfinite(b)):
            if a != b and not (math.isnan(a) and math.isnan(b)):
                return math.inf, None
            continue
        scale = abs(b)
        worst = max(worst, abs(a - b) / scale if scale > 0 else (0.0 if a == b else math.inf))
    return worst, abs(coarse.stress_drop - fine.stress_drop) if graze else None


def integrator_evaluations(solver: str, rtol: float) -> float:
    """Right-hand-side evaluations per slip phase, interpolated in log rtol from the calibration."""
    levels = np.log10([1e-3, 1e-6, 1e-9, 1e-12])
    counts = np.log10(INTEGRATOR_EVALUATIONS[solver])
    return float(10 ** np.interp(-np.log10(rtol), -levels, counts))


def slip_stiffness(system) -> float:
    """The slip phase's stiffness in the natural time omega t: (c + W max|mu'(u)|) / (M omega) over sliding speeds
    from 0 to 2V (seed 002's eps, :meth:`~faultslip.dynamics.vibration.QuasiHarmonic.small_parameter` at the
    amplitude V / omega). A polynomial curve at 10 m/s reaches 1,700: an explicit solver's steps are then
    stability-limited (DOP853 took 1.8 million evaluations where LSODA took 500). 0 where the kinetic law is
    not a curve of speed alone."""
    try:
        averaged = averaging.from_slider(system)
        return float(averaged.small_parameter(system.platform_speed / averaged.angular_frequency))
    except (InputError, TypeError, ValueError, ArithmeticError):
        return 0.0


def nearest_calibrated(solver: str) -> str:
    """The calibrated integrator nearest in kind (RK23 as RK45, BDF as Radau; the calibrated ones as themselves)."""
    return {"RK23": "RK45", "BDF": "Radau"}.get(solver, solver)


def evaluation_time(solver: str) -> float:
    """Seconds a right-hand-side evaluation, on the machine the families' costs were fitted on
    (:data:`INTEGRATOR_EVALUATION_TIME`, at :func:`nearest_calibrated`)."""
    return INTEGRATOR_EVALUATION_TIME[nearest_calibrated(solver)]


def stiff_evaluations(solver: str, stiffness: float) -> float:
    """Evaluations an explicit solver spends a natural period where the slip phase is stiff: stages x 2 pi x
    stiffness / stability limit (:data:`EXPLICIT_STABILITY`); 0 for the stiff solvers (LSODA switches, Radau is
    implicit)."""
    if solver not in EXPLICIT_STABILITY:
        return 0.0
    stages, limit = EXPLICIT_STABILITY[solver]
    return stages * 2 * math.pi * stiffness / limit


def slip_phase_evaluations(system, solver: str, rtol: float, stiffness: float | None = None) -> tuple[float, float]:
    """(accurate, stability-limited) right-hand-side evaluations of one slip phase: the calibration's count at rtol
    (:func:`integrator_evaluations`, of the nearest calibrated solver), times (2 + 2 min(eps, 2)) on a curved
    kinetic law (:data:`CURVED_LAW_EVALUATIONS`), and an explicit solver's steps at its stability limit over a
    natural period (:func:`stiff_evaluations`). ``stiffness`` is eps where already computed."""
    stiffness = slip_stiffness(system) if stiffness is None else stiffness
    accurate = integrator_evaluations(nearest_calibrated(solver), rtol)
    if not system.is_linear:  # a curved law's phase takes more steps than the linear calibration's
        base, slope, cap = CURVED_LAW_EVALUATIONS
        accurate *= base + slope * min(stiffness, cap)
    return accurate, stiff_evaluations(solver, stiffness)


class EventDriven(Method):
    imports = (*budget.DATASET_IMPORTS, *budget.INTEGRATION_IMPORTS)
    friction_laws = "any static law (rate, constant, time-of-stick); any kinetic law"
    domain = "everything the model describes (no reverse slip); error c rtol^q + floor"
    cost_model = ("cycles x evaluations per slip phase (grows as rtol tightens, (2 + 2 min(eps, 2)) times on a "
                  "curved kinetic law; for DOP853 and RK45, also as the slip phase's stiffness, stages x 2 pi x eps / "
                  "their stability limit) x ~2e-5 s; a steady cycle's run counts the cycles it takes to settle (4 "
                  "where static friction does not depend on the stick time)")
    declared_error = ("c rtol^q + floor per solver, fitted on random scenes against the exact cycle "
                      "(benchmarks/event_driven_calibration.py; faultslip bench checks it on held-out ones), "
                      "and the settling left; on a kinetic law the calibration never drew (a table, a callable), "
                      "at least 3 times the difference from a run at rtol / 100 (benchmarks/refinement_check.py)")

    def __init__(self, solver: str = "DOP853"):
        self.solver = solver
        self.name = f"event_driven_{solver}"

    def assess(self, system, outputs, tolerance, cycles, rtol=None):
        if system.static_excess is not None and system.static_excess < -BREAK_AWAY_ROUND_OFF * system.mu_m:
            return Assessment(self.name, False, f"mu_s ({system.rate_static_friction:.5g}) is below the kinetic "
                                                f"friction at zero sliding speed ({system.mu_m:.5g}): the slider "
                                                "cannot start to slip, so there is no stick-slip")
        # event times drift by the slip phases' error once a cycle
        drift = max(cycles, 1) if "event_times" in outputs else 1.0
        if rtol is None:  # the loosest calibrated rtol that meets the tolerance
            fitting = [r for r in RTOL_LEVELS if declared_slip_error(self.solver, r) * drift <= tolerance]
            rtol = fitting[0] if fitting else RTOL_LEVELS[-1]
        error = declared_slip_error(self.solver, rtol) * drift
        stiffness = slip_stiffness(system)
        accurate, limited = slip_phase_evaluations(system, self.solver, rtol, stiffness)
        evaluations = accurate + limited
        if not system.error_calibrated:  # checked by a second run at a hundredth of the rtol (refinement_check)
            evaluations += accurate * integrator_evaluations(self.solver, refined_rtol(rtol)) / \
                integrator_evaluations(self.solver, rtol) + limited
        # a steady-cycle run stops once settled: its cycles, not every one it may take (200 had been counted)
        cost = 1e-3 + settling_cycles(system, outputs, cycles) * evaluations * INTEGRATOR_EVALUATION_TIME[self.solver]
        stiff = (f"; its slip phase is stiff (eps = {stiffness:.3g}): about {evaluations:.3g} evaluations a phase"
                 if limited > accurate else "")
        return Assessment(self.name, True, f"{self.solver} at rtol = {rtol:g} (error <= "
                          f"{declared_slip_error(self.solver, rtol):.2g} at that rtol){stiff}",
                          error, cost, {"slip_solver": self.solver, "rtol": rtol})

    def run(self, system, cycles, settings):

        converge = settings.get("converge")
        # the evaluations the time budget affords: past them the run stops and says why, not hours later
        affordable = int(budget.time_budget() / evaluation_time(self.solver))
        try:
            dataset = simulate(system, cycles=cycles, slip_solver=self.solver, rtol=settings["rtol"],
                               stop_when_converged=converge, max_evaluations=affordable)
        except EvaluationBudgetError as error:
            raise EvaluationBudgetError(
                f"{self.name} would pass the time budget ({affordable:.3g} evaluations): {error}; the slip phase's "
                f"stiffness is eps = {slip_stiffness(system):.3g}, and an implicit solver (event_driven_LSODA or "
                "event_driven_Radau) steps a stiff phase in far fewer evaluations") from None
        return _cycle_from_dataset(system, dataset, self.name), dataset["event_time"].values, dataset, \
            dataset.attrs["function_evaluations"]


class Regularized(Method):
    imports = budget.INTEGRATION_IMPORTS
    friction_laws = "rate-law or constant static friction; any kinetic law (smoothed by tanh(u/w))"
    domain = "none trusted: it never truly sticks (creep ~ w) and must step through every stick phase"
    cost_model = "stiff: steps through stick phases; explicit solvers exceed any budget at large stick/slip ratios"
    declared_error = "none: a smoothed model (creep of order the width w), measured against the exact cycle only"

    def __init__(self, solver: str = "LSODA", width_ratio: float = 1e-3):
        self.solver, self.width_ratio = solver, width_ratio
        self.name = f"regularized_{solver}"
        self.selected_by = (f"a baseline the methods are measured against, not a run method: "
                            f"faultslip.dynamics.methods.solve(system, method={self.name!r}) runs it (with a warning "
                            "that it is out of its domain); 'faultslip bench' and 'faultslip stability' measure the "
                            "regularised baselines they list")

    def assess(self, system, outputs, tolerance, cycles):
        return Assessment(self.name, False, "regularised friction never truly sticks; it is a baseline to measure "
                          "against, not a method to choose")

    def run(self, system, cycles, settings):

        result = simulate_regularized(system, cycles, self.width_ratio * system.platform_speed, self.solver,
                                      rtol=settings.get("rtol", 1e-8))
        cycle = CycleResult(self.name, result["regime"], system.loading_rate, system.platform_speed, math.nan,
                            system.damping_ratio, math.nan,
                            float(result["amplitude"][-1]) if result["amplitude"].size else math.nan, math.nan,
                            math.nan, math.nan, float(result["period"][-1]) if result["period"].size else math.nan,
                            math.nan, math.nan, system.scale)
        return cycle, result["event_time"], None, result["evaluations"]


class SeedAppendixI(Method):
    """Seed 003 eq. I-22: the critical loading rate is its output, not a cycle."""

    name = "seed_appendix_I"
    friction_laws = "rate-law static friction; constant or linear kinetic friction"
    domain = "an approximation: agrees with the exact critical rate only near zeta 0.2-0.25 and has the opposite trend in damping"
    cost_model = "one scalar root: about 1e-5 s"
    declared_error = "none as a cycle method; its critical rate is off by the trend seed 003's appendix I admits"
    selected_by = "its critical loading rate, not a cycle: 'faultslip critical SCENE' prints it beside the exact one"

    def assess(self, system, outputs, tolerance, cycles):
        return Assessment(self.name, False, "gives a critical loading rate, not a stick-slip cycle; see faultslip critical")

    def run(self, system, cycles, settings):
        raise MethodError("seed_appendix_I gives only the critical loading rate; use faultslip critical")


class QuasiHarmonicAveraging(Method):
    """Seed 002's averaging (faultslip.dynamics.vibration) for a slider that, once broken away, never
    sticks again: a sustained quasi-harmonic oscillation or steady sliding."""

    imports = budget.INTEGRATION_IMPORTS  # its envelope's quadrature and root search
    name = "quasi_harmonic_averaging"
    friction_laws = "any kinetic law (polynomial in closed form, others by quadrature); rate or constant static law"
    domain = ("after break-away eq. (20) brings the amplitude below V / omega by the next velocity peak (else the "
              "slider sticks again: stick-slip, hand over), and the cycle it settles on stays 0.15 eps below it; "
              "no events, no time series; error 0.1 eps^2")
    cost_model = "an envelope over one period and a root search: about 2e-3 s"
    declared_error = "0.1 eps^2 relative (measured 0.010-0.049 eps^2 against integration)"

    def assess(self, system, outputs, tolerance, cycles):
        if {"event_times", "time_series"} & set(outputs):
            return Assessment(self.name, False, "averaging gives the settled amplitude and period, not events or a "
                                                "time series")
        if system.static_excess is None:
            return Assessment(self.name, False, "static friction depends on the time of stick")
        if getattr(system.kinetic_law, "holds_peak", False):
            return Assessment(self.name, False, "friction depends on the slip's history (separation held past the "
                                                "peak speed); averaging needs a curve mu(u)")
        if system.static_excess <= 0:
            return Assessment(self.name, False, "mu_s does not exceed mu_m: no break-away to start from")
        averaged = averaging.from_slider(system)
        start = averaging.after_break_away(system, averaged)
        if start["marginal"]:
            return Assessment(self.name, False, f"{start['reason']}; the event-driven methods decide")
        if start["sticks"]:
            return Assessment(self.name, False, f"{start['reason']}: the slider sticks again (stick-slip)")
        # from break-away the envelope starts high: it settles where eq. (20) carries that amplitude, which on a
        # subcritical slider (steady sliding stable) can be a cycle rather than steady sliding
        result = averaged.analyse(start=start["after_one_period"])
        if result.marginal:
            return Assessment(self.name, False, f"{result.notes[0]}; the event-driven methods decide")
        if not result.valid:
            return Assessment(self.name, False, result.notes[0] if result.notes else "the slider sticks")
        eps = averaged.small_parameter(result.amplitude)
        error = averaging.ERROR_CONSTANT * eps ** 2 if result.amplitude > 0 else 0.0
        settles = (f"settles on a quasi-harmonic cycle A = {result.amplitude:.4g} m" if result.amplitude > 0
                   else "decays to steady sliding")
        return Assessment(self.name, True, f"{start['reason']}; it {settles} (eps = {eps:.3g}, error model "
                                           f"0.1 eps^2 = {error:.2g})", error, 2e-3)

    def run(self, system, cycles, settings):
        averaged = averaging.from_slider(system)
        result = averaged.analyse(start=averaging.after_break_away(system, averaged)["after_one_period"])
        omega = averaged.angular_frequency
        amplitude = result.amplitude
        regime = SUSTAINED_OSCILLATION if amplitude > 0 else STEADY_SLIDING
        nan = math.nan
        cycle = CycleResult(
            self.name, regime, system.loading_rate, system.platform_speed, system.rate_static_friction,
            system.damping_ratio, system.dimensionless_rate if system.dimensionless_rate is not None else nan,
            2.0 * amplitude, nan, 0.0, math.inf, 2.0 * math.pi / omega if amplitude > 0 else math.inf,
            system.platform_speed + amplitude * omega, nan, system.scale,
            extra={"quasi_harmonic_amplitude": (amplitude, "m", "averaged amplitude A (seed 002 eq. 20)"),
                   "small_parameter": (result.small_parameter, None, "eps = (C + W max|f'|) / (M omega)")})
        return cycle, np.array([]), None, 0


def describe_seed_methods() -> list[dict]:
    """The seed law's methods as ``faultslip methods`` lists them (name, friction laws, domain, cost model):
    the spring-slider family's (faultslip.contract.method_rows gathers every family's)."""
    return [m.describe() for m in (CLOSED_FORM, EXACT, *INTEGRATORS.values(), AVERAGING, *BASELINES.values(),
                                   SEED_APPENDIX_I)]


def describe_integrators() -> list[dict]:
    """The event-driven integrators and the averaging, which seed 003's engine lends to other sliders (seed 000)."""
    return [m.describe() for m in (*INTEGRATORS.values(), AVERAGING)]


def check_lent_method(method: str, what: str) -> None:
    """Refuse, for a slider seed 003's engine lends its integrators to (``what``, e.g. "a rough-surface scene"),
    a method that is not one of :func:`describe_integrators` (or ``auto``, or ``simulate``: DOP853): the closed
    forms need the seed's linear kinetic law, the baselines are not run methods. Its run and estimate alike."""
    lent = ("auto", *(m.name for m in (*INTEGRATORS.values(), AVERAGING)), "simulate")
    if method not in lent:
        raise InputError(f"{what} runs one of {', '.join(lent)}, got {method!r}")


def _cycle_from_dataset(system, dataset, method_name) -> CycleResult:
    """Cycle quantities of the last simulated event (the limit cycle once converged)."""
    regime = dataset.attrs["regime"]
    if dataset.sizes["event"] == 0:
        nan = math.nan
        return CycleResult(method_name, regime, system.loading_rate, system.platform_speed, nan,
                           system.damping_ratio, system.dimensionless_rate or nan, nan, nan, nan, nan, math.inf,
                           nan, nan, system.scale)
    last = dataset.isel(event=-1)
    period = float(last["period"]) if dataset.sizes["event"] > 1 else math.nan
    return CycleResult(
        method=method_name, regime=regime, loading_rate=system.loading_rate,
        platform_speed=system.platform_speed, static_friction=float(last["static_friction"]),
        damping_ratio=system.damping_ratio,
        dimensionless_rate=system.dimensionless_rate if system.dimensionless_rate is not None else math.nan,
        amplitude=float(last["amplitude"]), slip_per_event=float(last["slip"]),
        stick_duration=float(last["stick_duration"]), slip_duration=float(last["slip_duration"]),
        period=period, peak_slip_speed=float(last["peak_slip_speed"]), stress_drop=float(last["stress_drop"]),
        scale=system.scale, stress_drop_slip=float(last["stress_drop"]) / system.stiffness,
    )


CLOSED_FORM = ClosedForm()
EXACT = ExactCycle()
EXACT_MAP = ExactMap()
AVERAGING = QuasiHarmonicAveraging()
INTEGRATORS = {solver: EventDriven(solver) for solver in ("DOP853", "RK45", "LSODA", "Radau")}
METHODS = {CLOSED_FORM.name: CLOSED_FORM, EXACT.name: EXACT, EXACT_MAP.name: EXACT_MAP, **{m.name: m for m in INTEGRATORS.values()},
           "simulate": INTEGRATORS["DOP853"], AVERAGING.name: AVERAGING}
BASELINES = {f"regularized_{s}": Regularized(s) for s in ("RK45", "LSODA", "Radau")}
SEED_APPENDIX_I = SeedAppendixI()


def _with_settling(error: float, reason: str, dataset, outputs) -> tuple[float, str]:
    """A run's declared error and reason with its settling: a steady cycle is only as good as its settling, and the
    remaining distance adds to the error (:func:`settled_error`)."""
    if dataset is None or "settling_remaining" not in dataset.attrs:
        return error, reason
    remaining = float(dataset.attrs["settling_remaining"])
    steady = not {"time_series", "event_times"} & set(outputs)
    if not dataset.attrs.get("settled", 1) and steady:
        reason = f"{reason}; {dataset.attrs['settling_reason']}"
    return (settled_error(error, remaining) if math.isfinite(remaining) or steady else error), reason


def refinement_check(chosen, system, outputs, tolerance, cycles, settings, run, error, reason):
    """The error of an event-driven run on a law the calibration never drew, checked by a finer run.

    The run at rtol is repeated at rtol / 100 (:func:`refined_rtol`); its declared error is the larger of the
    calibrated one and 3 times the runs' largest relative difference over amplitude, period, stress drop, peak
    slip speed and slip per event (:data:`REFINEMENT_FACTOR`; the event times' drift counts each cycle). While that
    exceeds the tolerance and a finer rtol is left, the finer run becomes the run and is checked in turn.

    Returns
    -------
    tuple
        (cycle, event times, dataset, evaluations of all runs, declared error, reason, settings of the answer).
    """
    drift = max(cycles, 1) if "event_times" in outputs else 1.0
    evaluations = run[3]
    while True:
        finer = {**settings, "rtol": refined_rtol(settings["rtol"])}
        if finer["rtol"] >= settings["rtol"]:  # no finer rtol: nothing to check against
            return (*run[:3], evaluations, math.inf, f"{reason}; no finer rtol than {settings['rtol']:g} to check "
                    "it against (its law was never drawn by the calibration), so its error is unbounded", settings)
        check = chosen.run(system, cycles, finer)
        evaluations += check[3]
        difference, graze = refinement_difference(run[0], check[0])
        difference *= drift
        checked = max(error, REFINEMENT_FACTOR * difference)
        note = (f"{reason}; checked against rtol = {finer['rtol']:g} (its law was never drawn by the calibration): "
                f"they differ by {difference:.2g}, so its error is declared {checked:.2g}" + (
                    "" if graze is None else f"; its stress drop is a graze (under {GRAZE_SHARE:g} of the swing), "
                    f"zero within {REFINEMENT_FACTOR * graze:.2g} {'N' if run[0].scale == 'lab' else 'Pa'}, with no "
                    "relative error"))
        if checked <= tolerance or finer["rtol"] <= FINEST_RTOL:
            return (*run[:3], evaluations, checked, note, settings)
        run, settings = check, finer
        error = _with_settling(chosen.assess(system, outputs, tolerance, cycles, rtol=settings["rtol"]).estimated_error,
                               "", run[2], outputs)[0]
        reason = (f"{chosen.solver} at rtol = {settings['rtol']:g}, after rtol = {settings['rtol'] * REFINEMENT:g} "
                  f"differed from it by {difference:.2g}, past the tolerance {tolerance:g}")


def check_method(method: str) -> None:
    """Refuse a method that is neither ``auto`` nor one of :data:`METHODS` or :data:`BASELINES`, in one sentence
    (a solve and a family's estimate of it alike)."""
    if method != "auto" and method not in METHODS and method not in BASELINES:
        raise InputError(f"unknown method {method!r}; allowed: auto, {', '.join(list(METHODS) + list(BASELINES))}")


def _check_request(outputs, tolerance, cycles):
    outputs = tuple(outputs)
    unknown = [o for o in outputs if o not in OUTPUTS]
    if unknown:
        raise InputError(f"unknown output {unknown[0]!r}; allowed: {', '.join(OUTPUTS)}")
    tolerance = ranges.check_tolerance(tolerance)
    if cycles < 1:
        raise InputError(f"cycles must be at least 1, got {cycles}")
    return outputs


def choose(system, outputs=("amplitude", "period"), tolerance=DEFAULT_TOLERANCE, cycles=10, price=None):
    """The cheapest applicable method whose estimated error meets ``tolerance``.

    Returns ``(method, assessment, assessments)``; ``assessments`` lists every candidate considered.
    If no method reaches the tolerance, the most accurate applicable one is chosen and the reason
    says so. ``price(assessment)``, where given, is what an integrator's or the averaging's run costs on the
    family's own law (its fitted rates: on a rough-surface table RK45 takes about twice DOP853's share of the
    evaluations the calibration counts); by default, the assessment's ``estimated_cost``.
    """
    outputs = _check_request(outputs, tolerance, cycles)
    if system.rate_static_friction is not None:  # no method has a stick-slip to find where it cannot break away
        check_break_away(system, system.normal_load * system.rate_static_friction)
    assessments = []
    for method in (CLOSED_FORM, EXACT, EXACT_MAP):  # cheapest first: stop at the first that suffices
        assessment = method.assess(system, outputs, tolerance, cycles)
        assessments.append(assessment)
        if assessment.applicable and assessment.estimated_error <= tolerance:
            reason = f"cheapest method within tolerance {tolerance:g}: {assessment.reason}"
            return method, Assessment(assessment.method, True, reason, assessment.estimated_error,
                                      assessment.estimated_cost, assessment.settings), assessments
    assessments += [method.assess(system, outputs, tolerance, cycles) for method in INTEGRATORS.values()]
    if not system.is_linear:  # linear laws: the exact cycle is cheaper and exact
        assessments.append(AVERAGING.assess(system, outputs, tolerance, cycles))
    usable = [a for a in assessments if a.applicable]
    if not usable:  # each says why it cannot run: the scene's physics, not a method's limit
        reasons = list(dict.fromkeys(a.reason for a in assessments))
        raise InputError(f"no method can run {system.name}: {'; '.join(reasons)}")
    good = sorted((a for a in usable if a.estimated_error <= tolerance), key=price or (lambda a: a.estimated_cost))
    if good:
        best = good[0]
        reason = f"cheapest method within tolerance {tolerance:g}: {best.reason}"
    else:
        best = min(usable, key=lambda a: a.estimated_error)
        reason = f"no method reaches tolerance {tolerance:g}; the most accurate is used: {best.reason}"
    chosen = METHODS[best.method]
    return chosen, Assessment(best.method, True, reason, best.estimated_error, best.estimated_cost, best.settings), assessments


def planned(system, method: str = "auto", outputs=("amplitude", "period"), tolerance: float = DEFAULT_TOLERANCE,
            cycles: int = 10, price=None):
    """The method a solve would run and its assessment, before it runs: ``auto``'s choice (:func:`choose`, by
    ``price``), or the forced method's own assessment. Estimates of a run's cost read it (its ``estimated_cost``,
    in the calibration machine's seconds, counts a refinement check's run)."""
    if method == "auto":
        chosen, assessment, _ = choose(system, outputs, tolerance, cycles, price)
        return chosen, assessment
    check_method(method)
    chosen = METHODS.get(method) or BASELINES[method]
    return chosen, chosen.assess(system, tuple(outputs), tolerance, cycles)


def solve(system, method: str = "auto", outputs=("amplitude", "period"), tolerance: float = DEFAULT_TOLERANCE,
          cycles: int = 10, converge: float | None = None, price=None) -> Solution:
    """Solve a scene's stick-slip cycle with ``method`` ("auto" picks the cheapest sufficient one).

    A forced method outside its domain, or less accurate than the tolerance, still runs but warns
    (:class:`~faultslip.errors.OutOfDomainWarning`) and names the method auto would use.

    Parameters
    ----------
    system : SliderSystem
        The slider.
    method : str
        A method's name (``faultslip methods``) or auto.
    outputs : tuple
        What is wanted (amplitude, period, time_series).
    tolerance : float
        Relative error allowed.
    cycles : int
        Cycles run by an integrator.
    converge : float, optional
        The settling tolerance.
    price : callable, optional
        ``price(assessment)``: a run's cost on the family's law, by which auto ranks the integrators (:func:`choose`).

    Returns
    -------
    Solution
        The cycle (m, s), the method, its declared error and ``report()``.
    """
    outputs = _check_request(outputs, tolerance, cycles)
    chosen, assessment = planned(system, method, outputs, tolerance, cycles, price)
    if method != "auto":
        better, better_assessment, _ = choose(system, outputs, tolerance, cycles, price)
        if not assessment.applicable or assessment.estimated_error > tolerance:
            problem = assessment.reason if not assessment.applicable else \
                f"its estimated error {assessment.estimated_error:.2g} exceeds the tolerance {tolerance:g}"
            warnings.warn(f"method {chosen.name} is outside its domain for {system.name}: {problem}; "
                          f"use {better.name} ({better_assessment.reason})", OutOfDomainWarning, stacklevel=2)
            if isinstance(chosen, (ClosedForm,)) and _linear_rate_system(system):
                raise MethodError(f"{chosen.name} cannot describe {system.name}: {_linear_rate_system(system)}; "
                                  f"use {better.name}")
            if isinstance(chosen, QuasiHarmonicAveraging) and not assessment.applicable:
                raise MethodError(f"{chosen.name} cannot describe {system.name}: {assessment.reason}; "
                                  f"use {better.name}")
            if isinstance(chosen, ExactCycle) and _linear_rate_system(system):
                raise MethodError(f"{chosen.name} cannot describe {system.name}: {_linear_rate_system(system)}; "
                                  f"use {better.name}")
        assessment.reason = f"forced by the user: {assessment.reason}"
    settings = dict(assessment.settings)
    if "time_series" in outputs:
        settings["time_series"] = True
    if converge is None and isinstance(chosen, (EventDriven, ExactMap)) and not {"time_series", "event_times"} & set(outputs):
        converge = tolerance  # only the limit cycle is wanted: stop once it has converged
    if converge is not None:
        settings["converge"] = converge
    started = time.perf_counter()
    cycle, event_times, dataset, evaluations = chosen.run(system, cycles, settings)
    elapsed = time.perf_counter() - started
    cycle.method = chosen.name
    error, reason = _with_settling(assessment.estimated_error, assessment.reason, dataset, outputs)
    if isinstance(chosen, EventDriven) and not system.error_calibrated:
        cycle, event_times, dataset, evaluations, error, reason, settings = refinement_check(
            chosen, system, outputs, tolerance, cycles, settings, (cycle, event_times, dataset, evaluations), error,
            reason)
        elapsed = time.perf_counter() - started
    solution = Solution(cycle, np.asarray(event_times), chosen.name, reason, error,
                        {k: v for k, v in settings.items() if k not in ("time_series",)}, dataset, evaluations, elapsed)
    if dataset is not None:
        dataset.attrs.update(method=chosen.name, method_reason=reason, estimated_relative_error=float(error))
    return solution
