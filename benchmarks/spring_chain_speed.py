"""The spring-block chain's speed (issue 45): 100 blocks and 10,000 events on one core, and the compiled
closed form against the same scheme in Python and against integrated slips, each doing the same work.

    python benchmarks/spring_chain_speed.py [--blocks 100] [--events 10000] [--baseline-events 300] [--rounds 3]

**The target** is 100 blocks and 10,000 events in under 10 s on one core: ``configs/spring_chain.toml``
with 100 blocks, its slips by faultslip's default (``auto``: the closed form, compiled), timed over
``--rounds`` runs in this process pinned to one core, the median kept.

**The baselines** run the first ``--baseline-events`` events of the same chain from the same start:
- the same closed form in Python (``closed_form``): the same sticks, sub-phases, grid and tolerances, the
  modes from scipy's eigensolver, what the compiled loop replaced;
- each slip sub-phase integrated by scipy's ``solve_ivp`` (DOP853 at rtol 1e-10, a terminal event for
  each slipping block's stop and each held neighbour's limit): the generic way to integrate a chain of
  sticking blocks, and the way seed 003's one slider integrates a nonlinear slip.
All three are interleaved over ``--rounds`` rounds with the order reversed every other round, the medians
kept. They agree on the events until the chaotic chain's round-off grows; how many events agree with the
Python closed form is recorded beside each ratio.

Writes benchmarks/results/spring_chain_speed.json; ``python benchmarks/readme.py`` writes the docs' table
``spring_chain_speed`` from it.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.models.spring_chain.dynamics import chosen_solver, simulate_chain  # noqa: E402
from faultslip.models.spring_chain.family import statistics as chain_statistics  # noqa: E402
from faultslip.models.spring_chain.scene import parse_chain_scene  # noqa: E402
from peer_runs import interleaved  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)

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

    default = chosen_solver("auto")
    print(f"{args.blocks} blocks, {default}, the Python closed form and DOP853 over {args.baseline_events} events, "
          f"{args.rounds} rounds:")
    solvers = list(dict.fromkeys([default, "closed_form", "DOP853"]))
    rounds = interleaved({name: timed(name, args.baseline_events) for name in solvers}, args.rounds)
    reference = rounds["closed_form"][0]["run"]

    def agreement(other):
        """(events with the same blocks slipped, leading events whose start times agree within 1e-9)"""
        differ = np.flatnonzero(reference.blocks_slipped != other.blocks_slipped)
        agree = int(differ[0]) if differ.size else reference.events
        apart = np.flatnonzero(np.abs(other.start[:agree] - reference.start[:agree])
                               > 1e-9 * np.abs(reference.start[:agree]))
        return agree, int(apart[0]) if apart.size else agree

    walls = {name: statistics.median(row["wall_s"] for row in rows) for name, rows in rounds.items()}
    cpus = {name: statistics.median(row["cpu_s"] for row in rows) for name, rows in rounds.items()}
    agreeing = {name: agreement(rows[0]["run"]) for name, rows in rounds.items() if name != "closed_form"}
    for name, wall in walls.items():
        print(f"  {name}: {wall:.3f} s ({wall / args.baseline_events * 1e3:.3f} ms an event)")
    print(f"{args.blocks} blocks, {args.events} events by {default}, {args.rounds} runs:")
    targets = [timed(default, args.events)() for _ in range(args.rounds)]
    target = {key: statistics.median(row[key] for row in targets) for key in ("wall_s", "cpu_s")}
    run = targets[0]["run"]
    print(f"  {target['wall_s']:.2f} s wall, {target['cpu_s']:.2f} s CPU (medians), {run.subphases} sub-phases, "
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
    result = {"blocks": args.blocks, "events": args.events, "solver": default, "wall_s": target["wall_s"],
              "cpu_s": target["cpu_s"], "catalogue": catalogue,
              "subphases": run.subphases, "mean_blocks_slipped": float(run.blocks_slipped.mean()),
              "target_s": 10.0, "baseline_events": args.baseline_events, "rounds": args.rounds,
              "baseline_wall_s": walls, "baseline_cpu_s": cpus,
              "ratio_over_python_closed_form": walls[default] / walls["closed_form"],
              "ratio_over_dop853": walls[default] / walls["DOP853"],
              "ratio_closed_form_over_dop853": walls["closed_form"] / walls["DOP853"],
              "events_agreeing": {name: agree for name, (agree, _) in agreeing.items()},
              "events_within_1e-9": {name: close for name, (_, close) in agreeing.items()},
              **stamp()}
    out = ROOT / "benchmarks" / "results" / "spring_chain_speed.json"
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}; {default} / Python closed form = {result['ratio_over_python_closed_form']:.4f}, "
          f"/ DOP853 = {result['ratio_over_dop853']:.4f}")
    return result


if __name__ == "__main__":
    main()
