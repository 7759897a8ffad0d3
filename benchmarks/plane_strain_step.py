"""The dense plane-strain step's CPU cost against its element count, for the 2-D fault's cost estimate.

    python benchmarks/plane_strain_step.py [--elements 50 100 200 400 800 1600] [--years 200]

SEAS BP3-QD's 60-degree thrust on N elements, integrated for ``--years`` of its first interseismic period (steps
there cost what they cost in an event: every step is six force balances and six products with the dense kernels),
timed in CPU seconds per step, each size in turn, twice, the faster kept. Fits c0 + c2 N^2 (the product of the
2N x N kernels dominates) by least squares in log space and writes benchmarks/results/plane_strain_step.json,
from which faultslip.models.fault_2d.cost.PLANE_STRAIN_STEP_SECONDS is taken (tests/models/fault_2d/test_budget_fit.py refits it).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
from provenance import stamp  # noqa: E402  (one stamp for every results file)

from faultslip.models.fault_2d.integrate import YEAR  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402


def fit(rows: list[dict]) -> tuple[float, float]:
    """(c0, c2) of seconds per step = c0 + c2 N^2, least squares on the relative misfit."""
    n = np.array([row["elements"] for row in rows], float)
    seconds = np.array([row["seconds_per_step"] for row in rows], float)
    design = np.column_stack([np.ones_like(n), n ** 2]) / seconds[:, None]
    (c0, c2), *_ = np.linalg.lstsq(design, np.ones_like(n), rcond=None)
    return float(max(c0, 0.0)), float(c2)


def timed(count: int, years: float = 200.0) -> dict:
    """BP3-QD's thrust on ``count`` elements over ``years``: CPU seconds a step, the faster of two runs."""
    base = read_fault_2d_scene(ROOT / "configs" / "seas_bp3_thrust60.toml")
    best = None
    for _ in range(2):
        scene = base.at_element_size(base.fault.width / count)
        scene.duration, scene.rtol, scene.stations = years * YEAR, 1e-6, (7500.0,)
        started = time.process_time()
        run = scene.run()
        seconds = (time.process_time() - started) / run.steps
        best = seconds if best is None else min(best, seconds)
    print(f"{count} elements: {best * 1e3:.3f} ms a step", flush=True)
    return {"elements": count, "steps": run.steps, "seconds_per_step": best}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    # down to 50 elements (a small dipping scene's 80 had been estimated at 3x its step from 200 and up), and 200
    # years, so that each size times thousands of steps, not a hundred
    parser.add_argument("--elements", type=int, nargs="+", default=[50, 100, 200, 400, 800, 1600])
    parser.add_argument("--years", type=float, default=200.0)
    parser.add_argument("--out", type=Path, default=HERE / "results" / "plane_strain_step.json")
    args = parser.parse_args(argv)
    rows = [timed(count, args.years) for count in args.elements]
    c0, c2 = fit(rows)
    worst = max(max(row["seconds_per_step"] / (c0 + c2 * row["elements"] ** 2),
                    (c0 + c2 * row["elements"] ** 2) / row["seconds_per_step"]) for row in rows)
    args.out.write_text(json.dumps({"rows": rows, "fit": {"c0": c0, "c2": c2, "worst_ratio": worst}, **stamp()},
                                   indent=1) + "\n", encoding="utf-8")
    print(f"c0 = {c0:.4g} s, c2 = {c2:.4g} s; within {worst:.2f}x of every size; wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
