"""The 2-D fault's recurrence against element size, on three faults of different W / h* and Lambda_0: what the
declared discretisation error and the coarse-resolution refusal are calibrated on (issue 42).

    python benchmarks/fault_2d_resolution.py [--quick]

Each fault runs at resolutions r = L_b / dz (elements per L_b = G D_c / (sigma_n b)) from 0.5 to 16; the
reference is the Richardson extrapolation of the two finest (order measured from the three finest). For each
run: the recurrence's relative error against the reference, and the sequence it found (periodic of period p,
aperiodic, unsettled). Writes benchmarks/results/fault_2d_resolution.json; the bound and the refusal in
faultslip/models/fault_2d/analysis.py are read from it (tests/models/fault_2d/test_fault_2d.py checks they cover every run).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.models.fault_2d.analysis import summarise  # noqa: E402
from faultslip.models.fault_2d.integrate import YEAR, run_cycles  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)

#: (name, scene, values replaced, years): BP1; the small fault (W / h* below 1); a short-D_c, high-stress one
FAULTS = [
    ("bp1", "seas_bp1.toml", {}, 700.0),
    ("small", "fault_2d_small.toml", {}, 700.0),
    ("short_dc", "fault_2d_small.toml", {"critical_slip": 0.010, "normal_stress": 60e6}, 1500.0),
]
RESOLUTIONS = (0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0, 16.0)


def run_one(scene, resolution: float, years: float) -> dict:
    width = scene.fault.element_size * scene.fault.count
    count = max(2, round(width * resolution / scene.fault.process_zone()))  # the elements divide the width
    size = width / count
    resolution = scene.fault.process_zone() / size
    sized = scene.at_element_size(size)
    run = run_cycles(sized.fault, years * YEAR, rtol=1e-8, stations=sized.stations, kernel="auto")
    summary = summarise(run, tolerance=1e-3)
    sequence = summary.sequence
    return {"resolution": resolution, "element_size_m": size, "elements": sized.fault.count,
            "lambda0_over_dz": 9 * math.pi / 32 * resolution, "years": years, "events": summary.events,
            "system_events": summary.system_events, "sequence": sequence.kind, "period": sequence.period,
            "recurrence_yr": summary.recurrence_interval / YEAR, "spread": summary.recurrence_spread,
            "steps": run.steps, "wall_s": run.wall_time}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the small fault alone")
    parser.add_argument("--only", help="one fault by name (the others are kept from the last results)")
    args = parser.parse_args(argv)
    out = ROOT / "benchmarks" / "results" / "fault_2d_resolution.json"
    kept = json.loads(out.read_text())["faults"] if args.only and out.exists() else []
    results = {**stamp(), "faults": []}
    chosen = FAULTS[1:2] if args.quick else [f for f in FAULTS if f[0] == args.only] if args.only else FAULTS
    results["faults"] = [entry for entry in kept if entry["name"] not in {f[0] for f in chosen}]
    for name, config, values, years in chosen:
        scene = read_fault_2d_scene(ROOT / "configs" / config, allow_large=True)
        if values:
            scene = scene.with_values(**values)
        fault = scene.fault
        entry = {"name": name, "scene": config, "values": values, "process_zone_m": fault.process_zone(),
                 "nucleation_size_m": fault.nucleation_size(), "seismogenic_width_m": fault.seismogenic_width(),
                 "runs": []}
        print(f"{name}: L_b {fault.process_zone():.4g} m, h* {fault.nucleation_size():.4g} m, "
              f"W {fault.seismogenic_width():.4g} m", flush=True)
        for resolution in RESOLUTIONS:
            row = run_one(scene, resolution, years)
            entry["runs"].append(row)
            print(f"  r {resolution:5g} ({row['element_size_m']:.4g} m, {row['elements']} elements): "
                  f"T {row['recurrence_yr']:.7g} yr, {row['sequence']} (p {row['period']}), "
                  f"{row['events']} events, {row['wall_s']:.1f} s", flush=True)
        runs = entry["runs"]
        (r6, fine), (r8, finer), (r16, finest) = ((row["resolution"], row["recurrence_yr"]) for row in runs[-3:])
        # Richardson: the order from the three finest (6, 8, 16 per L_b are not in a constant ratio: fit it)
        order = 2.0
        # the order p from the three finest: (T8 - T6) / (T16 - T8) = (r6^-p - r8^-p) / (r8^-p - r16^-p), by bisection
        target = (finer - fine) / (finest - finer) if finest != finer else math.inf
        low, high = 0.5, 6.0
        for _ in range(80):
            mid = 0.5 * (low + high)
            value = (r6 ** -mid - r8 ** -mid) / (r8 ** -mid - r16 ** -mid)
            low, high = (mid, high) if value < target else (low, mid)
        order = 0.5 * (low + high)
        if 1.0 < order < 5.5:  # a clean asymptotic order: Richardson's extrapolation
            reference = finest + (finest - finer) / ((r16 / r8) ** order - 1)
        else:  # not in the asymptotic range (oscillating convergence): the finest run is the reference
            reference = finest
        entry["order"], entry["reference_yr"] = order, reference
        for row in entry["runs"]:
            row["error"] = abs(row["recurrence_yr"] / reference - 1)
        print(f"  reference {reference:.8g} yr (order {order:.3g})", flush=True)
        results["faults"].append(entry)
    results["faults"].sort(key=lambda entry: [f[0] for f in FAULTS].index(entry["name"]))
    out.write_text(json.dumps(results, indent=2) + "\n")
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
