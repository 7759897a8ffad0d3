"""Laboratory fits: coverage, posteriors, p655, seed 002's free decay, the phone record (docs/lab_fits.md, docs/classroom.md)."""

from __future__ import annotations

import math
import re
import statistics

from ._common import _load, _load_with, _machine


#: the parameters of a rate-and-state fit as docs/lab_fits.md names them
_FIT_NAMES = {"a": "a", "b": "b", "critical_slip": "D_c", "stiffness": "k"}


def fit_coverage_table() -> str | None:
    result = _load("fit_coverage.json")
    if result is None:
        return None
    labels = {"covariance": "covariance (s² (JᵀJ)⁻¹, t quantile)",
              "bootstrap": "bootstrap (100 residual resamples, each refitted)",
              "posterior": "posterior (emcee until converged)"}
    names = list(result["coverage"]["covariance"])
    rows = ["| interval | " + " | ".join(_FIT_NAMES[n] for n in names) + " |", "| --- " * (1 + len(names)) + "|"]
    for kind, label in labels.items():
        rows.append(f"| {label} | " + " | ".join(f"{result['coverage'][kind][n]['coverage']:.1%}" for n in names)
                    + " |")
    every = [row for kind in labels for row in result["coverage"][kind].values()]
    low, high = every[0]["binomial_95"]
    inside = all(low <= row["coverage"] <= high for row in every)
    below = all(row["coverage"] < 0.95 for row in every)
    cases = result["cases"]
    boot = statistics.median(case["bootstrap_seconds"] for case in cases)
    post = statistics.median(case["posterior_seconds"] for case in cases)
    return ("\n".join(rows) + f"\n\nWith {every[0]['cases']} cases, a true 95 % lands in {low:.0%}-{high:.0%} "
            "nineteen times in twenty; " + ("every figure is inside that band" if inside else
                                            "some figures fall outside that band")
            + (", all below 95 %: the intervals are slightly narrow (the detected step times and the speeds measured "
               "from a noisy LVDT are taken as exact, and their errors are not carried)" if below else "")
            + f". A bootstrap case takes {boot:.1f} s and a posterior {post:.1f} s (medians, one core). "
            f"Failures: {result['failures']['bootstrap']} bootstraps, {result['failures']['posterior']} posteriors. "
            f"`python benchmarks/fit_coverage.py`. {_machine(result)}")


def posterior_speed_table() -> str | None:
    result = _load("posterior_speed.json")
    if result is None:
        return None
    return (f"The posterior of `{result['record']}` converged with {result['draws']:,} draws after burn-in "
            f"({result['walkers']} walkers, {result['steps']} steps) in {result['faultslip_seconds']:.1f} s, the "
            f"least-squares start included. The baseline ({result['baseline']}) did the same work in "
            f"{result['baseline_seconds']:.1f} s: **{result['ratio']:.2f}** of its time. Its friction agrees with "
            f"faultslip's to {result['baseline_minus_faultslip_friction_at_the_law']:.1e} at the posterior's median "
            f"law. `python benchmarks/posterior_speed.py`. {_machine(result)}")


def stiffness_free_table() -> str | None:
    result = _load("stiffness_free.json")
    if result is None:
        return None
    lines = []
    for kind, label in (("covariance", "least-squares covariance intervals"), ("posterior", "posterior's intervals")):
        row = result["coverage"][kind]
        lines.append(f"- The {label} with k free cover " + ", ".join(
            f"{_FIT_NAMES[n]} in {row[n]['coverage']:.1%}" for n in row) + f" of {row['a']['cases']} records.")
    low, high = result["coverage"]["covariance"]["a"]["binomial_95"]
    lines.append(f"- A perfect 95 % lands in {low:.1%}-{high:.1%} over {result['coverage']['covariance']['a']['cases']} "
                 "records, 95 times in 100.")
    timing = result["speed"]
    lines.append(f"- **Posterior speed.** {timing['record']}: with k free it converges in "
                 f"{timing['medians']['stiffness_free']['wall_s']:.1f} s on one core, with k fixed in "
                 f"{timing['medians']['stiffness_fixed']['wall_s']:.1f} s: freeing k costs "
                 f"{timing['ratio_free_over_fixed']:.2f}× (target under {timing['target_s']:g} s).")
    return "\n".join(lines) + f"\n\n`python benchmarks/stiffness_free.py`. {_machine(result)}"


def _figure(value: float) -> str:
    """A fitted or scored number as a reader wants it: whole from 100 up, three figures below."""
    return f"{value:.0f}" if abs(value) >= 100 else f"{value:.3g}"


def _pressure(label: str) -> float:
    """A p655 sequence's normal stress from its label ("75 MPa"), Pa."""
    return float(label.split()[0]) * 1e6


def _speeds(window: dict) -> str:
    return " → ".join(f"{value:.4g}" for value in window["speeds_um_s"]) + " µm/s"


def p655_found_table() -> str | None:
    result = _load("p655_analysis.json")
    if result is None or not all("steady_steps" in seq for seq in result["sequences"].values()):
        return None
    rows = ["| at | what | faultslip finds |", "| --- | --- | --- |"]
    for label, seq in result["sequences"].items():
        for hold in seq["holds"]:
            rows.append(f"| {label} | a hold, {hold['start_s']:.1f}-{hold['start_s'] + hold['hold_time_s']:.1f} s | "
                        f"{hold['hold_time_s']:.1f} s; healing Δμ = {hold['healing']:.4f}, relaxation "
                        f"{hold['relaxation']:.3f} |")
        fastest = max(seq["speeds_um_s"])
        for step in seq["steady_steps"]:
            difference = step["a_minus_b"]
            # a step into or out of the fastest segment carries that segment's slip weakening in its level
            biased = " (biased by the fast segment's slip weakening)" if fastest in step["speeds_um_s"] or max(
                step["speeds_um_s"]) >= 0.99 * fastest else f" (velocity {'strengthening' if difference > 0 else 'weakening'})"
            rows.append(f"| {label} | {_speeds(step)} at {step['time_s']:.1f} s | a − b = {difference:+.4f}{biased} |")
    return "\n".join(rows) + f"\n\n`python benchmarks/p655_analysis.py`. {_machine(result)}"


def _narrowness(fit: dict) -> tuple[float, float] | None:
    """(lag-one autocorrelation, how many times too narrow) from a fit's note, where it has one."""
    for note in fit.get("notes", []):
        found = re.search(r"autocorrelation ([\d.]+)\).*?about ([\d.]+) times too narrow", note)
        if found:
            return float(found.group(1)), float(found.group(2))
    return None


def p655_steps_table() -> str | None:
    result = _load("p655_analysis.json")
    if result is None:
        return None
    rows = ["| step | a | b | D_c | k (1/m) | c (1/m) | rms |", "| --- | --- | --- | --- | --- | --- | --- |"]
    ups, narrow = [], []
    for label, seq in result["sequences"].items():
        for window in seq["windows"]:
            fit = window["aging"]
            if window["kind"] == "hold" or "a" not in fit:
                continue
            value = {name: fit[name]["value"] for name in ("a", "b", "critical_slip", "stiffness", "trend")}
            rows.append(f"| {label}, {_speeds(window)} | {value['a']:.3g} | {value['b']:.3g} | "
                        f"{_figure(value['critical_slip'] * 1e6)} µm | {value['stiffness']:.0f} | {value['trend']:+.2g} | "
                        f"{fit['residual_rms']:.1e} |")
            if window["kind"] == "up":
                ups.append((label, value))
            if _narrowness(fit):
                narrow.append(_narrowness(fit))
    differences = [v["a"] - v["b"] for _, v in ups]
    springs = [v["stiffness"] for _, v in ups]
    machine_stiffness = [v["stiffness"] * _pressure(label) / 1e12 for label, v in ups]
    lines = [f"- **a − b is {min(differences):+.4f} to {max(differences):+.4f} in every up-step**"
             + (": the gouge is velocity strengthening, as the steady levels alone said (above)."
                if min(differences) > 0 else ".")]
    lines.append(f"- **The stiffness.** The up-steps give k = {min(springs):.0f}-{max(springs):.0f} /m, K = k sigma_n "
                 f"= {min(machine_stiffness):.2f}-{max(machine_stiffness):.2f} MPa/µm.")
    posteriors = result.get("posteriors") or {}
    if posteriors:
        said = []
        for label, posterior in posteriors.items():
            parameters = posterior["parameters"]
            worst = max(p["r_hat"] for p in parameters.values())
            scale = {"critical_slip": 1e6}  # D_c in µm
            said.append(f"at {label} " + ", ".join(
                f"{_FIT_NAMES[n]} {_figure(parameters[n]['median'] * scale.get(n, 1))}"
                f"{' µm' if n == 'critical_slip' else ' /m' if n == 'stiffness' else ''} "
                f"({_figure(parameters[n]['credible_95'][0] * scale.get(n, 1))}-"
                f"{_figure(parameters[n]['credible_95'][1] * scale.get(n, 1))})"
                for n in ("a", "b", "critical_slip", "stiffness")) + f" (R-hat ≤ {worst:.2f}, {posterior['seconds']:.0f} s)")
        lines.append("- **The posteriors of the two slow up-steps** (k and the trend free, emcee until converged): "
                     + "; ".join(said) + ".")
    if narrow:
        rhos, factors = [n[0] for n in narrow], [n[1] for n in narrow]
        lines.append(f"- **Those intervals are too narrow, and the fit says so.** The residuals are correlated (lag-one "
                     f"autocorrelation {min(rhos):.2f}-{max(rhos):.2f}); every interval treats the samples as "
                     f"independent, so for AR(1) noise it is about √((1+ρ)/(1−ρ)) too narrow: {min(factors):.2g} to "
                     f"{max(factors):.2g} times here. Each fit's notes state its factor.")
    joint = result.get("joint_slow_up_steps")
    if joint:
        shared = joint["shared"]
        lines.append("- **A joint fit of the two slow up-steps** (a, b, D_c shared; mu0, k and c each its own) gives "
                     f"a {shared['a']['value']:.3g}, b {shared['b']['value']:.3g}, D_c "
                     f"{shared['critical_slip']['value'] * 1e6:.3g} µm.")
    return ("\n".join(rows) + "\n\n" + "\n".join(lines) + "\n\n`python benchmarks/p655_analysis.py`. "
            + _machine(result))


def p655_laws_table() -> str | None:
    result = _load("p655_analysis.json")
    if result is None:
        return None
    rows = ["| window | chosen | ΔBIC of the others | effective points (of) |", "| --- | --- | --- | --- |"]
    favour = {"up": [], "down": []}
    for label, seq in result["sequences"].items():
        for window in seq["windows"]:
            chosen = window.get("selection")
            if not chosen:
                continue
            others = sorted(((law, value) for law, value in chosen["delta_bic"].items() if law != chosen["chosen"]),
                            key=lambda item: (item[1] is None, item[1] or 0))
            said = ", ".join(f"{law.replace('_', ' ')} {_figure(value)}" if value is not None else
                             f"{law.replace('_', ' ')}: no converged fit" for law, value in others)
            rows.append(f"| {label}, {_speeds(window)} | {chosen['chosen'].replace('_', ' ')} | {said} | "
                        f"{chosen['effective_points']:,.0f} ({chosen['points']:,}) |")
            aging, slip = chosen["delta_bic"].get("aging"), chosen["delta_bic"].get("slip")
            if aging is not None and slip is not None:
                favour[window["kind"]].append(aging - slip)  # > 0: the slip law fits better
    lines = []
    for kind, values in favour.items():
        if values:
            slip_wins = sum(value > 0 for value in values)
            lines.append(f"- {kind.capitalize()}-steps: the slip law beats the aging law in {slip_wins} of {len(values)} "
                         "(ΔBIC aging − slip: " + ", ".join(("+" if value > 0 else "") + _figure(value)
                                                            for value in values) + ").")
    return ("\n".join(rows) + "\n\nBetween the one-state laws:\n\n" + "\n".join(lines)
            + f"\n\n`python benchmarks/p655_analysis.py`. {_machine(result)}")


#: The synthetic phone record's inputs (configs/example_phyphox.csv, docs/classroom.md): band stiffness (N/m), phone
#: mass (kg), pulling speed (m/s) and the friction drop mu_s - mu_k it was generated with.
PHONE_RECORD_INPUTS = {"stiffness": 8.0, "mass": 0.2, "speed": 0.02, "friction_drop": 0.10}


def classroom_record_table() -> str | None:
    result = _load("docs_numbers.json")
    if result is None or not result.get("classroom_record"):
        return None
    record, given = result["classroom_record"], PHONE_RECORD_INPUTS
    low, high = record["friction_drop_range"]
    omega = math.sqrt(given["stiffness"] / given["mass"])
    rows = ["| quantity | recovered | the model's input |", "| --- | --- | --- |",
            f"| slips | {record['events']} in {record['duration']:.0f} s, every {record['recurrence']:.3g} s "
            f"(CV {record['recurrence_cv']:.1g}) | |",
            f"| μs − μk | {record['friction_drop']:.3f} (range {low:.3f}-{high:.3f}) | {given['friction_drop']:.2f} |",
            f"| ω of the band | {record['angular_frequency']:.3g} 1/s | √({given['stiffness']:g}/{given['mass']:g}) = "
            f"{omega:.3g} 1/s |",
            f"| pulling speed V | {record['pull_speed'] * 100:.2g} cm/s | {given['speed'] * 100:g} cm/s |",
            f"| slip distance | {record['slip_distance'] * 1e3:.1f} mm measured, {record['slip_distance_model'] * 1e3:.1f} "
            "mm from the fitted model | |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


def seed002_decay_table() -> str | None:
    """Seed 002's Appendix C recomputed by ``faultslip decay`` beside what it prints (docs/lab_fits.md)."""
    result = _load_with("docs_numbers.json", "seed002_decay")
    if result is None:
        return None
    values, inch, pound_force = result["seed002_decay"], 0.0254, 4.4482216152605
    mass_imperial = values["mass"] * inch / pound_force  # lb s^2 / in
    rows = ["| quantity | faultslip | seed 002 prints |", "| --- | --- | --- |",
            f"| decay constant Delta = ln(1.225) × 19.9 / 10 | {values['decay_constant']:.5g} 1/s | 0.404 rad/sec |",
            f"| natural frequency sqrt(omega_d² + Delta²) | {values['natural_frequency']:.6g} rad/s | (19.9 × 2 pi) |",
            f"| damping ratio Delta / omega_n | {values['damping_ratio']:.3g} | — |",
            f"| mass M = k / omega_n² | {values['mass']:.4g} kg = {mass_imperial:.5g} lb s²/in (weight "
            f"{values['mass_weight'] / pound_force:.4g} lb) | \"M = 1.76 lb\" |",
            f"| damping coefficient r = 2 M Delta | {values['damping_coefficient'] * inch / pound_force:.5g} lb s/in | "
            "\"0.00368 lb.in/sec\" |"]
    return "\n".join(rows) + f"\n\n`python benchmarks/docs_numbers.py`. {_machine(result)}"


#: The tables this module renders, by the marker name in the pages.
TABLES = {
    "fit_coverage": fit_coverage_table,
    "posterior_speed": posterior_speed_table,
    "stiffness_free": stiffness_free_table,
    "p655_found": p655_found_table,
    "p655_steps": p655_steps_table,
    "p655_laws": p655_laws_table,
    "classroom_record": classroom_record_table,
    "seed002_decay": seed002_decay_table,
}
