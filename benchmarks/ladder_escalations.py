"""Escalations up the ladder, each timed against the budget's estimate made before it started (issue 68).

    python benchmarks/ladder_escalations.py [--count 12] [--workers 2] [--seed 68000] [--tolerance 0.1]

Faults drawn at random over the one slider's calibrated box (benchmarks/ladder_designs.py's box; seed 68000 is
the draw the per-step cost was fitted on, FAULT_2D_STEP_SECONDS, and the step count's power of the elements per
L_b; seed 68001, written to ladder_escalations_held_out.json, is a draw they never saw; 68003, 68004, 68005,
68008, 68009, 68013 and 68021, with --out, seven more; 68050, run after the step model's last fit and never
fitted, an eighth; 68060, never fitted either, on another machine; 68070, the first with the machine speed
record; 68080, the first with the probe's weight beside its median), each as a scene over eight of its expected
recurrences, are
run as a user would: ``faultslip.run(scene, tolerance=...)``, by default at tolerance 0.1 on 1 to 1.5 times the
fewest elements per L_b at which one run can declare it (its element size's error with the change of kind of
sequence one run cannot see, faultslip.models.fault_2d.analysis.single_run_error: 8 to 12). Seed 68000, the fit,
ran at tolerance 0.05 on 3 to 5 per L_b (``--tolerance 0.05 --resolutions 3 5``), before one run declared that
term; the library now refuses those scenes before any work. The one slider's ±50 % cannot meet the tolerance, so
each escalates to the 2-D fault of the same scene, and its result reports the estimate made before it started and
the CPU time it used. Each
worker is a fresh process: its first escalation loads the compiled step (or compiles it, where numba's cache is
empty), which the estimate counts (FAULT_2D_FIRST_RUN_SECONDS). Writes benchmarks/results/ladder_escalations.json.
"""

from __future__ import annotations

import argparse
import json
import sys
from concurrent.futures import as_completed
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import faultslip  # noqa: E402
from faultslip.errors import InputError  # noqa: E402
from faultslip.fault.ladder import expected_recurrence  # noqa: E402
from faultslip.models.fault_2d.analysis import kind_checked_resolution  # noqa: E402
from faultslip.io import machine  # noqa: E402
from faultslip.io.processes import stop_pool, worker_pool  # noqa: E402
from ladder_designs import draw  # noqa: E402
from provenance import stamp  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "ladder_escalations.json"


def _escalate(design, resolution, tolerance):
    scene = design.two_d(resolution)
    scene = replace(scene, duration=8 * expected_recurrence(scene.fault.description()))
    try:
        result = faultslip.run(scene, tolerance=tolerance)
    except InputError as refused:  # as a user is told: e.g. a fault just past the cost model's fit, before any work
        return {"design": asdict(design), "elements_per_process_zone": resolution, "elements": scene.fault.count,
                "refused": str(refused)}
    speed = machine.speed_reading()
    return {"design": asdict(design), "elements_per_process_zone": resolution, "elements": scene.fault.count,
            "duration": scene.duration, "method": result.method, "escalated_from": result.values["escalated_from"],
            "estimated_seconds": float(result["estimated_seconds"].to("s").magnitude),
            "cpu_time": float(result["cpu_time"].to("s").magnitude), "runs": int(result.values["runs"]),
            "steps": int(result.values["steps"]), "sequence": result.values["sequence"],
            "recurrence": float(result["recurrence_interval"].to("s").magnitude),
            "declared_error": result.estimated_relative_error,
            # what the estimate took for this machine's speed (faultslip.io.machine), in this worker, and of how
            # many readings of the machine speed record (this worker's probe among them) that was the median
            "machine_factor": machine.factor("fault_2d_step"),
            "machine_readings": speed["readings"],
            "probe_factor": speed["reading"] / machine.references()["fault_2d_step"]}


def total_steps(row: dict) -> float:
    """An escalation's steps over all its runs: an unsettled run is rerun twice as long, so its runs took ``steps``
    (the last's) times (2^runs - 1) / 2^(runs - 1)."""
    runs = row.get("runs", 1)
    return row["steps"] * (2 ** runs - 1) / 2 ** (runs - 1)


def resolution_range(tolerance: float, rtol: float) -> tuple[float, float]:
    """The elements per L_b a draw runs on where none are given: from the fewest at which one run declares at most
    ``tolerance`` (its element size's error, kind-change term counted, plus 10 rtol) to 1.5 times that."""
    low = kind_checked_resolution(tolerance - 10 * rtol) * 1.001  # above the limit, not on it
    return low, 1.5 * low


def escalations(count: int, seed: int, workers: int = 2, tolerance: float = 0.1,
                resolutions: tuple[float, float] | None = None) -> list[dict]:
    """The draw's escalations, ``workers`` at a time, each in a fresh worker process: one row each."""
    designs = draw(count, seed, "escalation")
    low, high = resolutions or resolution_range(tolerance, designs[0].two_d(3.0).rtol)
    resolutions = np.random.default_rng(seed).uniform(low, high, count)
    pool = worker_pool(workers)
    rows = []
    try:
        futures = [pool.submit(_escalate, design, float(res), tolerance) for design, res in zip(designs, resolutions)]
        for future in as_completed(futures):
            row = future.result()
            rows.append(row)
            if "refused" in row:
                print(f"{row['design']['name']}: refused before it ran: {row['refused']}", flush=True)
                continue
            print(f"{row['design']['name']}: {row['elements']} elements, estimated {row['estimated_seconds']:.1f} s, "
                  f"used {row['cpu_time']:.1f} s CPU in {row['runs']} run(s) ({row['estimated_seconds'] / row['cpu_time']:.2f}x)",
                  flush=True)
    finally:
        stop_pool(pool)
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, default=12)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=68000)
    parser.add_argument("--tolerance", type=float, default=0.1, help="the tolerance each scene is run to (default 0.1)")
    parser.add_argument("--resolutions", type=float, nargs=2, default=None, metavar=("LOW", "HIGH"),
                        help="elements per L_b drawn in [LOW, HIGH] (default: from the tolerance, resolution_range)")
    parser.add_argument("--out", default=None,
                        help="where to write (default: ladder_escalations.json for seed 68000, else "
                             "ladder_escalations_held_out.json)")
    args = parser.parse_args(argv)
    rows = escalations(args.count, args.seed, args.workers, args.tolerance, args.resolutions)
    ran = [row for row in rows if "refused" not in row]
    ratios = [row["estimated_seconds"] / row["cpu_time"] for row in ran]
    summary = {"escalations": len(ran), "refused": len(rows) - len(ran), "within_2x": int(sum(0.5 <= r <= 2 for r in ratios)),
               "ratio_min": min(ratios), "ratio_median": float(np.median(ratios)), "ratio_max": max(ratios)}
    out = Path(args.out) if args.out else OUT if args.seed == 68000 else OUT.with_name("ladder_escalations_held_out.json")
    out.write_text(json.dumps({**stamp(), "seed": args.seed, "tolerance": args.tolerance, "summary": summary,
                               "rows": rows}, indent=1) + "\n", encoding="utf-8")
    print(summary)


if __name__ == "__main__":
    main()
