"""faultslip benchmarks: ratios measured side by side in one run (these machines are noisy).

Run from the repository root:

    python benchmarks/run.py            # all benchmarks (the 5e8-cell sweep needs ~25 GB of disk, ~20 min)
    python benchmarks/run.py --quick    # fewer repeats, sweeps of 1e6 and 1e7 cells

Each benchmark times our method and its baseline on the same problem in the same process,
interleaving repeats, and reports the ratio of medians. Results are printed and written to
benchmarks/results/latest.json.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from provenance import stamp  # noqa: E402  (one stamp for every results file)

warnings.simplefilter("ignore")


def timed(function, repeats):
    """Median wall time of ``repeats`` calls, and the last result."""
    times, result = [], None
    for _ in range(repeats):
        started = time.perf_counter()
        result = function()
        times.append(time.perf_counter() - started)
    return statistics.median(times), result


def side_by_side(ours, baseline, repeats):
    """Interleave the two so load changes hit both; medians of each."""
    ours_times, base_times = [], []
    ours_result = base_result = None
    for _ in range(repeats):
        started = time.perf_counter()
        ours_result = ours()
        ours_times.append(time.perf_counter() - started)
        started = time.perf_counter()
        base_result = baseline()
        base_times.append(time.perf_counter() - started)
    return statistics.median(ours_times), statistics.median(base_times), ours_result, base_result


def competent_slip(system, x_break, rtol, solver="DOP853"):
    """What a competent user writes for one slip phase: one solve_ivp call with a terminal event.

    The slip ends when the slider speed returns to V (event, direction +1); a second, non-terminal
    event at x' = 0 locates the largest displacement. No dense output. Returns (duration, x_end,
    x_max, x_min, evaluations).
    """
    from scipy.integrate import solve_ivp

    K, W, M, C, V = system.stiffness, system.normal_load, system.mass, system.dashpot, system.platform_speed
    kinetic = system.kinetic_law

    def rhs(t, y):
        return (y[1], (W * float(kinetic(V - y[1])) - K * y[0] - C * y[1]) / M)

    def restick(t, y):
        return y[1] - V

    restick.terminal, restick.direction = True, 1

    def turning(t, y):
        return y[1]

    horizon = 40 * 2 * np.pi / system.natural_frequency
    scale = W * 1e-3 / K
    solution = solve_ivp(rhs, (0.0, horizon), (x_break, V), method=solver, rtol=rtol, atol=rtol * scale,
                         events=(restick, turning))
    if not solution.t_events[0].size:
        raise RuntimeError("the baseline missed the re-stick")
    x_end = float(solution.y_events[0][0][0])
    extremes = np.concatenate([solution.y_events[1][:, 0], [x_break, x_end]])
    return float(solution.t_events[0][0]), x_end, float(extremes.max()), float(extremes.min()), solution.nfev


def competent_cycles(system, cycles, rtol, x0=0.0):
    """A competent user's stick-slip sequence: stick end by brentq on the static law, slip by solve_ivp.

    Returns the break-away times and stress drops of ``cycles`` events (the same work as
    faultslip.dynamics.spring_slider.simulate's event table) and the evaluations used.
    """
    from scipy.optimize import brentq

    K, W, C, V = system.stiffness, system.normal_load, system.dashpot, system.platform_speed
    law = system.static_law
    t, x, evaluations = 0.0, x0, 0
    times, drops = [], []
    for _ in range(cycles):
        def excess(tau, x=x):
            return K * (x + V * tau) + C * V - W * float(law.limit(system.loading_rate, tau))

        hi = 1.0 / system.natural_frequency
        while excess(hi) < 0:
            hi *= 2.0
        stick = 0.0 if excess(0.0) >= 0 else brentq(excess, 0.0, hi, xtol=1e-15 * hi, rtol=4 * np.finfo(float).eps)
        t += stick
        x_break = x + V * stick
        duration, x_end, _, _, nfev = competent_slip(system, x_break, rtol)
        evaluations += nfev
        times.append(t)
        drops.append(K * (x_break - x_end))
        t += duration
        x = x_end
    return np.array(times), np.array(drops), evaluations


def _loosest(check, rtols=(1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12)):
    for rtol in rtols:
        if check(rtol):
            return rtol
    return None


def exact_against_integrators(repeats):
    """Equal work at equal accuracy (1e-6): the analytic slip phase against a competent solve_ivp baseline.

    (a) One limit cycle: exact_cycle against stick (analytic, as anyone would) plus one solve_ivp slip
        phase with events. (b) 100 cycles that really differ: Cameron's time-of-stick law from an
        unloaded spring, a transient toward the limit cycle, where every stick and slip must be
        computed; faultslip.dynamics.spring_slider.simulate (analytic slip phases) against the same loop in scipy.
    The earlier figure (120x) compared one analytic cycle copied 100 times with 100 integrated
    slip phases: not the same work.
    """
    from faultslip.dynamics.spring_slider.critical import critical
    from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle
    from faultslip.fault.scene import read_slider_scene
    from faultslip.dynamics.spring_slider.simulate import simulate
    from faultslip.dynamics.spring_slider.slider import SliderSystem

    base = SliderSystem.from_preset("glass_dry", loading_rate="1 1/s", damping_ratio=0.01)
    system = base.at_loading_rate(0.1 * critical(base).critical_loading_rate)
    exact = exact_cycle(system)
    K, W, V = system.stiffness, system.normal_load, system.platform_speed
    x_break = (W * exact.static_friction - system.dashpot * V) / K

    def one_cycle(rtol):
        duration, x_end, x_max, x_min, nfev = competent_slip(system, x_break, rtol)
        stick = (x_break - x_end) / V
        return {"period": stick + duration, "stress_drop": K * (x_break - x_end), "amplitude": x_max - x_min,
                "evaluations": nfev}

    def accurate(rtol, target):
        got = one_cycle(rtol)
        return all(abs(got[k] / getattr(exact, k) - 1) <= target for k in ("period", "stress_drop", "amplitude"))

    rows = {}
    for target in (1e-6, 1e-10):
        rtol = _loosest(lambda r, t=target: accurate(r, t), rtols=tuple(10.0 ** -k for k in range(5, 14)))
        ours, theirs, _, baseline = side_by_side(lambda: exact_cycle(system), lambda r=rtol: one_cycle(r), repeats)
        rows[f"{target:g}"] = {"baseline": f"stick analytic + one DOP853 slip phase with events, rtol {rtol:g}",
                               "exact_s": ours, "baseline_s": theirs, "ratio": theirs / ours,
                               "evaluations": baseline["evaluations"]}
    single = {"scene": "glass_dry, zeta 0.01, 0.1 theta_c: one limit cycle (period, stress drop, swing)",
              "per_accuracy": rows, **rows["1e-06"]}

    cameron = read_slider_scene("lab_steel_dry_time_of_stick.toml").slider()
    reference = simulate(cameron, cycles=100)
    ref_times, ref_drops = reference["event_time"].values, reference["stress_drop"].values

    def sequence_accurate(rtol):
        times, drops, _ = competent_cycles(cameron, 100, rtol)
        return (np.max(np.abs(times / ref_times - 1)[1:]) <= 1e-6
                and np.max(np.abs(drops / ref_drops - 1)) <= 1e-6)

    rtol_seq = _loosest(sequence_accurate)
    ours_seq, theirs_seq, data, (_, _, nfev) = side_by_side(lambda: simulate(cameron, cycles=100),
                                                            lambda: competent_cycles(cameron, 100, rtol_seq),
                                                            max(3, repeats // 3))
    drops = data["stress_drop"].values
    sequence = {"scene": "steel, dry, Cameron's time-of-stick law from an unloaded spring: 100 distinct cycles "
                         "(break-away times and stress drops <= 1e-6)",
                "stress_drop_first_last": [float(drops[0]), float(drops[-1])],
                "baseline": f"brentq stick + DOP853 slip with events per cycle, rtol {rtol_seq:g}",
                "faultslip_s": ours_seq, "baseline_s": theirs_seq, "ratio": theirs_seq / ours_seq,
                "evaluations": int(nfev)}
    return {"one_cycle": single, "distinct_cycles": sequence,
            "target": "none claimed: the earlier >= 100x compared unequal work; this measures equal work"}


def fault_scale(repeats, budget):
    """100 cycles of the 1906 scene: the project's simulator against generic integration."""
    from faultslip.errors import SolverError
    from faultslip.dynamics.spring_slider.regularized import simulate_regularized
    from faultslip.fault.scene import read_slider_scene
    from faultslip.dynamics.spring_slider.simulate import simulate

    system = read_slider_scene("san_andreas_1906.toml").slider()
    ours, data = timed(lambda: simulate(system, cycles=100), repeats)
    # the event-driven integrator at the same rtol 1e-6 the row states (issue 28: it ran at 1e-8)
    hybrid, hybrid_data = timed(lambda: simulate(system, cycles=100, slip_solver="DOP853", rtol=1e-6), max(1, repeats // 2))
    generic = {}
    for solver in ("RK45", "LSODA", "Radau"):
        started = time.perf_counter()
        try:
            result = simulate_regularized(system, 100, 1e-2 * system.platform_speed, solver, rtol=1e-6,
                                          max_evaluations=budget)
            generic[solver] = {"seconds": time.perf_counter() - started, "outcome": f"{result['event_time'].size} events"}
        except SolverError as error:  # a failure is a finding, not a timing: no seconds are reported for it
            generic[solver] = {"seconds": None, "outcome": f"failed: {error}"}
    return {"ours_s": ours, "target": "< 0.1 s", "events": int(data.sizes["event"]),
            "event_driven_DOP853_s": hybrid, "ratio_DOP853_over_ours": hybrid / ours,
            "generic_regularized_w0.01V": generic, "budget_evaluations": budget}


def auto_against_best_fixed(repeats):
    """Over the standard scenes: solve(method="auto") against the cheapest fixed method meeting 1e-6."""
    from faultslip.evaluation.bench import standard_scenes
    from faultslip.dynamics.spring_slider.closed_form import closed_form_cycle
    from faultslip.dynamics.spring_slider.exact_cycle import exact_cycle
    from faultslip.dynamics.methods import choose, solve
    from faultslip.dynamics.spring_slider.simulate import simulate

    rows = {}
    for name, (system, _) in standard_scenes().items():
        method, assessment, _ = choose(system)
        if method.name == "closed_form":
            fixed = lambda s=system: closed_form_cycle(s)  # noqa: E731
        elif method.name == "exact_cycle":
            fixed = lambda s=system: exact_cycle(s)  # noqa: E731
        else:
            rtol = assessment.settings["rtol"]
            solver = assessment.settings["slip_solver"]
            fixed = lambda s=system, r=rtol, v=solver: simulate(s, cycles=10, slip_solver=v, rtol=r,  # noqa: E731
                                                                 stop_when_converged=1e-6)
        auto_s, fixed_s, _, _ = side_by_side(lambda s=system: solve(s), fixed, repeats)
        rows[name] = {"method": method.name, "auto_s": auto_s, "best_fixed_s": fixed_s, "ratio": auto_s / fixed_s}
    total_auto = sum(r["auto_s"] for r in rows.values())
    total_fixed = sum(r["best_fixed_s"] for r in rows.values())
    return {"per_scene": rows, "total_auto_s": total_auto, "total_best_fixed_s": total_fixed,
            "ratio_total": total_auto / total_fixed, "target": "<= 1.2"}


def _rate_law_jacobian(theta, rate, *_):
    """d mu_s / d (mu_m, ln drop, ln b, ln d) of eq. 2-18, mu_s = mu_m + drop / E, E = 1 + drop b rate^d: the
    analytic Jacobian a competent user gives least_squares (issue 28: the baseline used finite differences)."""
    drop, b, d = math.exp(theta[1]), math.exp(theta[2]), math.exp(theta[3])
    power = rate ** d
    e = 1.0 + drop * b * power
    common = -drop * drop * b * power / (e * e)
    return np.column_stack([np.ones_like(rate), drop / (e * e), common, common * np.log(rate) * d])


def fit_bootstrap(repeats):
    """2000 bootstrap resamples of a 600-point fit: all at once (batched Levenberg-Marquardt, analytic
    Jacobian) against one scipy least_squares per resample with the same analytic Jacobian (same draws),
    and the largest relative difference of the 95 % intervals."""
    import scipy.optimize

    from faultslip.friction import fitting
    from faultslip.friction.materials import get_preset

    data = fitting.synthetic_data(get_preset("granodiorite_water"), points=600, noise=0.005, seed=1)
    real, real_least_squares = fitting._batched_fit, scipy.optimize.least_squares

    def with_jacobian(fun, x0, **options):
        return real_least_squares(fun, x0, jac=_rate_law_jacobian, **options)

    def one_at_a_time():
        fitting._batched_fit = lambda rate, mu, *rest: (np.full((mu.shape[0], rest[0].size), np.nan), mu.shape[0])
        scipy.optimize.least_squares = with_jacobian  # fitting imports it where used: the baseline gets the Jacobian
        try:
            return fitting.fit_rate_law(data, bootstrap=2000, seed=0)
        finally:
            fitting._batched_fit, scipy.optimize.least_squares = real, real_least_squares

    fitting.fit_rate_law(data, bootstrap=20, seed=0)  # imports and caches warm
    ours, theirs, batched, single = side_by_side(lambda: fitting.fit_rate_law(data, bootstrap=2000, seed=0),
                                                 one_at_a_time, max(2, repeats // 5))
    difference = max(abs(a / b - 1) for k in batched.intervals for a, b in zip(batched.intervals[k], single.intervals[k]))
    return {"points": 600, "resamples": 2000, "batched_s": ours, "one_at_a_time_s": theirs, "ratio": theirs / ours,
            "interval_difference": difference, "target": ">= 5x, same intervals for the same seed"}


def rate_state_step(repeats):
    """The issue-12 velocity step (aging law, 1 -> 10 µm/s at 10 s, 40 s at 100 Hz) at <= 1e-8 in friction.

    Reference: DOP853 at rtol 1e-13 in linear variables (mu, theta), restarted at the step. Ours:
    simulate_rate_state with auto, which takes the numba-compiled Dormand-Prince kernel on the log
    states where numba is installed; also timed, our LSODA path (log states, analytic Jacobian), what
    auto takes without numba. Baseline: the straightforward odeint a user writes, (mu, theta) with
    numpy in the right-hand side and tcrit at the step. Each runs at the loosest rtol that meets 1e-8
    against the reference. The kernel's first call in a process (compile, or load from numba's
    on-disk cache) is reported apart: it is paid once.
    """
    from scipy.integrate import odeint, solve_ivp

    from faultslip.dynamics.rate_state.slider import LoadHistory, RateStateSlider, simulate_rate_state
    from faultslip.friction.rate_state import get_law

    a, b, dc, mu0, v0, k = 0.005, 0.01, 10e-6, 0.6, 1e-6, 1e-3 / 1e-6
    times = np.linspace(0.0, 40.0, 4001)

    def f(t, y):
        # scalar maths on scalars, as a competent user writes it (issue 28: numpy on single floats cost 1.7x)
        mu, theta = y
        load = 1e-6 if t < 10.0 else 10e-6
        speed = v0 * math.exp((mu - mu0 - b * math.log(v0 * theta / dc)) / a)
        return [k * (load - speed), 1.0 - speed * theta / dc]

    pieces, y = [], [mu0, dc / 1e-6]
    for t0, t1 in ((0.0, 10.0), (10.0, 40.0)):
        sol = solve_ivp(f, (t0, t1), y, method="DOP853", rtol=1e-13, atol=1e-16, dense_output=True)
        pieces.append(sol.sol(times[(times >= t0) & ((times < t1) | (t1 == 40.0))])[0])
        y = sol.y[:, -1]
    reference = np.concatenate(pieces)
    slider = RateStateSlider(get_law("step_example"), k, 1.0)
    history = LoadHistory.velocity_steps([(0.0, 1e-6), (10.0, 10e-6)], 40.0)

    def ours(rtol, method="auto"):
        return simulate_rate_state(slider, history, t_eval=times, rtol=rtol, method=method).friction

    def baseline(rtol):
        return odeint(lambda y, t: f(t, y), [mu0, dc / 1e-6], times, rtol=rtol, atol=rtol * 1e-3, tcrit=[10.0])[:, 0]

    started = time.perf_counter()
    method = simulate_rate_state(slider, history, t_eval=times, rtol=1e-8).method
    first_call = time.perf_counter() - started
    rtol_ours = _loosest(lambda r: np.max(np.abs(ours(r) - reference)) <= 1e-8)
    rtol_lsoda = _loosest(lambda r: np.max(np.abs(ours(r, "lsoda") - reference)) <= 1e-8)
    rtol_base = _loosest(lambda r: np.max(np.abs(baseline(r) - reference)) <= 1e-8)
    ours_s, base_s, ours_mu, base_mu = side_by_side(lambda: ours(rtol_ours), lambda: baseline(rtol_base), repeats)
    lsoda_s, base2_s, _, _ = side_by_side(lambda: ours(rtol_lsoda, "lsoda"), lambda: baseline(rtol_base), repeats)
    peer = rsfmodel_peer(lambda: ours(rtol_ours), reference, repeats)
    return {"rsfmodel": peer, "ours_s": ours_s, "baseline_s": base_s, "ratio": base_s / ours_s, "rtol_ours": rtol_ours, "method": method,
            "first_call_s": first_call, "lsoda_s": lsoda_s, "lsoda_ratio": base2_s / lsoda_s, "rtol_lsoda": rtol_lsoda,
            "rtol_baseline": rtol_base, "error_ours": float(np.max(np.abs(ours_mu - reference))),
            "error_baseline": float(np.max(np.abs(base_mu - reference))), "target": 3.0,
            "baseline": "scipy.integrate.odeint on (mu, theta), math.exp/math.log right-hand side, tcrit at the step"}


def rsfmodel_peer(ours, reference, repeats) -> dict:
    """rsfmodel's own code (github jrleeman/rsfmodel, its velocity_step_one_state example, the same step in
    um and um/s) beside ours: at the loosest rtol meeting 1e-8 in friction against the same reference, and
    at its default rtol 1e-12. RSFMODEL_DIR is a checkout; without one the row says so. Its
    ``scipy.integrate.cumtrapz`` was removed from scipy: aliased to ``cumulative_trapezoid``."""
    import os

    import scipy.integrate

    path = os.environ.get("RSFMODEL_DIR")
    if not path or not os.path.isfile(os.path.join(path, "rsfmodel", "rsf.py")):
        return {"available": False, "reason": "no rsfmodel checkout (set RSFMODEL_DIR)"}
    sys.path.insert(0, path)
    if not hasattr(scipy.integrate, "cumtrapz"):
        scipy.integrate.cumtrapz = scipy.integrate.cumulative_trapezoid
    from rsfmodel import rsf, staterelations

    def run(rtol):
        model = rsf.Model()
        model.mu0, model.a, model.k, model.v, model.vref = 0.6, 0.005, 1e-3, 1.0, 1.0
        state = staterelations.DieterichState()
        state.b, state.Dc = 0.01, 10.0
        model.state_relations = [state]
        model.time = np.arange(0, 40.01, 0.01)
        velocity = np.ones_like(model.time)
        velocity[10 * 100:] = 10.0
        model.loadpoint_velocity = velocity
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            model.solve(rtol=rtol, atol=rtol)
        return model.results.friction

    rtol = _loosest(lambda r: np.max(np.abs(run(r) - reference)) <= 1e-8)
    ours_s, fair_s, _, fair = side_by_side(ours, lambda: run(rtol), max(3, repeats // 3))
    _, default_s, _, default = side_by_side(ours, lambda: run(1e-12), max(3, repeats // 3))
    return {"available": True, "rtol": rtol, "seconds": fair_s, "ours_s": ours_s, "ratio": fair_s / ours_s,
            "default_seconds": default_s, "default_ratio": default_s / ours_s,
            "error": float(np.max(np.abs(fair - reference))), "default_error": float(np.max(np.abs(default - reference)))}


def rate_state_cycles(repeats):
    """100 quasi-dynamic cycles at fault scale: SCEC SEAS BP1's friction (a 0.010, b 0.015, D_c 8 mm,
    sigma_n 50 MPa, V_pl 1e-9 m/s, G 32 GPa, c_s 3464 m/s) on a slider with K = G / 20 km."""
    from faultslip.dynamics.rate_state.slider import RateStateSlider, fault_cycles
    from faultslip.friction.rate_state import RateStateLaw

    law = RateStateLaw(a=0.010, b=0.015, critical_slip=0.008, mu0=0.6, reference_speed=1e-6)
    slider = RateStateSlider.at_fault(law, 3.2e10, 20e3, 50e6, density=2670.0, shear_wave_speed=3464.0)
    seconds, cycles = timed(lambda: fault_cycles(slider, 1e-9, cycles=100), max(3, repeats // 3))
    return {"seconds": seconds, "cycles": 100, "steps": cycles.steps, "method": cycles.method,
            "recurrence_years": cycles.recurrence / 3.15576e7,
            "slip_per_event_m": float(np.mean(cycles.slip_per_event)), "stiffness_ratio": cycles.stiffness_ratio,
            "target_s": 1.0}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats, small sweeps")
    parser.add_argument("--skip-sweeps", action="store_true", help="skip benchmarks 4 and 5 (sweep overhead and scale)")
    args = parser.parse_args(argv)
    repeats = 5 if args.quick else 15
    results = stamp()
    print("1. analytic slip phases against a competent solve_ivp baseline, equal work at 1e-6")
    results["exact_vs_integrators"] = r = exact_against_integrators(repeats)
    print(f"   {r['one_cycle']['scene']}")
    for target, row in r["one_cycle"]["per_accuracy"].items():
        print(f"      at {target}: exact {row['exact_s'] * 1e3:.3f} ms vs {row['baseline']}: "
              f"{row['baseline_s'] * 1e3:.3f} ms -> {row['ratio']:.1f}x ({row['evaluations']} evaluations)")
    row = r["distinct_cycles"]
    print(f"   {row['scene']}\n      faultslip {row['faultslip_s'] * 1e3:.1f} ms vs {row['baseline']}: "
          f"{row['baseline_s'] * 1e3:.1f} ms -> {row['ratio']:.1f}x ({row['evaluations']} evaluations)")
    print("2. fault scale: 100 cycles of the 1906 scene")
    results["fault_scale"] = r = fault_scale(repeats, 300_000 if args.quick else 1_000_000)
    print(f"   faultslip simulator: {r['ours_s'] * 1e3:.1f} ms for {r['events']} cycles (target < 100 ms)")
    print(f"   event-driven DOP853 slip phases: {r['event_driven_DOP853_s'] * 1e3:.1f} ms ({r['ratio_DOP853_over_ours']:.1f}x)")
    for solver, row in r["generic_regularized_w0.01V"].items():
        timing = f"{row['seconds']:.2f} s, " if row["seconds"] is not None else ""
        print(f"   generic regularised {solver}: {timing}{row['outcome'][:110]}")
    print("3. auto against the best fixed method over the standard scenes (tolerance 1e-6)")
    results["auto_vs_fixed"] = r = auto_against_best_fixed(repeats)
    for name, row in r["per_scene"].items():
        print(f"   {name:24s} {row['method']:20s} auto {row['auto_s'] * 1e3:8.3f} ms, fixed {row['best_fixed_s'] * 1e3:8.3f} ms"
              f" -> {row['ratio']:.2f}x")
    print(f"   total: auto {r['total_auto_s'] * 1e3:.1f} ms vs best fixed {r['total_best_fixed_s'] * 1e3:.1f} ms "
          f"-> {r['ratio_total']:.2f}x (target <= 1.2x)")
    print("4. fit bootstrap: 2000 resamples of 600 points")
    results["fit_bootstrap"] = r = fit_bootstrap(repeats)
    print(f"   batched {r['batched_s']:.2f} s vs one least_squares per resample {r['one_at_a_time_s']:.2f} s "
          f"-> {r['ratio']:.1f}x (target >= 5x); intervals agree to {r['interval_difference']:.1e}")
    print("5. rate-and-state: the velocity step at <= 1e-8, and 100 quasi-dynamic fault cycles")
    results["rate_state_step"] = r = rate_state_step(repeats)
    print(f"   step: ours ({r['method']}) {r['ours_s'] * 1e3:.2f} ms (rtol {r['rtol_ours']:g}) vs odeint "
          f"{r['baseline_s'] * 1e3:.2f} ms (rtol {r['rtol_baseline']:g}) -> {r['ratio']:.1f}x (target >= 3x); "
          f"first call {r['first_call_s']:.2f} s")
    print(f"   step without numba: our LSODA {r['lsoda_s'] * 1e3:.2f} ms (rtol {r['rtol_lsoda']:g}) -> "
          f"{r['lsoda_ratio']:.1f}x")
    results["rate_state_cycles"] = r = rate_state_cycles(repeats)
    print(f"   100 quasi-dynamic cycles (SEAS BP1 friction): {r['seconds']:.2f} s (target < 1 s), "
          f"recurrence {r['recurrence_years']:.1f} yr, slip {r['slip_per_event_m']:.2f} m")
    out = Path(__file__).resolve().parent / "results"
    out.mkdir(exist_ok=True)
    (out / "latest.json").write_text(json.dumps(results, indent=2, default=float) + "\n")
    print(f"wrote {out / 'latest.json'}")
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import readme

    print("updated README tables:", ", ".join(readme.update()))
    if not args.skip_sweeps:  # 4 and 5: the study engine's overhead and out-of-core scale
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        import sweep_scale

        sweep_scale.main(["--quick"] if args.quick else [])


if __name__ == "__main__":
    main()
