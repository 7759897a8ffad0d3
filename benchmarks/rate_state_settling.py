"""How many steps a rate-and-state fault's recorded cycles take (what ``faultslip simulate`` of a one-slider fault
runs), fitted on random faults and tested on others: the settling model of
:func:`faultslip.dynamics.rate_state.methods.cycle_steps`.

    python benchmarks/rate_state_settling.py

A fault's cycles are measured once the sequence has settled (``fault_cycles``' settling test), so a run takes
the measured cycles and the cycles before them: four far from K_c, and near K_c many more, where the 1 % start
grows slowly into the cycle and settles slowly onto it. In steps, that is

    steps = steps_per_cycle(method, rtol, K / K_c) (cycles + settling),
    settling = base + c / ((1 - K / K_c)^p (1 - a / b)^q),

with steps_per_cycle the integrators' calibrated count (:mod:`faultslip.dynamics.rate_state.methods`). base, c, p
and q are least squares in ln(steps) over the faults of two random draws (seeds 1 and 2) and tested on a third
(seed 3) that never enters the fit. Each fault is BP1's friction with a / b 0.3-0.95, either evolution law,
sigma_n x 0.2-3, D_c x 0.25-4, and K / K_c set by its width: 1 - 10^U(-2.7, -1) for a third of them (near K_c),
10^U(-4, -0.05) for the rest; 2, 5 or 20 cycles recorded at the default tolerance, as ``simulate`` records them.
A fault with no events (its slip speed peaking below the event speed, or cycles longer than the run's
horizon) is counted apart. Steps do not depend on the machine's speed. Writes
benchmarks/results/rate_state_settling.json.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.dynamics.rate_state.methods import steps_per_cycle  # noqa: E402
from faultslip.dynamics.rate_state.slider import RateStateSlider, cycles_stiffness_ratio, fault_cycles  # noqa: E402
from faultslip.errors import NoEventsError  # noqa: E402
from faultslip.friction.rate_state import RateStateLaw  # noqa: E402
from provenance import write_results  # noqa: E402

FIT_SEEDS, HELD_OUT_SEED, FAULTS_PER_DRAW = (1, 2), 3, 60
#: simulate's tolerance (fault_cycles' default) and the modulus, density and wave speed of BP1
RTOL, MODULUS, DENSITY, WAVE_SPEED, PLATE_RATE = 1e-7, 32e9, 2670.0, 3464.0, 1e-9


def draw(seed: int, count: int) -> list[dict]:
    """Random faults about BP1's friction, K / K_c set by the block's width."""
    rng = np.random.default_rng(seed)
    faults = []
    for _ in range(count):
        ratio_b = float(rng.uniform(0.3, 0.95))
        evolution = "slip" if rng.uniform() < 0.3 else "aging"
        sigma = float(50e6 * math.exp(rng.uniform(math.log(0.2), math.log(3.0))))
        critical_slip = float(8e-3 * math.exp(rng.uniform(math.log(0.25), math.log(4.0))))
        near = rng.uniform() < 1 / 3
        ratio = float(1 - 10 ** rng.uniform(-2.7, -1) if near else 10 ** rng.uniform(-4, -0.05))
        faults.append({"a": 0.015 * ratio_b, "b": 0.015, "evolution": evolution, "normal_stress": sigma,
                       "critical_slip": critical_slip, "target_ratio": ratio, "cycles": int(rng.choice([2, 5, 20]))})
    return faults


def run(fault: dict) -> dict:
    law = RateStateLaw(a=fault["a"], b=fault["b"], critical_slip=fault["critical_slip"], evolution=fault["evolution"])
    critical = fault["normal_stress"] * (fault["b"] - fault["a"]) / fault["critical_slip"]
    slider = RateStateSlider.at_fault(law, MODULUS, MODULUS / (fault["target_ratio"] * critical),
                                      fault["normal_stress"], density=DENSITY, shear_wave_speed=WAVE_SPEED)
    ratio = cycles_stiffness_ratio(slider)
    try:
        cycles = fault_cycles(slider, PLATE_RATE, cycles=fault["cycles"], rtol=RTOL, record=True)
    except NoEventsError as error:
        return {**fault, "stiffness_ratio": ratio, "no_events": str(error)}
    return {**fault, "stiffness_ratio": ratio, "method": cycles.method, "spin_up": cycles.spin_up,
            "steps": int(cycles.steps), "steps_per_cycle": steps_per_cycle(cycles.method, RTOL, ratio)}


def settling(parameters, ratio, ratio_b):
    base, log_c, power, ab_power = parameters
    return base + np.exp(log_c) / ((1 - ratio) ** power * (1 - ratio_b) ** ab_power)


def residuals(parameters, rows) -> np.ndarray:
    """ln(estimated / measured steps) of each fault."""
    ratio = np.array([row["stiffness_ratio"] for row in rows])
    ratio_b = np.array([row["a"] / row["b"] for row in rows])
    cycles = np.array([row["cycles"] for row in rows])
    per_cycle = np.array([row["steps_per_cycle"] for row in rows])
    measured = np.array([row["steps"] for row in rows])
    return np.log(per_cycle * (cycles + settling(parameters, ratio, ratio_b)) / measured)


def summary(rows, parameters) -> dict:
    ratios = np.exp(residuals(parameters, rows))
    return {"faults": len(rows), "within_2x": int(np.sum((ratios >= 0.5) & (ratios <= 2))),
            "ratio_min": float(ratios.min()), "ratio_median": float(np.median(ratios)),
            "ratio_max": float(ratios.max())}


def main() -> int:
    runs = {seed: [run(fault) for fault in draw(seed, FAULTS_PER_DRAW)] for seed in (*FIT_SEEDS, HELD_OUT_SEED)}
    fitted = [row for seed in FIT_SEEDS for row in runs[seed] if "steps" in row]
    held_out = [row for row in runs[HELD_OUT_SEED] if "steps" in row]
    fit = least_squares(residuals, [4.0, math.log(0.03), 1.0, 1.0], args=(fitted,),
                        bounds=([0.0, -30.0, 0.0, 0.0], [10.0, 5.0, 3.0, 3.0]))
    base, log_c, power, ab_power = (float(value) for value in fit.x)
    document = {"computed_by": "benchmarks/rate_state_settling.py", "rtol": RTOL,
                "model": "steps = steps_per_cycle(method, rtol, K / K_c) (cycles + base + c / ((1 - K / K_c)^p "
                         "(1 - a / b)^q))",
                "fit": {"base": base, "c": math.exp(log_c), "p": power, "q": ab_power},
                "summary": {"fitted": summary(fitted, fit.x), "held_out": summary(held_out, fit.x),
                            "no_events": sum("no_events" in row for seed in runs for row in runs[seed])},
                "runs": {str(seed): rows for seed, rows in runs.items()}}
    write_results("rate_state_settling.json", document)
    for name, line in document["summary"].items():
        print(name, line)
    print("fit", document["fit"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
