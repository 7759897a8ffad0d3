"""The event-driven and exact-map cycle methods' declared cost against the CPU time their runs use.

    python benchmarks/lab_cycle_cost.py [--quick]

On the random scenes of faultslip.evaluation.bench.random_scenes (12 a seed), each applicable steady-cycle method
(event_driven_DOP853, event_driven_LSODA, exact_map) is run twice at tolerance 1e-6 and 200 cycles, as ``faultslip
run`` does; the second run's CPU time (``time.process_time``) is set against the method's declared cost
(``Assessment.estimated_cost``) and the cycles it counted (:func:`faultslip.dynamics.methods.settling_cycles`)
against the cycles run. The calibration seeds (101-606) set TIME_OF_STICK_CYCLES and CURVED_LAW_EVALUATIONS;
the held-out seeds (707-1203) never did. Writes benchmarks/results/lab_cycle_cost.json (docs/methods.md's table).
"""

from __future__ import annotations

import argparse
import statistics
import time
import warnings

from faultslip.dynamics import methods
from faultslip.errors import FaultslipError, OutOfDomainWarning
from faultslip.evaluation import bench
from provenance import write_results

CALIBRATION_SEEDS = (101, 202, 303, 404, 505, 606)
HELD_OUT_SEEDS = (707, 808, 909, 1001, 1102, 1203)
METHODS = ("event_driven_DOP853", "event_driven_LSODA", "exact_map")
STEADY = ("amplitude", "period")


def measure(seeds, per_seed: int = 12) -> list[dict]:
    """One row per scene and applicable method: declared cost, CPU used, cycles counted and run."""
    rows = []
    for seed in seeds:
        for name, scene in bench.random_scenes(seed, per_seed).items():
            system = scene[0]
            for method in METHODS:
                assessment = methods.METHODS[method].assess(system, STEADY, 1e-6, 200)
                if not assessment.applicable:
                    continue
                try:
                    with warnings.catch_warnings():
                        warnings.simplefilter("ignore", OutOfDomainWarning)
                        methods.solve(system, method=method, cycles=200)  # warm: what is timed is the method
                        started = time.process_time()
                        solution = methods.solve(system, method=method, cycles=200)
                        used = time.process_time() - started
                except FaultslipError as error:
                    rows.append({"scene": name, "method": method, "failed": str(error)})
                    continue
                rows.append({"scene": name, "method": method, "auto": methods.choose(system, STEADY, 1e-6, 200)[0].name,
                             "kinetic_law": type(system.kinetic_law).__name__,
                             "time_of_stick": bool(system.static_law.depends_on_stick_time),
                             "declared_seconds": assessment.estimated_cost, "cpu_seconds": used,
                             "cycles_counted": methods.settling_cycles(system, STEADY, 200,
                                                                       steady_above_critical=method == "exact_map"),
                             "cycles_run": int(solution.dataset["event_time"].size)})
    return rows


def summary(rows: list[dict]) -> dict:
    """Declared / used: median, range, and how many within 2x, per method."""
    out = {}
    for method in METHODS:
        ratios = [r["declared_seconds"] / r["cpu_seconds"] for r in rows if r["method"] == method and "failed" not in r]
        if ratios:
            under = [r["auto"] for r in rows if r["method"] == method and "failed" not in r
                     and r["declared_seconds"] < 0.5 * r["cpu_seconds"]]
            out[method] = {"runs": len(ratios), "median": statistics.median(ratios), "low": min(ratios),
                           "high": max(ratios), "within_2x": sum(0.5 <= q <= 2 for q in ratios),
                           "under_half": len(under), "auto_where_under": sorted(set(under))}
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="3 scenes a seed")
    args = parser.parse_args(argv)
    per_seed = 3 if args.quick else 12
    calibration, held_out = measure(CALIBRATION_SEEDS, per_seed), measure(HELD_OUT_SEEDS, per_seed)
    write_results("lab_cycle_cost.json", {"calibration": summary(calibration), "held_out": summary(held_out),
                                          "scenes_per_seed": per_seed, "calibration_seeds": list(CALIBRATION_SEEDS),
                                          "held_out_seeds": list(HELD_OUT_SEEDS),
                                          "rows": {"calibration": calibration, "held_out": held_out}})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
