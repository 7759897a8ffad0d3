"""Penn State's p655, end to end (issue 46, item 2): each velocity step fitted, the laws compared, posteriors.

    python benchmarks/p655_analysis.py            # ~2 min on one core
    python benchmarks/p655_analysis.py --quick    # no posteriors

The run's own r-file reduces data/p655/p655intact100l (faultslip.lab.run_r_file); the two sequences of velocity
steps, 2400-3150 s at 75 MPa and 3350-4240 s at 100 MPa, are read by the reduction's column names, the steps found
from the load point's displacement, and every step fitted in its own window (from half the segment before it to
the next step) with the machine's stiffness and a linear trend free (fit_each_step). Both evolution laws and the
two-state aging law are compared by BIC on effective points (select_law) in each window. The two slow up-steps
(2.29 -> 22.86 um/s at 75 and 100 MPa) get a posterior each (stiffness and trend free) and a joint fit with a, b,
D_c shared; and, before any fit, each hold's healing and each step's a - b from the steady levels. Writes
benchmarks/results/p655_analysis.json and docs/figures/p655_steps.png; benchmarks/readme.py renders docs/lab_fits.md's
tables from it.
"""

from __future__ import annotations

import argparse
import json
import sys
import time as clock
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from faultslip.lab.healing import healing, steady_state_dependence  # noqa: E402
from faultslip.lab.law_selection import select_law  # noqa: E402
from faultslip.lab.look_reduction import run_r_file  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)
from faultslip.lab.posterior import sample_posterior  # noqa: E402
from faultslip.lab.rate_state_fit import fit_joint  # noqa: E402
from faultslip.lab.raw_records import (fit_each_step, read_rig_record, prepare_record, step_windows,  # noqa: E402
                                       window_record)

COLUMNS = {"time": "Time", "load_point_displacement": "LP_disp", "shear_stress": "Shear_stress",
           "normal_stress": "Nor_stress"}
SEQUENCES = {"75 MPa": (2400.0, 3150.0), "100 MPa": (3350.0, 4240.0)}
STATED_STIFFNESS = "2000 1/m"  # the free stiffness's start and its prior's median (the onset slopes give 1.5-2.2e3)
RESULTS = ROOT / "benchmarks" / "results" / "p655_analysis.json"
FIGURE = ROOT / "docs" / "figures" / "p655_steps.png"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="no posteriors")
    args = parser.parse_args()
    started = clock.perf_counter()
    reduced = ROOT / "benchmarks" / "results" / "p655_reduced.nc"
    run_r_file(ROOT / "data" / "p655" / "p655_r").to_dataset().to_netcdf(reduced)
    out = {**stamp(), "started": datetime.now(timezone.utc).isoformat(timespec="seconds"), "stated_stiffness": STATED_STIFFNESS,
           "sequences": {}}
    figure, axes = plt.subplots(2, 4, figsize=(15, 6.5), constrained_layout=True)
    slow = []
    for row, (label, span) in enumerate(SEQUENCES.items()):
        record = read_rig_record(reduced, columns=COLUMNS, span=span)
        prepared = prepare_record(record, STATED_STIFFNESS)
        history = prepared.record.history
        steps = []
        windows = step_windows(prepared)
        fits = {law: fit_each_step(prepared, law, stiffness_free=True, trend=True) for law in ("aging", "slip")}
        panel = 0
        for (start, end), aging, slip in zip(windows, fits["aging"], fits["slip"]):
            window = window_record(prepared.record, start, end, "p655 window")
            speeds = window.history.speeds
            entry = {"window_s": [start + span[0], end + span[0]],
                     "speeds_um_s": [round(v * 1e6, 3) for v in speeds],
                     "kind": "hold" if 0.0 in speeds else ("up" if speeds[1] > speeds[0] else "down")}
            for law, fitted in (("aging", aging), ("slip", slip)):
                if "fit" in fitted:
                    fit = fitted["fit"]
                    entry[law] = {name: {"value": value, "interval_95": list(fit.intervals[name])}
                                  for name, value in fit.parameters.items()}
                    entry[law]["residual_rms"] = fit.residual_rms
                    entry[law]["notes"] = fit.notes
                else:
                    entry[law] = {"error": fitted["error"]}
            if entry["kind"] != "hold":
                selection = select_law(window, prepared.stiffness, stiffness_free=True, trend=True)
                entry["selection"] = {"chosen": selection.chosen, "verdict": selection.verdict(),
                                      "effective_points": selection.effective_points, "points": selection.points,
                                      "delta_bic": {r["law"]: r.get("delta") for r in selection.rows}}
            if entry["kind"] == "up" and speeds[0] < 5e-6 and "fit" in aging:
                slow.append((label, window, aging["fit"]))
            if panel < 4 and entry["kind"] != "hold" and "fit" in aging:
                axis = axes[row, panel]
                fit = aging["fit"]
                axis.plot(window.time, window.friction, ",", color="0.5", label="p655")
                axis.plot(window.time, window.friction + fit.residuals, color="C3", lw=1.0,
                          label=f"aging: a {fit.parameters['a']:.4f}, b {fit.parameters['b']:.4f},\n"
                                f"D_c {fit.parameters['critical_slip'] * 1e6:.1f} um, k {fit.parameters['stiffness']:.0f}/m")
                axis.set_title(f"{label}: " + " -> ".join(f"{v * 1e6:.3g}" for v in speeds) + " um/s", fontsize=9)
                axis.set_xlabel("time in window (s)")
                axis.legend(fontsize=7, loc="best")
                panel += 1
            steps.append(entry)
        for axis in axes[row, panel:]:
            axis.set_visible(False)
        axes[row, 0].set_ylabel("friction")
        # what the record shows before any fit: each hold's healing, each step's a - b from the steady levels
        held = healing(prepared.record).as_dict()["holds"] if 0.0 in history.speeds else []
        out["sequences"][label] = {"span_s": list(span), "steps_s": [t + span[0] for t in history.times[1:-1]],
                                   "speeds_um_s": [round(v * 1e6, 3) for v in history.speeds], "windows": steps,
                                   "holds": [{"start_s": hold["start"]["value"] + span[0],
                                              "hold_time_s": hold["hold_time"]["value"], "healing": hold["healing"],
                                              "relaxation": hold["relaxation"]} for hold in held],
                                   "steady_steps": [{"time_s": row.time + span[0],
                                                     "speeds_um_s": [row.speed_before * 1e6, row.speed_after * 1e6],
                                                     "a_minus_b": row.a_minus_b}
                                                    for row in steady_state_dependence(prepared.record)]}
    figure.savefig(FIGURE, dpi=110)
    records = [window for _, window, _ in slow]
    joint = fit_joint(records, [fit.parameters["stiffness"] for _, _, fit in slow], stiffness_free=True, trend=True)
    out["joint_slow_up_steps"] = joint.to_dict()
    if not args.quick:
        out["posteriors"] = {}
        for label, window, fit in slow:
            begun = clock.perf_counter()
            posterior = sample_posterior(window, fit.parameters["stiffness"], stiffness_free=True, trend=True,
                                         initial_fit=fit, seed=0)
            summary = posterior.to_dict()
            summary["seconds"] = clock.perf_counter() - begun
            out["posteriors"][label] = summary
    out["seconds"] = clock.perf_counter() - started
    reduced.unlink()
    RESULTS.write_text(json.dumps(out, indent=1, default=float) + "\n", encoding="utf-8")
    print(json.dumps({label: [(w["kind"], w["speeds_um_s"], {k: round(v["value"], 7) for k, v in w["aging"].items()
                                                            if isinstance(v, dict) and "value" in v},
                               w.get("selection", {}).get("chosen"))
                              for w in seq["windows"]] for label, seq in out["sequences"].items()}, indent=1))
    print(f"{out['seconds']:.0f} s; {RESULTS.relative_to(ROOT)}, {FIGURE.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
