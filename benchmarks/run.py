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
import platform
import statistics
import sys
import time
import warnings
from pathlib import Path

import numpy as np

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


def exact_against_integrators(repeats):
    """100 lab cycles at equal accuracy (1e-6 on amplitude): exact cycle vs the best scipy integrator."""
    from faultslip.critical import critical
    from faultslip.exact_cycle import exact_cycle
    from faultslip.simulate import simulate
    from faultslip.slider import SliderSystem

    base = SliderSystem.from_preset("glass_dry", loading_rate="1 1/s", damping_ratio=0.01)
    system = base.at_loading_rate(0.1 * critical(base).critical_loading_rate)
    exact = exact_cycle(system)
    candidates = {}
    for solver in ("RK45", "DOP853", "Radau", "LSODA"):
        for rtol in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12):
            data = simulate(system, cycles=100, slip_solver=solver, rtol=rtol, verify_regime=False)
            if data.sizes["event"] == 100 and np.max(np.abs(data["amplitude"].values / exact.amplitude - 1)) <= 1e-6:
                candidates[solver] = rtol
                break
    rows = {}
    for solver, rtol in candidates.items():
        ours, theirs, data, other = side_by_side(lambda: simulate(system, cycles=100, slip_solver="analytic"),
                                                 lambda: simulate(system, cycles=100, slip_solver=solver, rtol=rtol,
                                                                  verify_regime=False), repeats)
        rows[solver] = {"rtol": rtol, "exact_s": ours, "integrator_s": theirs, "ratio": theirs / ours,
                        "evaluations": int(other.attrs["function_evaluations"])}
    best = min(rows, key=lambda s: rows[s]["integrator_s"])
    return {"scene": "glass_dry, zeta 0.01, 0.1 theta_c, 100 cycles, amplitude error <= 1e-6",
            "per_integrator": rows, "best_integrator": best, "ratio_best": rows[best]["ratio"], "target": ">= 100"}


def fault_scale(repeats, budget):
    """100 cycles of the 1906 scene: the project's simulator against generic integration."""
    from faultslip.errors import SolverError
    from faultslip.regularized import simulate_regularized
    from faultslip.scene import load_scene
    from faultslip.simulate import simulate

    system = load_scene("san_andreas_1906.toml").slider()
    ours, data = timed(lambda: simulate(system, cycles=100), repeats)
    hybrid, hybrid_data = timed(lambda: simulate(system, cycles=100, slip_solver="DOP853", rtol=1e-8), max(1, repeats // 2))
    generic = {}
    for solver in ("RK45", "LSODA", "Radau"):
        started = time.perf_counter()
        try:
            result = simulate_regularized(system, 100, 1e-2 * system.platform_speed, solver, rtol=1e-6,
                                          max_evaluations=budget)
            generic[solver] = {"seconds": time.perf_counter() - started, "outcome": f"{result['event_time'].size} events"}
        except SolverError as error:
            generic[solver] = {"seconds": time.perf_counter() - started, "outcome": f"failed: {error}"}
    return {"ours_s": ours, "target": "< 0.1 s", "events": int(data.sizes["event"]),
            "event_driven_DOP853_s": hybrid, "ratio_DOP853_over_ours": hybrid / ours,
            "generic_regularized_w0.01V": generic, "budget_evaluations": budget}


def auto_against_best_fixed(repeats):
    """Over the standard scenes: solve(method="auto") against the cheapest fixed method meeting 1e-6."""
    from faultslip.bench import standard_scenes
    from faultslip.closed_form import closed_form_cycle
    from faultslip.exact_cycle import exact_cycle
    from faultslip.methods import choose, solve
    from faultslip.simulate import simulate

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


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats, small sweeps")
    parser.add_argument("--skip-sweeps", action="store_true", help="skip benchmarks 4 and 5 (sweep overhead and scale)")
    args = parser.parse_args(argv)
    repeats = 5 if args.quick else 15
    results = {"machine": {"python": sys.version.split()[0], "platform": platform.platform(),
                           "processor": platform.processor()}}
    print("1. exact cycle against the best scipy integrator (100 lab cycles, amplitude error <= 1e-6)")
    results["exact_vs_integrators"] = r = exact_against_integrators(repeats)
    for solver, row in r["per_integrator"].items():
        print(f"   {solver:7s} rtol {row['rtol']:.0e}: {row['integrator_s'] * 1e3:8.1f} ms vs exact "
              f"{row['exact_s'] * 1e3:6.2f} ms -> {row['ratio']:7.0f}x ({row['evaluations']} evaluations)")
    print(f"   best integrator {r['best_integrator']}: exact is {r['ratio_best']:.0f}x faster (target >= 100x)")
    print("2. fault scale: 100 cycles of the 1906 scene")
    results["fault_scale"] = r = fault_scale(repeats, 300_000 if args.quick else 1_000_000)
    print(f"   faultslip simulator: {r['ours_s'] * 1e3:.1f} ms for {r['events']} cycles (target < 100 ms)")
    print(f"   event-driven DOP853 slip phases: {r['event_driven_DOP853_s'] * 1e3:.1f} ms ({r['ratio_DOP853_over_ours']:.1f}x)")
    for solver, row in r["generic_regularized_w0.01V"].items():
        print(f"   generic regularised {solver}: {row['seconds']:.2f} s, {row['outcome'][:110]}")
    print("3. auto against the best fixed method over the standard scenes (tolerance 1e-6)")
    results["auto_vs_fixed"] = r = auto_against_best_fixed(repeats)
    for name, row in r["per_scene"].items():
        print(f"   {name:24s} {row['method']:20s} auto {row['auto_s'] * 1e3:8.3f} ms, fixed {row['best_fixed_s'] * 1e3:8.3f} ms"
              f" -> {row['ratio']:.2f}x")
    print(f"   total: auto {r['total_auto_s'] * 1e3:.1f} ms vs best fixed {r['total_best_fixed_s'] * 1e3:.1f} ms "
          f"-> {r['ratio_total']:.2f}x (target <= 1.2x)")
    out = Path(__file__).resolve().parent / "results"
    out.mkdir(exist_ok=True)
    (out / "latest.json").write_text(json.dumps(results, indent=2, default=float) + "\n")
    print(f"wrote {out / 'latest.json'}")
    if not args.skip_sweeps:  # 4 and 5: the study engine's overhead and out-of-core scale
        sys.path.insert(0, str(Path(__file__).resolve().parent))
        import sweep_scale

        sweep_scale.main(["--quick"] if args.quick else [])


if __name__ == "__main__":
    main()
