"""Integrators of a rate-and-state fault's cycles behind the method interface: error and cost declared, auto by cost.

A quasi-dynamic spring-slider fault (:func:`faultslip.dynamics.rate_state.slider.fault_cycles`) spends
centuries creeping and seconds rupturing. Two integrators:

* ``dopri5``: explicit Dormand-Prince 5(4), any law. Between events its step is stability-limited
  once the rupture is stiff: steps per cycle = max(N(rtol), 9.3 / (K / K_c)), where N(rtol) is
  what accuracy alone needs (250 at rtol 1e-5, 450 at 1e-7, 1000 at 1e-9);
* ``lsoda``: scipy's LSODA (Adams / BDF switching) with the analytic Jacobian, one-state laws:
  600, 1100 and 1800 steps per cycle at those tolerances, nearly independent of K / K_c.

Error model (relative error of recurrence and slip per event, :data:`ERROR_MODEL`): c rtol^q + floor per
integrator, and near K_c, where the cycle amplifies it, k rtol^p / ((1 - K / K_c) (1 - a / b)); the larger of the
two (a perturbation of the cycle decays the more slowly the nearer K / K_c and a / b are to 1). The
event edges are found on dopri5's own continuous extension (LSODA: a cubic Hermite of the step's ends). The
constants are fitted by ``benchmarks/rate_state_calibration.py`` on random faults (a / b, the evolution law,
sigma_n, G, the fault's width, the plate rate and K / K_c drawn over wide ranges) against the C stepper at rtol
1e-12, at least 1.5 times every calibration error, and checked on held-out faults; ``docs/rate_state.md`` has
the table. Cost model: cycles x steps per cycle x seconds per step (:data:`SECONDS_PER_STEP`), from
``faultslip rate-state bench`` on SEAS BP1 friction (a 0.010, b 0.015, sigma_n 50 MPa, G 32 GPa, D 20 km) with
D_c set for K / K_c from 1e-5 to 0.9 (docs/figures/work_precision_rate_state.md, with the chart).

``auto`` takes the cheaper method whose declared error meets the tolerance: LSODA where the rupture
is stiff (at a tolerance of 1e-6, below K / K_c of about 2e-4 where the C stepper is built, and about
9e-3 where it is not), the C stepper or dopri5 elsewhere.
"""

from __future__ import annotations

import math

import numpy as np

from faultslip.dynamics.rate_state import native
from faultslip.dynamics.shared.assessment import Assessment
from faultslip import ranges
from faultslip.errors import InputError, beside

#: calibrated tolerances: the loosest that meets a requested error is used
RTOL_LEVELS = (1e-5, 3e-6, 1e-6, 3e-7, 1e-7, 3e-8, 1e-8, 3e-9, 1e-9, 3e-10, 1e-10)
#: steps per cycle that accuracy alone needs, at rtol 1e-5, 1e-7, 1e-9 (interpolated in log rtol)
ACCURACY_STEPS = {"dopri5": (250.0, 450.0, 1000.0), "lsoda": (600.0, 1100.0, 1800.0)}
ACCURACY_STEPS["dopri5_compiled"] = ACCURACY_STEPS["dopri5"]  # the same scheme, stepped in C
#: dopri5's stability limit between events: steps per cycle = STIFF_STEPS / (K / K_c)
STIFF_STEPS = 9.3
#: Seconds per step on the "families" machine reference (faultslip.io.machine): the median of each integrator's
#: measured wall time over steps across 'faultslip rate-state bench''s grid (K / K_c 1e-5 to 0.9, rtol 1e-5 to
#: 1e-10), over that run's machine factor, the mean of three runs (10.2, 9.0, 7.6; 5.7, 5.1, 4.0; 0.25, 0.22, 0.21
#: us: the factor's probe moves them by 15 %); the bench prints both beside these. They had been 16, 12 and 0.4
#: us, set on an earlier host and never anchored, and a study's cycles were estimated at up to 4 times their CPU
#: (LSODA's wall time 0.25 to 0.52 of the model's).
SECONDS_PER_STEP = {"dopri5": 8.9e-6, "lsoda": 4.9e-6, "dopri5_compiled": 0.23e-6}
#: Declared relative error of recurrence and slip per event, per integrator: far from K_c, c rtol^q + floor
#: ("far": (c, q, floor)); near K_c, where the cycle amplifies the integrator's error,
#: k rtol^p / ((1 - K / K_c) (1 - a / b)) ("near": (k, p)); the larger of the two. Fitted by
#: benchmarks/rate_state_calibration.py on 420 random faults (a / b 0.3 to 0.95, both laws, sigma_n 5 to 150 MPa,
#: K / K_c 1e-5 to 0.999) against the C stepper at rtol 1e-12, each model at least 1.5 times every calibration
#: error, and checked on 40 held-out faults and on fresh draws. The former constants (20 rtol dopri5, 500 LSODA,
#: 2 rtol / (1 - K / K_c) near K_c) were set on SEAS BP1 alone: on random faults dopri5 erred by 93 rtol where a / b
#: nears 1 (its event edges, then a cubic Hermite of the step's ends), LSODA by 1,700 rtol at rtol 1e-6 on a
#: lab-scale D_c, and both by 2 to 4 times the near-K_c bound. LSODA's far model was refitted (from 3500 rtol^1.05)
#: once its cycles settle against its own scatter (slider.cycle_noise): runs that had ended unsettled at rtol 1e-5,
#: their error declared as settling's, now count as the integrator's. The near model had no (1 - a / b): fresh
#: faults at a / b 0.76 and 0.88 by K_c broke (0.099 rtol^0.76, 2.9 rtol^0.81) / (1 - K / K_c) by up to 3.9 times
#: (rate_state_bench.LATER_CALIBRATION_SEEDS), and the calibration's own regression gives the factor.
ERROR_MODEL = {"dopri5": {"far": (58.0, 1.05, 0.0), "near": (0.22, 0.85)},
               "lsoda": {"far": (7000.0, 1.1, 0.0), "near": (3.0, 0.84)}}
ERROR_MODEL["dopri5_compiled"] = ERROR_MODEL["dopri5"]  # the same scheme and steps, stepped in C
#: the calibration fits the near-K_c model on faults from this K / K_c up, the far model on those below
NEAR_CRITICAL_FROM = 0.9
#: the a / b of the calibration's random faults (faultslip.evaluation.rate_state_bench.random_faults)
A_OVER_B_BOX = (0.3, 0.95)


def near_critical_error(rtol: float, stiffness_ratio: float, method: str = "dopri5", *, a_over_b) -> float:
    """The integrator's error amplified near K_c: k rtol^p / ((1 - K / K_c) (1 - a / b)) (:data:`ERROR_MODEL`).

    The amplification is the cycle's slow decay of a perturbation, as in the settling's
    (:data:`SETTLING_CYCLES`): a least-squares fit of ln error on the calibration's runs from K / K_c 0.9 up
    gives exponents near 1 on both (1 - K / K_c) and (1 - a / b) (``benchmarks/rate_state_calibration.py``
    prints them; docs/rate_state.md). Without the last factor the model missed fresh faults at a / b 0.76 and
    0.88 by up to 3.9 times.
    ``a_over_b`` None (a law not known) takes the calibration box's largest, :data:`A_OVER_B_BOX`'s."""
    constant, power = ERROR_MODEL[method]["near"]
    ab = A_OVER_B_BOX[1] if a_over_b is None else min(max(float(a_over_b), 0.0), 1.0)
    return constant * rtol ** power / (max(1.0 - stiffness_ratio, 1e-12) * max(1.0 - ab, 1e-3))


def steps_per_cycle(method: str, rtol: float, stiffness_ratio: float) -> float:
    """Integrator steps per earthquake cycle from the calibration (see the module docstring)."""
    digits = -math.log10(rtol)
    counts = np.log10(ACCURACY_STEPS[method])
    # piecewise linear in (digits, log10 steps) through 5, 7 and 9 digits, extended by the end segments
    segment = 0 if digits < 7 else 1
    slope = (counts[segment + 1] - counts[segment]) / 2.0
    accuracy = float(10 ** (counts[segment] + slope * (digits - (5 + 2 * segment))))
    if method.startswith("dopri5"):
        return max(accuracy, STIFF_STEPS / max(stiffness_ratio, 1e-300))
    return accuracy


#: Cycle-equivalents of steps a fault's cycles take before the measured ones: base + c / ((1 - K / K_c)^p
#: (1 - a / b)^q). Four cycles settle far from K_c; near it the 1 % start grows slowly into the cycle and settles
#: slowly onto it, and more slowly as a / b nears 1. Fitted by benchmarks/rate_state_settling.py on random faults
#: (ln steps, least squares) and tested there on a draw it never saw; tests/models/rate_state_slider pins it.
SETTLING_CYCLES = {"base": 3.654, "c": 0.02968, "p": 1.081, "q": 1.057}


def settling_cycles(stiffness_ratio: float, a_over_b: float) -> float:
    """Cycles' worth of steps before the measured cycles (:data:`SETTLING_CYCLES`)."""
    fit = SETTLING_CYCLES
    closeness = max(1.0 - min(stiffness_ratio, 1.0), 1e-6) ** fit["p"] * max(1.0 - a_over_b, 1e-3) ** fit["q"]
    return fit["base"] + fit["c"] / closeness


def cycle_steps(method: str, rtol: float, stiffness_ratio: float, a_over_b: float, cycles: float) -> float:
    """Steps of a fault's cycles from its start: those it takes to settle (:func:`settling_cycles`) and then
    ``cycles`` measured, at :func:`steps_per_cycle` each.

    Parameters
    ----------
    method : str
        The integrator (:data:`ACCURACY_STEPS`' names).
    rtol : float
        Its relative tolerance.
    stiffness_ratio : float
        K / K_c (quasi-static K_c).
    a_over_b : float
        The law's a / b.
    cycles : float
        The cycles measured.

    Returns
    -------
    float
        Integrator steps, about.
    """
    return steps_per_cycle(method, rtol, stiffness_ratio) * (cycles + settling_cycles(stiffness_ratio, a_over_b))


def error_bound(method: str, rtol: float, stiffness_ratio: float = 0.1, *, a_over_b) -> float:
    """Declared relative error of recurrence and slip per event at ``rtol`` for a fault at K / K_c whose law has
    ``a_over_b``: the larger of the integrator's own, c rtol^q + floor, and its amplification near K_c
    (:func:`near_critical_error`)."""
    constant, power, floor = ERROR_MODEL[method]["far"]
    return max(constant * rtol ** power + floor, near_critical_error(rtol, stiffness_ratio, method,
                                                                     a_over_b=a_over_b))


class CycleMethod:
    """One integrator of a fault's cycles, with its declared domain, error and cost."""

    def __init__(self, name: str, friction_laws: str, domain: str, cost_model: str):
        self.integrator = name
        self.name = f"rate_state_{name}"
        self.friction_laws, self.domain, self.cost_model = friction_laws, domain, cost_model

    def describe(self) -> dict:
        return {"name": self.name, "friction_laws": self.friction_laws, "domain": self.domain,
                "cost_model": self.cost_model,
                "declared_error": ("c rtol^q per cycle quantity, and near K_c k rtol^p / ((1 - K / K_c) (1 - a / b)), "
                                   "fitted "
                                   "per integrator on random faults against the C stepper at rtol 1e-12 "
                                   "(benchmarks/rate_state_calibration.py; faultslip rate-state bench checks it on "
                                   "held-out ones), and the settling left"),
                "run_method": None,
                "selected_by": (f"the one slider's integrator, chosen for each fault by its error and cost ('faultslip "
                                f"run' takes the rung, one_slider); a rate-and-state study or map names it by method = "
                                f"\"{self.integrator}\", and 'faultslip rate-state simulate SCENE --method "
                                f"{self.integrator}' integrates a laboratory load history with it")}

    def assess(self, stiffness_ratio: float, tolerance: float, cycles: int, two_state: bool = False,
               rtol: float | None = None, a_over_b: float | None = None) -> Assessment:
        """Error and cost for a fault at ``stiffness_ratio`` = K / K_c (at ``rtol``, or the loosest that suffices).
        With the law's ``a_over_b`` the cost is that of ``cycles`` measured after the fault settles
        (:func:`cycle_steps`, as :func:`~faultslip.dynamics.rate_state.slider.fault_cycles` runs them), and the
        error is the law's (:func:`near_critical_error`); without it, the cost is of ``cycles`` in all and the error
        the calibration box's largest."""
        if not stiffness_ratio < 1:
            return Assessment(self.name, False, f"K / K_c = {beside(stiffness_ratio, 1.0)} >= 1: steady sliding is stable, "
                              "there are no cycles to integrate")
        if two_state and self.integrator == "lsoda":
            return Assessment(self.name, False, "LSODA here takes one-state laws (its analytic Jacobian)")
        if self.integrator == "dopri5_compiled" and not native.available():
            return Assessment(self.name, False, "the C stepper was not built with this install (no C compiler)")
        if self.integrator == "dopri5_compiled" and two_state:
            return Assessment(self.name, False, "the C stepper takes one-state, unregularised laws")
        if rtol is None:
            fitting = [r for r in RTOL_LEVELS
                       if error_bound(self.integrator, r, stiffness_ratio, a_over_b=a_over_b) <= tolerance]
            rtol = fitting[0] if fitting else RTOL_LEVELS[-1]
        steps = steps_per_cycle(self.integrator, rtol, stiffness_ratio)
        total = (max(cycles, 1) * steps if a_over_b is None
                 else cycle_steps(self.integrator, rtol, stiffness_ratio, a_over_b, cycles))
        cost = total * SECONDS_PER_STEP[self.integrator]
        error = error_bound(self.integrator, rtol, stiffness_ratio, a_over_b=a_over_b)
        return Assessment(self.name, True, f"{self.integrator} at rtol {rtol:g}: about {steps:.3g} steps a cycle at "
                          f"K / K_c = {stiffness_ratio:.3g}, error <= {error:.2g}", error, cost,
                          {"method": self.integrator, "rtol": rtol})


CYCLE_METHODS = {
    "dopri5": CycleMethod("dopri5", "rate-and-state, one or two state variables (aging or slip law)",
                          "any K / K_c < 1; its steps grow as 9.3 / (K / K_c) once ruptures are stiff",
                          "cycles x max(N(rtol), 9.3 / (K/K_c)) steps x 8.9 us; N = 250, 450, 1000 at rtol 1e-5, 1e-7, "
                          "1e-9"),
    "dopri5_compiled": CycleMethod("dopri5_compiled", "rate-and-state, one state variable, unregularised (aging or "
                                   "slip law); built at install where a C compiler is",
                                   "as dopri5, the same scheme and error, stepped in C between event edges",
                                   "as dopri5's steps x 0.23 us"),
    "lsoda": CycleMethod("lsoda", "rate-and-state, one state variable (analytic Jacobian)",
                         "any K / K_c < 1; its error control is loose (thousands of rtol at loose rtol on stiff "
                         "faults: the declared error says so)",
                         "cycles x 600-1800 steps (rtol 1e-5 to 1e-9) x 4.9 us, nearly independent of K / K_c"),
}


def choose_cycle_method(stiffness_ratio: float, tolerance: float = 1e-6, cycles: int = 5,
                        two_state: bool = False, rtol: float | None = None, a_over_b: float | None = None):
    """``(method name, rtol, assessment, assessments)``: the cheapest integrator whose declared error meets
    ``tolerance`` (at ``rtol`` if given); if none does, the most accurate, and the reason says so. ``cycles`` and
    ``a_over_b`` are :meth:`CycleMethod.assess`'s."""
    tolerance = ranges.check_tolerance(tolerance)
    assessments = [method.assess(stiffness_ratio, tolerance, cycles, two_state, rtol, a_over_b)
                   for method in CYCLE_METHODS.values()]
    usable = [a for a in assessments if a.applicable]
    if not usable:
        raise InputError(assessments[0].reason)
    good = sorted((a for a in usable if a.estimated_error <= tolerance), key=lambda a: a.estimated_cost)
    if good:
        best, why = good[0], f"cheapest within tolerance {tolerance:g}"
    else:
        # the most accurate, and of equally accurate ones the cheapest (the compiled dopri5 before the Python one)
        best = min(usable, key=lambda a: (a.estimated_error, a.estimated_cost))
        why = f"none reaches tolerance {tolerance:g}; the most accurate"
    best = Assessment(best.method, True, f"{why}: {best.reason}", best.estimated_error, best.estimated_cost,
                      best.settings)
    return best.settings["method"], best.settings["rtol"], best, assessments
