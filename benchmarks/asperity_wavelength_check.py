"""Set and check asperity_wavelength's declared error on seed 004's systems and on random ones (docs/asperity.md).

    python benchmarks/asperity_wavelength_check.py            # ~25 min on 2 cores
    python benchmarks/asperity_wavelength_check.py --quick    # 2 random systems a draw, n = 1

The closed form gives v_cn = f0 lambda / n (eqs. 28-29). What it predicts is a lock: at v_cn the forcing
frequency v / lambda is f0 / n, so the block swings n times on its natural frequency in each forcing period: n
loops a period. The m_D curves carry fractional locks of comparable height beside the integer ones, so
the nearest peak or the largest one can be another lock (in Table I case 1's sweep the largest m_D is a
fractional one). The simulated critical speed is therefore the speed of the largest m_D among the
sweep's responses with n loops a period, in a quasi-static sweep (C = 200 kg/s, 3 s, the last half analysed) of
0.75 to 1.5 times the closed form's v_cn on a grid of 1.25 % of it. Systems: Table I cases 1-5 and random ones
about case 3 (f0 5-100 Hz and the contact length 0.03-0.3 um log-uniform, s 0.05-0.35, initial approach 0.2-0.45
um). The declared error (dynamics.WAVELENGTH_ERROR) is the largest error over Table I and the calibration draws
times :data:`MARGIN`, rounded up to one figure; the held-out draw is then measured once against it.

Writes benchmarks/results/asperity_wavelength_check.json (benchmarks/readme.py renders docs/asperity.md's table).
"""

from __future__ import annotations

import argparse
import math
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.models.asperity.dynamics import (STEPS_PER_PERIOD, WAVELENGTH_ERROR, AsperityModel,  # noqa: E402
                                                speed_sweep)
from provenance import write_results  # noqa: E402  (one stamp for every results file)

#: two calibration draws: on the first alone (4004) the declared error came to 0.2, and the second (4005), then
#: held out, erred by up to 0.192 where f0 and the contact length are large; both now set it
CALIBRATION_SEEDS, HELD_OUT_SEED = (4004, 4005), 4006
RANDOM_SYSTEMS = 12
#: the declared error stands this far above every calibration error, so that systems not drawn have room
MARGIN = 1.5
ORDERS = (1, 2)
#: the sweep about each v_cn, as multiples of it
LOW, HIGH, POINTS = 0.75, 1.5, 61


def systems(count: int, seed: int, table: bool) -> list[tuple[str, int, dict]]:
    """Table I cases 1-5 (if ``table``), then ``count`` random systems about case 3 drawn from ``seed``."""
    found = [(f"Table I case {case}", case, {}) for case in (1, 2, 3, 4, 5)] if table else []
    rng = np.random.default_rng(seed)
    for index in range(count):
        changes = {"natural_frequency": float(10 ** rng.uniform(math.log10(5.0), 2.0)),
                   "slope_std": float(rng.uniform(0.05, 0.35)),
                   "initial_approach": float(rng.uniform(0.2e-6, 0.45e-6)),
                   "contact_length": float(10 ** rng.uniform(math.log10(0.03e-6), math.log10(0.3e-6)))}
        found.append((f"random {seed}-{index}", 3, changes))
    return found


def measure(job) -> dict:
    """One system and order: the closed form's v_cn and the strongest n-loop response of the sweep about it."""
    label, case, changes, order = job
    model = AsperityModel.table_case(case, dashpot=200.0, **changes)
    closed = float(model.critical_speeds((order,))[0])
    speeds = closed * np.linspace(LOW, HIGH, POINTS)
    sweep = speed_sweep(model, speeds, duration=3.0)
    strength = sweep["mean_deformation_friction"].values
    locked = np.isfinite(strength) & (np.round(sweep["loops"].values) == order)
    row = {"system": label, "natural_frequency": model.natural_frequency, "slope_std": model.slope_std,
           "initial_approach": model.initial_approach, "contact_length": model.contact_length, "order": order,
           "closed_form": closed,
           "cells_failed": int(np.sum([status != "ok" for status in sweep["status"].values]))}
    if locked.any():
        best = int(np.argmax(np.where(locked, strength, -np.inf)))
        band = speeds[locked]
        row.update(simulated=float(speeds[best]), band=[float(band.min()), float(band.max())])
        row["error"] = float(closed / row["simulated"] - 1)  # relative to the simulated speed, as declared
    else:
        row.update(simulated=None, band=None, error=None)
    return row


def declared_from(rows) -> float:
    """:data:`MARGIN` times the largest |error| of ``rows``, rounded up to one significant figure."""
    need = MARGIN * max(abs(row["error"]) for row in rows if row["error"] is not None)
    exponent = math.floor(math.log10(need))
    return round(math.ceil(need / 10 ** exponent - 1e-9) * 10 ** exponent, -exponent)


def measure_all(chosen, orders) -> list[dict]:
    jobs = [(label, case, changes, order) for label, case, changes in chosen for order in orders]
    with ProcessPoolExecutor(2) as pool:
        return list(pool.map(measure, jobs))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 random systems a draw, n = 1")
    args = parser.parse_args(argv)
    count = 2 if args.quick else RANDOM_SYSTEMS
    orders = (1,) if args.quick else ORDERS
    chosen = [system for index, seed in enumerate(CALIBRATION_SEEDS) for system in systems(count, seed, index == 0)]
    calibration = measure_all(chosen, orders)
    fitted = declared_from(calibration)
    held_out = measure_all(systems(count, HELD_OUT_SEED, False), orders)
    errors = [abs(row["error"]) for row in held_out if row["error"] is not None]
    document = {"declared_error": WAVELENGTH_ERROR, "fitted_error": fitted, "margin": MARGIN,
                "seeds": {"calibration": list(CALIBRATION_SEEDS), "held_out": HELD_OUT_SEED}, "orders": list(orders),
                "sweep": [LOW, HIGH, POINTS], "rows": calibration, "held_out_rows": held_out,
                "largest_error": max(abs(row["error"]) for row in calibration if row["error"] is not None),
                "held_out_largest_error": max(errors) if errors else None,
                "without_lock": sum(row["error"] is None for row in calibration + held_out), "quick": bool(args.quick),
                "steps_per_period": STEPS_PER_PERIOD}
    write_results("asperity_wavelength_check.json", document)
    print(f"largest |closed form / simulated - 1|: {document['largest_error']:.3g} (calibration), fitted declared "
          f"error {fitted:g} (shipped {WAVELENGTH_ERROR:g}); held out {document['held_out_largest_error']:.3g}; "
          f"{document['without_lock']} sweeps without the lock")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
