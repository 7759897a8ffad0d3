"""The 3-D fault's declared square-size error on faults it was not fitted on: drawn patches at 100, 50 and 25 m
(about 2-3.5, 4.5-7 and 9-14 squares per L_b), each run's error against the fault's resolved answer, and whether the
kind of sequence changes with the square size.

    python benchmarks/fault_3d_resolution.py [--seed 7401] [--count 8] [--workers 2]
    python benchmarks/fault_3d_resolution.py --reuse --sizes 25 --only 1 2 3 4 6 7   # 25 m runs of six (5-12 min each)
    python benchmarks/fault_3d_resolution.py --seed 7403 --count 5 --sizes 100 50 25 --out FRESH   # see below

:data:`faultslip.models.fault_3d.family.DISCRETISATION` was fitted on one fault, SEAS BP5-QD at 2000, 1000 and
500 m. On the 2-D fault, runs changed their kind of sequence with the element size near bifurcations, which one
run cannot see (``faultslip.models.fault_2d.analysis.KIND_CHANGE_TERM``); the 3-D fault reports that term and does
not add it, and no 3-D run had measured a change. Here each fault is BP5 at 1/20 (``fault_3d_model_error.py``'s
cells, ``configs/fault_3d_small.toml``) with a patch drawn over that benchmark's held-out box (L / W 1.2-7.5, W
450-750 m, its top at 200-400 m) and D_c set by a W / h* drawn over 1.2-2 (the nucleation patch's with it), so the
squares per L_b move too. Every fault's geometry is rounded to 100 m, so its three runs are the same fault.

Each run is ``faultslip.run`` of the scene, read as a user reads it: recurrence, slip per event, the sequence, and
the declared error. Per fault the **reference** is the Richardson limit of its three runs where they settled into
the same kind (periodic, or the same period) and show an order in (0.5, 5.5), and a run may differ from it by its
declared ``estimated_relative_error``; else it is the finest run, and a coarser run may differ from it by the two
runs' declared errors added (a larger difference shows one of them untrue). A run's declared error is read with the
square size's bound as declared now, so ``margin_needed``, the least margin on that bound that covers every run,
sets it. A **change of kind** is a run whose kind
is not the finest run's. Slip per event is judged the same way against its own declared error
(``slip_per_event_error``); no fault's slip shows a Richardson order. Each run's cost estimate
(``faultslip.models.estimate``) is saved beside the CPU it used.

``--reuse`` keeps the runs already saved for the same inputs. Writes
``benchmarks/results/fault_3d_resolution.json`` after every run, or ``--out``'s file: the faults of seed 7403,
drawn after :data:`DISCRETISATION`'s margin was set from seed 7401's, are its held-out check
(``benchmarks/results/fault_3d_resolution_fresh.json``), and those of seed 7405, drawn sessions later with nothing
refitted since, a second (``fault_3d_resolution_fresh_second.json``).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from concurrent.futures import as_completed
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(ROOT))
from fault_2d_resolution_designs import richardson  # noqa: E402  (three sizes halving: limit and order)
from fault_3d_model_error import buried_draw, scene_text  # noqa: E402
from provenance import stamp  # noqa: E402

from faultslip.io.processes import stop_pool, worker_pool  # noqa: E402
from faultslip.models.fault_3d.family import (DISCRETISATION, SLIP_DISCRETISATION,  # noqa: E402
                                              discretisation_error)
from faultslip.models.fault_2d.integrate import YEAR  # noqa: E402

OUT = HERE / "results" / "fault_3d_resolution.json"
#: square sizes (m), coarsest first; the geometry is rounded to the coarsest
SIZES = (100.0, 50.0, 25.0)
#: W / h* (the widest velocity-weakening extent down dip over h*): below about 1.2 the patch creeps without events
WIDTH_OVER_NUCLEATION = (1.2, 2.0)
#: the 100 m squares' fewest per L_b: above the 2 below which the 3-D fault declares nothing
LOWEST_RESOLUTION = 2.2
YEARS = 120.0
#: the Richardson order's window (fault_2d_resolution_designs.richardson's upper end): outside it the three runs are
#: not in the asymptotic range
ORDERS = (0.5, 5.5)


def draw(seed: int, count: int) -> list[dict]:
    """``count`` faults: a buried patch over fault_3d_model_error's held-out box, and D_c set by a W / h* drawn
    uniform over :data:`WIDTH_OVER_NUCLEATION` (redrawn where that puts the 100 m squares below
    :data:`LOWEST_RESOLUTION` per L_b)."""
    from faultslip.models.fault_3d.scene import parse_fault_3d_scene

    rng = np.random.default_rng(seed)
    faults = []
    while len(faults) < count:
        ratio, height, top = buried_draw(rng, SIZES[0])
        target = rng.uniform(*WIDTH_OVER_NUCLEATION)
        fault = {"aspect": ratio, "height_m": height, "top_m": top, "critical_slip_factor": 1.0}
        plain = parse_fault_3d_scene(fault_text(fault, SIZES[0]), "draw", allow_large=True).fault
        # h* and L_b both scale with D_c
        factor = plain.seismogenic_width() / plain.nucleation_size() / target
        if plain.process_zone() * factor / SIZES[0] < LOWEST_RESOLUTION:
            continue
        faults.append({"name": f"drawn {len(faults)}", **fault, "critical_slip_factor": float(np.round(factor, 3))})
    return faults


def fault_text(fault: dict, size: float) -> str:
    """A drawn fault's scene on squares of ``size`` m, its geometry rounded to the coarsest (its 100 m squares)."""
    return scene_text(fault["aspect"], fault["height_m"], fault["top_m"], size, YEARS,
                      critical_slip_factor=fault["critical_slip_factor"], geometry_element_size=SIZES[0])


def _run(job) -> tuple[str, float, dict]:
    """One fault at one square size, through the library as a user runs it: its estimate first, then the run."""
    import faultslip
    from faultslip.fault.strike_error import groups_of
    from faultslip.models import estimate as estimate_of
    from faultslip.models.fault_3d.family import summarise
    from faultslip.models.fault_3d.scene import parse_fault_3d_scene

    fault, size = job
    scene = parse_fault_3d_scene(fault_text(fault, size), fault["name"], allow_large=True)
    estimate = estimate_of(scene).seconds
    started = time.process_time()
    result = faultslip.run(scene, allow_large=True)
    values = result.values

    def number(key):  # the family's stored SI number, None where it is not finite
        value = result.si(key)
        return float(value) if value is not None and math.isfinite(value) else None
    return fault["name"], size, {
        "element_size_m": size, "elements": scene.fault.count, "resolution": number("resolution"),
        "width_over_nucleation": groups_of(scene.fault)["width_over_nucleation"],
        "sequence": str(values["sequence"]),
        "recurrence_yr": None if number("recurrence_interval") is None else number("recurrence_interval") / YEAR,
        "slip_per_event_m": number("slip_per_event"), "events": int(values["events"]),
        "system_events": int(values["system_size_events"]), "declared": number("estimated_relative_error"),
        "discretisation_error": number("discretisation_error"), "kind_change_error": number("kind_change_error"),
        "sequence_error": number("sequence_error"), "slip_declared": number("slip_per_event_error"),
        "slip_sequence_error": number("slip_sequence_error"), "rtol": number("rtol"), "steps": int(values["steps"]),
        "intervals_yr": [float(v) / YEAR for v in summarise(result.extras["run"])["intervals"]],
        "estimated_steps": scene.expected_steps(), "estimated_cpu_s": estimate,
        "cpu_time_s": time.process_time() - started}


def declared_now(run: dict) -> float | None:
    """A run's declared recurrence error with the square size's bound as declared now (the sequence's and 10 rtol
    as the run declared them): a change of :data:`DISCRETISATION` is read without running again."""
    if run["declared"] is None or run["discretisation_error"] is None:
        return None
    return run["declared"] - run["discretisation_error"] + discretisation_error(run["resolution"])


def margin_needed(faults: list[dict]) -> float:
    """The least margin on the square size's bound (scale r^-order of :data:`DISCRETISATION`) at which every
    coarser run lies within what it may differ by (:func:`judged`): each run's sequence and rtol terms kept."""
    scale, order = DISCRETISATION["scale"], DISCRETISATION["order"]
    needed = 0.0
    for fault in faults:
        finest = fault["runs"][f"{min(fault['sizes_m']):g}"]
        for row in fault["errors"]:
            if row["error_recurrence"] is None:
                continue
            pair = [fault["runs"][f"{row['element_size_m']:g}"]]
            if not fault["richardson_recurrence"]:
                pair.append(finest)
            rest = sum(run["declared"] - run["discretisation_error"] for run in pair)
            needed = max(needed, (row["error_recurrence"] - rest) / sum(scale * run["resolution"] ** -order
                                                                         for run in pair))
    return needed


def slip_declared(run: dict) -> float | None:
    """A run's declared error in slip per event; for a run saved before the family declared one, the square size's
    bound alone (its sequence and rtol terms left out, which only tightens a check against it)."""
    if "slip_declared" in run:
        return run["slip_declared"]
    return discretisation_error(run["resolution"], SLIP_DISCRETISATION)


def settled(run: dict) -> bool:
    return run["sequence"] == "periodic" or run["sequence"].startswith("period_")


def judged(fault: dict) -> dict:
    """A fault's reference, and each run's error against it, what it may be off by, and its kind.

    With three sizes in one settled kind whose order lies in :data:`ORDERS`, the reference is their Richardson
    limit and a run may be off by its own declared error. Otherwise the reference is the finest run, itself off by
    up to its declared error: a coarser run may then differ from it by the two declared errors added, and a larger
    difference shows that one of the two is not true."""
    sizes = sorted((float(size) for size in fault["runs"]), reverse=True)
    runs = [fault["runs"][f"{size:g}"] for size in sizes]
    finest = runs[-1]
    same_kind = all(settled(run) and run["sequence"] == finest["sequence"] for run in runs)
    entry = {**fault, "sizes_m": sizes, "same_kind": same_kind}
    for quantity, key in (("recurrence", "recurrence_yr"), ("slip", "slip_per_event_m")):
        values = [run[key] for run in runs]
        limit, order = ((richardson(values[-3:], slowest=ORDERS[0]) if len(values) >= 3 and same_kind
                         else (values[-1], math.nan))
                        if None not in values else (None, math.nan))
        entry[f"reference_{quantity}"] = limit
        entry[f"order_{quantity}"] = None if not math.isfinite(order) else order
        entry[f"richardson_{quantity}"] = bool(same_kind and ORDERS[0] < order < ORDERS[1])
    errors = []
    for size, run in zip(sizes, runs):
        row = {"element_size_m": size, "resolution": run["resolution"], "declared": run["declared"],
               "kind_kept": run["sequence"] == finest["sequence"] and settled(run) == settled(finest),
               "sequence": run["sequence"]}
        for quantity, key in (("recurrence", "recurrence_yr"), ("slip", "slip_per_event_m")):
            reference = entry[f"reference_{quantity}"]
            row[f"error_{quantity}"] = (None if reference is None or run[key] is None
                                        or (run is finest and not entry[f"richardson_{quantity}"])
                                        else abs(run[key] / reference - 1.0))
        if entry["richardson_recurrence"] or run is finest:
            row["allowed"] = declared_now(run)
        else:
            row["allowed"] = None if None in (declared_now(run), declared_now(finest)) else \
                declared_now(run) + declared_now(finest)
        row["holds"] = (None if row["error_recurrence"] is None or row["allowed"] is None
                        else row["error_recurrence"] <= row["allowed"])
        mine, finest_slip = slip_declared(run), slip_declared(finest)
        row["allowed_slip"] = (mine if entry["richardson_slip"] or run is finest else
                               None if None in (mine, finest_slip) else mine + finest_slip)
        row["holds_slip"] = (None if row["error_slip"] is None or row["allowed_slip"] is None
                             else row["error_slip"] <= row["allowed_slip"])
        errors.append(row)
    entry["errors"] = errors
    return entry


def summary(faults: list[dict]) -> dict:
    judged_faults = [judged(fault) for fault in faults if len(fault["runs"]) >= 2]
    rows = [row for fault in judged_faults for row in fault["errors"]]
    per_size = {}
    for size in SIZES:
        mine = [row for row in rows if row["element_size_m"] == size]
        measured = [row for row in mine if row["holds"] is not None]
        per_size[f"{size:g}"] = {
            "runs": len(mine), "kind_changed": sum(not row["kind_kept"] for row in mine),
            "measured": len(measured), "holds": sum(row["holds"] for row in measured),
            "resolutions": [min(row["resolution"] for row in mine), max(row["resolution"] for row in mine)]
            if mine else None,
            "largest_error_recurrence": max((row["error_recurrence"] for row in measured), default=None),
            "largest_error_slip": max((row["error_slip"] for row in mine if row["error_slip"] is not None),
                                      default=None),
            "largest_share_of_allowed": max((row["error_recurrence"] / row["allowed"] for row in measured),
                                            default=None),
            "measured_slip": sum(row.get("holds_slip") is not None for row in mine),
            "holds_slip": sum(bool(row.get("holds_slip")) for row in mine),
            "largest_share_of_allowed_slip": max((row["error_slip"] / row["allowed_slip"] for row in mine
                                                  if row.get("holds_slip") is not None), default=None)}
    runs = [run for fault in faults for run in fault["runs"].values() if "estimated_cpu_s" in run]
    ratios = [run["estimated_cpu_s"] / run["cpu_time_s"] for run in runs]
    cost = {"runs": len(runs), "estimate_over_cpu": [min(ratios), max(ratios)] if ratios else None,
            "within_2x": sum(0.5 <= ratio <= 2.0 for ratio in ratios),
            "steps_estimate_over_measured": [min(r["estimated_steps"] / r["steps"] for r in runs),
                                             max(r["estimated_steps"] / r["steps"] for r in runs)] if runs else None}
    return {"fault_count": len(judged_faults), "same_kind": sum(fault["same_kind"] for fault in judged_faults),
            "margin_needed": margin_needed(judged_faults), "margin": DISCRETISATION["margin"],
            "richardson": sum(fault["richardson_recurrence"] for fault in judged_faults),
            "per_size": per_size, "cost": cost, "judged": judged_faults}


def write(seed: int, faults: list[dict], out: Path = OUT) -> None:
    # every drawn fault's runs are in "judged" (a fault with fewer than two sizes run is left out)
    result = {"seed": seed, "years": YEARS, **summary(faults), **stamp()}
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=7401)
    parser.add_argument("--count", type=int, default=8)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--reuse", action="store_true", help="keep the runs saved for the same inputs")
    parser.add_argument("--sizes", type=float, nargs="+", default=SIZES[:2],
                        help="square sizes (m) to run, of %(default)s's and 25 m (a 25 m run takes 5-12 min)")
    parser.add_argument("--only", type=int, nargs="+", help="run --sizes on these faults only (their indices)")
    parser.add_argument("--out", type=Path, default=OUT, help="results file (a fresh draw's own, not the fitted)")
    args = parser.parse_args(argv)
    faults = draw(args.seed, args.count)
    if args.reuse and args.out.is_file():
        saved = {json.dumps({k: f[k] for k in ("aspect", "height_m", "top_m", "critical_slip_factor")}): f["runs"]
                 for f in json.loads(args.out.read_text(encoding="utf-8"))["judged"]}
        for fault in faults:
            fault["runs"] = dict(saved.get(json.dumps({k: fault[k] for k in ("aspect", "height_m", "top_m",
                                                                              "critical_slip_factor")}), {}))
    for fault in faults:
        fault.setdefault("runs", {})
    # the finest (longest) runs first, so that the workers end together
    chosen = [faults[index] for index in args.only] if args.only else faults
    # a run saved before the family declared its slip's error is run again, and an unsettled one saved before it
    # read the intervals after the spin-up (saved with them since)
    def stale(run: dict) -> bool:
        return "slip_declared" not in run or (run["sequence"] == "unsettled" and "intervals_yr" not in run)
    jobs = [(fault, size) for size in sorted(args.sizes) for fault in chosen
            if stale(fault["runs"].get(f"{size:g}", {"sequence": ""}))]
    by_name = {fault["name"]: fault for fault in faults}
    pool = worker_pool(min(args.workers, max(len(jobs), 1)))
    try:
        for future in as_completed([pool.submit(_run, job) for job in jobs]):
            name, size, run = future.result()
            by_name[name]["runs"][f"{size:g}"] = run
            write(args.seed, faults, args.out)
            print(f"{name} at {size:g} m ({run['resolution']:.3g} per L_b): {run['sequence']}, "
                  f"T {run['recurrence_yr']} yr, declared {run['declared']}, {run['cpu_time_s']:.0f} s CPU",
                  flush=True)
    finally:
        stop_pool(pool)
    write(args.seed, faults, args.out)
    print(json.dumps({k: v for k, v in summary(faults).items() if k != "judged"}, indent=1))


if __name__ == "__main__":
    main()
