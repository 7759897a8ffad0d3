"""The refinement check of event-driven runs on a law the calibration never drew, on fresh rough-surface scenes.

    python benchmarks/refinement_check.py [--count 12] [--spread 2] [--seeds 20261210 20261211] [--held-out 20261212]

The event-driven integrators' declared error was fitted on seed 003's laws (benchmarks/event_driven_calibration.py).
Seed 000's rough-surface law is a table (kinks at its knots), and its stress drops are a fraction of the slip, so
the calibrated error had been exceeded on it. Such a run is now checked against one at a hundredth of its rtol
(``faultslip.dynamics.methods.refinement_check``). Each draw moves three of the example scene's parameters by a
factor log-uniform within 1 / spread to spread; each scene is run by every integrator at tolerances 1e-3 to 1e-7
(``solve``, the method forced, as ``faultslip run --method`` does) and measured against DOP853 at rtol 1e-12: the
largest relative error over amplitude, period, stress drop (a graze's excepted), peak slip speed and slip per event,
over the declared error with the check, and over the calibrated error alone (the first run's, as before the check).
Seeds 20261210 and 20261211 are the draws the factor 3 was chosen on; the held-out seed is a draw it never saw.
Writes benchmarks/results/refinement_check.json.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import warnings
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip import contract  # noqa: E402
from faultslip.contract.registry import cells_of, read_scene  # noqa: E402
from faultslip.dynamics import methods  # noqa: E402
from faultslip.errors import FaultslipError  # noqa: E402
from faultslip.models.rough_surface.scene import read_rough_scene  # noqa: E402
from faultslip.units import to_si_scalar  # noqa: E402
from provenance import stamp  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "refinement_check.json"
SOLVERS = ("RK45", "DOP853", "LSODA", "Radau")
TOLERANCES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7)


def draw(seed: int, count: int, spread: float) -> list[dict]:
    """``count`` rough-surface scenes: three of the example's parameters each moved by a log-uniform factor."""
    family = contract.families()["rough_surface"]
    base, found = read_scene(family.example.scene)
    parameters = {k: p for k, p in cells_of(found, base).parameters(base).items() if p.unit}
    document = base.document()
    rng = np.random.default_rng(seed)
    scenes = []
    for _ in range(count):
        values = {}
        for name in rng.choice(sorted(parameters), size=3, replace=False):
            table, key = parameters[name].location
            given = to_si_scalar((document.get(table, {}) if table else document)[key], parameters[name].kind, name,
                                 parameters[name].unit)
            values[str(name)] = given * math.exp(rng.uniform(-math.log(spread), math.log(spread)))
        scenes.append(values)
    return scenes


def _largest_error(cycle, reference) -> float:
    graze = methods._grazes(reference)
    return max(abs(getattr(cycle, name) / getattr(reference, name) - 1) for name in methods.CHECKED_OUTPUTS
               if not (graze and name == "stress_drop"))


def _unchecked(chosen, system, outputs, tolerance, cycles, settings, run, error, reason):
    """The run as solve had declared it before the check: its calibrated error and settling."""
    return (*run, error, reason, settings)


def measure_draw(seed: int, count: int, spread: float) -> dict:
    """Every scene of the draw by every integrator and tolerance: one row each."""
    warnings.simplefilter("ignore")
    base = read_scene(contract.families()["rough_surface"].example.scene)[0]
    rows, skipped = [], 0
    for index, values in enumerate(draw(seed, count, spread)):
        try:
            system, _, settings = read_rough_scene(base.with_values(**values))
            reference = methods.solve(system, method="event_driven_DOP853", tolerance=1e-11, cycles=settings["cycles"])
        except FaultslipError:
            skipped += 1
            continue
        for solver in SOLVERS:
            for tolerance in TOLERANCES:
                try:
                    solution = methods.solve(system, method=f"event_driven_{solver}", tolerance=tolerance,
                                             cycles=settings["cycles"])
                except FaultslipError:
                    continue
                error = _largest_error(solution.cycle, reference.cycle)
                checking = methods.refinement_check
                methods.refinement_check = _unchecked  # the same run as before the check: its calibrated error
                try:
                    before = methods.solve(system, method=f"event_driven_{solver}", tolerance=tolerance,
                                           cycles=settings["cycles"])
                finally:
                    methods.refinement_check = checking
                rows.append({"scene": index, "solver": solver, "tolerance": tolerance, "rtol": solution.settings["rtol"],
                             "first_rtol": before.settings["rtol"],
                             "error": error, "declared": solution.estimated_relative_error,
                             "error_before": _largest_error(before.cycle, reference.cycle),
                             "declared_before": before.estimated_relative_error,
                             "evaluations_before": int(before.function_evaluations),
                             "reference_declared": reference.estimated_relative_error,
                             "evaluations": int(solution.function_evaluations)})
    return {"seed": seed, "scenes": count, "skipped": skipped, "rows": rows, "summary": summary(rows)}


def summary(rows: list[dict]) -> dict:
    """The largest error / declared with the check and before it (the first run, its calibrated error), and the
    evaluations the check costs."""
    checked = [r["error"] / r["declared"] for r in rows]
    before = [r["error_before"] / r["declared_before"] for r in rows]
    worst = rows[int(np.argmax(checked))]
    cost = [r["evaluations"] / r["evaluations_before"] for r in rows]
    return {"runs": len(rows), "largest_ratio": max(checked), "over_declared": int(sum(c > 1 for c in checked)),
            "at": f"{worst['solver']} tolerance {worst['tolerance']:g}, scene {worst['scene']}",
            "largest_ratio_before": max(before), "over_declared_before": int(sum(b > 1 for b in before)),
            "tightened": int(sum(r["rtol"] < r["first_rtol"] for r in rows)),
            "evaluations_ratio_median": float(np.median(cost)), "evaluations_ratio_max": max(cost)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=12)
    parser.add_argument("--spread", type=float, default=2.0)
    parser.add_argument("--seeds", type=int, nargs="+", default=[20261210, 20261211])
    parser.add_argument("--held-out", type=int, default=20261212)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    seeds = [*args.seeds, args.held_out]
    with ProcessPoolExecutor(args.workers) as pool:
        draws = list(pool.map(measure_draw, seeds, [args.count] * len(seeds), [args.spread] * len(seeds)))
    for found in draws:
        print(f"seed {found['seed']}: {json.dumps(found['summary'])}", flush=True)
    result = {**stamp(), "spread": args.spread, "tolerances": list(TOLERANCES), "solvers": list(SOLVERS),
              "factor": methods.REFINEMENT_FACTOR, "refinement": methods.REFINEMENT,
              "chosen_on": draws[:-1], "held_out": draws[-1]}
    args.out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
