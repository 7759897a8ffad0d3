"""Sweep benchmarks: overhead against bare numpy, and out-of-core grids with flat peak memory.

    python benchmarks/sweep_scale.py            # sizes 1e7, 1e8, 5e8 cells (5e8 needs ~25 GB of disk)
    python benchmarks/sweep_scale.py --quick    # sizes 1e6, 1e7

Peak memory is the largest resident-set size of the whole process tree (the sweep and its
workers), sampled every 0.1 s with psutil. Outputs go to a temporary directory and are removed.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

STUDY = """[study]
name = "closed-form scale benchmark"
base = "san_andreas_1906.toml"
method = "closed_form"

[sweep]
shear_modulus = {{ linspace = ["0.15e6 bar", "0.35e6 bar", {n_g}] }}
slip_rate = {{ logspace = ["1 mm/yr", "100 mm/yr", 1000] }}
zone_width = {{ linspace = ["5 km", "30 km", 1000] }}
"""


def bare_numpy(shape_g, repeats=5):
    """The closed-form outputs written inline in numpy, on the same inputs as the study."""
    return bare_numpy_at(np.linspace(0.15e11, 0.35e11, shape_g))


def bare_numpy_at(shear_moduli):
    """The bare kernel on given shear moduli (Pa) and the study's 1000 x 1000 slip rates and widths."""
    G = np.asarray(shear_moduli, dtype=float)[:, None, None]
    V = np.geomspace(1e-3, 0.1, 1000)[None, :, None] / 31557600.0
    D = np.linspace(5e3, 30e3, 1000)[None, None, :]
    tau, muso, mum, b, d, rho, L, H = 2.5e7, 0.65, 0.55, 38.0, 0.665, 2700.0, 434522.88, 12e3

    def run():
        K = G / D
        sn = tau / muso
        th = K * V / sn
        ex = (muso - mum) / (1 + (muso - mum) * b * th**d)
        alpha = sn / K * ex * 2.0  # eq. 2-19 undamped: the stress-drop slip
        wn = np.sqrt(K / (rho * D))
        eps = th / (wn * ex)
        per = alpha / V + np.pi / wn
        slip = V * per  # slip per event, the integral of u dt
        drop = K * alpha
        mus = mum + ex
        M0 = G * L * H * slip
        Mw = 2 / 3 * (np.log10(M0) - 9.1)
        err = 1.5 * eps * eps
        crit = np.full(slip.shape, np.inf)
        regime = np.zeros(slip.shape, np.int8)
        method = np.zeros(slip.shape, np.int8)
        return slip, per, th, mus, drop, crit, regime, method, err, eps, M0, Mw

    return run


def overhead(repeats):
    from faultslip.studies.grid import compute_block, parse_study

    study = parse_study(STUDY.format(n_g=1))  # 1e6 cells in memory
    bare = bare_numpy(1)
    compute_block(study)
    bare()
    ours, theirs = [], []
    for _ in range(repeats):
        started = time.perf_counter()
        dataset = compute_block(study)
        ours.append(time.perf_counter() - started)
        started = time.perf_counter()
        outputs = bare()
        theirs.append(time.perf_counter() - started)
    np.testing.assert_allclose(dataset["slip_per_event"].values, outputs[0], rtol=1e-12)
    cells = 1e6
    return {"cells": cells, "study_points_per_s": cells / statistics.median(ours),
            "numpy_points_per_s": cells / statistics.median(theirs),
            "fraction_of_numpy": statistics.median(theirs) / statistics.median(ours), "target": ">= 0.70"}


def peak_tree_rss(process):
    import psutil

    peak = 0
    root = psutil.Process(process.pid)
    while process.poll() is None:
        try:
            total = root.memory_info().rss + sum(child.memory_info().rss for child in root.children(recursive=True))
        except psutil.Error:
            total = 0
        peak = max(peak, total)
        time.sleep(0.1)
    return peak


def scale(sizes, scheduler):
    rows = []
    for cells in sizes:
        n_g = int(cells // 1_000_000)
        with tempfile.TemporaryDirectory(dir=Path.cwd()) as scratch:
            study = Path(scratch) / "study.toml"
            study.write_text(STUDY.format(n_g=n_g))
            out = Path(scratch) / "out.nc"
            command = [sys.executable, "-m", "faultslip.cli", "sweep", str(study), "-o", str(out), "--json",
                       "--chunks", "1000000", "--workers", "2"]
            if scheduler:
                command += ["--scheduler", scheduler]
            started = time.perf_counter()
            process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            peak = peak_tree_rss(process)
            stdout, stderr = process.communicate()
            seconds = time.perf_counter() - started
            if process.returncode != 0:
                raise SystemExit(f"sweep of {cells:g} cells failed: {stderr}")
            size = out.stat().st_size
        raw = cells * (10 * 8 + 2)
        rows.append({"cells": cells, "seconds": seconds, "points_per_s": cells / seconds,
                     "peak_memory_bytes": peak, "output_bytes_raw": raw, "file_bytes": size,
                     "raw_over_memory": raw / peak})
        print(f"   {cells:9.0e} cells: {seconds:7.1f} s, {cells / seconds / 1e6:6.2f} M points/s, peak RSS "
              f"{peak / 2**20:7.0f} MiB (outputs {raw / 2**30:.1f} GiB raw, {size / 2**30:.1f} GiB on disk)", flush=True)
    return rows


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="sizes 1e6 and 1e7 only")
    parser.add_argument("--scheduler", default="local", help="dask scheduler for the scale runs (default: local)")
    args = parser.parse_args(argv)
    import os
    import platform
    from datetime import datetime, timezone

    results = {"machine": f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}",
               "date": datetime.now(timezone.utc).strftime("%Y-%m-%d"),
               "scheduler": args.scheduler}
    print("4. sweep overhead: closed-form study against bare numpy on the same 1e6 cells")
    results["sweep_overhead"] = r = overhead(5 if args.quick else 11)
    print(f"   study {r['study_points_per_s'] / 1e6:.2f} M points/s, numpy {r['numpy_points_per_s'] / 1e6:.2f} M points/s "
          f"-> {r['fraction_of_numpy']:.2f} of bare numpy (target >= 0.70)")
    sizes = (1e6, 1e7) if args.quick else (1e7, 1e8, 5e8)
    print(f"5. out-of-core closed-form sweeps, all outputs, dask scheduler {args.scheduler!r}")
    results["sweep_scale"] = scale(sizes, args.scheduler)
    out = Path(__file__).resolve().parent / "results"
    out.mkdir(exist_ok=True)
    (out / ("sweep_quick.json" if args.quick else "sweep.json")).write_text(json.dumps(results, indent=2) + "\n")
    if not args.quick:
        import readme

        readme.update()
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
