"""The first compiled run's cost: cold (numba compiles, into an empty cache) against warm (it loads the cache).

    python benchmarks/first_run.py [--rounds 3]

Each command runs as a whole process, ``faultslip ... --json``, with NUMBA_CACHE_DIR pointing at a folder of its
round: empty for the cold run, then the same folder for the warm one; rounds alternate which command goes first.
The figure is the median over rounds of cold / warm wall time (and CPU time of the child, from its rusage). The
commands: the small 2-D fault (its whole step compiled, with rocket-fft) and a rate-and-state fit (the lab
integrator and the likelihood). Writes benchmarks/results/first_run.json; docs/benchmarks.md's table is written
from it by benchmarks/readme.py.
"""

from __future__ import annotations

import argparse
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

from fault_2d_profile import write_results  # noqa: E402

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


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args(argv)
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
    write_results("first_run.json", {"rounds": args.rounds, "rows": rows})
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
