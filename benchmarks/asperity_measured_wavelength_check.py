"""Set and check asperity_measured_wavelength's declared error on the locks asperity_wavelength_check found.

    python benchmarks/asperity_measured_wavelength_check.py     # ~1 min on 2 cores, after asperity_wavelength_check

asperity_measured_wavelength predicts v_cn = f0 lambda_run / n, with lambda_run the slip per approach cycle of a
run at the closed form's v_c1, at rtol 1e-8 and, as its convergence check, 1e-10 (dynamics.measured_wavelength). Its reference is the same one as the closed form's:
the strongest n-loop lock in each quasi-static sweep of benchmarks/asperity_wavelength_check.py, read from its
results (every row's system is rebuilt from its seed, and its parameters checked against the row). The declared
error (dynamics.MEASURED_WAVELENGTH_ERROR) is :data:`MARGIN` times the largest error over Table I and the calibration
draws, rounded up to one figure, as the closed form's is; the held-out draw is measured once against it.

Writes benchmarks/results/asperity_measured_wavelength_check.json (benchmarks/readme.py renders docs/asperity.md's
table).
"""

from __future__ import annotations

import hashlib
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from asperity_wavelength_check import (CALIBRATION_SEEDS, HELD_OUT_SEED, MARGIN, RANDOM_SYSTEMS,  # noqa: E402
                                       declared_from, systems)
from faultslip.errors import SolverError  # noqa: E402
from faultslip.io.atomic import save_figure  # noqa: E402
from faultslip.models.asperity.dynamics import (MEASURE_PERIODS, MEASURED_WAVELENGTH_ERROR,  # noqa: E402
                                                STEPS_PER_PERIOD, AsperityModel, measured_wavelength)
from provenance import write_results  # noqa: E402  (one stamp for every results file)

LOCKS = ROOT / "benchmarks" / "results" / "asperity_wavelength_check.json"
FIGURE = ROOT / "docs" / "figures" / "asperity_critical_speed_error.png"
#: closed-form evaluations timed together: one takes microseconds, below the process clock's resolution
CLOSED_FORM_REPEATS = 2000


def error_cost_figure(document: dict):
    """Each lock's |error| against the CPU its prediction took, for both predictors, coloured by the contact length
    alpha; dashed: the declared errors."""
    from faultslip.plots.figures import _pyplot

    plt = _pyplot()
    figure, axis = plt.subplots(figsize=(7.5, 4.6), constrained_layout=True)
    systems = {line["system"]: line for line in document["systems"] if line["wavelength"] is not None}
    lines = [line for line in document["rows"] + document["held_out_rows"]
             if line["error"] is not None and line["system"] in systems]
    alpha = np.array([1e6 * line["contact_length"] for line in lines])
    for key, cost, marker, name in (("closed_form_error", "closed_form_cpu_seconds", "v", "closed form f0 λ / n"),
                                    ("error", "cpu_seconds", "o", "f0 λ_run / n (two runs)")):
        shown = axis.scatter([systems[line["system"]][cost] for line in lines],
                             [max(abs(line[key]), 1e-4) for line in lines], c=alpha, cmap="viridis", marker=marker,
                             s=22, label=name, vmin=0.03, vmax=0.3)
    for declared, name in ((document["closed_form_declared_error"], "asperity_wavelength"),
                           (document["declared_error"], "asperity_measured_wavelength")):
        axis.axhline(declared, color="0.4", ls="--", lw=0.8)
        axis.annotate(f"{name} declares {declared:g}", (1e-6, declared), xytext=(2, 3), textcoords="offset points",
                      fontsize=8, color="0.3")
    axis.axhline(1.0 / (document["sweep_points"] - 1) * (document["sweep_high"] - document["sweep_low"]),
                 color="0.7", ls=":", lw=0.8)
    axis.set(xscale="log", yscale="log", xlim=(5e-7, 5), xlabel="CPU per prediction (s)",
             ylabel="|predicted / simulated lock - 1|",
             title="seed 004 critical speeds: error against cost (dotted: the sweeps' speed step)")
    figure.colorbar(shown, ax=axis, label="contact length α (µm)")
    axis.legend(fontsize=8, loc="lower right")
    axis.grid(True, alpha=0.3, which="both")
    return figure


def measure(job) -> dict:
    """One system: the wavelength its run slides, how many cycles it is the median of, their spread, the CPU."""
    label, case, changes = job
    model = AsperityModel.table_case(case, dashpot=200.0, **changes)
    started = time.process_time()
    for _ in range(CLOSED_FORM_REPEATS):
        model.critical_speeds((1, 2))
    closed_form_cpu = (time.process_time() - started) / CLOSED_FORM_REPEATS
    started = time.process_time()
    try:
        found = measured_wavelength(model)
    except SolverError as error:
        return {"system": label, "wavelength": None, "failure": str(error)}
    return {"system": label, "wavelength": found.wavelength, "closed_form_wavelength": model.wavelength,
            "cycles": found.cycles, "spread": found.spread, "cpu_seconds": time.process_time() - started,
            "numerical_error": found.numerical_error,
            "closed_form_cpu_seconds": closed_form_cpu,
            "natural_frequency": model.natural_frequency, "slope_std": model.slope_std,
            "initial_approach": model.initial_approach, "contact_length": model.contact_length}


def predicted(rows: list[dict], wavelengths: dict) -> list[dict]:
    """Each lock row with f0 lambda_run / n beside it, its error against the strongest lock, and whether it lies
    inside the n-loop band."""
    out = []
    for row in rows:
        measured = wavelengths[row["system"]]
        for key in ("natural_frequency", "slope_std", "initial_approach", "contact_length"):
            if measured.get(key) is not None and measured[key] != row[key]:
                raise SystemExit(f"{row['system']}: its {key} is not the lock file's: the seeds' draws changed; "
                                 "rerun benchmarks/asperity_wavelength_check.py")
        line = {"system": row["system"], "order": row["order"], "closed_form_error": row["error"],
                "closed_form_inside_band": None if row["band"] is None else
                bool(row["band"][0] <= row["closed_form"] <= row["band"][1]),
                "simulated": row["simulated"], "contact_length": row["contact_length"]}
        if measured["wavelength"] is None or row["simulated"] is None:
            line.update(prediction=None, error=None, inside_band=None, failure=measured.get("failure"))
        else:
            speed = row["natural_frequency"] * measured["wavelength"] / row["order"]
            line.update(prediction=speed, error=speed / row["simulated"] - 1,
                        inside_band=bool(row["band"][0] <= speed <= row["band"][1]))
        out.append(line)
    return out


def main(argv=None) -> int:
    locks = json.loads(LOCKS.read_text(encoding="utf-8"))
    count = 2 if locks.get("quick") else RANDOM_SYSTEMS  # a --quick lock file has 2 random systems a draw
    chosen = [system for index, seed in enumerate(CALIBRATION_SEEDS) for system in systems(count, seed, index == 0)]
    held = systems(count, HELD_OUT_SEED, False)
    with ProcessPoolExecutor(2) as pool:
        found = list(pool.map(measure, chosen + held))
    wavelengths = {line["system"]: line for line in found}
    calibration, held_out = predicted(locks["rows"], wavelengths), predicted(locks["held_out_rows"], wavelengths)
    fitted = declared_from(calibration)
    held_errors = [abs(row["error"]) for row in held_out if row["error"] is not None]
    document = {"declared_error": MEASURED_WAVELENGTH_ERROR, "fitted_error": fitted, "margin": MARGIN,
                "locks": {"file": "benchmarks/results/asperity_wavelength_check.json",
                          "sha256": hashlib.sha256(LOCKS.read_bytes()).hexdigest(),
                          "steps_per_period": locks.get("steps_per_period"), "date": locks.get("date")},
                "measure_periods": MEASURE_PERIODS, "steps_per_period": STEPS_PER_PERIOD,
                "systems": found, "rows": calibration, "held_out_rows": held_out,
                "largest_error": max(abs(row["error"]) for row in calibration if row["error"] is not None),
                "held_out_largest_error": max(held_errors) if held_errors else None,
                "closed_form_largest_error": locks["largest_error"],
                "closed_form_held_out_largest_error": locks["held_out_largest_error"],
                "closed_form_declared_error": locks["declared_error"],
                "closed_form_inside_band": sum(bool(row["closed_form_inside_band"]) for row in calibration + held_out),
                "inside_band": sum(bool(row["inside_band"]) for row in calibration + held_out),
                "compared": sum(row["error"] is not None for row in calibration + held_out),
                "failed": sum(line["wavelength"] is None for line in found), "quick": bool(locks.get("quick")),
                "largest_numerical_error": max((line["numerical_error"] for line in found
                                                if line["wavelength"] is not None), default=None),
                "sweep_low": locks["sweep"][0], "sweep_high": locks["sweep"][1], "sweep_points": locks["sweep"][2]}
    write_results("asperity_measured_wavelength_check.json", document)
    if not document["quick"]:
        save_figure(error_cost_figure(document), FIGURE, dpi=110)
        print(f"drawn to {FIGURE}")
    print(f"largest |f0 lambda_run / n / simulated - 1|: {document['largest_error']:.3g} (calibration), fitted "
          f"declared error {fitted:g} (shipped {MEASURED_WAVELENGTH_ERROR:g}); held out "
          f"{document['held_out_largest_error']:.3g}; the closed form's {locks['largest_error']:.3g} and "
          f"{locks['held_out_largest_error']:.3g}; {document['failed']} systems without a measured wavelength")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
