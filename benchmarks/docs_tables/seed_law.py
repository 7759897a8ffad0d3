"""Seed 003's law on faults and catalogs: 1906, Parkfield, renewal, the critical rate, rate and state (docs/results.md, docs/catalogs.md, docs/critical_rate.md, docs/rate_state.md, docs/spring_chain.md)."""

from __future__ import annotations

import numpy as np

from ._common import _load, _load_with, _machine


def renewal_coverage_table() -> str | None:
    """The renewal fits' 95 % ranges: coverage of the true mean and aperiodicity (renewal_coverage.py)."""
    result = _load("renewal_coverage.json")
    if result is None:
        return None
    rows = ["| model | aperiodicity | mean: pivotal | mean: bootstrap | aperiodicity: pivotal | aperiodicity: bootstrap |",
            "| --- | --- | --- | --- | --- | --- |"]
    for row in result["rows"]:
        pivotal, bootstrap = row["coverage"]["pivotal"], row["coverage"]["bootstrap"]
        rows.append(f"| {row['model']} | {row['aperiodicity']:g} | **{100 * pivotal['mean']:.1f} %** | "
                    f"{100 * bootstrap['mean']:.1f} % | **{100 * pivotal['aperiodicity']:.1f} %** | "
                    f"{100 * bootstrap['aperiodicity']:.1f} % |")
    return ("\n".join(rows) + f"\n\n{result['catalogs']} catalogs of {result['events']} events per row, "
            f"{result['draws']} draws each (benchmarks/renewal_coverage.py).")


def chain_example_table() -> str | None:
    """The shipped chain's run and its predictability (chain_example.py): what the chain and classroom pages quote."""
    r = _load("chain_example.json")
    if r is None:
        return None
    low, high = r["b_over_cutoffs"]
    b = (f"b = {r['b_value']:.3g} (GR holds: KS p = {r['gr_p_value']:.2g})" if r["gutenberg_richter"] else
         f"none: not Gutenberg-Richter (KS p = {r['gr_p_value']:.2g}; b moves from {low:.2f} to {high:.2f} with the "
         "cutoff)")
    time_r, slip_r = r["time_predictable"], r["slip_predictable"]
    rows = ["| quantity | value |", "| --- | --- |",
            f"| blocks, events | {r['blocks']}, {r['events']} |",
            f"| magnitudes | {r['magnitude_range'][0]:.2f} to {r['magnitude_range'][1]:.2f} |",
            f"| b-value | {b} |",
            f"| system-size events (half the blocks or more) | {r['system_events']} |",
            f"| CV of their intervals (0 periodic, 1 Poisson) | {r['system_cv']:.2f} |",
            f"| CV of all intervals | {r['all_events_cv']:.2f} ({r['all_events_cv_range'][0]:.2f}-"
            f"{r['all_events_cv_range'][1]:.2f}) |",
            f"| r(slip, the interval after): time-predictable | {time_r['r']:.2f} ({time_r['range'][0]:.2f} to "
            f"{time_r['range'][1]:.2f}): {'yes' if time_r['holds'] else 'no'} |",
            f"| r(the interval before, slip): slip-predictable | {slip_r['r']:.2f} ({slip_r['range'][0]:.2f} to "
            f"{slip_r['range'][1]:.2f}): {'yes' if slip_r['holds'] else 'no'} |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/chain_example.py` ({r['scene']}). {_machine(r)}"


def san_andreas_empirical_table() -> str | None:
    """The San Andreas map's slip against W&C's expectation, segment by segment (docs/catalogs.md)."""
    result = _load_with("docs_numbers.json", "san_andreas_empirical")
    if result is None:
        return None
    values = result["san_andreas_empirical"]
    (low, high), (_, z_high) = values["slip_ratio"], values["slip_z"]
    return (f"On the San Andreas map the slip ratio runs from {low:.1f} to {high:.1f} across the segments: the seed "
            f"law's slip, with its 1906 stress and zone width, is larger than W&C expect for the segments' own Mw, by "
            f"up to {z_high:.1f} σ.\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}")


def parkfield_predictability_table() -> str | None:
    """QuakeCaster's test on the bundled Parkfield sequence (docs/catalogs.md)."""
    result = _load_with("docs_numbers.json", "parkfield_predictability")
    if result is None:
        return None
    values = result["parkfield_predictability"]
    low, high = values["aperiodicity_95"]
    verdict = ("periodic" if values["periodic"] else "Poisson" if values["poisson"] else "neither periodic nor Poisson")
    return (f"`faultslip predictability configs/catalog_san_andreas.csv --name Parkfield`: {values['events']} events, "
            f"a coefficient of variation of {values['aperiodicity']:.2f} ({low:.2f}-{high:.2f}): {verdict}.\n\n"
            f"`python benchmarks/docs_numbers.py`. {_machine(result)}")


def _b_text(run: dict) -> str:
    return f"b = {run['b_value']:.2f}" if run["b_value"] is not None else run["b_value_label"]


def chain_identical_table() -> str | None:
    """The chain of identical blocks from identical starts (chain_example.py): what docs/spring_chain.md quotes."""
    r = _load_with("chain_example.json", "variants")
    if r is None:
        return None
    alike = r["variants"]["identical blocks from identical starts"]
    return (f"After {alike['events']} events: magnitudes {alike['magnitude_range'][0]:.2f} to "
            f"{alike['magnitude_range'][1]:.2f}, {alike['blocks_per_event']:.1f} blocks an event on average, "
            f"{alike['system_events']} system-size events; {_b_text(alike)}.\n\n"
            f"`python benchmarks/chain_example.py`. {_machine(r)}")


def chain_knobs_table() -> str | None:
    """The shipped chain and the classroom's knobs, one run each (chain_example.py; docs/classroom.md)."""
    r = _load_with("chain_example.json", "variants")
    if r is None:
        return None
    rows = ["| chain | blocks an event (mean) | magnitudes | system-size events (CV of their intervals) | b-value |",
            "| --- | --- | --- | --- | --- |"]
    for label, run in {"shipped (configs/spring_chain.toml)": r["shipped"], **r["variants"]}.items():
        rows.append(f"| {label} | {run['blocks_per_event']:.1f} | {run['magnitude_range'][0]:.2f} to "
                    f"{run['magnitude_range'][1]:.2f} | {run['system_events']} ({run['system_cv']:.2f}) | "
                    f"{_b_text(run)} |")
    return "\n".join(rows) + f"\n\n`python benchmarks/chain_example.py`, {r['shipped']['events']} events each. {_machine(r)}"


YEAR_S = 365.25 * 86400.0


#: What seed 003 prints for the 1906 example (quoted from the seed, beside what faultslip computes).
SEED_003_PRINTS = {"normal_stress": "385 bar", "stiffness": "4.4 psi/in",
                   "loading_rate": "5 × 10^-10 1/s (a factor-10 slip)", "stress_drop_slip": "254 in = 21.2 ft",
                   "slip_per_event": "—", "recurrence_period": "(formula only, eq. 5-5)", "stress_drop": "—",
                   "moment": "— (Song et al. 2008: 7.9e20, Mw 7.9)",
                   "inverse": "0.079, mu_m = 0.57 (printed with K = 3.25 for 3.52)", "radiation": "—"}


def seed_1906_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None:
        return None
    seed, quote = result["seed_003_1906"], SEED_003_PRINTS
    feet, bar = 0.3048, 1e5
    slip_phase = seed["slip_per_event"] - seed["stress_drop_slip"]
    rows = ["| quantity | faultslip | seed 003 printed |", "| --- | --- | --- |",
            f"| sigma_n = tau / mu_so | {seed['normal_stress'] / bar:.2f} bar | {quote['normal_stress']} |",
            f"| K = G / D | {seed['stiffness']:.5g} Pa/m = {seed['stiffness'] * 0.0254 / 6894.757:.5g} psi/in | "
            f"{quote['stiffness']} |",
            f"| theta_dot = K V / sigma_n | **{seed['loading_rate']:.4g} 1/s** | {quote['loading_rate']} |",
            f"| stress-drop slip alpha = x1 − x2 (eq. 2-19) | {seed['stress_drop_slip']:.4g} m = "
            f"{seed['stress_drop_slip'] / feet:.4g} ft | {quote['stress_drop_slip']} |",
            f"| slip per event, ∫u dt = alpha + V t_slip | {seed['slip_per_event']:.4g} m (V t_slip = "
            f"{slip_phase:.1e} m) | {quote['slip_per_event']} |",
            f"| recurrence T = alpha / V + t_slip | {seed['recurrence_period'] / YEAR_S:.4g} yr | "
            f"{quote['recurrence_period']} |",
            f"| stress drop K alpha | {seed['stress_drop'] / bar:.3g} bar | {quote['stress_drop']} |",
            f"| M0, Mw (L = 270 mi, H = 12 km) | {seed['seismic_moment']:.3g} N m, Mw {seed['moment_magnitude']:.3g} | "
            f"{quote['moment']} |",
            f"| granite inverse: mu_so − mu_m | {result['granite_inverse']['friction_drop']:.3g}, mu_m = "
            f"{result['granite_inverse']['kinetic_friction']:.3f} | {quote['inverse']} |",
            f"| with radiation damping (c_s = sqrt(G/rho), so zeta = {result['radiation']['damping_ratio']:g}) | "
            f"{result['radiation']['slip_per_event']:.3g} m, {result['radiation']['recurrence_period'] / YEAR_S:.3g} yr "
            f"| {quote['radiation']} |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def _e(value: float, digits: int) -> str:
    """value in e-notation as the docs write it: 1.195e6, 5.0e-11."""
    mantissa, exponent = f"{value:.{digits}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def getting_started_1906_table() -> str | None:
    """The 1906 example step by step (docs/getting_started.md), from the same run as :func:`seed_1906_table`."""
    result = _load("docs_numbers.json")
    if result is None:
        return None
    seed, bar, feet = result["seed_003_1906"], 1e5, 0.3048
    empirical = next((row for row in result["empirical_1906"] if row["relation"].startswith("W&C 1994 AD(Mw)")), None)
    steps = [f"1. **The stiffness** of the elastic zone is K = G / D: with G = 0.25e6 bar and D = 13 mi,\n"
             f"   K = {_e(seed['stiffness'], 3)} Pa/m ({seed['stiffness'] * 0.0254 / 6894.757:.4g} psi/in).",
             "2. **The normal stress** follows from the shear stress and the static friction at vanishing\n"
             f"   loading rate: sigma_n = tau / mu_so = 250 bar / 0.65 = {seed['normal_stress'] / bar:.4g} bar.",
             f"3. **The loading rate** is theta_dot = K V / sigma_n = {_e(seed['loading_rate'], 1)} 1/s for a plate rate of "
             "2 in/yr.\n   The seed prints 5e-10, a factor-10 slip (see the seed discrepancies).",
             "4. **The slip per event** is the stick-slip amplitude of the slider at that rate, seed 003\n"
             f"   eq. 2-19: alpha = 2 sigma_n (mu_s - mu_m) / K = {seed['slip_per_event']:.3g} m "
             f"({seed['slip_per_event'] / feet:.3g} ft). Here mu_s is the static\n"
             "   friction of wet granodiorite at that loading rate (eq. 2-18).",
             "5. **The recurrence** is the time the plate takes to reload the slip: T = alpha / V + t_slip,\n"
             f"   {seed['recurrence_period'] / YEAR_S:.4g} years.",
             f"6. **The magnitude** follows from M0 = G L H alpha = {_e(seed['seismic_moment'], 1)} N m over a 270 mi, "
             f"12 km rupture:\n   Mw {seed['moment_magnitude']:.3g}."]
    if empirical is not None:
        steps[-1] += (f" Wells & Coppersmith (1994) expect {empirical['expected']['value']:.3g} m of average "
                      f"displacement at that magnitude\n   (ratio {empirical['ratio']:.2f}, z = {empirical['z_score']:+.2f}).")
    return "\n".join(steps) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def _signed(value: float, digits: int = 2) -> str:
    return f"{value:+.{digits}f}".replace("-", "−")


def empirical_1906_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None:
        return None
    rows = ["| relation | expects | prediction | ratio or difference | z |", "| --- | --- | --- | --- | --- |"]
    for row in result["empirical_1906"]:
        slip = row["quantity"] == "slip_per_event"
        expected, predicted = row["expected"]["value"], row["predicted"]["value"]
        shown = (lambda v: f"{v:.3g} m") if slip else (lambda v: f"{v:.3g}")
        compared = f"{row['ratio']:.3g}" if slip else _signed(predicted - expected)
        z = _signed(row["z_score"]) if row["z_score"] is not None else "–"
        rows.append(f"| {row['relation'].replace('1994 ', '').replace('2010 ', '')} | {shown(expected)} | "
                    f"{shown(predicted)} | {compared} | {z} |")
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def parkfield_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None:
        return None
    c = result["parkfield_catalog"]
    year = lambda entry: entry["value"] / YEAR_S  # noqa: E731
    pair = lambda values, scale=1.0: f"{values[0] / scale:.3g}-{values[1] / scale:.3g}"  # noqa: E731
    horizon_year = int(c["as_of"][:4]) + int(float(c["horizon"].split()[0]))
    rows = ["| | observed | predicted (seed law, D = 6 km) |", "| --- | --- | --- |",
            f"| mean interval | {year(c['observed_mean_interval']):.3g} yr (CV {c['observed_cv']:.2f}, "
            f"{c['observed_intervals']} intervals) | {year(c['predicted_recurrence']):.3g} yr ({c['recurrence_ratio']:.3g} "
            f"times; percentile {min(c['lognormal_percentile'], c['bpt_percentile']):.0%} or more of both fits) |"]
    for name, label in (("lognormal", "lognormal fit"), ("bpt", "BPT fit")):
        rows.append(f"| {label} | mean {year(c[name + '_mean']):.3g} yr (95 %: "
                    f"{pair(c[name + '_mean_95']['value'], YEAR_S)}), aperiodicity {c[name + '_aperiodicity']:.2f} "
                    f"({pair(c[name + '_aperiodicity_95'])}) | |")
    rows.append(f"| P(event by {horizon_year}), as of {c['as_of']} | {c['bpt_probability']:.2f} (BPT; 95 %: "
                f"{c['bpt_probability_95'][0]:.2f}-{c['bpt_probability_95'][1]:.2f}) | |")
    rows.append(f"| magnitude | M {c['observed_max_magnitude']:.1f} | Mw {c['predicted_magnitude']:.3g} (slip "
                f"{c['predicted_slip_per_event']['value']:.3g} m) |")
    widths = ["| D | slip per event | recurrence | Mw |", "| --- | --- | --- | --- |"]
    for row in result["parkfield_widths"]:
        widths.append(f"| {row['zone_width']} | {row['slip_per_event_m']:.3g} m | {row['recurrence_s'] / YEAR_S:.3g} yr | "
                      f"{row['moment_magnitude']:.3g} |")
    return ("\n".join(rows) + f"\n\nThe seed law does not reproduce Parkfield: its recurrence is "
            f"{c['recurrence_ratio']:.2g} times the observed mean and its magnitude {c['magnitude_difference']:.2g} units "
            "too large, because its slip per event scales with σ_n D Δμ / G. The prediction depends on the choice of D "
            "(the same scene at three widths):\n\n" + "\n".join(widths)
            + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}")


def critical_comparison_table() -> str | None:
    result = _load_with("docs_numbers.json", "critical_comparison")
    if result is None:
        return None
    table = result["critical_comparison"]
    exact = np.asarray(table["critical_loading_rate"]["value"], float)  # 1/s, presets x damping ratios
    seed = np.asarray(table["seed_appendix_I_loading_rate"]["value"], float)
    ratio = seed / exact  # presets x damping ratios
    said = [f"at zeta = {zeta:g} the seed's is {ratio[:, k].min():.3g}-{ratio[:, k].max():.3g} times the exact value"
            for k, zeta in enumerate(table["damping_ratio"])]
    return (table["markdown"].rstrip() + "\n\nSeed over exact, over the presets: " + "; ".join(said)
            + f".\n\n`python benchmarks/docs_numbers.py` (`faultslip critical --table`). {_machine(result)}")


def rate_state_examples_table() -> str | None:
    result = _load_with("docs_numbers.json", "rate_state_examples")
    if result is None:
        return None
    rows = ["| scene | K / K_c | slip per event | recurrence | the 2-D fault's recurrence by the model error | "
            "seed law beside it |", "| --- | --- | --- | --- | --- | --- |"]
    for row in result["rate_state_examples"]:
        low, high = row["recurrence_range"]
        within = f"{low / YEAR_S:.3g} yr or more" if high is None else f"{low / YEAR_S:.3g}-{high / YEAR_S:.3g} yr"
        rows.append(f"| {row['scene']} | {row['stiffness_ratio']:.3g} | {row['slip_per_event']:.3g} m | "
                    f"{row['recurrence_period'] / YEAR_S:.3g} yr | {within} (model error {row['model_error']:.2f}) | "
                    f"{row['seed_law_slip_per_event']:.3g} m every {row['seed_law_recurrence_period'] / YEAR_S:.3g} yr "
                    f"(slip ratio {row['slip_per_event'] / row['seed_law_slip_per_event']:.2f}) |")
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def closed_form_near_critical_table() -> str | None:
    """docs/results.md: the closed form's relative errors near the critical rate, by damping ratio (docs_numbers)."""
    result = _load_with("docs_numbers.json", "closed_form_near_critical")
    if result is None:
        return None
    found = result["closed_form_near_critical"]
    rows = ["| damping ratio zeta | slip per event and period, closed form / exact - 1 | stress-drop slip |",
            "| --- | --- | --- |"]
    rows += [f"| {row['damping_ratio']:g} | {100 * row['slip_per_event']:+.1f} % | {100 * row['stress_drop_slip']:+.1f} % |"
             for row in found["rows"]]
    return "\n".join(rows) + (f"\n\nAt {found['fraction_of_critical']:g} theta_c, against the exact cycle "
                              f"(`faultslip.dynamics.spring_slider.closed_form.relative_error_against_exact`). "
                              f"`python benchmarks/docs_numbers.py`. {_machine(result)}")


def dashpot_force_table() -> str | None:
    """docs/seed_discrepancies.md: eps_c overestimated by leaving the dashpot force out of break-away."""
    result = _load_with("docs_numbers.json", "closed_form_near_critical")
    if result is None:
        return None
    rows = ["| damping ratio zeta | eps_c without C V at break-away / exact eps_c - 1 |", "| --- | --- |"]
    rows += [f"| {row['damping_ratio']:g} | {100 * row['overestimate']:+.1f} % |"
             for row in result["closed_form_near_critical"]["dashpot_force"]]
    return "\n".join(rows) + ("\n\n`faultslip.dynamics.spring_slider.critical.critical_rate_without_dashpot_force`; "
                              f"`python benchmarks/docs_numbers.py`. {_machine(result)}")


def poisson_verdicts_table() -> str | None:
    """docs/catalogs.md: how often each predictability verdict is given on Poisson catalogues (docs_numbers)."""
    result = _load_with("docs_numbers.json", "poisson_verdicts")
    if result is None:
        return None
    found = result["poisson_verdicts"]
    share = {name: count / found["catalogues"] for name, count in found["counts"].items()}
    return (f"Over {found['catalogues']} seeded catalogues of {found['events']} events with exponential intervals "
            f"({found['draws']} bootstrap draws each), the Poisson verdict holds in {share['poisson']:.0%}, the "
            f"periodic one in {share['periodic']:.0%}, and a time- or slip-predictable model is claimed in "
            f"{share['time_predictable']:.0%} and {share['slip_predictable']:.0%}: a bootstrap range of a "
            "coefficient of variation under-covers (`tests/capabilities/hazard/test_predictability.py` asks at least "
            f"80 % and at most 10 %). `python benchmarks/docs_numbers.py`. {_machine(result)}")


def b_value_coverage_table() -> str | None:
    """docs/spring_chain.md: the b-value intervals' coverage and bias on seeded catalogues (docs_numbers)."""
    result = _load_with("docs_numbers.json", "b_value_coverage")
    if result is None:
        return None
    found = result["b_value_coverage"]
    rows = ["| b | magnitudes | faultslip: interval holds b | median b / b - 1 | Utsu's shortcut: interval holds b | "
            "median b / b - 1 |", "| --- | --- | --- | --- | --- | --- |"]
    for row in found["rows"]:
        kind = "continuous" if row["bin_width"] == 0 else f"binned to {row['bin_width']:g}"
        ours, utsu = row["faultslip"], row["utsu"]
        rows.append(f"| {row['b_value']:g} | {kind} | {ours['coverage']:.1%} | {100 * ours['median_bias']:+.2f} % | "
                    f"{utsu['coverage']:.1%} | {100 * utsu['median_bias']:+.2f} % |")
    return "\n".join(rows) + (f"\n\n{found['catalogues']} seeded catalogues of {found['events']} events each, "
                              f"{found['confidence']:.0%} intervals; for continuous magnitudes the two are the same. "
                              f"`python benchmarks/docs_numbers.py`. {_machine(result)}")


def chain_coverage_table() -> str | None:
    """docs/spring_chain.md: how often the chain's declared range holds a long run's mean (chain_coverage)."""
    result = _load("chain_coverage.json")
    if result is None:
        return None
    rows = ["| draw | events a run | chains | declaring a range | range holds the long run's mean | factor 1 | "
            "independent Student's t | median half-width |", "| --- | --- | --- | --- | --- | --- | --- | --- |"]
    for name in ("calibration", "held_out"):
        for seed, found in result[name].items():
            declared = max(found["declared"], 1)
            rows.append(f"| {name.replace('_', ' ')} {seed} | {found['events']} | {found['chains']} | "
                        f"{found['declared']} | {found['held'] / declared:.1%} | {found['held_unit'] / declared:.1%} | "
                        f"{found['held_independent'] / declared:.1%} | ±{found['median_half_width']:.0%} |")
    return "\n".join(rows) + (
        f"\n\nFitted factor {result['fitted_factor']:g} (shipped {result['shipped_factor']:g}): the "
        f"{result['coverage']:.0%} quantile of |long / short - 1| over the correlated half-width, over the calibration "
        f"draws. A run declares a range from {result['min_system_intervals']} system-size intervals; the long runs are "
        f"thirty (500 events: twelve) times the run, their first {result['reference_spin_up']:.0%} left out. "
        f"`python benchmarks/chain_coverage.py`. {_machine(result)}")


def lab_cycle_cost_table() -> str | None:
    """docs/methods.md: the steady-cycle methods' declared cost against the CPU their runs use (lab_cycle_cost.py)."""
    result = _load("lab_cycle_cost.json")
    if result is None:
        return None
    rows = ["| draw | method | runs | declared / CPU used, median (range) | within 2x | under half |",
            "| --- | --- | --- | --- | --- | --- |"]
    for draw, label in (("calibration", "calibration seeds"), ("held_out", "held-out seeds")):
        for method, found in result[draw].items():
            auto = f" (auto takes {', '.join(found['auto_where_under'])})" if found["under_half"] else ""
            rows.append(f"| {label} | {method} | {found['runs']} | {found['median']:.2f} ({found['low']:.2g}-"
                        f"{found['high']:.2g}) | {found['within_2x']} | {found['under_half']}{auto} |")
    return "\n".join(rows) + (
        f"\n\nRandom scenes of `faultslip.evaluation.bench.random_scenes`, {result['scenes_per_seed']} a seed "
        f"(calibration {', '.join(map(str, result['calibration_seeds']))}; held out "
        f"{', '.join(map(str, result['held_out_seeds']))}), "
        "each method run twice at tolerance 1e-6, the second run timed. A run far under its declared cost is a forced "
        "method's slip phase grazing re-stick; where auto takes another method there, it is named. "
        f"`python benchmarks/lab_cycle_cost.py`. {_machine(result)}")


def slider_simulation_cost_table() -> str | None:
    """docs/methods.md: the seed-law slider's simulation estimate against its CPU where the slip phase is stiff
    (slider_simulation_cost.py)."""
    result = _load("slider_simulation_cost.json")
    if result is None:
        return None
    rows = ["| law | solver | runs | eps | ended sliding | estimated / CPU used, median (range) | most over, s |",
            "| --- | --- | --- | --- | --- | --- | --- |"]
    for law in dict.fromkeys(row["law"] for row in result["rows"]):
        for solver in result["solvers"]:
            found = [row for row in result["rows"] if row["law"] == law and row["solver"] == solver]
            if not found:
                continue
            ratios = sorted(row["ratio"] for row in found)
            eps = [row["eps"] for row in found]
            steady = sum(row["events"] < row["cycles"] for row in found)  # a phase ran to the horizon
            rows.append(f"| {law} | {solver} | {len(found)} | {min(eps):.2g}-{max(eps):.2g} | {steady} | "
                        f"{np.median(ratios):.2f} ({ratios[0]:.2g}-{ratios[-1]:.2g}) | "
                        f"{max(row['estimated_seconds'] - row['cpu_seconds'] for row in found):.2g} |")
    summary = result["summary"]
    return "\n".join(rows) + (
        f"\n\n`configs/lab_steel_dry_polynomial.toml` (shipped law) and two held-out polynomial laws (a quadratic "
        f"and a cubic in m/s), at platform speeds from {result['speeds'][0]} to {result['speeds'][-1]} (the cubic to "
        f"10 m/s), simulated for {' and '.join(map(str, result['cycles']))} cycles by each solver; eps is the slip "
        "phase's stiffness. A run that ended sliding had a slip phase that never re-stuck and ran to simulate's "
        "horizon. A run that re-sticks in milliseconds is still estimated with one phase to the horizon (up to a "
        "few seconds where the motion about steady sliding is lightly damped): the large ratios are those. Of "
        f"{summary['cases']} runs, {summary['under']} used more "
        f"CPU than estimated ({summary['under_half']} more than twice). `python benchmarks/slider_simulation_cost.py`. "
        f"{_machine(result)}")


#: The tables this module renders, by the marker name in the pages.
TABLES = {
    "b_value_coverage": b_value_coverage_table,
    "chain_coverage": chain_coverage_table,
    "poisson_verdicts": poisson_verdicts_table,
    "closed_form_near_critical": closed_form_near_critical_table,
    "lab_cycle_cost": lab_cycle_cost_table,
    "slider_simulation_cost": slider_simulation_cost_table,
    "dashpot_force": dashpot_force_table,
    "renewal_coverage": renewal_coverage_table,
    "chain_example": chain_example_table,
    "chain_identical": chain_identical_table,
    "chain_knobs": chain_knobs_table,
    "san_andreas_empirical": san_andreas_empirical_table,
    "parkfield_predictability": parkfield_predictability_table,
    "seed_1906": seed_1906_table,
    "getting_started_1906": getting_started_1906_table,
    "empirical_1906": empirical_1906_table,
    "parkfield": parkfield_table,
    "critical_comparison": critical_comparison_table,
    "rate_state_examples": rate_state_examples_table,
}
