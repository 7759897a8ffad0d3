"""Sweep benchmarks: the engine against bare numpy, the writer against a single-threaded one, work against size.

    python benchmarks/sweep_scale.py                  # every figure; work against size from 1e4 to 1e8 cells
    python benchmarks/sweep_scale.py --largest 1e9    # ... and the default path at 1e9 (~30 GB of disk)
    python benchmarks/sweep_scale.py --quick          # engine, writer at 1e6, sizes 1e4 to 1e6

Each figure is a ratio against a baseline doing the same work, measured in the same run:

1. **Engine.** ``compute_block`` (the in-memory study engine, xarray Dataset out) against a numpy
   kernel written inline that computes the same 17 outputs of the same closed-form cells, at 1e6
   and 1e7 cells. Targets: >= 0.8 and >= 0.9 of numpy's throughput.
2. **Writer.** ``faultslip sweep`` with default options (1e7 cells, 17 outputs, zlib level 1 with
   shuffle) against a single-threaded script that computes the same outputs with numpy and writes
   them with netCDF4 (zlib level 1, shuffle, the same chunks). Both run as fresh processes.
   Target: <= 0.75 of the script's wall time.
3. **Floor.** The default sweep of 1e7 cells against the machine's floor computed in the same run
   from its own component speeds (:func:`floor`), and against ``--workers 1``. Targets: <= 2x the
   floor, >= 1.6x from the second worker.
4. **Work against size.** Wall time and peak memory of the whole process tree (the sweep and its
   workers, sampled every 0.1 s with psutil) for each execution path: in process, the process
   pool (default), a dask LocalCluster, and a Zarr store. Drawn to docs/figures/work_against_size.png.

Outputs go to a temporary directory and are removed. Results: benchmarks/results/sweep.json,
then the README tables (benchmarks/readme.py).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
from provenance import stamp  # noqa: E402  (one stamp for every results file)

ROOT = Path(__file__).resolve().parent.parent
STUDY = """[study]
name = "closed-form scale benchmark"
base = "san_andreas_1906.toml"
method = "closed_form"

[sweep]
shear_modulus = {{ linspace = ["0.15e6 bar", "0.35e6 bar", {n_g}] }}
slip_rate = {{ logspace = ["1 mm/yr", "100 mm/yr", {n_v}] }}
zone_width = {{ linspace = ["5 km", "30 km", {n_d}] }}
"""
OUTPUTS = ("slip_per_event", "recurrence_period", "loading_rate", "static_friction", "stress_drop",
           "critical_loading_rate", "regime", "method", "estimated_relative_error", "dimensionless_rate",
           "seismic_moment", "moment_magnitude", "empirical_slip", "empirical_slip_ratio", "empirical_slip_z",
           "empirical_magnitude", "empirical_magnitude_z")
YEAR = 31557600.0


def grid_shape(cells: float) -> tuple[int, int, int]:
    """(shear moduli, slip rates, widths) for a grid of ``cells`` (1e4 and up; 1000 x 1000 from 1e6)."""
    cells = int(cells)
    if cells >= 1_000_000:
        return cells // 1_000_000, 1000, 1000
    side = int(round(np.sqrt(cells)))
    return 1, side, side


def bare_kernel(shear_moduli, n_v=1000, n_d=1000):
    """The closed-form outputs written inline in numpy (seed 003 eqs. 2-18 and 2-19), as a user would."""
    G = np.asarray(shear_moduli, dtype=float)[:, None, None]
    V = np.geomspace(1e-3, 0.1, n_v)[None, :, None] / YEAR
    D = np.linspace(5e3, 30e3, n_d)[None, None, :]
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
        # constant outputs as 0-stride views, as the engine keeps them (issue 28: materialising them here
        # was work the engine does not do)
        crit = np.broadcast_to(np.inf, slip.shape)
        regime = np.broadcast_to(np.int8(0), slip.shape)
        method = np.broadcast_to(np.int8(0), slip.shape)
        # Wells & Coppersmith (1994) strike-slip, as the study reports beside the prediction
        expected = 10.0 ** (-6.32 + 0.90 * Mw)
        ratio = np.where(slip > 0, slip / expected, np.nan)
        from_length = np.broadcast_to(5.16 + 1.12 * np.log10(L / 1e3), slip.shape)
        return (slip, per, th, mus, drop, crit, regime, method, err, eps, M0, Mw, expected, ratio,
                np.log10(ratio) / 0.28, from_length, (Mw - from_length) / 0.28)

    return run


def engine(cells: float, repeats: int) -> dict:
    from faultslip.studies.grid import compute_block, parse_study

    n_g, n_v, n_d = grid_shape(cells)
    study = parse_study(STUDY.format(n_g=n_g, n_v=n_v, n_d=n_d))
    bare = bare_kernel(np.linspace(0.15e11, 0.35e11, n_g), n_v, n_d)
    dataset, outputs = compute_block(study), bare()
    np.testing.assert_allclose(dataset["slip_per_event"].values, outputs[0], rtol=1e-12)
    np.testing.assert_allclose(dataset["moment_magnitude"].values, outputs[11], rtol=1e-12)
    np.testing.assert_allclose(dataset["empirical_slip_z"].values, outputs[14], rtol=1e-10, atol=1e-12)
    del dataset, outputs
    ours, theirs = [], []
    for _ in range(repeats):  # interleaved: both see the same machine state
        started = time.perf_counter()
        compute_block(study)
        ours.append(time.perf_counter() - started)
        started = time.perf_counter()
        bare()
        theirs.append(time.perf_counter() - started)
    return {"cells": n_g * n_v * n_d, "engine_s": statistics.median(ours), "numpy_s": statistics.median(theirs),
            "fraction_of_numpy": statistics.median(theirs) / statistics.median(ours),
            "target": 0.8 if cells < 5e6 else 0.9}


BASELINE_WRITER = r'''
import sys, numpy as np, netCDF4
sys.path.insert(0, {bench!r})
from sweep_scale import OUTPUTS, bare_kernel
n_g, path = {n_g}, {path!r}
nc = netCDF4.Dataset(path, "w")
for name, size in (("shear_modulus", n_g), ("slip_rate", 1000), ("zone_width", 1000)):
    nc.createDimension(name, size)
for name in OUTPUTS:
    small = name in ("regime", "method")
    nc.createVariable(name, "i1" if small else "f8", ("shear_modulus", "slip_rate", "zone_width"), zlib=True,
                      complevel=1, shuffle=True, chunksizes={chunks})
G = np.linspace(0.15e11, 0.35e11, n_g)
for i in range(n_g):  # one shear modulus (1e6 cells) at a time: memory stays flat
    for name, values in zip(OUTPUTS, bare_kernel(G[i:i + 1])()):
        nc[name][i:i + 1] = values
nc.close()
'''


def peak_tree_rss(process, done=None) -> int:
    """The largest resident memory of ``process`` and its children, sampled every 0.05 s until it exits (or until
    ``done`` is set)."""
    import psutil

    peak = 0
    root = psutil.Process(process.pid)
    while process.poll() is None and not (done is not None and done.is_set()):
        try:
            total = root.memory_info().rss + sum(child.memory_info().rss for child in root.children(recursive=True))
        except psutil.Error:
            total = 0
        peak = max(peak, total)
        time.sleep(0.05)
    return peak


def timed(command, cwd) -> dict:
    """Wall time and peak memory of a whole command. The clock stops when the process exits, not at the memory
    sampler's next tick (a sampler in the loop that timed it had added up to 0.1 s to every command)."""
    import threading

    peaks, done = [], threading.Event()
    started = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=cwd)
    sampler = threading.Thread(target=lambda: peaks.append(peak_tree_rss(process, done)), daemon=True)
    sampler.start()
    stdout, stderr = process.communicate()
    seconds = time.perf_counter() - started
    done.set()
    sampler.join()
    if process.returncode != 0:
        raise SystemExit(f"{' '.join(map(str, command))} failed: {stderr}")
    return {"seconds": seconds, "peak_memory_bytes": peaks[0] if peaks else 0, "stdout": stdout}


def _size_on_disk(path: Path) -> int:
    return path.stat().st_size if path.is_file() else sum(f.stat().st_size for f in path.rglob("*") if f.is_file())


def sweep_command(study: Path, out: Path, path: str) -> list:
    command = [sys.executable, "-m", "faultslip.cli", "sweep", str(study), "-o", str(out), "--json"]
    return command + {"in-process": ["--workers", "1"], "process pool": [], "dask LocalCluster": ["--scheduler", "local"],
                      "zarr (process pool)": []}[path]


def writer(cells: float) -> dict:
    """Default sweep against the single-threaded numpy + netCDF4 writer, same outputs and chunks."""
    from faultslip.studies.grid import parse_study
    from faultslip.studies.streaming import DEFAULT_CHUNK_CELLS, plan_blocks

    n_g, n_v, n_d = grid_shape(cells)
    with tempfile.TemporaryDirectory(dir=Path.cwd()) as scratch:
        scratch = Path(scratch)
        study = scratch / "study.toml"
        study.write_text(STUDY.format(n_g=n_g, n_v=n_v, n_d=n_d))
        chunks, _ = plan_blocks(parse_study(study.read_text()), DEFAULT_CHUNK_CELLS)
        script = scratch / "baseline.py"
        script.write_text(BASELINE_WRITER.format(bench=str(ROOT / "benchmarks"), n_g=n_g, path=str(scratch / "base.nc"),
                                                 chunks=tuple(chunks.values())))
        rows = {"baseline": [], "ours": []}
        for _ in range(2):  # alternated; the better of two each (the machine's noise is one-sided)
            rows["baseline"].append(timed([sys.executable, str(script)], scratch))
            rows["ours"].append(timed(sweep_command(study, scratch / "ours.nc", "process pool") + ["--overwrite"],
                                      scratch))
        import xarray as xr

        with xr.open_dataset(scratch / "ours.nc") as a, xr.open_dataset(scratch / "base.nc") as b:
            np.testing.assert_allclose(a["slip_per_event"].values, b["slip_per_event"].values, rtol=1e-12)
        sizes = {"ours": _size_on_disk(scratch / "ours.nc"), "baseline": _size_on_disk(scratch / "base.nc")}
    best = {k: min(v, key=lambda r: r["seconds"]) for k, v in rows.items()}
    return {"cells": n_g * n_v * n_d, "chunks": chunks, "ours_s": best["ours"]["seconds"],
            "baseline_s": best["baseline"]["seconds"], "ratio": best["ours"]["seconds"] / best["baseline"]["seconds"],
            "ours_peak_memory_bytes": best["ours"]["peak_memory_bytes"],
            "baseline_peak_memory_bytes": best["baseline"]["peak_memory_bytes"], "file_bytes": sizes,
            "executor": json.loads(best["ours"]["stdout"])["executor"], "target": 0.75}


def floor(cells: float, repeats: int = 5) -> dict:
    """The machine's floor for a sweep's work, from its component speeds measured here, against the default
    sweep and ``--workers 1`` as whole commands (interleaved, median of ``repeats``).

    The floor is what any implementation must do: compute the 17 outputs (the inline numpy kernel, one
    shear modulus at a time), byte-shuffle and deflate them as the file's filters say (numpy's transpose
    copy, ISA-L level 1), spread over the cores, then write the compressed bytes (one buffered file write,
    no fsync, as the sweep's). Python's start-up and imports are not in it: the sweep of one cell, a
    whole command too, shows them.
    """
    from faultslip.io.chunks import deflate_compress

    load_before = os.getloadavg()[0]  # the machine's state goes beside the figures: the gain depends on it
    started_at = datetime.now(timezone.utc)
    from faultslip.io.processes import retain_freed_memory

    retain_freed_memory()  # the floor is the best this machine does: no page faults on reused arrays either
    n_g, n_v, n_d = grid_shape(cells)
    cores = os.cpu_count() or 1
    parts = {"kernel": 0.0, "shuffle": 0.0, "deflate": 0.0}
    compressed = []
    for g in np.linspace(0.15e11, 0.35e11, n_g):
        started = time.perf_counter()
        outputs = bare_kernel([g], n_v, n_d)()
        outputs = [np.ascontiguousarray(o, dtype=np.int8 if o.dtype == np.int8 else float) for o in outputs]
        parts["kernel"] += time.perf_counter() - started
        for values in outputs:
            started = time.perf_counter()
            raw = values.view(np.uint8).reshape(-1, values.itemsize).T.tobytes() if values.itemsize > 1 else \
                values.tobytes()
            parts["shuffle"] += time.perf_counter() - started
            started = time.perf_counter()
            compressed.append(deflate_compress(raw))
            parts["deflate"] += time.perf_counter() - started
        del outputs
    total = sum(len(c) for c in compressed)
    with tempfile.TemporaryDirectory(dir=Path.cwd()) as scratch:
        target = Path(scratch) / "bytes.bin"
        started = time.perf_counter()
        with open(target, "wb") as handle:
            for chunk in compressed:
                handle.write(chunk)
        parts["write"] = time.perf_counter() - started
        study = Path(scratch) / "study.toml"
        study.write_text(STUDY.format(n_g=n_g, n_v=n_v, n_d=n_d))
        tiny = Path(scratch) / "tiny.toml"
        tiny.write_text(STUDY.format(n_g=1, n_v=1, n_d=1))
        runs = {"default (2 workers)": [], "--workers 1": [], "one cell": []}
        memory = {"default (2 workers)": []}
        for _ in range(repeats):  # interleaved: a busy moment hits every command alike
            for label, extra, scene in (("default (2 workers)", [], study), ("--workers 1", ["--workers", "1"], study),
                                        ("one cell", [], tiny)):
                result = timed(sweep_command(scene, Path(scratch) / "out.nc", "process pool") + extra
                               + ["--overwrite"], scratch)
                runs[label].append(result["seconds"])
                if label in memory:
                    memory[label].append(result["peak_memory_bytes"])
    del compressed
    cpu = parts["kernel"] + parts["shuffle"] + parts["deflate"]
    floor_s = cpu / cores + parts["write"]
    seconds = {label: statistics.median(values) for label, values in runs.items()}
    return {"cells": n_g * n_v * n_d, "cores": cores, "parts_s": parts, "compressed_bytes": total,
            "floor_s": floor_s, "sweep_s": seconds, "ratio_to_floor": seconds["default (2 workers)"] / floor_s,
            "second_worker_speedup": seconds["--workers 1"] / seconds["default (2 workers)"],
            "peak_memory_bytes": statistics.median(memory["default (2 workers)"]), "repeats": repeats,
            "target_ratio": 2.0, "target_speedup": 1.6, "state": {
                "measured_at": started_at.strftime("%Y-%m-%d %H:%M UTC"), "load_average_before": load_before,
                "load_average_after": os.getloadavg()[0],
                "seconds_per_window": {"each pair": [list(pair) for pair in zip(runs["default (2 workers)"],
                                                                               runs["--workers 1"])]}}}


PATHS = ("in-process", "process pool", "dask LocalCluster", "zarr (process pool)")


def work_against_size(sizes, largest_paths_limit: float, largest: float | None) -> list:
    rows = []
    for cells in sizes + ([largest] if largest else []):
        n_g, n_v, n_d = grid_shape(cells)
        paths = PATHS if cells <= largest_paths_limit else ("process pool",)
        for path in paths:
            with tempfile.TemporaryDirectory(dir=Path.cwd()) as scratch:
                scratch = Path(scratch)
                study = scratch / "study.toml"
                study.write_text(STUDY.format(n_g=n_g, n_v=n_v, n_d=n_d))
                out = scratch / ("out.zarr" if path.startswith("zarr") else "out.nc")
                command = sweep_command(study, out, path) + (["--allow-large"] if cells > 1e8 else [])
                result = timed(command, scratch)
                size = _size_on_disk(out)
                shutil.rmtree(out, ignore_errors=True) if out.is_dir() else out.unlink()
            summary = json.loads(result["stdout"])
            row = {"cells": n_g * n_v * n_d, "path": path, "seconds": result["seconds"],
                   "peak_memory_bytes": result["peak_memory_bytes"], "bytes_on_disk": size,
                   "executor": summary["executor"]}
            rows.append(row)
            print(f"   {row['cells']:8.0e} cells  {path:20s} {row['seconds']:8.2f} s  "
                  f"{row['peak_memory_bytes'] / 2**20:6.0f} MiB  ({summary['executor']})", flush=True)
    return rows


def chart(rows, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, (time_axis, memory_axis) = plt.subplots(1, 2, figsize=(11, 4.2))
    for name, marker in zip(PATHS, "osD^"):
        points = sorted((r["cells"], r["seconds"], r["peak_memory_bytes"]) for r in rows if r["path"] == name)
        if not points:
            continue
        cells, seconds, memory = zip(*points)
        time_axis.loglog(cells, seconds, marker=marker, label=name)
        memory_axis.semilogx(cells, np.array(memory) / 2**30, marker=marker, label=name)
    time_axis.set(xlabel="cells", ylabel="wall time of the whole command (s)", title="work against size")
    memory_axis.set(xlabel="cells", ylabel="peak memory, whole process tree (GiB)", title="peak memory")
    memory_axis.axhline(2.0, color="0.5", linestyle="--", linewidth=1, label="2 GiB target")
    memory_axis.set_ylim(bottom=0)
    for axis in (time_axis, memory_axis):
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize=8)
    figure.suptitle("faultslip sweep, closed-form study, 17 outputs, zlib level 1 (benchmarks/sweep_scale.py)",
                    fontsize=9)
    figure.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, dpi=110)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a quick pass: engine, writer at 1e6, sizes to 1e6")
    parser.add_argument("--largest", type=float, help="also run the default path at this many cells (e.g. 1e9)")
    parser.add_argument("--floor-only", action="store_true",
                        help="measure only figure 3 (the floor and the second worker) again, into sweep.json")
    args = parser.parse_args(argv)
    results = stamp()
    if args.floor_only:
        path = ROOT / "benchmarks" / "results" / "sweep.json"
        stamped, results = results, json.loads(path.read_text()) | {"floor_date": results["date"]}
        results["floor"] = row = floor(1e7)
        row["stamp"] = stamped  # the rest of the file keeps its own
        print(f"   1e7 cells: default {row['sweep_s']['default (2 workers)']:.2f} s, --workers 1 "
              f"{row['sweep_s']['--workers 1']:.2f} s -> {row['second_worker_speedup']:.2f}x from the second worker "
              f"(target >= 1.6); one cell {row['sweep_s']['one cell']:.2f} s; median of {row['repeats']} interleaved")
        path.write_text(json.dumps(results, indent=2) + "\n")
        return
    print("1. engine against a numpy kernel computing the same 17 outputs (in memory)")
    results["engine"] = []
    for cells in ((1e6,) if args.quick else (1e6, 1e7)):
        row = engine(cells, 7 if args.quick else 15)
        results["engine"].append(row)
        print(f"   {row['cells']:.0e} cells: engine {row['engine_s'] * 1e3:.1f} ms, numpy {row['numpy_s'] * 1e3:.1f} ms "
              f"-> {row['fraction_of_numpy']:.2f} of numpy (target >= {row['target']})", flush=True)
    print("2. default sweep against a single-threaded numpy + netCDF4 (zlib 1, shuffle) writer")
    results["writer"] = row = writer(1e6 if args.quick else 1e7)
    print(f"   {row['cells']:.0e} cells: sweep {row['ours_s']:.2f} s ({row['executor']}), writer "
          f"{row['baseline_s']:.2f} s -> {row['ratio']:.2f}x (target <= 0.75)", flush=True)
    print("3. the default sweep against the machine's floor, and the second worker")
    results["floor"] = row = floor(1e6 if args.quick else 1e7)
    print(f"   {row['cells']:.0e} cells: floor {row['floor_s']:.2f} s ({', '.join(f'{k} {v:.2f} s' for k, v in row['parts_s'].items())}"
          f"), sweep {row['sweep_s']['default (2 workers)']:.2f} s -> {row['ratio_to_floor']:.2f}x the floor (target <= 2); "
          f"--workers 1 {row['sweep_s']['--workers 1']:.2f} s -> {row['second_worker_speedup']:.2f}x from the second "
          f"worker (target >= 1.6); one cell {row['sweep_s']['one cell']:.2f} s", flush=True)
    print("4. work against size, per execution path")
    sizes = [1e4, 1e5, 1e6] if args.quick else [1e4, 1e5, 1e6, 1e7, 1e8]
    results["work_against_size"] = work_against_size(sizes, 1e8, args.largest)
    out = ROOT / "benchmarks" / "results"
    out.mkdir(exist_ok=True)
    name = "sweep_quick.json" if args.quick else "sweep.json"
    (out / name).write_text(json.dumps(results, indent=2) + "\n")
    if not args.quick:
        chart(results["work_against_size"], ROOT / "docs" / "figures" / "work_against_size.png")
    print(f"wrote {out / name}; python benchmarks/readme.py puts it in the README")


if __name__ == "__main__":
    main()
