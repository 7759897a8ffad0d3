"""The 3-D fault's operator: its error against the dense product, and its memory and product time as the fault
grows, beside the dense product doing the same work.

    python benchmarks/fault_3d_operator.py [--quick]
    python -m benchmarks fault_3d_operator

Two families of grids, squares of 1 km on a vertical strike-slip fault:

* **refined** (BP5's shape, N_x = 2.5 N_z): N from 1,000 to 16,000; both directions grow (the assembly, every
  offset's dislocations on one thread, takes minutes beyond);
* **lengthened** (N_z = 20 fixed, N_x growing): N from 1,000 to 32,000; only the strike grows, where the FFT works.

For each: the operator's bytes, its assembly's wall time, and the median wall time of a product over interleaved
repeats. Up to 2,000 squares the dense matrix (every square's own dislocations, no translation used) is built
too: the relative error of the FFT product against it, and the dense product's median time, interleaved with the
FFT's. The growth exponents are least-squares slopes in log-log.

Then whole runs, each in a fresh process: the small 3-D fault (configs/fault_3d_small.toml) cold (the process's
first: imports, the compiled force balance loaded, the operator assembled) against warm (the same run again in
that process); and SEAS BP5-QD at 1000 m over 1800 yr with the BLAS library held to one thread against its default
(the per-frequency block products are BLAS's; the rest is one thread), interleaved, CPU and wall time each.
Writes benchmarks/results/fault_3d_operator.json.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from provenance import stamp  # noqa: E402  (one stamp for every results file)

from faultslip.models.fault_3d.kernel import StrikeConvolution, dense_matrices  # noqa: E402

G, NU, H = 3.2038e10, 0.25, 1000.0
DENSE_UP_TO = 2000  # the dense reference is every pair's dislocations: minutes beyond


def grids(kind: str, quick: bool) -> list[tuple[int, int]]:
    if kind == "refined":
        rows = (20, 40, 60, 80) if not quick else (20, 40)
        return [(int(round(2.5 * z)), z) for z in rows]
    lengths = (50, 100, 200, 400, 800, 1600) if not quick else (50, 100)
    return [(x, 20) for x in lengths]


def timed(product, vector, repeats: int) -> list[float]:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        product(vector)
        times.append(time.perf_counter() - start)
    return times


def measure(strike_count: int, dip_count: int, repeats: int) -> dict:
    count = strike_count * dip_count
    start = time.perf_counter()
    operator = StrikeConvolution(strike_count, dip_count, H, 90.0, "strike", G, NU)
    assembly = time.perf_counter() - start
    slip = np.random.default_rng(count).normal(size=count)
    row = {"strike": strike_count, "dip": dip_count, "elements": count, "bytes": operator.nbytes,
           "assembly_s": assembly}
    fft_times, dense_times = [], []
    if count <= DENSE_UP_TO:
        start = time.perf_counter()
        shear, _ = dense_matrices(strike_count, dip_count, H, 90.0, "strike", G, NU)
        row["dense_assembly_s"] = time.perf_counter() - start
        row["dense_bytes"] = shear.nbytes
        exact = shear @ slip
        row["relative_error"] = float(np.max(np.abs(operator(slip) - exact)) / np.max(np.abs(exact)))
        for _ in range(repeats):  # interleaved: each round times both on the same machine state
            fft_times += timed(operator, slip, 1)
            dense_times += timed(shear.__matmul__, slip, 1)
        row["dense_product_s"] = float(np.median(dense_times))
    else:
        fft_times = timed(operator, slip, repeats)
    row["product_s"] = float(np.median(fft_times))
    return row


def slope(rows: list, key: str) -> float:
    x = np.log([row["elements"] for row in rows])
    y = np.log([row[key] for row in rows])
    return float(np.polyfit(x, y, 1)[0])


WHOLE_RUN = """
import json, resource, sys, time
from faultslip.models.fault_3d.scene import load_fault_3d_scene
from faultslip.models.fault_2d.integrate import YEAR
times = []
for _ in range(int(sys.argv[3])):
    start, cpu = time.perf_counter(), time.process_time()
    scene = load_fault_3d_scene(sys.argv[1], allow_large=True)
    scene.duration = float(sys.argv[2]) * YEAR
    run = scene.run()
    times.append({"wall_s": time.perf_counter() - start, "cpu_s": time.process_time() - cpu, "steps": run.steps,
                  "events": run.event_count})
print(json.dumps({"runs": times, "peak_memory_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024}))
"""


def whole_run(scene: str, years: float, repeats: int, threads: int | None = None) -> dict:
    """A fresh process running ``scene`` ``repeats`` times (the first cold); BLAS held to ``threads`` if given."""
    environment = dict(os.environ)
    if threads is not None:
        for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
            environment[name] = str(threads)
    done = subprocess.run([sys.executable, "-c", WHOLE_RUN, scene, str(years), str(repeats)], capture_output=True,
                          text=True, env=environment, cwd=ROOT, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two sizes a family, fewer repeats")
    parser.add_argument("--out", default=str(HERE / "results" / "fault_3d_operator.json"))
    args = parser.parse_args(argv)
    repeats = 5 if args.quick else 21
    result = {"families": {}}
    for kind in ("refined", "lengthened"):
        rows = []
        for strike_count, dip_count in grids(kind, args.quick):
            rows.append(measure(strike_count, dip_count, repeats))
            print(kind, rows[-1], flush=True)
        result["families"][kind] = {"rows": rows, "memory_exponent": slope(rows, "bytes"),
                                    "product_exponent": slope(rows, "product_s")}
    small = whole_run(str(ROOT / "configs" / "fault_3d_small.toml"), 60.0, 2)
    result["cold_warm"] = {"cold": small["runs"][0], "warm": small["runs"][1],
                           "ratio": small["runs"][0]["wall_s"] / small["runs"][1]["wall_s"]}
    print("cold/warm", result["cold_warm"], flush=True)
    if not args.quick:
        bp5 = str(ROOT / "configs" / "seas_bp5.toml")
        pairs = []
        for _ in range(2):  # interleaved: one thread, then the default, twice
            one = whole_run(bp5, 1800.0, 1, threads=1)
            default = whole_run(bp5, 1800.0, 1)
            pairs.append({"one_thread": {**one["runs"][0], "peak_memory_bytes": one["peak_memory_bytes"]},
                          "default": {**default["runs"][0], "peak_memory_bytes": default["peak_memory_bytes"]}})
            print("threads", pairs[-1], flush=True)
        result["bp5_threads"] = {"pairs": pairs, "wall_ratio": float(np.median(
            [p["one_thread"]["wall_s"] / p["default"]["wall_s"] for p in pairs]))}
    checked = [row for family in result["families"].values() for row in family["rows"] if "relative_error" in row]
    result["largest_relative_error"] = max(row["relative_error"] for row in checked)
    result.update(stamp())
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
