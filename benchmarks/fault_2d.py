"""SEAS BP1-QD on faultslip's 2-D fault: convergence, cost, and the loosest tolerance that keeps it.

    python benchmarks/fault_2d.py [--quick] [--sizes 50 25] [--rtols 1e-6 1e-7 1e-8 1e-9]

1. **Convergence.** BP1 for 3000 years at each element size (default 50 m and 25 m, rtol 1e-8):
   its recurrence interval and surface slip per event from the settled sequence, the steps and the
   wall time, and the relative difference between the two sizes.
2. **Equal accuracy.** At 100 m (cheap), the recurrence at each rtol against the tightest: the
   loosest rtol within 0.1 % of it is the fair setting at which to time a code (issue 33); then
   BP1 at 25 m for 3000 years at that rtol, timed.

Writes benchmarks/results/fault_2d.json, rendered into the docs' tables. Every number is measured in
this run; the machine and date are recorded. --quick runs 1000 years at 100 m and 200 m only.
"""

from __future__ import annotations

import argparse
import json
import sys
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.models.fault_2d.analysis import summarise  # noqa: E402
from faultslip.models.fault_2d.integrate import YEAR, run_cycles  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)

SCENE = ROOT / "configs" / "seas_bp1.toml"


def one(size: float, years: float, rtol: float) -> dict:
    scene = read_fault_2d_scene(SCENE).at_element_size(size)
    run = run_cycles(scene.fault, years * YEAR, rtol=rtol, stations=scene.stations, kernel="auto")
    summary = summarise(run, tolerance=1e-3)
    row = {"element_size_m": size, "elements": scene.fault.count, "years": years, "rtol": rtol,
           "steps": run.steps, "rejected": run.rejected, "wall_s": run.wall_time, "kernel": run.kernel,
           "events": summary.events, "settled": summary.settled, "recurrence_yr": summary.recurrence_interval / YEAR,
           "recurrence_spread": summary.recurrence_spread, "surface_slip_m": summary.surface_slip_per_event,
           "plate_slip_balance": summary.plate_slip_balance_surface,
           "plate_slip_balance_range": list(summary.plate_slip_balance_range)}
    print(f"  {size:g} m, {years:g} yr, rtol {rtol:g}: T {row['recurrence_yr']:.6g} yr (settled {summary.settled}), "
          f"surface slip {row['surface_slip_m']:.6g} m, {run.steps} steps, {run.wall_time:.1f} s", flush=True)
    return row


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--sizes", type=float, nargs="+", default=[50.0, 25.0])
    parser.add_argument("--rtols", type=float, nargs="+", default=[1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9])
    parser.add_argument("--tolerance-years", type=float, default=1500.0)
    parser.add_argument("--finer", type=float, help="run only this finer element size (m) for 3000 yr at rtol 1e-8 and "
                        "add it to the saved results, with its convergence against the finest saved run")
    parser.add_argument("--keep-finer", action="store_true", help="with --finer: keep the saved run at that size and "
                        "run the next coarser one again, so that both costs come from this machine and code")
    args = parser.parse_args(argv)
    if args.finer is not None:
        return _finer(args.finer, args.keep_finer)
    years = 1000.0 if args.quick else 3000.0
    sizes = [200.0, 100.0] if args.quick else args.sizes
    print("convergence:")
    convergence = [one(size, years, 1e-8) for size in sizes]
    coarse, fine = convergence[0], convergence[-1]
    differences = {"recurrence": abs(coarse["recurrence_yr"] / fine["recurrence_yr"] - 1),
                   "surface_slip": abs(coarse["surface_slip_m"] / fine["surface_slip_m"] - 1)}
    print("tolerance at 100 m:")
    tolerance = [one(100.0, args.tolerance_years, rtol) for rtol in sorted(args.rtols, reverse=True)]
    reference = tolerance[-1]["recurrence_yr"]
    for row in tolerance:
        row["recurrence_error"] = abs(row["recurrence_yr"] / reference - 1)
    good = [row for row in tolerance[:-1] if row["recurrence_error"] <= 1e-3 and row["settled"]]
    loosest = max((row["rtol"] for row in good), default=tolerance[-1]["rtol"])
    print(f"loosest rtol within 0.1 %: {loosest:g}; BP1 at {sizes[-1]:g} m with it:")
    timed = one(sizes[-1], years, loosest) if loosest != 1e-8 else dict(fine)
    result = {"convergence": convergence, "difference_coarse_fine": differences, "tolerance_study": tolerance,
              "loosest_rtol": loosest, "timed_at_loosest": timed,
              **stamp(), "quick": args.quick}
    out = ROOT / "benchmarks" / "results" / ("fault_2d_quick.json" if args.quick else "fault_2d.json")
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}; python benchmarks/readme.py writes the docs' table")
    return result


def _finer(size: float, keep_finer: bool = False) -> dict:
    """One more convergence row at ``size`` (3000 yr, rtol 1e-8), its differences from the next coarser row, and
    where its cost went against that row: steps, cost per step, and the N log N an FFT product scales as.
    ``keep_finer``: the saved row at ``size`` stays and the coarser row is run again (both costs then come from
    this machine and code)."""
    out = ROOT / "benchmarks" / "results" / "fault_2d.json"
    result = json.loads(out.read_text(encoding="utf-8"))
    saved = {r["element_size_m"]: r for r in result["convergence"]}
    coarser = [r for r in result["convergence"] if r["element_size_m"] > size]
    if not coarser:
        raise SystemExit(f"--finer {size:g} m has no coarser saved run to converge against")
    previous = min(coarser, key=lambda row: row["element_size_m"])
    if keep_finer:
        if size not in saved:
            raise SystemExit(f"--keep-finer: no saved run at {size:g} m")
        print(f"the saved {size:g} m run kept; {previous['element_size_m']:g} m run again:")
        previous = one(previous["element_size_m"], 3000.0, 1e-8)
        result["convergence"] = [r for r in result["convergence"] if r["element_size_m"] != previous["element_size_m"]]
        result["convergence"].insert(0, previous)
        result["convergence"].sort(key=lambda r: -r["element_size_m"])
        row = saved[size]
    else:
        print("convergence, one size finer:")
        row = one(size, 3000.0, 1e-8)
    ratio = row["elements"] / previous["elements"]
    result["convergence"] = [r for r in result["convergence"] if r["element_size_m"] != size] + [row]
    result["convergence"].sort(key=lambda r: -r["element_size_m"])
    result["finer"] = {
        "sizes_m": [previous["element_size_m"], size],
        "recurrence_difference": abs(previous["recurrence_yr"] / row["recurrence_yr"] - 1),
        "surface_slip_difference": abs(previous["surface_slip_m"] / row["surface_slip_m"] - 1),
        "cost_ratio": row["wall_s"] / previous["wall_s"], "steps_ratio": row["steps"] / previous["steps"],
        "cost_per_step_ratio": (row["wall_s"] / row["steps"]) / (previous["wall_s"] / previous["steps"]),
        "n_log_n_ratio": ratio * np.log(row["elements"]) / np.log(previous["elements"]),
        "date": datetime.now(timezone.utc).strftime("%Y-%m-%d")}
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(result["finer"])
    return result


if __name__ == "__main__":
    main()
