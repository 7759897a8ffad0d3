"""The fuzzer's record (docs/reliability.md) and the integrators' declared errors (docs/methods.md, docs/rate_state.md)."""

from __future__ import annotations

from ._common import _load, _load_with, _machine


def reliability_table() -> str | None:
    fuzz, kills = _load("fuzz.json"), _load("kills.json")
    if fuzz is None:
        return None
    outcomes = fuzz["outcomes"]
    rows = ["| check | result |", "| --- | --- |",
            f"| mutated inputs run through the CLI (`benchmarks/fuzz.py`) | {fuzz['cases']:,} |",
            f"| answered (exit 0) | {outcomes.get('ok', 0):,} (+ {outcomes.get('mismatch', 0)} tampered files "
            f"that `reproduce` reported as differing) |",
            f"| refused with one sentence, exit 2 | {outcomes.get('clean', 0):,} |",
            f"| tracebacks and multi-line errors | **{sum(outcomes.get(k, 0) for k in ('traceback', 'unclean', 'environment'))}** |",
            f"| silent: a changed input answered as if unchanged (exit 0) | **{outcomes.get('silent', 0)}** |",
            f"| cases over the fuzzer's {fuzz.get('timeout_s', 60):g} s limit | {outcomes.get('timeout', 0)} |"]
    hard = {"zarr": "Zarr stores as written, or damaged (missing, corrupted or swapped chunks, an attribute edited in the "
                    "store or its consolidated metadata), converted or reproduced (whole, or spot-checked with good and bad --cells)",
            "netcdf": "a sweep's sealed netCDF output, bytes mutated, one bit flipped, or an attribute or coordinate "
                      "edited, then reproduced (whole, or spot-checked with good and bad --cells and --seed), read as a record or fitted",
            "ledger": "a sweep's failure ledger edited (cells dropped, indices changed) or mutated, then --retry-failed",
            "partial": "an interrupted sweep's partial output (netCDF or Zarr: bytes, an attribute, a coordinate, a "
                       "chunk) or progress record damaged, then --resume (exit 0 must give the run without a stop)",
            "registry": "the fit registry edited (a fit's parameter, its checksum, the version) or mutated, then the "
                        "fit used",
            "catalog": "catalogs: CSV mutated, or faultslip's QuakeML with a value's digit changed, its checksum "
                       "removed or its bytes mutated, then fitted",
            "mseed": "faultslip's miniSEED records with a bit flipped in a data record or bytes mutated, then analysed",
            "table": "a table faultslip ships and reads back (a calibration, a cost model, a declared error) edited "
                     "or mutated, then read by a command",
            "deep": "TOML nested 33 to 3,000 deep", "device": "devices, FIFOs and folders given as files",
            "lock": "symlinks, hard links and FIFOs planted at an output's lock",
            "full": "writes into a full disk (300 kB tmpfs)", "race": "a second writer of another kind holding the output",
            "gaf": "GAF GeoJSON: slip types, MultiLineStrings, repeated ids",
            "fault_2d": "mutated 2-D fault scenes (run, and simulate into a folder)",
            "checkpoint": "a stopped 2-D run's checkpoint flipped, cut, emptied, re-saved, edited or linked, then --resume",
            "stream": "its record streams flipped, cut, grown, deleted or linked to a victim file, then --resume",
            "hazard": "hazard options: b-value, magnitudes, bin width, moment constant, scaling relations",
            "raw": "raw rig records with stiffness, area, trend, steps, windows, priors and posteriors",
            "upload": "classroom uploads with hostile names and headers (no markup may reach the page)",
            "bundle": "fit bundles edited, emptied, shadowed, inflated or given options of the wrong kind, replayed",
            "xlsx": "Excel workbooks: bytes flipped, a stray cell far out, text among the numbers",
            "rfile": "xlook r-files (lines and bytes mutated), reduced",
            "memo": "the unit memo edited or damaged, then units read through it",
            "names": "path names the file system may not take (too long for a name, a folder or a path; a broken "
                     "link; not UTF-8; control characters) and bundled examples' bare names, as inputs or outputs"}
    by_input = fuzz.get("by_input", {})
    for kind, label in hard.items():
        if kind in by_input:
            counts = by_input[kind]
            bad = sum(counts.get(k, 0) for k in ("traceback", "unclean", "environment", "timeout", "silent"))
            differing = f" {counts['mismatch']} reported by `reproduce` as differing," if counts.get("mismatch") else ""
            rows.append(f"| of which {label} | {sum(counts.values()):,}: {counts.get('ok', 0)} answered,{differing} "
                        f"{counts.get('clean', 0)} refused in one sentence, {bad} failures |")
    if kills:
        k, r = kills["kills"], kills["races"]
        rows += [f"| sweeps killed at random moments (`benchmarks/kills.py`) | {k['kill -9']} kill -9 and "
                 f"{k['ctrl-c']} Ctrl-C; {len(k['problems'])} problems (orphan workers, half-written files, "
                 "resumed results that differ) |",
                 f"| two sweeps racing for one output | {r['rounds']} rounds, {r['one_refused']} refused the second "
                 f"writer by name; {len(r['problems'])} problems |"]
    second = _load("fuzz_second_seed.json")
    if second is not None:  # a second seed, the same kinds (issue 69: two new seeds of 10,000 cases)
        o = second["outcomes"]
        rows.append(f"| second seed ({second['seed']}): {second['cases']:,} cases | {o.get('ok', 0):,} answered, "
                    f"{o.get('clean', 0):,} refused in one sentence, **"
                    f"{sum(o.get(k, 0) for k in ('traceback', 'unclean', 'environment', 'timeout', 'silent'))}** "
                    "failures |")
    return "\n".join(rows) + "\n\n" + _machine(fuzz) + (f" Kills: {_machine(kills)[12:]}" if kills else "")


def _model_text(model) -> str:
    constant, power, floor = model
    text = f"{constant:g} rtol" + (f"^{power:g}" if power != 1 else "")
    return text + (f" + {floor:.2g}" if floor else "")


def _fresh_cell(fresh: list, name: str) -> str:
    """A table cell: each fresh draw's largest error / declared for one integrator, in the draws' order."""
    return " " + ", ".join(f"{draw['summary'][name]['largest_ratio']:.2f}" for draw in fresh) + " |" if fresh else ""


def _fresh_text(fresh: list, what: str) -> str:
    """The fresh draws' seeds and sizes, and the runs each measured, for a table's notes."""
    if not fresh:
        return ""
    return ("; fresh draws, run after the model was shipped and read against it as it is: "
            + ", ".join(f"seed {draw['seed']} ({draw[what]} {what})" for draw in fresh) + _measured_text(fresh)
            + "".join(f"; on seed {draw['seed']}, {name}'s largest error is {row['largest_ratio']:.2g} times its "
                      f"declared ({row['at']}): past it, not fixed"
                      for draw in fresh for name, row in draw["summary"].items()
                      if not row.get("within_declared", True)))


def _measured_text(fresh: list) -> str:
    """How many runs each fresh draw measured: one clause when every run was."""
    if all(row["failed"] == 0 for draw in fresh for row in draw["summary"].values()):
        return " (every run measured)"
    return (" (runs measured: " + "; ".join(", ".join(f"{name} {row['runs'] - row['failed']} of {row['runs']}"
                                                      for name, row in draw["summary"].items())
                                            for draw in fresh) + ")")


def event_driven_errors_table() -> str | None:
    """docs/methods.md: each event-driven integrator's declared error, the largest calibration error against it,
    and the held-out draw's (benchmarks/event_driven_calibration.py)."""
    result = _load_with("event_driven_calibration.json", "held_out")
    if result is None:
        return None
    calibration, held, fresh = result["calibration"], result["held_out"], result.get("fresh", [])
    rows = ["| integrator | declared error | calibration: largest error / declared, over rtol 1e-3 to 1e-12 | "
            "held out: runs measured | held out: largest error / declared | where |"
            + (" fresh draws: largest error / declared |" if fresh else ""),
            "| --- | --- | --- | --- | --- | --- |" + (" --- |" if fresh else "")]
    for solver, model in result["model"].items():
        row, found = calibration["envelope"][solver], held["summary"][solver]
        ratios = [e / d for e, d in zip(row["largest_error"], row["declared_error"])]
        rows.append(f"| {solver} | {_model_text(model)} | {max(ratios):.2f} | {found['runs'] - found['failed']} of "
                    f"{found['runs']} | {found['largest_ratio']:.2f} | {found['at']} |" + _fresh_cell(fresh, solver))
    later_seeds, per_later = calibration.get("later_seeds", []), calibration.get("per_later_seed", 0)
    drawn = calibration["per_seed"] * len(calibration["seeds"]) + per_later * len(later_seeds)
    later = (f", and {per_later} from each of seeds {', '.join(str(s) for s in later_seeds)}, first checked as fresh "
             "draws against the model set on the first three, then added where runs broke it (the test "
             "test_cells_that_broke_earlier_declared_errors_are_inside_the_shipped_one reruns such cells)"
             if later_seeds else "")
    rows += ["", f"Errors as the contract declares them: the larger relative error of amplitude and period, or the "
             f"event times' drift per cycle, over {calibration['cycles']} cycles against the exact cycle (DOP853 at "
             f"rtol 1e-13 for Cameron's law and nonlinear kinetic laws). Calibration: {calibration['scenes']} scenes, "
             f"the bench's {calibration['scenes'] - drawn} stick-slip "
             f"scenes with an exact cycle and {calibration['per_seed']} random scenes from each of seeds "
             f"{', '.join(str(s) for s in calibration['seeds'])}{later}; held out: {held['scenes']} scenes from seed "
             f"{held['seed']}, measured once against the shipped model{_fresh_text(fresh, 'scenes')}. Random scenes: "
             "every Table I row, damping "
             "ratio 0 or 1e-3 to 0.3, 1e-4 to 0.98 theta_c, with a kinetic slope, Cameron's law or a polynomial "
             "kinetic law on three in four. Largest calibration error / rtol by friction law: "
             + "; ".join(f"{solver}: " + ", ".join(f"{law} {value:.3g}" for law, value in
                                                 calibration["envelope"][solver]["largest_over_rtol_by_law"].items())
                         for solver in result["model"])
             + ". `python benchmarks/event_driven_calibration.py`. " + _machine(result)]
    return "\n".join(rows)


def refinement_check_table() -> str | None:
    """docs/methods.md: the event-driven runs on a law the calibration never drew, before and with the refinement
    check (benchmarks/refinement_check.py)."""
    result = _load_with("refinement_check.json", "held_out")
    if result is None:
        return None
    rows = ["| draw | runs | before: largest error / declared | before: runs over | with the check: largest "
            "error / declared | with the check: runs over | rtol tightened | evaluations, with / before (median, "
            "largest) |", "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for label, found in [*((f"seed {d['seed']} (chose the factor)", d) for d in result["chosen_on"]),
                         (f"seed {result['held_out']['seed']} (held out)", result["held_out"])]:
        s = found["summary"]
        rows.append(f"| {label} | {s['runs']} | {s['largest_ratio_before']:.3g} | {s['over_declared_before']} | "
                    f"{s['largest_ratio']:.2f} | {s['over_declared']} | {s['tightened']} | "
                    f"{s['evaluations_ratio_median']:.2g}, {s['evaluations_ratio_max']:.2g} |")
    rows += ["", f"Each draw: {result['held_out']['scenes']} rough-surface scenes (seed 000), three of the example's "
             f"parameters moved by a factor within 1/{result['spread']:g} to {result['spread']:g}; every integrator "
             f"({', '.join(result['solvers'])}) at tolerances {', '.join(f'{t:g}' for t in result['tolerances'])}, "
             "against DOP853 at rtol 1e-12. The error is the largest relative error of amplitude, period, stress "
             "drop (a graze's excepted), peak slip speed and slip per event. Before: the first run and its "
             f"calibrated error; with the check: the answer and at least {result['factor']:g} times its difference "
             f"from a run at rtol / {result['refinement']:g}, the rtol tightened while that exceeds the tolerance. "
             "`python benchmarks/refinement_check.py`. " + _machine(result)]
    return "\n".join(rows)


def rough_auto_choice_table() -> str | None:
    """docs/methods.md: auto on rough-surface scenes ranking by the family's fitted prices against by the
    calibration's seconds (benchmarks/rough_auto_choice.py)."""
    result = _load_with("rough_auto_choice.json", "summary")
    if result is None:
        return None
    s, ways = result["summary"], ("fitted prices", "calibration's seconds")
    rows = ["| tolerance | runs | method changed | CPU by the calibration's ranking / by the fitted prices (median) |",
            "| --- | --- | --- | --- |"]
    for tolerance in result["tolerances"]:
        found = [r for r in result["rows"] if r["tolerance"] == tolerance]
        rows.append(f"| {tolerance:g} | {len(found)} | {sum(r[ways[0]]['method'] != r[ways[1]]['method'] for r in found)}"
                    f" | {s['by_tolerance'][f'{tolerance:g}']:.2f} |")
    rows += ["", f"{result['count']} fresh rough-surface scenes (seed "
             f"{result['seed']}), each solved by auto at each tolerance both ways, interleaved; CPU the median of "
             f"{result['rounds']} timings. Over all {s['runs']} runs the ratio is {s['cpu_ratio_median']:.2f} "
             f"(median), from {s['cpu_ratio_min']:.2f} to {s['cpu_ratio_max']:.2f}. The largest error over the "
             f"declared is {s['largest_error_over_declared'][ways[0]]:.2f} ranked by the fitted prices and "
             f"{s['largest_error_over_declared'][ways[1]]:.2f} by the calibration's seconds, against DOP853 at rtol "
             "1e-12. `python benchmarks/rough_auto_choice.py`. " + _machine(result)]
    return "\n".join(rows)


def _rate_state_model_text(model) -> str:
    far, near = model["far"], model["near"]
    return f"max({_model_text(far)}, {near[0]:g} rtol^{near[1]:g} / ((1 - K / K_c) (1 - a / b)))"


def rate_state_errors_table() -> str | None:
    """docs/rate_state.md: each cycle integrator's declared error, the calibration's margin and the held-out
    faults' largest error against it (benchmarks/rate_state_calibration.py)."""
    result = _load_with("rate_state_calibration.json", "held_out")
    if result is None:
        return None
    calibration, held, fresh = result["calibration"], result["held_out"], result.get("fresh", [])
    rows = ["| integrator | declared error (recurrence, slip per event) | calibration: runs measured | calibration: "
            "smallest declared / error | held out: runs measured | held out: largest error / declared | where |"
            + (" fresh draws: largest error / declared |" if fresh else ""),
            "| --- | --- | --- | --- | --- | --- | --- |" + (" --- |" if fresh else "")]
    for method, model in result["model"].items():
        row, found = calibration["envelope"][method], held["summary"][method]
        failed = sum(row["failed_runs"].values())
        rows.append(f"| {method} | {_rate_state_model_text(model)} | {row['runs'] - failed} of {row['runs']} | "
                    f"{row['smallest_declared_over_error']:.2f} | {found['runs'] - found['failed']} of "
                    f"{found['runs']} | {found['largest_ratio']:.2f} | {found['at']} |" + _fresh_cell(fresh, method))

    def where(row):
        place = row.get("failed_where") or {}
        if not place.get("stiffness_ratio"):
            return ""
        low, high = place["stiffness_ratio"]
        return (f" (K / K_c {low:.3g} to {high:.3g}, rtol {min(place['rtol']):g} to {max(place['rtol']):g})")

    failures = "; ".join(f"{method}: " + ", ".join(f"{count} {outcome.replace('_', ' ')}"
                                                   for outcome, count in row["failed_runs"].items()) + where(row)
                         for method, row in calibration["envelope"].items() if row["failed_runs"])
    without = len(calibration["reference_failures"])
    later_seeds, per_later = calibration.get("later_seeds", []), calibration.get("per_later_seed", 0)
    later = (f", and {per_later} from each of seeds {', '.join(str(s) for s in later_seeds)}, fresh draws that "
             "broke the near model while it was k rtol^p / (1 - K / K_c) and joined the calibration when it took "
             "(1 - a / b) in" if later_seeds else "")
    regression = calibration.get("near_regression")
    form = (" The near model's form is the calibration's: least squares of ln error on its near runs gives "
            "exponents " + "; ".join(f"{method} {row['stiffness_ratio_exponent']:.2f} on (1 - K / K_c) and "
                                     f"{row['a_over_b_exponent']:.2f} on (1 - a / b)"
                                     for method, row in regression.items()) + "." if regression else "")
    rows += ["", f"Errors: the larger relative error of recurrence and slip per event, {calibration['cycles']} cycles "
             f"once settled, against the C stepper at rtol {calibration['reference_rtol']:g}, at rtol 1e-5 to 1e-10. "
             f"Calibration: {calibration['faults']} random faults, {calibration['per_seed']} from each of seeds "
             f"{', '.join(str(s) for s in calibration['seeds'])}{later}; the far model is fitted on those below "
             f"K / K_c {calibration['near_critical_from']:g}, the near one on those above, each at least "
             f"{calibration['margin_required']:g} times every error a run's declared settling does not already cover; "
             f"the declared error a run reports is this plus its settling left. Held out: "
             f"{held['faults']} faults from seed {held['seed']}, measured once against the shipped model"
             f"{_fresh_text(fresh, 'faults')}. "
             "Random faults: a 0.003 to 0.02, a / b 0.3 to 0.95, the aging or the slip law, sigma_n 5 to 150 MPa, "
             "G 20 to 40 GPa, width 1 to 50 km, plate rate 1e-10 to 5e-9 m/s, K / K_c 1e-5 to 0.9 or (1 in 5) "
             "0.9 to 0.999. Runs not measured: "
             + (failures or "none") + "; a budget exceeded is a run past the bench's 400,000 steps (dopri5's steps "
             "are stability-limited at a lab-scale D_c, where auto takes LSODA)"
             + (f"; {without} faults whose reference did not run (past its budget, or no events near K_c) are left "
                "out" if without else "") + "." + form + " `python benchmarks/rate_state_calibration.py`. "
             + _machine(result)]
    return "\n".join(rows)


def rate_state_settling_table() -> str | None:
    """docs/rate_state.md: the steps a fault's recorded cycles take, the settling model against random faults
    (benchmarks/rate_state_settling.py)."""
    result = _load_with("rate_state_settling.json", "summary")
    if result is None:
        return None
    fit, summary = result["fit"], result["summary"]
    rows = ["| faults | count | modelled / measured steps, median (range) | within 2x |", "| --- | --- | --- | --- |"]
    for name, label in (("fitted", "fitted (seeds 1, 2)"), ("held_out", "held out (seed 3, unseen)")):
        line = summary[name]
        rows.append(f"| {label} | {line['faults']} | {line['ratio_median']:.2f} ({line['ratio_min']:.2f}-"
                    f"{line['ratio_max']:.2f}) | {line['within_2x']} |")
    rows += ["", f"steps = steps_per_cycle(method, rtol, K / K_c) (cycles + {fit['base']:.3g} + {fit['c']:.3g} / "
             f"((1 - K / K_c)^{fit['p']:.3g} (1 - a / b)^{fit['q']:.3g})), rtol {result['rtol']:g} "
             "(`faultslip.dynamics.rate_state.methods.cycle_steps`). Random faults about BP1's friction: a / b 0.3 to "
             "0.95, either law, sigma_n x 0.2 to 3, D_c x 0.25 to 4, K / K_c 1e-4 to 0.9 or (1 in 3) 0.9 to 0.998; 2, "
             f"5 or 20 cycles recorded. {summary['no_events']} drawn faults had no events (slip speed peaking below "
             "1 mm/s, or cycles longer than the run's horizon) and are left out. Steps do not depend on the "
             "machine. `python benchmarks/rate_state_settling.py`. " + _machine(result)]
    return "\n".join(rows)


#: The tables this module renders, by the marker name in the pages.
TABLES = {
    "reliability": reliability_table,
    "event_driven_errors": event_driven_errors_table,
    "refinement_check": refinement_check_table,
    "rough_auto_choice": rough_auto_choice_table,
    "rate_state_errors": rate_state_errors_table,
    "rate_state_settling": rate_state_settling_table,
}
