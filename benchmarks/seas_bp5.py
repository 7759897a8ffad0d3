"""SEAS BP5-QD: faultslip's 3-D fault at 2000, 1000 and 500 m, beside a published participant.

    python benchmarks/seas_bp5.py [--sizes 2000 1000 500] [--years 1800] [--finest-years 1800]
    python -m benchmarks seas_bp5

The participant is tandem (Uphoff et al.; 4000 m elements of polynomial degree 4), whose BP5-QD station file at
(0 km along strike, 10 km deep) the SEAS platform publishes; benchmarks/data/bp5_tandem_excerpts.txt holds the rows
of it this project read, with the file's provenance (the whole file is 4.7 MB of text; its rows around the second
and third events and between them are enough for the comparison below, and are read here, not typed).

Both codes are read the same way at that station: an event's arrival is its slip rate crossing 1e-3 m/s (linear
in log10 rate between rows), its slip the station's slip across it. tandem's third arrival lies between the last
row before it and the first after it that the excerpts hold; its midpoint is used and the half-gap reported.

Per element size the file records the events (start of each, the peak slip rate anywhere above 1e-3 m/s), the
station's arrivals and slips, the last interval between system-size events (the sequence settles after the first,
which the nucleation patch starts at t = 0), the differences from tandem's and from the finest run, the declared
error (:func:`faultslip.models.fault_3d.family.discretisation_error`) and whether it holds, and the cost: steps,
wall and CPU time, peak memory. The finest size runs ``--finest-years`` (600 yr, three events, give one settled
interval, where a finer size's full run would take hours). The
declared error's bound is fitted here too (``fit``: c r^-p through the two coarsest sizes' differences from the
finest, r the squares per L_b, times a margin of 2), whose scale and order
faultslip.models.fault_3d.family.DISCRETISATION takes (its margin is what drawn faults needed:
fault_3d_resolution.py).
Writes benchmarks/results/seas_bp5.json.
"""

from __future__ import annotations

import argparse
import json
import math
import resource
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from provenance import stamp  # noqa: E402  (one stamp for every results file)

from faultslip.models.fault_2d.integrate import YEAR  # noqa: E402
from faultslip.models.fault_3d.family import discretisation_error, summarise  # noqa: E402
from faultslip.models.fault_3d.scene import load_fault_3d_scene  # noqa: E402

STATION = (0.0, 10e3)
THRESHOLD = -3.0  # log10 m/s
EXCERPTS = HERE / "data" / "bp5_tandem_excerpts.txt"


def read_excerpts(path: Path = EXCERPTS) -> dict:
    """The excerpt file's blocks: offset -> rows (t, slip_2, slip_3, log10 V_2, log10 V_3, tau_2, tau_3, log10 state),
    and its provenance lines."""
    blocks, provenance, current = {}, [], None
    for line in path.read_text(encoding="utf-8").splitlines():
        if line.startswith("# block offset"):
            current = int(line.split()[3].rstrip(":"))
            blocks[current] = []
        elif line.startswith("#"):
            provenance.append(line[1:].strip())
        elif line.strip():
            blocks[current].append([float(v) for v in line.split()])
    return {"blocks": {k: np.array(v) for k, v in blocks.items()}, "provenance": provenance}


def crossing(time: np.ndarray, log_rate: np.ndarray) -> list[float]:
    """Times the log10 slip rate rises through THRESHOLD, linear in log10 rate between rows."""
    above = log_rate > THRESHOLD
    rises = np.flatnonzero(~above[:-1] & above[1:]) + 1
    return [float(time[i - 1] + (THRESHOLD - log_rate[i - 1]) / (log_rate[i] - log_rate[i - 1])
                  * (time[i] - time[i - 1])) for i in rises]


def tandem_station() -> dict:
    """tandem's second and third arrivals (yr) and the slips of its first three events (m) at the station."""
    excerpts = read_excerpts()
    blocks = excerpts["blocks"]
    second = crossing(blocks[650000][:, 0], blocks[650000][:, 3])
    if len(second) != 1:
        raise SystemExit("the excerpt at offset 650000 should hold one arrival")
    before_third, after_third = blocks[1200000], blocks[1500000]
    third_low, third_high = before_third[-1, 0], after_third[0, 0]
    slips = [float(blocks[650000][0, 1]), float(before_third[0, 1] - blocks[650000][0, 1]),
             float(after_third[0, 1] - before_third[0, 1])]
    return {"second_arrival_yr": second[0] / YEAR, "third_arrival_yr": 0.5 * (third_low + third_high) / YEAR,
            "third_arrival_half_gap_yr": 0.5 * (third_high - third_low) / YEAR,
            "interval_yr": (0.5 * (third_low + third_high) - second[0]) / YEAR, "event_slips_m": slips,
            "provenance": excerpts["provenance"]}


def run_size(size: float, years: float) -> dict:
    scene = load_fault_3d_scene(ROOT / "configs" / "seas_bp5.toml", allow_large=True).at_element_size(size)
    scene.duration = years * YEAR
    index = [tuple(p) for p in scene.stations].index(STATION)
    start_cpu, start_wall = time.process_time(), time.perf_counter()
    run = scene.run()
    cpu, wall = time.process_time() - start_cpu, time.perf_counter() - start_wall
    summary = summarise(run)
    system_starts = np.asarray(run.events["start"])[summary["system"]]
    last_interval = float(system_starts[-1] - system_starts[-2]) / YEAR if system_starts.size > 2 else math.nan
    station_time = np.asarray(run.station_time)
    log_rate = np.asarray(run.stations["log10_slip_rate"][:, index])
    slip = np.asarray(run.stations["slip"][:, index])
    arrivals = crossing(station_time, log_rate)
    ends = [float(e) for e in run.events["end"]]
    event_slips = []  # the station's slip across each event (from the last row before its start to its end)
    for start, end in zip(run.events["start"], ends):
        event_slips.append(float(np.interp(end, station_time, slip) - np.interp(start, station_time, slip)))
    resolution = scene.fault.process_zone() / size
    return {"element_size_m": size, "elements": scene.fault.count, "resolution": resolution,
            "event_starts_yr": (np.asarray(run.events["start"]) / YEAR).tolist(),
            "station_arrivals_yr": [t / YEAR for t in arrivals], "station_event_slips_m": event_slips,
            "settled_interval_yr": summary["sequence"].mean_interval / YEAR, "last_interval_yr": last_interval,
            "sequence": summary["sequence"].kind, "mean_slip_m": summary["mean_slip"],
            "declared_error": discretisation_error(resolution), "steps": run.steps, "cpu_s": cpu, "wall_s": wall,
            "peak_memory_bytes": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024, "rtol": run.rtol,
            "years": years}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=[2000.0, 1000.0, 500.0])
    parser.add_argument("--years", type=float, default=1800.0)
    parser.add_argument("--finest-years", type=float, default=1800.0,
                        help="the finest size's duration (three events give one settled interval: 600 yr)")
    parser.add_argument("--out", default=str(HERE / "results" / "seas_bp5.json"))
    parser.add_argument("--reuse", help="an earlier results file: its runs of the same size and years are kept")
    args = parser.parse_args(argv)
    peer = tandem_station()
    earlier = {}
    if args.reuse and Path(args.reuse).is_file():
        earlier = {(r["element_size_m"], r["years"]): r
                   for r in json.loads(Path(args.reuse).read_text(encoding="utf-8"))["runs"]}
    runs = []
    finest_size = min(args.sizes)
    for size in args.sizes:
        years = args.finest_years if size == finest_size and len(args.sizes) > 1 else args.years
        row = earlier.get((size, years)) or run_size(size, years)
        arrivals = row["station_arrivals_yr"]
        if len(arrivals) >= 3:
            row["against_tandem"] = {
                "second_arrival": arrivals[1] / peer["second_arrival_yr"] - 1,
                "interval": (arrivals[2] - arrivals[1]) / peer["interval_yr"] - 1,
                "event_slips": [ours / theirs - 1 for ours, theirs in zip(row["station_event_slips_m"][:3],
                                                                          peer["event_slips_m"])]}
        runs.append(row)
        print(json.dumps({k: v for k, v in row.items() if not isinstance(v, list)}), flush=True)
        partial = Path(args.out).with_suffix(".partial.json")  # each size's run kept as it ends (--reuse it)
        partial.write_text(json.dumps({"peer": peer, "runs": runs, **stamp()}, indent=1) + "\n", encoding="utf-8")
    finest = min(runs, key=lambda r: r["element_size_m"])
    for row in runs:
        row["interval_difference_from_finest"] = row["last_interval_yr"] / finest["last_interval_yr"] - 1
    coarse = sorted((r for r in runs if r is not finest), key=lambda r: r["resolution"])[:2]
    fit = None
    if len(coarse) == 2 and all(abs(r["interval_difference_from_finest"]) > 0 for r in coarse):
        (r1, e1), (r2, e2) = ((r["resolution"], abs(r["interval_difference_from_finest"])) for r in coarse)
        order = math.log(e1 / e2) / math.log(r2 / r1)
        fit = {"scale": e1 * r1 ** order, "order": order, "margin": 2.0}
    for row in runs:  # the bound as fitted here (the family's constants are these, rounded up)
        if fit is not None:
            row["declared_error"] = fit["margin"] * fit["scale"] * row["resolution"] ** -fit["order"]
        row["within_declared_of_finest"] = bool(abs(row["interval_difference_from_finest"]) <= row["declared_error"])
        row["interval_difference_from_tandem"] = row["last_interval_yr"] / peer["interval_yr"] - 1
        row["within_declared_of_tandem"] = bool(abs(row["interval_difference_from_tandem"]) <= row["declared_error"])
    result = {"peer": peer, "runs": runs, "station": list(STATION), "fit": fit}
    result.update(stamp())
    Path(args.out).write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    Path(args.out).with_suffix(".partial.json").unlink(missing_ok=True)
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
