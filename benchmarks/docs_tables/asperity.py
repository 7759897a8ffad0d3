"""Seed 004's asperity friction against the paper's Tables II and III (docs/asperity.md)."""

from __future__ import annotations

from ._common import _load, _machine


def _bands(speeds_mm_s: list, step_mm_s: float) -> list[str]:
    """Runs of adjacent speeds (mm/s) as "low-high" bands: a gap wider than 1.5 steps starts a new band."""
    if not speeds_mm_s:
        return []
    bands, start, last = [], speeds_mm_s[0], speeds_mm_s[0]
    for speed in speeds_mm_s[1:]:
        if speed - last > 1.5 * step_mm_s:
            bands.append(f"{start:.2f}-{last:.2f}")
            start = speed
        last = speed
    bands.append(f"{start:.2f}-{last:.2f}")
    return bands


def _stuck_bands(stuck: dict) -> str:
    return "; ".join(_bands([v * 1e3 for v in stuck["stick_speeds"]], stuck["step"] * 1e3)) or "none"


def _millimetres(values: list, digits: str = ".2f") -> str:
    return ", ".join(f"{v * 1e3:{digits}}" for v in values)


def _before_the_bound(result) -> str:
    """Said of results measured before the quasi-static integrator's step bound (dynamics.STEPS_PER_PERIOD)."""
    return ("" if "steps_per_period" in result else "These runs predate the quasi-static step bound (\"The "
            "quasi-static method against the six-state one\") and have not been rerun with it. ")


def asperity_trends_table() -> str | None:
    result = _load("asperity_trends.json")
    if result is None:
        return None
    lines = ["**m_D peaks (C = 200 kg/s, no adhesion; quasi-static method) against Tables II and III**", "",
             "| system | computed v_c1/n from eqs. (28)-(29) (mm/s) | simulated peaks (mm/s) | paper (mm/s) |",
             "| --- | --- | --- | --- |"]
    ours, theirs = [], []
    for row in result["peaks"]:
        lines.append(f"| {row['system']} | {_millimetres(row['computed'])} | {_millimetres(row['simulated'])} | "
                     f"{_millimetres(row['paper'], '.4g')} |")
        ours += [p / c - 1 for p, c in zip(row["integer"], row["computed"])]
        theirs += [p / c - 1 for p, c in zip(row["paper"], row["computed"])]
    lines += ["", "Integer peaks (the simulated peak nearest each v_c1/n): "
              + "; ".join(f"{row['system']}: {_millimetres(row['integer'])} mm/s" for row in result["peaks"]) + ".",
              "", f"Against v_c1/n from eqs. (28)-(29), the paper's peaks sit {100 * min(theirs):+.0f} % to "
              f"{100 * max(theirs):+.0f} % off, ours {100 * min(ours):+.0f} % to {100 * max(ours):+.0f} % "
              f"({sum(o < 0 for o in ours)} of {len(ours)} below)."]
    bands = result["case_6_bands"]
    low, high = bands["range"]
    lines += ["", f"**Stick-slip bands, case 6 (C = 2 kg/s), {low * 1e3:g}-{high * 1e3:g} mm/s in steps of "
              f"{bands['step'] * 1e3:.2g} mm/s:** {_stuck_bands(bands)} mm/s.", "",
              "**Single runs (6 s, last half analysed)**", "",
              "| run | method | stick fraction | loops per period | m-bar | m-bar_D |", "| --- | --- | --- | --- | --- | --- |"]
    for row in result["single_runs"]:
        if row["status"] != "ok":
            lines.append(f"| {row['run']} | {row['method']} | {row['status']} | | | |")
            continue
        lines.append(f"| {row['run']} | {row['method']} | {row['stick_fraction']:.3f} | {row['loops']} | "
                     f"{row['mean_friction']:.4f} | {row['mean_deformation_friction']:.2e} |")
    choices = result["choices"]
    first_low, first_high = choices[0]["range"]
    lines += ["", f"**Dependence on our choices: the stick-slip band around v_c1 (case 6, C = 2 kg/s, "
              f"{first_low * 1e3:g}-{first_high * 1e3:g} mm/s in steps of {choices[0]['step'] * 1e3:.2g} mm/s, "
              "quasi-static)**", "",
              "| choice | v_c1 = f0 lambda (mm/s) | stick-slip speeds (mm/s) | m-bar at the band |", "| --- | --- | --- | --- |"]
    lines += [f"| {row['choice']} | {row['critical_speed'] * 1e3:.2f} | {_stuck_bands(row)} | {row['mean_friction']:.4f} |"
              for row in choices]
    lines += ["", "**Contact loss (asperity_LSODA, C = 200 kg/s, first failing speed of a x1.25 ladder)**", "",
              "| s | closed-form estimate (m/s) | six-state integration fails at (m/s) | paper: m_D vanishes at (m/s) |",
              "| --- | --- | --- | --- |"]
    for row in result["contact_loss"]:
        failed = (f"{row['six_state_fails_at']:.3g} ({row['status']})" if row["six_state_fails_at"]
                  else "none up to the ladder's top")
        lines.append(f"| {row['slope_std']} | {row['estimate']:.3g} | {failed} | {row['paper']} |")
    ratios = [row["estimate"] / row["paper"] for row in result["contact_loss"]]
    lines += ["", f"The closed-form estimate is {min(ratios):.2g}-{max(ratios):.2g} times the paper's speeds.", "",
              f"`python benchmarks/asperity_trends.py`. {_before_the_bound(result)}{_machine(result)}"]
    return "\n".join(lines)


def asperity_wavelength_table() -> str | None:
    """docs/asperity.md: the closed form's critical speeds against the simulated locks (asperity_wavelength_check)."""
    result = _load("asperity_wavelength_check.json")
    if result is None or "held_out_rows" not in result:
        return None
    rows = ["| draw | system | n | f0 (Hz) | s | α (µm) | closed form f0 λ / n (mm/s) | n-loop lock (mm/s) | strongest in "
            "it (mm/s) | closed form / strongest - 1 |", "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
    for draw, key in (("calibration", "rows"), ("held out", "held_out_rows")):
        for row in result[key]:
            if row["error"] is None:
                found = "none in the sweep | | "
            else:
                low, high = row["band"]
                found = (f"{1e3 * low:.3g}-{1e3 * high:.3g} | {1e3 * row['simulated']:.3g} | "
                         f"{100 * row['error']:+.1f} %")
            rows.append(f"| {draw} | {row['system']} | {row['order']} | {row['natural_frequency']:.3g} | "
                        f"{row['slope_std']:.2f} | {1e6 * row['contact_length']:.3g} | {1e3 * row['closed_form']:.3g} | "
                        f"{found} |")
    return "\n".join(rows) + (
        f"\n\nLargest |closed form / simulated - 1|: {result['largest_error']:.3f} (calibration), so the declared "
        f"error is {result['fitted_error']:g} (shipped {result['declared_error']:g}); held out, "
        f"{result['held_out_largest_error']:.3f}. {result['without_lock']} sweeps showed no n-loop lock. Quasi-static "
        f"sweeps, C = 200 kg/s, 3 s each, {result['sweep'][0]:g} to {result['sweep'][1]:g} v_cn on {result['sweep'][2]} "
        f"speeds; random systems from seeds {', '.join(str(seed) for seed in result['seeds']['calibration'])} "
        f"(calibration) and {result['seeds']['held_out']} (held out). "
        f"`python benchmarks/asperity_wavelength_check.py`. "
        f"{_before_the_bound(result)}"
        f"{_machine(result)}")


def asperity_measured_wavelength_table() -> str | None:
    """docs/asperity.md: f0 lambda_run / n against the same locks (asperity_measured_wavelength_check)."""
    result = _load("asperity_measured_wavelength_check.json")
    if result is None:
        return None
    lines = result["rows"] + result["held_out_rows"]
    compared = [line for line in lines if line["error"] is not None]
    closed = [abs(line["closed_form_error"]) for line in compared]
    ours = [abs(line["error"]) for line in compared]
    systems = [line for line in result["systems"] if line["wavelength"] is not None]
    cpu = [line["cpu_seconds"] for line in systems]
    rows = ["| predictor | largest error, calibration | largest error, held out | median error | predictions "
            "inside the n-loop band | declared error | cost |", "| --- | --- | --- | --- | --- | --- | --- |",
            f"| closed form f0 λ / n (`asperity_wavelength`) | {result['closed_form_largest_error']:.3f} | "
            f"{result['closed_form_held_out_largest_error']:.3f} | {sorted(closed)[len(closed) // 2]:.3f} | "
            f"{result['closed_form_inside_band']} of {result['compared']} | {result['closed_form_declared_error']:g} | "
            "closed form |",
            f"| run's wavelength f0 λ_run / n (`asperity_measured_wavelength`) | {result['largest_error']:.3f} | "
            f"{result['held_out_largest_error']:.3f} | {sorted(ours)[len(ours) // 2]:.3f} | {result['inside_band']} "
            f"of {result['compared']} | {result['fitted_error']:g} (shipped {result['declared_error']:g}) | "
            f"{min(cpu):.2g}-{max(cpu):.2g} s CPU |"]
    ratio = [line["wavelength"] / line["closed_form_wavelength"] for line in systems]
    return "\n".join(rows) + (
        f"\n\nThe same {result['compared']} locks as the table above (their file's SHA-256 "
        f"{result['locks']['sha256'][:12]}...). Each system's run lasts {result['measure_periods']} natural periods at "
        f"the closed form's v_c1; its wavelength is {min(ratio):.3f} to {max(ratio):.3f} times eq. (29)'s, the median "
        f"of {min(line['cycles'] for line in systems)} or more cycles that differ by at most "
        f"{max(line['spread'] for line in systems):.3f} (relative); from rtol 1e-8 to 1e-10 it changes by at most "
        f"{result['largest_numerical_error']:.1g}. The locks are located on the sweeps' speed step, "
        f"{(result['sweep_high'] - result['sweep_low']) / (result['sweep_points'] - 1):.4f} of v_cn, so errors below "
        f"it are within the reference's own resolution. The declared error is {result['margin']:g} times "
        "the largest calibration error, rounded up. `python benchmarks/asperity_measured_wavelength_check.py`. "
        f"{_machine(result)}")


def asperity_quasistatic_table() -> str | None:
    """docs/asperity.md: the quasi-static method against the six-state one on random systems."""
    result = _load("asperity_quasistatic_check.json")
    if result is None:
        return None
    measured = [row for row in result["rows"] if row["measured"]]
    sticking_differ = sum(row["loops"][0] != row["loops"][1] for row in measured if row["stick_fraction"][1] > 0.05)
    rows = ["| systems run | sticking (> 5 % of the time) | largest stick-fraction error (absolute) | largest, "
            "relative, where sticking | largest mean-friction error (relative) | loops differ (where sticking) | "
            "declared |", "| --- | --- | --- | --- | --- | --- | --- |",
            f"| {result['measured']} | {result['sticking']} | {result['largest_stick_fraction_error']:.4f} | "
            f"{result['largest_stick_fraction_relative_error']:.4f} | {result['largest_mean_friction_error']:.2g} | "
            f"{result['loops_differ']} ({sticking_differ}) | {result['declared_error']:g} |"]
    return "\n".join(rows) + (
        f"\n\nRandom systems about case 6 from seeds {', '.join(str(seed) for seed in result['seeds'])}, at 0.95-1.1 "
        f"of a critical speed v_cn (n = 1-3), {result['duration']:g} s by both methods, each converged against a "
        f"tighter rtol as `faultslip run` does. Loops (the response period over the natural period, from the spectrum) "
        f"are ill-defined where the block barely moves off steady sliding. `python benchmarks/asperity_quasistatic_check.py`"
        f"{' (quick)' if result.get('quick') else ''}. {_machine(result)}")


def asperity_single_rtol_table() -> str | None:
    """docs/asperity.md: the quasi-static method at one rtol alone, with and without its step bound."""
    result = _load("asperity_quasistatic_check.json")
    if result is None or "single_rtol" not in result:
        return None
    rows = ["| rtol alone | step | largest stick-fraction change against the converged run | systems off by more "
            f"than {result['skipped_threshold']:g} |", "| --- | --- | --- | --- |"]
    for key, line in result["single_rtol"].items():
        rtol, bound = key.split()
        step = f"at most 1/{result['steps_per_period']:g} of the natural period" if bound == "bounded" else "unbounded"
        rows.append(f"| {rtol} | {step} | {line['largest']:.2g} | {line['off']} of {result['measured']} |")
    return "\n".join(rows) + (
        "\n\nThe same systems, the quasi-static method alone at a speed sweep's rtol (1e-7) and at the convergence "
        "test's first (1e-8), against its converged run. The six-state runs changed by at most "
        f"{max(row['numerical_error'][1] for row in result['rows'] if row['measured']):.2g} (relative) against a "
        "tighter rtol. `python benchmarks/asperity_quasistatic_check.py`"
        f"{' (quick)' if result.get('quick') else ''}.")


def asperity_lsoda_steps_table() -> str | None:
    """docs/asperity.md: the six-state run at its own steps against steps bounded to a small part of a period."""
    result = _load("asperity_lsoda_steps.json")
    if result is None:
        return None
    rows = ["| draw | runs | sticking | status and sticks agree | largest stick-fraction difference | touches found "
            "by the search (own steps, bounded) |", "| --- | --- | --- | --- | --- | --- |"]
    for draw in dict.fromkeys(row["draw"] for row in result["rows"]):
        mine = [row for row in result["rows"] if row["draw"] == draw]
        rows.append(f"| {draw} | {len(mine)} | {sum(row['sticks'][1] > 0 for row in mine)} | "
                    f"{sum(row['agree'] for row in mine)} of {len(mine)} | "
                    f"{max(row.get('stick_fraction_difference', 0.0) for row in mine):.2g} | "
                    f"{sum(row['touches_found'][0] for row in mine)}, {sum(row['touches_found'][1] for row in mine)} |")
    return "\n".join(rows) + (
        f"\n\nasperity_LSODA for {result['duration']:g} s at rtol {result['rtol']:g}, at its own steps and with "
        f"steps of at most 1/{result['fine_steps_per_period']:g} of the natural period. "
        "`python benchmarks/asperity_lsoda_steps.py`"
        f"{' (quick)' if result.get('quick') else ''}. {_machine(result)}")


#: The tables this module renders, by the marker name in the pages.
TABLES = {
    "asperity_lsoda_steps": asperity_lsoda_steps_table,
    "asperity_trends": asperity_trends_table,
    "asperity_quasistatic": asperity_quasistatic_table,
    "asperity_single_rtol": asperity_single_rtol_table,
    "asperity_wavelength": asperity_wavelength_table,
    "asperity_measured_wavelength": asperity_measured_wavelength_table,
}
