"""Spring-block chains against an integration no stop or join can slip through, over 30 events (issue 69).

    python benchmarks/chain_stops.py [--chains 12] [--workers 2]

Chains of 2 to 8 blocks drawn at random (seed 69): coupling k_c / k_p log-uniform in 0.1-30, damping ratio 0-0.5,
static limits 0.6-0.7, kinetic friction 0.5, starts within 0.2 mm ("narrow"); and as many (seed 70) with limits
0.5-1.0, kinetic friction 0.1-0.45, k_c / k_p log-uniform in 0.25-40 and damping ratio 0-0.3 ("wide": larger
stress drops, where a join that the grid alone missed was found). Each runs 30 events by the closed form (Python,
and C where built), by DOP853 at its own steps (rtol 1e-10), and by DOP853 stepped at no more than 1/1000 of the
fastest mode's period, whose steps no dip of a speed below zero, nor touch of a force on its limit, can pass
between (the reference). Recorded: whether the blocks of every event agree, and the largest relative differences
of the start times and slips; how many stops and joins the grid alone would have missed (found by the closed
form's dip search); and how many changes DOP853's own steps passed over (found by locating each speed's and
headroom's least value), and the reference's (none expected). Writes benchmarks/results/chain_stops.json.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from concurrent.futures import as_completed
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.io.processes import stop_pool, worker_pool  # noqa: E402
from faultslip.models.spring_chain import dynamics  # noqa: E402
from probes import found_by  # noqa: E402
from provenance import stamp  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "chain_stops.json"
EVENTS = 30


def _compare(run, reference) -> dict:
    same = bool(np.array_equal(run.blocks_slipped, reference.blocks_slipped))
    return {"same_blocks": same,
            "start": float(np.max(np.abs(run.start - reference.start) / reference.start)) if same else None,
            "slip": float(np.max(np.abs(run.slip - reference.slip)) / np.abs(reference.slip).max()) if same else None}


def _chain(values):
    family, blocks, coupling, zeta, spread, start, kinetic = values
    low, width = (0.6, 0.1) if family == "narrow" else (0.5, 0.5)
    chain = dynamics.Chain(mass=1.0, leaf_stiffness=1e3, coupling_stiffness=1e3 * coupling, normal_load=10.0,
                           platform_speed=1e-4, kinetic_friction=kinetic, dashpot=2 * zeta * math.sqrt(1e3),
                           static_friction=low + width * np.array(spread[:blocks]))
    return chain, 2e-4 * np.array(start[:blocks])


def _draws(count: int) -> list:
    """(family, blocks, k_c / k_p, damping ratio, limits' spread, start, kinetic friction) of each chain."""
    narrow, wide = np.random.default_rng(69), np.random.default_rng(70)
    return ([("narrow", int(narrow.integers(2, 9)), float(10 ** narrow.uniform(-1, math.log10(30))),
              float(narrow.uniform(0, 0.5)), narrow.uniform(0, 1, 8).tolist(), narrow.uniform(0, 1, 8).tolist(), 0.5)
             for _ in range(count)]
            + [("wide", int(wide.integers(2, 9)), float(10 ** wide.uniform(math.log10(0.25), math.log10(40))),
                float(wide.uniform(0, 0.3)), wide.uniform(0, 1, 8).tolist(), wide.uniform(0, 1, 8).tolist(),
                float(wide.uniform(0.1, 0.45))) for _ in range(count)])


def _passed_over(chain, position, **options):
    """The run by DOP853 (rtol 1e-10), and how many changes its steps passed over."""
    with found_by(dynamics, "_passed_over") as found:
        run = dynamics.simulate_chain(chain, EVENTS, initial_position=position, slip_solver="DOP853", rtol=1e-10,
                                      **options)
    return run, found[0]


def _run(values):
    chain, position = _chain(values)
    reference, row_reference = _passed_over(chain, position, steps_per_period=1000)
    row = {"chain": {"family": values[0], "blocks": values[1], "coupling_ratio": values[2], "damping_ratio": values[3],
                     "kinetic_friction": values[6]}}
    solvers = ["closed_form"] + (["closed_form_compiled"] if dynamics.compiled_available() else [])
    for solver in solvers:
        row[solver] = _compare(dynamics.simulate_chain(chain, EVENTS, initial_position=position, slip_solver=solver),
                               reference)
    coarse, row["passed_over_by_steps"] = _passed_over(chain, position)
    row["DOP853"] = _compare(coarse, reference)
    row["passed_over_by_reference"] = row_reference
    dips = {"stop": 0, "join": 0}
    original = dynamics._dip

    def counting(change, *args, **kwargs):
        found = original(change, *args, **kwargs)
        if found is not None and kwargs.get("depth", 0) == 0:  # a join's change is a closure over headroom()
            dips["join" if "headroom" in change.__code__.co_freevars else "stop"] += 1
        return found

    dynamics._dip = counting
    try:
        dynamics.simulate_chain(chain, EVENTS, initial_position=position, slip_solver="closed_form")
    finally:
        dynamics._dip = original
    row["stops_between_points"], row["joins_between_points"] = dips["stop"], dips["join"]
    return row


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--chains", type=int, default=12, help="chains of each family")
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args(argv)
    draws = _draws(args.chains)
    pool = worker_pool(args.workers)
    rows = []
    try:
        for future in as_completed([pool.submit(_run, values) for values in draws]):
            row = future.result()
            rows.append(row)
            print(json.dumps(row), flush=True)
    finally:
        stop_pool(pool)
    agree = sum(all(row[s]["same_blocks"] for s in row if s.startswith("closed") or s == "DOP853") for row in rows)
    OUT.write_text(json.dumps({**stamp(), "events": EVENTS, "chains": len(rows), "agree": agree,
                               **{key: sum(row[key] for row in rows) for key in (
                                   "stops_between_points", "joins_between_points", "passed_over_by_steps",
                                   "passed_over_by_reference")},
                               "rows": rows}, indent=1) + "\n",
                   encoding="utf-8")
    print(f"{agree} of {len(rows)} chains agree with the reference over {EVENTS} events")


if __name__ == "__main__":
    main()
