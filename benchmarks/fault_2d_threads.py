"""A 2-D run on one core and on two (issue 43, item 3: ">= 1.6x from one to two cores at 1600 elements or more").

    python benchmarks/fault_2d_threads.py [--elements 1600 3200 6400 12800] [--years 200] [--rounds 3] [--pairs 8]

SEAS BP1 (configs/seas_bp1.toml) at each element count over ``--years`` at rtol 1e-4 (faultslip's loosest
tolerance within 0.1 % of its converged recurrence). Each run is ``run_cycles`` in this process: once with
``threads=1`` pinned to one core, once with ``threads=2`` pinned to two, interleaved over ``--rounds`` rounds
with the order reversed every other round, medians kept. The baseline is the same run, the same steps and the
same bits (checked here: the final slip and state of every pair are identical), on one thread. The numba kernels
are compiled (and cached) before the first timed run. Writes benchmarks/results/fault_2d_threads.json.

Beside each pair it times the round trip between the two cores: two threads passing a spin barrier back and forth
(the threaded step's own atomics). On a virtual machine it depends on where the host puts the two vCPUs, and on
the benchmark machine that changes within a second: below 0.06 us (one physical core's two hardware threads, it
seems: two threads gain nothing there), 0.06-0.2 us (near: two cores sharing a cache) or above 0.2 us (far). A
whole run spans many such changes, so beside the runs it measures:
- the placement: the round trip every 50 ms over ``--placement`` seconds, the share of the time in each class and
  how long a class lasts;
- trial steps in each class: batches of 100 trial steps of BP1 a year in, through a run's compiled loop (from the
  same state each time, its Newton warm start reset), on one thread pinned to one core and on two, interleaved
  for ``--batches`` seconds a count, each pair kept in the class its round trips before and after agree on;
- short whole runs in pairs (``--pairs`` pairs over ``--pair-years``, one thread then two or the other way, in
  turn): the gain of each pair and their median. A short run is less likely to span a change of placement than a
  long one, and a pair's ratio cancels the host's slower drifts of pace.
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

from provenance import write_results  # noqa: E402  (one stamp for every results file)
from faultslip.constants import JULIAN_YEAR  # noqa: E402
from faultslip.models.fault_2d.integrate import run_cycles  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402

WIDTH = 40e3


def spin_barrier():
    """A compiled spin barrier of two tasks on a ``sync`` array (:func:`compiled.new_sync`), with the threaded
    step's atomics."""
    import numba  # heavy: the benchmark measures the compiled path

    from faultslip.models.fault_2d import compiled

    atomic_add, atomic_load, _ = compiled._atomic_intrinsics()
    arrivals, generations = 0, compiled.LINE  # a counter a cache line, as the step's barrier word has its own

    @numba.njit
    def barrier(sync):
        generation = atomic_load(sync, generations)
        if atomic_add(sync, arrivals, 1) == 1:
            atomic_add(sync, arrivals, -2)
            atomic_add(sync, generations, 1)
        else:
            while atomic_load(sync, generations) == generation:
                pass
    return barrier


def _round_trip_kernel():
    """A compiled loop of two tasks passing the threaded step's spin barrier ``repeats`` times."""
    import numba  # heavy: the benchmark measures the compiled path
    from numba import prange

    barrier = spin_barrier()

    @numba.njit(parallel=True)
    def passes(sync, repeats):
        for task in prange(2):
            for _ in range(repeats):
                barrier(sync)
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


#: round trips (us) below which the vCPUs count as one core's two hardware threads, and above which as far apart
SHARED, FAR = 0.06, 0.2
CLASSES = ("shared core", "near", "far")


def placement(round_trip: float) -> str:
    """The class of the two vCPUs' placement a round trip (us) shows."""
    return CLASSES[0] if round_trip < SHARED else CLASSES[1] if round_trip <= FAR else CLASSES[2]


def placement_series(passes, seconds: float) -> dict:
    """The round trip every 50 ms for ``seconds``: the share of the time in each class, and the median length (s)
    of a stretch in one class."""
    classes, stamps = [], []
    ends = time.perf_counter() + seconds
    while time.perf_counter() < ends:
        classes.append(placement(round_trip_us(passes)))
        stamps.append(time.perf_counter())
        time.sleep(0.05)
    stretches, began = [], stamps[0]
    for i in range(1, len(classes)):
        if classes[i] != classes[i - 1]:
            stretches.append(stamps[i] - began)
            began = stamps[i]
    stretches.append(stamps[-1] - began)
    return {"samples": len(classes), "share": {name: classes.count(name) / len(classes) for name in CLASSES},
            "median_stretch_s": statistics.median(stretches)}


def trial_batches(fault, passes, seconds: float) -> dict:
    """Batches of 100 trial steps through a run's compiled loop (``run_steps``, in one parallel region on two
    threads), from BP1 a year in (the same state, its Newton warm start reset, each time; no event, profile or
    record to return for), on one thread pinned to one core and on two, interleaved for ``seconds``; the median
    batch's time a trial (us) and the gain in each placement class."""
    import numpy as np

    from faultslip.models.fault_2d import compiled, integrate
    from faultslip.models.fault_2d.kernel import StressKernel
    from faultslip.models.fault_2d.model import ForceBalance, newton_tolerance

    run = run_cycles(fault, JULIAN_YEAR, rtol=1e-4, threads=1)
    count = fault.count
    y = np.concatenate([run.final_slip, run.final_state])
    h = float(np.diff(run.station_time)[-1])
    operator = StressKernel(count, fault.element_size, fault.shear_modulus)
    balance = ForceBalance(fault, operator)
    balance.tolerance = newton_tolerance(1e-4)
    speed, rate, _ = balance.rates(run.final_time, y[:count], y[count:])
    k1, start = np.concatenate([speed, rate]), balance.u.copy()
    scale = np.concatenate([fault.critical_slip, np.ones(count)])
    never = 1e300  # no run's end, event or profile within a batch: its trials are all the loop does
    settings = {"duration": never, "rtol": 1e-4, "memory_weight": integrate.step_memory(1e-4),
                "event_speed": never, "profile_interval": never, "coseismic_interval": never}
    loops = {threads: integrate._CompiledSteps(integrate._FusedTrial(fault, operator, balance, scale, 1e-4, threads),
                                               np.array([0, count // 2]), settings) for threads in (1, 2)}
    results = {}

    def batch(threads):
        os.sched_setaffinity(0, set(range(threads)))
        loop = loops[threads]
        balance.u[:] = start
        loop.states[0], loop.trial.stages[0] = y, k1
        loop.clock[:] = (run.final_time, h, 1e-4, 0.0, h, h, speed.max(), speed.max(), 0.0, run.final_time,
                         run.final_time, run.final_time)
        loop.counters[:] = 0
        loop.counters[[compiled.STOP_AT, compiled.MAX_STEPS]] = (-1, 10**9)
        loop.settings[compiled.INSIDE] = 0.0
        began = time.perf_counter()
        loop(100)
        elapsed = time.perf_counter() - began
        trials = int(loop.counters[compiled.STEPS] + loop.counters[compiled.REJECTED])
        results[threads] = loop.states[int(loop.counters[compiled.CURRENT])].tobytes()
        return elapsed / trials * 1e6

    for threads in (1, 2):
        batch(threads)
    pairs = {name: [] for name in CLASSES}
    ends = time.perf_counter() + seconds
    while time.perf_counter() < ends:
        before = placement(round_trip_us(passes))
        pair = (batch(1), batch(2))
        if placement(round_trip_us(passes)) == before:
            pairs[before].append(pair)
    same = results[1] == results[2]
    return {"identical_bits": same, **{name: {
        "pairs": len(rows), "one_thread_us": statistics.median(one for one, _ in rows) if rows else None,
        "two_threads_us": statistics.median(two for _, two in rows) if rows else None,
        "speedup": statistics.median(one / two for one, two in rows) if rows else None}
        for name, rows in pairs.items()}}


def run_pairs(fault, passes, years: float, pairs: int) -> dict:
    """``pairs`` interleaved pairs of whole runs over ``years`` on one thread and on two: each pair's gain, their
    median, and the placement class each pair's round trips before and after agree on (None where they differ)."""
    rows = []
    for pair in range(pairs):
        before = placement(round_trip_us(passes))
        times = {}
        for threads in ((1, 2) if pair % 2 == 0 else (2, 1)):
            times[threads] = timed(fault, years, threads)
        after = placement(round_trip_us(passes))
        rows.append({"one_thread_s": times[1]["wall_s"], "two_threads_s": times[2]["wall_s"],
                     "gain": times[1]["wall_s"] / times[2]["wall_s"], "placement": before if before == after else None,
                     "identical_bits": times[1]["bits"] == times[2]["bits"]})
    gains = [row["gain"] for row in rows]
    near = [row["gain"] for row in rows if row["placement"] == "near"]
    return {"years": years, "pairs": rows, "median_gain": statistics.median(gains),
            "near_median_gain": statistics.median(near) if near else None, "near_pairs": len(near),
            "pairs_at_or_above_1_6": sum(gain >= 1.6 for gain in gains),
            "identical_bits": all(row["identical_bits"] for row in rows)}


def timed(fault, years: float, threads: int) -> dict:
    os.sched_setaffinity(0, set(range(threads)))
    began, cpu = time.perf_counter(), time.process_time()
    run = run_cycles(fault, years * JULIAN_YEAR, rtol=1e-4, threads=threads)
    return {"wall_s": time.perf_counter() - began, "cpu_s": time.process_time() - cpu, "steps": run.steps,
            "bits": (run.final_slip.tobytes() + run.final_state.tobytes()).hex()[:64]}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, nargs="+", default=[1600, 3200, 6400, 12800])  # the target's range
    parser.add_argument("--years", type=float, default=200.0)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--placement", type=float, default=60.0, help="seconds of round trips")
    parser.add_argument("--batches", type=float, default=60.0, help="seconds of trial-step batches a count")
    parser.add_argument("--pairs", type=int, default=8, help="pairs of short whole runs a count")
    parser.add_argument("--pair-years", type=float, default=60.0, help="the span of each short whole run")
    args = parser.parse_args(argv)
    if (os.cpu_count() or 1) < 2:
        raise SystemExit("this benchmark needs two cores")
    rows = []
    started = time.strftime("%H:%M", time.gmtime())
    import numba  # heavy: the benchmark measures the compiled path

    # numba's threads start at its first parallel call and keep the CPUs the process had then: started while this
    # process is pinned to one core (a one-thread run first), both would share it, and two threads gain nothing
    os.sched_setaffinity(0, {0, 1})
    numba.get_num_threads()
    passes = _round_trip_kernel()
    where = placement_series(passes, args.placement)
    print("placement: " + ", ".join(f"{name} {share:.0%}" for name, share in where["share"].items())
          + f" of {where['samples']} round trips; a stretch lasts {where['median_stretch_s']:.2f} s (median)",
          flush=True)
    for elements in args.elements:
        fault = read_fault_2d_scene(ROOT / "configs" / "seas_bp1.toml").at_element_size(WIDTH / elements).fault
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
        steps = trial_batches(fault, passes, args.batches)
        short = run_pairs(fault, passes, args.pair_years, args.pairs) if args.pairs else None
        row = {"elements": elements, "years": args.years, "steps": runs[1][0]["steps"],
               "identical_bits": same and steps["identical_bits"], "one_thread": medians[1],
               "two_threads": medians[2], "speedup": one_thread / medians[2]["wall_s"], "target": 1.6,
               "round_trips_us": [round(row["round_trip_us"], 3) for row in runs[2]], "trial_steps": steps,
               "short_runs": short}
        rows.append(row)
        classes = "; ".join(f"{name} {steps[name]['speedup']:.2f}x ({steps[name]['one_thread_us']:.0f} against "
                            f"{steps[name]['two_threads_us']:.0f} us, {steps[name]['pairs']} pairs)"
                            for name in CLASSES if steps[name]["pairs"])
        print(f"{elements} elements, {row['steps']} steps: one thread {one_thread:.2f} s, two "
              f"{medians[2]['wall_s']:.2f} s -> {row['speedup']:.2f}x (target 1.6); trial steps: {classes}; the "
              f"same bits: {row['identical_bits']}", flush=True)
        if short:
            near = (f"{short['near_median_gain']:.2f}x in the {short['near_pairs']} near throughout"
                    if short["near_pairs"] else "none near throughout")
            print(f"  {args.pairs} pairs of {args.pair_years:g}-yr runs: median gain {short['median_gain']:.2f}x ({near}), "
                  f"{short['pairs_at_or_above_1_6']} of {args.pairs} at 1.6x or more; each: "
                  + ", ".join(f"{pair['gain']:.2f}x ({pair['placement'] or 'changed'})" for pair in short["pairs"])
                  + f"; the same bits: {short['identical_bits']}", flush=True)
    write_results("fault_2d_threads.json", {"runs": rows, "rounds": args.rounds, "rtol": 1e-4, "placement": where,
                                            "started": started, "ended": time.strftime("%H:%M", time.gmtime())})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
