"""The surface slip per event of every dipping fault benchmarks/dip_model_error.py measured, for the one slider's
calibration against plane strain (benchmarks/dip_slider_calibration.py).

    python benchmarks/dip_slider_runs.py [--workers 2] [--every 1]

dip_model_error.py saved each plane-strain run's recurrence and mean slip over the weakening width, not the slip
at the surface, which the one slider also predicts. This reruns each fault's plane-strain run, as that benchmark
ran it (SEAS BP3's scene at the fault's dip, sense, D_c and H, 100 m elements, 1500 yr), and keeps its summary:
the rerun's recurrence and mean slip must be the saved ones (the run is deterministic), or the script stops.
Faults already in benchmarks/results/dip_slider_runs.json are reused; the file is rewritten as each run ends.

A rerun costs what the run did (about 30 s of CPU), so ``--every N`` reruns every N-th measured fault (in the
results' order: grid, first held out, then the draws) and the held-out ones; the fresh draws' newer runs keep
their surface slip. Every measured fault is rerun (``--every 1``, the default): a first try on every 4th had
few stiff faults.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from concurrent.futures import as_completed
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))

from provenance import stamp  # noqa: E402  (one stamp for every results file)

from faultslip.io.atomic import write_text_atomic  # noqa: E402
from faultslip.io.processes import stop_pool, worker_pool  # noqa: E402
from faultslip.models.fault_2d.analysis import summarise  # noqa: E402
from faultslip.models.fault_2d.integrate import YEAR  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402

import dip_model_error as measured  # noqa: E402

OUT = HERE / "results" / "dip_slider_runs.json"
INPUTS = ("dip", "sense", "critical_slip_m", "seismogenic_depth_m", "element_size_m", "years")


def saved_faults(every: int = 1, done: frozenset = frozenset()) -> list[dict]:
    """The faults of dip_model_error.py's results to rerun: every ``every``-th of its measured rows (and those in
    ``done``), then its held-out rows, once each."""
    data = json.loads((HERE / "results" / "dip_model_error.json").read_text(encoding="utf-8"))
    seen, faults = set(), []
    for index, row in enumerate(data["rows"]):
        key = measured._key(row)
        if row["set"] == "grid" and row["dip"] == 90.0 and row["sense"] == "normal":
            continue  # the vertical fault's copy: the thrust's run stands for both (a rerun differs at 1e-8)
        if key not in seen and (index % every == 0 or key in done):
            seen.add(key)
            faults.append(row)
    for row in data["held_out"]:
        if measured._key(row) not in seen:
            seen.add(measured._key(row))
            faults.append(row)
    return faults


def plane_strain(row: dict) -> dict:
    """The fault's plane-strain run, summarised (in a worker)."""
    base = read_fault_2d_scene(ROOT / "configs" / "seas_bp3_thrust60.toml")
    scene = measured.fault_scene(base, row["element_size_m"], row["years"], row["dip"], row["sense"],
                                 row["critical_slip_m"], row["seismogenic_depth_m"])
    summary = summarise(scene.run())
    return {**{name: row[name] for name in INPUTS}, "recurrence_yr": summary.recurrence_interval / YEAR,
            "mean_slip_m": summary.mean_slip_per_event, "surface_slip_m": summary.surface_slip_per_event,
            "settled": summary.settled}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--every", type=int, default=1, help="rerun every N-th measured fault (and the held out)")
    args = parser.parse_args(argv)
    done = {}
    if OUT.exists():
        done = {measured._key(row): row for row in json.loads(OUT.read_text(encoding="utf-8"))["runs"]}
    faults = saved_faults(args.every, frozenset(done))
    todo = [row for row in faults if measured._key(row) not in done]
    print(f"{len(faults)} faults, {len(todo)} to run", flush=True)
    pool = worker_pool(args.workers)
    try:
        futures = {pool.submit(plane_strain, row): row for row in todo}
        for future in as_completed(futures):
            row, run = futures[future], future.result()
            saved = row["plane_strain"]
            for name in ("recurrence_yr", "mean_slip_m"):  # the same run as the one measured, or stop
                if not math.isclose(run[name], saved[name], rel_tol=1e-9):
                    raise SystemExit(f"{row['dip']} deg {row['sense']}, D_c {row['critical_slip_m']} m: the rerun's "
                                     f"{name} {run[name]!r} is not the saved {saved[name]!r}")
            done[measured._key(row)] = run
            write_text_atomic(OUT, json.dumps({"runs": list(done.values()), "every": args.every, **stamp()}, indent=1)
                              + "\n")  # atomic: a run stopped between faults keeps every fault it finished
            print(f"{len(done)}: {row['dip']} deg {row['sense']}, D_c {row['critical_slip_m'] * 1e3:g} mm: surface "
                  f"slip {run['surface_slip_m']:.3f} m", flush=True)
    finally:
        stop_pool(pool)
    return 0


if __name__ == "__main__":
    sys.exit(main())
