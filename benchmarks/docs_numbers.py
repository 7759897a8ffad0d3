"""The computed numbers the docs quote beside the seeds' and the catalogs' (generated, never typed).

    python benchmarks/docs_numbers.py

Runs, through the command line a user types (``--json``):

* seed 003's 1906 example (configs/san_andreas_1906.toml), its granite inverse and its radiation-damped form, and the
  empirical relations the 1906 prediction sits beside (docs/results.md, docs/catalogs.md);
* the predictability verdicts' rates on seeded Poisson catalogues, through the Python API (docs/catalogs.md);
* the Parkfield catalog against the seed law (configs/catalog_san_andreas.csv on configs/parkfield.toml, as of
  2026-01-01, a fixed date so that the probability is reproducible), and the Parkfield scene at three elastic-zone
  widths (docs/catalogs.md);
* the California map's sources beside the scaling relations, and the California fault system's rupture sets on
  three scaling branches (docs/hazard.md);
* the exact critical loading rate against seed 003's Appendix I (docs/critical_rate.md);
* the closed form's error near the critical rate, and what the dashpot force at break-away does to it, through the
  Python API (docs/results.md, docs/seed_discrepancies.md);
* one rate-and-state block on the bundled faults beside the seed law, with its model error (docs/rate_state.md);
* seed 002's Appendix C free decay (``faultslip decay``, docs/lab_fits.md);
* the classroom's phone record read back (configs/example_phyphox.csv, docs/classroom.md);
* through the Python API: seed 000's addendum AD1.2 (docs/surfaces.md), Leonard's Table 6 from his Table 5
  (docs/hazard.md), and the binned against the continuous moment rate of a truncated Gutenberg-Richter
  distribution (docs/hazard.md), the b-value intervals' coverage (docs/spring_chain.md), the 2-D kernel on a
  surface-breaking crack (docs/fault_2d.md) and seed 001's charge against slip (docs/quasi_harmonic.md).

Writes benchmarks/results/docs_numbers.json; benchmarks/readme.py renders the tables.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import numpy as np  # noqa: E402

from provenance import write_results  # noqa: E402  (one stamp for every results file)

#: The catalog comparison's fixed date (a probability depends on it) and horizon, as docs/catalogs.md reads them.
AS_OF, HORIZON = "2026-01-01", "30 yr"
#: The Parkfield scene's elastic-zone widths compared: the seed's 1906 value, the scene's, and a narrow one.
ZONE_WIDTHS = ("13 mi", "6 km", "2 km")


def faultslip_json(*arguments: str) -> dict:
    """``faultslip ARGUMENTS --json`` as a user runs it, its JSON."""
    done = subprocess.run([sys.executable, "-m", "faultslip", *arguments, "--json"], cwd=ROOT, capture_output=True,
                          text=True, check=True)
    return json.loads(done.stdout)


def value(document: dict, key: str):
    """A report field's number (a quantity's value, or the plain number)."""
    entry = document[key]
    return entry["value"] if isinstance(entry, dict) else entry


def parkfield_widths() -> list[dict]:
    """The Parkfield scene with each of :data:`ZONE_WIDTHS`: slip per event (m), recurrence (s), Mw."""
    text = (ROOT / "configs" / "parkfield.toml").read_text(encoding="utf-8")
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for width in ZONE_WIDTHS:
            scene = Path(folder) / "parkfield.toml"
            scene.write_text(text.replace('zone_width = "6 km"', f'zone_width = "{width}"'), encoding="utf-8")
            result = faultslip_json("run", str(scene))
            rows.append({"zone_width": width, "slip_per_event_m": value(result, "slip_per_event"),
                         "recurrence_s": value(result, "recurrence_period"),
                         "moment_magnitude": value(result, "moment_magnitude")})
    return rows


def hazard_maps() -> dict:
    """The bundled California map's sources beside the scaling relations, and the fault system's rupture sets on
    three branches (docs/hazard.md), from ``faultslip map ... --nrml ... --json``."""
    with tempfile.TemporaryDirectory() as folder:
        segments = faultslip_json("map", "configs/california_faults_map.toml", "-o", f"{folder}/m.nc", "--nrml",
                                  f"{folder}/m.xml")
        system = faultslip_json("map", "configs/california_fault_system.toml", "-o", f"{folder}/s.nc", "--nrml",
                                f"{folder}/system.xml", "--scaling-relations", "faultslip,WC1994,Leonard2010")
    keep = ("relation", "sections", "ruptures", "ruptures_with_rate", "multi_fault_ruptures_with_rate",
            "budget_error", "b_value", "shape_misfit")
    return {"california_sources": [{"id": source["id"], "moment_rate": source["moment_rate"]["value"],
                                    "magnitude": source["magnitude"], "empirical": source["empirical"]}
                                   for source in segments["hazard"]["sources"]],
            "rupture_sets": [{key: branch[key] for key in keep} for branch in
                             system["hazard"]["rupture_sets"].values()]}


def san_andreas_empirical() -> dict:
    """The San Andreas map's slip per event against Wells & Coppersmith's AD(Mw) for each segment's own Mw
    (docs/catalogs.md): the range of the ratio and of z over the segments with stick-slip."""
    import xarray as xr

    with tempfile.TemporaryDirectory() as folder:
        faultslip_json("map", "configs/san_andreas_map.toml", "-o", f"{folder}/m.nc")
        with xr.open_dataset(f"{folder}/m.nc") as dataset:
            ratio, z = dataset["empirical_slip_ratio"].values, dataset["empirical_slip_z"].values
    return {"slip_ratio": [float(np.nanmin(ratio)), float(np.nanmax(ratio))],
            "slip_z": [float(np.nanmin(z)), float(np.nanmax(z))]}


def critical_comparison() -> dict:
    """The exact critical loading rate against seed 003's Appendix I over Table I's presets and damping ratios
    (docs/critical_rate.md), from ``faultslip critical --table``: its arrays and the Markdown it writes."""
    with tempfile.TemporaryDirectory() as folder:
        table = faultslip_json("critical", "--table", "--output-dir", folder)
        markdown = (Path(folder) / "critical_comparison.md").read_text(encoding="utf-8")
    return {key: table[key] for key in ("preset", "damping_ratio", "critical_loading_rate",
                                         "seed_appendix_I_loading_rate")} | {"markdown": markdown}


def rate_state_examples() -> list[dict]:
    """One rate-and-state block on the bundled faults, with the seed law beside it and its model error against
    the 2-D fault (docs/rate_state.md): the seed-law form's 1906 scene through ``run``, BP1's friction on one block
    through ``rate-state cycles --seed-law granodiorite``."""
    rows = []
    for label, document in (
            ("configs/san_andreas_1906_rate_state.toml (`faultslip run`)",
             faultslip_json("run", "configs/san_andreas_1906_rate_state.toml")),
            ("configs/rsf_block_bp1.toml (`faultslip rate-state cycles --seed-law granodiorite`)",
             faultslip_json("rate-state", "cycles", "configs/rsf_block_bp1.toml", "--seed-law", "granodiorite"))):
        rows.append({"scene": label, **{key: value(document, key) for key in (
            "stiffness_ratio", "slip_per_event", "recurrence_period", "seed_law_slip_per_event",
            "seed_law_recurrence_period", "model_error")},
            "recurrence_range": document["recurrence_range"]["value"]})
    return rows


def seed_000_addendum() -> dict:
    """Seed 000's addendum AD1.2 recomputed (docs/surfaces.md): the contact modulus of two steel surfaces, GW's
    elastic contact hardness and plasticity index, and the real area at the seed's plastic contact pressure. The
    seed's inputs, in SI: E 210 kN/mm^2, nu 0.3, summit spread 2.37 um and radius 58.7 um, H 208 kgf/mm^2,
    30 N on p_c = 280 N/mm^2."""
    from faultslip.friction.contact import contact_modulus, elastic_contact_hardness, plasticity_index

    modulus = contact_modulus(210e9, 0.3)
    return {"contact_modulus": modulus,
            "elastic_contact_hardness_at_printed_modulus": elastic_contact_hardness(115e9, 2.37e-6, 58.7e-6),
            "plasticity_index": plasticity_index(modulus, 208 * 9.80665e6, 2.37e-6, 58.7e-6),
            "real_area": 30.0 / 280e6}


#: Seed 000's AD1.3 runs (its figs. AD3-AD5): the scene's spring and separation coefficient, then a smaller c, then a
#: softer spring, then no separation, each as a (stiffness, c) replacing the scene's.
ROUGH_SLIDER_RUNS = (("12.66e3 N/m", "0.8 s/m"), ("12.66e3 N/m", "0.4 s/m"), ("6e3 N/m", "0.4 s/m"),
                     ("12.66e3 N/m", "0 s/m"))
#: The seed's peak relative sliding speed (m/s), where the doc compares how far friction has fallen.
ROUGH_SLIDER_PEAK_SPEED = 0.06


def rough_slider() -> dict:
    """Seed 000's sliding model (configs/rough_surface_seed000.toml) at the addendum's springs and separation
    coefficients, from ``faultslip simulate ... --json`` (docs/surfaces.md): each run's peak-to-peak swing, slip
    duration and natural frequency, and how far the scene's friction has fallen at the seed's peak speed."""
    from faultslip.models.rough_surface.scene import read_rough_scene

    path = ROOT / "configs" / "rough_surface_seed000.toml"
    text = path.read_text(encoding="utf-8")
    runs = []
    with tempfile.TemporaryDirectory() as folder:
        for stiffness, coefficient in ROUGH_SLIDER_RUNS:
            scene = Path(folder) / "rough.toml"
            scene.write_text(text.replace('stiffness = "12.66e3 N/m"', f'stiffness = "{stiffness}"').replace(
                'separation_coefficient = "0.8 s/m"', f'separation_coefficient = "{coefficient}"'), encoding="utf-8")
            result = faultslip_json("simulate", str(scene))
            runs.append({"stiffness": stiffness, "separation_coefficient": coefficient,
                         **{key: value(result, key) for key in (
                             "peak_to_peak_swing", "slip_duration", "natural_frequency", "static_friction_model",
                             "area_fraction_at_rest", "peak_slip_speed", "regime", "events")}})
    system, details, _ = read_rough_scene(path)
    fallen = 1.0 - float(system.kinetic_law(ROUGH_SLIDER_PEAK_SPEED)) / details["static_friction"]
    friction = tomllib.loads(text)["friction"]
    return {"runs": runs, "peak_speed": ROUGH_SLIDER_PEAK_SPEED, "friction_fall_at_peak_speed": fallen,
            "synthetic": friction["synthetic"], "synthetic_size": friction["synthetic_size"]}


#: The quasi-harmonic scene's speed the docs quote, and the seed 002 curve speed where damping is compared.
VIBRATION_SPEED, SEED002_DAMPING_SPEED = "12.5 in/s", 5 * 0.0254


def quasi_harmonic() -> dict:
    """Seed 002's quasi-harmonic vibration (docs/quasi_harmonic.md): the scene's averaged amplitude and averaging's
    measured error (``faultslip quasi-harmonic ... --error-chart --json``), eq. (10) integrated beside it
    (``faultslip simulate``), the band where the scene vibrates without sticking (its edges by bisection on the
    analysis), and seed 002's Figs. 9-11 in kind (``faultslip plot seed002 --json``, and curve (A)'s amplitude at
    5 in/s with the damping doubled)."""
    from dataclasses import replace

    from scipy.optimize import brentq

    from faultslip.lab.seed002_curves import CURVES, seed_branch
    from faultslip.models.vibration.scene import read_vibration_scene

    scene = "configs/vibration_seed002.toml"
    with tempfile.TemporaryDirectory() as folder:
        averaged = faultslip_json("quasi-harmonic", scene, "--speed", VIBRATION_SPEED, "--error-chart",
                                  f"{folder}/error.png")
        figures = faultslip_json("plot", "seed002", "-o", f"{folder}/seed002.png")
    simulated = faultslip_json("simulate", scene)
    system, _ = read_vibration_scene(ROOT / scene)
    speeds = np.linspace(0.05, 2.0, 400) * system.speed
    vibrates = [replace(system, speed=float(v)).analyse() for v in speeds]
    band = [i for i, result in enumerate(vibrates) if result.valid and result.amplitude > 0]
    first, last = band[0], band[-1]
    sticks_below = brentq(lambda v: 0.5 - replace(system, speed=v).analyse().valid, speeds[first - 1], speeds[first],
                          xtol=1e-9)
    onset = brentq(lambda v: replace(system, speed=v).steady_sliding_growth, speeds[last], speeds[last + 1], xtol=1e-12)
    damped = [float(seed_branch(CURVES["A"], [SEED002_DAMPING_SPEED], factor)["amplitude"][0]) for factor in (1, 2)]
    return {"speed": VIBRATION_SPEED, "amplitude": value(averaged, "amplitude"),
            "declared_error": averaged["estimated_relative_error"],
            "error_over_eps_squared": averaged["averaging_error"]["error_over_eps_squared"],
            "measured": averaged["averaging_error"]["measured"],
            "simulated_error": simulated["averaging_relative_error"], "simulated_duration": value(simulated, "duration"),
            "sticks_below": sticks_below, "steady_above": onset,
            "seed002_ends": {key[len("curve_"):-len("_ends")]: value(figures, key) for key in figures
                             if key.endswith("_ends")},
            "flattening_speeds": {name: curve.flattening_speed for name, curve in CURVES.items()},
            "damping_speed": SEED002_DAMPING_SPEED, "damped_amplitude_ratio": damped[1] / damped[0]}


#: The damping ratios the closed form's failure near theta_c is shown at (docs/results.md), and those the dashpot
#: force's part in the critical rate is (docs/seed_discrepancies.md).
NEAR_CRITICAL_DAMPING = (0.01, 0.1, 0.2, 0.3, 0.4, 0.5)
DASHPOT_DAMPING = (0.01, 0.1, 0.2, 0.5, 0.9)


def closed_form_near_critical(fraction: float = 0.9) -> dict:
    """The closed form's relative errors against the exact cycle at ``fraction`` of the critical rate, per damping
    ratio (docs/results.md), and what leaving the dashpot force out of break-away does to the critical rate
    (docs/seed_discrepancies.md), through the Python API."""
    from faultslip.dynamics.spring_slider.closed_form import relative_error_against_exact
    from faultslip.dynamics.spring_slider.critical import (critical_dimensionless_rate,
                                                           critical_rate_without_dashpot_force)

    rows = []
    for zeta in NEAR_CRITICAL_DAMPING:
        errors = relative_error_against_exact(zeta, fraction * float(critical_dimensionless_rate(zeta)))
        rows.append({"damping_ratio": zeta, **{key: float(v) for key, v in errors.items()}})
    dashpot = [{"damping_ratio": zeta, "overestimate": critical_rate_without_dashpot_force(zeta)
                / float(critical_dimensionless_rate(zeta)) - 1} for zeta in DASHPOT_DAMPING]
    return {"fraction_of_critical": fraction, "rows": rows, "dashpot_force": dashpot}


def poisson_verdicts(catalogues: int = 300, events: int = 40, draws: int = 2000) -> dict:
    """How often ``faultslip.hazard.predictability`` gives each verdict on seeded Poisson catalogues (exponential
    intervals of mean 100 yr, slips uniform in 1 to 3): the rates the docs quote (docs/catalogs.md)."""
    from faultslip.hazard import predictability

    year = 365.25 * 86400
    counts = {"poisson": 0, "periodic": 0, "time_predictable": 0, "slip_predictable": 0}
    for seed in range(catalogues):
        rng = np.random.default_rng(seed)
        times = np.concatenate([[0.0], np.cumsum(rng.exponential(100 * year, events - 1))])
        verdicts = predictability(times, rng.uniform(1.0, 3.0, events), draws=draws).verdicts
        for name in counts:
            counts[name] += bool(verdicts[name])
    return {"catalogues": catalogues, "events": events, "draws": draws, "counts": counts}


#: The b-value intervals' coverage (docs/spring_chain.md): seeded catalogues, their size, and the binned cases
#: (b, bin width) measured beside the continuous one at b = 1.
B_VALUE_CATALOGUES, B_VALUE_EVENTS, B_VALUE_BINNED = 400, 1000, ((1.0, 0.1), (1.5, 0.2))


def b_value_coverage() -> dict:
    """How often the 95 % b-value interval holds the truth, and the median estimate's bias, on seeded
    Gutenberg-Richter catalogues: continuous magnitudes (Aki), and binned ones by ``b_value`` (Tinti & Mulargia)
    beside Utsu's shortcut with its chi-square interval (docs/spring_chain.md)."""
    import math

    from scipy.stats import chi2

    from faultslip.fault.gutenberg_richter import b_value

    def measure(truth, width, seed):
        rng = np.random.default_rng(seed)
        ours, utsu = {"covered": 0, "estimates": []}, {"covered": 0, "estimates": []}
        for _ in range(B_VALUE_CATALOGUES):
            sample = 2.0 - width / 2 + rng.exponential(1 / (truth * math.log(10)), B_VALUE_EVENTS)
            if width:
                sample = 2.0 + width * np.round((sample - 2.0) / width)
            found = b_value(sample, completeness=2.0, bin_width=width)
            ours["covered"] += found["interval"][0] <= truth <= found["interval"][1]
            ours["estimates"].append(found["b"])
            excess = float(np.sum(sample - (2.0 - width / 2)))
            utsu["estimates"].append(math.log10(math.e) * B_VALUE_EVENTS / excess)
            utsu["covered"] += bool(chi2.ppf(0.025, 2 * B_VALUE_EVENTS) <= 2 * excess * math.log(10) * truth
                                    <= chi2.ppf(0.975, 2 * B_VALUE_EVENTS))
        row = {"b_value": truth, "bin_width": width}
        for name, found in (("faultslip", ours), ("utsu", utsu)):
            row[name] = {"coverage": found["covered"] / B_VALUE_CATALOGUES,
                         "median_bias": float(np.median(found["estimates"]) / truth - 1)}
        return row

    rows = [measure(1.0, 0.0, 45)] + [measure(b, width, 46 + i) for i, (b, width) in enumerate(B_VALUE_BINNED)]
    return {"catalogues": B_VALUE_CATALOGUES, "events": B_VALUE_EVENTS, "confidence": 0.95, "rows": rows}


def surface_crack(depth_extent: float = 10e3, stress_drop: float = 3e6, shear_modulus: float = 32.04e9) -> dict:
    """The 2-D fault's stress kernel on a surface-breaking crack of uniform stress drop against Knopoff's (1958)
    exact ellipse, by element count (docs/fault_2d.md): the largest relative slip error above 0.9 of the depth
    (the tip's square root converges slowly on uniform elements) and the potency's error, tip included."""
    import math

    from faultslip.models.fault_2d.kernel import dense_matrix

    rows = []
    for count in (100, 200, 400, 800, 1600):
        size = depth_extent / count
        depth = (np.arange(count) + 0.5) * size
        slip = np.linalg.solve(dense_matrix(count, size, shear_modulus), -np.full(count, stress_drop))
        exact = 2 * stress_drop / shear_modulus * np.sqrt(depth_extent ** 2 - depth ** 2)
        inside = depth < 0.9 * depth_extent
        rows.append({"elements": count, "slip": float(np.max(np.abs(slip[inside] / exact[inside] - 1))),
                     "potency": float(slip.sum() * size / (math.pi * depth_extent ** 2 * stress_drop
                                                           / (2 * shear_modulus)) - 1)})
    return {"depth_extent": depth_extent, "rows": rows}


def nanoscale_charge() -> dict:
    """Seed 001's deposited charge over displacement against the steady-sliding slope Sigma* / a, in stick-slip
    (the slides' damping) and in steady sliding (A = 13), with the stick-slip run's correlation (docs/
    quasi_harmonic.md)."""
    from faultslip.models.nanoscale.dynamics import NanoscaleModel

    model = NanoscaleModel()
    stick_slip = model.simulate(duration=1500.0, samples=3001)
    steady = NanoscaleModel(damping=13.0).simulate(duration=600.0, samples=601)
    return {"steady_slope": model.steady_charge / model.charge_length, "stick_slip_events": stick_slip.slip_events(),
            "correlation": float(stick_slip.charge_correlation()),
            "stick_slip_ratio": float(stick_slip.deposited[-1] / stick_slip.displacement[-1]),
            "steady_ratio": float(steady.deposited[-1] / steady.displacement[-1])}


#: The b-values and bin widths the binned and continuous moment rates of a truncated Gutenberg-Richter
#: distribution are compared at (docs/hazard.md); the map's own are mfd.B_VALUE and mfd.BIN_WIDTH.
GR_B_VALUES, GR_BIN_WIDTHS = (0.8, 1.0, 1.2), (0.05, 0.1, 0.2)


def truncated_gr_moment_rates() -> dict:
    """The moment rate faultslip balances (the bins' rates times M0 at their centres) over the one the engine's
    ``TruncatedGRMFD`` integrates from the continuous density (``faultslip.fault.mfd.continuous_moment_rate``),
    minus 1, by b-value at the map's bin width and by bin width at the map's b-value (docs/hazard.md)."""
    from faultslip.fault import mfd

    def apart(b_value, bin_width):
        distribution = mfd.truncated_gutenberg_richter(1e17, 7.4, 5.0, b_value, bin_width)
        return distribution.moment_rate() / mfd.continuous_moment_rate(distribution) - 1

    return {"b_value": mfd.B_VALUE, "bin_width": mfd.BIN_WIDTH,
            "by_b_value": [{"b_value": b, "apart": apart(b, mfd.BIN_WIDTH)} for b in GR_B_VALUES],
            "by_bin_width": [{"bin_width": w, "apart": apart(mfd.B_VALUE, w)} for w in GR_BIN_WIDTHS]}


def leonard_table_6() -> dict:
    """Leonard's (2010) Table 6 intercepts recomputed from his Table 5 (docs/hazard.md): Mw - log10 A at A =
    1000 km^2, and Mw - (5/3) log10 L at L = 20 km (every setting's middle segment), by setting."""
    import math

    from faultslip.fault import empirical

    return {setting: {"area": float(empirical.leonard_magnitude_from_area(1000e6, setting)) - 3.0,
                      "length": float(empirical.leonard_magnitude_from_length(20e3, setting)) - 5 / 3 * math.log10(20)}
            for setting in empirical.LEONARD_SETTINGS}


def main() -> int:
    seed_1906 = faultslip_json("run", "configs/san_andreas_1906.toml")
    inverse = faultslip_json("run", "configs/granite_inverse_1906.toml")
    radiation = faultslip_json("run", "configs/san_andreas_1906_radiation.toml")
    keys = ("normal_stress", "stiffness", "loading_rate", "stress_drop_slip", "slip_per_event", "recurrence_period",
            "stress_drop", "seismic_moment", "moment_magnitude", "slip_rate")
    catalog = faultslip_json("catalog", "configs/catalog_san_andreas.csv", "--fault", "configs/parkfield.toml",
                             "--max-magnitude", "6.5", "--as-of", AS_OF, "--horizon", HORIZON)
    document = {
        "seed_003_1906": {key: value(seed_1906, key) for key in keys},
        "granite_inverse": {"friction_drop": value(inverse, "friction_drop"),
                            "kinetic_friction": value(inverse, "kinetic_friction")},
        "radiation": {"damping_ratio": value(radiation, "damping_ratio"),
                      "slip_per_event": value(radiation, "slip_per_event"),
                      "recurrence_period": value(radiation, "recurrence_period")},
        "empirical_1906": [seed_1906[key] for key in sorted(seed_1906) if key.startswith("empirical_")],
        "parkfield_catalog": {"as_of": AS_OF, "horizon": HORIZON, **{key: catalog[key] for key in catalog
                                                 if key not in ("event_list", "notes", "title")}},
        "parkfield_widths": parkfield_widths(),
    }
    document.update(hazard_maps())
    document["san_andreas_empirical"] = san_andreas_empirical()
    parkfield = faultslip_json("predictability", "configs/catalog_san_andreas.csv", "--name", "Parkfield")
    document["parkfield_predictability"] = {key: parkfield[key] for key in (
        "events", "aperiodicity", "periodic", "poisson", "time_predictable", "slip_predictable")} | {
        "aperiodicity_95": parkfield["aperiodicity_95"]["value"]}
    document["critical_comparison"] = critical_comparison()
    document["rate_state_examples"] = rate_state_examples()
    record = faultslip_json("record", "configs/example_phyphox.csv")
    document["classroom_record"] = {key: value(record, key) for key in (
        "events", "duration", "recurrence", "recurrence_cv", "friction_drop", "friction_drop_range",
        "angular_frequency", "pull_speed", "slip_distance", "slip_distance_model")}
    document["closed_form_near_critical"] = closed_form_near_critical()
    document["poisson_verdicts"] = poisson_verdicts()
    document["seed_000_addendum"] = seed_000_addendum()
    document["leonard_table_6"] = leonard_table_6()
    document["truncated_gr_moment_rates"] = truncated_gr_moment_rates()
    document["b_value_coverage"] = b_value_coverage()
    document["surface_crack"] = surface_crack()
    document["nanoscale_charge"] = nanoscale_charge()
    document["rough_slider"] = rough_slider()
    document["quasi_harmonic"] = quasi_harmonic()
    decay = faultslip_json("decay", "--stiffness", "70.5 lbf/in", "--ratio", "1.225", "--cycles-between", "10",
                           "--frequency", "19.9 Hz")
    document["seed002_decay"] = {key: value(decay, key) for key in (
        "decay_constant", "natural_frequency", "damping_ratio", "mass", "mass_weight", "damping_coefficient")}
    write_results("docs_numbers.json", document)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
