"""The 2-D fault's discretisation error on faults that never shaped its bound: the ladder's held-out designs at
3, 6 and 12 elements per L_b (issue 68; the bound is issue 42's).

    python benchmarks/fault_2d_resolution_designs.py [--workers 2] [--quick]

The bound of :func:`faultslip.models.fault_2d.analysis.discretisation_error` was measured on three faults
(``benchmarks/fault_2d_resolution.py``). The ladder's 34 held-out designs (``benchmarks/results/ladder_designs.json``,
drawn at random over the calibration box, buried and surface-breaking) are
faults it never saw. Each runs as :func:`faultslip.models.fault_2d.calibration.run_design` runs it, over the same
window, at 3 (the ladder's resolution), 6 and 12 elements per L_b = G D_c / (sigma_n b). Every run is the same
fault: its depth extent and its profile's one-element steps are those of the 3 per L_b run (a design built at
each size on its own moves its creeping base by up to an element, and that alone moved one fault's recurrence
more than its element size did). The 3 per L_b run must reproduce the row saved in ladder_designs.json
(recurrence and mean slip to 1e-9), or the script stops.

Per fault: the **reference** is the Richardson limit of the three runs where all three settled into the same
kind of sequence (the same period, and partial events interleaving in all or none: :func:`ladder_regimes.interleaves`)
and the order they show lies in (1, 5.5); else the 12 per L_b run. Each run's **error** in recurrence and mean slip
against it, and whether its kind is the reference's. ``--quick``: the first 8 designs.

**The one slider's ranges** (``ladder``): the shipped 95 % ranges (``data/ladder_calibration.json``) were
fitted and tested on 3 per L_b answers. Here each held-out fault inside the box is read against its 3 per L_b
answer and against its reference: does a range that holds the coarse answer hold the resolved one?

``--reuse`` rebuilds the summaries from the saved runs without running them again.

Writes ``benchmarks/results/fault_2d_resolution_designs.json``.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from concurrent.futures import as_completed
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.io.processes import stop_pool, worker_pool  # noqa: E402
from faultslip.models.fault_2d.calibration import Design, run_design  # noqa: E402
from ladder_regimes import interleaves  # noqa: E402
from provenance import stamp  # noqa: E402

RAW = ROOT / "benchmarks" / "results" / "ladder_designs.json"
OUT = ROOT / "benchmarks" / "results" / "fault_2d_resolution_designs.json"
#: elements per L_b: the ladder's, and twice and four times finer
RESOLUTIONS = (3.0, 6.0, 12.0)
#: the same run twice agrees to round-off; the saved row is a run of the same code on the same design
REPRODUCED = 1e-9


def _run(job):
    design, resolution = job
    return design.name, resolution, run_design(design, cycles=6, elements_per_process_zone=resolution,
                                               geometry_resolution=RESOLUTIONS[0])


def kind(row: dict) -> tuple:
    """A run's kind of sequence: (settled, period, partial events interleave)."""
    return row["sequence"] == "periodic", row["period"], interleaves(row)


def summary_of_run(row: dict) -> dict:
    return {"sequence": row["sequence"], "period": row["period"], "interleaves": interleaves(row),
            "events": row["events"], "system_events": row["system_events"], "elements": row["elements"],
            "recurrence": row["recurrence_2d"], "mean_slip": row["mean_slip_2d"], "spread": row["spread_2d"],
            "intervals": row["intervals"], "cpu_time": row["cpu_time"]}


def richardson(values: list[float], ratio: float = 2.0) -> tuple[float, float]:
    """(the limit, the order) of three values at resolutions in a constant ``ratio``; (finest, nan) where the order
    is not in (1, 5.5): not in the asymptotic range."""
    coarse, fine, finest = values
    if fine == finest or (coarse - fine) / (fine - finest) <= 0:
        return finest, math.nan
    order = math.log((coarse - fine) / (fine - finest)) / math.log(ratio)
    if not 1.0 < order < 5.5:
        return finest, order
    return finest + (finest - fine) / (ratio ** order - 1.0), order


def fault_entry(design: Design, runs: dict[float, dict]) -> dict:
    """One fault's runs, reference and errors (``runs`` by resolution)."""
    kinds = {resolution: kind(row) for resolution, row in runs.items()}
    finest = runs[RESOLUTIONS[-1]]
    same = len(set(kinds.values())) == 1 and kinds[RESOLUTIONS[-1]][0]
    entry = {"name": design.name, "width_over_nucleation": design.width_over_nucleation,
             "a_over_b": design.a / design.b, "cap": design.cap, "same_kind": same, "runs": {}}
    for quantity, key in (("recurrence", "recurrence_2d"), ("mean_slip", "mean_slip_2d")):
        values = [runs[r][key] for r in RESOLUTIONS]
        limit, order = richardson(values) if same else (finest[key], math.nan)
        entry[f"reference_{quantity}"], entry[f"order_{quantity}"] = limit, order
    for resolution, row in runs.items():
        entry["runs"][f"{resolution:g}"] = {
            **summary_of_run(row), "kind_of_reference": kinds[resolution] == kinds[RESOLUTIONS[-1]],
            "error_recurrence": abs(row["recurrence_2d"] / entry["reference_recurrence"] - 1),
            "error_mean_slip": abs(row["mean_slip_2d"] / entry["reference_mean_slip"] - 1)}
    return entry


def summarise(faults: list[dict]) -> dict:
    """Per resolution below the finest: how many runs keep the reference's kind, and the largest error among them
    and among those that do not."""
    out = {"faults": len(faults), "same_kind_at_every_resolution": sum(f["same_kind"] for f in faults)}
    for resolution in RESOLUTIONS[:-1]:
        runs = [f["runs"][f"{resolution:g}"] for f in faults
                if f["runs"][f"{RESOLUTIONS[-1]:g}"]["sequence"] == "periodic"]
        kept = [r for r in runs if r["kind_of_reference"] and r["sequence"] == "periodic"]
        changed = [r for r in runs if not r["kind_of_reference"]]
        out[f"{resolution:g}"] = {
            "runs": len(runs), "kept_kind": len(kept), "changed_kind": len(changed),
            "largest_error_kept": max((r["error_recurrence"] for r in kept), default=None),
            "largest_error_changed": max((r["error_recurrence"] for r in changed), default=None),
            "changed_interleaving_coarse": sum(r["interleaves"] for r in changed)}
    return out


def ladder_ranges(saved: list[dict], faults: list[dict]) -> dict:
    """Per quantity: of the held-out faults inside the box, how many of the shipped ranges hold the 3 per L_b
    answer, and how many the reference (the resolved answer)."""
    from faultslip.fault import ladder
    from ladder_calibration import prepared

    table = ladder.load_calibration()
    by_name = {fault["name"]: fault for fault in faults}
    out = {}
    for quantity in ("recurrence", "mean_slip"):
        coarse, resolved, names = [], [], []
        for row in saved:
            item = prepared(row)
            if item is None or ladder.outside_box(item["group"], table):
                continue
            fault = by_name[item["name"]]
            raw = item["block"]["recurrence" if quantity == "recurrence" else "slip"]
            band = ladder.predict(quantity, raw, item["group"], table)
            inside = [band["low"] <= value <= band["high"] for value in
                      (item["two_d"][quantity], fault[f"reference_{quantity}"])]
            coarse.append(inside[0])
            resolved.append(inside[1])
            if inside[0] != inside[1]:
                names.append(item["name"])
        out[quantity] = {"faults": len(coarse), "hold_coarse": int(sum(coarse)), "hold_resolved": int(sum(resolved)),
                         "differ": names}
    return out


def _as_row(name: str, run: dict) -> dict:
    """A saved run's summary as run_design's row (``--reuse``)."""
    return {"design": {"name": name}, "sequence": run["sequence"], "period": run["period"], "events": run["events"],
            "system_events": run["system_events"], "elements": run["elements"], "recurrence_2d": run["recurrence"],
            "mean_slip_2d": run["mean_slip"], "spread_2d": run["spread"], "intervals": run["intervals"],
            "cpu_time": run["cpu_time"]}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--quick", action="store_true", help="the first 8 held-out designs")
    parser.add_argument("--reuse", action="store_true", help="the saved runs, summarised again")
    args = parser.parse_args(argv)
    saved = [row for row in json.loads(RAW.read_text())["rows"] if row["design"]["name"].startswith("held out")]
    saved = saved[:8] if args.quick else saved
    designs = {row["design"]["name"]: Design(**row["design"]) for row in saved}
    if args.reuse:
        kept = {fault["name"]: fault for fault in json.loads(OUT.read_text())["faults"]}
        runs = {name: {float(r): _as_row(name, run) for r, run in kept[name]["runs"].items()}
                for name in designs}
        return finish(saved, designs, runs)
    # the finest runs first: the longest jobs start while the pool is full
    jobs = [(design, resolution) for resolution in reversed(RESOLUTIONS) for design in designs.values()]
    runs: dict[str, dict[float, dict]] = {name: {} for name in designs}
    pool = worker_pool(min(args.workers, len(jobs)))
    try:
        for future in as_completed([pool.submit(_run, job) for job in jobs]):
            name, resolution, row = future.result()
            runs[name][resolution] = row
            print(f"{name} at {resolution:g} per L_b: {row['sequence']} (period {row['period']}), interleaves "
                  f"{interleaves(row)}, T {row['recurrence_2d'] / 3.15576e7:.5g} yr, {row['cpu_time']:.0f} s CPU",
                  flush=True)
    finally:
        stop_pool(pool)
    return finish(saved, designs, runs)


def finish(saved: list[dict], designs: dict, runs: dict) -> None:
    """Summarise and write (the runs first, so a failed check keeps them: ``--reuse``); check the 3 per L_b runs
    against the saved rows."""
    faults = [fault_entry(designs[name], runs[name]) for name in designs]
    summary = summarise(faults)

    def write():
        OUT.write_text(json.dumps({**stamp(), "resolutions": RESOLUTIONS, "summary": summary, "faults": faults},
                                  indent=1) + "\n", encoding="utf-8")

    write()
    for row in saved:
        again = runs[row["design"]["name"]][RESOLUTIONS[0]]
        for key in ("recurrence_2d", "mean_slip_2d"):
            if not abs(again[key] / row[key] - 1) <= REPRODUCED:
                raise SystemExit(f"{row['design']['name']}: {key} {again[key]!r} does not reproduce the saved "
                                 f"{row[key]!r} (ladder_designs.json)")
    summary["ladder"] = ladder_ranges(saved, faults)
    write()
    print(json.dumps(summary, indent=1))
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
