"""Set and check the event-driven integrators' declared errors (docs/methods.md).

    python benchmarks/event_driven_calibration.py            # ~15 min on 2 cores
    python benchmarks/event_driven_calibration.py --quick    # a few scenes per draw
    python benchmarks/event_driven_calibration.py --fresh 20261204   # and a fresh draw, unseen (repeatable)

The calibration scenes are the bench's stick-slip scenes with an exact cycle, and the random draws of
faultslip.evaluation.bench.CALIBRATION_SEEDS and LATER_CALIBRATION_SEEDS (fresh draws that broke the model set on
the first, then added); on them each integrator's error (as the contract declares it:
amplitude and period, or event times per cycle) is measured at every rtol from 1e-3 to 1e-12, 10 cycles a
run. Per integrator and rtol the results give the largest error, which the shipped model
(simulate.SOLVER_ERROR_MODEL, c rtol^q + floor) must bound with a margin; then the held-out draw
(HELD_OUT_SEED), never part of the calibration, is measured once against the shipped model, and so is each --fresh
seed's draw of as many scenes (drawn after the model was shipped).

Writes benchmarks/results/event_driven_calibration.json (benchmarks/readme.py renders docs/methods.md's table).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from faultslip.dynamics.spring_slider.simulate import SOLVER_ERROR_MODEL
from faultslip.evaluation import bench
from faultslip.evaluation.error_models import fit_power_law
from provenance import write_results

#: the shipped model must exceed every calibration error by this factor, so that scenes not drawn have room
MARGIN = 1.5


def calibration_scenes(count: int) -> dict:
    standard = {name: scene for name, scene in bench.standard_scenes().items()
                if scene[0].is_linear and scene[0].static_excess is not None}
    drawn = {}
    for seed in bench.CALIBRATION_SEEDS:
        drawn.update(bench.random_scenes(seed, count))
    for seed in bench.LATER_CALIBRATION_SEEDS:  # checked as fresh draws first, then added (bench's comment)
        drawn.update(bench.random_scenes(seed, min(count, bench.HELD_OUT_SCENES)))
    return {**standard, **drawn}


#: the friction laws of the scenes, by a word of their description (bench.random_scenes)
LAW_CLASSES = {"polynomial kinetic law": "polynomial", "Cameron's law": "Cameron", "rate law with a constant or linear kinetic law": ""}


def law_class(description: str) -> str:
    return next(name for name, word in LAW_CLASSES.items() if word in description)


def envelope(dataset) -> dict:
    """Per solver and rtol: the largest error over the scenes, how many runs failed, and the largest error /
    rtol over each class of friction law."""
    classes = np.array([law_class(str(d)) for d in dataset["description"].values])
    out = {}
    for solver in dataset["solver"].values:
        part = dataset.sel(solver=solver)
        ok = part["status"].values == 0
        error = np.where(ok, part["error"].values, np.nan)
        largest = np.nanmax(error, axis=0)
        over_rtol = error / part["rtol"].values
        out[str(solver)] = {"rtol": [float(r) for r in part["rtol"].values],
                            "largest_error": [float(x) for x in largest],
                            "declared_error": [float(x) for x in part["declared_error"].values],
                            "failed_runs": int((~ok).sum()), "runs": int(ok.size),
                            "largest_over_rtol_by_law": {name: float(np.nanmax(over_rtol[classes == name]))
                                                         for name in LAW_CLASSES if (classes == name).any()},
                            "scenes_by_law": {name: int((classes == name).sum()) for name in LAW_CLASSES}}
    return out


def fit_model(rtols, largest, margin: float = MARGIN) -> tuple:
    """The tightest c rtol^q + floor, q from 0.70 to 1.10, at least ``margin`` x ``largest`` at every rtol."""
    return fit_power_law(rtols, largest, margin, powers=POWERS)


#: the powers this calibration tries (the event-driven errors fall at least as fast as rtol^0.7)
POWERS = tuple(float(p) for p in np.round(np.arange(0.70, 1.101, 0.01), 2))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="6 scenes per draw")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--fresh", type=int, action="append", default=[],
                        help="also measure this seed's draw against the shipped model (repeatable)")
    args = parser.parse_args(argv)
    count = 6 if args.quick else bench.CALIBRATION_SCENES
    calibration = bench.declared_error_check(calibration_scenes(count), workers=args.workers)
    found = envelope(calibration)
    short = {solver: min(d / e for d, e in zip(row["declared_error"], row["largest_error"]) if math.isfinite(e))
             for solver, row in found.items()}
    fitted = {solver: fit_model(row["rtol"], row["largest_error"]) for solver, row in found.items()}
    held_out_count = 8 if args.quick else bench.HELD_OUT_SCENES
    held_out = bench.declared_error_check(bench.random_scenes(bench.HELD_OUT_SEED, held_out_count),
                                          workers=args.workers)
    held = bench.declared_error_summary(held_out)
    fresh = [{"seed": seed, "scenes": held_out_count, "summary": bench.declared_error_summary(
        bench.declared_error_check(bench.random_scenes(seed, held_out_count), workers=args.workers))}
        for seed in args.fresh]
    document = {
        "calibration": {"scenes": int(calibration.sizes["scene"]), "seeds": list(bench.CALIBRATION_SEEDS),
                        "per_seed": count, "later_seeds": list(bench.LATER_CALIBRATION_SEEDS),
                        "per_later_seed": min(count, bench.HELD_OUT_SCENES), "cycles": bench.CHECK_CYCLES,
                        "envelope": found,
                        "smallest_declared_over_largest": short, "margin_required": MARGIN,
                        "fitted_model": {solver: list(model) for solver, model in fitted.items()},
                        "wall_time_s": calibration.attrs["total_wall_time_s"]},
        "held_out": {"seed": bench.HELD_OUT_SEED, "scenes": int(held_out.sizes["scene"]), "summary": held,
                     "wall_time_s": held_out.attrs["total_wall_time_s"]},
        "fresh": fresh,
        "model": {solver: list(SOLVER_ERROR_MODEL[solver]) for solver in bench.INTEGRATOR_NAMES},
        "quick": bool(args.quick),
    }
    write_results("event_driven_calibration.json", document)
    for solver, ratio in short.items():
        print(f"{solver}: the declared error is at least {ratio:.3g} x the largest calibration error"
              f"{'' if ratio >= MARGIN else f' (below the margin {MARGIN})'}; fitted (c, q, floor) {fitted[solver]}, "
              f"shipped {SOLVER_ERROR_MODEL[solver]}")
    print(bench.declared_error_text(held))
    for draw in fresh:
        print(f"fresh draw, seed {draw['seed']}:\n" + bench.declared_error_text(draw["summary"]))
    bad = [s for s, r in short.items() if r < MARGIN] + [s for s, row in held.items() if not row["within_declared"]]
    bad += [s for draw in fresh for s, row in draw["summary"].items() if not row["within_declared"]]
    return 1 if bad else 0


if __name__ == "__main__":
    raise SystemExit(main())
