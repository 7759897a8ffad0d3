"""Why the rates are the ridge's where the rates that fit are nearly one point: the exact least-norm point there,
found by an interior-point solver, and how far round-off moves it.

    python benchmarks/rupture_rate_exact_point.py [--quick]

The first three rule sets of each of benchmarks/rupture_rate_stability.py's draws (seeds 7 and 8) with at most
100 ruptures whose least-norm step met the nearly-one-point case (the exact solves take minutes each). For each, the problem the step solved (the NNLS matrix at the weight
taken, and NNLS's fitted values) is solved exactly as well: min ½‖rates‖² subject to matrix @ [rates; c] = fitted,
[rates; c] ≥ 0, by scipy's trust-constr (gtol and xtol 1e-14), from the ridge's rates. Recorded: how far the exact
point lies from the ridge's rates (over the largest rate), how well each meets the rows, their norms, and how far
each moves when every slip is moved by a relative 1e-12 (seeds 1 and 2), as faultslip's final rates do.
Writes benchmarks/results/rupture_rate_exact_point.json.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.studies import rupture_sets as rs  # noqa: E402
from faultslip.studies.maps import read_map, run_map  # noqa: E402
from provenance import stamp  # noqa: E402
from rupture_rate_stability import CHANGE, SEEDS, SYSTEM, draw  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "rupture_rate_exact_point.json"
MOST_RUPTURES = 100
#: rule sets a draw
COUNT = 3


def exact_point(matrix: np.ndarray, fitted: np.ndarray, start: np.ndarray) -> tuple:
    """(the exact least-norm [rates; c], how well it meets the rows relative to the largest fitted value)."""
    from scipy.optimize import Bounds, LinearConstraint, minimize

    norms = np.max(np.abs(matrix), axis=1)
    rows, target = matrix / norms[:, None], fitted / norms
    weight = np.ones(rows.shape[1])
    weight[-1] = 0.0  # c, the shape's level, unpenalised as faultslip's step leaves it
    found = minimize(lambda x: 0.5 * np.sum(weight * x * x), start, jac=lambda x: weight * x,
                     hess=lambda x: np.diag(weight), method="trust-constr",
                     constraints=[LinearConstraint(rows, target, target)],
                     bounds=Bounds(np.zeros(rows.shape[1]), np.full(rows.shape[1], np.inf)),
                     options={"gtol": 1e-14, "xtol": 1e-14, "maxiter": 5000})
    point = np.maximum(found.x, 0.0)
    return point, float(np.max(np.abs(rows @ point - target)) / np.max(np.abs(target)))


def met(matrix, fitted, point) -> float:
    norms = np.max(np.abs(matrix), axis=1)
    return float(np.max(np.abs((matrix @ point - fitted) / norms)) / np.max(np.abs(fitted / norms)))


def solved(sections, ruptures, magnitude, slip, rules, relation, shear_modulus) -> tuple:
    """(faultslip's result, the problem its least-norm step met as nearly one point, or None)."""
    seen = []
    original = rs.least_norm_rates

    def watched(matrix, fitted, start):
        answer = original(matrix, fitted, start)
        seen.append((matrix, fitted, answer))
        return answer

    rs.least_norm_rates = watched
    try:
        result = rs.solve_rates(sections, ruptures, magnitude, slip, rules, relation, shear_modulus)
    finally:
        rs.least_norm_rates = original
    taken = seen[-1] if seen and seen[-1][2][1] is not None and seen[-1][2][0] is not None else None
    return result, taken


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the first rule set of each draw")
    args = parser.parse_args(argv)
    spec = read_map(SYSTEM)
    dataset = run_map(spec)
    shear_modulus = float(spec.scene.fault().shear_modulus)
    rows = []
    for seed in (7, 8):
        rng = np.random.default_rng(seed)
        for index in range(140):
            rules, relation = draw(rng)
            if sum(row["seed"] == seed for row in rows) >= (1 if args.quick else COUNT):
                break
            sections = rs.fault_sections(spec, dataset, rules)
            ruptures = rs.enumerate_ruptures(sections, rules)
            if len(ruptures) > MOST_RUPTURES:
                continue
            magnitude, slip = rs.rupture_magnitudes(sections, ruptures, relation, shear_modulus)
            try:
                base, problem = solved(sections, ruptures, magnitude, slip, rules, relation, shear_modulus)
            except (rs.InputError, rs.SolverError):
                continue
            if problem is None:
                continue
            matrix, fitted, (ridge, _) = problem
            exact, exact_met = exact_point(matrix, fitted, ridge)
            largest = float(ridge[:-1].max())
            row = {"seed": seed, "index": index, "relation": relation, "ruptures": len(ruptures),
                   "ridge_meets_rows": met(matrix, fitted, ridge), "exact_meets_rows": exact_met,
                   "exact_from_ridge": float(np.max(np.abs(exact[:-1] - ridge[:-1])) / largest),
                   "ridge_norm": float(np.linalg.norm(ridge[:-1])), "exact_norm": float(np.linalg.norm(exact[:-1])),
                   "ridge_moved": 0.0, "exact_moved": 0.0, "rates_moved": 0.0}
            for change_seed in SEEDS:
                noise = 1 + CHANGE * np.random.default_rng(change_seed).standard_normal(slip.shape)
                moved, again = solved(sections, ruptures, magnitude, slip * noise, rules, relation, shear_modulus)
                row["rates_moved"] = max(row["rates_moved"], float(np.max(np.abs(moved.rate - base.rate))
                                                                   / base.rate.max()))
                if again is None:
                    row["ridge_moved"] = row["exact_moved"] = None
                    continue
                other = exact_point(again[0], again[1], again[2][0])[0]
                if row["ridge_moved"] is not None:
                    row["ridge_moved"] = max(row["ridge_moved"], float(np.max(np.abs(again[2][0][:-1] - ridge[:-1]))
                                                                       / largest))
                    row["exact_moved"] = max(row["exact_moved"], float(np.max(np.abs(other[:-1] - exact[:-1]))
                                                                       / exact[:-1].max()))
            rows.append(row)
            print(row, flush=True)
    result = {**stamp(), "change": CHANGE, "change_seeds": list(SEEDS), "most_ruptures": MOST_RUPTURES, "count": COUNT,
              "system": SYSTEM.name, "quick": args.quick, "rule_sets": rows}
    OUT.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    print(f"written to {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
