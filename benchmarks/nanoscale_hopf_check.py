"""Check the Hopf normal form's declared error on random nanoscale models it never saw (seed 001's toy model).

    python benchmarks/nanoscale_hopf_check.py            # ~3 min on 2 cores
    python benchmarks/nanoscale_hopf_check.py --quick    # 6 models

Each model is drawn log-uniform about the slides' (v_a 0.012-0.06 with v_m = 0.01, tau 0.3-10, a 0.3-5, f_ch
1e-8-0.3); its Hopf point is classified by the sign of the first Lyapunov coefficient. Below a supercritical A_c
the damping is set where sigma / omega_0 is drawn log-uniform in 1e-3 to HOPF_REFERENCE, and the normal form
(``nanoscale_hopf_normal_form``: its error measured on the model at HOPF_REFERENCE and scaled by sigma) is
compared with LSODA's settled cycle there at rtol 1e-12 (tolerance 1e-9): the largest relative error of the
swing, period and least speed against the declared error. Nearer A_c than 1e-3 LSODA's own settling error
approaches the normal form's, so the check stops there. 1 % above every A_c the run from rest is integrated: the
result says how many models stick-slip there beside stable steady sliding (bistable; expected only where the Hopf
point is subcritical, which ``auto`` then integrates) and how many decay to steady sliding.

Writes benchmarks/results/nanoscale_hopf_check.json.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.models.nanoscale.dynamics import (HOPF_REFERENCE, NanoscaleModel, damping_at_growth,  # noqa: E402
                                                 normal_form)
from faultslip.models.nanoscale.hopf import hopf_point  # noqa: E402
from provenance import write_results  # noqa: E402  (one stamp for every results file)

SEED, MODELS, QUICK_MODELS = 2026, 40, 6
NEAREST = 1e-3


def draw(rng) -> dict:
    return {"drive_speed": float(10 ** rng.uniform(math.log10(0.012), math.log10(0.06))),
            "charging_time": float(10 ** rng.uniform(math.log10(0.3), 1.0)),
            "charge_length": float(10 ** rng.uniform(math.log10(0.3), math.log10(5.0))),
            "charge_force": float(10 ** rng.uniform(-8.0, math.log10(0.3))),
            "ratio": float(10 ** rng.uniform(math.log10(NEAREST), math.log10(HOPF_REFERENCE)))}


def check(parameters: dict) -> dict:
    """One model: its Hopf point's kind, and the normal form against LSODA (supercritical) or the run from rest
    above A_c (subcritical)."""
    ratio = parameters.pop("ratio")
    base = NanoscaleModel(**parameters)
    point = hopf_point(base)
    row = {"model": parameters, "kind": "none" if point is None else
           "supercritical" if point.supercritical else "subcritical"}
    if point is None:
        return row
    above = replace(base, damping=1.01 * point.critical_damping)  # what a tip started from rest does there
    cycle = above.settled_cycle(1e-6)
    row.update(above_regime=cycle.regime, above_swing=cycle.force_swing)
    if not point.supercritical:
        return row
    damping = damping_at_growth(base, point, ratio)
    model = replace(base, damping=damping)
    start = time.process_time()
    cycle, why = normal_form(model)
    row.update(ratio=ratio, damping=damping, normal_form_cpu_s=time.process_time() - start)
    if cycle is None:
        row["declined"] = why
        return row
    truth = model.settled_cycle(1e-9, rtol=1e-12, max_cycles=20000)
    errors = [abs(ours / theirs - 1.0) for ours, theirs in ((cycle.force_swing, truth.force_swing),
                                                             (cycle.period, truth.period),
                                                             (cycle.least_speed, truth.least_speed))]
    row.update(declared=cycle.estimated_error, actual=max(errors), swing_error=errors[0], period_error=errors[1],
               truth_settled=bool(truth.settling.settled), truth_declared=truth.estimated_error,
               used=max(errors) / cycle.estimated_error)
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    rng = np.random.default_rng(SEED)
    draws = [draw(rng) for _ in range(QUICK_MODELS if args.quick else MODELS)]
    with ProcessPoolExecutor(max_workers=2) as pool:
        rows = list(pool.map(check, draws))
    checked = [row for row in rows if "used" in row]
    held = [row for row in checked if row["used"] <= 1.0]
    subcritical = [row for row in rows if row["kind"] == "subcritical"]
    summary = {
        "models": len(rows), "supercritical": sum(row["kind"] == "supercritical" for row in rows),
        "subcritical": len(subcritical), "checked": len(checked), "held": len(held),
        "declined": sum("declined" in row for row in rows),
        "largest_used": max((row["used"] for row in checked), default=None),
        "smallest_used": min((row["used"] for row in checked), default=None),
        "subcritical_stick_slip_from_rest_1pct_above": sum(row.get("above_regime") == "stick_slip"
                                                           for row in subcritical),
        "supercritical_moving_from_rest_1pct_above": sum(row.get("above_regime") != "steady_sliding"
                                                         for row in rows if row["kind"] == "supercritical"),
    }
    print(summary)
    write_results("nanoscale_hopf_check.json", {"summary": summary, "rows": rows, "seed": SEED,
                                                "reference": HOPF_REFERENCE, "nearest": NEAREST})


if __name__ == "__main__":
    main()
