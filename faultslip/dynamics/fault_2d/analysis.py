"""What a 2-D fault run says: its event sequence, whether it has settled, and the slip budget.

A steady-cycle answer (recurrence, slip per event) comes only from a sequence shown to have
settled: the last ``compare`` intervals between system-size events must agree to ``tolerance``;
otherwise the answer carries the spread as its error and says the sequence has not settled.
System-size events are those whose surface slip exceeds half the largest (a run may also hold
partial ruptures at depth, which are counted but not used for the recurrence).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from faultslip.dynamics.fault_2d.integrate import YEAR, Fault2DRun

#: Intervals compared to call a sequence periodic.
SETTLED_INTERVALS = 3


@dataclass
class Fault2DSummary:
    events: int
    system_events: int
    recurrence_interval: float  # s, the last settled interval (NaN if fewer than 2 system-size events)
    recurrence_spread: float  # relative spread of the last SETTLED_INTERVALS intervals
    settled: bool
    surface_slip_per_event: float  # m, last system-size event
    mean_slip_per_event: float  # m, averaged over the velocity-weakening width
    moment_per_length: float  # N (N m per m along strike), last system-size event
    hypocentre_depth: float  # m, last system-size event
    peak_slip_rate: float  # m/s over the run
    plate_slip_balance_surface: float  # slip at the shallowest station over the last cycle / (V_pl T)
    plate_slip_balance_range: tuple  # (min, max) over the stations
    creep_rate_deep: float  # m/s, slip rate at the bottom element at the end (steady at V_pl)
    note: str = ""


def summarise(run: Fault2DRun, tolerance: float = 1e-3) -> Fault2DSummary:
    fault = run.fault
    starts = run.events["start"]
    slip = run.events["slip"]
    count = starts.size
    surface = slip[:, 0] if count else np.empty(0)
    system = np.flatnonzero(surface >= 0.5 * surface.max()) if count else np.empty(0, int)
    intervals = np.diff(starts[system]) if system.size > 1 else np.empty(0)
    if intervals.size >= 1:
        recurrence = float(intervals[-1])
        last = intervals[-SETTLED_INTERVALS:]
        spread = float((last.max() - last.min()) / last.mean()) if last.size > 1 else math.inf
    else:
        recurrence, spread = math.nan, math.inf
    settled = intervals.size >= SETTLED_INTERVALS and spread <= tolerance
    weakening = fault.b > fault.a
    if system.size:
        last_event = system[-1]
        surface_slip = float(surface[last_event])
        mean_slip = float(slip[last_event][weakening].mean()) if np.any(weakening) else math.nan
        moment = float(run.moments_per_length()[last_event])
        hypocentre = float(run.events["hypocentre_depth"][last_event])
    else:
        surface_slip = mean_slip = moment = hypocentre = math.nan
    balance_surface, balance_range = math.nan, (math.nan, math.nan)
    if system.size > 1:
        # slip over the last full cycle at every station, between the two last system-size event starts
        first, second = starts[system[-2]], starts[system[-1]]
        station_slip = run.stations["slip"]
        cycle_slip = np.array([np.interp(second, run.station_time, station_slip[:, k])
                               - np.interp(first, run.station_time, station_slip[:, k])
                               for k in range(station_slip.shape[1])])
        expected = fault.plate_rate * (second - first)
        shallowest = int(np.argmin(run.station_depths))
        balance_surface = float(cycle_slip[shallowest] / expected)
        balance_range = (float(cycle_slip.min() / expected), float(cycle_slip.max() / expected))
    peak = float(run.events["peak_slip_rate"].max()) if count else float(run.profile_max_speed.max())
    deep = float(10 ** run.profile_log10_slip_rate[-1, -1]) if run.profile_time.size else math.nan
    note = ""
    if not settled:
        note = (f"the sequence has not settled: the last {min(intervals.size, SETTLED_INTERVALS)} intervals between "
                f"system-size events differ by {spread:.3g} (relative), more than {tolerance:g}; run longer"
                if intervals.size else "fewer than two system-size events: no recurrence; run longer")
    return Fault2DSummary(count, int(system.size), recurrence, spread, settled, surface_slip, mean_slip, moment,
                          hypocentre, peak, balance_surface, balance_range, deep, note)


def moment_magnitude(moment_per_length: float, fault_length: float) -> float:
    """Mw = (2/3) (log10 M0 - 9.1), M0 = moment per length times the fault length (Hanks & Kanamori 1979)."""
    return 2.0 / 3.0 * (math.log10(moment_per_length * fault_length) - 9.1)


def years(seconds: float) -> float:
    return seconds / YEAR


#: BP1's recurrence at 100 m (3.42 elements per L_b) lies 0.108 % below the 25 m value, at 50 m (6.8)
#: 0.020 % (benchmarks/fault_2d.py, tests/test_fault_2d.py). Declared: 0.12 % at 3.42 per L_b (the 25 m
#: value is itself off by the 25 m error), falling as (h / L_b)^2, more slowly than measured (safe).
DISCRETISATION_AT_REFERENCE, REFERENCE_RESOLUTION, DISCRETISATION_ORDER = 1.2e-3, 3.42, 2.0


def discretisation_error(resolution: float) -> float:
    """The recurrence's relative error from the element size, at ``resolution`` elements per L_b, scaled
    from BP1's measured convergence (an estimate for other faults: it assumes BP1's rupture style)."""
    return DISCRETISATION_AT_REFERENCE * (REFERENCE_RESOLUTION / resolution) ** DISCRETISATION_ORDER


#: The 2-D fault as a method, for 'faultslip methods' (faultslip.dynamics.methods.describe_all).
METHODS = {
    "fault_2d": {
        "name": "fault_2d", "friction_laws": "rate-and-state (aging or slip law), depth-varying (SEAS BP1)",
        "domain": "a vertical strike-slip fault in an elastic half-space, quasi-dynamic (radiation damping); "
                  "elements of 3 or more per L_b = G D_c / (sigma_n b); declared error in recurrence: the largest "
                  f"of the settling spread, 10 rtol and the element size's {DISCRETISATION_AT_REFERENCE:g} "
                  f"(3.42 h / L_b)^{DISCRETISATION_ORDER:g}, from BP1's measured convergence",
        "cost_model": "Dormand-Prince 5(4) steps: about 15 (V_pl / 1e-9 m/s) (W / h*) (rtol / 1e-7)^-0.18 a simulated "
                      "year, times the resolution's factor (faultslip.io.budget.fault_2d_steps), each step "
                      "0.1 ms + 0.85 us per element; BP1 at 25 m over 3000 yr: 262,150 steps, 6 min"},
}
