"""The one slider's correction and 95 % ranges against the 2-D fault, fitted on calibration designs and tested on
held-out designs it never saw (issue 68).

    python benchmarks/ladder_designs.py        # the 2-D runs (long: about an hour on two cores)
    python benchmarks/ladder_calibration.py    # the fit, the held-out test and the budget's check (a minute)

**Calibration faults**: every 2-D run of ``benchmarks/results/fault_2d_designs.json`` (the designed set and the
15 faults held out of the older calibration, SEAS BP1 among them) and the ``calibration`` draws of
``benchmarks/results/ladder_designs.json``. **Held out**: that file's ``held out`` draws, a second random draw
over the same box that never enters the fit.

For each fault the block is derived from its profile (:func:`faultslip.fault.ladder.derived_block`), and
ln(2-D / block) is fitted for the recurrence, the slip per event averaged over the rupture zone, and the surface
slip (surface-breaking faults only). A 2-D run whose system-size events did not settle into a period is used
through its mean interval after the spin-up where it has four or more, and left out otherwise (said below).

**What limits the range** (``limits`` in the held-out file): each 2-D run either interleaves events that do not
break the zone with its system-size events or does not (:func:`ladder_regimes.interleaves`). Per quantity: the
residual of ln(2-D / block) in each kind; the residual sd of a fit within each kind; the held-out coverage and
mean half-width the one slider would reach if it were told each fault's kind (the best any range built on the
block and these groups can do here); the same for a nonlinear fit of the groups, a Gaussian process, on all the
calibration faults and within each kind; and how often a logistic regression on the groups, and a fault's nearest
calibration faults, name the kind of a held-out fault; and whether more designs would narrow the range (both fits on
random subsets of the calibration faults, and the linear range's limit with unlimited designs). And the narrowest ranges any one slider
could declare, set with the 2-D answers in hand (``narrowest``): lower bounds on the width, not fits.

**The budget**: the estimate each run recorded before it ran, against the CPU it used, over the runs whose row
records the cost model now declared (the held-out ones apart: the event-step model is fitted on the others).

**Fresh draws** (``python benchmarks/ladder_designs.py --fresh 40 [--seed 68012 | 68014 | 68031 | 68041 | 68061 |
68071 | 68081]``, ``ladder_fresh.json``, ``ladder_fresh_second.json``, ``ladder_fresh_third.json``,
``ladder_fresh_fourth.json``, ``ladder_fresh_fifth.json``, ``ladder_fresh_sixth.json``, ``ladder_fresh_seventh.json``
and ``ladder_fresh_eighth.json``): a third to a tenth independent draw over the box,
each run after the ranges were shipped, tested against them as they are.

Writes ``data/ladder_calibration.json`` (what faultslip declares) and ``benchmarks/results/ladder_held_out.json``
(each held-out fault, its 2-D answer, the range and whether it holds; the budget's estimates against the CPU used).
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.io.resources import write_bundled_table  # noqa: E402
from faultslip import __version__  # noqa: E402
from faultslip.fault import ladder  # noqa: E402
from faultslip.models.fault_2d.calibration import Design  # noqa: E402
from ladder_designs import FRESH_DRAWS, cost_model  # noqa: E402
from faultslip.models.fault_2d.analysis import PARTIAL_SHARE  # noqa: E402
from ladder_regimes import interleaves  # noqa: E402
from provenance import stamp  # noqa: E402

OLD = ROOT / "benchmarks" / "results" / "fault_2d_designs.json"
NEW = ROOT / "benchmarks" / "results" / "ladder_designs.json"
OUT = ROOT / "data" / ladder.CALIBRATION_FILE
HELD = ROOT / "benchmarks" / "results" / "ladder_held_out.json"


def two_d_answer(row: dict) -> dict | None:
    """The 2-D run's recurrence (s), mean slip over the rupture zone and surface slip (m); None if unsettled."""
    if row["sequence"] == "unsettled":
        if len(row.get("intervals", ())) < 4:
            return None
        return {"recurrence": float(np.mean(row["intervals"][2:])),
                "mean_slip": float(np.mean(row["system_slips"][3:])), "surface_slip": math.nan}
    return {"recurrence": row["recurrence_2d"], "mean_slip": row["mean_slip_2d"], "surface_slip": row["surface_slip_2d"]}


def prepared(row: dict, elements_per_process_zone: float = 3.0) -> dict | None:
    answer = two_d_answer(row)
    if answer is None or not all(math.isfinite(answer[k]) and answer[k] > 0 for k in ("recurrence", "mean_slip")):
        return None
    design = Design(**row["design"])
    fault = design.two_d(elements_per_process_zone).fault.description()
    block, group = ladder.block_answer(fault)
    return {"name": row["design"]["name"], "group": group, "block": block, "two_d": answer,
            "surface_breaking": group["burial"] == 0.0, "interleaves": interleaves(row)}


def targets(items, quantity):
    if quantity == "recurrence":
        return [(item, math.log(item["two_d"]["recurrence"] / item["block"]["recurrence"])) for item in items]
    key = "mean_slip" if quantity == "mean_slip" else "surface_slip"
    chosen = [item for item in items if quantity == "mean_slip" or item["surface_breaking"]]
    return [(item, math.log(item["two_d"][key] / item["block"]["slip"])) for item in chosen
            if math.isfinite(item["two_d"][key]) and item["two_d"][key] > 0]


def _logistic(x: np.ndarray, labels: np.ndarray, penalty: float = 1.0) -> np.ndarray:
    """Coefficients of an L2-penalised logistic regression (the intercept unpenalised) on standardised columns."""
    from scipy import optimize

    def loss(beta):
        z = x @ beta
        return float(np.sum(np.logaddexp(0.0, z) - labels * z) + 0.5 * penalty * beta[1:] @ beta[1:])

    def gradient(beta):
        g = x.T @ (1.0 / (1.0 + np.exp(-(x @ beta))) - labels)
        g[1:] += penalty * beta[1:]
        return g

    return optimize.minimize(loss, np.zeros(x.shape[1]), jac=gradient, method="BFGS").x


def gaussian_process(x_train: np.ndarray, y_train: np.ndarray, x_test: np.ndarray, restarts: int = 4,
                     seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Predictive mean and sd (the noise included) of a Gaussian process on standardised columns: a squared-
    exponential kernel with one length per column plus white noise, its hyperparameters by the largest marginal
    likelihood over ``restarts`` + 1 starts (Rasmussen & Williams 2006, eqs. 2.25-2.30 and 5.8)."""
    from scipy import linalg, optimize

    mean, scale = x_train.mean(axis=0), x_train.std(axis=0)
    scale[scale == 0] = 1.0
    a, b = (x_train - mean) / scale, (x_test - mean) / scale
    centre = float(y_train.mean())
    y = y_train - centre
    n, dims = a.shape
    spread = float(y.std())

    def kernel(p, u, v):
        return math.exp(2 * p[0]) * np.exp(-0.5 * (((u[:, None, :] - v[None, :, :]) / np.exp(p[1:1 + dims])) ** 2).sum(-1))

    def factor(p):
        return linalg.cho_factor(kernel(p, a, a) + (math.exp(2 * p[-1]) + 1e-10) * np.eye(n), lower=True)

    def negative_log_likelihood(p):
        try:
            chol = factor(p)
        except linalg.LinAlgError:
            return 1e10
        return 0.5 * y @ linalg.cho_solve(chol, y) + float(np.log(np.diag(chol[0])).sum())

    rng = np.random.default_rng(seed)
    starts = [np.r_[math.log(spread), np.zeros(dims), math.log(spread / 2)]]
    starts += [np.r_[math.log(spread) + rng.normal(0, 0.5), rng.normal(0.5, 1.0, dims),
                     math.log(spread / 2) + rng.normal(0, 0.5)] for _ in range(restarts)]
    bounds = ([(math.log(spread) - 4, math.log(spread) + 4)] + [(math.log(0.05), math.log(100.0))] * dims
              + [(math.log(spread) - 6, math.log(spread) + 2)])
    best = min((optimize.minimize(negative_log_likelihood, start, method="L-BFGS-B", bounds=bounds) for start in starts),
               key=lambda result: result.fun).x
    chol, cross = factor(best), kernel(best, b, a)
    variance = math.exp(2 * best[0]) + math.exp(2 * best[-1]) - np.einsum("ij,ji->i", cross, linalg.cho_solve(chol, cross.T))
    return cross @ linalg.cho_solve(chol, y) + centre, np.sqrt(np.maximum(variance, 0.0))


def nearest_kind(x_train: np.ndarray, labels: np.ndarray, x_test: np.ndarray) -> tuple[np.ndarray, int]:
    """The kind of each test row by a majority of its k nearest calibration faults in standardised groups, k (odd,
    1-15) chosen by leave-one-out over the calibration faults."""
    mean, scale = x_train.mean(axis=0), x_train.std(axis=0)
    scale[scale == 0] = 1.0
    a, b = (x_train - mean) / scale, (x_test - mean) / scale

    def vote(distance, k):
        return labels[np.argsort(distance, axis=1, kind="stable")[:, :k]].mean(axis=1) > 0.5

    inner = ((a[:, None, :] - a[None, :, :]) ** 2).sum(-1)
    np.fill_diagonal(inner, np.inf)
    best = max(range(1, 16, 2), key=lambda k: (np.sum(vote(inner, k) == labels.astype(bool)), -k))
    return vote(((b[:, None, :] - a[None, :, :]) ** 2).sum(-1), best), best


def learning_curve(pairs: list, kept: list, sizes=(40, 55, 70), draws: int = 5, seed: int = 0) -> list[dict]:
    """Held-out coverage and mean half-width of the declared (linear) range and of the Gaussian process when fitted
    on ``draws`` random subsets of each size of the calibration faults, and on all of them: do more designs narrow
    the range? ``pairs`` and ``kept`` are (fault, ln 2-D / block) of the calibration and held-out faults."""
    normal = 1.959963984540054
    rng = np.random.default_rng(seed)
    x_all = np.array([ladder.features(i["group"])[1:] for i, _ in pairs])
    y_all = np.array([y for _, y in pairs])
    x_test = np.array([ladder.features(i["group"])[1:] for i, _ in kept])
    y_test = np.array([y for _, y in kept])
    out = []
    for size in [n for n in sizes if n < len(pairs)] + [len(pairs)]:
        rows = []
        for _ in range(draws if size < len(pairs) else 1):
            chosen = rng.choice(len(pairs), size, replace=False) if size < len(pairs) else np.arange(size)
            model = ladder.fit([pairs[k][0]["group"] for k in chosen], y_all[chosen])
            spread = np.array([model["t_quantile"] * model["residual_sd"] * math.sqrt(1.0 + float(
                ladder.features(i["group"]) @ np.asarray(model["inverse_gram"]) @ ladder.features(i["group"])))
                for i, _ in kept])
            centre = np.array([float(ladder.features(i["group"]) @ np.asarray(model["coefficients"])) for i, _ in kept])
            process_centre, sd = gaussian_process(x_all[chosen], y_all[chosen], x_test)
            rows.append((np.mean(np.abs(y_test - centre) <= spread), np.mean(np.expm1(spread)),
                         np.mean(np.abs(y_test - process_centre) <= normal * sd), np.mean(np.expm1(normal * sd))))
        mean = np.mean(rows, axis=0)
        out.append({"faults": int(size), "draws": len(rows), "linear_coverage": float(mean[0]),
                    "linear_mean_half_width": float(mean[1]), "gaussian_process_coverage": float(mean[2]),
                    "gaussian_process_mean_half_width": float(mean[3])})
    return out


def limits(train: list[dict], test: list[dict], table: dict) -> dict:
    """What the two kinds of 2-D sequence do to the one slider's range (module docstring)."""
    out = {"partial_share": PARTIAL_SHARE, "calibration_interleaving": sum(i["interleaves"] for i in train),
           "calibration_faults": len(train), "held_out_interleaving": sum(i["interleaves"] for i in test),
           "held_out_faults": len(test)}
    for quantity in ("recurrence", "mean_slip"):
        pairs = targets(train, quantity)
        model = table[quantity]
        residual = {kind: [y - float(ladder.features(i["group"]) @ np.asarray(model["coefficients"]))
                           for i, y in pairs if i["interleaves"] == kind] for kind in (False, True)}
        by_kind = {kind: ladder.fit([i["group"] for i, _ in pairs if i["interleaves"] == kind],
                                    np.array([y for i, y in pairs if i["interleaves"] == kind])) for kind in (False, True)}
        covered, widths = [], []
        for item, _ in targets(test, quantity):
            if ladder.outside_box(item["group"], table):
                continue
            truth = item["two_d"]["recurrence" if quantity == "recurrence" else quantity]
            raw = item["block"]["recurrence" if quantity == "recurrence" else "slip"]
            band = ladder.predict(quantity, raw, item["group"], {quantity: by_kind[item["interleaves"]]})
            covered.append(band["low"] <= truth <= band["high"])
            widths.append(band["half_width"])
        # a nonlinear fit of the same groups, on all calibration faults and within each kind (told the kind)
        kept = [(item, y) for item, y in targets(test, quantity) if not ladder.outside_box(item["group"], table)]
        x_train = np.array([ladder.features(i["group"])[1:] for i, _ in pairs])
        y_train, kinds = np.array([y for _, y in pairs]), np.array([i["interleaves"] for i, _ in pairs])
        x_test = np.array([ladder.features(i["group"])[1:] for i, _ in kept])
        y_test, test_kinds = np.array([y for _, y in kept]), np.array([i["interleaves"] for i, _ in kept])
        normal = 1.959963984540054  # the 95 % range of a normal predictive distribution
        centre, sd = gaussian_process(x_train, y_train, x_test)
        process = {"coverage": float(np.mean(np.abs(y_test - centre) <= normal * sd)),
                   "mean_half_width": float(np.mean(np.expm1(normal * sd)))}
        inside, half = [], []
        for kind in (False, True):
            centre, sd = gaussian_process(x_train[kinds == kind], y_train[kinds == kind], x_test[test_kinds == kind])
            inside += list(np.abs(y_test[test_kinds == kind] - centre) <= normal * sd)
            half += list(np.expm1(normal * sd))
        process.update(told_kind_coverage=float(np.mean(inside)), told_kind_mean_half_width=float(np.mean(half)),
                       held_out=len(kept))
        out[quantity] = {
            "gaussian_process": process, "learning_curve": learning_curve(pairs, kept),
            # unlimited designs: no leverage, the normal quantile, the residual sd alone
            "unlimited_designs_half_width": float(np.expm1(normal * model["residual_sd"])),
            "mean_residual_single": float(np.mean(residual[False])), "mean_residual_interleaving": float(np.mean(residual[True])),
            "residual_sd_all": model["residual_sd"],
            "residual_sd_single": by_kind[False]["residual_sd"], "residual_sd_interleaving": by_kind[True]["residual_sd"],
            "told_kind_coverage": float(np.mean(covered)), "told_kind_mean_half_width": float(np.mean(widths)),
            "told_kind_held_out": len(widths)}
    x = np.array([ladder.features(i["group"]) for i in train])
    mean, scale = x[:, 1:].mean(axis=0), x[:, 1:].std(axis=0)

    def design(items):
        rows = np.array([ladder.features(i["group"]) for i in items])
        return np.column_stack([np.ones(len(items)), (rows[:, 1:] - mean) / scale])

    labels = np.array([i["interleaves"] for i in train], float)
    beta = _logistic(design(train), labels)
    guessed = (design(test) @ beta) > 0.0
    truth = np.array([i["interleaves"] for i in test])
    rows_train = np.array([ladder.features(i["group"])[1:] for i in train])
    rows_test = np.array([ladder.features(i["group"])[1:] for i in test])
    neighbours, k = nearest_kind(rows_train, labels, rows_test)
    out["kind_named_from_groups"] = {"held_out": int(truth.size), "right": int(np.sum(guessed == truth)),
                                     "nearest_neighbours": k, "right_by_neighbours": int(np.sum(neighbours == truth)),
                                     "always_the_commoner": int(max(truth.sum(), truth.size - truth.sum()))}
    return out


def _narrowest_log_width(residuals, level: float = 0.95) -> float:
    """The smallest w with at least ``level`` of the residuals (ln) inside +-w: the ceil(level n)-th smallest |r|."""
    ordered = np.sort(np.abs(np.asarray(residuals, float)))
    return float(ordered[math.ceil(level * ordered.size) - 1])


def narrowest(items: list[dict], unseen: list[dict], table: dict, bands: int = 4) -> dict:
    """The narrowest 95 % ranges a one slider on these groups could declare, each set with the 2-D answers in hand:
    lower bounds on the width the declared range can reach, not ranges anyone could declare.

    Per quantity, the mean half-width (relative, exp(w) - 1, as the declared ranges): ``unseen``, about the shipped
    centre, one width holding 95 % of the held-out and fresh faults inside the box; ``refitted``, the correction
    refitted on all ``items`` (calibration, held out and fresh) and one width holding 95 % of their own residuals;
    ``by_band``, that refit with a width of its own in each of ``bands`` equal-count bands of W/h*; and
    ``by_band_told_kind``, refitted within each kind of 2-D sequence, a width per kind and band."""
    out = {"bands": bands, "faults": len(items)}
    for quantity in ("recurrence", "mean_slip"):
        beta = np.asarray(table[quantity]["coefficients"])
        shipped = [y - float(ladder.features(i["group"]) @ beta) for i, y in targets(unseen, quantity)
                   if not ladder.outside_box(i["group"], table)]
        pairs = targets(items, quantity)
        width = np.array([i["group"]["width_over_nucleation"] for i, _ in pairs])
        kinds = np.array([i["interleaves"] for i, _ in pairs])
        edges = np.quantile(width, np.linspace(0.0, 1.0, bands + 1))
        band = np.clip(np.searchsorted(edges, width, side="right") - 1, 0, bands - 1)

        def residuals(chosen):
            model = ladder.fit([pairs[k][0]["group"] for k in chosen], np.array([pairs[k][1] for k in chosen]))
            return np.array([pairs[k][1] - float(ladder.features(pairs[k][0]["group"]) @ np.asarray(model["coefficients"]))
                             for k in chosen])

        everyone = np.arange(len(pairs))
        refit = residuals(everyone)
        per_band = np.array([_narrowest_log_width(refit[band == b]) for b in band])
        per_kind_band = np.empty(len(pairs))
        for kind in (False, True):
            chosen = everyone[kinds == kind]
            within = residuals(chosen)
            per_kind_band[chosen] = [_narrowest_log_width(within[band[chosen] == band[k]]) for k in chosen]
        out[quantity] = {"unseen": float(np.expm1(_narrowest_log_width(shipped))), "unseen_faults": len(shipped),
                         "refitted": float(np.expm1(_narrowest_log_width(refit))), "refitted_faults": len(pairs),
                         "by_band": float(np.mean(np.expm1(per_band))),
                         "by_band_told_kind": float(np.mean(np.expm1(per_kind_band)))}
    return out


def evaluate(items: list[dict], table: dict) -> tuple[list[dict], dict]:
    """Each fault's 2-D answer against the declared range (``table``, as data/ladder_calibration.json), and per
    quantity how many of the faults inside the box it holds and the ranges' mean half-width."""
    rows, covered, widths = [], {q: [] for q in ladder.QUANTITIES}, {q: [] for q in ladder.QUANTITIES}
    for item in items:
        outside = ladder.outside_box(item["group"], table)
        row = {"name": item["name"], "width_over_nucleation": item["group"]["width_over_nucleation"],
               "burial": item["group"]["burial"], "outside": outside, "group": item["group"]}
        for quantity in ladder.QUANTITIES:
            truth = item["two_d"]["recurrence" if quantity == "recurrence" else quantity]
            if quantity == "surface_slip" and not item["surface_breaking"]:
                continue
            if not (math.isfinite(truth) and truth > 0):
                continue
            raw = item["block"]["recurrence" if quantity == "recurrence" else "slip"]
            band = ladder.predict(quantity, raw, item["group"], table)
            holds = band["low"] <= truth <= band["high"]
            row[quantity] = {"two_d": truth, "block": raw, **band, "holds": bool(holds),
                             "error_corrected": band["value"] / truth - 1, "error_uncorrected": raw / truth - 1}
            if not outside:
                covered[quantity].append(holds)
                widths[quantity].append(band["half_width"])
        rows.append(row)
    summary = {q: {"held_out": len(covered[q]), "holds": int(sum(covered[q])),
                   "coverage": float(np.mean(covered[q])) if covered[q] else math.nan,
                   "mean_half_width": float(np.mean(widths[q])) if widths[q] else math.nan,
                   "median_bias_uncorrected": table[q]["median_bias_uncorrected"],
                   "median_bias_corrected": table[q]["median_bias_corrected"]} for q in ladder.QUANTITIES}
    return rows, summary


def main():
    old = json.loads(OLD.read_text())["rows"]
    new = json.loads(NEW.read_text())["rows"]
    train_rows = old + [row for row in new if row["design"]["name"].startswith("calibration")]
    test_rows = [row for row in new if row["design"]["name"].startswith("held out")]
    train = [p for p in map(prepared, train_rows) if p is not None]
    test = [p for p in map(prepared, test_rows) if p is not None]
    skipped = {"calibration": len(train_rows) - len(train), "held_out": len(test_rows) - len(test)}
    table = {"provenance": {"computed_by": "benchmarks/ladder_calibration.py", "faultslip": __version__, **stamp(),
                            "definition": "ln(2-D / block) linear in the groups of faultslip.fault.ladder.FEATURES, "
                                          "least squares; ranges are the 95 % prediction intervals",
                            "calibration_faults": len(train), "held_out_faults": len(test),
                            "left_out_unsettled": skipped}}
    for quantity in ladder.QUANTITIES:
        pairs = targets(train, quantity)
        table[quantity] = ladder.fit([item["group"] for item, _ in pairs], np.array([y for _, y in pairs]))
        # the shipped table declares ranges; the fit's per-fault residuals are the held-out file's to show
        table[quantity].pop("standardized_residuals")
    table["box"] = ladder.box_of([item["group"] for item in train])
    # the designs stand in for "no ramp" and "creep right below the zone" with one element (0.002 W): a scene
    # stating none at all lies on that edge, not beyond it
    for name in ("ramp", "log_strengthening_depth"):
        table["box"][name][0] = 0.0
    rows, summary = evaluate(test, table)
    table["held_out"] = summary
    limit = limits(train, test, table)
    table["limits"] = {key: limit[key] for key in ("partial_share", "calibration_interleaving", "calibration_faults")}
    for quantity in ("recurrence", "mean_slip"):
        table["limits"][quantity] = {key: limit[quantity][key] for key in ("mean_residual_single", "mean_residual_interleaving")}
    # the budget's check counts the runs the cost model now declared estimated before they ran
    declared = cost_model()
    measured = [row for row in new + old if "cpu_time" in row and row["cpu_time"] > 0]
    runs = [row for row in measured if row.get("cost_model") == declared]

    def spread(chosen):
        ratios = [row["estimated_seconds"] / row["cpu_time"] for row in chosen]
        return {"runs": len(ratios), "within_2x": int(sum(0.5 <= r <= 2 for r in ratios)),
                "ratio_min": min(ratios, default=math.nan),
                "ratio_median": float(np.median(ratios)) if ratios else math.nan, "ratio_max": max(ratios, default=math.nan)}

    # the step count's model (FAULT_2D_EVENT_STEPS) is fitted on the calibration runs: the held-out ones test it
    budget = {**spread(runs), "estimated_by_older_models": len(measured) - len(runs),
              "held_out": spread([row for row in runs if row["design"]["name"].startswith("held out")]),
              "rows": [{"name": row["design"]["name"], "elements": row["elements"], "cpu_time": row["cpu_time"],
                        "estimated_seconds": row["estimated_seconds"], "steps": row["steps"],
                        "estimated_steps": row.get("estimated_steps")} for row in runs]}
    # a third draw, run after the ranges were shipped: neither the fit nor the choices behind it saw these faults
    # later draws, each run after the ranges were shipped and read against them as they are
    fresh, fresh_items = [], []
    for seed, (_, path) in FRESH_DRAWS.items():
        if not path.exists():
            continue
        fresh_rows = json.loads(path.read_text())["rows"]
        items = [p for p in map(prepared, fresh_rows) if p is not None]
        fresh_faults, fresh_summary = evaluate(items, table)
        fresh.append({"seed": seed, "file": path.name, "faults": len(fresh_rows),
                      "left_out_unsettled": len(fresh_rows) - len(items), "summary": fresh_summary,
                      "rows": fresh_faults,
                      "budget": spread([row for row in fresh_rows if row.get("cost_model") == declared])})
        fresh_items += items
    limit["narrowest"] = narrowest(train + test + fresh_items, test + fresh_items, table)
    write_bundled_table(OUT, table)
    HELD.write_text(json.dumps({**stamp(), "summary": summary, "rows": rows, "budget": budget, "limits": limit,
                                "left_out_unsettled": skipped, **({"fresh": fresh} if fresh else {})}, indent=1) + "\n",
                    encoding="utf-8")
    for quantity, line in summary.items():
        print(f"{quantity}: residual sd {table[quantity]['residual_sd']:.3f} over {table[quantity]['faults']} faults; "
              f"held out {line['holds']} of {line['held_out']} within the 95 % range "
              f"({line['coverage']:.3f}), mean half-width {line['mean_half_width']:.3f}; median bias "
              f"{line['median_bias_uncorrected']:+.3f} uncorrected, {line['median_bias_corrected']:+.3f} corrected")
    for quantity in ("recurrence", "mean_slip"):
        line = limit[quantity]
        print(f"{quantity}: residual {line['mean_residual_single']:+.3f} where every event breaks the zone, "
              f"{line['mean_residual_interleaving']:+.3f} where partial events interleave; sd {line['residual_sd_all']:.3f} "
              f"overall, {line['residual_sd_single']:.3f} and {line['residual_sd_interleaving']:.3f} within each kind; "
              f"told the kind, held out {line['told_kind_coverage']:.3f} covered at mean half-width "
              f"{line['told_kind_mean_half_width']:.3f}")
    named = limit["kind_named_from_groups"]
    for quantity in ("recurrence", "mean_slip"):
        line = limit[quantity]["gaussian_process"]
        print(f"{quantity}: a Gaussian process on the groups covers {line['coverage']:.3f} of {line['held_out']} held "
              f"out at mean half-width {line['mean_half_width']:.3f}; told the kind, {line['told_kind_coverage']:.3f} "
              f"at {line['told_kind_mean_half_width']:.3f}")
    for quantity in ("recurrence", "mean_slip"):
        curve = ", ".join(f"{p['faults']}: {p['linear_mean_half_width']:.3f} / {p['gaussian_process_mean_half_width']:.3f}"
                          for p in limit[quantity]["learning_curve"])
        print(f"{quantity}: mean half-width (linear / Gaussian process) by calibration faults {curve}; unlimited designs "
              f"(linear) {limit[quantity]['unlimited_designs_half_width']:.3f}")
    for quantity in ("recurrence", "mean_slip"):
        line = limit["narrowest"][quantity]
        print(f"{quantity}: narrowest 95 % ranges with the answers in hand: about the shipped centre "
              f"{line['unseen']:.3f} ({line['unseen_faults']} unseen faults); refitted on all {line['refitted_faults']} "
              f"{line['refitted']:.3f}; a width per W/h* band {line['by_band']:.3f}; and told the kind "
              f"{line['by_band_told_kind']:.3f}")
    print(f"the kind named from the groups on {named['right']} of {named['held_out']} held-out faults by a logistic "
          f"regression, {named['right_by_neighbours']} by {named['nearest_neighbours']} nearest neighbours "
          f"(always the commoner: {named['always_the_commoner']})")
    print(f"outside the box: {sum(bool(r['outside']) for r in rows)} held-out faults; unsettled left out: {skipped}")
    for draw in fresh:
        for quantity, line in draw["summary"].items():
            print(f"fresh draw (seed {draw['seed']}), {quantity}: {line['holds']} of {line['held_out']} within the 95 % "
                  f"range, mean half-width {line['mean_half_width']:.3f}")
    print(f"budget (the declared cost model's estimates): estimate / CPU from {budget['ratio_min']:.2f} to "
          f"{budget['ratio_max']:.2f} (median {budget['ratio_median']:.2f}), {budget['within_2x']} of {budget['runs']} "
          f"within 2x (held out: {budget['held_out']['within_2x']} of {budget['held_out']['runs']}, "
          f"{budget['held_out']['ratio_min']:.2f} to {budget['held_out']['ratio_max']:.2f}); "
          f"{budget['estimated_by_older_models']} runs estimated by older models left out")


if __name__ == "__main__":
    main()
