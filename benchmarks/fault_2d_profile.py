"""Where a 2-D fault run's time goes (issue 43, item 2: "profile first and say where the time goes").

    python benchmarks/fault_2d_profile.py [--elements 1024 1600] [--years 300] [--rtol 1e-4] [--core 0]

SEAS BP1 (configs/seas_bp1.toml) at each element count, over ``--years`` at ``--rtol`` (faultslip's loosest
tolerance within 0.1 % of its converged recurrence, benchmarks/fault_2d_qdyn.py), pinned to one core, under
cProfile. The profile's own time is split into what each part of a step costs:

- **force balance**: the compiled (numba) Newton solve of tau = sigma_n a asinh(...) + eta V on every element;
- **kernel FFT**: scipy's real FFT and inverse (pocketfft) of the stress kernel's product;
- **kernel, other**: the spectrum's products and the kernel's Python around the FFT;
- **stage arithmetic**: the Dormand-Prince stages, the error norm and the step control in numpy;
- **recording**: stations, profiles, events and the SEAS files;
- **the rest**: start-up, imports and writing.

cProfile adds a few microseconds to every Python call, so its shares overstate the Python parts somewhat; the
wall time without it is measured too. Writes benchmarks/results/fault_2d_profile.json.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import os
import platform
import pstats
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.constants import JULIAN_YEAR  # noqa: E402
from faultslip.models.fault_2d.integrate import run_cycles  # noqa: E402
from faultslip.models.fault_2d.scene import load_fault_2d_scene  # noqa: E402

WIDTH = 40e3
PARTS = {
    "force balance": ("fault_2d/compiled.py",),
    "kernel FFT": ("pypocketfft",),
    "kernel, other": ("fault_2d/kernel.py", "scipy/fft", "numpy/lib/_type_check_impl.py", "numpy/fft"),
    "recording": ("io/seas.py", "io/records.py", "station_row", "profile_row", "_Stations"),
}


def _part(filename: str, function: str) -> str:
    where = f"{filename}:{function}"
    for part, keys in PARTS.items():
        if any(key in where for key in keys):
            return part
    if "fault_2d/integrate.py" in filename or "fault_2d/model.py" in filename or filename == "~":
        return "stage arithmetic"
    return "the rest"


def profile(elements: int, years: float, rtol: float) -> dict:
    scene = load_fault_2d_scene(ROOT / "configs" / "seas_bp1.toml").at_element_size(WIDTH / elements)
    fault = scene.fault
    with tempfile.TemporaryDirectory() as folder:
        began = time.perf_counter()
        plain = run_cycles(fault, years * JULIAN_YEAR, rtol=rtol, folder=Path(folder) / "plain")
        wall = time.perf_counter() - began
        profiler = cProfile.Profile()
        profiler.enable()
        run_cycles(fault, years * JULIAN_YEAR, rtol=rtol, folder=Path(folder) / "profiled")
        profiler.disable()
    stats = pstats.Stats(profiler)
    parts = dict.fromkeys([*PARTS, "stage arithmetic", "the rest"], 0.0)
    for (filename, _, function), row in stats.stats.items():
        parts[_part(filename, function)] += row[2]  # tottime: each function's own time
    total = sum(parts.values())
    stages = plain.function_evaluations
    return {"elements": elements, "years": years, "rtol": rtol, "steps": plain.steps, "stages": stages,
            "wall_s": wall, "per_step_ms": wall / plain.steps * 1e3, "per_stage_us": wall / stages * 1e6,
            "profiled_s": total, "shares": {part: seconds / total for part, seconds in parts.items()},
            "per_stage_us_by_part": {part: seconds / stages * 1e6 * wall / total for part, seconds in parts.items()}}


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
        print(f"{row['elements']} elements: {row['per_step_ms']:.3f} ms a step ({row['steps']} steps), "
              + ", ".join(f"{part} {share:.0%}" for part, share in row["shares"].items()))
    write_results("fault_2d_profile.json", {"runs": rows})
    return 0


def write_results(name: str, document: dict) -> None:
    """benchmarks/results/NAME: ``document`` with the machine and the date."""
    out = ROOT / "benchmarks" / "results" / name
    document = {**document, "machine": f"{platform.machine()}, {os.cpu_count()} cores, Python "
                                       f"{platform.python_version()}",
                "date": datetime.now(timezone.utc).strftime("%Y-%m-%d")}
    out.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    print(f"written to {out}")


if __name__ == "__main__":
    raise SystemExit(main())
