"""2-D faults drawn at random over the one slider's calibration box: the runs behind its corrected answer and its
95 % ranges (``faultslip.fault.ladder``), and the held-out runs that test them.

    python benchmarks/ladder_designs.py [--workers 2] [--calibration 36] [--held-out 34]
    python benchmarks/ladder_designs.py --fresh 40     # a third draw, to test the ranges as shipped
    python benchmarks/ladder_designs.py --fresh 40 --seed 68012   # a fourth, run sessions after the third
    python benchmarks/ladder_designs.py --fresh 40 --seed 68014   # a fifth, sessions after the fourth
    python benchmarks/ladder_designs.py --fresh 40 --seed 68031   # a sixth, sessions after the fifth
    python benchmarks/ladder_designs.py --fresh 40 --seed 68041   # a seventh, sessions after the sixth
    python benchmarks/ladder_designs.py --fresh 40 --seed 68061   # an eighth, sessions after the seventh
    python benchmarks/ladder_designs.py --fresh 40 --seed 68071   # a ninth, on another machine
    python benchmarks/ladder_designs.py --fresh 40 --seed 68081   # a tenth, with the machine speed record

**The box**, about SEAS BP1 (Erickson et al. 2020): the seismogenic depth H of 15 km x 0.5-1.5, sigma_n of
50 MPa x 0.5-2 and D_c of 8 mm x 0.25-4, each log-uniform; a above the ramp uniform in 0.008-0.0115 (b = 0.015),
a below it in 0.018-0.030; a ramp of 0.05-0.3 H, velocity-strengthening depth below of 0-2 H, and on three
designs in ten a strengthening cap (burial) of up to 0.3 H. A draw is kept where the width over the nucleation
size, W / h*, lies in 1.5-8 (below, the 2-D fault's events are few and irregular; above, a run on two cores takes
too long for a calibration of this size) and the frictional fault spans at most 1,000 elements at 3 per L_b.

Two independent draws (seeds 68 and 6800): the calibration set, and the held-out set that never enters it.
Each run records its 2-D answer, the budget's estimate of its cost and the CPU time it used. Rows are appended
to ``benchmarks/results/ladder_designs.json`` as they finish (a rerun reuses the rows already there).
``--fresh`` runs a third independent draw (seed 68002) into ``benchmarks/results/ladder_fresh.json``: faults
drawn after the ranges were fitted and shipped, which neither the fit nor its choices ever saw. ``--seed 68012``
runs a fourth into ``ladder_fresh_second.json``, drawn once the third had been read and the cost model refitted;
``--seed 68014`` a fifth into ``ladder_fresh_third.json``, drawn once the fourth had been read and the step count's
model refitted; ``--seed 68031`` a sixth into ``ladder_fresh_fourth.json``, drawn sessions later, once the fifth had
been read; ``--seed 68041`` a seventh into ``ladder_fresh_fifth.json``, sessions after the sixth; ``--seed 68061``
an eighth into ``ladder_fresh_sixth.json``, sessions after the seventh, with nothing refitted since;
``--seed 68071`` a ninth into ``ladder_fresh_seventh.json``, on another machine, nothing refitted since;
``--seed 68081`` a tenth into ``ladder_fresh_eighth.json``, the first whose estimates took the machine speed
record's median, nothing refitted since (:data:`FRESH_DRAWS`).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from concurrent.futures import as_completed
from dataclasses import asdict
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.io.processes import stop_pool, worker_pool  # noqa: E402
from faultslip.models.fault_2d.calibration import SHEAR_MODULUS, Design, run_design  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)

RAW = ROOT / "benchmarks" / "results" / "ladder_designs.json"
#: The draws run after the ranges were shipped: seed -> (the designs' name prefix, results file)
FRESH_DRAWS = {68002: ("fresh", ROOT / "benchmarks" / "results" / "ladder_fresh.json"),
               68012: ("fresh2", ROOT / "benchmarks" / "results" / "ladder_fresh_second.json"),
               68014: ("fresh3", ROOT / "benchmarks" / "results" / "ladder_fresh_third.json"),
               68031: ("fresh4", ROOT / "benchmarks" / "results" / "ladder_fresh_fourth.json"),
               68041: ("fresh5", ROOT / "benchmarks" / "results" / "ladder_fresh_fifth.json"),
               68061: ("fresh6", ROOT / "benchmarks" / "results" / "ladder_fresh_sixth.json"),
               68071: ("fresh7", ROOT / "benchmarks" / "results" / "ladder_fresh_seventh.json"),
               68081: ("fresh8", ROOT / "benchmarks" / "results" / "ladder_fresh_eighth.json")}
FRESH_SEED = 68002
FRESH = FRESH_DRAWS[FRESH_SEED][1]
ELEMENTS_PER_PROCESS_ZONE = 3.0
MAX_ELEMENTS = 1000
RATIO_RANGE = (1.5, 8.0)


def draw(count: int, seed: int, prefix: str, ratio_range: tuple = RATIO_RANGE) -> list[Design]:
    """``count`` designs drawn over the box (module docstring), kept where W / h* lies in ``ratio_range`` and the
    element count allows."""
    rng = np.random.default_rng(seed)
    designs = []
    while len(designs) < count:
        width = 15e3 * math.exp(rng.uniform(math.log(0.5), math.log(1.5)))
        sigma = 50e6 * math.exp(rng.uniform(math.log(0.5), math.log(2.0)))
        critical_slip = 8e-3 * math.exp(rng.uniform(math.log(0.25), math.log(4.0)))
        a = float(rng.uniform(0.008, 0.0115))
        deep = float(rng.uniform(0.018, 0.030))
        ramp, below = float(rng.uniform(0.05, 0.3)), float(rng.uniform(0.0, 2.0))
        cap = float(rng.uniform(0.0, 0.3)) if rng.random() < 0.3 else 0.0
        b = 0.015
        nucleation = math.pi / 2 * SHEAR_MODULUS * critical_slip * b / (sigma * (b - a) ** 2)
        ratio = width / nucleation
        if not ratio_range[0] <= ratio <= ratio_range[1]:
            continue
        design = Design(f"{prefix} {len(designs)}", ratio, a, b=b, normal_stress=sigma, seismogenic_width=width,
                        cap=cap, ramp=ramp, below=below, a_strengthening=deep)
        process = SHEAR_MODULUS * design.critical_slip / (sigma * b)
        if design.total_width(process / ELEMENTS_PER_PROCESS_ZONE) / (process / ELEMENTS_PER_PROCESS_ZONE) > MAX_ELEMENTS:
            continue
        designs.append(design)
    return designs


def _changed(earlier: dict, row: dict) -> str:
    """What differs between two runs of one design beyond round-off: the steps by more than 0.1 % (a step or two
    can come and go with the last bits of a sum), the sequence, or the answers by more than 1e-4 (an event's edges
    fall between steps: the settled events' mean slip moves by 1e-5 with them)."""
    out = []
    if abs(row["steps"] - earlier["steps"]) > 1e-3 * earlier["steps"]:
        out.append(f"{earlier['steps']} -> {row['steps']} steps")
    if (row["sequence"], row["period"]) != (earlier["sequence"], earlier["period"]):
        out.append(f"sequence {earlier['sequence']} {earlier['period']} -> {row['sequence']} {row['period']}")
    for key in ("recurrence_2d", "mean_slip_2d"):
        if not math.isclose(row[key], earlier[key], rel_tol=1e-4, abs_tol=0.0) and not (
                math.isnan(row[key]) and math.isnan(earlier[key])):
            out.append(f"{key} {earlier[key]:.6g} -> {row[key]:.6g}")
    return "; ".join(out)


def cost_model() -> dict:
    """The constants of the 2-D cost model that estimated a run (a row records them: an estimate is the model's
    that made it, and docs/ladder.md says which rows the model now declared estimated)."""
    from faultslip.models.fault_2d import cost

    return {"step_seconds": list(cost.FAULT_2D_STEP_SECONDS), "event_steps": dict(cost.FAULT_2D_EVENT_STEPS)}


def _run(design):
    return {**run_design(design, cycles=6, elements_per_process_zone=ELEMENTS_PER_PROCESS_ZONE), "cost_model": cost_model()}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--calibration", type=int, default=36)
    parser.add_argument("--held-out", type=int, default=34)
    parser.add_argument("--fresh", type=int, default=0, metavar="COUNT",
                        help="run COUNT faults of a draw after the ranges were shipped into its file instead")
    parser.add_argument("--seed", type=int, default=FRESH_SEED, choices=sorted(FRESH_DRAWS),
                        help="which fresh draw (68002: the third, ladder_fresh.json; 68012: the fourth, "
                             "ladder_fresh_second.json; 68014: the fifth, ladder_fresh_third.json; 68031: the sixth, "
                             "ladder_fresh_fourth.json; 68041: the seventh, ladder_fresh_fifth.json; 68061: the "
                             "eighth, ladder_fresh_sixth.json)")
    parser.add_argument("--remeasure-above", type=int, default=None, metavar="ELEMENTS",
                        help="run again the designs of more than ELEMENTS elements already done, to measure their CPU "
                             "time on this machine and the current budget's estimate (an answer that changes "
                             "beyond round-off is said)")
    args = parser.parse_args(argv)
    if args.fresh:
        prefix, path = FRESH_DRAWS[args.seed]
        run_all(draw(args.fresh, args.seed, prefix), path, args.workers, args.remeasure_above)
        return
    calibration, held_out = draw(args.calibration, 68, "calibration"), draw(args.held_out, 6800, "held out")
    # interleaved, cheapest first, so that both sets grow together
    designs = [d for pair in zip(calibration, held_out) for d in pair] + calibration[len(held_out):] + held_out[len(calibration):]
    run_all(designs, RAW, args.workers, args.remeasure_above)


def run_all(designs: list[Design], path: Path, workers: int, remeasure_above: int | None = None) -> None:
    """Run the designs not yet in ``path`` (or changed, or above ``remeasure_above`` elements), cheapest first,
    appending each row to ``path`` as it finishes."""
    done = {}
    if path.exists():
        done = {row["design"]["name"]: row for row in json.loads(path.read_text())["rows"]}
    todo = [d for d in designs if d.name not in done or done[d.name]["design"] != asdict(d)
            or (remeasure_above is not None and done[d.name]["elements"] > remeasure_above)]
    todo.sort(key=lambda d: d.total_width(1.0) * d.width_over_nucleation)
    pool = worker_pool(min(workers, max(len(todo), 1)))
    try:
        futures = {pool.submit(_run, design): design for design in todo}
        for future in as_completed(futures):
            row = future.result()
            earlier = done.get(row["design"]["name"])
            if earlier is not None and earlier["design"] == row["design"]:
                changed = _changed(earlier, row)
                if changed:
                    # the current code's answer replaces the row; say so, since the calibration reads it
                    print(f"{row['design']['name']}: rerun differs from the recorded run: {changed}", flush=True)
            done[row["design"]["name"]] = row
            print(f"{row['design']['name']}: W/h* {row['design']['width_over_nucleation']:.2f}, {row['sequence']} "
                  f"(p {row['period']}), T {row['recurrence_2d'] / 3.15576e7:.1f} yr, {row['elements']} elements, "
                  f"{row['cpu_time']:.0f} s CPU (estimated {row['estimated_seconds']:.0f} s)", flush=True)
            path.write_text(json.dumps({**stamp(), "rows": list(done.values())}, indent=1) + "\n", encoding="utf-8")
    finally:
        stop_pool(pool)


if __name__ == "__main__":
    main()
