"""Seed 000's surfaces and seed 002's vibration recomputed (docs/surfaces.md, docs/quasi_harmonic.md)."""

from __future__ import annotations

from ._common import _load, _load_with, _machine


def seed_000_addendum_table() -> str | None:
    result = _load_with("docs_numbers.json", "seed_000_addendum")
    if result is None:
        return None
    values = result["seed_000_addendum"]
    rows = ["| quantity | seed 000 prints | computed |", "| --- | --- | --- |",
            f"| E' for E = 210 kN/mm², ν = 0.3 | 115 kN/mm² | {values['contact_modulus'] / 1e9:.5g} kN/mm² |",
            f"| H' = 0.25 E' √(2.37/58.7) | 5.78 kN/mm² | "
            f"{values['elastic_contact_hardness_at_printed_modulus'] / 1e9:.4g} kN/mm² (with E' = 115) |",
            f"| ψ with H = 208 kgf/mm² | 11.3 | {values['plasticity_index']:.4g} |",
            f"| real area for 30 N at p_c = 280 N/mm² | 0.107 mm² | {values['real_area'] * 1e6:.4g} mm² |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def rough_slider_table() -> str | None:
    """Seed 000's AD1.3 runs beside what the seed prints (docs/surfaces.md)."""
    result = _load_with("docs_numbers.json", "rough_slider")
    if result is None:
        return None
    values = result["rough_slider"]
    scene, smaller, softer, flat = values["runs"]
    slip_frequency = lambda run: 1.0 / (2.0 * run["slip_duration"])  # noqa: E731 (a half period per slip)
    swing = lambda run: f"{run['peak_to_peak_swing'] * 1e3:.3g} mm"  # noqa: E731
    rows = ["| | seed 000 | computed |", "| --- | --- | --- |",
            f"| real area at rest, 30 N on H = 2.04e9 Pa | 0.0147 mm² | "
            f"{scene['area_fraction_at_rest']:.3g} mm² (of 1 mm² nominal) |",
            f"| √(k/M)/2π, k = 12.66e3 N/m and 6e3 N/m | 23.1 Hz, 16 Hz | {scene['natural_frequency']:.4g} Hz, "
            f"{softer['natural_frequency']:.4g} Hz |",
            f"| μ_s = p_s / H for 6.0e8 / 2.04e9 | \"0.34\" | {scene['static_friction_model']:.3f} (the seed's "
            "arithmetic slip; its break-away displacement gives 0.32) |",
            f"| c from 0.8 to 0.4 (fig. AD4) | smaller stick-slip | smaller: {swing(scene)} to {swing(smaller)} "
            "peak-to-peak |",
            f"| k from 12.66e3 to 6e3 N/m (fig. AD5) | slip-time frequency 20 to 14 Hz (×0.70) | "
            f"{slip_frequency(smaller):.3g} to {slip_frequency(softer):.2g} Hz "
            f"(×{slip_frequency(softer) / slip_frequency(smaller):.2f}); larger stick-slip ({swing(softer)}) |",
            f"| c = 0 | (the map-based chapter 5 model is erratic) | no weakening: μ(u) = μ_s, a harmonic swing "
            f"of 2V/ω = {swing(flat)} |"]
    note = (f"The seed's slips last about a half period (20 Hz against 23.1 Hz natural); the scene's last longer "
            f"({slip_frequency(scene):.3g} Hz), because its friction falls less: "
            f"{100 * values['friction_fall_at_peak_speed']:.1f} % at {values['peak_speed']:g} m/s. Each run is "
            f"`faultslip simulate configs/rough_surface_seed000.toml` (a {values['synthetic_size']} × "
            f"{values['synthetic_size']} Gaussian stand-in, RMS {values['synthetic'][0]}, correlation length "
            f"{values['synthetic'][1]}) with its spring and c replaced.")
    return "\n".join(rows) + f"\n\n{note}\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def _quasi_harmonic():
    result = _load_with("docs_numbers.json", "quasi_harmonic")
    return (None, None) if result is None else (result, result["quasi_harmonic"])


def quasi_harmonic_error_table() -> str | None:
    """Averaging's measured error over eps^2 per curve (docs/quasi_harmonic.md)."""
    result, values = _quasi_harmonic()
    if values is None:
        return None
    rows = ["| curve | eps measured over | error / eps² |", "| --- | --- | --- |"]
    for curve, measured in values["error_over_eps_squared"].items():
        low, high = measured["small_parameter"]
        spread = (f"{measured['lowest']:.3f}" if f"{measured['lowest']:.3f}" == f"{measured['highest']:.3f}"
                  else f"{measured['lowest']:.3f}-{measured['highest']:.3f}")
        rows.append(f"| {curve} | {low:.2g} to {high:.2g} | {spread} |")
    worst = max(error / declared for error, declared in zip(values["measured"]["error"],
                                                             values["measured"]["declared"]))
    return ("\n".join(rows) + f"\n\nThe declared error is 0.1 eps²; the largest measured error is {worst:.2f} of it. "
            "Each is measured against eq. (10)'s periodic orbit by shooting (DOP853 at rtols 1e-11 and 1e-13, "
            "extremes located by event search); the scene's row is the scene at five speeds of "
            f"its band. `python benchmarks/docs_numbers.py`. {_machine(result)}")


def averaging_check_table() -> str | None:
    """Averaging re-measured on random curves and sliders (docs/quasi_harmonic.md, benchmarks/averaging_check.py)."""
    result = _load("averaging_check.json")
    if result is None:
        return None
    rows = ["| draw | cycles measured | largest error / eps² | first-order sticking calls: wrong / made (farthest, eps) | "
            "break-away regimes: wrong / answered (before) | subcritical sliders |",
            "| --- | --- | --- | --- | --- | --- |"]
    for draw in result["draws"]:
        rows.append(f"| {draw['seed']} | {draw['amplitudes_measured']} | {draw['largest_ratio']:.3f} | "
                    f"{draw['boundary_wrong']} / {draw['boundary_calls']} "
                    f"({draw['boundary_wrong_largest_distance']:.2g}) | {draw['sliders_wrong']} / "
                    f"{draw['sliders_answered']} ({draw['sliders_wrong_before']}) | {draw['subcritical_sliders']} |")
    return ("\n".join(rows) + f"\n\nDeclared: {result['error_constant']:g} eps² in the amplitude; no call within "
            f"{result['hand_over_margin']:g} eps of the sticking bound: every wrong first-order call lies inside that margin, where "
            "averaging now declines and integration decides. \"Before\" is the regime averaging gave a slider "
            "when it took the cycle reached from small disturbances rather than the one the envelope reaches from "
            f"break-away. `python benchmarks/averaging_check.py`{' (quick)' if result.get('quick') else ''}. "
            f"{_machine(result)}")


def nanoscale_hopf_table() -> str | None:
    """The Hopf normal form and the subcritical case on random nanoscale models (docs/methods.md,
    benchmarks/nanoscale_hopf_check.py)."""
    result = _load("nanoscale_hopf_check.json")
    if result is None:
        return None
    summary = result["summary"]
    rows = ["| random models | supercritical (l_1 < 0) | normal form's error within its declared one "
            "| actual / declared | subcritical (l_1 > 0) | of those, stick-slip from rest 1 % above A_c "
            "| supercritical models moving from rest 1 % above A_c |", "| --- | --- | --- | --- | --- | --- | --- |",
            f"| {summary['models']} | {summary['supercritical']} | {summary['held']} of {summary['checked']} "
            f"({summary['declined']} declined) | {summary['smallest_used']:.2f}-{summary['largest_used']:.2f} | "
            f"{summary['subcritical']} | {summary['subcritical_stick_slip_from_rest_1pct_above']} | "
            f"{summary['supercritical_moving_from_rest_1pct_above']} |"]
    return ("\n".join(rows) + "\n\nEach supercritical model is set at sigma / omega_0 drawn from "
            f"{result['nearest']:g} to {result['reference']:g} and compared with LSODA's settled cycle at rtol "
            "1e-12 (the largest error of swing, period and least speed). "
            "`python benchmarks/nanoscale_hopf_check.py`. " + _machine(result))


def quasi_harmonic_scene_table() -> str | None:
    """configs/vibration_seed002.toml's amplitude, its integration and its band (docs/quasi_harmonic.md)."""
    result, values = _quasi_harmonic()
    if values is None:
        return None
    inch = 0.0254
    rows = ["| quantity | computed |", "| --- | --- |",
            f"| amplitude at {values['speed']}, averaged (eq. 20) | {values['amplitude'] / inch:.4f} in, declared "
            f"error {values['declared_error']:.1e} |",
            f"| eq. (10) integrated for {values['simulated_duration']:.0f} s from 5 % of it (`simulate`) | "
            f"{values['simulated_error']:.1e} from the averaged amplitude (relative) |",
            f"| below this driving speed the cycle's peak speed reaches it: the slider sticks | "
            f"{values['sticks_below'] / inch:.2f} in/s |",
            f"| above this speed r + W f'(v) > 0: steady sliding | {values['steady_above'] / inch:.2f} in/s |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def seed002_figures_table() -> str | None:
    """Where seed 002's Figs. 9-11 branches end, rebuilt in kind (docs/quasi_harmonic.md)."""
    result, values = _quasi_harmonic()
    if values is None:
        return None
    inch, ends, flat = 0.0254, values["seed002_ends"], values["flattening_speeds"]
    rows = ["| | ends at | the curve flattens at |", "| --- | --- | --- |"]
    rows += [f"| curve ({name}) | {ends[name] / inch:.3g} in/s | {flat[name] / inch:.3g} in/s |" for name in "ABCD"]
    rows += [f"| curve (A), damping ×{factor} | {ends[f'A_damping_x{factor}'] / inch:.3g} in/s | |"
             for factor in (1, 2, 4)]
    note = (f"Doubling the damping changes curve (A)'s amplitude at {values['damping_speed'] / inch:g} in/s by "
            f"{100 * (values['damped_amplitude_ratio'] - 1):+.0f} %.")
    return "\n".join(rows) + f"\n\n{note} `python benchmarks/docs_numbers.py`. {_machine(result)}"


def _sweep_table(title: str, sweep: dict) -> list[str]:
    lines = [f"**{title}**", "", "| c (s/mm) | " + " | ".join(f"{memory}: amplitude / x_break, lowest x (mm)"
                                                           for memory in sweep["memory"]) + " |",
             "| --- |" + " --- |" * len(sweep["memory"])]
    for c, amplitudes, lowest in zip(sweep["separation_coefficient"], sweep["relative_amplitude"],
                                     sweep["lowest_displacement"]):
        lines.append(f"| {c:g} | " + " | ".join(f"{a:.3f}, {low * 1e3:+.3f}" for a, low in zip(amplitudes, lowest))
                     + " |")
    return lines + [""]


def surface_trends_table() -> str | None:
    """Seed 000's chapter 5 runs, as the seed ran them and corrected (docs/surfaces.md)."""
    result = _load("surface_trends.json")
    if result is None:
        return None
    surface = result["surface"]
    lines = [f"The surface is the scenes' Gaussian stand-in (RMS {surface['rms'] * 1e6:g} um, correlation length "
             f"{surface['correlation_length'] * 1e6:g} um, {surface['size']} x {surface['size']}, seed {surface['seed']}). "
             "x_break = W mu_s / K is the spring's stretch at break-away; a negative lowest x is the seed's overshoot. "
             f"`falling` uses gravity (fall time {result['gravity_fall_time'] * 1e3:.1f} ms).", ""]
    lines += _sweep_table("Chapter 5 as the seed ran it (Table 5.1, its two errors kept: effective mass 600 kg, "
                          "p_c 280 N/mm²)", result["sweeps"]["as run"])
    lines += _sweep_table("Chapter 5 corrected (mass 0.6 kg, H 2040 N/mm², p_s 601 N/mm²)", result["sweeps"]["corrected"])
    lines += ["**Chapter 5's other runs, as the seed ran them (memory held)**", "",
              "| run | amplitude (mm) | amplitude / x_break | stick (s) | slip (s) | peak sliding speed (mm/s) |",
              "| --- | --- | --- | --- | --- | --- |"]
    lines += [f"| {row['run']} | {row['amplitude_mm']:.4f} | {row['relative']:.3f} | {row['stick_s']:.3f} | "
              f"{row['slip_s']:.3f} | {row['peak_mm_s']:.3f} |" for row in result["chapter5_runs"]]
    lines += ["", "**The addendum's AD3 scene (c 0.8 s/m x RMS) with each memory**", "",
              "| memory | amplitude (mm) | slip (s) | slip-time frequency (Hz) | peak sliding speed (m/s) |",
              "| --- | --- | --- | --- | --- |"]
    lines += [f"| {row['memory']} | {row['amplitude_mm']:.4f} | {row['slip_s']:.4f} | {1 / (2 * row['slip_s']):.1f} | "
              f"{row['peak_mm_s'] * 1e-3:.4f} |" for row in result["ad3_runs"]]
    separation, omega = result["peak_separation"], result["slip_angular_frequency"]
    lines += ["", f"The fall matters only if it is slower than the deceleration: a < h_peak omega^2 = "
              f"{separation * 1e9:.3g} nm x ({omega:.3g} rad/s)^2 = {separation * omega ** 2:.2g} m/s² here.", "",
              f"Falling 0.5 um under gravity takes sqrt(2 h / g) = {result['gravity_fall_time'] * 1e3:.3f} ms (seed 000 "
              "§4.5 prints \"about 3 ms\").", "", f"`python benchmarks/surface_trends.py`. {_machine(result)}"]
    return "\n".join(lines)


def surface_trends_findings_table() -> str | None:
    """The figures docs/surfaces.md's comparisons with chapter 5 quote, from the same runs."""
    result = _load("surface_trends.json")
    if result is None:
        return None
    runs = {row["run"].split(":")[0]: row for row in result["chapter5_runs"]}
    as_run, corrected = result["sweeps"]["as run"], result["sweeps"]["corrected"]
    held = as_run["memory"].index("held")
    largest = as_run["separation_coefficient"][-1]
    overshoot = next((c for c, lowest in zip(corrected["separation_coefficient"], corrected["lowest_displacement"])
                      if lowest[held] < 0), None)
    speeds = [runs[name] for name in ("fig. 5.15", "fig. 5.16", "fig. 5.12", "fig. 5.17")]
    soft, stiff = runs["fig. 5.21"], runs["fig. 5.13"]
    rows = [f"- as run, held, at c = {largest:g} s/mm: amplitude {as_run['relative_amplitude'][-1][held]:.2f} of the "
            f"break-away stretch, lowest x {as_run['lowest_displacement'][-1][held] * 1e3:+.3f} mm "
            f"({'an overshoot' if as_run['lowest_displacement'][-1][held] < 0 else 'no overshoot'});",
            "- corrected, held: the slider overshoots its unloaded position from c = "
            + (f"{overshoot:g} s/mm;" if overshoot is not None else "(never, on this grid);"),
            f"- fig. 5.22 (k = 6.3 N/mm): c from 0.02 to 0.03 multiplies the amplitude by "
            f"{runs['fig. 5.22']['amplitude_mm'] / soft['amplitude_mm']:.2f};",
            f"- fig. 5.21 against fig. 5.13 (c = 0.02): {soft['amplitude_mm']:.2f} against {stiff['amplitude_mm']:.2f} mm, "
            f"{soft['relative']:.2f} against {stiff['relative']:.2f} of the break-away stretch;",
            f"- figs. 5.15-5.17 (V0 from 0.05 to 0.5 mm/s, c = 0.01): amplitude {speeds[0]['amplitude_mm']:.3f} to "
            f"{speeds[-1]['amplitude_mm']:.3f} mm, stick time {speeds[0]['stick_s']:.3f} to {speeds[-1]['stick_s']:.3f} s."]
    return "\n".join(rows) + f"\n\n`python benchmarks/surface_trends.py`. {_machine(result)}"


def nanoscale_charge_table() -> str | None:
    """docs/quasi_harmonic.md: seed 001's deposited charge against displacement (docs_numbers)."""
    result = _load_with("docs_numbers.json", "nanoscale_charge")
    if result is None:
        return None
    found = result["nanoscale_charge"]
    below = 1 - found["stick_slip_ratio"] / found["steady_slope"]
    return (f"Over a run of {found['stick_slip_events']} slips at the slides' damping, the deposited charge tracks the "
            f"displacement with correlation 1 - {1 - found['correlation']:.1e}. Its slope, charge over displacement, "
            f"is {found['stick_slip_ratio']:.4f}: {below:.1%} below Sigma*/a = {found['steady_slope']:.4f}, where each "
            f"slip depletes the contact's charge. In steady sliding (A = 13) it is {found['steady_ratio']:.4f}. "
            f"`python benchmarks/docs_numbers.py`. {_machine(result)}")


#: The tables this module renders, by the marker name in the pages.
TABLES = {
    "nanoscale_charge": nanoscale_charge_table,
    "surface_trends_findings": surface_trends_findings_table,
    "surface_trends": surface_trends_table,
    "seed_000_addendum": seed_000_addendum_table,
    "rough_slider": rough_slider_table,
    "quasi_harmonic_error": quasi_harmonic_error_table,
    "averaging_check": averaging_check_table,
    "nanoscale_hopf": nanoscale_hopf_table,
    "quasi_harmonic_scene": quasi_harmonic_scene_table,
    "seed002_figures": seed002_figures_table,
}
