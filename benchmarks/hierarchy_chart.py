"""Speed against accuracy up the model hierarchy, on SEAS BP1 (issue 42, item 5).

    python benchmarks/hierarchy_chart.py

One chart for a BP1-like fault: each way faultslip can answer its recurrence, its error against the converged
2-D answer against its cost, and what each declares.

* **One slider** (``faultslip run configs/rsf_block_bp1.toml``): timed here (the median of five whole calls);
  its true error against BP1's 2-D answer is the calibration's held-out BP1 row (data/fault_2d_model_error.json,
  recurrence and slip), its declared bound the calibration's.
* **The 2-D fault at several resolutions** (elements per L_b from 0.5 to 16): benchmarks/results/
  fault_2d_resolution.json, each run's recurrence against the Richardson limit, and what one run declares at
  that resolution (the a-priori bound, at least the kind-change term); below 2 elements per L_b it is refused.
* **The 2-D fault at several tolerances** (39 m elements, rtol 1e-4 to 1e-9): benchmarks/results/
  fault_2d_qdyn_study.json, against the same limit, each declaring what one run declares there.

Costs are each run's wall time on this machine (the 2-D runs over 700 or 1000 simulated years, enough to settle
and measure BP1's cycle). Writes data/fault_2d_hierarchy.json, which ``faultslip model-error --plot`` draws beside
the calibration, and docs/figures/hierarchy.png.
"""

from __future__ import annotations

import json
import statistics
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import faultslip  # noqa: E402
from faultslip.io.resources import write_bundled_table  # noqa: E402
from faultslip.models.rate_state_slider.one_slider import load_calibration  # noqa: E402
from faultslip.io.atomic import save_figure  # noqa: E402
from faultslip.models.fault_2d.analysis import MIN_RESOLUTION, single_run_error  # noqa: E402


def main():
    resolution = json.loads((ROOT / "benchmarks" / "results" / "fault_2d_resolution.json").read_text())
    bp1 = next(fault for fault in resolution["faults"] if fault["name"] == "bp1")
    reference = bp1["reference_yr"]
    points = []
    for run in bp1["runs"]:
        refused = run["resolution"] < MIN_RESOLUTION
        points.append({"method": "fault_2d", "label": f"{run['resolution']:.3g} elements per L_b",
                       "resolution": run["resolution"], "seconds": run["wall_s"], "error": run["error"],
                       "declared": None if refused else single_run_error(run["resolution"]),
                       "refused": refused, "sequence": run["sequence"]})
    study = json.loads((ROOT / "benchmarks" / "results" / "fault_2d_qdyn_study.json").read_text())
    process_zone = bp1["process_zone_m"]
    for run in study["faultslip"]["study"]:
        element = 40e3 / run["elements"]
        points.append({"method": "fault_2d_tolerance", "label": f"rtol {run['tolerance']:g}, {element:.3g} m",
                       "resolution": process_zone / element, "tolerance": run["tolerance"], "seconds": run["wall_s"],
                       "error": abs(run["recurrence_yr"] / reference - 1),
                       "declared": single_run_error(process_zone / element), "refused": False,
                       "sequence": "periodic" if run["settled"] else "unsettled"})
    seconds = []
    for _ in range(5):
        started = time.perf_counter()
        result = faultslip.run(ROOT / "configs" / "rsf_block_bp1.toml")
        seconds.append(time.perf_counter() - started)
    calibration = load_calibration()["geometric"]
    held = next(row for row in calibration["held_out"] if row["name"] == "SEAS BP1")
    block_error = abs(result["recurrence_period"].to("yr").magnitude / reference - 1)
    points.append({"method": "one_slider", "label": "one slider, K = c G / W", "seconds": statistics.median(seconds),
                   "error": max(block_error, held["model_error"]), "recurrence_error": block_error,
                   "declared": result["model_error"], "refused": False, "sequence": "periodic"})
    table = {"provenance": {"computed_by": "benchmarks/hierarchy_chart.py", "faultslip": faultslip.__version__,
                            "date": datetime.now(timezone.utc).strftime("%Y-%m-%d"),
                            "reference": f"SEAS BP1's recurrence, the Richardson limit of the resolution study: "
                                         f"{reference:.6g} yr",
                            "sources": ["benchmarks/results/fault_2d_resolution.json",
                                        "benchmarks/results/fault_2d_qdyn_study.json",
                                        "data/fault_2d_model_error.json (held-out SEAS BP1)"]},
             "reference_yr": reference, "points": points}
    out = ROOT / "data" / "fault_2d_hierarchy.json"
    write_bundled_table(out, table)
    from faultslip.models.rate_state_slider.figures import hierarchy_figure

    figure = hierarchy_figure(table)
    save_figure(figure, ROOT / "docs" / "figures" / "hierarchy.png", dpi=110)
    for point in points:
        print(f"{point['label']:>32}: {point['seconds']:8.3g} s, error {point['error']:.3g}, declared "
              f"{point['declared'] if point['declared'] is None else format(point['declared'], '.3g')}"
              + (" (refused)" if point["refused"] else ""))
    print(f"written to {out}")


if __name__ == "__main__":
    main()
