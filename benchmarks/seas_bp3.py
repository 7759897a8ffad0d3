"""SEAS BP3-QD: faultslip's dipping fault beside a published participant, at 100, 50 and 25 m.

    python benchmarks/seas_bp3.py --peer DIR [--sizes 100 50 25] [--years 1500]
    python -m benchmarks seas_bp3 --peer DIR

The peer is FDRA (Cattania & Segall's boundary-element code), whose BP3-QD results the SEAS platform
(https://strike.scec.org/cvws/cgi-bin/seas.cgi) publishes and RSFaultZ ships beside its own runs
(github.com/rmskarbek/RSFaultZ, benchmarks/BP3QD/, downloaded from that platform): ``DIR`` holds

    cattania_fltst_dp075_T60.txt, cattania_fltst_dp075_N30.txt          (on fault, 7.5 km down dip; C. Cattania)
    cattania_srfst_fn_{n16,p0,p16}_{T60,N30}.txt                         (surface, -16, 0+, +16 km; Y. Sun)

Both codes' series are read the same way: an event at 7.5 km is the station's slip rate above 1e-3 m/s (BP3's
seismic threshold); its slip is the station's slip across it; its surface offset the displacement's change across
it at each surface station. Per case and element size the file records the event times, intervals and slips, the
supercycle's period (the shortest whose last two cycles repeat to 2e-3), the largest
relative differences from FDRA's at 25 m over events matched in order, the declared resolution error
(:func:`faultslip.models.fault_2d.analysis.sequence_discretisation`) and the cost: steps, wall time and CPU
seconds per simulated year, beside the antiplane fault on as many elements (BP1 for 150 yr, timed the same way).
Writes benchmarks/results/seas_bp3.json.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
from provenance import stamp  # noqa: E402  (one stamp for every results file)

from faultslip.io.seas import read_seas  # noqa: E402
from faultslip.models.fault_2d.analysis import sequence_discretisation  # noqa: E402
from faultslip.models.fault_2d.integrate import YEAR  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402

CASES = {"thrust60": ("T60", "configs/seas_bp3_thrust60.toml"), "normal30": ("N30", "configs/seas_bp3_normal30.toml")}
SURFACE = {"n16": -16e3, "p0": 0.0, "p16": 16e3}
THRESHOLD = 1e-3  # m/s: BP3's seismic threshold


def station_events(time, slip, log10_rate, surface=None) -> dict:
    """Events at one station: start times (linear in log10 rate across the threshold), slip across each, and each
    surface station's (u, w) offset across it; an event under way at the end is left out."""
    above = log10_rate > math.log10(THRESHOLD)
    starts = np.flatnonzero(~above[:-1] & above[1:]) + 1
    ends = np.flatnonzero(above[:-1] & ~above[1:]) + 1
    starts = starts[: ends.size] if ends.size else starts[:0]
    ends = ends[ends > starts[0]] if starts.size else ends[:0]
    count = min(starts.size, ends.size)
    starts, ends = starts[:count], ends[:count]
    previous, current = log10_rate[starts - 1], log10_rate[starts]
    fraction = (math.log10(THRESHOLD) - previous) / (current - previous)
    times = time[starts - 1] + fraction * (time[starts] - time[starts - 1])
    out = {"start_yr": (times / YEAR).tolist(), "slip_m": (slip[ends] - slip[starts - 1]).tolist()}
    if surface is not None:
        out["surface_offset_m"] = {name: [[float(v) for v in disp[e] - disp[s - 1]] for s, e in zip(starts, ends)]
                                   for name, disp in surface.items()}
    return out


#: Surface speed (m/s) above which a surface station is moving coseismically (interseismic speeds are ~1e-10).
SURFACE_SPEED = 1e-6


def surface_offsets(time, displacement, velocity) -> list:
    """Each coseismic offset (u, w) of a surface station, from its own series: the displacement's change across
    each run of records whose speed exceeds :data:`SURFACE_SPEED`."""
    moving = np.hypot(velocity[:, 0], velocity[:, 1]) > SURFACE_SPEED
    starts = np.flatnonzero(~moving[:-1] & moving[1:]) + 1
    ends = np.flatnonzero(moving[:-1] & ~moving[1:]) + 1
    ends = ends[ends > starts[0]] if starts.size else ends[:0]
    return [[float(v) for v in displacement[e] - displacement[s - 1]] for s, e in zip(starts, ends)]


def peer_series(folder: Path, code: str) -> dict:
    header, names, rows = read_seas(folder / f"cattania_fltst_dp075_{code}.txt")
    sign = 1.0 if code.startswith("T") else -1.0  # BP3's signs: a normal fault's slip is negative
    events = station_events(rows[:, 0], sign * rows[:, 1], rows[:, 2])
    # the surface files come from another of FDRA's runs (another modeler, date and time steps): each station's
    # coseismic offsets from its own series, matched to ours by their order in the settled supercycle
    events["surface_offset_m"] = {}
    for name in SURFACE:
        _, _, surface_rows = read_seas(folder / f"cattania_srfst_fn_{name}_{code}.txt")
        # BP3's signs, as faultslip's surface offsets are kept (our_series turns a normal fault's to them)
        events["surface_offset_m"][name] = surface_offsets(surface_rows[:, 0], surface_rows[:, 1:3],
                                                           surface_rows[:, 3:5])
    events["files"] = [f"cattania_fltst_dp075_{code}.txt"] + [f"cattania_srfst_fn_{name}_{code}.txt" for name in SURFACE]
    events["modelers"] = sorted({header.get("modeler", "")} | {read_seas(folder / f"cattania_srfst_fn_p0_{code}.txt")[0]
                                                              .get("modeler", "")})
    events["code"] = header.get("code", "fdra")
    events["element_size"] = header.get("element size", "")
    return events


def our_series(scene, element_size: float, years: float, rtol: float | None) -> dict:
    scene = scene.at_element_size(element_size)
    scene.duration = years * YEAR
    scene.rtol = rtol or scene.rtol
    scene.stations = (7500.0,)
    scene.surface_stations = tuple(SURFACE.values())
    started_cpu, started = time.process_time(), time.perf_counter()
    run = scene.run()
    cpu, wall = time.process_time() - started_cpu, time.perf_counter() - started
    sign = 1.0 if scene.fault.sense == "thrust" else -1.0
    surface = {name: sign * run.plane_strain["surface_displacement"][:, :, k] for k, name in enumerate(SURFACE)}
    events = station_events(run.station_time, np.asarray(run.stations["slip"])[:, 0],
                            np.asarray(run.stations["log10_slip_rate"])[:, 0], surface)
    events.update(element_size_m=element_size, elements=scene.fault.count, steps=run.steps, wall_s=wall, cpu_s=cpu,
                  cpu_s_per_year=cpu / years, resolution=scene.resolution, rtol=scene.rtol)
    return events


def antiplane_cost(elements: int, years: float, rtol: float) -> dict:
    """BP1 (the antiplane fault) on ``elements`` elements for ``years`` at ``rtol``: CPU seconds per simulated
    year."""
    scene = read_fault_2d_scene(ROOT / "configs" / "seas_bp1.toml").at_element_size(40e3 / elements)
    scene.duration = years * YEAR
    scene.rtol = rtol
    started = time.process_time()
    run = scene.run()
    cpu = time.process_time() - started
    return {"elements": elements, "years": years, "rtol": rtol, "steps": run.steps, "cpu_s_per_year": cpu / years}


def _period(intervals: np.ndarray, tolerance: float = 2e-3) -> int:
    """The supercycle's period: the shortest p up to 8 whose last 2p intervals repeat with period p to
    ``tolerance`` (relative); 0 if none. Two cycles in view, not classify's three: BP3's 1500 yr hold two and a
    half of the thrust's period-4 supercycle after its spin-up."""
    for period in range(1, 9):
        if intervals.size < 2 * period:
            break
        window = intervals[-2 * period:]
        if np.max(np.abs(window[period:] - window[:period])) <= tolerance * window.mean():
            return period
    return 0


def _aligned(mine: np.ndarray, theirs: np.ndarray, period: int) -> tuple[np.ndarray, np.ndarray]:
    """The last 2 ``period`` values of each, ``theirs`` shifted by up to ``period`` - 1 places to the phase that
    matches ``mine`` best: a run that skipped or added a transient event is in another phase of one supercycle."""
    span = min(2 * max(period, 1), mine.size, theirs.size)
    tail = mine[mine.size - span:]
    best = None
    for shift in range(max(period, 1)):
        end = theirs.size - shift
        if end - span < 0:
            break
        other = theirs[end - span:end]
        worst = float(np.max(np.abs(tail / other - 1)))
        if best is None or worst < best[0]:
            best = (worst, other)
    return tail, best[1]


def compare(ours: dict, peer: dict) -> dict:
    """Differences from the peer's: over events matched in order (the transient's first events included), and over
    the settled supercycle, phase-aligned (:func:`_aligned`); and each one's period."""
    count = min(len(ours["start_yr"]), len(peer["start_yr"]))
    mine, theirs = np.array(ours["start_yr"]), np.array(peer["start_yr"])
    periods = [_period(np.diff(mine)), _period(np.diff(theirs))]
    period = max(periods[1], 1)
    settled_mine, settled_theirs = _aligned(np.diff(mine), np.diff(theirs), period)
    slip_mine, slip_theirs = _aligned(np.array(ours["slip_m"]), np.array(peer["slip_m"]), period)
    offsets = {}
    for name in SURFACE:  # each component's coseismic offset over the settled supercycle, phase-aligned
        a = np.array(ours["surface_offset_m"][name])
        b = np.array(peer["surface_offset_m"][name])
        worst = 0.0
        for component in range(2):
            x, y = _aligned(a[:, component], b[:, component], period)
            worst = max(worst, float(np.max(np.abs(x - y)) / np.max(np.abs(b))))
        offsets[name] = worst
    return {"events_matched": count, "event_count": [mine.size, theirs.size],
            "in_order_time_difference_yr": float(np.max(np.abs(mine[:count] - theirs[:count]))),
            "in_order_interval_difference": float(np.max(np.abs(np.diff(mine[:count]) / np.diff(theirs[:count]) - 1))),
            "settled_interval_difference": float(np.max(np.abs(settled_mine / settled_theirs - 1))),
            "settled_slip_difference": float(np.max(np.abs(slip_mine / slip_theirs - 1))),
            "surface_offset_difference": offsets, "period": periods}


def recompare(path: Path, peer: Path | None = None) -> None:
    """Recompute every comparison of a results file from the series it holds (no run); with ``peer``, the peer's
    series are read again from its files first."""
    results = json.loads(path.read_text(encoding="utf-8"))
    for name, case in results["cases"].items():
        if peer is not None:
            case["peer"] = peer_series(peer, CASES[name][0])
        for run in case["runs"]:
            run["against_peer"] = compare(run, case["peer"])
        finest = case["runs"][-1]
        for run in case["runs"][:-1]:
            period = max(run["against_peer"]["period"][1], 1)
            a, b = _aligned(np.diff(run["start_yr"]), np.diff(finest["start_yr"]), period)
            run["settled_interval_difference_from_finest"] = float(np.max(np.abs(a / b - 1)))
    path.write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--peer", type=Path, help="folder with FDRA's BP3-QD files (see above)")
    parser.add_argument("--recompare", action="store_true", help="recompute the comparisons in --out, no runs")
    parser.add_argument("--sizes", type=float, nargs="+", default=[100.0, 50.0, 25.0])
    parser.add_argument("--years", type=float, default=1500.0)
    parser.add_argument("--cases", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--rtol", type=float, default=None, help="the integrator's tolerance (default: the scenes')")
    parser.add_argument("--out", type=Path, default=HERE / "results" / "seas_bp3.json")
    args = parser.parse_args(argv)
    if args.recompare:
        recompare(args.out, args.peer)
        print(f"recompared {args.out}")
        return 0
    if args.peer is None:
        parser.error("--peer DIR is needed (the folder with FDRA's files), or --recompare")
    results = {"cases": {}}
    for case in args.cases:
        code, config = CASES[case]
        scene = read_fault_2d_scene(ROOT / config)
        peer = peer_series(args.peer, code)
        rows = []
        for size in args.sizes:
            ours = our_series(scene, size, args.years, args.rtol)
            ours["against_peer"] = compare(ours, peer)
            period = ours["against_peer"]["period"][0]
            mean, each = sequence_discretisation(ours["resolution"], max(period, 1))
            ours["declared_resolution_error"] = {"mean": mean, "interval": each}
            rows.append(ours)
            print(f"{case} {size:g} m: {ours['steps']} steps, {ours['cpu_s']:.0f} s CPU; against FDRA: settled "
                  f"intervals {ours['against_peer']['settled_interval_difference']:.2%}, slip "
                  f"{ours['against_peer']['settled_slip_difference']:.2%}", flush=True)
        results["cases"][case] = {"config": config, "peer": {k: v for k, v in peer.items()}, "runs": rows}
    results["antiplane_cost"] = [antiplane_cost(run["elements"], 150.0, run["rtol"])
                                 for run in results["cases"][args.cases[0]]["runs"]]
    results.update(stamp())
    args.out.write_text(json.dumps(results, indent=1) + "\n", encoding="utf-8")
    recompare(args.out)  # and each coarser size against the finest
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
