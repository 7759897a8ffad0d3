"""Auto on rough-surface scenes, ranking the integrators by the family's fitted prices against by the calibration's
seconds: the CPU each takes and the error each makes, on fresh scenes.

    python benchmarks/rough_auto_choice.py [--seed 20261214] [--count 6] [--rounds 3]

The event-driven integrators' cost model counts evaluations as seed 003's laws take them. On a rough-surface table
the integrators' shares of them differ (RK45 takes more than counted and checks at a hundredth of its rtol where
it is dearest; LSODA's tight rtols cost it less), so auto ranked by that model takes DOP853 where LSODA costs less
(it had taken RK45 before the count was re-derived) (``benchmarks/family_costs.py`` fits each
integrator's rate; ``faultslip.models.rough_surface.cost.price``). Each draw moves three of the example's parameters
by a factor within 1/2 to 2 (``benchmarks/refinement_check.py``'s draw); each scene is solved by auto at each
tolerance, both ways, the two interleaved and alternating which goes first, CPU the median of ``--rounds`` timings
after a warm-up. Both are measured against DOP853 at rtol 1e-12 (the largest relative error over amplitude, period,
stress drop, a graze's excepted, peak slip speed and slip per event) and against their declared errors: the same
work, the same tolerance. Writes benchmarks/results/rough_auto_choice.json.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip import contract  # noqa: E402
from faultslip.contract.registry import read_scene  # noqa: E402
from faultslip.dynamics import methods  # noqa: E402
from faultslip.errors import FaultslipError  # noqa: E402
from faultslip.models.rough_surface import cost  # noqa: E402
from faultslip.models.rough_surface.scene import read_rough_scene  # noqa: E402
from provenance import stamp  # noqa: E402
from refinement_check import _largest_error, draw  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "rough_auto_choice.json"
TOLERANCES = (1e-3, 1e-4, 1e-6, 1e-8)
WAYS = {"fitted prices": cost.price, "calibration's seconds": None}


def _cpu(call) -> float:
    start = time.process_time()
    call()
    return time.process_time() - start


def measure(seed: int, count: int, rounds: int) -> list[dict]:
    warnings.simplefilter("ignore")
    base = read_scene(contract.families()["rough_surface"].example.scene)[0]
    rows = []
    for index, values in enumerate(draw(seed, count, 2.0)):
        try:
            system, _, settings = read_rough_scene(base.with_values(**values))
            reference = methods.solve(system, method="event_driven_DOP853", tolerance=1e-11, cycles=settings["cycles"])
        except FaultslipError:
            continue
        for tolerance in TOLERANCES:
            solve = {way: (lambda price=price: methods.solve(system, tolerance=tolerance, cycles=settings["cycles"],
                                                             price=price)) for way, price in WAYS.items()}
            answers = {way: call() for way, call in solve.items()}  # the warm-up, and the answers measured
            timings = {way: [] for way in WAYS}
            for round_ in range(rounds):
                for way in (list(WAYS) if round_ % 2 == 0 else list(WAYS)[::-1]):
                    timings[way].append(_cpu(solve[way]))
            row = {"scene": index, "tolerance": tolerance}
            for way, answer in answers.items():
                row[way] = {"method": answer.method, "rtol": answer.settings.get("rtol"),
                            "cpu_seconds": statistics.median(timings[way]),
                            "error": _largest_error(answer.cycle, reference.cycle),
                            "declared": answer.estimated_relative_error}
            row["cpu_ratio"] = row["calibration's seconds"]["cpu_seconds"] / row["fitted prices"]["cpu_seconds"]
            rows.append(row)
            print(json.dumps(row), flush=True)
    return rows


def summary(rows: list[dict]) -> dict:
    ratios = [row["cpu_ratio"] for row in rows]
    return {"runs": len(rows), "changed_method": sum(row["fitted prices"]["method"] != row["calibration's seconds"]
                                                     ["method"] for row in rows),
            "cpu_ratio_median": statistics.median(ratios), "cpu_ratio_min": min(ratios),
            "cpu_ratio_max": max(ratios),
            "by_tolerance": {f"{t:g}": statistics.median(r["cpu_ratio"] for r in rows if r["tolerance"] == t)
                             for t in TOLERANCES},
            "largest_error_over_declared": {way: max(r[way]["error"] / r[way]["declared"] for r in rows)
                                            for way in WAYS},
            "over_tolerance": {way: sum(r[way]["declared"] > r["tolerance"] for r in rows) for way in WAYS}}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=20261214)
    parser.add_argument("--count", type=int, default=6)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    rows = measure(args.seed, args.count, args.rounds)
    result = {**stamp(), "seed": args.seed, "count": args.count, "rounds": args.rounds,
              "tolerances": list(TOLERANCES), "summary": summary(rows), "rows": rows}
    print(json.dumps(result["summary"], indent=1))
    args.out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
