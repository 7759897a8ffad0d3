"""A 2-D run on one core and on two (issue 43, item 3: ">= 1.6x from one to two cores at 1600 elements or more").

    python benchmarks/fault_2d_threads.py [--elements 1024 1600 3200] [--years 200] [--rounds 3]

SEAS BP1 (configs/seas_bp1.toml) at each element count over ``--years`` at rtol 1e-4 (faultslip's loosest
tolerance within 0.1 % of its converged recurrence). Each run is ``run_cycles`` in this process: once with
``threads=1`` pinned to one core, once with ``threads=2`` pinned to two, interleaved over ``--rounds`` rounds
with the order reversed every other round, medians kept. The baseline is the same run, the same steps and the
same bits (checked here: the final slip and state of every pair are identical), on one thread. The numba kernels
are compiled (and cached) before the first timed run. Writes benchmarks/results/fault_2d_threads.json.

Beside each pair it times the round trip between the two cores: two threads passing a spin barrier back and forth
(the threaded step's own atomics). On a virtual machine it depends on where the host puts the two vCPUs, near each
other or far apart, which changes over minutes (0.07 us and 0.4 us were both seen on the benchmark machine), and a
threaded step is slower where they are far apart; each run's figure is recorded, and the medians are given for
the rounds taken near and far apart as well as for all.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from fault_2d_profile import write_results  # noqa: E402  (one way to write a result, with the machine and date)
from faultslip.constants import JULIAN_YEAR  # noqa: E402
from faultslip.models.fault_2d.integrate import run_cycles  # noqa: E402
from faultslip.models.fault_2d.scene import load_fault_2d_scene  # noqa: E402

WIDTH = 40e3


def _round_trip_kernel():
    """A compiled loop of two tasks passing the threaded step's spin barrier ``repeats`` times."""
    import numba  # heavy: the benchmark measures the compiled path
    from numba import prange

    from faultslip.models.fault_2d import compiled

    atomic_add, atomic_load = compiled._atomic_intrinsics()

    @numba.njit(parallel=True)
    def passes(sync, repeats):
        for task in prange(2):
            for _ in range(repeats):
                generation = atomic_load(sync, compiled.GENERATION)
                if atomic_add(sync, compiled.ARRIVALS, 1) == 1:
                    atomic_add(sync, compiled.ARRIVALS, -2)
                    atomic_add(sync, compiled.GENERATION, 1)
                else:
                    while atomic_load(sync, compiled.GENERATION) == generation:
                        pass
    return passes


def round_trip_us(passes) -> float:
    """The two cores' barrier round trip now (us), the best of three timings of 20,000 passes."""
    import numba  # heavy: as above

    from faultslip.models.fault_2d import compiled

    os.sched_setaffinity(0, {0, 1})
    numba.set_num_threads(2)
    sync = compiled.new_sync()
    passes(sync, 10)
    best = float("inf")
    for _ in range(3):
        began = time.perf_counter()
        passes(sync, 20_000)
        best = min(best, (time.perf_counter() - began) / 20_000 * 1e6)
    return best


#: round trips above this (us) count as the cores far apart
FAR = 0.2


def timed(fault, years: float, threads: int) -> dict:
    os.sched_setaffinity(0, set(range(threads)))
    began, cpu = time.perf_counter(), time.process_time()
    run = run_cycles(fault, years * JULIAN_YEAR, rtol=1e-4, threads=threads)
    return {"wall_s": time.perf_counter() - began, "cpu_s": time.process_time() - cpu, "steps": run.steps,
            "bits": (run.final_slip.tobytes() + run.final_state.tobytes()).hex()[:64]}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[1024, 1600, 3200])
    parser.add_argument("--years", type=float, default=200.0)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
    if (os.cpu_count() or 1) < 2:
        raise SystemExit("this benchmark needs two cores")
    rows = []
    import numba  # heavy: the benchmark measures the compiled path

    # numba's threads start at its first parallel call and keep the CPUs the process had then: started while this
    # process is pinned to one core (a one-thread run first), both would share it, and two threads gain nothing
    os.sched_setaffinity(0, {0, 1})
    numba.get_num_threads()
    passes = _round_trip_kernel()
    for elements in args.elements:
        fault = load_fault_2d_scene(ROOT / "configs" / "seas_bp1.toml").at_element_size(WIDTH / elements).fault
        for threads in (1, 2):  # compile and load both builds before timing
            run_cycles(fault, 0.01 * JULIAN_YEAR, rtol=1e-4, threads=threads)
        runs = {1: [], 2: []}
        for round_ in range(args.rounds):
            for threads in ((1, 2) if round_ % 2 == 0 else (2, 1)):
                before = round_trip_us(passes)
                runs[threads].append(timed(fault, args.years, threads))
                runs[threads][-1]["round_trip_us"] = max(before, round_trip_us(passes))
        same = len({row["bits"] for rows_ in runs.values() for row in rows_}) == 1
        medians = {threads: {key: statistics.median(row[key] for row in rows_) for key in ("wall_s", "cpu_s")}
                   for threads, rows_ in runs.items()}
        one_thread = medians[1]["wall_s"]
        two = runs[2]
        near = [row["wall_s"] for row in two if row["round_trip_us"] <= FAR]
        far = [row["wall_s"] for row in two if row["round_trip_us"] > FAR]
        row = {"elements": elements, "years": args.years, "steps": runs[1][0]["steps"], "identical_bits": same,
               "one_thread": medians[1], "two_threads": medians[2],
               "speedup": one_thread / medians[2]["wall_s"], "target": 1.6,
               "round_trips_us": [round(row["round_trip_us"], 3) for row in two],
               "speedup_near": one_thread / statistics.median(near) if near else None, "rounds_near": len(near),
               "speedup_far": one_thread / statistics.median(far) if far else None, "rounds_far": len(far)}
        rows.append(row)
        split = ", ".join(f"{name} {row['speedup_' + name]:.2f}x ({row['rounds_' + name]} rounds)"
                          for name in ("near", "far") if row["rounds_" + name])
        print(f"{elements} elements, {row['steps']} steps: one thread {one_thread:.2f} s, two "
              f"{medians[2]['wall_s']:.2f} s -> {row['speedup']:.2f}x (target 1.6; cores {split}); the same "
              f"bits: {same}", flush=True)
    write_results("fault_2d_threads.json", {"runs": rows, "rounds": args.rounds, "rtol": 1e-4})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
