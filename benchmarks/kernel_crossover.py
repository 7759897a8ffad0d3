"""Where the 2-D fault's dense stress product stops paying (issue 69: "the dense/FFT switch comes from a measured
crossover, not a constant").

    python benchmarks/kernel_crossover.py [--elements 32 64 ...] [--years 0.5] [--rounds 5]

SEAS BP1 (configs/seas_bp1.toml) at each element count, the first ``--years`` at rtol 1e-4, by ``run_cycles`` on
one thread, on each step path (:data:`faultslip.models.fault_2d.kernel.STEP_PATHS`: the whole step compiled, the
element-wise work compiled, numpy alone; the last two forced by hiding rocket-fft or numba from the run): once with ``kernel="dense"`` and once with ``kernel="fft"``, interleaved over ``--rounds`` rounds with
the order reversed every other round. The figure is CPU time per accepted step (the two kernels take nearly the same
steps; per step removes what round-off changes), the median over rounds. Both paths are compiled (and cached) before
the first timed run. Beside each path's limit it writes the path's step cost relative to the fused path's (the median
over counts, each with the kernel ``auto`` takes), which scales the 2-D cost model. The crossover is the smallest count from which the FFT is faster at every larger count
measured, taken midway (in log N) between the last count where dense wins and it. It is written to
``data/kernel_crossover.json``, which :func:`faultslip.models.fault_2d.kernel.dense_limit` reads, and the timings to
``benchmarks/results/kernel_crossover.json``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from provenance import write_results  # noqa: E402  (one stamp for every results file)
from faultslip.io.resources import write_bundled_table  # noqa: E402
from faultslip.constants import JULIAN_YEAR  # noqa: E402
from faultslip.models.fault_2d import compiled  # noqa: E402
from faultslip.models.fault_2d.integrate import run_cycles, step_path  # noqa: E402
from faultslip.models.fault_2d.kernel import STEP_PATHS, crossover, relative_costs  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402
from provenance import stamp  # noqa: E402

WIDTH = 40e3  # BP1's fault, m (every count below divides it)
COUNTS = (4, 8, 16, 32, 50, 100, 160, 200, 250, 320, 400, 500, 800)
AVAILABLE, FUSED_AVAILABLE = compiled.available, compiled.fused_available


def take_path(path: str) -> None:
    """Make this process's runs take step path ``path`` (the compiled modules look these up at each run)."""
    compiled.available = AVAILABLE if path != "numpy" else (lambda: False)
    compiled.fused_available = FUSED_AVAILABLE if path == "fused" else (lambda: False)
    if step_path() != path:
        raise SystemExit(f"this machine cannot take the {path} path (install faultslip[fast] with rocket-fft)")


def per_step(fault, kernel: str, years: float) -> tuple[float, int]:
    """CPU seconds per accepted step of one run, and its steps."""
    began = time.process_time()
    run = run_cycles(fault, years * JULIAN_YEAR, rtol=1e-4, kernel=kernel, threads=1)
    return (time.process_time() - began) / max(run.steps, 1), run.steps


def measure(scene, count: int, years: float, rounds: int, path: str) -> dict:
    """One element count's row: the median CPU per step of each kernel, interleaved."""
    fault = scene.at_element_size(WIDTH / count).fault
    for kernel in ("dense", "fft"):  # compile and cache both before timing
        run_cycles(fault, 0.01 * JULIAN_YEAR, rtol=1e-4, kernel=kernel, threads=1)
    times, steps = {"dense": [], "fft": []}, {}
    for round_ in range(rounds):
        for kernel in (("dense", "fft") if round_ % 2 == 0 else ("fft", "dense")):
            seconds, steps[kernel] = per_step(fault, kernel, years)
            times[kernel].append(seconds)
    row = {"elements": count, "dense_us": 1e6 * statistics.median(times["dense"]),
           "fft_us": 1e6 * statistics.median(times["fft"]), "dense_steps": steps["dense"], "fft_steps": steps["fft"]}
    row["dense_over_fft"] = row["dense_us"] / row["fft_us"]
    print(f"{path:8s} N = {count:5d}: dense {row['dense_us']:8.1f} us, FFT {row['fft_us']:8.1f} us a step "
          f"(dense/FFT {row['dense_over_fft']:.2f})", flush=True)
    return row


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=list(COUNTS))
    parser.add_argument("--years", type=float, default=0.5)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args(argv)
    scene = read_fault_2d_scene(ROOT / "configs" / "seas_bp1.toml")
    limits, tables = {}, {}
    for path in STEP_PATHS:
        take_path(path)
        rows = [measure(scene, count, args.years, args.rounds, path) for count in args.elements]
        limits[path], tables[path] = int(crossover(rows)), rows
        print(f"{path}: dense at and below {limits[path]} elements", flush=True)
    take_path("fused")
    costs = relative_costs(tables, limits)
    print("step cost against the fused path:", ", ".join(f"{path} {value:.2f}x" for path, value in costs.items()))
    table = {"dense_limit": limits, "relative_step_cost": costs, "rows": tables, "method": " ".join(__doc__.split("\n\n")[2].split()),
             "provenance": {"script": "benchmarks/kernel_crossover.py", "years": args.years, "rounds": args.rounds,
                            **stamp()}}
    write_bundled_table(ROOT / "data" / "kernel_crossover.json", table)
    write_results("kernel_crossover.json", {"dense_limit": limits, "rows": tables, "years": args.years,
                                            "rounds": args.rounds})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
