"""Is the 2-D fault's kind of sequence a function of the fault? The held-out faults where both kinds occur,
each rerun with its D_c moved by a few per cent, and every held-out fault rerun from other starts (issue 68:
what limits the one slider's range).

    python benchmarks/ladder_regimes.py [--workers 2] [--part critical_slip|start|all]

Where the 2-D fault interleaves small deep events with its system-size ones, the system-size interval is
longer than where every event breaks the zone, and the one slider's groups do not tell the two kinds apart
(``benchmarks/ladder_calibration.py``). Two causes could make it so: the kind could hinge on the run (its
start, its round-off: a chaotic or bistable fault, which nothing could predict), or on the fault itself through
something the groups do not carry. Moving D_c by -3 %, -1 %, +1 % and +3 % on each held-out fault whose W / h*
lies where both kinds occur, and rerunning the 2-D fault from its usual start, tells which: a kind that stays put
and a recurrence that moves smoothly is the fault's own.

**The start** (``--part start``): every held-out fault rerun from a steady start at 0.1 and at 10 times the plate
rate (:data:`STARTS`) instead of at the plate rate, over the same cycles. A fault that settles to the same cycle
from every start has one answer; one that settles elsewhere is multistable, and its answer is its start's.

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
from faultslip.models.fault_2d import analysis  # noqa: E402
from faultslip.models.fault_2d.calibration import PLATE_RATE, Design, run_design  # noqa: E402
from provenance import stamp  # noqa: E402

RAW = ROOT / "benchmarks" / "results" / "ladder_designs.json"
OUT = ROOT / "benchmarks" / "results" / "ladder_regimes.json"
#: W / h* where the calibration and held-out faults show both kinds of sequence
MIXED = (1.7, 4.3)
#: D_c factors; W / h* goes as 1 / D_c
FACTORS = (0.97, 0.99, 1.0, 1.01, 1.03)
#: The other starts, as multiples of the plate rate at which every element starts in steady state
STARTS = (0.1, 10.0)
#: A rerun from another start has the same answer where its recurrence is within this of the usual start's: the
#: tolerance the runs' sequences are settled to (run_design's classify)
SAME_ANSWER = 0.01


def interleaves(row: dict) -> bool:
    """Whether a 2-D run interleaves events that do not break the zone with its system-size events
    (:func:`faultslip.models.fault_2d.analysis.interleaves`)."""
    return analysis.interleaves(row["events"], row["system_events"])


def _run(job):
    design, factor = job
    moved = dataclasses.replace(design, width_over_nucleation=design.width_over_nucleation / factor)
    return design.name, factor, run_design(moved, cycles=6)


def _pooled(function, jobs: list, workers: int, label: str):
    """Each job's (fault name, factor, run_design row) from a worker pool, as the runs end, each said on a line."""
    pool = worker_pool(min(workers, len(jobs)))
    try:
        for future in as_completed([pool.submit(function, job) for job in jobs]):
            name, factor, row = future.result()
            print(f"{name} {label.format(factor=factor)}: {row['sequence']} (period {row['period']}), "
                  f"{row['events']} events, {row['system_events']} system-size, T "
                  f"{row['recurrence_2d'] / 3.15576e7:.1f} yr, {row['cpu_time']:.0f} s CPU", flush=True)
            yield name, factor, row
    finally:
        stop_pool(pool)


def _run_from(job):
    design, factor = job
    return design.name, factor, run_design(design, initial_speed=factor * PLATE_RATE)


def _summary_of_start(row: dict) -> dict:
    return {"sequence": row["sequence"], "period": row["period"], "recurrence": row["recurrence_2d"],
            "mean_slip": row["mean_slip_2d"], "interleaves": interleaves(row), "intervals": row["intervals"]}


def starts(rows: list[dict], workers: int) -> dict:
    """Every held-out fault from the :data:`STARTS` (the usual start's run is its recorded row): does it settle to
    the same cycle?"""
    designs = {row["design"]["name"]: Design(**row["design"]) for row in rows}
    runs: dict[str, dict] = {name: {1.0: _summary_of_start(row)} for name, row in
                             ((row["design"]["name"], row) for row in rows)}
    jobs = [(design, factor) for design in designs.values() for factor in STARTS]
    for name, factor, row in _pooled(_run_from, jobs, workers, "from {factor:g} V_pl"):
        runs[name][factor] = _summary_of_start(row)
    faults = []
    for name, by_start in runs.items():
        usual = by_start[1.0]
        change = {factor: by_start[factor]["recurrence"] / usual["recurrence"] - 1 for factor in STARTS}
        faults.append({"name": name, "width_over_nucleation": designs[name].width_over_nucleation,
                       "starts": {f"{factor:g}": by_start[factor] for factor in (1.0, *STARTS)},
                       "recurrence_change": {f"{factor:g}": value for factor, value in change.items()},
                       "largest_change": max(abs(value) for value in change.values()),
                       "kind_changed": len({by_start[f]["interleaves"] for f in (1.0, *STARTS)}) > 1})
    return {"initial_speeds_over_plate_rate": STARTS, "summary": summarise_starts(faults), "faults": faults}


def _elsewhere(fault: dict) -> dict:
    """Where a fault that does not keep its answer goes: the start that moves it most, and what it settles to."""
    start = max(fault["recurrence_change"], key=lambda factor: abs(fault["recurrence_change"][factor]))
    reached = fault["starts"][start]
    return {"name": fault["name"], "start": float(start), "largest_change": fault["recurrence_change"][start],
            "sequence": reached["sequence"], "period": reached["period"],
            "usual_period": fault["starts"]["1"]["period"]}


def summarise_starts(faults: list[dict]) -> dict:
    """How many faults settle to the same cycle from every start, which do not, and what the rest do."""
    settled = [f for f in faults if f["starts"]["1"]["sequence"] == "periodic"]
    elsewhere = [f for f in settled if f["largest_change"] > SAME_ANSWER]
    unsettled = [f for f in faults if f["starts"]["1"]["sequence"] != "periodic"]
    summary = {"faults": len(faults), "settled_from_usual_start": len(settled),
               "same_answer": len(settled) - len(elsewhere), "same_answer_within": SAME_ANSWER,
               "elsewhere": [_elsewhere(f) for f in elsewhere],
               "kind_changed": sum(f["kind_changed"] for f in faults),
               "unsettled_from_usual_start": len(unsettled),
               "unsettled_largest_change": max((f["largest_change"] for f in unsettled), default=math.nan)}
    return summary


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--part", choices=("critical_slip", "start", "all"), default="all")
    args = parser.parse_args(argv)
    rows = [row for row in json.loads(RAW.read_text())["rows"] if row["design"]["name"].startswith("held out")]
    if args.part == "start":
        kept = json.loads(OUT.read_text())
        kept.update(stamp())
        kept["starts"] = starts(rows, args.workers)
        OUT.write_text(json.dumps(kept, indent=1) + "\n", encoding="utf-8")
        print(kept["starts"]["summary"])
        return
    chosen = [Design(**row["design"]) for row in rows if MIXED[0] <= row["design"]["width_over_nucleation"] <= MIXED[1]]
    jobs = [(design, factor) for design in chosen for factor in FACTORS]
    runs: dict[str, dict] = {design.name: {} for design in chosen}
    for name, factor, row in _pooled(_run, jobs, args.workers, "D_c x{factor}"):
        runs[name][factor] = row
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
    table = {**stamp(), "factors": FACTORS, "mixed_width_over_nucleation": MIXED, "summary": summary, "faults": faults}
    if args.part == "all":
        table["starts"] = starts(rows, args.workers)
    elif OUT.exists() and "starts" in json.loads(OUT.read_text()):
        table["starts"] = json.loads(OUT.read_text())["starts"]
    OUT.write_text(json.dumps(table, indent=1) + "\n", encoding="utf-8")
    print(summary, table.get("starts", {}).get("summary"))


if __name__ == "__main__":
    main()
