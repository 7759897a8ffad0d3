"""The 3-D fault's cost model, fitted on 3-D faults of every kind the rung builds and tested on a draw it never saw.

    python benchmarks/fault_3d_cost.py --part fit        # the fit runs, and the cost model's constants (about 15 min)
    python benchmarks/fault_3d_cost.py --part held-out   # the held-out draw, estimated by the shipped model (about 15 min)
    python benchmarks/fault_3d_cost.py --part rtol       # the steps against rtol (about a minute)
    python benchmarks/fault_3d_cost.py --part re-estimate  # the saved runs' estimates again, nothing rerun
    python benchmarks/fault_3d_cost.py --part fresh --seed 7321  # a fresh draw against the shipped model (about 10 min)

The model (faultslip.models.fault_3d.cost) had been fitted on SEAS BP5-QD alone, whose three runs change the squares
along strike and down dip together. It estimated a 2-D scene's 3-D fault (configs/fault_2d_small.toml, 282 x 80
squares) at 4.5 times its CPU and a surface-breaking patch twice as wide as BP5's at half of its CPU (short: the
budget would have let it start). Here:

- ``fit``: 3-D faults of each kind the rung builds, run one after another in one process: BP5 at 2000 and 1000 m;
  patches of BP5 at 1/20 (benchmarks/fault_3d_model_error.py's cells: L / W 2-16, buried and breaking the surface,
  W / h* 1.2-2.6, on 100 and 50 m squares); configs/fault_3d_small.toml; and 2-D scenes read as 3-D faults
  (configs/fault_2d_surface_small.toml at 3 km on 100 and 50 m elements, configs/fault_2d_small.toml at 50 km, and
  configs/fault_2d_dipping_small.toml at 4 km: a dipping fault, whose step also turns the normal stress). Each
  records what the estimate reads before the run (its squares, expected events, W / h*, rtol) and what the run
  used (steps; CPU, its operator's assembly timed apart). The steps are machine-independent, so the steps of every
  cell fault_3d_model_error.json records are fitted too, and those of fault_3d_resolution.json's draw (eight patches
  at 100, 50 and 25 m); fault_3d_resolution_fresh.json's five patches, never fitted, test the fit. Fitted: ln steps
  = ln A + p ln events + q ln(W / h*) + r ln N_x + u B + s ln R + rtol term (least squares; B the patch's burial,
  its top over its width; R the squares per L_b), the CPU per step c0 + c1 N + c2 k (N_x + 1) N_z^2, k the
  spectral products a force balance makes (2 where the normal stress changes), by relative non-negative least
  squares over the fit runs, and the CPU per dislocation pair of the operator's assembly (the median over the fit
  runs that spent a second or more on it). ``refit`` fits again from the file's runs without running them. ``re-
  estimate`` (after a change to what an estimate reads, such as the recurrence the one slider expects outside its box)
  recomputes each saved run's features and estimate from its scene, on the machine state the runs were measured in
  (factor 1: the group's anchor, ``benchmarks/machine_speed.py``), recomputes the recorded cells' features, and refits
  the steps; their steps and CPU are the runs' own, so nothing is rerun.
- ``rtol``: the steps' power of rtol, which the steps fit takes as the 2-D fault's (-0.18): three of the fit's
  kinds at rtol 1e-5 to 1e-8, each fault's slope of ln steps on ln rtol and the pooled one (about a minute).
- ``held-out``: faults drawn at random (seed 7302) from the same kinds (patches of other shapes and squares, 2-D
  scenes at other lengths, BP5 at other squares), each estimated by the shipped model before it runs, as a user's
  run is, and run: the estimate over the CPU used. The earlier draws (``EARLIER_DRAWS``: 7300, and 7301, whose
  small buried patch the model of its day estimated at 2.96x its CPU, and which led to the burial term) keep the
  estimates of their day; ``re-estimate`` adds the shipped model's.
- ``fresh --seed N``: a draw of the held-out kinds with a seed never used, run after the model was last refitted
  (``FRESH_DRAWS``), each estimated by the shipped model before it runs; kept with the model of its day, and
  ``re-estimate`` adds the shipped model's.

tests/models/fault_3d/test_fault_3d.py refits the constants from the results file and holds the held-out estimates
within 2x of the CPU. Writes benchmarks/results/fault_3d_cost.json.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(HERE))
from fault_3d_model_error import scene_text  # noqa: E402  (its cells, the 1/20 BP5 patches)
from fault_3d_resolution import fault_text  # noqa: E402  (its drawn patches)
from provenance import stamp  # noqa: E402

from faultslip.fault.strike_error import groups_of  # noqa: E402
from faultslip.io import machine  # noqa: E402
from faultslip.models.fault_2d.integrate import YEAR  # noqa: E402
from faultslip.models.fault_2d.scene import read_fault_2d_scene  # noqa: E402
from faultslip.models.fault_3d import cost  # noqa: E402
from faultslip.models.fault_3d.scene import from_two_d, load_fault_3d_scene, parse_fault_3d_scene  # noqa: E402

OUT = HERE / "results" / "fault_3d_cost.json"
CELLS = HERE / "results" / "fault_3d_model_error.json"
#: benchmarks/fault_3d_resolution.py's runs: eight drawn patches at 100, 50 and 25 m (seed 7401) join the steps fit;
#: five more (seed 7403, its held-out check) are the resolution term's held-out check here
RESOLUTION_RUNS = HERE / "results" / "fault_3d_resolution.json"
RESOLUTION_HELD_OUT = HERE / "results" / "fault_3d_resolution_fresh.json"
#: the held-out draw, run after the cost model took the burial (the first, 7300, and a second, 7301, were run before:
#: EARLIER_DRAWS)
HELD_OUT_SEED = 7302
#: earlier held-out draws, kept with the estimates the model of their day made and the shipped model's
EARLIER_DRAWS = (7300, 7301)
#: BP5's squares a later draw picks two of: sizes dividing 100 and 40 km that the fit runs never used; the earlier
#: draws' two were chosen
BP5_SIZES = (2500.0, 1250.0, 800.0, 625.0)
CHOSEN_BP5_SIZES = {7300: (1250.0, 800.0), 7301: (2500.0, 625.0)}
#: fresh draws, each run once after a refit (``--part fresh --seed N``): 7321 after the steps were refitted on the
#: model-error cells' rerun (two cells at 480 yr, two long cells); 7323 after the steps took the squares per L_b;
#: 7325 sessions later, nothing refitted since; 7327 and 7329 on other machines, nothing refitted since; 7331 the first
#: whose estimates took the machine speed record's median, nothing refitted since
FRESH_DRAWS = (7321, 7323, 7325, 7327, 7329, 7331)
CONFIGS = ROOT / "configs"


def cell(ratio: float, height: float, top: float, element_size: float = 100.0, years: float = 120.0):
    return parse_fault_3d_scene(scene_text(ratio, height, top, element_size, years),
                                f"patch {ratio:g} x {height:g} m at {top:g} m on {element_size:g} m", allow_large=True)


def bp5(element_size: float, years: float = 1800.0):
    scene = load_fault_3d_scene(CONFIGS / "seas_bp5.toml", allow_large=True).at_element_size(element_size)
    scene.duration = years * YEAR
    return scene


def two_d(config: str, length_km: float, element_size: float | None = None, years: float | None = None):
    loaded = read_fault_2d_scene(CONFIGS / config, allow_large=True)
    if element_size is not None:
        loaded = loaded.at_element_size(element_size)
    loaded = replace(loaded, fault_length=length_km * 1e3,
                     duration=loaded.duration if years is None else years * YEAR)
    return from_two_d(loaded, allow_large=True)


#: (what, scene builder): each kind of 3-D fault the rung builds
FIT = [
    ("BP5 at 2000 m", lambda: bp5(2000.0)),
    ("BP5 at 1000 m", lambda: bp5(1000.0)),
    ("patch 2 x 800 m at 200 m", lambda: cell(2.0, 800.0, 200.0)),
    ("patch 4 x 600 m at 200 m", lambda: cell(4.0, 600.0, 200.0)),
    ("patch 16 x 600 m at 200 m", lambda: cell(16.0, 600.0, 200.0)),
    ("patch 8 x 1400 m at the surface", lambda: cell(8.0, 1400.0, 0.0, years=480.0)),
    ("patch 4 x 600 m at 200 m on 50 m", lambda: cell(4.0, 600.0, 200.0, 50.0)),
    ("configs/fault_3d_small.toml", lambda: load_fault_3d_scene(CONFIGS / "fault_3d_small.toml", allow_large=True)),
    ("fault_2d_surface_small at 3 km", lambda: two_d("fault_2d_surface_small.toml", 3.0)),
    ("fault_2d_surface_small at 3 km on 50 m", lambda: two_d("fault_2d_surface_small.toml", 3.0, 50.0)),
    ("fault_2d_dipping_small at 4 km, 150 yr", lambda: two_d("fault_2d_dipping_small.toml", 4.0, years=150.0)),
    ("fault_2d_small at 50 km", lambda: two_d("fault_2d_small.toml", 50.0)),
]


def held_out_draw(seed: int = HELD_OUT_SEED) -> list:
    """Fourteen faults of the fit's kinds at shapes it never ran: six patches, five 2-D scenes (one dipping), three
    BP5 sizes."""
    rng = np.random.default_rng(seed)
    draws = []
    for _ in range(6):
        ratio = float(np.exp(rng.uniform(np.log(1.5), np.log(12.0))))
        height = float(rng.choice([400.0, 500.0, 700.0, 900.0, 1100.0, 1300.0]))
        top = float(rng.choice([0.0, 200.0, 300.0]))
        size = float(rng.choice([100.0, 50.0])) if height <= 700.0 and ratio <= 6.0 else 100.0
        years = 120.0 if height <= 800.0 else 360.0
        draws.append((f"patch {ratio:.3g} x {height:g} m at {top:g} m on {size:g} m, {years:g} yr",
                      lambda r=ratio, h=height, t=top, s=size, y=years: cell(r, h, t, s, y)))
    for _ in range(3):
        length = float(rng.uniform(2.0, 10.0))
        size = float(rng.choice([100.0, 50.0])) if length <= 5.0 else 100.0
        draws.append((f"fault_2d_surface_small at {length:.3g} km on {size:g} m",
                      lambda k=length, s=size: two_d("fault_2d_surface_small.toml", k, s)))
    length = float(rng.uniform(15.0, 30.0))
    draws.append((f"fault_2d_small at {length:.3g} km, 300 yr",
                  lambda k=length: two_d("fault_2d_small.toml", k, years=300.0)))
    # BP5 on squares that divide its 100 x 40 km and that the fit never ran: the earlier draws' were chosen; later
    # ones are drawn, from a generator of their own so that the draws above and below stay the seed's
    sizes = CHOSEN_BP5_SIZES.get(seed) or np.random.default_rng([seed, 5]).choice(BP5_SIZES, size=2, replace=False)
    for size in sizes:
        draws.append((f"BP5 at {size:g} m", lambda s=float(size): bp5(s)))
    # its largest operator (20 MB of spectra, beyond the caches), which seas_bp5.py's run took 3x this fit's CPU on
    draws.append(("BP5 at 500 m, 600 yr", lambda: bp5(500.0, 600.0)))
    length = float(rng.uniform(3.0, 6.0))
    draws.append((f"fault_2d_dipping_small at {length:.3g} km, 100 yr",
                  lambda k=length: two_d("fault_2d_dipping_small.toml", k, years=100.0)))
    return draws


def features(scene) -> dict:
    """What the estimate reads before a run."""
    fault = scene.fault
    groups = groups_of(fault)
    return {"strike_count": fault.strike_count, "dip_count": fault.dip_count, "elements": fault.count,
            "products": cost.products(fault), "years": scene.duration / YEAR, "rtol": scene.rtol,
            "expected_events": scene.expected_events(), "width_over_nucleation": groups["width_over_nucleation"],
            "burial": groups["burial"], "resolution": scene.resolution}


def measured(what: str, scene) -> dict:
    row = {"what": what, **features(scene), "estimated_s": scene.estimate().seconds,
           "estimated_assembly_s": cost.assembly_seconds(scene.fault.strike_count, scene.fault.dip_count),
           "machine_factor": machine.factor("fault_3d")}  # what the estimate took for this machine's speed
    with machine.assumed(1.0):  # and the estimate on the machine the costs were anchored on (the test recomputes it)
        row["estimated_anchored_s"] = scene.estimate().seconds
    start = time.process_time()
    scene.operator()  # assembled once, and kept for the run: timed apart, so the steps' CPU is the run's own
    assembled = time.process_time()
    run = scene.run()
    end = time.process_time()
    row.update({"cpu_s": end - start, "assembly_s": assembled - start, "steps_cpu_s": end - assembled,
                "steps": int(run.steps), "events": int(run.event_count)})
    row["estimate_over_cpu"] = row["estimated_s"] / row["cpu_s"]
    print(json.dumps(row), flush=True)
    return row


def recorded_cells() -> list:
    """The cells fault_3d_model_error.json records: their steps, and what their estimate reads."""
    result = json.loads(CELLS.read_text(encoding="utf-8"))
    rows = []
    for row in result["rows"] + result["held_out"]:
        scene = cell(row["aspect"], row["height_m"], row["top_m"], row["element_size_m"], row["years"])
        rows.append({"what": scene.name, **features(scene), "steps": int(row["fault_3d"]["steps"])})
    return rows


def resolution_runs(path: Path = RESOLUTION_RUNS) -> list:
    """benchmarks/fault_3d_resolution.py's runs (``path``): each drawn patch at each square size, its steps and
    CPU, and what its estimate reads (its scene rebuilt as that benchmark built it)."""
    result = json.loads(path.read_text(encoding="utf-8"))
    rows = []
    for fault in result["judged"]:
        for size, run in fault["runs"].items():
            scene = parse_fault_3d_scene(fault_text(fault, float(size)), fault["name"], allow_large=True)
            rows.append({"what": f"seed {result['seed']} {fault['name']} on {float(size):g} m", **features(scene),
                         "steps": int(run["steps"]), "cpu_s": run["cpu_time_s"]})
    return rows


def recorded_rows() -> tuple[list, list, list]:
    """The other benchmarks' runs the steps fit reads (nothing is run): the model-error cells, the resolution draw,
    and the resolution benchmark's held-out faults."""
    return recorded_cells(), resolution_runs(), resolution_runs(RESOLUTION_HELD_OUT)


def fit_steps(rows: list, burial: bool = True, resolution: bool = True) -> dict:
    """ln steps = ln A + p ln events + q ln(W / h*) + r ln N_x + u B + s ln R (``burial``, ``resolution``: without
    u, or s, the models before them; R the squares per L_b), the rtol factor taken as the 2-D fault's; the
    residuals' range and standard deviation (ln), and the burial's and R's fitted ranges."""
    rtol_power = cost.FAULT_3D_STEPS["rtol"]
    y = np.log([row["steps"] / (row["rtol"] / 1e-6) ** rtol_power for row in rows])
    columns = [np.ones(len(rows)), np.log([max(row["expected_events"], 1.0) for row in rows]),
               np.log([row["width_over_nucleation"] for row in rows]), np.log([row["strike_count"] for row in rows])]
    if burial:
        columns.append([row["burial"] for row in rows])
    if resolution:
        columns.append(np.log([row["resolution"] for row in rows]))
    design = np.column_stack(columns)
    beta, *_ = np.linalg.lstsq(design, y, rcond=None)
    residual = y - design @ beta
    return {"scale": float(math.exp(beta[0])), "events": float(beta[1]), "width_over_nucleation": float(beta[2]),
            "strike_columns": float(beta[3]), "burial": float(beta[4]) if burial else 0.0,
            "resolution": float(beta[-1]) if resolution else 0.0, "rtol": rtol_power,
            "burial_fitted": float(max(row["burial"] for row in rows)),
            "resolution_fitted": [float(min(row["resolution"] for row in rows)),
                                  float(max(row["resolution"] for row in rows))],
            "residual_range": [float(math.exp(residual.min())), float(math.exp(residual.max()))],
            "residual_sd": float(residual.std()), "rows": len(rows)}


def steps_over_measured(rows: list, model: dict | None = None) -> dict:
    """The steps ``model`` (a :func:`fit_steps` result; the shipped one if None) estimates over those each run took:
    how many, the range, median and sd in ln."""
    model = model or cost.FAULT_3D_STEPS
    ratios = np.array([cost.steps(row["strike_count"], row["expected_events"], row["width_over_nucleation"],
                                  row["rtol"], row["burial"], row["resolution"], model=model) / row["steps"]
                       for row in rows])
    return {"count": len(rows), "range": [float(ratios.min()), float(ratios.max())],
            "median": float(np.median(ratios)), "sd_ln": float(np.log(ratios).std())}


def fit_step_seconds(rows: list) -> dict:
    """CPU per step, c0 + c1 N + c2 k (N_x + 1) N_z^2, relative non-negative least squares over the runs' steps (their
    operator's assembly timed apart)."""
    from scipy.optimize import nnls

    design = np.array([[1.0, row["elements"], row["products"] * (row["strike_count"] + 1) * row["dip_count"] ** 2]
                       for row in rows])
    per_step = np.array([row["steps_cpu_s"] / row["steps"] for row in rows])
    coefficients, _ = nnls(design / per_step[:, None], np.ones(len(rows)))
    ratio = design @ coefficients / per_step
    return {"coefficients": [float(c) for c in coefficients], "ratio_range": [float(ratio.min()), float(ratio.max())]}


def fit_assembly(rows: list) -> dict:
    """CPU per (source triangle, observation point) pair of the operator's assembly: the median over the runs that
    spent a second or more on it (:func:`faultslip.models.fault_3d.cost.assembly_pairs` counts the pairs)."""
    per_pair = [row["assembly_s"] / cost.assembly_pairs(row["strike_count"], row["dip_count"]) for row in rows
                if row["assembly_s"] >= 1.0]
    return {"pair_seconds": float(np.median(per_pair)), "runs": len(per_pair),
            "range": [float(min(per_pair)), float(max(per_pair))]}


#: (what, scene builder) of the rtol part: a buried patch, a surface-breaking one, a 2-D scene's 3-D fault
RTOL_FAULTS = [("patch 4 x 600 m at 200 m", lambda: cell(4.0, 600.0, 200.0)),
               ("patch 8 x 600 m at the surface", lambda: cell(8.0, 600.0, 0.0)),
               ("fault_2d_surface_small at 3 km", lambda: two_d("fault_2d_surface_small.toml", 3.0))]
RTOLS = (1e-5, 1e-6, 1e-7, 1e-8)


def rtol_runs() -> list:
    """Each of :data:`RTOL_FAULTS` at each of :data:`RTOLS`: its steps."""
    rows = []
    for what, make in RTOL_FAULTS:
        for rtol in RTOLS:
            scene = make()
            scene.rtol = rtol
            run = scene.run()
            rows.append({"what": what, "rtol": rtol, "steps": int(run.steps), "events": int(run.event_count)})
            print(json.dumps(rows[-1]), flush=True)
    return rows


def fit_rtol(rows: list) -> dict:
    """The steps' power of rtol: the slope of ln steps on ln rtol, each fault about its own mean (pooled), and each
    fault's own slope."""
    slopes, x, y = {}, [], []
    for what in dict.fromkeys(row["what"] for row in rows):
        mine = [row for row in rows if row["what"] == what]
        log_rtol = np.log([row["rtol"] for row in mine])
        log_steps = np.log([row["steps"] for row in mine])
        slopes[what] = float(np.polyfit(log_rtol, log_steps, 1)[0])
        x.extend(log_rtol - log_rtol.mean())
        y.extend(log_steps - log_steps.mean())
    x, y = np.array(x), np.array(y)
    return {"power": float(x @ y / (x @ x)), "per_fault": slopes}


def fits(runs: list, cells: list, resolution: list, resolution_held_out: list) -> dict:
    """The steps (over the fit runs, the model-error cells and the resolution draw), without the burial and without
    the resolution term as they were before, each tried on the resolution benchmark's held-out faults; the CPU a
    step and the assembly (over the fit runs)."""
    rows = runs + cells + resolution
    steps, without = fit_steps(rows), fit_steps(rows, resolution=False)
    return {"steps_fit": steps, "steps_fit_without_burial": fit_steps(rows, burial=False, resolution=False),
            "steps_fit_without_resolution": without,
            "resolution_held_out_steps": steps_over_measured(resolution_held_out, steps),
            "resolution_held_out_steps_without_resolution": steps_over_measured(resolution_held_out, without),
            "step_seconds_fit": fit_step_seconds(runs), "assembly_fit": fit_assembly(runs)}


def summary(ratios: list) -> dict:
    """Estimates over CPU: how many, how many within 2x, their range and median."""
    return {"count": len(ratios), "within_2x": sum(0.5 <= r <= 2.0 for r in ratios),
            "ratio_range": [min(ratios), max(ratios)], "ratio_median": float(np.median(ratios))}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=("fit", "refit", "held-out", "rtol", "re-estimate", "fresh"), required=True,
                        help="refit: the fits again from the file's runs, without running them")
    parser.add_argument("--seed", type=int, help="--part fresh: the draw's seed (one of FRESH_DRAWS)")
    parser.add_argument("--out", type=Path, default=OUT)
    args = parser.parse_args(argv)
    result = json.loads(args.out.read_text(encoding="utf-8")) if args.out.exists() else {}
    if args.part not in ("refit", "re-estimate"):
        cell(4.0, 600.0, 200.0, years=5.0).run()  # load the compiled force balance before any run is timed
    if args.part == "rtol":
        rows = rtol_runs()
        result.update({"rtol_runs": rows, "rtol_fit": fit_rtol(rows)})
        print(json.dumps(result["rtol_fit"]))
    elif args.part == "re-estimate":
        made = dict(FIT)
        for seed in (result.get("held_out_seed", HELD_OUT_SEED), *EARLIER_DRAWS, *FRESH_DRAWS):
            made |= dict(held_out_draw(seed))
        earlier = result.get("earlier_draws", [])
        # each run's estimate again, on the machine state it recorded (the fit runs': the state the fault_3d group is
        # anchored on, factor 1), and on the anchoring state
        for row in result["fit_runs"] + result.get("held_out", []):
            scene = made[row["what"]]()
            with machine.assumed(row.get("machine_factor", 1.0)):
                row.update(features(scene), estimated_s=scene.estimate().seconds,
                           estimated_assembly_s=cost.assembly_seconds(scene.fault.strike_count, scene.fault.dip_count))
            with machine.assumed(1.0):
                row["estimated_anchored_s"] = scene.estimate().seconds
            row["estimate_over_cpu"] = row["estimated_s"] / row["cpu_s"]
        with machine.assumed(1.0):
            # an earlier draw keeps the estimate its day's model made, and gets the shipped model's on the
            # machine state its runs recorded
            for draw in earlier + result.get("fresh_draws", []):
                for row in draw["rows"]:
                    scene = made[row["what"]]()
                    with machine.assumed(row["machine_factor"]):
                        row.update(features(scene), estimated_now_s=scene.estimate().seconds)
                    row["estimate_now_over_cpu"] = row["estimated_now_s"] / row["cpu_s"]
                draw["summary_now"] = summary([row["estimate_now_over_cpu"] for row in draw["rows"]])
                draw["model_now"] = cost.describe()
        cells, resolution, resolution_held_out = recorded_rows()
        fitted = fits(result["fit_runs"], cells, resolution, resolution_held_out)
        result.update({"recorded_cells": cells, "resolution_runs": resolution,
                       "resolution_held_out_runs": resolution_held_out, **fitted})
        if result.get("held_out"):
            result.update(held_out_summary=summary([row["estimate_over_cpu"] for row in result["held_out"]]),
                          held_out_model=cost.describe())
        print(json.dumps({**fitted, "held_out_summary": result.get("held_out_summary")}))
    elif args.part == "fresh":
        if args.seed not in FRESH_DRAWS:
            parser.error(f"--seed {args.seed}: a fresh draw's seed is listed in FRESH_DRAWS first ({FRESH_DRAWS})")
        rows = [measured(what, make()) for what, make in held_out_draw(args.seed)]
        kept = [draw for draw in result.get("fresh_draws", []) if draw["seed"] != args.seed]
        result["fresh_draws"] = kept + [{"seed": args.seed, "rows": rows, "model_then": cost.describe(),
                                         "summary_then": summary([row["estimate_over_cpu"] for row in rows]),
                                         **stamp()}]
        print(json.dumps(result["fresh_draws"][-1]["summary_then"]))
    elif args.part == "refit":
        fitted = fits(result["fit_runs"], result["recorded_cells"], result["resolution_runs"],
                      result["resolution_held_out_runs"])
        result.update(fitted)
        print(json.dumps(fitted))
    elif args.part == "fit":
        runs = [measured(what, make()) for what, make in FIT]
        cells, resolution, resolution_held_out = recorded_rows()
        fitted = fits(runs, cells, resolution, resolution_held_out)
        result.update({"fit_runs": runs, "recorded_cells": cells, "resolution_runs": resolution,
                       "resolution_held_out_runs": resolution_held_out, **fitted, **stamp()})
        print(json.dumps(fitted))
    else:
        rows = [measured(what, make()) for what, make in held_out_draw(HELD_OUT_SEED)]
        result.update({"held_out": rows, "held_out_seed": HELD_OUT_SEED,
                       "held_out_summary": summary([row["estimate_over_cpu"] for row in rows]),
                       "held_out_model": cost.describe(), **stamp()})
        print(json.dumps(result["held_out_summary"]))
    args.out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
