"""The one slider against the 2-D fault: calibration, limits and escalations (docs/ladder.md, docs/results.md)."""

from __future__ import annotations

import statistics

from ._common import ONE_SLIDER_QUANTITIES, _load, _load_with, _machine


#: the ordinals the draws' files and sentences are named by (a draw past the last is not shown)
ORDINALS = ("second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth", "tenth", "eleventh", "twelfth")


def ladder_table() -> str | None:
    """The one slider's corrected answers and 95 % ranges against held-out 2-D faults (ladder_calibration.py)."""
    result = _load("ladder_held_out.json")
    if result is None:
        return None
    names = ONE_SLIDER_QUANTITIES
    rows = ["| quantity | held-out 2-D faults inside the 95 % range | mean half-width | median bias, block "
            "uncorrected | median bias, corrected |", "| --- | --- | --- | --- | --- |"]
    for key, line in result["summary"].items():
        rows.append(f"| {names[key]} | {line['holds']} of {line['held_out']} ({100 * line['coverage']:.0f} %) | "
                    f"±{100 * line['mean_half_width']:.0f} % | {100 * line['median_bias_uncorrected']:+.0f} % | "
                    f"{100 * line['median_bias_corrected']:+.1f} % |")
    draws = result.get("fresh") or []
    ordinals = ORDINALS[1:]  # the first two draws are the calibration and the held-out designs
    for draw, ordinal in zip(draws, ordinals):
        for key, line in draw["summary"].items():
            rows.append(f"| {names[key]}, **{ordinal} draw, fresh** | {line['holds']} of {line['held_out']} "
                        f"({100 * line['coverage']:.0f} %) | ±{100 * line['mean_half_width']:.0f} % | | |")
    outside = sum(bool(row["outside"]) for row in result["rows"])
    budget = result["budget"]
    fresh_note = ""
    for draw, ordinal in zip(draws, ordinals):
        spent = draw["budget"]
        fresh_note += (f"The {ordinal} draw: {draw['faults']} faults (seed {draw['seed']}, `python "
                       f"benchmarks/ladder_designs.py --fresh {draw['faults']}"
                       + (f" --seed {draw['seed']}" if draw is not draws[0] else "")
                       + "`), run after the ranges were fitted and shipped and read against them as they are, "
                       f"{sum(bool(row['outside']) for row in draw['rows'])} of them outside the box"
                       + (f", {draw['left_out_unsettled']} left out unsettled" if draw["left_out_unsettled"] else "")
                       + (f"; the cost model estimated their CPU at {spent['ratio_min']:.2f} to {spent['ratio_max']:.2f}× "
                          f"what they used, {spent['within_2x']} of {spent['runs']} within 2×" if spent["runs"] else "")
                       + ". ")
    return ("\n".join(rows) + f"\n\n{len(result['rows'])} held-out faults drawn at random over the box "
            f"(`python benchmarks/ladder_designs.py`, then `benchmarks/ladder_calibration.py`), {outside} of them "
            f"outside it (no range declared). " + fresh_note
            + (f"Before each of the {budget['runs']} runs of `ladder_designs.py` (calibration and held out), the cost model now declared "
               f"estimated its CPU: {budget['ratio_min']:.2f} to {budget['ratio_max']:.2f}× what it used (median "
               f"{budget['ratio_median']:.2f}×), {budget['within_2x']} of {budget['runs']} within 2×"
               + (f"; on the {held['runs']} held-out faults, whose steps it was not fitted on, {held['within_2x']} "
                  f"of {held['runs']} ({held['ratio_min']:.2f} to {held['ratio_max']:.2f}×)"
                  if (held := budget.get("held_out")) and held["runs"] else "")
               + (f" ({budget['estimated_by_older_models']} runs estimated by older models are left out)"
                  if budget.get("estimated_by_older_models") else "") + ". " if budget["runs"] else "")
            + _machine(result))


def ladder_limits_table() -> str | None:
    """What limits the one slider's range: the two kinds of 2-D sequence (ladder_calibration.py) and how the kind
    and the recurrence move with D_c on the faults where both kinds occur (ladder_regimes.py)."""
    result = _load_with("ladder_held_out.json", "limits")
    if result is None:
        return None
    limits = result["limits"]
    names = {"recurrence": "recurrence", "mean_slip": "slip per event, mean over the rupture zone"}
    rows = ["| quantity | residual sd, all faults | mean residual: every event breaks the zone / partial events "
            "interleave | residual sd within each kind | held out, if told the kind: inside the 95 % range, mean "
            "half-width | a Gaussian process on the groups, held out: inside, mean half-width; told the kind |",
            "| --- | --- | --- | --- | --- | --- |"]
    for key, name in names.items():
        line = limits[key]
        rows.append(f"| {name} | {line['residual_sd_all']:.3f} | {line['mean_residual_single']:+.3f} / "
                    f"{line['mean_residual_interleaving']:+.3f} | {line['residual_sd_single']:.3f} / "
                    f"{line['residual_sd_interleaving']:.3f} | {100 * line['told_kind_coverage']:.0f} % of "
                    f"{line['told_kind_held_out']}, ±{100 * line['told_kind_mean_half_width']:.0f} % | "
                    + (f"{100 * gp['coverage']:.0f} %, ±{100 * gp['mean_half_width']:.0f} %; "
                       f"{100 * gp['told_kind_coverage']:.0f} %, ±{100 * gp['told_kind_mean_half_width']:.0f} % |"
                       if (gp := line.get("gaussian_process")) else "not run |"))
    named = limits["kind_named_from_groups"]
    text = ("\n".join(rows) + f"\n\nResiduals of ln(2-D / block) after the correction. Partial events interleave "
            f"(at least {limits['partial_share']:g} per system-size event) on {limits['calibration_interleaving']} of "
            f"{limits['calibration_faults']} calibration faults and {limits['held_out_interleaving']} of "
            f"{limits['held_out_faults']} held-out ones. A logistic regression on the groups, fitted on the "
            f"calibration faults, names the kind of {named['right']} of {named['held_out']} held-out faults"
            + (f", and a held-out fault's {named['nearest_neighbours']} nearest calibration faults in the groups (k by "
               f"leave-one-out) name {named['right_by_neighbours']}" if "right_by_neighbours" in named else "")
            + f"; always guessing the commoner kind names {named['always_the_commoner']}. The Gaussian process "
            "(a squared-exponential kernel with a length per group, and noise, fitted by marginal likelihood) is a "
            "nonlinear fit of the same groups.")
    # every range in the table: the linear fit told the kind, the Gaussian process without and with it
    fits = [(limits[key]["told_kind_coverage"], limits[key]["told_kind_mean_half_width"]) for key in names]
    fits += [(gp[prefix + "coverage"], gp[prefix + "mean_half_width"]) for key in names
             if (gp := limits[key].get("gaussian_process")) for prefix in ("", "told_kind_")]
    reached = sum(coverage >= 0.95 and half <= 0.25 for coverage, half in fits)
    text += (f"\n\nOf the {len(fits)} ranges above, {reached or 'none'} {'reaches' if reached <= 1 else 'reach'} 95 % "
             "of the held-out faults inside at a mean half-width of ±25 % or less.")
    if all("learning_curve" in limits[key] for key in names):
        def widths(key, fit):
            return ", ".join(f"±{100 * point[fit + '_mean_half_width']:.0f} %" for point in limits[key]["learning_curve"])

        curve = limits["recurrence"]["learning_curve"]
        sizes = ", ".join(str(point["faults"]) for point in curve[:-1])
        unlimited = [limits[key]["unlimited_designs_half_width"] for key in names]
        text += (f"\n\nFitted on random subsets of {sizes} of the {curve[-1]['faults']} calibration faults "
                 f"({curve[0]['draws']} draws each) and on all of them, the held-out recurrence range's mean half-width is "
                 f"{widths('recurrence', 'linear')} (the Gaussian process's {widths('recurrence', 'gaussian_process')}); "
                 f"the slip's {widths('mean_slip', 'linear')} ({widths('mean_slip', 'gaussian_process')}). With unlimited "
                 f"designs the declared range would tend to ±{100 * unlimited[0]:.0f} % (recurrence) and "
                 f"±{100 * unlimited[1]:.0f} % (slip), the residual's own spread"
                 + (": more designs of this kind do not bring it to ±25 %." if min(unlimited) > 0.25 else "."))
    if "narrowest" in limits:
        low = limits["narrowest"]
        rec, slip = low["recurrence"], low["mean_slip"]
        floor = min(low[key][fit] for key in names for fit in ("unseen", "refitted", "by_band", "by_band_told_kind"))
        text += ("\n\nSet with the 2-D answers in hand, the narrowest 95 % ranges of these groups are "
                 + ("all wider than ±25 %" if floor > 0.25 else f"as narrow as ±{100 * floor:.0f} %")
                 + f": one width about the shipped centre holding 95 % of the {rec['unseen_faults']} unseen faults (held out and "
                 f"fresh) is ±{100 * rec['unseen']:.0f} % (recurrence) and ±{100 * slip['unseen']:.0f} % (slip); the "
                 f"correction refitted on all {rec['refitted_faults']} faults, ±{100 * rec['refitted']:.0f} % and "
                 f"±{100 * slip['refitted']:.0f} % of its own residuals; a width of its own in each of "
                 f"{low['bands']} bands of W/h*, ±{100 * rec['by_band']:.0f} % and ±{100 * slip['by_band']:.0f} % on "
                 f"average; and told each fault's kind as well, ±{100 * rec['by_band_told_kind']:.0f} % and "
                 f"±{100 * slip['by_band_told_kind']:.0f} %. These bounds are not ranges anyone could declare: they "
                 "use the answers.")
    text += _resolved_sentence()
    regimes = _load("ladder_regimes.json")
    if regimes is not None:
        summary = regimes["summary"]
        factors = ", ".join(f"{100 * (f - 1):+.0f} %" for f in regimes["factors"] if f != 1.0)
        kinds = " or ".join(f"{kind} (period {period})" if kind == "periodic" else kind
                             for kind, period in summary["widest"]["sequences"])
        text += (f"\n\nRerun with D_c moved by {factors} (`python benchmarks/ladder_regimes.py`), the "
                 f"{summary['faults']} held-out faults whose W/h* lies in {regimes['mixed_width_over_nucleation'][0]:g}-"
                 f"{regimes['mixed_width_over_nucleation'][1]:g}, where both kinds occur, change kind on "
                 f"{summary['kind_changed']}. Their recurrence moves by at most {100 * summary['median_largest_change']:.1f} % "
                 f"on the median fault, and by up to {100 * summary['largest_change']:.0f} % where the sequence changes "
                 f"({summary['widest']['name']}'s runs are {kinds}). The partial events of their unmoved runs ({summary['partial_events']}) start a median "
                 f"{summary['partial_hypocentre_median']:.2f} W below the zone's top and break a median "
                 f"{100 * summary['partial_broken_median']:.0f} % of it.")
        if "starts" in regimes:
            text += "\n\n" + _starts_sentence(regimes["starts"])
    return text + "\n\n" + _machine(result)


def _resolved_sentence() -> str:
    """Whether the 3 per L_b answers the ranges were fitted on widen them: the spread of each unseen fault's
    residual about the shipped centre, against its 3 per L_b answer and against its resolved one
    (benchmarks/fault_2d_resolution_designs.py, summary ladder.residuals)."""
    import numpy as np
    from fault_2d_resolution_designs import DRAWS

    results = [_load(f"fault_2d_resolution_{name}.json") for name in DRAWS]
    results = [result for result in results if result is not None]
    ladders = [result["summary"].get("ladder", {}) for result in results]
    if not ladders or not all("residuals" in ladder.get(key, {}) for ladder in ladders
                              for key in ("recurrence", "mean_slip")):
        return ""
    spread = {}
    for key in ("recurrence", "mean_slip"):
        rows = np.array([row[1:] for ladder in ladders for row in ladder[key]["residuals"]], float)
        spread[key] = (len(rows), *np.std(rows, axis=0, ddof=1), *np.quantile(np.abs(rows), 0.95, axis=0))
    rec, slip = spread["recurrence"], spread["mean_slip"]
    wider = rec[2] >= rec[1] and slip[2] >= slip[1]
    return (f"\n\nRead against their resolved answers instead of their 3 per L_b ones (the Richardson limit of runs "
            f"to 12 or 24 elements per L_b, `benchmarks/fault_2d_resolution_designs.py`), the {rec[0]} unseen faults "
            f"inside the box scatter about the shipped centre with a residual sd of {rec[2]:.3f} (recurrence) and "
            f"{slip[2]:.3f} (slip), against {rec[1]:.3f} and {slip[1]:.3f}; 95 % of them lie within "
            f"±{100 * np.expm1(rec[4]):.0f} % and ±{100 * np.expm1(slip[4]):.0f} % "
            f"(±{100 * np.expm1(rec[3]):.0f} % and ±{100 * np.expm1(slip[3]):.0f} % at 3 per L_b). "
            + ("The element size the calibration ran at is not what widens the range: resolved, the scatter is no "
               "narrower." if wider else "Resolved, the scatter is narrower: the calibration's element size widens "
               "the range."))


def _starts_sentence(block: dict) -> str:
    """What the held-out faults do from other starts (ladder_regimes.py --part start)."""
    summary = block["summary"]
    speeds = " and ".join(f"{factor:g}" for factor in block["initial_speeds_over_plate_rate"])

    def reached(entry):
        kind = (f"another period-{entry['period']} cycle" if entry["sequence"] == "periodic" else "no settled cycle")
        return (f"{entry['name']} (period {entry['usual_period']} from the usual start; from {entry['start']:g} times "
                f"the plate rate, {kind}, its mean interval {100 * entry['largest_change']:+.0f} %)")

    elsewhere = "; ".join(reached(entry) for entry in summary["elsewhere"])
    return (f"Rerun from other starts, every element in steady state at {speeds} times the plate rate "
            f"(`python benchmarks/ladder_regimes.py --part start`), {summary['same_answer']} of the "
            f"{summary['settled_from_usual_start']} held-out faults that settle from the usual start settle to the "
            f"same cycle (recurrence within {summary['same_answer_within']:g})"
            + (f"; {len(summary['elsewhere'])} do not, and are multistable: {elsewhere}" if summary["elsewhere"] else "")
            + f". The kind changes on {summary['kind_changed']} of {summary['faults']}; the "
            f"{summary['unsettled_from_usual_start']} that do not settle move their mean interval by up to "
            f"{100 * summary['unsettled_largest_change']:.0f} %. A fault's answer can depend on its start, which no "
            "range built on its friction and geometry can know.")


def ladder_escalations_table() -> str | None:
    """Escalations up the ladder: the budget's estimate against the CPU used (ladder_escalations.py), on the draw
    the per-step cost was not fitted on (seed 68001) where it has been run."""
    result = _load("ladder_escalations_held_out.json")
    if result is None:
        return None
    rows = ["| fault | elements | 2-D runs | estimated | CPU used | estimate / CPU | machine factor | CPU a step / fitted |",
            "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for row in sorted(result["rows"], key=lambda r: r["design"]["name"]):
        name = f"| {row['design']['name']} (W/h* {row['design']['width_over_nucleation']:.2f}) | {row['elements']} | "
        if "refused" in row:
            rows.append(name + "refused before it ran, in one sentence | | | | | |")
            continue
        factor = f"{row['machine_factor']:.2f}" if "machine_factor" in row else "not taken"
        rows.append(name + f"{row.get('runs', 1)} | {row['estimated_seconds']:.1f} s | {row['cpu_time']:.1f} s | "
                    f"{row['estimated_seconds'] / row['cpu_time']:.2f} | {factor} | {_step_speed(row):.2f} |")
    summary = result["summary"]
    refused = summary.get("refused", 0)
    return ("\n".join(rows) + f"\n\nEach scene {_how_run(result)}. "
            f"{summary['within_2x']} of {summary['escalations']} escalations within 2x (median "
            f"{summary['ratio_median']:.2f}, {summary['ratio_min']:.2f} to {summary['ratio_max']:.2f})"
            + (f", {refused} refused before any work, in one sentence" if refused else "") + "; "
            f"`python benchmarks/ladder_escalations.py --seed {result.get('seed', 68000)}`"
            f"{' (a draw the per-step cost never saw)' if result.get('seed', 68000) != 68000 else ''}. "
            + _further_draws() + "The machine factor is what the estimate took for this machine's speed: the "
            "reference work's CPU time in the escalation's process (in draws run since the machine speed record, the "
            "median of the readings it keeps) over its time where the step's cost was anchored "
            "(`faultslip.io.machine`, `benchmarks/machine_speed.py`). The last column is each escalation's CPU a step "
            "(its runs' steps, its first run's loading of the compiled step included) over the per-step CPU the cost "
            "model was fitted with (`FAULT_2D_STEP_SECONDS`): below 1, the machine ran the steps faster than when the "
            f"model was fitted (median {statistics.median(_step_speed(r) for r in result['rows'] if 'refused' not in r):.2f} "
            "here), which the factor is there to follow. "
            f"{_machine(result)}")


def _how_run(result: dict) -> str:
    """The tolerance a draw's scenes were run to and the elements per L_b they were drawn on."""
    resolutions = [row["elements_per_process_zone"] for row in result["rows"]]
    return (f"run to tolerance {result.get('tolerance', 0.05):g} on {min(resolutions):.1f}-"
            f"{max(resolutions):.1f} elements per L_b")


def _step_speed(row: dict) -> float:
    """An escalation's CPU a step, over all its runs, over the fitted per-step CPU."""
    from faultslip.models.fault_2d import cost
    from ladder_escalations import total_steps

    c0, c1, _ = cost.FAULT_2D_STEP_SECONDS
    return row["cpu_time"] / total_steps(row) / (c0 + c1 * row["elements"])


def _further_draws() -> str:
    """Further draws of escalations the cost model never saw (ladder_escalations_second_draw.json, then the
    third to twelfth), a sentence each."""
    text = ""
    for ordinal in ORDINALS:
        name = f"ladder_escalations_{ordinal}_draw.json"
        result = _load(name)
        if result is None:
            continue
        summary = result["summary"]
        article = "An" if ordinal[0] in "aeiou" else "A"
        text += (f"{article} {ordinal} unseen draw (`--seed {result['seed']}`; {_how_run(result)}): "
                 f"{summary['within_2x']} of "
                 f"{summary['escalations']} within 2x ({summary['ratio_min']:.2f} to {summary['ratio_max']:.2f}, median "
                 f"{summary['ratio_median']:.2f})"
                 + (f"; {summary['refused']} refused before any work, in one sentence" if summary.get("refused") else "")
                 + ". " + _probes_apart(result) + _record_against_probe(result))
    return text


#: The escalation draws run with the machine speed record before its median took the process's own probe beside it.
MEDIAN_ALONE_SEEDS = {68070}


def _record_against_probe(result: dict) -> str:
    """For a draw run since the machine speed record: the readings its medians were of, and the same estimates
    with each worker's probe alone (the estimate scales as the factor, first-run cost included)."""
    ran = [row for row in result["rows"] if "refused" not in row and "probe_factor" in row]
    if not ran:
        return ""
    alone = [row["estimated_seconds"] * row["probe_factor"] / row["machine_factor"] / row["cpu_time"] for row in ran]
    def span(values, digits=".2f"):
        low, high = f"{min(values):{digits}}", f"{max(values):{digits}}"
        return low if low == high else f"{low}-{high}"

    taken = ("the median of the machine speed record" if result["seed"] in MEDIAN_ALONE_SEEDS else
             "the machine speed record's median with each worker's own probe weighted beside it (`PROBE_WEIGHT`)")
    return (f"Its estimates took {taken} "
            f"({span([row['machine_readings'] for row in ran], 'd')} readings, factor "
            f"{span([row['machine_factor'] for row in ran])}); with each worker's probe alone (factor "
            f"{span([row['probe_factor'] for row in ran])}) the same estimates would have been {min(alone):.2f} to "
            f"{max(alone):.2f}x their CPU, {sum(0.5 <= r <= 2 for r in alone)} of {len(ran)} within 2x. ")


def _probes_apart(result: dict) -> str:
    """Where a draw's workers read the machine's speed more than 25 % apart (each worker probes once, when it
    first estimates): the factors, the steps' own speed on each, and the estimates over CPU of each."""
    ran = [row for row in result["rows"] if "refused" not in row]
    factors = sorted({round(row["machine_factor"], 3) for row in ran})
    if len(factors) < 2 or factors[-1] < 1.25 * factors[0]:
        return ""
    speeds = [_step_speed(row) for row in ran]
    text = (f"Its workers' probes read the machine at {' and '.join(f'{f:.2f}' for f in factors)} times the reference "
            f"work's anchored time, while the steps ran at {min(speeds):.2f} to {max(speeds):.2f} times the fitted "
            "CPU a step on every worker")
    for factor in factors:
        ratios = [row["estimated_seconds"] / row["cpu_time"] for row in ran
                  if round(row["machine_factor"], 3) == factor]
        text += f"; the estimates of the worker that read {factor:.2f}, {min(ratios):.2f} to {max(ratios):.2f}x its CPU"
    return text + ". "


def ladder_outside_box_table() -> str | None:
    """The recurrence a budget expects of faults below the calibrated box against their 2-D answer
    (ladder_outside_box.py)."""
    result = _load("ladder_outside_box.json")
    if result is None:
        return None
    names = {"block": "the derived block, uncorrected", "median_ratio": "the block times the calibration's median ratio",
             "clamped": "the correction at the box's nearest point (taken)"}
    rows = ["| expected recurrence | faults within 2x of the 2-D recurrence | expected / 2-D, median | range |",
            "| --- | --- | --- | --- |"]
    for key, label in names.items():
        line = result["summary"][key]
        rows.append(f"| {label} | {line['within_2x']} of {line['faults']} | {line['ratio_median']:.2f} | "
                    f"{line['ratio_min']:.2f}-{line['ratio_max']:.2f} |")
    low, high = result["ratios"]
    return ("\n".join(rows) + f"\n\nFaults drawn as the calibration's are, with W / h* of {low:g}-{high:g} "
            f"(seed {result['seed']}); {result['left_out_unsettled']} whose 2-D run did not settle are left out. "
            "`python benchmarks/ladder_outside_box.py`. " + _machine(result))


def fault_2d_event_steps_table() -> str | None:
    """The 2-D fault's step count from its events, estimated against measured, on the runs it was fitted on and the
    runs it never saw, beside the earlier model (fault_2d_event_steps.py)."""
    result = _load("fault_2d_event_steps.json")
    if result is None:
        return None
    rows = ["| runs | count | declared model: estimated / measured steps, median (range) | within 2x | earlier model "
            "(events^p (W/h*)^q N^r), refitted | within 2x |", "| --- | --- | --- | --- | --- | --- |"]
    fitted = {"calibration": "calibration designs (fitted: A, q, r)",
              "escalations 68000": "escalation draw 68000, first runs (fitted: s)",
              "fresh": "fresh designs, seed 68002 (unseen)", "fresh2": "fresh designs, seed 68012 (unseen)",
              "fresh3": "fresh designs, seed 68014 (unseen)", "fresh4": "fresh designs, seed 68031 (unseen)",
              "fresh5": "fresh designs, seed 68041 (unseen)", "fresh6": "fresh designs, seed 68061 (unseen)"}
    for name, line in result["sets"].items():
        label = fitted.get(name, f"{name}{', first runs' if name.startswith('escalations') else ' designs'} (unseen)")
        d, e = line["declared"], line["earlier"]
        rows.append(f"| {label} | {d['runs']} | {d['ratio_median']:.2f} ({d['ratio_min']:.2f}-{d['ratio_max']:.2f}) | "
                    f"{d['within_2x']} | {e['ratio_median']:.2f} ({e['ratio_min']:.2f}-{e['ratio_max']:.2f}) | "
                    f"{e['within_2x']} |")
    model = result["model"]
    return ("\n".join(rows) + "\n\nsteps = A events (W/h*)^q (W/L_b)^r (L_b/h / 3)^s (rtol / 1e-8)^-0.18 + 100, "
            f"with A = {model['scale']:.4g}, q = {model['width_over_nucleation']:.3f}, "
            f"r = {model['width_over_process_zone']:.3f}, s = {model['elements_per_process_zone']:.3f} "
            "(`FAULT_2D_EVENT_STEPS`); the events are a run's duration over the recurrence the one-slider rung "
            "expects. " + "".join(f"{count} of the {name} draw's runs, outside the one slider's box and run before "
                                  "its recurrence there was clamped to the box's edge, are left out (their duration "
                                  "is not the one the rule now gives). " for name, count in
                                  result.get("left_out", {}).items() if count)
            + "Steps do not depend on the machine: `python benchmarks/fault_2d_event_steps.py` refits it from the "
            "saved runs. " + _machine(result))


#: The tables this module renders, by the marker name in the pages.
TABLES = {
    "ladder": ladder_table,
    "ladder_limits": ladder_limits_table,
    "ladder_escalations": ladder_escalations_table,
    "ladder_outside_box": ladder_outside_box_table,
    "fault_2d_event_steps": fault_2d_event_steps_table,
}
