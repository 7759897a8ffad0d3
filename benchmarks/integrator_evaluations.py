"""Right-hand-side evaluations per slip phase of the event-driven integrators: auto's cost table, re-derived.

    python benchmarks/integrator_evaluations.py [--quick]

faultslip.dynamics.methods.INTEGRATOR_EVALUATIONS gives each scipy integrator's evaluations per slip phase at rtol
1e-3, 1e-6, 1e-9 and 1e-12 on a linear kinetic law (a curved law multiplies it: CURVED_LAW_EVALUATIONS); auto's
cost of an event-driven run is built on it. Here every integrator runs the linear-law stick-slip scenes of
faultslip.evaluation.bench.random_scenes (the integrators' calibration seeds, 1-3, 60 scenes a seed) for 10 cycles
at each of those rtols; a run's evaluations over its slip phases (its events) is one count, and the table is the
median count. Writes benchmarks/results/integrator_evaluations.json, which tests/models/spring_slider/
test_methods.py reads against the table; ``--quick`` (10 scenes a seed, for a look) writes
integrator_evaluations_quick.json instead, so that the table's evidence is always the full measurement.
"""

from __future__ import annotations

import argparse
import statistics
import warnings

from faultslip.dynamics.methods import INTEGRATOR_EVALUATIONS
from faultslip.dynamics.spring_slider.simulate import simulate
from faultslip.errors import FaultslipError, OutOfDomainWarning
from faultslip.evaluation import bench
from provenance import write_results

RTOLS = (1e-3, 1e-6, 1e-9, 1e-12)
CYCLES = 10


def measure(seeds, per_seed: int) -> dict:
    """Per integrator: the evaluations per slip phase of every linear-law scene's run at each rtol."""
    counts = {solver: {str(rtol): [] for rtol in RTOLS} for solver in INTEGRATOR_EVALUATIONS}
    failed = []
    for seed in seeds:
        for name, (system, _) in bench.random_scenes(seed, per_seed).items():
            if not system.is_linear:
                continue
            for solver in INTEGRATOR_EVALUATIONS:
                for rtol in RTOLS:
                    try:
                        with warnings.catch_warnings():
                            warnings.simplefilter("ignore", OutOfDomainWarning)
                            dataset = simulate(system, cycles=CYCLES, slip_solver=solver, rtol=rtol,
                                               verify_regime=False)
                    except FaultslipError as error:
                        failed.append({"scene": name, "solver": solver, "rtol": rtol, "error": str(error)})
                        continue
                    phases = dataset.sizes["event"]
                    if phases:
                        counts[solver][str(rtol)].append(dataset.attrs["function_evaluations"] / phases)
    return {"counts": counts, "failed": failed}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="10 scenes a seed")
    args = parser.parse_args(argv)
    per_seed = 10 if args.quick else bench.CALIBRATION_SCENES
    measured = measure(bench.CALIBRATION_SEEDS, per_seed)
    medians = {solver: [statistics.median(values[str(rtol)]) for rtol in RTOLS]
               for solver, values in measured["counts"].items()}
    write_results("integrator_evaluations_quick.json" if args.quick else "integrator_evaluations.json", {
        "rtol": list(RTOLS), "cycles": CYCLES, "seeds": list(bench.CALIBRATION_SEEDS), "scenes_per_seed": per_seed,
        "linear_scenes": len(next(iter(measured["counts"].values()))[str(RTOLS[0])]),
        "median_per_phase": medians, "table": {solver: list(values) for solver, values in INTEGRATOR_EVALUATIONS.items()},
        **measured})
    for solver, values in medians.items():
        print(solver, " ".join(f"{value:.0f}" for value in values), "table", INTEGRATOR_EVALUATIONS[solver])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
