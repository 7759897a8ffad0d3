"""A sequence that is not periodic in one event: BP1's period-3 variant at three resolutions (issue 42, item 2).

    python benchmarks/fault_2d_period3.py [--years 1500]

configs/seas_bp1_period3.toml is SEAS BP1-QD with a = 0.010 down to 12 km (not 15) and sigma_n = 40 MPa (not 50).
Its system-size events form a period-3 supercycle. This runs it on 25 m, 50 m and 100 m elements, each for the
same simulated time, and records what ``faultslip run`` reports: the sequence's kind and period, each interval of
the supercycle, the slip and hypocentre of each event, and the mean interval. The 25 m run is the reference: on
BP1 itself faultslip's 25 m recurrence is within 2e-4 of QDYN's (benchmarks/results/fault_2d_qdyn_study.json).
Intervals are compared supercycle against supercycle, aligned at the longest interval (a run of another length
or resolution may enter the supercycle at another of its events).

Writes benchmarks/results/fault_2d_period3.json, which tests/models/fault_2d/test_fault_2d.py reads for its reference.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.models.fault_2d.analysis import summarise  # noqa: E402
from faultslip.models.fault_2d.integrate import YEAR  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)

SCENE = ROOT / "configs" / "seas_bp1_period3.toml"


def aligned(intervals) -> list[float]:
    """A supercycle's intervals starting at its longest (the phase every run can agree on)."""
    values = list(intervals)
    start = int(np.argmax(values))
    return values[start:] + values[:start]


def measure(element_size: float, years: float) -> dict:
    scene = read_fault_2d_scene(SCENE).at_element_size(element_size)
    scene.duration = years * YEAR
    started = time.perf_counter()
    run = scene.run()
    seconds = time.perf_counter() - started
    summary = summarise(run, tolerance=1e-3)
    sequence = summary.sequence
    return {"element_size_m": element_size, "elements": int(scene.fault.a.size), "years": years,
            "kind": sequence.kind, "period": sequence.period, "spread": sequence.spread,
            "intervals_yr": aligned((sequence.intervals / YEAR).tolist()),
            "mean_interval_yr": sequence.mean_interval / YEAR, "event_slips_m": list(summary.event_slips),
            "hypocentres_m": list(summary.event_hypocentres), "wall_s": seconds, "steps": run.steps}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--years", type=float, default=1500.0)
    args = parser.parse_args(argv)
    runs = [measure(size, args.years) for size in (25.0, 50.0, 100.0)]
    reference = runs[0]
    for run in runs:
        if run["period"] == reference["period"] and reference["period"] > 0:
            run["interval_errors"] = [abs(a / b - 1) for a, b in zip(run["intervals_yr"], reference["intervals_yr"])]
        print(f"{run['element_size_m']:5.0f} m: {run['kind']} (p {run['period']}), intervals "
              + ", ".join(f"{v:.3f}" for v in run["intervals_yr"])
              + f" yr, mean {run['mean_interval_yr']:.4f} yr, {run['wall_s']:.0f} s"
              + (f"; largest interval error {max(run['interval_errors']):.2e}" if "interval_errors" in run else ""))
    out = ROOT / "benchmarks" / "results" / "fault_2d_period3.json"
    out.write_text(json.dumps({**stamp(), "scene": SCENE.name,
                               "runs": runs}, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}")


if __name__ == "__main__":
    main()
