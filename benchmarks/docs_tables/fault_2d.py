"""The 2-D antiplane fault against QDYN, its threads, placement, profile, resolution and period-3 run (docs/fault_2d.md, docs/benchmarks.md)."""

from __future__ import annotations

from ._common import _load, _load_with, _machine, _packages, _peer_closing


def fault_2d_table() -> str | None:
    result = _load("fault_2d.json")
    if result is None:
        return None
    rows = ["| run | elements | recurrence | surface slip per event | settled (spread) | steps | wall time |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for row in result["convergence"] + [result["timed_at_loosest"]]:
        rows.append(f"| BP1, {row['element_size_m']:g} m, {row['years']:g} yr, rtol {row['rtol']:g} | {row['elements']} | "
                    f"{row['recurrence_yr']:.5f} yr | {row['surface_slip_m']:.5f} m | {row['settled']} "
                    f"({row['recurrence_spread']:.1e}) | {row['steps']:,} | {row['wall_s'] / 60:.1f} min |")
    difference = result["difference_coarse_fine"]
    rows.append("")
    rows.append(f"Between the two element sizes: recurrence {difference['recurrence'] * 100:.3f} %, surface slip "
                f"{difference['surface_slip'] * 100:.3f} %. The loosest rtol tested whose recurrence (100 m, "
                f"{result['tolerance_study'][0]['years']:g} yr) stays within 0.1 % of the tightest's: "
                f"{result['loosest_rtol']:g} (relative differences: " + ", ".join(
                    f"{row['rtol']:g}: {row['recurrence_error']:.1e}" for row in result["tolerance_study"]) + ").")
    finer = result.get("finer")
    if finer:
        coarse, fine = finer["sizes_m"]
        rows.append("")
        rows.append(f"{fine:g} m against {coarse:g} m: recurrence {finer['recurrence_difference'] * 100:.4f} %, surface "
                    f"slip {finer['surface_slip_difference'] * 100:.4f} %. Its cost is {finer['cost_ratio']:.2f}× "
                    f"{coarse:g} m's: {finer['steps_ratio']:.2f}× the steps (finer elements resolve faster slip, so the "
                    f"steps through each rupture shorten) and {finer['cost_per_step_ratio']:.2f}× the cost a step, "
                    + ("within" if finer["cost_per_step_ratio"] <= finer["n_log_n_ratio"] else "above")
                    + f" the {finer['n_log_n_ratio']:.2f}× that an N log N product predicts for twice the elements "
                    f"(the {coarse:g} m and {fine:g} m rows at rtol 1e-8 measured on {finer['date']}, one after the "
                    "other on one pinned core; the other rows on the date below).")
    return "\n".join(rows) + "\n\n" + _machine(result)


def fault_2d_qdyn_table() -> str | None:
    result = _load("fault_2d_qdyn.json")
    if result is None:
        return None
    grid = result.get("tolerance_grid") or []
    rows = ["| code, solver | loosest tolerance within 0.1 % of its own converged recurrence | recurrence (its "
            "converged value) | steps | wall time | CPU time | peak memory |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for name, code in result["codes"].items():
        timed = code.get("timed")
        study = [row for row in code["study"] if "failed" not in row and row.get("settled")]
        failed = [row for row in code["study"] if "failed" in row]
        converged = min(study, key=lambda row: row["tolerance"])["recurrence_yr"] if study else float("nan")
        failures = (" (failed at " + ", ".join(f"{row['tolerance']:g}" for row in failed) + ": " +
                    failed[0]["failed"].split(":")[0] + ")") if failed else ""
        if timed is None or "failed" in timed:
            rows.append(f"| {name} | none{failures} | | | not timed | | |")
            continue
        rows.append(f"| {name} | {code['setting']:g}{failures} | {timed['recurrence_yr']:.4f} yr ({converged:.4f} yr) "
                    f"| {timed['steps']:,} | {timed['wall_s']:.1f} s | {timed.get('cpu_s', float('nan')):.1f} s | "
                    f"{timed.get('peak_mib', float('nan')):.0f} MiB |")
    rows.append("")
    if result.get("ratio_faultslip_over_best_peer"):
        rows.append(f"faultslip / {result['best_peer']} = **{result['ratio_faultslip_over_best_peer']:.2f}** in wall time, "
                    f"{result.get('cpu_ratio_faultslip_over_best_peer', float('nan')):.2f} in CPU time (target ≤ 0.5). "
                    f"BP1 for {result['years']:g} yr on {result['elements']} elements of "
                    f"{result['element_size_m']:.4g} m; every code's tolerance study ran over "
                    f"{result['tolerance_years']:g} yr on the same grid, {grid[0]:g} to {grid[-1]:g}; each timed run a "
                    f"whole process pinned to core {result.get('pinned_core', 0)}, the codes interleaved over "
                    f"{result.get('rounds', 1)} rounds (order reversed every other round), the medians shown; QDYN "
                    f"commit {(result.get('qdyn_commit') or 'unknown')[:7]}.")
        memory = [f"{name} {code['memory']['short_peak_mib']:.0f} MiB over {code['memory']['short_years']:g} yr and "
                  f"{code['memory']['long_peak_mib']:.0f} MiB over {code['memory']['long_years']:g} yr "
                  f"({code['memory']['growth']:+.1%})" for name, code in result["codes"].items() if code.get("memory")]
        if memory:
            rows.append("")
            rows.append("Peak memory against the simulated span: " + "; ".join(memory) + ".")
    return _peer_closing(rows, result)


def fault_2d_threads_table() -> str | None:
    result = _load("fault_2d_threads.json")
    if result is None:
        return None
    rows = [f"| elements | {result['runs'][0]['years']:g}-yr runs: one / two threads | gain | trial steps near "
            "(pairs) | short runs in pairs, near throughout: median (pairs, range) |", "| --- | --- | --- | --- | --- |"]
    for run in result["runs"]:
        near = run["trial_steps"]["near"]
        steps = f"{near['speedup']:.2f}× ({near['pairs']})" if near["pairs"] else "none near"
        short = run.get("short_runs") or {}
        gains = [pair["gain"] for pair in short.get("pairs", []) if pair["placement"] == "near"]
        pairs = (f"{short['near_median_gain']:.2f}× ({len(gains)}, {min(gains):.2f}-{max(gains):.2f}×)" if gains
                 else "none near throughout")
        rows.append(f"| {run['elements']:,} | {run['one_thread']['wall_s']:.2f} / {run['two_threads']['wall_s']:.2f} s "
                    f"| {run['speedup']:.2f}× | {steps} | {pairs} |")
    share = result["placement"]["share"]
    span = f", {result['started']}-{result['ended']} UTC" if result.get("started") else ""
    years = result["runs"][0].get("short_runs", {}) or {}
    return ("\n".join(rows) + f"\n\nTarget ≥ 1.6×. {result['rounds']} interleaved rounds of whole runs (medians), "
            + (f"pairs of {years['years']:g}-yr runs, " if years else "")
            + f"batches of 100 trial steps through the run's loop; the placement over the run: shared core "
            f"{share['shared core']:.0%}, near {share['near']:.0%}, far {share['far']:.0%}. The same bits on one "
            f"thread and two: {all(run['identical_bits'] for run in result['runs'])}. "
            f"`python benchmarks/fault_2d_threads.py`; {result['machine']}, {result['date']}{span}."
            + _packages(result))


def fault_2d_placement_table() -> str | None:
    result = _load("fault_2d_placement.json")
    if result is None:
        return None
    rows = ["| placement | rounds | private work, the other core busy | private work, a spin barrier after each "
            f"{result.get('chunk_values', 800)} values | a barrier | a line written on one core, read on the "
            f"other | a task's {result['trial_lines']:,} such lines a trial at {result['elements']:,} elements |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for name, row in result["classes"].items():
        if row["rounds"]:
            between = row.get("work_between_barriers")
            barrier = row.get("barrier_us")
            rows.append(f"| {name} | {row['rounds']} | {row['private_slowdown']:.2f}× | "
                        + (f"{between:.3f}× | " if between is not None else "not measured | ")
                        + (f"{barrier:.2f} µs | " if barrier is not None else "not measured | ")
                        + f"{row['crossing_ns_per_line']:.1f} ns | {row['trial_crossing_us']:.0f} µs |")
    span = f", {result['started']}-{result['ended']} UTC" if result.get("started") else ""
    return ("\n".join(rows) + f"\n\nEach round kept in the class its round trips before and after agree on. "
            f"`python benchmarks/fault_2d_placement.py`; {result['machine']}, {result['date']}{span}."
            + _packages(result))


def fault_2d_profile_table() -> str | None:
    result = _load("fault_2d_profile.json")
    if result is None:
        return None
    parts = list(result["runs"][0]["inside_the_step_us"])
    rows = ["| elements | a trial step | " + " | ".join(result["runs"][0]["shares"]) + " | "
            + " | ".join(f"inside: {part}" for part in parts) + " |", "| --- " * (2 + len(result["runs"][0]["shares"])
                                                                               + len(parts)) + "|"]
    for run in result["runs"]:
        rows.append(f"| {run['elements']:,} | {run['per_trial_us'] / 1e3:.2f} ms | "
                    + " | ".join(f"{share:.0%}" for share in run["shares"].values()) + " | "
                    + " | ".join(f"{run['inside_the_step_us'][part]:.0f} µs" for part in parts) + " |")
    first = result["runs"][0]
    return ("\n".join(rows) + f"\n\nBP1 over {first['years']:g} yr at rtol {first['rtol']:g} on one pinned core; the "
            "shares split the run by cProfile, the parts inside the step are each timed alone on the run's last state. "
            f"`python benchmarks/fault_2d_profile.py`. {_machine(result)}")


def fault_2d_resolution_table() -> str | None:
    result = _load("fault_2d_resolution.json")
    if result is None:
        return None
    from faultslip.models.fault_2d.analysis import MIN_RESOLUTION, discretisation_error

    levels = [run["resolution"] for run in result["faults"][0]["runs"]]
    rows = ["| fault | W / h* | " + " | ".join(f"{level:.2g} per L_b" for level in levels) + " |",
            "| --- " * (2 + len(levels)) + "|"]
    for fault in result["faults"]:
        cells = [("unsettled" if run["sequence"] == "unsettled" else f"{run['error']:.2%}") for run in fault["runs"]]
        rows.append(f"| {fault['name']} ({fault['scene']}) | "
                    f"{fault['seismogenic_width_m'] / fault['nucleation_size_m']:.2g} | " + " | ".join(cells) + " |")
    nominal = [round(level, 1) for level in levels]  # the designed levels (a size is a whole number of elements)
    rows.append("| declared | | " + " | ".join("refused" if level < MIN_RESOLUTION else
                                                 f"{discretisation_error(level):.2%}" for level in nominal) + " |")
    return ("\n".join(rows) + "\n\nEach run's recurrence against its fault's Richardson limit over the element "
            "sizes; elements per L_b = G D_c / (sigma_n b) rounded. `python benchmarks/fault_2d_resolution.py`. "
            + _machine(result))


def _resolution_designs_rows(result: dict) -> list[str]:
    """Per element size: the runs measured (their fault settled at its finest run, and they are not its
    reference), how many keep the reference's kind, the largest error, the bound declared now and how many runs
    exceed it (for their period), and the runs whose kind changed."""
    from fault_2d_resolution_designs import measured
    from faultslip.models.fault_2d.analysis import discretisation_error, sequence_discretisation

    rows = ["| elements per L_b | runs measured | kind kept | largest error, kind kept | declared (period 1) | "
            "above the declared bound | kind changed (largest error) |", "| --- " * 7 + "|"]
    for resolution in (*result["resolutions"], result["refined"]):
        line = result["summary"].get(f"{resolution:g}")  # the benchmark's counts; the bound is read here, as now
        if not line or not line["runs"]:
            continue
        above = [fault for fault in result["faults"] if measured(fault, f"{resolution:g}")
                 and (run := fault["runs"][f"{resolution:g}"])["kind_of_reference"] and run["sequence"] == "periodic"
                 and run["error_recurrence"] > sequence_discretisation(resolution, run["period"])[0]]
        rows.append(f"| {resolution:g} | {line['runs']} | {line['kept_kind']} | {line['largest_error_kept']:.2%} | "
                    f"{discretisation_error(resolution):.2%} | {len(above)} | {line['changed_kind']}"
                    + (f" ({line['largest_error_changed']:.1%})" if line["changed_kind"] else "") + " |")
    return rows


def _resolution_designs_note(result: dict) -> str:
    ladder = result["summary"]["ladder"]
    everywhere = _refine_flag(result) == "--refine-all"
    where = "too (every fault)" if everywhere else "where those three show no order in (1, 5.5)"
    return (f"Each fault run at {', '.join(f'{r:g}' for r in result['resolutions'])} elements per L_b, and at "
            f"{result['refined']:g} {where}; its reference is the Richardson "
            "limit of its finest three runs (the finest run where they are not in the asymptotic range or change "
            "kind). Declared: the bound as now, for the run's period. The one slider's shipped ranges hold the 3 per "
            f"L_b answer on {ladder['recurrence']['hold_coarse']} and the resolved one on "
            f"{ladder['recurrence']['hold_resolved']} of {ladder['recurrence']['faults']} faults inside the box "
            f"(recurrence), {ladder['mean_slip']['hold_coarse']} and {ladder['mean_slip']['hold_resolved']} of "
            f"{ladder['mean_slip']['faults']} (mean slip).")


def fault_2d_resolution_designs_table() -> str | None:
    result = _load("fault_2d_resolution_designs.json")
    if result is None or "ladder" not in result["summary"]:
        return None
    fit = result["summary"]["envelope"]

    def form(envelope):
        return " + ".join(f"{scale:.3g} (2 / r)^{order:g}" for scale, order in envelope["terms"])

    exceeded = "; ".join(f"{draw['draw'].removeprefix('fault_2d_resolution_').removesuffix('.json')} by "
                         f"{draw['exceeded']:.2f} times ({draw['by']} at {draw['at']:g} per L_b)"
                         for draw in fit["draws"])
    return ("\n".join(_resolution_designs_rows(result)) + f"\n\nThe ladder's {result['summary']['faults']} "
            f"held-out designs. {_resolution_designs_note(result)} The envelope of least geometric mean over 2-16 "
            f"per L_b through every measured run of these and the three faults above ({fit['before_draws']['faults']}"
            f" faults) is {form(fit['before_draws'])}. Fresh draws (below), each run against the envelope of everything "
            f"before it, exceeded it: {exceeded}. Through "
            f"all {fit['faults']} faults it is {form(fit)}; declared: that envelope times {fit['margin']:.2f}, "
            "rounded outward. `python benchmarks/fault_2d_resolution_designs.py --refine`. " + _machine(result))


def _fresh_table(draw: str, how: str) -> str | None:
    result = _load(f"fault_2d_resolution_{draw}.json")
    if result is None or "ladder" not in result["summary"]:
        return None
    return ("\n".join(_resolution_designs_rows(result)) + f"\n\nThe first {result['summary']['faults']} designs of "
            f"a fresh draw ({result['source']}), {how}. {_resolution_designs_note(result)} "
            f"`python benchmarks/fault_2d_resolution_designs.py {_refine_flag(result)} --source {result['source']} "
            f"--first {result['summary']['faults']}`. " + _machine(result))


def _refine_flag(result: dict) -> str:
    """The benchmark's option that ran the finest size: on every fault (--refine-all) or where needed."""
    everywhere = all(f"{result['refined']:g}" in fault["runs"] for fault in result["faults"])
    return "--refine-all" if everywhere else "--refine"


#: how the draws run with every fault at 24 per L_b (--refine-all) were run
RUN_FINER_EVERYWHERE = ("run after the bound and the kind-change term were declared, every fault at 24 per L_b too: "
                        "faults neither ever saw")


def fault_2d_resolution_fresh_third_table() -> str | None:
    return _fresh_table("ladder_fresh_third", RUN_FINER_EVERYWHERE)


def fault_2d_resolution_fresh_first_table() -> str | None:
    return _fresh_table("ladder_fresh", RUN_FINER_EVERYWHERE)


def fault_2d_resolution_fresh_sixth_table() -> str | None:
    return _fresh_table("ladder_fresh_sixth", RUN_FINER_EVERYWHERE + ", drawn sessions after the two above")


def fault_2d_resolution_fresh_table() -> str | None:
    return _fresh_table("ladder_fresh_second", "run against the envelope of the held-out designs, which it exceeded: "
                                               "the bound is now fitted through it")


def fault_2d_resolution_fresh_fifth_table() -> str | None:
    return _fresh_table("ladder_fresh_fifth", "run against the envelope of the held-out designs and the draw above, "
                                              "which it exceeded: the bound is now fitted through it, with its margin")


def fault_2d_resolution_fresh_fourth_table() -> str | None:
    return _fresh_table("ladder_fresh_fourth", "run after, against the bound as declared now: faults it never saw")


def fault_2d_kind_changes_table() -> str | None:
    """docs/fault_2d.md: the runs whose element size changed the kind of sequence, over the held-out designs and
    the fresh draws, against the kind-change term one run declares (faultslip.models.fault_2d.analysis)."""
    from fault_2d_resolution_designs import KIND_CHANGE_FITTED, KIND_CHANGE_UNSEEN, kind_changes
    from faultslip.models.fault_2d.analysis import KIND_CHANGE_TERM

    results = [_load(f"fault_2d_resolution_{name}.json") for name in KIND_CHANGE_FITTED]
    if any(result is None for result in results):
        return None
    faults = sum(len(result["faults"]) for result in results)
    scale, order = KIND_CHANGE_TERM
    text = ("\n".join(_kind_change_rows([change for result in results for change in kind_changes(result["faults"])]))
            + f"\n\nOver {faults} faults of the held-out designs and three fresh draws "
            f"(`benchmarks/results/fault_2d_resolution_*.json`), each run whose kind of sequence is not its finest "
            f"run's, against that fault's reference. One run declares the larger of the bound and "
            f"{scale:g} (2 / r)^{order:g}: the envelope through these runs at the steepest order the runs at 6 per "
            "L_b allow, rounded outward. Two sizes that agree in kind (`--richardson`) lift it. "
            + _machine(results[0]))
    unseen = [result for name in KIND_CHANGE_UNSEEN if (result := _load(f"fault_2d_resolution_{name}.json"))]
    if not unseen:
        return text
    faults = [fault for result in unseen for fault in result["faults"]]
    changes = kind_changes(faults)
    counts = ", ".join(f"{sum(r == resolution for _, r, _ in changes)} of "
                       f"{sum(f'{resolution:g}' in fault['runs'] for fault in faults)} at {resolution:g}"
                       for resolution in unseen[0]["resolutions"])
    drawn = "; ".join(f"{result['source']}, its first {len(result['faults'])} designs" for result in unseen)
    commands = "; ".join(f"`python benchmarks/fault_2d_resolution_designs.py --refine-all --source {result['source']} "
                         f"--first {len(result['faults'])}`" for result in unseen)
    return (text + f"\n\nThen fresh draws the term never saw, every fault also run at {unseen[0]['refined']:g} per "
            f"L_b, so that each run at 6 and 12 per L_b has a finer run to be read against ({drawn}). Runs whose "
            f"kind is not their finest run's: {counts} per L_b.\n\n"
            + "\n".join(_kind_change_rows(changes) if changes else ["No run changed kind."])
            + f"\n\n{commands}. " + _machine(unseen[-1]))



def _kind_change_rows(changes: list) -> list[str]:
    """Per element size: the runs whose kind is not their finest run's, the worst of them, the bound and what one
    run declares, and how many runs exceed that."""
    from faultslip.models.fault_2d.analysis import discretisation_error, single_run_error

    rows = ["| elements per L_b | runs that changed kind | largest error | worst (its kind; finest run's) | "
            "bound, kind kept | declared by one run | above it |", "| --- " * 7 + "|"]

    def kind(run):
        return ("unsettled" if run["sequence"] != "periodic" else f"period {run['period']}") + (
            ", interleaved" if run["interleaves"] else "")

    for resolution in sorted({resolution for _, resolution, _ in changes}):
        here = [(fault, run) for fault, r, run in changes if r == resolution]
        fault, worst = max(here, key=lambda item: item[1]["error_recurrence"])
        finest = fault["runs"][f"{fault['reference_resolutions'][-1]:g}"]
        declared = single_run_error(resolution)
        rows.append(f"| {resolution:g} | {len(here)} | {worst['error_recurrence']:.1%} | {fault['name']} "
                    f"({kind(worst)}; finest: {kind(finest)}) | {discretisation_error(resolution):.2%} | "
                    f"{declared:.1%} | "
                    f"{sum(run['error_recurrence'] > declared for _, run in here)} |")
    return rows


def fault_2d_period3_table() -> str | None:
    result = _load("fault_2d_period3.json")
    if result is None:
        return None
    rows = ["| element size | sequence | intervals (yr) | mean (yr) | largest interval error | steps | wall time |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for run in result["runs"]:
        errors = run.get("interval_errors")
        rows.append(f"| {run['element_size_m']:g} m | {run['kind']}, period {run['period']} | "
                    + ", ".join(f"{value:.3f}" for value in run["intervals_yr"])
                    + f" | {run['mean_interval_yr']:.4f} | " + (f"{max(errors):.1e}" if errors else "n/a")
                    + f" | {run['steps']:,} | {run['wall_s']:.0f} s |")
    return ("\n".join(rows) + f"\n\n`configs/{result['scene']}` over {result['runs'][0]['years']:g} yr; each "
            f"interval against the {result['runs'][0]['element_size_m']:g} m run's. "
            f"`python benchmarks/fault_2d_period3.py`. {_machine(result)}")


def surface_crack_table() -> str | None:
    """docs/fault_2d.md: the stress kernel on a surface-breaking crack against Knopoff's ellipse (docs_numbers)."""
    result = _load_with("docs_numbers.json", "surface_crack")
    if result is None:
        return None
    rows = ["| elements | slip, largest error above 0.9 of the depth | potency, tip included |", "| --- | --- | --- |"]
    rows += [f"| {row['elements']} | {row['slip']:.2e} | {row['potency']:.2e} |" for row in result["surface_crack"]["rows"]]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


#: The tables this module renders, by the marker name in the pages.
TABLES = {
    "surface_crack": surface_crack_table,
    "fault_2d": fault_2d_table,
    "fault_2d_qdyn": fault_2d_qdyn_table,
    "fault_2d_threads": fault_2d_threads_table,
    "fault_2d_placement": fault_2d_placement_table,
    "fault_2d_profile": fault_2d_profile_table,
    "fault_2d_resolution": fault_2d_resolution_table,
    "fault_2d_resolution_designs": fault_2d_resolution_designs_table,
    "fault_2d_resolution_fresh": fault_2d_resolution_fresh_table,
    "fault_2d_resolution_fresh_fifth": fault_2d_resolution_fresh_fifth_table,
    "fault_2d_resolution_fresh_fourth": fault_2d_resolution_fresh_fourth_table,
    "fault_2d_kind_changes": fault_2d_kind_changes_table,
    "fault_2d_resolution_fresh_third": fault_2d_resolution_fresh_third_table,
    "fault_2d_resolution_fresh_first": fault_2d_resolution_fresh_first_table,
    "fault_2d_resolution_fresh_sixth": fault_2d_resolution_fresh_sixth_table,
    "fault_2d_period3": fault_2d_period3_table,
}
