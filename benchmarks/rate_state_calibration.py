"""Set and check the rate-and-state cycle integrators' declared errors (docs/rate_state.md).

    python benchmarks/rate_state_calibration.py            # ~5 min on 2 cores
    python benchmarks/rate_state_calibration.py --quick    # a few faults per draw
    python benchmarks/rate_state_calibration.py --fresh 20261204 --fresh 20261205   # and fresh draws, unseen

The calibration faults are the random draws of faultslip.evaluation.rate_state_bench.CALIBRATION_SEEDS (a, a / b,
the evolution law, sigma_n, G, the fault's width, the plate rate and K / K_c, one in five near K_c), and the
draws of LATER_CALIBRATION_SEEDS (fresh draws that broke the near-K_c model before it took a / b in). On each, every
integrator's error in recurrence and slip per event, 2 cycles once settled, is measured at rtol 1e-5 to 1e-10
against the C stepper at rtol 1e-12. Per integrator the results give, at each rtol, the largest error of the faults
below K / K_c 0.9 and the largest error x (1 - K / K_c) (1 - a / b) of those above; the shipped model
(methods.ERROR_MODEL: c rtol^q + floor, and k rtol^p / ((1 - K / K_c) (1 - a / b)) near K_c) must bound both with a
margin. The near model's form is the calibration's own: a least-squares fit of ln error over its near runs gives
exponents about 1 on both (1 - K / K_c) and (1 - a / b) (printed as ``near_regression``).
Then the held-out draw (HELD_OUT_SEED), never part of the calibration, is measured once against the shipped model,
and so is each --fresh seed's draw of as many faults (drawn after the model was shipped).

Writes benchmarks/results/rate_state_calibration.json (benchmarks/readme.py renders docs/rate_state.md's table).
"""

from __future__ import annotations

import argparse
import math

import numpy as np

from faultslip.dynamics.rate_state.methods import ERROR_MODEL, NEAR_CRITICAL_FROM
from faultslip.evaluation import rate_state_bench as bench
from faultslip.evaluation.error_models import fit_power_law
from provenance import write_results

#: the shipped model must exceed every calibration error by this factor, so that faults not drawn have room
MARGIN = 1.5


def _with_reference(dataset):
    """(the faults whose reference ran, their K / K_c, their 1 - a / b, which are near K_c)."""
    dataset = dataset.isel(fault=np.nonzero(dataset["reference_failure"].values == "")[0])
    ratio = dataset["stiffness_ratio"].values
    return dataset, ratio, 1.0 - dataset["a"].values / dataset["b"].values, ratio >= NEAR_CRITICAL_FROM


def _errors(part):
    """(which runs were measured, their errors, the errors that are the integrator's to bound)."""
    ok = part["status"].values == 0
    error = np.where(ok, part["error"].values, np.nan)
    # a run whose sequence had not come within its error of the steady cycle declares the distance left; where
    # that covers the error with the margin, the error is the settling's, not the integrator's to bound
    with np.errstate(invalid="ignore"):
        return ok, error, np.where(part["settling_left"].values >= MARGIN * error, np.nan, error)


def envelope(dataset) -> dict:
    """Per integrator and rtol, over the faults whose reference ran: the largest error of the faults below K / K_c
    :data:`NEAR_CRITICAL_FROM`, the largest error x (1 - K / K_c) (1 - a / b) of those above (leaving out runs
    whose declared settling covers their error), the runs that failed (by outcome), and the smallest error a
    run declared over the error measured (the margin the shipped model keeps)."""
    dataset, ratio, weakening, near = _with_reference(dataset)
    out = {}
    for method in dataset["integrator"].values:
        part = dataset.sel(integrator=method)
        ok, error, integrator_error = _errors(part)
        outcomes = part["status"].values[~ok]
        failed_at = np.nonzero(~ok)
        with np.errstate(all="ignore"):
            far_largest = np.nanmax(np.where(near[:, None], np.nan, integrator_error), axis=0)
            near_largest = np.nanmax(np.where(near[:, None], integrator_error * (1 - ratio[:, None])
                                              * weakening[:, None], np.nan), axis=0)
            kept = np.nanmin(part["declared_error"].values / error)
        out[str(method)] = {
            "rtol": [float(r) for r in part["rtol"].values],
            "largest_error_far": [float(x) for x in far_largest],
            "largest_error_times_distance_near": [float(x) for x in near_largest],
            "faults_far": int((~near).sum()), "faults_near": int(near.sum()),
            "runs": int(ok.size), "failed_runs": {bench.STATUS[int(code)]: int((outcomes == code).sum())
                                                  for code in np.unique(outcomes)},
            "failed_where": {"stiffness_ratio": [float(ratio[failed_at[0]].min()), float(ratio[failed_at[0]].max())]
                             if failed_at[0].size else [],
                             "rtol": sorted({float(r) for r in part["rtol"].values[failed_at[1]]})},
            "smallest_declared_over_error": float(kept)}
    return out


def near_regression(dataset) -> dict:
    """Per integrator: least squares of ln error = ln k + p ln rtol - s ln(1 - a / b) - r ln(1 - K / K_c) over the
    near runs the envelope keeps: the exponents the near model's form rests on."""
    dataset, ratio, weakening, near = _with_reference(dataset)
    out = {}
    for method in dataset["integrator"].values:
        part = dataset.sel(integrator=method)
        error = _errors(part)[2]
        rtol = np.broadcast_to(part["rtol"].values[None, :], error.shape)
        keep = near[:, None] & np.isfinite(error) & (error > 0)
        design = np.column_stack([np.ones(keep.sum()), np.log(rtol[keep]),
                                  -np.log(np.broadcast_to(weakening[:, None], error.shape)[keep]),
                                  -np.log(np.broadcast_to(1 - ratio[:, None], error.shape)[keep])])
        coefficients = np.linalg.lstsq(design, np.log(error[keep]), rcond=None)[0]
        out[str(method)] = {"runs": int(keep.sum()), "rtol_power": float(coefficients[1]),
                            "a_over_b_exponent": float(coefficients[2]),
                            "stiffness_ratio_exponent": float(coefficients[3])}
    return out


def fit(found: dict) -> dict:
    """Per integrator: the tightest far and near models that stand :data:`MARGIN` above the envelope."""
    fitted = {}
    for method, row in found.items():
        far = fit_power_law(row["rtol"], row["largest_error_far"], MARGIN)
        near = fit_power_law(row["rtol"], row["largest_error_times_distance_near"], MARGIN, floors=(0.0,))
        fitted[method] = {"far": list(far), "near": list(near[:2])}
    return fitted


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="8 faults per draw")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--fresh", type=int, action="append", default=[],
                        help="also measure this seed's draw against the shipped model (repeatable)")
    args = parser.parse_args(argv)
    count = 8 if args.quick else bench.CALIBRATION_FAULTS
    later_count = min(count, bench.HELD_OUT_FAULTS)
    faults = [fault for seed in bench.CALIBRATION_SEEDS for fault in bench.random_faults(seed, count)]
    faults += [fault for seed in bench.LATER_CALIBRATION_SEEDS for fault in bench.random_faults(seed, later_count)]
    calibration = bench.declared_error_check(faults, workers=args.workers)
    found = envelope(calibration)
    regression = near_regression(calibration)
    fitted = fit(found)
    held_count = 6 if args.quick else bench.HELD_OUT_FAULTS
    held_out = bench.declared_error_check(bench.random_faults(bench.HELD_OUT_SEED, held_count), workers=args.workers)
    held = bench.declared_error_summary(held_out)
    fresh = []
    for seed in args.fresh:
        draw = bench.declared_error_check(bench.random_faults(seed, held_count), workers=args.workers)
        fresh.append({"seed": seed, "faults": held_count, "summary": bench.declared_error_summary(draw),
                      "reference_failures": [str(x) for x in draw["reference_failure"].values if x]})
    shipped = {method: ERROR_MODEL[method] for method in found}
    document = {
        "calibration": {"faults": len(faults), "seeds": list(bench.CALIBRATION_SEEDS), "per_seed": count,
                        "later_seeds": list(bench.LATER_CALIBRATION_SEEDS), "per_later_seed": later_count,
                        "near_regression": regression,
                        "near_critical_from": NEAR_CRITICAL_FROM, "cycles": bench.CYCLES,
                        "reference_rtol": bench.CHECK_REFERENCE_RTOL, "envelope": found,
                        "reference_failures": [str(x) for x in calibration["reference_failure"].values if x],
                        "margin_required": MARGIN, "fitted_model": fitted,
                        "wall_time_s": calibration.attrs["total_wall_time_s"]},
        "held_out": {"seed": bench.HELD_OUT_SEED, "faults": held_count, "summary": held,
                     "reference_failures": [str(x) for x in held_out["reference_failure"].values if x],
                     "wall_time_s": held_out.attrs["total_wall_time_s"]},
        "fresh": fresh,
        "model": {method: {"far": list(model["far"]), "near": list(model["near"])} for method, model in shipped.items()},
        "quick": bool(args.quick),
    }
    write_results("rate_state_calibration.json", document)
    for method, row in found.items():
        kept = row["smallest_declared_over_error"]
        print(f"{method}: the declared error is at least {kept:.3g} x every calibration error"
              f"{'' if kept >= MARGIN else f' (below the margin {MARGIN})'}; fitted {fitted[method]}, shipped "
              f"{shipped[method]}; failed runs {row['failed_runs']}")
    print(f"near K_c, ln error on ln rtol, ln(1 - a / b) and ln(1 - K / K_c): {regression}")
    print(bench.declared_error_text(held))
    for draw in fresh:
        print(f"fresh draw, seed {draw['seed']}:\n" + bench.declared_error_text(draw["summary"]))
    bad = [m for m, row in found.items() if not row["smallest_declared_over_error"] >= MARGIN]
    bad += [m for m, row in held.items() if not row["within_declared"]]
    bad += [m for draw in fresh for m, row in draw["summary"].items() if not row["within_declared"]]
    return 1 if bad or not all(math.isfinite(r["smallest_declared_over_error"]) for r in found.values()) else 0


if __name__ == "__main__":
    raise SystemExit(main())
