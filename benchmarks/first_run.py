"""The first compiled run's cost: cold (numba compiles, into an empty cache) against warm (it loads the cache).

    python benchmarks/first_run.py [--rounds 3]

Each command runs as a whole process, ``faultslip ... --json``, with NUMBA_CACHE_DIR pointing at a folder of its
round: empty for the cold run, then the same folder for the warm one; rounds alternate which command goes first.
The figure is the median over rounds of cold / warm wall time (and CPU time of the child, from its rusage). The
commands: the small 2-D fault (its whole step compiled, with rocket-fft) and a rate-and-state fit (the lab
integrator and the likelihood). Writes benchmarks/results/first_run.json; docs/benchmarks.md's table is written
from it by benchmarks/readme.py.

    python benchmarks/first_run.py --part first-run [--rounds 3]

**The first 2-D run's own cost** (``first_run`` in the file), what a run's estimate adds where its process does not
hold the compiled step yet (faultslip.models.fault_2d.cost.FAULT_2D_FIRST_RUN_SECONDS): in a fresh process, the
estimate a run's budget check makes (which tells loading from compiling), then the same short run twice
(``simulate_fault``); the first run's CPU less the second's. Per step path (the small antiplane fault with its FFT
kernel, the whole step fused; with its dense kernel, the force balance and stages compiled, which a dipping fault's
and a 3-D fault's steps load a part of, on one thread) and build (one thread, or two), with numba's cache empty
("compile") and then filled ("load"). ``--part commands`` runs only the whole-command figures; either part keeps the
other's rows from the file.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

from provenance import write_results  # noqa: E402  (one stamp for every results file)

COMMANDS = {
    "2-D fault (configs/fault_2d_small.toml)": ["run", "configs/fault_2d_small.toml", "--json"],
    "rate-and-state fit (configs/example_velocity_steps.csv)":
        ["fit", "--law", "rate-state", "configs/example_velocity_steps.csv", "--stiffness", "1e-2 1/um", "--json"],
}


def timed(arguments: list, cache: str) -> tuple[float, float]:
    """Wall and child CPU seconds of ``faultslip ARGUMENTS`` with numba's cache in ``cache``."""
    environment = {**os.environ, "NUMBA_CACHE_DIR": cache}
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    began = time.perf_counter()
    subprocess.run([sys.executable, "-m", "faultslip.cli", *arguments], cwd=ROOT, env=environment, check=True,
                   capture_output=True)
    wall = time.perf_counter() - began
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


#: the first-run cases: step path and build -> (scene, threads, kernel): the small antiplane fault with its FFT
#: kernel (the whole step fused) or its dense one (the force balance and stages compiled, a step in Python)
FIRST_RUN_CASES = {"fused serial": ("configs/fault_2d_small.toml", 1, "fft"),
                   "fused parallel": ("configs/fault_2d_small.toml", 2, "fft"),
                   "compiled serial": ("configs/fault_2d_small.toml", 1, "dense"),
                   "compiled parallel": ("configs/fault_2d_small.toml", 2, "dense")}
#: the run: the scene's first 1/2000 of its duration (a few dozen steps: the first-run cost dominates it)
CHILD = """
import json, sys, time
from dataclasses import replace
from faultslip.models.fault_2d.scene import read_fault_2d_scene
from faultslip.models.fault_2d.family import simulate_fault
scene = read_fault_2d_scene(sys.argv[1])
scene = replace(scene, duration=scene.duration / 2000, threads=int(sys.argv[2]), kernel=sys.argv[3])
_, why = scene.first_run_cost()  # as the run's budget check makes it, before its clock starts
times = []
for _ in range(2):
    started = time.process_time()
    simulate_fault(scene)
    times.append(time.process_time() - started)
print(json.dumps({"first": times[0], "second": times[1], "compiled_here": why.startswith("to compile")}))
"""


def first_run(scene: str, threads: int, kernel: str, cache: str) -> dict:
    """The first and second runs' CPU seconds of ``scene`` on ``threads`` threads with its ``kernel`` in a fresh
    process whose numba cache is ``cache``, and whether the estimate said it would compile."""
    environment = {**os.environ, "NUMBA_CACHE_DIR": cache}
    done = subprocess.run([sys.executable, "-c", CHILD, scene, str(threads), kernel], cwd=ROOT, env=environment, check=True,
                          capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def first_run_rows(rounds: int) -> list[dict]:
    """Per case of :data:`FIRST_RUN_CASES`: the median over ``rounds`` of the first run's CPU less the second's,
    cold (an empty cache: the estimate must say it compiles) and warm (the cache just filled: it must not)."""
    samples = {case: {"compile": [], "load": []} for case in FIRST_RUN_CASES}
    for round_ in range(rounds):
        order = list(FIRST_RUN_CASES) if round_ % 2 == 0 else list(reversed(FIRST_RUN_CASES))
        for case in order:
            with tempfile.TemporaryDirectory() as cache:
                for state in ("compile", "load"):
                    measured = first_run(*FIRST_RUN_CASES[case], cache)
                    if measured["compiled_here"] != (state == "compile"):
                        raise SystemExit(f"{case}: the estimate said {'compile' if measured['compiled_here'] else 'load'} "
                                         f"where the cache was {'empty' if state == 'compile' else 'filled'}")
                    samples[case][state].append(measured["first"] - measured["second"])
            print(f"{case}: compile {samples[case]['compile'][-1]:.2f} s, load {samples[case]['load'][-1]:.2f} s",
                  flush=True)
    return [{"case": case, "scene": FIRST_RUN_CASES[case][0], "threads": FIRST_RUN_CASES[case][1],
             "kernel": FIRST_RUN_CASES[case][2],
             **{state: statistics.median(values) for state, values in samples[case].items()},
             **{f"{state}_samples": values for state, values in samples[case].items()}} for case in FIRST_RUN_CASES]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--part", choices=("all", "commands", "first-run"), default="all")
    args = parser.parse_args(argv)
    path = ROOT / "benchmarks" / "results" / "first_run.json"
    kept = json.loads(path.read_text(encoding="utf-8")) if path.exists() else {}
    if args.part == "first-run":
        write_results("first_run.json", {key: kept[key] for key in ("rounds", "rows") if key in kept}
                      | {"first_run": {"rounds": args.rounds, "rows": first_run_rows(args.rounds)}})
        return 0
    samples = {name: {"cold_wall": [], "warm_wall": [], "cold_cpu": [], "warm_cpu": []} for name in COMMANDS}
    for round_ in range(args.rounds):
        order = list(COMMANDS) if round_ % 2 == 0 else list(reversed(COMMANDS))
        for name in order:
            with tempfile.TemporaryDirectory() as cache:
                for state in ("cold", "warm"):
                    wall, cpu = timed(COMMANDS[name], cache)
                    samples[name][f"{state}_wall"].append(wall)
                    samples[name][f"{state}_cpu"].append(cpu)
            print(f"{name}: cold {samples[name]['cold_wall'][-1]:.1f} s, warm {samples[name]['warm_wall'][-1]:.1f} s",
                  flush=True)
    rows = []
    for name, values in samples.items():
        row = {"command": name, "arguments": COMMANDS[name]}
        for key, series in values.items():
            row[key] = statistics.median(series)
        row["ratio_wall"] = statistics.median(c / w for c, w in zip(values["cold_wall"], values["warm_wall"]))
        row["ratio_cpu"] = statistics.median(c / w for c, w in zip(values["cold_cpu"], values["warm_cpu"]))
        rows.append(row)
    document = {"rounds": args.rounds, "rows": rows}
    if args.part == "all":
        document["first_run"] = {"rounds": args.rounds, "rows": first_run_rows(args.rounds)}
    elif "first_run" in kept:
        document["first_run"] = kept["first_run"]
    write_results("first_run.json", document)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
