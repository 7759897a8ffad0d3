"""The spring-block chain's speed (issue 45): 100 blocks and 10,000 events on one core, and the closed-form
slips against integrated ones doing the same work.

    python benchmarks/spring_chain_speed.py [--blocks 100] [--events 10000] [--baseline-events 300] [--rounds 3]

**The target** is 100 blocks and 10,000 events in under 10 s on one core: ``configs/spring_chain.toml``
with 100 blocks, its slips by the closed form (faultslip's default), timed once in this process pinned
to one core.

**The baseline** is the same event-driven chain with each slip sub-phase integrated by scipy's
``solve_ivp`` (DOP853 at rtol 1e-10, a terminal event for each slipping block's stop and each held
neighbour's limit): the generic way to integrate a chain of sticking blocks, and the way seed 003's one
slider integrates a nonlinear slip. Both run the first ``--baseline-events`` events of the same chain
from the same start, interleaved over ``--rounds`` rounds with the order reversed every other round, the
medians kept. They agree on the events until the chaotic chain's round-off grows; how many events agree
is recorded beside the ratio.

Writes benchmarks/results/spring_chain_speed.json; ``python benchmarks/readme.py`` writes the README's table
``spring_chain_speed`` from it.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.models.spring_chain.dynamics import simulate_chain  # noqa: E402
from faultslip.models.spring_chain.family import statistics as chain_statistics  # noqa: E402
from faultslip.models.spring_chain.scene import parse_chain_scene  # noqa: E402
from peer_runs import interleaved  # noqa: E402

SCENE = ROOT / "configs" / "spring_chain.toml"


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--blocks", type=int, default=100)
    parser.add_argument("--events", type=int, default=10_000)
    parser.add_argument("--baseline-events", type=int, default=300)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--core", type=int, default=0)
    args = parser.parse_args(argv)
    os.sched_setaffinity(0, {args.core})
    text = SCENE.read_text(encoding="utf-8").replace("blocks = 50", f"blocks = {args.blocks}")
    loaded = parse_chain_scene(text, SCENE.name)

    def timed(solver, events):
        def go():
            began, cpu = time.perf_counter(), time.process_time()
            run = simulate_chain(loaded.chain, events, initial_position=loaded.initial_position, slip_solver=solver)
            return {"wall_s": time.perf_counter() - began, "cpu_s": time.process_time() - cpu, "run": run}
        return go

    print(f"{args.blocks} blocks, the closed form and DOP853 over {args.baseline_events} events, {args.rounds} rounds:")
    rounds = interleaved({"closed_form": timed("closed_form", args.baseline_events),
                          "DOP853": timed("DOP853", args.baseline_events)}, args.rounds)
    ours, theirs = rounds["closed_form"][0]["run"], rounds["DOP853"][0]["run"]
    differ = np.flatnonzero(ours.blocks_slipped != theirs.blocks_slipped)
    agree = int(differ[0]) if differ.size else ours.events
    walls = {name: statistics.median(row["wall_s"] for row in rows) for name, rows in rounds.items()}
    for name, wall in walls.items():
        print(f"  {name}: {wall:.2f} s ({wall / args.baseline_events * 1e3:.2f} ms an event)")
    print(f"{args.blocks} blocks, {args.events} events by the closed form:")
    target = timed("closed_form", args.events)()
    run = target["run"]
    print(f"  {target['wall_s']:.1f} s wall, {target['cpu_s']:.1f} s CPU, {run.subphases} sub-phases, "
          f"{run.blocks_slipped.mean():.1f} blocks an event on average")
    stats = chain_statistics(loaded, run)  # what the long catalogue says (docs/spring_chain.md quotes it)
    b = stats["b"] or {}
    catalogue = {"b": b.get("b"), "b_interval": b.get("interval"), "b_shi_bolt_error": b.get("shi_bolt_error"),
                 "magnitude_range": stats["magnitude_range"], "system_events": stats["system_events"],
                 "recurrence_cv": stats["recurrence_cv"], "plate_balance": stats["plate_balance"],
                 "plate_balance_bound": stats["plate_balance_bound"],
                 "size_counts": np.bincount(run.blocks_slipped, minlength=args.blocks + 1).tolist()}
    print(f"  b = {catalogue['b']:.3f} ({catalogue['b_interval'][0]:.3f}-{catalogue['b_interval'][1]:.3f}), "
          f"system-size events {catalogue['system_events']}, their CV {catalogue['recurrence_cv']:.2f}")
    result = {"blocks": args.blocks, "events": args.events, "wall_s": target["wall_s"], "cpu_s": target["cpu_s"],
              "catalogue": catalogue,
              "subphases": run.subphases, "mean_blocks_slipped": float(run.blocks_slipped.mean()),
              "target_s": 10.0, "baseline_events": args.baseline_events, "rounds": args.rounds,
              "baseline_wall_s": walls, "ratio_closed_form_over_dop853": walls["closed_form"] / walls["DOP853"],
              "events_agreeing": agree,
              "start_time_difference": float(np.max(np.abs(ours.start[:agree] / theirs.start[:agree] - 1)))
              if agree else None,
              "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}",
              "date": datetime.now(timezone.utc).strftime("%Y-%m-%d")}
    out = ROOT / "benchmarks" / "results" / "spring_chain_speed.json"
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}; closed form / DOP853 = {result['ratio_closed_form_over_dop853']:.2f}")
    return result


if __name__ == "__main__":
    main()
