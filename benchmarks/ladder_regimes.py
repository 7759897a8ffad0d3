"""Is the 2-D fault's kind of sequence a function of the fault? The held-out faults where both kinds occur,
each rerun with its D_c moved by a few per cent (issue 68: what limits the one slider's range).

    python benchmarks/ladder_regimes.py [--workers 2]

Where the 2-D fault interleaves small deep events with its system-size ones, the system-size interval is
longer than where every event breaks the zone, and the one slider's groups do not tell the two kinds apart
(``benchmarks/ladder_calibration.py``). Two causes could make it so: the kind could hinge on the run (its
start, its round-off: a chaotic or bistable fault, which nothing could predict), or on the fault itself through
something the groups do not carry. Moving D_c by -3 %, -1 %, +1 % and +3 % on each held-out fault whose W / h*
lies where both kinds occur, and rerunning the 2-D fault from its usual start, tells which: a kind that stays put
and a recurrence that moves smoothly is the fault's own.

Writes ``benchmarks/results/ladder_regimes.json``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import statistics
import sys
from concurrent.futures import as_completed
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.io.processes import stop_pool, worker_pool  # noqa: E402
from faultslip.models.fault_2d.calibration import Design, run_design  # noqa: E402
from provenance import stamp  # noqa: E402

RAW = ROOT / "benchmarks" / "results" / "ladder_designs.json"
OUT = ROOT / "benchmarks" / "results" / "ladder_regimes.json"
#: W / h* where the calibration and held-out faults show both kinds of sequence
MIXED = (1.7, 4.3)
#: D_c factors; W / h* goes as 1 / D_c
FACTORS = (0.97, 0.99, 1.0, 1.01, 1.03)
#: partial events per system-size event at and above which a run interleaves them (the runs show 0-0.11, then
#: 0.41 and more: the spin-up's odd partial event stays below)
PARTIAL_SHARE = 0.25


def interleaves(row: dict) -> bool:
    """Whether a 2-D run interleaves events that do not break the zone with its system-size events."""
    return (row["events"] - row["system_events"]) / max(row["system_events"], 1) >= PARTIAL_SHARE


def _run(job):
    design, factor = job
    moved = dataclasses.replace(design, width_over_nucleation=design.width_over_nucleation / factor)
    return design.name, factor, run_design(moved, cycles=6)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    rows = [row for row in json.loads(RAW.read_text())["rows"] if row["design"]["name"].startswith("held out")]
    chosen = [Design(**row["design"]) for row in rows if MIXED[0] <= row["design"]["width_over_nucleation"] <= MIXED[1]]
    jobs = [(design, factor) for design in chosen for factor in FACTORS]
    runs: dict[str, dict] = {design.name: {} for design in chosen}
    pool = worker_pool(min(args.workers, len(jobs)))
    try:
        futures = [pool.submit(_run, job) for job in jobs]
        for future in as_completed(futures):
            name, factor, row = future.result()
            runs[name][factor] = row
            print(f"{name} D_c x{factor}: {row['events']} events, {row['system_events']} system-size, "
                  f"T {row['recurrence_2d'] / 3.15576e7:.1f} yr, {row['cpu_time']:.0f} s CPU", flush=True)
    finally:
        stop_pool(pool)
    faults = []
    for name, by_factor in runs.items():
        base = by_factor[1.0]
        faults.append({
            "name": name, "width_over_nucleation": base["design"]["width_over_nucleation"],
            "interleaves": [interleaves(by_factor[f]) for f in FACTORS],
            "recurrence": [by_factor[f]["recurrence_2d"] for f in FACTORS],
            "sequence": [by_factor[f]["sequence"] for f in FACTORS], "period": [by_factor[f]["period"] for f in FACTORS],
            "largest_change": max(abs(by_factor[f]["recurrence_2d"] / base["recurrence_2d"] - 1) for f in FACTORS),
            "cpu_time": sum(by_factor[f]["cpu_time"] for f in FACTORS),
            # every partial event of the unmoved run, the spin-up's included: (hypocentre depth
            # below the zone's top over W, the share of the zone they break)
            "partial_events": list(zip(base["partial_hypocentres"], base["partial_broken"]))})
    changed = [f for f in faults if len(set(f["interleaves"])) > 1]
    widest = max(faults, key=lambda f: f["largest_change"])
    partial = [(depth, broken) for f in faults for depth, broken in f["partial_events"]]
    summary = {"partial_events": len(partial),
               "partial_hypocentre_median": statistics.median(d for d, _ in partial) if partial else math.nan,
               "partial_broken_median": statistics.median(b for _, b in partial) if partial else math.nan,
               "widest": {"name": widest["name"], "sequences": sorted(set(zip(widest["sequence"], widest["period"])))},
               "faults": len(faults), "interleaving": sum(f["interleaves"][FACTORS.index(1.0)] for f in faults),
               "kind_changed": len(changed),
               "largest_change": max((f["largest_change"] for f in faults), default=math.nan),
               "median_largest_change": statistics.median(f["largest_change"] for f in faults) if faults else math.nan}
    OUT.write_text(json.dumps({**stamp(), "factors": FACTORS, "mixed_width_over_nucleation": MIXED,
                               "summary": summary, "faults": faults}, indent=1) + "\n", encoding="utf-8")
    print(summary)


if __name__ == "__main__":
    main()
