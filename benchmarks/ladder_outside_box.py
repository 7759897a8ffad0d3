"""The recurrence a 2-D run's budget expects of a fault outside the one slider's calibrated box, against its 2-D
answer (issue 68: the budget counts a run's events by it).

    python benchmarks/ladder_outside_box.py [--count 16] [--workers 2]

Outside the box the one slider declares no corrected answer; the budget still needs a recurrence to count the
events a 2-D run will see (:func:`faultslip.fault.ladder.expected_recurrence`). Three candidates, each set beside
the 2-D recurrence of faults drawn as ``benchmarks/ladder_designs.py`` draws them but with W / h* of 0.55-1.2, below
the calibrated box (seed 68006; every bundled small 2-D scene lies there, at 0.55):

- the derived block, uncorrected;
- the block times the calibration faults' median ratio (what the budget took before);
- the correction evaluated with each group clamped to the box (what it takes now).

Writes ``benchmarks/results/ladder_outside_box.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
from concurrent.futures import as_completed
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.constants import JULIAN_YEAR as YEAR  # noqa: E402
from faultslip.fault import ladder  # noqa: E402
from faultslip.io.processes import stop_pool, worker_pool  # noqa: E402
from faultslip.models.fault_2d.calibration import Design, run_design  # noqa: E402
from ladder_designs import ELEMENTS_PER_PROCESS_ZONE, draw  # noqa: E402
from provenance import stamp  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "ladder_outside_box.json"
SEED = 68006
RATIOS = (0.55, 1.2)


def predictions(design: Design) -> dict:
    """The three candidates' recurrences (s) of a design, and where its groups lie outside the box."""
    fault = design.two_d(ELEMENTS_PER_PROCESS_ZONE).fault.description()
    table = ladder.load_calibration()
    raw, group = ladder.block_answer(fault, cycles=2)
    return {"block": raw["recurrence"],
            "median_ratio": raw["recurrence"] * (1.0 + table["recurrence"]["median_bias_uncorrected"]),
            "clamped": ladder.clamped_recurrence(raw["recurrence"], group, table),
            "outside": ladder.outside_box(group, table)}


def _run(design: Design) -> dict:
    return {**run_design(design, cycles=6, elements_per_process_zone=ELEMENTS_PER_PROCESS_ZONE),
            "predicted": predictions(design)}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=16)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    designs = draw(args.count, SEED, "outside", ratio_range=RATIOS)
    pool = worker_pool(args.workers)
    rows = []
    try:
        for future in as_completed([pool.submit(_run, design) for design in designs]):
            row = future.result()
            rows.append(row)
            print(f"{row['design']['name']}: W/h* {row['design']['width_over_nucleation']:.2f}, 2-D recurrence "
                  f"{row['recurrence_2d'] / YEAR:.4g} yr ({row['sequence']}), clamped block "
                  f"{row['predicted']['clamped'] / YEAR:.4g} yr", flush=True)
    finally:
        stop_pool(pool)
    settled = [row for row in rows if row["sequence"] != "unsettled" and math.isfinite(row["recurrence_2d"])
               and row["recurrence_2d"] > 0]
    summary = {}
    for name in ("block", "median_ratio", "clamped"):
        ratios = [row["predicted"][name] / row["recurrence_2d"] for row in settled]
        summary[name] = {"faults": len(ratios), "within_2x": sum(0.5 <= r <= 2.0 for r in ratios),
                         "ratio_min": min(ratios), "ratio_median": statistics.median(ratios),
                         "ratio_max": max(ratios)}
        print(f"{name}: predicted / 2-D {summary[name]['ratio_min']:.2f} to {summary[name]['ratio_max']:.2f}, median "
              f"{summary[name]['ratio_median']:.2f}; {summary[name]['within_2x']} of {len(ratios)} within 2x")
    OUT.write_text(json.dumps({**stamp(), "seed": SEED, "ratios": list(RATIOS), "summary": summary,
                               "left_out_unsettled": len(rows) - len(settled), "rows": rows}, indent=1) + "\n",
                   encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main())
