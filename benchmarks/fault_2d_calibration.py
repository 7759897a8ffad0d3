"""The one-slider model's error against the 2-D fault over W / h*: computes and ships the calibration.

    python benchmarks/fault_2d_calibration.py [--workers 2] [--quick]

Each row runs the 2-D fault (uniform SEAS BP1 friction from the surface to D = 20 km, steady slip
below, 4 elements per L_b, ten cycles after the spin-up) and the one-block fault with K = G / D
(faultslip.models.fault_2d.calibration.compare), changing D_c to set W / h*. Writes
data/fault_2d_model_error.json, which faultslip.models.rate_state_slider.model_error.declared_model_error reads and
the one-slider methods declare. --quick computes three ratios into benchmarks/results/ instead.
"""

from __future__ import annotations

import argparse
import json
import sys
from concurrent.futures import as_completed
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.fault.rate_state_scene import load_rate_state_scene  # noqa: E402
from faultslip.io.processes import stop_pool, worker_pool  # noqa: E402
from faultslip.models.fault_2d import calibration as model_error  # noqa: E402
from faultslip.models.rate_state_slider import model_error as declared  # noqa: E402

BASE = ROOT / "configs" / "rsf_fault_bp1.toml"


def _row(ratio):
    return model_error.calibration_row(load_rate_state_scene(BASE), ratio)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    ratios = (1.5, 3.0, 6.0) if args.quick else model_error.RATIOS
    table = model_error.calibrate(load_rate_state_scene(BASE), ratios=())
    pool = worker_pool(min(args.workers, len(ratios)))
    try:
        futures = {pool.submit(_row, ratio): ratio for ratio in ratios}
        rows = []
        for future in as_completed(futures):
            row = future.result()
            rows.append(row)
            print(f"W/h* {row['width_over_nucleation']:5.2f}: model error {row['model_error']:.3f}"
                  + (f" (T 2-D {row['recurrence_2d'] / 3.15576e7:.1f} yr, block {row['recurrence_one_slider'] / 3.15576e7:.1f} yr; "
                     f"{row['elements']} elements, {row['wall_time_2d']:.0f} s)" if "recurrence_2d" in row else
                     f" ({row.get('note', '')})"), flush=True)
    finally:
        stop_pool(pool)
    table["rows"] = sorted(rows, key=lambda row: row["width_over_nucleation"])
    out = (ROOT / "benchmarks" / "results" / "fault_2d_calibration_quick.json" if args.quick
           else ROOT / "data" / declared.CALIBRATION_FILE)
    out.write_text(json.dumps(table, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}")


if __name__ == "__main__":
    main()
