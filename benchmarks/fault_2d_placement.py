"""What the placement of the two vCPUs costs a threaded 2-D step (issue 43, item 3), in each placement class.

    python benchmarks/fault_2d_placement.py [--seconds 120] [--lines 100] [--elements 1600]

On the benchmark machine two threads gain about 1.65x near and 1.1x far (benchmarks/fault_2d_threads.py). This
asks why, with three measurements taken in turn and each kept in the class its round trips before and after agree
on (:func:`fault_2d_threads.placement`):

- **private work**: a loop of exponentials over 512 KB (in a core's own cache) on one core, alone and then with
  the other core running the same loop over its own array: the slowdown. 1.0 means the cores do not share a
  pipeline, a clock budget or a cache that either of them fills.
- **work between barriers**: each task runs the same loop over its own ``CHUNK_VALUES`` values (a task's
  elements at 1,600), a spin barrier after each pass as the threaded step has between its phases, against the
  same passes with no barrier; the cycle counter times the loop alone. The ratio is what the meetings do to the
  work itself (1.0: nothing), and the difference in wall time a pass is what a meeting costs (us).
- **data that crosses**: two tasks in one parallel region, each writing its own block of ``--lines`` cache lines
  (the threaded step's slip deficit at 1,600 elements is 100 lines a task) and then, past a spin barrier,
  reading the other task's block; against the same loop reading its own block. The difference over the lines
  read is what a line that crosses between the two cores costs (ns), written by one and read by the other, as
  the step's slip deficit and K x's halves are each stage.

From these, what the lines a trial step moves cost at ``--elements``: each of a trial's six evaluations of K x has
each task read the other's half of the slip deficit (N / 2 values) and the other's half of K x for its own
elements (N / 2 values), so a task reads 6 N / 8 lines that the other core wrote, a trial.

Writes benchmarks/results/fault_2d_placement.json.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import numpy as np  # noqa: E402

from provenance import write_results  # noqa: E402  (one stamp for every results file)
from fault_2d_threads import CLASSES, _round_trip_kernel, placement, round_trip_us, spin_barrier  # noqa: E402

#: float64s a cache line
LINE = 8
#: the private loop's array: 512 KB, in a core's own L2 cache
PRIVATE_VALUES = 65536
#: evaluations of K x a Dormand-Prince trial step (k1 is the last step's k7)
EVALUATIONS = 6
#: the values each task's loop passes over between two barriers: a task's elements at 1,600
CHUNK_VALUES = 800


def lines_a_trial(elements: int) -> int:
    """Cache lines a task reads that the other core wrote, a trial step of ``elements`` elements split in two:
    each evaluation, the other half of the slip deficit and of K x (N / 2 float64s each)."""
    return EVALUATIONS * 2 * (elements // 2) // LINE


def _kernels():
    """The compiled loops: the private sweep (nogil, for a Python thread a core), the two tasks' crossing and their
    work between barriers."""
    import numba  # heavy: the benchmark measures compiled code
    from numba import prange

    from faultslip.models.fault_2d import compiled

    barrier = spin_barrier()
    cycles = compiled._cycle_counter_intrinsic()  # the threaded step's own counter (0 where there is none)

    @numba.njit(nogil=True)
    def sweep(values, repeats):
        total = 0.0
        for _ in range(repeats):
            for i in range(values.shape[0]):
                value = values[i]
                total += np.exp(value * 1e-3)
                values[i] = value * 0.999999 + 1e-9
        return total

    @numba.njit
    def task_exchange(task, sync, blocks, repeats, cross):
        read = 1 - task if cross else task
        total = 0.0
        for _ in range(repeats):
            for i in range(blocks.shape[1]):
                blocks[task, i] = blocks[task, i] + 1.0
            barrier(sync)
            for i in range(blocks.shape[1]):
                total += blocks[read, i]
            barrier(sync)
        return total

    @numba.njit(parallel=True)
    def exchange(sync, blocks, repeats, cross):
        # each task writes its own block, then (past the barrier) reads the other's block, or its own
        totals = np.zeros(2)
        for task in prange(2):
            totals[task] = task_exchange(np.int64(task), sync, blocks, repeats, cross)  # prange gives uint64
        return totals[0] + totals[1]

    @numba.njit
    def task_chunks(task, sync, values, repeats, meet):
        worked = 0
        for _ in range(repeats):
            began = cycles()
            for i in range(values.shape[1]):
                value = values[task, i]
                values[task, i] = value * 0.999999 + 1e-9 * np.exp(value * 1e-3)
            worked += cycles() - began
            if meet:
                barrier(sync)
        return worked

    @numba.njit(parallel=True)
    def chunks(sync, values, repeats, meet):
        # each task passes over its own values; with ``meet``, both pass a spin barrier after each pass
        worked = np.zeros(2, dtype=np.int64)
        for task in prange(2):
            worked[task] = task_chunks(np.int64(task), sync, values, repeats, meet)  # prange gives uint64
        return worked[0] + worked[1]

    return sweep, exchange, chunks


def private_slowdown(sweep, arrays) -> float:
    """The private loop's time on core 0 with core 1 running its own, over its time alone."""
    repeats = 20_000_000 // PRIVATE_VALUES

    def pinned(core, values, repeats_, out):
        os.sched_setaffinity(0, {core})
        began = time.perf_counter()
        sweep(values, repeats_)
        out.append(time.perf_counter() - began)

    alone = []
    worker = threading.Thread(target=pinned, args=(0, arrays[0], repeats, alone))
    worker.start()
    worker.join()
    first, second = [], []
    workers = [threading.Thread(target=pinned, args=(1, arrays[1], repeats + repeats // 5, second)),
               threading.Thread(target=pinned, args=(0, arrays[0], repeats, first))]
    for worker in workers:  # the other core starts first and ends later: core 0's loop runs beside it throughout
        worker.start()
    for worker in workers:
        worker.join()
    return first[0] / alone[0]


def crossing_ns(exchange, lines: int, repeats: int = 2000) -> float:
    """What a cache line written by one core and read by the other costs (ns): the exchange reading the other
    task's block, less the same reading its own, over the lines read (both tasks' blocks a repeat)."""
    from faultslip.models.fault_2d import compiled

    os.sched_setaffinity(0, {0, 1})
    sync, blocks = compiled.new_sync(), compiled.on_lines((2, lines * LINE))
    times = {}
    for cross in (True, False):
        exchange(sync, blocks, 10, cross)
        began = time.perf_counter()
        exchange(sync, blocks, repeats, cross)
        times[cross] = time.perf_counter() - began
    return (times[True] - times[False]) / (repeats * lines) * 1e9  # each task reads ``lines`` lines a repeat


def meeting_costs(chunks, repeats: int = 2000) -> tuple[float | None, float]:
    """Both tasks' passes over their own values with a barrier after each, against the same with none: the work's
    cycles with over without (None where there is no cycle counter), and what a meeting adds to a pass (us)."""
    from faultslip.models.fault_2d import compiled

    os.sched_setaffinity(0, {0, 1})
    sync, values = compiled.new_sync(), compiled.on_lines((2, CHUNK_VALUES))
    values[...] = np.random.default_rng(3).random(values.shape)
    worked, wall = {}, {}
    for meet in (True, False):
        chunks(sync, values, 10, meet)
        began = time.perf_counter()
        worked[meet] = chunks(sync, values, repeats, meet)
        wall[meet] = time.perf_counter() - began
    ratio = worked[True] / worked[False] if worked[False] > 0 else None
    return ratio, (wall[True] - wall[False]) / repeats * 1e6


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=120.0)
    parser.add_argument("--lines", type=int, default=100, help="cache lines each task writes and the other reads")
    parser.add_argument("--elements", type=int, default=1600, help="the trial step whose crossing lines are costed")
    args = parser.parse_args(argv)
    if (os.cpu_count() or 1) < 2:
        raise SystemExit("this benchmark needs two cores")
    if not 1 <= args.lines <= 1_000_000:
        parser.error("--lines must be from 1 to 1,000,000")  # one sentence, exit 2
    if not 16 <= args.elements <= 10_000_000:
        parser.error("--elements must be from 16 to 10,000,000")
    if not 0 < args.seconds <= 86_400:
        parser.error("--seconds must be above 0 and at most a day")
    import numba  # heavy: as above

    os.sched_setaffinity(0, {0, 1})  # numba's threads keep the CPUs the process had at its first parallel call
    numba.get_num_threads()
    passes = _round_trip_kernel()
    sweep, exchange, chunks = _kernels()
    arrays = [np.random.default_rng(seed).random(PRIVATE_VALUES) for seed in (1, 2)]
    sweep(arrays[0], 1)
    crossing_ns(exchange, args.lines, 10)
    meeting_costs(chunks, 10)
    started = time.strftime("%H:%M", time.gmtime())
    kept = {name: [] for name in CLASSES}
    ends = time.perf_counter() + args.seconds
    while time.perf_counter() < ends:
        before = placement(round_trip_us(passes))
        row = (private_slowdown(sweep, arrays), crossing_ns(exchange, args.lines), *meeting_costs(chunks))
        if placement(round_trip_us(passes)) == before:
            kept[before].append(row)
    classes = {name: {"rounds": len(rows),
                      "private_slowdown": statistics.median(row[0] for row in rows) if rows else None,
                      "crossing_ns_per_line": statistics.median(row[1] for row in rows) if rows else None,
                      "work_between_barriers": statistics.median(row[2] for row in rows)
                      if rows and rows[0][2] is not None else None,
                      "barrier_us": statistics.median(row[3] for row in rows) if rows else None}
               for name, rows in kept.items()}
    lines = lines_a_trial(args.elements)
    for name, row in classes.items():
        if row["rounds"]:
            row["trial_crossing_us"] = lines * row["crossing_ns_per_line"] / 1e3
            print(f"{name}: {row['rounds']} rounds; private work {row['private_slowdown']:.3f}x slower with the "
                  f"other core busy; a line crossing between the cores {row['crossing_ns_per_line']:.1f} ns, "
                  f"{row['trial_crossing_us']:.0f} us for a task's {lines:,} a trial at {args.elements:,} elements; "
                  f"work between barriers {row['work_between_barriers'] or float('nan'):.3f}x, a meeting "
                  f"{row['barrier_us']:.2f} us")
    write_results("fault_2d_placement.json", {"lines": args.lines, "private_values": PRIVATE_VALUES,
                                              "chunk_values": CHUNK_VALUES,
                                              "elements": args.elements, "trial_lines": lines,
                                              "classes": classes, "started": started,
                                              "ended": time.strftime("%H:%M", time.gmtime())})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
