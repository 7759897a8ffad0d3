"""Where a 2-D fault run's time goes (issue 43, item 2: "profile first and say where the time goes").

    python benchmarks/fault_2d_profile.py [--elements 1024 1600] [--years 300] [--rtol 1e-4] [--core 0]

SEAS BP1 (configs/seas_bp1.toml) at each element count, over ``--years`` at ``--rtol`` (faultslip's loosest
tolerance within 0.1 % of its converged recurrence is 1e-3, benchmarks/fault_2d_qdyn.py; 1e-4 is the default
here), one thread pinned to one core. The whole trial step is one compiled call (numba, with rocket-fft for the
FFTs), which cProfile sees as one function; so the run is split in two ways:

- **by cProfile**: the compiled step, recording (stations, profiles, events, files) and the step's Python;
- **inside the compiled step**, each part timed alone on the run's last state, a stage at a time, with the
  same compiled kernels: the force balance (its exponentials, a SIMD pass, then Newton's method and the
  rates, every element), K x (a real
  FFT, the spectrum's product and the inverse), and the stage arithmetic with the error norm. What the parts
  leave of the step's measured time is its glue (calls, copies, the error's largest ratio), and what timing
  each part alone on one state misses (a real stage's solve may take another Newton step; a part alone keeps
  its data in cache).

Writes benchmarks/results/fault_2d_profile.json.
"""

from __future__ import annotations

import argparse
import cProfile
import math
import os
import pstats
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from faultslip.constants import JULIAN_YEAR  # noqa: E402
from faultslip.models.fault_2d.integrate import run_cycles  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402
from provenance import write_results  # noqa: E402  (one stamp for every results file)

WIDTH = 40e3
def _alone(call) -> float:
    """Seconds ``call`` takes, the best of three (it runs alone here: no other part's cache)."""
    call()
    best = math.inf
    for _ in range(3):
        began = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - began)
    return best


def parts_alone(fault, run, rtol: float) -> dict:
    """Microseconds a stage of each part of the compiled step, on ``run``'s last state (one thread)."""
    import numba  # heavy: the benchmark measures the compiled path

    from faultslip.models.fault_2d import compiled
    from faultslip.models.fault_2d.kernel import StressKernel
    from faultslip.models.fault_2d.model import NEWTON_ITERATIONS, ForceBalance, newton_tolerance

    count = fault.count
    operator = StressKernel(count, fault.element_size, fault.shear_modulus)
    balance = ForceBalance(fault, operator)
    balance.tolerance = newton_tolerance(rtol)
    y = np.concatenate([run.final_slip, run.final_state])
    speed, psi_rate, stress = balance.rates(run.final_time, y[:count], y[count:])
    kernels = compiled.kernels(True, 1)
    operator.padded[:count] = y[:count] - fault.plate_rate * run.final_time
    halves = operator.halves  # the step's K x: its two halves of the spectrum and their sum, the same kernel
    padded = np.zeros(halves.half_length)
    padded[:count] = operator.padded[:count]
    transforms = np.empty((4, halves.half_length // 2 + 1), dtype=complex)
    even_product, product_buffer = np.empty(halves.half_length), np.empty(count)
    stress_product = kernels["stress_product"]

    stages = np.zeros((7, 2 * count))
    stages[0], stages[1] = np.concatenate([speed, psi_rate]), np.concatenate([speed, psi_rate])
    work, ratios = np.empty(2 * count), np.empty(2 * count)
    rows, weights = np.array([0, 1, 2], dtype=np.int64), np.array([0.3, 0.2, 0.1])  # a stage's mean: three terms
    error_rows, error_weights = np.arange(6, dtype=np.int64), np.full(6, 0.01)
    scale = np.concatenate([fault.critical_slip, np.ones(count)])
    k_x = operator.product_of_padded()
    exponentials_kernel, solve_kernel, stage_kernel, error_kernel = (
        kernels[name] for name in ("exponentials", "solve_elements", "stage", "error_ratios"))
    coefficients, healing = np.empty(count), np.empty(count)
    warm = np.empty((compiled.WARM_ROWS, count))  # the Newton iteration's warm start, as the step keeps it

    # each part repeated inside compiled code, as the step calls it: no Python call in the time
    @numba.njit
    def exponentials(repeats, psi, u, sigma_a, inverse_a, two_v0_eta, aging, f0, inverse_b, coefficients, healing,
                     warm):
        for _ in range(repeats):
            exponentials_kernel(0, psi.shape[0], psi, u, sigma_a, inverse_a, two_v0_eta, aging, f0, inverse_b,
                                coefficients, healing, warm)

    @numba.njit
    def newton(repeats, k_x, initial, stress, psi, u, sigma_a, inverse_a, two_v0_eta, inverse_damping, aging,
               aging_rate, f0, inverse_b, v0, critical_slip, b, speed, psi_rate, iterations, tolerance, coefficients,
               healing, warm):
        for _ in range(repeats):
            solve_kernel(0, psi.shape[0], k_x, initial, True, stress, psi, u, sigma_a, inverse_a, two_v0_eta,
                         inverse_damping, aging, aging_rate, f0, inverse_b, v0, critical_slip, b, speed, psi_rate,
                         iterations, tolerance, coefficients, healing, warm, True)

    @numba.njit
    def stage_and_norm(repeats, work, padded, y, weights, rows, stages, count, plate_rate, time, ratios,
                       error_weights, error_rows, rtol, scale):
        for _ in range(repeats):  # six stages to one error norm a trial step: a sixth of the norm a stage
            stage_kernel(work, padded, y, 1.0, weights, rows, stages, count, plate_rate, time)
            if _ % 6 == 0:
                error_kernel(ratios, y, work, 1.0, error_weights, error_rows, stages, rtol, scale)

    @numba.njit
    def products(repeats, padded, transforms, table, even_product, result):
        for _ in range(repeats):
            stress_product(padded, transforms, table, even_product, result)

    repeats = 402
    exponentials(1, y[count:], balance.u, balance.sigma_a, balance.inverse_a, balance.two_v0_eta, balance.aging,
                 fault.reference_friction, balance.inverse_b, coefficients, healing, warm)
    seconds = {
        "force balance: exponentials and warm start (SIMD)": _alone(lambda: exponentials(
            repeats, y[count:], balance.u, balance.sigma_a, balance.inverse_a, balance.two_v0_eta, balance.aging,
            fault.reference_friction, balance.inverse_b, coefficients, healing, warm)) / repeats,
        "force balance: Newton and rates": _alone(lambda: newton(
            repeats, k_x, fault.initial_shear_stress, stress, y[count:], balance.u, balance.sigma_a, balance.inverse_a,
            balance.two_v0_eta, 1.0 / balance.damping, balance.aging, balance.aging_rate, fault.reference_friction,
            balance.inverse_b, fault.reference_speed, fault.critical_slip, fault.b, speed, psi_rate,
            NEWTON_ITERATIONS, balance.tolerance, coefficients, healing, warm)) / repeats,
        "K x (two halves of its spectrum, summed)": _alone(lambda: products(
            repeats, padded, transforms, halves.table, even_product, product_buffer)) / repeats,
        "stage arithmetic and error norm": _alone(lambda: stage_and_norm(
            repeats, work, operator.padded, y, weights, rows, stages, count, fault.plate_rate, run.final_time, ratios,
            error_weights, error_rows, rtol, scale)) / repeats}
    return {part: value * 1e6 for part, value in seconds.items()}


def profile(elements: int, years: float, rtol: float) -> dict:
    scene = read_fault_2d_scene(ROOT / "configs" / "seas_bp1.toml").at_element_size(WIDTH / elements)
    fault = scene.fault
    run_cycles(fault, 0.01 * JULIAN_YEAR, rtol=rtol)  # compiled (or loaded from numba's cache) before any timing
    with tempfile.TemporaryDirectory() as folder:
        began = time.perf_counter()
        plain = run_cycles(fault, years * JULIAN_YEAR, rtol=rtol, folder=Path(folder) / "plain")
        wall = time.perf_counter() - began
        profiler = cProfile.Profile()
        profiler.enable()
        run_cycles(fault, years * JULIAN_YEAR, rtol=rtol, folder=Path(folder) / "profiled")
        profiler.disable()
    stats = pstats.Stats(profiler)
    split = {"the compiled step": 0.0, "recording": 0.0, "the step's Python": 0.0}
    for (filename, _, function), row in stats.stats.items():
        where = f"{filename}:{function}"
        if "_fused_step" in where or "compiled.py" in where:
            split["the compiled step"] += row[2]  # tottime: each function's own time
        elif any(key in where for key in ("io/seas.py", "io/records.py", "station_row", "profile_row", "_Stations")):
            split["recording"] += row[2]
        else:
            split["the step's Python"] += row[2]
    total = sum(split.values())
    trials = plain.steps + plain.rejected
    step_us = wall * split["the compiled step"] / total / trials * 1e6
    alone = parts_alone(fault, plain, rtol)
    inside = {part: 6 * value for part, value in alone.items()}  # six stages a trial step
    inside["the rest (calls, copies, the largest ratio; what timing the parts alone misses)"] = (
        step_us - sum(inside.values()))
    return {"elements": elements, "years": years, "rtol": rtol, "steps": plain.steps, "trials": trials,
            "wall_s": wall, "per_trial_us": wall / trials * 1e6, "profiled_s": total,
            "shares": {part: seconds / total for part, seconds in split.items()},
            "compiled_step_us": step_us, "inside_the_step_us": inside,
            "inside_shares": {part: value / step_us for part, value in inside.items()}}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[1024, 1600])
    parser.add_argument("--years", type=float, default=300.0)
    parser.add_argument("--rtol", type=float, default=1e-4)
    parser.add_argument("--core", type=int, default=0)
    args = parser.parse_args(argv)
    os.sched_setaffinity(0, {args.core})
    rows = [profile(n, args.years, args.rtol) for n in args.elements]
    for row in rows:
        print(f"{row['elements']} elements: {row['per_trial_us']:.0f} us a trial step ({row['trials']} trials), "
              + ", ".join(f"{part} {share:.0%}" for part, share in row["shares"].items())
              + "; inside the step: " + ", ".join(f"{part} {share:.0%}" for part, share in row["inside_shares"].items()))
    write_results("fault_2d_profile.json", {"runs": rows})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
